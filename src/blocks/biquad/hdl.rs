//! rust-hdl description of the biquad engine (see the module docs of `biquad`): the engine
//! [`BiquadRtl`] around its three leaves in [`super::parts`]: the single multiplier
//! [`BiquadMul`], the program ROM [`BiquadProgram`] and the state RAM [`BiquadStateRam`].
pub use super::parts::{BiquadMul, BiquadProgram, BiquadStateRam};
use super::{ctrl, BiquadParams};
use crate::blocks::{c32, mask};
use crate::cosim::Port;
use rust_hdl::prelude::*;

/// The time-multiplexed biquad engine (ports in the module docs of `biquad`).
#[derive(LogicBlock)]
pub struct BiquadRtl {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high: abort, clear outputs, flags and state.
    pub rst: Signal<In, Bit>,
    /// Start strobe (accepted while busy is low).
    pub in_valid: Signal<In, Bit>,
    /// Branch inputs, D-bit two's complement in the low bits.
    pub in_data: Vec<Signal<In, Bits<32>>>,
    /// One-clock strobe: out_data and overflow are new.
    pub out_valid: Signal<Out, Bit>,
    /// Branch outputs, D-bit two's complement (saturated), held between strobes.
    pub out_data: Vec<Signal<Out, Bits<32>>>,
    /// With out_valid: some section of this sample saturated.
    pub overflow: Signal<Out, Bit>,
    /// Computing or clearing the state: in_valid is dropped.
    pub busy: Signal<Out, Bit>,
    /// One-clock flag set by the edge that ignored an in_valid (busy).
    pub dropped: Signal<Out, Bit>,
    prog: BiquadProgram,
    ram: BiquadStateRam,
    mul: BiquadMul,
    busy_reg: DFF<Bit>,
    clr_reg: DFF<Bit>,
    clr_addr: DFF<Bits<32>>,
    pc: DFF<Bits<32>>,
    /// The program word of this clock (ROM read one clock ahead, at the next pc).
    ctrl_reg: DFF<Bits<32>>,
    coefw_reg: DFF<Bits<32>>,
    /// Registered multiplier operands (data, coefficient).
    opa: DFF<Bits<32>>,
    opb: DFF<Bits<32>>,
    parity: DFF<Bits<32>>,
    xcur: DFF<Bits<32>>,
    coef_reg: DFF<Bits<32>>,
    prod_reg: DFF<Bits<32>>,
    acc: DFF<Bits<32>>,
    sample_ovf: DFF<Bit>,
    valid_reg: DFF<Bit>,
    ovf_reg: DFF<Bit>,
    drop_reg: DFF<Bit>,
    in_lat: Vec<DFF<Bits<32>>>,
    osel: Vec<DFF<Bit>>,
    out_sh: Vec<DFF<Bits<32>>>,
    out_reg: Vec<DFF<Bits<32>>>,
    ctrl_w: Signal<Local, Bits<32>>,
    /// The next pc (the ROM address).
    pc_n: Signal<Local, Bits<32>>,
    c_we: Signal<Local, Bit>,
    c_wsrc: Signal<Local, Bit>,
    c_ldx: Signal<Local, Bit>,
    c_xin: Signal<Local, Bit>,
    c_opx: Signal<Local, Bit>,
    c_acc: Signal<Local, Bit>,
    c_first: Signal<Local, Bit>,
    c_push: Signal<Local, Bit>,
    c_last: Signal<Local, Bit>,
    /// Bits S-1..A-1 of acc.
    top: Signal<Local, Bits<32>>,
    hit: Signal<Local, Bit>,
    sat: Signal<Local, Bits<32>>,
    yout: Signal<Local, Bits<32>>,
    /// Mask of the D data bits.
    dmask: Constant<Bits<32>>,
    /// Mask of the S state bits.
    smask: Constant<Bits<32>>,
    /// Mask of the A accumulator bits.
    amask: Constant<Bits<32>>,
    /// Sign bit of the accumulator (2^(A-1)).
    asign: Constant<Bits<32>>,
    /// Bits S-1..A-1: acc is in the S-bit range iff they are all 0 or all 1.
    tmask: Constant<Bits<32>>,
    /// Largest S-bit value (2^(S-1) - 1).
    smax: Constant<Bits<32>>,
    /// Smallest S-bit value as raw S bits (2^(S-1)).
    smin: Constant<Bits<32>>,
    /// Guard bits G (shift amount).
    guard: Constant<Bits<32>>,
    /// Mask of the program counter bits.
    pcmask: Constant<Bits<32>>,
    /// Mask of the RAM address bits.
    admask: Constant<Bits<32>>,
    /// Last state word (W - 1): end of the clearing sweep.
    wlast: Constant<Bits<32>>,
    /// Control bit masks.
    k_addr: Constant<Bits<32>>,
    k_we: Constant<Bits<32>>,
    k_wsrc: Constant<Bits<32>>,
    k_ldx: Constant<Bits<32>>,
    k_xin: Constant<Bits<32>>,
    k_opx: Constant<Bits<32>>,
    k_acc: Constant<Bits<32>>,
    k_first: Constant<Bits<32>>,
    k_push: Constant<Bits<32>>,
    k_last: Constant<Bits<32>>,
    one: Constant<Bits<32>>,
    zero: Constant<Bits<32>>,
}

