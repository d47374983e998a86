//! The logic of [`Velocity`] (`super`), in named stages.
use super::*;

// The estimator's logic in named stages, run in this order (`logic_stages!`).
crate::blocks::logic_stages!(Velocity: FrontEnd, Operands, Schedule, Reset);

/// The multiplier's ports and the front end's unwrapped position.
impl stages::FrontEnd for Velocity {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clk, init, pos, padj, cnt, tickr, state, mlast, j, jlr, primed, first, snap, opd,
            theta, acc, k, tx, tsel, mwait, opa, out_reg, valid_reg
        );
        for i in 0..self.hist.len() {
            self.hist[i].clock.next = self.clk.val();
            self.hist[i].d.next = self.hist[i].q.val();
        }
        // j and mwait hold their low bits only: every bit above is 0 in every assignment,
        // so synthesis drops those flip-flops and the compares on them are narrow.
        self.j.d.next = self.j.q.val() & self.jmask.val();
        self.mwait.d.next = self.mwait.q.val() & self.wmask.val();
        // The multiplier: operand a from `opa`, the coefficient straight from the ROM,
        // started in `Op`; its result is taken in `Acc`.
        self.jl.next = self.jlr.q.val();
        self.mul.clk.next = self.clk.val();
        self.mul.a.next = self.opa.q.val();
        self.mul.b.next = self.rom.coef.val();
        self.mul.start.next = self.state.q.val() == VelState::Op;
        // One assignment (no default-then-override): a momentary value on a port between
        // two modules' combinational blocks makes Icarus loop forever at one time step.
        self.rom.addr.next =
            (self.j.q.val() & self.jsel.val()) | (self.k.q.val() & self.ksel.val());
        self.valid_reg.d.next = false;
        // Front end: pos += sext((in_p - pos) mod 2^(F+2)), modulo 2^Wp; the first sample
        // loads it. The low F+2 bits become in_p; the bits above are those of
        // pos - in_p + 2^(F+1) - 1 = padj - in_p - 1 (in_p zero-extended): the one value
        // congruent to in_p modulo 2^(F+2) within [-2^(F+1), 2^(F+1)) of pos. padj (pos +
        // 2^(F+1)) follows with padj - sext(in_p) - 1 above F+2, and in_p with its bit F+1
        // inverted below. Each is one carry chain from registers and the port, no LUT in
        // front: a - b - 1 as {a, 0} - {b, 1} shifted right.
        self.inp.next = bit_cast::<64, 32>(self.in_p.val()) & self.f2mask.val();
        self.sinp.next = self.inp.val();
        if (self.inp.val() & self.f2sign.val()).any() {
            self.sinp.next = self.inp.val() | self.f2ext.val();
        }
        self.vpos.next = (((self.padj.q.val() << self.one.val())
            - ((self.inp.val() << self.one.val()) | self.one64.val()))
            >> self.one.val())
            & self.wpmask.val();
        self.vadj.next = (((self.padj.q.val() << self.one.val())
            - ((self.sinp.val() << self.one.val()) | self.one64.val()))
            >> self.one.val())
            & self.wpmask.val();
        if self.in_valid.val() {
            if self.init.q.val() {
                self.pos.d.next = (self.vpos.val() & !self.f2mask.val()) | self.inp.val();
                self.padj.d.next =
                    (self.vadj.val() & !self.f2mask.val()) | (self.inp.val() ^ self.f2sign.val());
            } else {
                self.pos.d.next = self.inp.val();
                self.padj.d.next = self.inp.val() ^ self.f2sign.val();
                if (self.inp.val() & self.f2sign.val()).any() {
                    self.padj.d.next = (self.inp.val() ^ self.f2sign.val()) | self.f2one.val();
                }
                self.init.d.next = true;
            }
        }
    }
}

