//! rust-hdl description of the velocity block (maths, fixed point and sketch in the module
//! docs of [`crate::blocks::velocity`]; the schedule below and in `docs/velocity.md`).
//! [`VelocityModel`](super::model::VelocityModel) is its cycle reference.
//!
//! Words: every datapath word is a `Bits<64>` holding a w-bit two's-complement value in its
//! low w bits (upper bits zero), w from [`VelocityParams`] through per-instance masks, as
//! in the other blocks (`crate::blocks`); the product (up to 127 bits) lives in the leaf
//! [`VelMul`], whose Verilog is hand-written. The widths hold every word as long as the
//! position changes by at most `max_step` per update period (the contract the widths are
//! derived from); beyond it the RTL's words wrap where the model's i64/i128 do not.
//!
//! Schedule of one update (E0 = the divider's tick edge; one multiply = n + 3 clocks:
//! operand register and multiplier start in `Op`, n + 1 multiplier clocks in `Prod` (x
//! cleared, then n radix-4 Booth digits: [`VelMul`]), accumulate; latency (n + 3) m + 2 =
//! [`VelocityParams::latency`], n = [`Layout::mul_steps`]):
//! ```text
//! edge   E0     E1     E2    E3 .. E(n+3)   E(n+4)  ...  E((n+3)m+1)  E((n+3)m+2)
//! state  Idle > Prep > Op  > Prod x (n+1) > Acc   > Op ...  Acc    >  Out > Idle
//! does   snap   diffs  opa,  Booth digits   acc += p         acc      out_velocity,
//!        (prime)       start                                          strobe
//! diff_lpf, kalman (m = 1): E0 d = Delta; Prep d = U - X; Acc X += p.  Out: y = q(X / 2^G)
//! tracking (m = 2): E0 tx = W (theta 2^(S+G) at the first update); Prep e, Theta += tx;
//!   Acc 1: W += p = q(beta e), Theta += p (Theta + W_new); Acc 2: Theta += p = q(alpha e).
//! lsq (m = M): Acc i < M: P += n_i r_i (r_i from the rotating history; tap n_i 2^B);
//!   Op M: a = P, P := 0; Acc M: P += q(P R / 2^B).
//! ```
//! Timing: every register-to-register path holds one carry chain at most (no adder feeds
//! another within a clock), and at most one LUT after it: the front end takes the bits
//! above F+2 from one adder, padj - in_p - 1, where padj = pos + 2^(F+1) is kept beside pos
//! (no select of candidates after the chain); Delta is taken at the tick, U - X a clock
//! later; Theta's one adder adds a register (`tx` or the multiplier's R); the tick, "last
//! multiply" and "last multiplier clock" are registered; the multiplier's adder adds
//! registers only. The schedule is one [`VelState`] register; `j` and `mwait` have their
//! own widths (bits(m - 1), bits(n)), so their compares are narrow.
pub use super::layout::Layout;
use super::parts::{VelCoefRom, VelMul};
use super::{MethodConsts, VelocityParams};
use crate::blocks::mask;
use crate::error::Result;
use rust_hdl::prelude::*;

mod update;

/// Where the update is in its schedule (the states of the sketch above).
#[derive(Copy, Clone, PartialEq, Eq, Debug, LogicState)]
pub enum VelState {
    /// Waiting for a tick (reset and power-up).
    Idle,
    /// Differences of this update into `d` (lsq: shift the history, clear P).
    Prep,
    /// Multiplier operands registered, multiplier started.
    Op,
    /// Multiplier running: n + 1 clocks (x cleared, then n Booth digits).
    Prod,
    /// Product accumulated.
    Acc,
    /// Output register loaded, strobe raised.
    Out,
}

fn c64(v: u64) -> Constant<Bits<64>> {
    Constant::new(Bits::<64>::from(v))
}

fn c32(v: u64) -> Constant<Bits<32>> {
    crate::blocks::c32(v)
}

/// Bits needed for the values 0..=v (0 for v = 0).
fn bits(v: u64) -> u32 {
    64 - v.leading_zeros()
}