impl BiquadRtl {
    /// Engine for validated parameters.
    pub fn new(p: &BiquadParams) -> Self {
        let k = p.branch_count();
        let s = p.state_width();
        let a = p.acc_width();
        BiquadRtl {
            clk: Default::default(),
            rst: Default::default(),
            in_valid: Default::default(),
            in_data: (0..k).map(|_| Signal::default()).collect(),
            out_valid: Default::default(),
            out_data: (0..k).map(|_| Signal::default()).collect(),
            overflow: Default::default(),
            busy: Default::default(),
            dropped: Default::default(),
            prog: BiquadProgram::new(p),
            ram: BiquadStateRam::new(p.state_words(), s, p.addr_width()),
            mul: BiquadMul::new(s, p.coef_width, p.coef_frac),
            busy_reg: Default::default(),
            clr_reg: Default::default(),
            clr_addr: Default::default(),
            pc: Default::default(),
            ctrl_reg: Default::default(),
            coefw_reg: Default::default(),
            opa: Default::default(),
            opb: Default::default(),
            parity: Default::default(),
            xcur: Default::default(),
            coef_reg: Default::default(),
            prod_reg: Default::default(),
            acc: Default::default(),
            sample_ovf: Default::default(),
            valid_reg: Default::default(),
            ovf_reg: Default::default(),
            drop_reg: Default::default(),
            in_lat: (0..k).map(|_| DFF::default()).collect(),
            osel: (0..k).map(|_| DFF::default()).collect(),
            out_sh: (0..k).map(|_| DFF::default()).collect(),
            out_reg: (0..k).map(|_| DFF::default()).collect(),
            ctrl_w: Default::default(),
            pc_n: Default::default(),
            c_we: Default::default(),
            c_wsrc: Default::default(),
            c_ldx: Default::default(),
            c_xin: Default::default(),
            c_opx: Default::default(),
            c_acc: Default::default(),
            c_first: Default::default(),
            c_push: Default::default(),
            c_last: Default::default(),
            top: Default::default(),
            hit: Default::default(),
            sat: Default::default(),
            yout: Default::default(),
            dmask: c32(mask(p.data_width)),
            smask: c32(mask(s)),
            amask: c32(mask(a)),
            asign: c32(1 << (a - 1)),
            tmask: c32(mask(a) & !mask(s - 1)),
            smax: c32(mask(s - 1)),
            smin: c32(1 << (s - 1)),
            guard: c32(p.guard_frac as u64),
            pcmask: c32(mask(p.pc_width())),
            admask: c32(mask(p.addr_width())),
            wlast: c32(p.state_words() as u64 - 1),
            k_addr: c32(ctrl::ADDR_MASK as u64),
            k_we: c32(ctrl::WE as u64),
            k_wsrc: c32(ctrl::WSRC_ACC as u64),
            k_ldx: c32(ctrl::LDX as u64),
            k_xin: c32(ctrl::XIN as u64),
            k_opx: c32(ctrl::OPX as u64),
            k_acc: c32(ctrl::ACC as u64),
            k_first: c32(ctrl::FIRST as u64),
            k_push: c32(ctrl::PUSH as u64),
            k_last: c32(ctrl::LAST as u64),
            one: c32(1),
            zero: c32(0),
        }
    }
}