/// The update tick and each method's operands.
impl stages::Operands for Velocity {
    #[hdl_gen]
    fn update(&mut self) {
        // Divider: tick every D clocks (D >= 64), decoded one clock ahead.
        self.tick.next = self.tickr.q.val();
        self.tickr.d.next = self.cnt.q.val() == self.dprev.val();
        self.cnt.d.next = self.cnt.q.val() + self.one.val();
        if self.tick.val() {
            self.cnt.d.next = self.zero.val();
        }
        // diff_lpf / kalman: Delta = sext(theta - theta(k-1)) (state width), into `d` at the
        // tick; U = Delta 2^(S+G) in `Prep`.
        self.delta.next = (self.pos.q.val() - self.hist[0].q.val()) & self.wpmask.val();
        self.sdelta.next = self.delta.val();
        if (self.delta.val() & self.wpsign.val()).any() {
            self.sdelta.next = (self.delta.val() | self.wpext.val()) & self.smask.val();
        }
        // tracking: theta 2^(S+G) modulo 2^(Wp+S+G); Theta's one adder adds registers
        // only: `tx` in `Prep`, the product in `Acc`.
        self.meas.next = (self.snap.q.val() << self.sg.val()) & self.twmask.val();
        self.tadd.next = self.mul.p.val();
        if self.tsel.q.val() {
            self.tadd.next = self.tx.q.val();
        }
        // lsq: r = x_i - theta (Wp bits) and P, each sign-extended/cut to operand a's width.
        self.r.next = (self.hist[0].q.val() - self.snap.q.val()) & self.wpmask.val();
        self.rext.next = self.r.val();
        if (self.r.val() & self.wpsign.val()).any() {
            self.rext.next = (self.r.val() | self.wpext.val()) & self.amask.val();
        }
        self.pa.next = self.acc.q.val() & self.amask.val();
        if (self.acc.q.val() & self.accsign.val()).any() {
            self.pa.next = (self.acc.q.val() | self.accext.val()) & self.amask.val();
        }
        // Output: q(acc / 2^G), sign-extended or cut to `width`.
        self.yr.next = (self.acc.q.val() + self.ghalf.val()) & self.accmask.val();
        self.ys.next = (self.yr.val() >> self.g.val()) & self.ymask.val();
        if (self.yr.val() & self.accsign.val()).any() {
            self.ys.next = ((self.yr.val() >> self.g.val()) | self.yext.val()) & self.ymask.val();
        }
    }
}