/// Bits of a 64-bit word above the low `w`: OR-ed into a negative w-bit value to sign-extend.
fn ext(w: u32) -> u64 {
    !mask(w)
}

/// The velocity estimator (ports below; maths in the module docs of `velocity`).
#[derive(LogicBlock)]
pub struct Velocity {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high: everything to 0, a pending result is dropped.
    pub rst: Signal<In, Bit>,
    /// Decoded position modulo 2^(F+2) (the low F+2 bits; higher bits ignored).
    pub in_p: Signal<In, Bits<32>>,
    /// A decoded sample is on `in_p` this clock.
    pub in_valid: Signal<In, Bit>,
    /// Velocity, `width`-bit two's complement in the low bits (upper bits zero), held
    /// between strobes: 2^-(F + frac_bits) quadrant per update period.
    pub out_velocity: Signal<Out, Bits<64>>,
    /// One-clock strobe: `out_velocity` is new (once per update period).
    pub out_velocity_valid: Signal<Out, Bit>,
    /// The single multiplier.
    mul: VelMul,
    /// The coefficient ROM (address j, or k for kalman).
    rom: VelCoefRom,
    /// A sample has loaded `pos`.
    init: DFF<Bit>,
    /// Unwrapped position theta, Wp bits.
    pos: DFF<Bits<64>>,
    /// pos + 2^(F+1) modulo 2^Wp, kept beside pos: the front end's one adder reads it.
    padj: DFF<Bits<64>>,
    /// The update divider's count, 0..D-1.
    cnt: DFF<Bits<32>>,
    /// The divider's tick, registered: high while `cnt` = D - 1 (keeps the `cnt` compare
    /// off the cnt -> state and cnt -> snap paths).
    tickr: DFF<Bit>,
    /// The schedule's state.
    state: DFF<VelState>,
    /// `mwait` = n in `Prod` (the multiplier's last clock), registered a clock ahead: keeps
    /// the `mwait` compare off the mwait -> state path.
    mlast: DFF<Bit>,
    /// The multiply of this update, 0..m-1 (bits(m - 1) bits).
    j: DFF<Bits<32>>,
    /// j = m - 1 (this is the last multiply), registered with j: keeps the `j` compare off
    /// the j -> state and j -> accumulator paths.
    jlr: DFF<Bit>,
    /// The first update has run (the history holds positions).
    primed: DFF<Bit>,
    /// This update is the first.
    first: DFF<Bit>,
    /// theta at this update's tick.
    snap: DFF<Bits<64>>,
    /// diff_lpf/kalman: positions theta(k-1) (one); lsq: the M newest, oldest first.
    hist: Vec<DFF<Bits<64>>>,
    /// The multiplier's next operand: Delta then U - X (diff_lpf/kalman), e (tracking); `d`
    /// in the module docs (not named `d`: its DFF's port `d` would hide it, VARHIDDEN).
    opd: DFF<Bits<64>>,
    /// Tracking: the loop's position Theta (Wp + S + G bits).
    theta: DFF<Bits<64>>,
    /// The accumulator: X, W or P.
    acc: DFF<Bits<64>>,
    /// Kalman: index of the gain in use (stops at the table's last).
    k: DFF<Bits<32>>,
    /// Tracking: Theta's addend in `Prep` (theta 2^(S+G) at the first update, else W).
    tx: DFF<Bits<64>>,
    /// The state is `Prep` (registered with it, without the reset): Theta's addend select,
    /// so that the select of Theta's 41-bit chain is one flip-flop with no other load (after
    /// a reset it may be high for a clock in which nothing adds to Theta).
    tsel: DFF<Bit>,
    /// Clocks waited in `Prod` for the multiplier, 0..n (bits(n) bits).
    mwait: DFF<Bits<32>>,
    /// The multiplier's operand a.
    opa: DFF<Bits<64>>,
    /// `out_velocity`.
    out_reg: DFF<Bits<64>>,
    /// `out_velocity_valid`.
    valid_reg: DFF<Bit>,
    /// in_p's low F+2 bits.
    inp: Signal<Local, Bits<64>>,
    /// in_p's F+2 bits sign-extended to Wp bits.
    sinp: Signal<Local, Bits<64>>,
    /// padj - in_p - 1 and padj - sext(in_p) - 1 (Wp bits): their bits above F+2 are
    /// pos's and padj's next high bits.
    vpos: Signal<Local, Bits<64>>,
    vadj: Signal<Local, Bits<64>>,
    tick: Signal<Local, Bit>,
    jl: Signal<Local, Bit>,
    delta: Signal<Local, Bits<64>>,
    sdelta: Signal<Local, Bits<64>>,
    /// Tracking: what `Theta` adds this clock: `tx` in `Prep`, else the product.
    tadd: Signal<Local, Bits<64>>,
    meas: Signal<Local, Bits<64>>,
    r: Signal<Local, Bits<64>>,
    rext: Signal<Local, Bits<64>>,
    pa: Signal<Local, Bits<64>>,
    yr: Signal<Local, Bits<64>>,
    ys: Signal<Local, Bits<64>>,
    /// Index of the last history entry (a loop bound: rust-hdl indexes only by loop index).
    _hlast: usize,
    /// Masks of F+2 bits and its sign bit.
    f2mask: Constant<Bits<64>>,
    f2sign: Constant<Bits<64>>,
    /// 2^(F+2): padj's bit F+2 when the first sample loads it with a negative in_p.
    f2one: Constant<Bits<64>>,
    /// Bits F+2 .. Wp-1: in_p's sign extension.
    f2ext: Constant<Bits<64>>,
    /// Masks of Wp bits, its sign bit, the bits above it.
    wpmask: Constant<Bits<64>>,
    wpsign: Constant<Bits<64>>,
    wpext: Constant<Bits<64>>,
    /// Mask of the state words (diff_lpf/kalman d, U).
    smask: Constant<Bits<64>>,
    /// Mask of Theta (Wp + S + G bits).
    twmask: Constant<Bits<64>>,
    /// Mask of the multiplier's operand a.
    amask: Constant<Bits<64>>,
    /// Mask of the accumulator, its sign bit, the bits above it.
    accmask: Constant<Bits<64>>,
    accsign: Constant<Bits<64>>,
    accext: Constant<Bits<64>>,
    /// S + G: position to state alignment.
    sg: Constant<Bits<32>>,
    /// G: the output's rounding shift, and 2^(G-1) (0 when G = 0).
    g: Constant<Bits<32>>,
    ghalf: Constant<Bits<64>>,
    /// Bits above acc_width - G: sign extension after the output's shift.
    yext: Constant<Bits<64>>,
    /// Mask of `width` bits.
    ymask: Constant<Bits<64>>,
    /// D - 2: the count before the divider's last.
    dprev: Constant<Bits<32>>,
    /// n - 1 (n: the multiplier's Booth digits, the last count of `mwait`); mask of
    /// `mwait` (bits(n)).
    wprev: Constant<Bits<32>>,
    wmask: Constant<Bits<32>>,
    /// m - 2: the multiply before the last (unused when m = 1), and m = 1; mask of `j`
    /// (bits(m - 1)).
    jprev: Constant<Bits<32>>,
    jmask: Constant<Bits<32>>,
    jl0: Constant<Bit>,
    /// Last entry of the Kalman gain table.
    klast: Constant<Bits<32>>,
    /// ROM address select: all ones for j (not kalman) / for k (kalman), else zero.
    jsel: Constant<Bits<32>>,
    ksel: Constant<Bits<32>>,
    /// Method flags.
    is_lsq: Constant<Bit>,
    is_track: Constant<Bit>,
    is_kal: Constant<Bit>,
    one: Constant<Bits<32>>,
    zero: Constant<Bits<32>>,
    zero64: Constant<Bits<64>>,
    one64: Constant<Bits<64>>,
}