impl Logic for BiquadRtl {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clk, busy_reg, clr_reg, clr_addr, pc, ctrl_reg, coefw_reg, opa, opb, parity,
            xcur, coef_reg, prod_reg, acc, sample_ovf, valid_reg, ovf_reg, drop_reg
        );
        for i in 0..self.in_lat.len() {
            self.in_lat[i].clock.next = self.clk.val();
            self.in_lat[i].d.next = self.in_lat[i].q.val();
            self.osel[i].clock.next = self.clk.val();
            self.osel[i].d.next = self.osel[i].q.val();
            self.out_sh[i].clock.next = self.clk.val();
            self.out_sh[i].d.next = self.out_sh[i].q.val();
            self.out_reg[i].clock.next = self.clk.val();
            self.out_reg[i].d.next = self.out_reg[i].q.val();
        }
        // Program word of this clock, read at the previous clock's next pc.
        self.ctrl_w.next = self.ctrl_reg.q.val();
        self.c_we.next = (self.ctrl_w.val() & self.k_we.val()) != self.zero.val();
        self.c_wsrc.next = (self.ctrl_w.val() & self.k_wsrc.val()) != self.zero.val();
        self.c_ldx.next = (self.ctrl_w.val() & self.k_ldx.val()) != self.zero.val();
        self.c_xin.next = (self.ctrl_w.val() & self.k_xin.val()) != self.zero.val();
        self.c_opx.next = (self.ctrl_w.val() & self.k_opx.val()) != self.zero.val();
        self.c_acc.next = (self.ctrl_w.val() & self.k_acc.val()) != self.zero.val();
        self.c_first.next = (self.ctrl_w.val() & self.k_first.val()) != self.zero.val();
        self.c_push.next = (self.ctrl_w.val() & self.k_push.val()) != self.zero.val();
        self.c_last.next = (self.ctrl_w.val() & self.k_last.val()) != self.zero.val();
        // The single multiplier: operand xcur or RAM data, times the coefficient register,
        // both registered (op), and the product registered.
        self.opa.d.next = self.ram.q.val();
        if self.c_opx.val() {
            self.opa.d.next = self.xcur.q.val();
        }
        self.opb.d.next = self.coef_reg.q.val();
        self.mul.a.next = self.opa.q.val();
        self.mul.b.next = self.opb.q.val();
        self.prod_reg.d.next = self.mul.p.val() & self.amask.val();
        // Saturation of the accumulator to S bits: out of range iff bits S-1..A-1 differ.
        self.top.next = self.acc.q.val() & self.tmask.val();
        self.hit.next = (self.top.val() != self.zero.val()) & (self.top.val() != self.tmask.val());
        self.sat.next = self.acc.q.val() & self.smask.val();
        if self.hit.val() {
            if (self.acc.q.val() & self.asign.val()) != self.zero.val() {
                self.sat.next = self.smin.val();
            } else {
                self.sat.next = self.smax.val();
            }
        }
        self.yout.next = (self.sat.val() >> self.guard.val()) & self.dmask.val();
        // State RAM port: program address XOR sample parity.
        self.ram.clk.next = self.clk.val();
        self.ram.addr.next =
            ((self.ctrl_w.val() & self.k_addr.val()) ^ self.parity.q.val()) & self.admask.val();
        self.ram.we.next = false;
        self.ram.wd.next = self.xcur.q.val();
        if self.c_wsrc.val() {
            self.ram.wd.next = self.sat.val();
        }
        self.valid_reg.d.next = false;
        self.ovf_reg.d.next = false;
        self.drop_reg.d.next = false;
        self.pc_n.next = self.pc.q.val();
        if self.rst.val() {
            self.busy_reg.d.next = false;
            self.clr_reg.d.next = true;
            self.clr_addr.d.next = self.zero.val();
            self.pc_n.next = self.zero.val();
            self.parity.d.next = self.zero.val();
            for i in 0..self.out_reg.len() {
                self.out_reg[i].d.next = self.zero.val();
            }
        } else if self.clr_reg.q.val() {
            // Clearing sweep: one zero word per clock.
            self.ram.addr.next = self.clr_addr.q.val() & self.admask.val();
            self.ram.we.next = true;
            self.ram.wd.next = self.zero.val();
            self.clr_addr.d.next = (self.clr_addr.q.val() + self.one.val()) & self.admask.val();
            if self.clr_addr.q.val() == self.wlast.val() {
                self.clr_reg.d.next = false;
            }
            self.drop_reg.d.next = self.in_valid.val();
        } else if !self.busy_reg.q.val() {
            if self.in_valid.val() {
                for i in 0..self.in_lat.len() {
                    self.in_lat[i].d.next = self.in_data[i].val() & self.dmask.val();
                    self.osel[i].d.next = false;
                }
                self.osel[0].d.next = true;
                self.busy_reg.d.next = true;
                self.pc_n.next = self.zero.val();
                self.sample_ovf.d.next = false;
            }
        } else {
            self.drop_reg.d.next = self.in_valid.val();
            self.pc_n.next = (self.pc.q.val() + self.one.val()) & self.pcmask.val();
            self.coef_reg.d.next = self.coefw_reg.q.val();
            if self.c_we.val() {
                self.ram.we.next = true;
            }
            if self.c_ldx.val() {
                if self.c_xin.val() {
                    self.xcur.d.next =
                        (self.in_lat[0].q.val() << self.guard.val()) & self.smask.val();
                    for i in 1..self.in_lat.len() {
                        self.in_lat[i - 1].d.next = self.in_lat[i].q.val();
                    }
                } else {
                    self.xcur.d.next = self.sat.val();
                    self.sample_ovf.d.next = self.sample_ovf.q.val() | self.hit.val();
                }
            }
            if self.c_acc.val() {
                if self.c_first.val() {
                    self.acc.d.next = self.prod_reg.q.val();
                } else {
                    self.acc.d.next = (self.acc.q.val() + self.prod_reg.q.val()) & self.amask.val();
                }
            }
            if self.c_push.val() {
                for i in 0..self.out_sh.len() {
                    if self.osel[i].q.val() {
                        self.out_sh[i].d.next = self.yout.val();
                    }
                }
                self.osel[0].d.next = false;
                for i in 1..self.osel.len() {
                    self.osel[i].d.next = self.osel[i - 1].q.val();
                }
                self.sample_ovf.d.next = self.sample_ovf.q.val() | self.hit.val();
            }
            if self.c_last.val() {
                self.busy_reg.d.next = false;
                self.pc_n.next = self.zero.val();
                self.parity.d.next = self.parity.q.val() ^ self.one.val();
                self.valid_reg.d.next = true;
                self.ovf_reg.d.next = self.sample_ovf.q.val();
                for i in 0..self.out_reg.len() {
                    self.out_reg[i].d.next = self.out_sh[i].q.val();
                }
            }
        }
        self.pc.d.next = self.pc_n.val();
        self.prog.pc.next = self.pc_n.val();
        self.ctrl_reg.d.next = self.prog.ctrl.val();
        self.coefw_reg.d.next = self.prog.coef.val();
        for i in 0..self.out_data.len() {
            self.out_data[i].next = self.out_reg[i].q.val();
        }
        self.out_valid.next = self.valid_reg.q.val();
        self.overflow.next = self.ovf_reg.q.val();
        self.busy.next = self.busy_reg.q.val() | self.clr_reg.q.val();
        self.dropped.next = self.drop_reg.q.val();
    }
}