/// The schedule: one arm per state of the sketch in the module docs.
impl stages::Schedule for Velocity {
    #[hdl_gen]
    fn update(&mut self) {
        self.tsel.d.next = false;
        self.mlast.d.next = false;
        match self.state.q.val() {
            VelState::Idle => {
                if self.tick.val() & self.init.q.val() {
                    self.snap.d.next = self.pos.q.val();
                    self.state.d.next = VelState::Prep;
                    self.tsel.d.next = true;
                    // Theta = 0 before the first update (reset clears it): adding
                    // theta 2^(S+G) loads it.
                    self.tx.d.next = self.acc.q.val();
                    if !self.primed.q.val() {
                        self.tx.d.next = (self.pos.q.val() << self.sg.val()) & self.twmask.val();
                    }
                    self.first.d.next = !self.primed.q.val();
                    if !self.is_lsq.val() & !self.is_track.val() {
                        self.opd.d.next = self.sdelta.val();
                        if !self.primed.q.val() {
                            self.opd.d.next = self.zero64.val();
                        }
                    }
                    if !self.primed.q.val() {
                        // First update: the history as if at rest at theta (output 0).
                        self.primed.d.next = true;
                        for i in 0..self.hist.len() {
                            self.hist[i].d.next = self.pos.q.val();
                        }
                    }
                }
            }
            VelState::Prep => {
                self.j.d.next = self.zero.val();
                self.jlr.d.next = self.jl0.val();
                self.state.d.next = VelState::Op;
                if self.is_lsq.val() {
                    for i in 1..self.hist.len() {
                        self.hist[i - 1].d.next = self.hist[i].q.val();
                    }
                    for i in self._hlast..self.hist.len() {
                        self.hist[i].d.next = self.snap.q.val();
                    }
                    self.acc.d.next = self.zero64.val();
                } else if self.is_track.val() {
                    // e (0 at the first update); Theta += W (or the load), + q(beta e) and
                    // q(alpha e) in the two `Acc`.
                    self.opd.d.next = (self.meas.val() - self.theta.q.val()) & self.twmask.val();
                    if self.first.q.val() {
                        self.opd.d.next = self.zero64.val();
                    }
                    self.theta.d.next = (self.theta.q.val() + self.tadd.val()) & self.twmask.val();
                } else {
                    self.opd.d.next =
                        ((self.opd.q.val() << self.sg.val()) - self.acc.q.val()) & self.smask.val();
                    self.hist[0].d.next = self.snap.q.val();
                }
            }
            VelState::Op => {
                self.opa.d.next = self.opd.q.val();
                if self.is_lsq.val() {
                    // Rotate the history: x_1 comes back to the front after M multiplies.
                    self.opa.d.next = self.rext.val();
                    if self.jl.val() {
                        // P goes to the multiplier; the accumulator restarts from 0 for
                        // q(P R / 2^B).
                        self.opa.d.next = self.pa.val();
                        self.acc.d.next = self.zero64.val();
                    }
                    for i in 1..self.hist.len() {
                        self.hist[i - 1].d.next = self.hist[i].q.val();
                    }
                    for i in self._hlast..self.hist.len() {
                        self.hist[i].d.next = self.hist[0].q.val();
                    }
                }
                self.mwait.d.next = self.zero.val();
                self.state.d.next = VelState::Prod;
            }
            VelState::Prod => {
                // n + 1 clocks for the multiplier (its start clock zeroes x, then n
                // digits); `mlast` marks the last (mwait = n).
                self.mwait.d.next = (self.mwait.q.val() + self.one.val()) & self.wmask.val();
                self.mlast.d.next = self.mwait.q.val() == self.wprev.val();
                if self.mlast.q.val() {
                    self.state.d.next = VelState::Acc;
                }
            }
            VelState::Acc => {
                self.acc.d.next = (self.acc.q.val() + self.mul.p.val()) & self.accmask.val();
                if self.is_track.val() {
                    self.theta.d.next = (self.theta.q.val() + self.tadd.val()) & self.twmask.val();
                    if self.jl.val() {
                        self.acc.d.next = self.acc.q.val();
                    }
                }
                if self.is_kal.val() & !self.first.q.val() & (self.k.q.val() != self.klast.val()) {
                    self.k.d.next = self.k.q.val() + self.one.val();
                }
                if self.jl.val() {
                    self.state.d.next = VelState::Out;
                } else {
                    self.j.d.next = (self.j.q.val() + self.one.val()) & self.jmask.val();
                    self.jlr.d.next = self.j.q.val() == self.jprev.val();
                    self.state.d.next = VelState::Op;
                }
            }
            VelState::Out => {
                self.out_reg.d.next = self.ys.val();
                self.valid_reg.d.next = true;
                self.state.d.next = VelState::Idle;
            }
        }
    }
}

/// Reset.
impl stages::Reset for Velocity {
    #[hdl_gen]
    fn update(&mut self) {
        if self.rst.val() {
            self.init.d.next = false;
            self.pos.d.next = self.zero64.val();
            self.padj.d.next = self.f2sign.val();
            self.cnt.d.next = self.zero.val();
            self.tickr.d.next = false;
            self.state.d.next = VelState::Idle;
            self.mlast.d.next = false;
            self.j.d.next = self.zero.val();
            self.jlr.d.next = self.jl0.val();
            self.primed.d.next = false;
            self.first.d.next = false;
            self.snap.d.next = self.zero64.val();
            for i in 0..self.hist.len() {
                self.hist[i].d.next = self.zero64.val();
            }
            self.opd.d.next = self.zero64.val();
            self.theta.d.next = self.zero64.val();
            self.acc.d.next = self.zero64.val();
            self.k.d.next = self.zero.val();
            self.tx.d.next = self.zero64.val();
            self.mwait.d.next = self.zero.val();
            self.opa.d.next = self.zero64.val();
            self.out_reg.d.next = self.zero64.val();
            self.valid_reg.d.next = false;
        }
        self.out_velocity.next = self.out_reg.q.val();
        self.out_velocity_valid.next = self.valid_reg.q.val();
    }
}