impl Velocity {
    /// The block for validated parameters (an error if its words exceed 64 bits).
    pub fn new(p: &VelocityParams) -> Result<Self> {
        let l = Layout::new(p)?;
        let f2 = p.spec.fine_bits + 2;
        let wp = p.pos_width;
        let ws = p.state_width;
        let aw = l.acc_width;
        let g = p.guard;
        let nhist = match &p.consts {
            MethodConsts::Lsq { n, .. } => n.len(),
            _ => 1,
        };
        let is_kal = matches!(p.consts, MethodConsts::Kalman { .. });
        let klast = match &p.consts {
            MethodConsts::Kalman { gains } => gains.len() as u64 - 1,
            _ => 0,
        };
        Ok(Velocity {
            clk: Default::default(),
            rst: Default::default(),
            in_p: Default::default(),
            in_valid: Default::default(),
            out_velocity: Default::default(),
            out_velocity_valid: Default::default(),
            mul: VelMul::new(l.a_width, l.b_width, aw, l.shift),
            rom: VelCoefRom::new(&l.coefs, l.b_width),
            init: Default::default(),
            pos: Default::default(),
            padj: Default::default(),
            cnt: Default::default(),
            tickr: Default::default(),
            state: Default::default(),
            mlast: Default::default(),
            j: Default::default(),
            jlr: Default::default(),
            primed: Default::default(),
            first: Default::default(),
            snap: Default::default(),
            hist: (0..nhist).map(|_| DFF::default()).collect(),
            opd: Default::default(),
            theta: Default::default(),
            acc: Default::default(),
            k: Default::default(),
            tx: Default::default(),
            tsel: Default::default(),
            mwait: Default::default(),
            opa: Default::default(),
            out_reg: Default::default(),
            valid_reg: Default::default(),
            inp: Default::default(),
            sinp: Default::default(),
            vpos: Default::default(),
            vadj: Default::default(),
            tick: Default::default(),
            jl: Default::default(),
            delta: Default::default(),
            sdelta: Default::default(),
            tadd: Default::default(),
            meas: Default::default(),
            r: Default::default(),
            rext: Default::default(),
            pa: Default::default(),
            yr: Default::default(),
            ys: Default::default(),
            _hlast: nhist - 1,
            f2mask: c64(mask(f2)),
            f2sign: c64(1 << (f2 - 1)),
            f2one: c64(1 << f2),
            f2ext: c64(mask(wp) & !mask(f2)),
            wpmask: c64(mask(wp)),
            wpsign: c64(1 << (wp - 1)),
            wpext: c64(ext(wp)),
            smask: c64(mask(ws)),
            twmask: c64(mask(l.theta_width)),
            amask: c64(mask(l.a_width)),
            accmask: c64(mask(aw)),
            accsign: c64(1 << (aw - 1)),
            accext: c64(ext(aw)),
            sg: c32(p.state_frac() as u64),
            g: c32(g as u64),
            ghalf: c64(if g == 0 { 0 } else { 1 << (g - 1) }),
            yext: c64(ext(aw - g)),
            ymask: c64(mask(p.spec.width)),
            dprev: c32(p.period_clocks - 2),
            wprev: c32(l.mul_steps() as u64 - 1),
            wmask: c32(mask(bits(l.mul_steps() as u64))),
            jprev: c32((l.mults as u64).wrapping_sub(2) & mask(32)),
            jmask: c32(mask(bits(l.mults as u64 - 1))),
            jl0: Constant::new(l.mults == 1),
            klast: c32(klast),
            jsel: c32(if is_kal { 0 } else { mask(32) }),
            ksel: c32(if is_kal { mask(32) } else { 0 }),
            is_lsq: Constant::new(matches!(p.consts, MethodConsts::Lsq { .. })),
            is_track: Constant::new(matches!(p.consts, MethodConsts::Tracking { .. })),
            is_kal: Constant::new(is_kal),
            one: c32(1),
            zero: c32(0),
            zero64: c64(0),
            one64: c64(1),
        })
    }
}

crate::cosim::cosim_block!(Velocity {
    inputs: [rst: 1, in_p: 32, in_valid: 1],
    outputs: [out_velocity: 64, out_velocity_valid: 1],
});