impl crate::cosim::step::Clocked for BiquadRtl {
    fn set_clock(&mut self, high: bool) {
        self.clk.next = Clock::from(high);
    }
}

impl crate::cosim::CosimBlock for BiquadRtl {
    fn input_ports(&self) -> Vec<Port> {
        let mut v = vec![Port::new("rst", 1), Port::new("in_valid", 1)];
        v.extend((0..self.in_data.len()).map(|k| Port::new(&format!("in_data_{k}"), 32)));
        v
    }
    fn output_ports(&self) -> Vec<Port> {
        let mut v = vec![Port::new("out_valid", 1)];
        v.extend((0..self.out_data.len()).map(|k| Port::new(&format!("out_data_{k}"), 32)));
        v.push(Port::new("overflow", 1));
        v.push(Port::new("busy", 1));
        v.push(Port::new("dropped", 1));
        v
    }
    fn apply(&mut self, r: &[u64]) {
        self.rst.next = r.first().copied().unwrap_or(0) != 0;
        self.in_valid.next = r.get(1).copied().unwrap_or(0) != 0;
        for (k, s) in self.in_data.iter_mut().enumerate() {
            s.next = Bits::<32>::from(r.get(2 + k).copied().unwrap_or(0) & 0xffff_ffff);
        }
    }
    fn sample(&self) -> Vec<u64> {
        let mut v = vec![self.out_valid.val() as u64];
        v.extend(self.out_data.iter().map(|s| s.val().to_u64()));
        v.push(self.overflow.val() as u64);
        v.push(self.busy.val() as u64);
        v.push(self.dropped.val() as u64);
        v
    }
}
