//! rust-hdl description of the end-of-window solve of the ellipse fit: the integer
//! specification of [`super::fit::solve`] on one serial shift-add multiplier and one serial
//! non-restoring divider / square root, all three on one shared adder, sequenced by a state
//! machine.
//!
//! ```text
//!  start ─► snapshot N, |Σd| (+sign), Σd², Σd_s d_c (its magnitude two clocks later), b_ref
//!   │
//!   ▼ one operation at a time on the shared units (u_x, u_d, u_r, it):
//!  m_s,m_c = rdiv(|Σd| 2^8, N)      DIV 64 steps   V = floor(Σd² 2^16 / N)  DIV 80 steps
//!  Cq = floor(Σsc 2^16 / N)         DIV 80 steps   V -= m², C = Cq - m_s m_c  MUL 32 steps
//!  Amp = isqrt(2V)                  SQRT 32 steps  Amp < min 2^8 (checked after Amp_s Amp_c) ► Idle
//!  S = rdiv(-C 2^16, Amp_s Amp_c)   MUL, DIV       |S| <= smax; Cc = isqrt(2^30 - S²)
//!  b = b_ref + rdiv(m, 2^8)         add, out of range (checked after g_s's DIV) ► Idle
//!  g_s, g_c, k                      MUL, DIV x 3, clamp ──► Load: all coefficients at once
//!
//!  shared adder, one 53-bit carry chain, each step over two clocks:
//!    B clock: oa = opa, ob = {opb, cin}: opa = 2 u_r (+ msb(u_x)) or 4 u_r + top2(u_x);
//!             opb = up ? u_d : !u_d (!0 in a MUL), cin = !up, up = u_r < 0 (MUL: msb(u_x));
//!             one LUT a bit from registers (u_r, u_x, u_d, flags); the previous step's
//!             bit (!sign of u_r) into u_x bit 0 (DIV) or into u_d (SQRT)
//!    A clock: u_r = ({oa, 1} + ob) >> 1 (the chain and nothing else); u_x <<= 1 (2 in a SQRT)
//!    ┌──────────┐  B   ┌─────────┐  A   ┌────────────┐
//!    │u_r u_x u_d├─LUT─►│ oa  ob  ├─+───►│ u_r (52 b) │── sign ──► next B
//!    └──────────┘      └─────────┘      └────────────┘
//!  DIV (non-restoring, dividend and quotient share u_x):  SQRT (non-restoring, 2 bits a step):
//!    t = 2 u_r + msb(u_x)                                   t = 4 u_r + top2(u_x)
//!    u_r = u_r < 0 ? t + u_d : t - u_d                      u_r = u_r < 0 ? t + (4q+3) : t - (4q+1)
//!    u_x = 2 u_x + (u_r >= 0)                               q = 2 q + (u_r >= 0); u_d = 8 q + 1
//!  (the quotient bits equal the restoring ones; the true remainder is u_r, or u_r + u_d
//!  when u_r < 0, zero when u_r + u_d = 0: (u_r ^ u_d) == (u_r | u_d) << 1, no chain)
//!  then: adj = round ? 2 r >= u_d (sign of the rounding sum 2 u_r -+ u_d, one more A clock)
//!  : neg & r != 0 (registered zero tests rz, req); u_mag = u_x + adj and the signed
//!  u_q = uxs + (adj ^ neg), uxs = neg ? !u_x : u_x (free-running), i.e. -(u_x + adj) =
//!  !u_x + !adj or u_x + adj, one chain from registers (adj the carry in); u_x = u_q
//!  MUL (MSB first, multiplier a < 2^32 in the top half of u_x, 32 steps):
//!    u_r = 2 u_r + (msb(u_x) ? u_d : 0); u_x <<= 1
//!
//!  control, one-hot: a flag per state (s_*), set for one clock by the state before; a
//!  set-up state leaves its successor pending (p_*) with the loads of the return (rx_*,
//!  rd_*) and sets the mode flag of its run; the run returns with f_ret (a product's or
//!  square root's last B clock, a division's sign state DivNeg):
//!    s_P ──► p_X, rx_*, rd_*, f_div|f_sq|f_mul ──► run ── f_ret ──► s_X, x_*, d_*
//!  each wide register loads on one state flag; u_x and u_d AND-OR their sources by
//!  one-hot load flags (x_*, d_*) under one registered enable (x_en, d_en); the sources a
//!  return loads are final long before it and reach u_x / u_d through free-running
//!  registers (uxr, udr); compares, sums and negations the states need (clamps,
//!  amplitude and offset checks, 2^30 - S², V - m² (one register for V_s, V_c), -C, Cq ±
//!  |m_s m_c|, the remainder's
//!  zero tests) are free-running registers, read a state after their inputs settle
//!  (u_mag's clamps from the quotient u_x, two clocks ahead); the run's flags and `it`
//!  follow the registered mode flags
//! ```
//!
//! # Bit growth (A <= 16, N <= N_MAX = 2^24, T < 2^15, GF <= 15)
//! * |Σd| < 2^(A+24) = 2^40, so |Σd| 2^8 < 2^48; Σd² and |Σd_s d_c| < 2^(2A+24) = 2^56.
//! * Division by N of Σd² 2^16 (72 bits) needs no 72-bit word: the dividend is Σd² and the
//!   divider runs 80 steps instead of 64; after 64 steps the bits entering from the top of
//!   u_x are the quotient's bits 79..64, which are zero because the quotient
//!   floor(Σd² 2^16 / N) < 2^(2A+16) <= 2^48 — exactly the 16 zero bits the dividend needs.
//! * Remainders are below the divisor; the largest divisor is Amp_s Amp_c < 2^49
//!   (Amp = isqrt(2V), V <= 2^(2A-2+16) because a variable in a range of width 2^A has a
//!   variance of at most 2^(2A-2)), so |2 u_r + 1| < 2^50; the non-restoring remainder
//!   lies in [-u_d, u_d), so every sum of the shared adder is below 2^51 in magnitude (the
//!   square root's below 2^36, the products below 2^50): u_r, u_d and the chain's operands
//!   are 52-bit two's complement words (the chain is 53 bits: bit 0 carries cin in) and
//!   never wrap. Every value u_d loads (N, m, Amp, |S|, Cc, Amp_s Cc, a product, 8 q + 1
//!   < 2^36) is below 2^50, and every u_r another register reads (a product) is
//!   non-negative, so the 52-bit words are zero-extended to 64 bits.
//! * |C| <= sqrt(V_s V_c) < 2^(2A+14) <= 2^46, so |C| 2^16 < 2^62; T 2^(GF+23) < 2^53;
//!   T |S| 2^(GF+8) < 2^52; every dividend fits 64 bits (u_x stays 64 bits).
//! * Multiplier operands: |m| < 2^(A+8) <= 2^24, Amp < 2^25, |S| < 2^14, Cc <= 2^15, T < 2^15:
//!   all below 2^32 (the 32 steps), products below 2^50.
//! * Stored values at the widths these bounds give (Yosys cannot know them: a 64-bit
//!   register keeps every bit some read uses, and the LUTs of their load select): N 25 bits, |Σd| 40,
//!   Σd² and |Σd_s d_c| 56, |m| 24 (|Σd| 2^8 / N <= (2^16 - 1) 2^8 < 2^24, and the rounding
//!   stays below), V 49 (two's complement: floor(Σd² 2^16 / N) < 2^48 less m² < 2^48), C 50
//!   (|Cq| < 2^48 plus |m_s m_c| < 2^48), |C| 48 (the bits |C| 2^16 keeps), Amp 25, |S| and
//!   Cc 16, Amp_s Cc 40, 2^30 - S² 31, the quotient's magnitude u_mag 24 (read as m, or
//!   under a clamp below 2^16). A difference such as V - m² is taken in the narrow width:
//!   its low bits are exact, and the true value fits. `tests/blocks/correction_fit_solver.rs`
//!   drives the solver at these bounds (N = 2^24, |d| = 2^16 - 1, full correlation); with
//!   m one bit narrower it fails.
//! * Each state writes its registers through at most one adder or compare (the timing rule
//!   of docs/correction.md): abs, add, round and negate are separate states or free-running
//!   registers.
//! * The root has 32 bits (32 steps, one bit each; in u_d as 8 q + 1 while it grows);
//!   `it` counts at most 80 steps: 8 bits.
//!
//! # Timing
//! [`SOLVE_CYCLES`] clocks from `start` to `done` when the update is accepted (fewer when
//! refused). The window that follows must last longer (`min_samples` x clocks per sample),
//! which the config checks; a window that ends while the solver is busy is dropped.
use super::autocal::c16;
use super::fit::N_MAX;
use super::{CorrectionParams, COS, SIN};
use crate::blocks::{c32, mask};
use rust_hdl::prelude::*;

/// Clocks from the rising edge that takes `start` to the one that loads the coefficients
/// of an accepted solve. An operation of n steps runs 2 n + 1 clocks (B, then A and B per
/// step) after its set-up state; a division adds its rounding sum, decision, increment and
/// sign states: 6 divisions of 64 steps (1 + 129 + 4 = 134 clocks), 3 of 80 steps (166),
/// 8 multiplications and 3 square roots of 32 steps (1 + 65 = 66) and 4 single states:
/// 804 + 498 + 726 + 4.
pub const SOLVE_CYCLES: u32 =
    6 * (1 + (2 * 64 + 1) + 4) + 3 * (1 + (2 * 80 + 1) + 4) + 11 * (1 + (2 * 32 + 1)) + 4;

/// Clocks from a window's first sample after its closing boundary (the sample presented
/// before rising edge j) to the new coefficients (on the outputs after edge j +
/// UPDATE_LATENCY): the fit's pipeline stages ([`super::fit_hdl::FIT_STAGES`]), then [`SOLVE_CYCLES`];
/// `tests/blocks/correction_fit_rtl.rs` checks every update against it.
pub const UPDATE_LATENCY: u32 = SOLVE_CYCLES + super::fit_hdl::FIT_STAGES;

// The widths of the module doc assume windows of at most 2^24 samples.
const _: () = assert!(N_MAX <= 1 << 24);
const _: () = assert!(SOLVE_CYCLES == 2032);

/// A 64-bit constant.
pub(super) fn c64(v: u64) -> Constant<Bits<64>> {
    Constant::new(Bits::<64>::from(v))
}

/// An N-bit constant.
fn cw<const N: usize>(v: u64) -> Constant<Bits<N>> {
    Constant::new(Bits::<N>::from(v))
}

/// An 8-bit constant.
fn c8(v: u64) -> Constant<Bits<8>> {
    Constant::new(Bits::<8>::from(v))
}

/// The serial solver and the coefficient registers it loads.
#[derive(LogicBlock)]
pub struct FitSolve {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high: aborts a solve, restores the configured coefficients.
    pub rst: Signal<In, Bit>,
    /// One clock: take the window's sums below and solve.
    pub start: Signal<In, Bit>,
    /// Samples N of the window.
    pub n: Signal<In, Bits<32>>,
    /// Σd_s, two's complement.
    pub s1_s: Signal<In, Bits<64>>,
    /// Σd_c, two's complement.
    pub s1_c: Signal<In, Bits<64>>,
    /// Σd_s².
    pub s2_s: Signal<In, Bits<64>>,
    /// Σd_c².
    pub s2_c: Signal<In, Bits<64>>,
    /// Σd_s d_c, two's complement.
    pub ssc: Signal<In, Bits<64>>,
    /// Sine reference offset b_ref of the window, 32-bit two's complement.
    pub bref_s: Signal<In, Bits<32>>,
    /// Cosine reference offset b_ref of the window, 32-bit two's complement.
    pub bref_c: Signal<In, Bits<32>>,
    /// A solve is under way.
    pub busy: Signal<Out, Bit>,
    /// One clock when new coefficients have been loaded.
    pub done: Signal<Out, Bit>,
    /// Sine offset in use, 32-bit two's complement.
    pub off_s: Signal<Out, Bits<32>>,
    /// Cosine offset in use, 32-bit two's complement.
    pub off_c: Signal<Out, Bits<32>>,
    /// Sine gain code in use, UQ(16-GF).GF.
    pub g_s: Signal<Out, Bits<16>>,
    /// Cosine gain code in use (carries 1 / cos phi).
    pub g_c: Signal<Out, Bits<16>>,
    /// |k| of the cross code in use.
    pub k_mag: Signal<Out, Bits<16>>,
    /// k < 0 (never with |k| = 0).
    pub k_neg: Signal<Out, Bit>,
    /// A solve is under way (not idle): set by `start`, cleared after Load or a refusal.
    busy_r: DFF<Bit>,
    /// State ms (one clock): m_s = rdiv(Σd_s 2^8, N).
    s_ms: DFF<Bit>,
    /// State mc (one clock): m_c = rdiv(Σd_c 2^8, N).
    s_mc: DFF<Bit>,
    /// State vs (one clock): floor(Σd_s² 2^16 / N).
    s_vs: DFF<Bit>,
    /// State vc (one clock): floor(Σd_c² 2^16 / N).
    s_vc: DFF<Bit>,
    /// State cq (one clock): floor(Σd_s d_c 2^16 / N).
    s_cq: DFF<Bit>,
    /// State m1 (one clock): m_s².
    s_m1: DFF<Bit>,
    /// State m2 (one clock): V_s -= m_s²; m_c².
    s_m2: DFF<Bit>,
    /// State m3 (one clock): V_c -= m_c²; |m_s m_c|.
    s_m3: DFF<Bit>,
    /// State cv (one clock): C = Cq - m_s m_c.
    s_cv: DFF<Bit>,
    /// State sqs (one clock): Amp_s = isqrt(2 V_s).
    s_sqs: DFF<Bit>,
    /// State sqc (one clock): |C| (from C or its negation `ccn`); Amp_c = isqrt(2 V_c).
    s_sqc: DFF<Bit>,
    /// State chk (one clock): Amp_s Amp_c.
    s_chk: DFF<Bit>,
    /// State sn (one clock): amplitude check; S = rdiv(-C 2^16, Amp_s Amp_c).
    s_sn: DFF<Bit>,
    /// State sn2 (one clock): clamp S; S².
    s_sn2: DFF<Bit>,
    /// State offa (one clock): round(|m| / 2^8).
    s_offa: DFF<Bit>,
    /// State cs (one clock): Cc = isqrt(2^30 - S²).
    s_cs: DFF<Bit>,
    /// State offb (one clock): b = b_ref +- round(|m| / 2^8).
    s_offb: DFF<Bit>,
    /// State offc (one clock): g_s = rdiv(T 2^(GF+8), Amp_s).
    s_offc: DFF<Bit>,
    /// State q1 (one clock): offset range check; clamp g_s; Amp_c Cc.
    s_q1: DFF<Bit>,
    /// State gc (one clock): g_c = rdiv(T 2^(GF+23), Amp_c Cc).
    s_gc: DFF<Bit>,
    /// State q2 (one clock): clamp g_c; Amp_s Cc.
    s_q2: DFF<Bit>,
    /// State ts (one clock): T |S|.
    s_ts: DFF<Bit>,
    /// State kd (one clock): k = rdiv(T S 2^(GF+8), Amp_s Cc).
    s_kd: DFF<Bit>,
    /// State load (one clock): clamp k; load every coefficient.
    s_load: DFF<Bit>,
    /// State dadj (one clock, after a division's run): divider rounding sum (2 u_r -+ u_d).
    s_dadj: DFF<Bit>,
    /// State dtst (one clock, after a division's run): divider rounding decision.
    s_dtst: DFF<Bit>,
    /// State dinc (one clock, after a division's run): divider rounding add.
    s_dinc: DFF<Bit>,
    /// State mc follows the run under way (set by the state before, cleared by `f_ret`).
    p_mc: DFF<Bit>,
    /// State vs follows the run under way (set by the state before, cleared by `f_ret`).
    p_vs: DFF<Bit>,
    /// State vc follows the run under way (set by the state before, cleared by `f_ret`).
    p_vc: DFF<Bit>,
    /// State cq follows the run under way (set by the state before, cleared by `f_ret`).
    p_cq: DFF<Bit>,
    /// State m1 follows the run under way (set by the state before, cleared by `f_ret`).
    p_m1: DFF<Bit>,
    /// State m2 follows the run under way (set by the state before, cleared by `f_ret`).
    p_m2: DFF<Bit>,
    /// State m3 follows the run under way (set by the state before, cleared by `f_ret`).
    p_m3: DFF<Bit>,
    /// State cv follows the run under way (set by the state before, cleared by `f_ret`).
    p_cv: DFF<Bit>,
    /// State sqc follows the run under way (set by the state before, cleared by `f_ret`).
    p_sqc: DFF<Bit>,
    /// State chk follows the run under way (set by the state before, cleared by `f_ret`).
    p_chk: DFF<Bit>,
    /// State sn follows the run under way (set by the state before, cleared by `f_ret`).
    p_sn: DFF<Bit>,
    /// State sn2 follows the run under way (set by the state before, cleared by `f_ret`).
    p_sn2: DFF<Bit>,
    /// State offa follows the run under way (set by the state before, cleared by `f_ret`).
    p_offa: DFF<Bit>,
    /// State offb follows the run under way (set by the state before, cleared by `f_ret`).
    p_offb: DFF<Bit>,
    /// State q1 follows the run under way (set by the state before, cleared by `f_ret`).
    p_q1: DFF<Bit>,
    /// State gc follows the run under way (set by the state before, cleared by `f_ret`).
    p_gc: DFF<Bit>,
    /// State q2 follows the run under way (set by the state before, cleared by `f_ret`).
    p_q2: DFF<Bit>,
    /// State ts follows the run under way (set by the state before, cleared by `f_ret`).
    p_ts: DFF<Bit>,
    /// State kd follows the run under way (set by the state before, cleared by `f_ret`).
    p_kd: DFF<Bit>,
    /// State load follows the run under way (set by the state before, cleared by `f_ret`).
    p_load: DFF<Bit>,
    /// This clock returns from a run: the pending state `p_*` is next (a product's or
    /// square root's last B clock, or a division's sign state).
    f_ret: DFF<Bit>,
    /// Dividend / quotient, multiplier operand or radicand: shifted out at the top.
    u_x: DFF<Bits<64>>,
    /// Divisor or multiplicand; in a square root the trial 8 q + 1 (q: the root so far).
    u_d: DFF<Bits<52>>,
    /// Remainder, product or root remainder, two's complement (|u_r| < 2^50).
    u_r: DFF<Bits<52>>,
    /// The division's rounded quotient magnitude u_x + adj, low 24 bits: what is read of
    /// it is m (< 2^24), or a value checked against a clamp below 2^16 (`big_s`, `big_c`).
    u_mag: DFF<Bits<24>>,
    /// The signed quotient: u_mag, or -(u_x + adj) = !u_x + !adj when u_neg (uxs + u_adjq),
    /// written beside it, loaded into u_x by DivNeg.
    u_q: DFF<Bits<64>>,
    /// The division's quotient is negated (taken from neg_n in B_0).
    u_neg: DFF<Bit>,
    /// The division rounds (64 steps) rather than truncates (80 steps), taken in B_0.
    u_rnd: DFF<Bit>,
    /// The quotient's increment adj (DivTst).
    u_adj: DFF<Bit>,
    /// u_adj ^ u_neg, written beside it: the addend of the signed quotient u_q = uxs + it.
    u_adjq: DFF<Bit>,
    /// u_x, inverted when u_neg (free-running): -(u_x + adj) = !u_x + !adj.
    uxs: DFF<Bits<64>>,
    /// Steps left in the run.
    it: DFF<Bits<8>>,
    /// N of the window (N <= 2^24: 25 bits).
    sn: DFF<Bits<25>>,
    /// |Σd_s| (< 2^40).
    a1_s: DFF<Bits<40>>,
    /// |Σd_c| (< 2^40).
    a1_c: DFF<Bits<40>>,
    /// Σd_s < 0.
    n1_s: DFF<Bit>,
    /// Σd_c < 0.
    n1_c: DFF<Bit>,
    /// Σd_s² (< 2^56).
    a2_s: DFF<Bits<56>>,
    /// Σd_c² (< 2^56).
    a2_c: DFF<Bits<56>>,
    /// |Σd_s d_c| (< 2^56), from two clocks after the load (the load takes Σd_s d_c; a
    /// negative sum is replaced in the clock after Ms by -x = ~x + 1 from the free-running
    /// halves below: a select, no chain).
    asc: DFF<Bits<56>>,
    /// The clock after Ms with Σd_s d_c < 0: asc takes its negation.
    asc_h: DFF<Bit>,
    /// 0 - asc's bits 0-27 (free-running, a 28-bit chain from asc): the low half of -x.
    asl: DFF<Bits<28>>,
    /// 0 - asc's bits 28-55 (free-running): the high half of -x when bits 0-27 are zero
    /// (~hi + 1); otherwise the high half is ~hi.
    ash: DFF<Bits<28>>,
    /// asc's bits 0-27 are zero (free-running): the carry of ~x + 1 into bit 28.
    alz: DFF<Bit>,
    /// Σd_s d_c < 0.
    nsc: DFF<Bit>,
    /// Sine b_ref of the window.
    br_s: DFF<Bits<32>>,
    /// Cosine b_ref of the window.
    br_c: DFF<Bits<32>>,
    /// |m_s| = |rdiv(Σd_s 2^8, N)| (< 2^24).
    m_s: DFF<Bits<24>>,
    /// |m_c| (< 2^24).
    m_c: DFF<Bits<24>>,
    /// floor(Σd_s² 2^16 / N) (< 2^48), then V_s = that - m_s², 49-bit two's complement.
    v_s: DFF<Bits<49>>,
    /// floor(Σd_c² 2^16 / N), then V_c, 49-bit two's complement.
    v_c: DFF<Bits<49>>,
    /// Cq = floor(Σd_s d_c 2^16 / N) (|Cq| < 2^48), then C = Cq - m_s m_c (|C| < 2^49),
    /// 50-bit two's complement.
    cc: DFF<Bits<50>>,
    /// |C|, the 48 bits that |C| 2^16 keeps in a 64-bit dividend (|C| < 2^46): C or
    /// `ccn`, selected by C's sign in state sqc (no chain in front of it).
    cmag: DFF<Bits<48>>,
    /// The low 48 bits of -C (free-running, settled a clock after C's load in state cv).
    ccn: DFF<Bits<48>>,
    /// C >= 0 (the quotient -C 2^16 / (Amp_s Amp_c) is negated).
    cpos: DFF<Bit>,
    /// Amp_s = isqrt(2 V_s) (< 2^25).
    amp_s: DFF<Bits<25>>,
    /// Amp_c (< 2^25).
    amp_c: DFF<Bits<25>>,
    /// |S|, clamped to smax (< 2^14).
    smag: DFF<Bits<16>>,
    /// S < 0.
    sneg: DFF<Bit>,
    /// Cc = isqrt(2^30 - S²) (<= 2^15).
    cs: DFF<Bits<16>>,
    /// round(|m_s| / 2^8).
    t_s: DFF<Bits<32>>,
    /// round(|m_c| / 2^8).
    t_c: DFF<Bits<32>>,
    /// The new sine offset b_ref +- t_s.
    o_s: DFF<Bits<32>>,
    /// The new cosine offset.
    o_c: DFF<Bits<32>>,
    /// The new sine gain code, clamped.
    ng_s: DFF<Bits<16>>,
    /// The new cosine gain code, clamped.
    ng_c: DFF<Bits<16>>,
    /// Amp_s Cc (< 2^40), the divisor of k.
    q2: DFF<Bits<40>>,
    r_os: DFFWithInit<Bits<32>>,
    r_oc: DFFWithInit<Bits<32>>,
    r_gs: DFFWithInit<Bits<16>>,
    r_gc: DFFWithInit<Bits<16>>,
    r_km: DFF<Bits<16>>,
    r_kn: DFF<Bit>,
    r_done: DFF<Bit>,
    /// Run is a division (set by its set-up state, like the two below).
    f_div: DFF<Bit>,
    /// Run is a square root.
    f_sq: DFF<Bit>,
    /// Run is a multiplication.
    f_mul: DFF<Bit>,
    /// An A clock: u_r takes the chain's sum {oa, 1} + ob (also the divider's rounding sum).
    f_add: DFF<Bit>,
    /// An A clock of a division or product: u_x shifts by one.
    f_sh1: DFF<Bit>,
    /// An A clock of a square root: u_x shifts by two.
    f_sh2: DFF<Bit>,
    /// A division's B clock after an A clock: the quotient bit !rneg into u_x bit 0.
    f_qx: DFF<Bit>,
    /// A square root's B clock after an A clock: the root bit !rneg into u_d (8 q + 1).
    f_qd: DFF<Bit>,
    /// The run's last B clock (the last step's bit; a division's rounding operands).
    f_last: DFF<Bit>,
    /// No run in the clock before (B_0 of a run, or outside one): `it` loads the step count
    /// (32, 64 or 80 from the mode flags and f_80), u_rnd and u_neg a division's settings.
    f_ld: DFF<Bit>,
    /// Vs, Vc or Cq was the state before: the run is an 80-step (truncating) division.
    f_80: DFF<Bit>,
    /// The sign the division set up in the state before applies (u_neg, taken in B_0).
    neg_n: DFF<Bit>,
    /// opa, the chain's first operand, written in a B clock; the chain adds {oa, 1} (the
    /// constant 1 is not a register: a flip-flop that only ever loads 1 is merged by Yosys
    /// with any other such flip-flop of the design, wherever it is placed).
    oa: DFF<Bits<52>>,
    /// {opb, cin}: its second operand and carry in.
    ob: DFF<Bits<53>>,
    /// u_x loads |Σd_s| 2^8 in this clock.
    x_a1s: DFF<Bit>,
    /// u_x loads uxr (a return with a select of the uxa / uxb / uxc groups) in this clock.
    x_uxr: DFF<Bit>,
    /// u_x loads the clamped |S| 2^32 (a return) in this clock.
    x_scl: DFF<Bit>,
    /// u_x loads 2^30 - S² in this clock.
    x_t30: DFF<Bit>,
    /// u_x loads T |S| 2^(GF+8) (a return) in this clock.
    x_urk: DFF<Bit>,
    /// u_x loads the signed quotient u_q in this clock (DivNeg).
    x_q: DFF<Bit>,
    /// u_x loads (one of the x_* flags, or a run's shift) in this clock.
    x_en: DFF<Bit>,
    /// u_d loads N (the first division) in this clock.
    d_sn: DFF<Bit>,
    /// u_d loads udr (a return with a select of the static sources) in this clock.
    d_udr: DFF<Bit>,
    /// u_d loads the square root just finished, (8 q + 1) >> 3 (a return) in this clock.
    d_uq: DFF<Bit>,
    /// u_d loads the product just finished, u_r (a return) in this clock.
    d_ur: DFF<Bit>,
    /// u_d loads the clamped |S| (a return) in this clock.
    d_scl: DFF<Bit>,
    /// u_d loads 1: a square root's first trial 8 q + 1 (q = 0) in this clock.
    d_one: DFF<Bit>,
    /// u_d loads (one of the d_* flags, or a square root's root bit) in this clock.
    d_en: DFF<Bit>,
    /// u_r is cleared in this state.
    clr_r: DFF<Bit>,
    /// One of the uxr groups' return selects is set (free-running, a clock behind them).
    rx_uxr: DFF<Bit>,
    /// Return select (set by Sn): u_x loads the clamped |S| 2^32.
    rx_scl: DFF<Bit>,
    /// Return select (set by Ts): u_x loads T |S| 2^(GF+8).
    rx_urk: DFF<Bit>,
    /// Return select (set by the set-up state, cleared by the return): uxr takes Σd_c 2^8.
    rx_a1c8: DFF<Bit>,
    /// Return select (set by the set-up state, cleared by the return): uxr takes Σd_s².
    rx_a2s: DFF<Bit>,
    /// Return select (set by the set-up state, cleared by the return): uxr takes Σd_c².
    rx_a2c: DFF<Bit>,
    /// Return select (set by the set-up state, cleared by the return): uxr takes |Σd_s d_c|.
    rx_asc: DFF<Bit>,
    /// Return select (set by M3, cleared by the return): uxr takes 2 V_s (0 if V_s < 0).
    rx_vs2: DFF<Bit>,
    /// Return select (set by Cs): uxr takes T 2^(GF+8).
    rx_tgs: DFF<Bit>,
    /// Return select (set by the set-up state, cleared by the return): uxr takes m_s 2^32.
    rx_ms32: DFF<Bit>,
    /// Return select (set by the set-up state, cleared by the return): uxr takes m_c 2^32.
    rx_mc32: DFF<Bit>,
    /// Return select (set by the set-up state, cleared by the return): uxr takes 2 V_c.
    rx_vc2: DFF<Bit>,
    /// Return select (set by the set-up state, cleared by the return): uxr takes Amp_s 2^32.
    rx_amps32: DFF<Bit>,
    /// Return select (set by the set-up state, cleared by the return): uxr takes Amp_c 2^32.
    rx_ampc32: DFF<Bit>,
    /// Return select (set by the set-up state, cleared by the return): uxr takes |C| 2^16.
    rx_cmag16: DFF<Bit>,
    /// Return select (set by the set-up state, cleared by the return): uxr takes T 2^(GF+23).
    rx_tgc: DFF<Bit>,
    /// Return select (set by the set-up state, cleared by the return): uxr takes T 2^32.
    rx_tamp32: DFF<Bit>,
    /// u_x's source for the return selects rx_*: uxa | uxb | uxc (free-running, two clocks
    /// behind the sources, every one of which is final long before the return).
    uxr: DFF<Bits<64>>,
    /// The selected source among Σd_c 2^8, Σd_s², Σd_c², |Σd_s d_c|, 2 V_s (0 otherwise).
    uxa: DFF<Bits<64>>,
    /// The selected source among m_s 2^32, m_c 2^32, 2 V_c, Amp_s 2^32 (0 otherwise).
    uxb: DFF<Bits<64>>,
    /// The selected source among Amp_c 2^32, |C| 2^16, T 2^(GF+8), T 2^(GF+23), T 2^32 (0
    /// otherwise).
    uxc: DFF<Bits<64>>,
    /// One of udr's return selects is set (free-running, a clock behind them).
    rd_st: DFF<Bit>,
    /// Return select (set by SqC): u_d loads the root (8 q + 1) >> 3.
    rd_uq: DFF<Bit>,
    /// Return select (set by Chk, Q1): u_d loads the product u_r.
    rd_ur: DFF<Bit>,
    /// Return select (set by Sn): u_d loads the clamped |S|.
    rd_scl: DFF<Bit>,
    /// Return select (set by SqS): u_d loads 1.
    rd_one: DFF<Bit>,
    /// Return select (set by the set-up state, cleared by the return): udr takes N.
    rd_sn: DFF<Bit>,
    /// Return select (set by the set-up state, cleared by the return): udr takes m_s.
    rd_ms: DFF<Bit>,
    /// Return select (set by the set-up state, cleared by the return): udr takes m_c.
    rd_mc: DFF<Bit>,
    /// Return select (set by the set-up state, cleared by the return): udr takes Cc.
    rd_cs: DFF<Bit>,
    /// Return select (set by the set-up state, cleared by the return): udr takes |S|.
    rd_smag: DFF<Bit>,
    /// Return select (set by the set-up state, cleared by the return): udr takes Amp_s Cc.
    rd_q2: DFF<Bit>,
    /// Return select (set by Cs): udr takes Amp_s.
    rd_amps: DFF<Bit>,
    /// u_d's source for the static return selects rd_* (N, m_s, m_c, Amp_s, Cc, |S|,
    /// Amp_s Cc; 0 otherwise), free-running a clock behind them, final long before the return.
    udr: DFF<Bits<52>>,
    /// (v_c while M3 is pending, else v_s) - u_r (free-running): V_s - m_s², loaded by M2,
    /// then V_c - m_c², loaded by M3.
    vd: DFF<Bits<49>>,
    /// cc + u_r (free-running): C = Cq - m_s m_c when the means' signs differ, loaded by Cv.
    ccp: DFF<Bits<50>>,
    /// cc - u_r (free-running): C = Cq - m_s m_c when they agree.
    ccm: DFF<Bits<50>>,
    /// (u_r ^ u_d) ^ ((u_r | u_d) << 1) (free-running): zero exactly when u_r + u_d = 0
    /// (mod 2^52), the zero test of the true remainder u_r + u_d without a carry chain (in
    /// a zero sum every bit a ^ b ^ carry is 0, so the carry into bit i is a_i ^ b_i and the
    /// carry out of it a_i | b_i).
    xr: DFF<Bits<52>>,
    /// u_r == 0 (free-running).
    rz: DFF<Bit>,
    /// xr == 0, i.e. u_r == -u_d (free-running, a clock behind xr, two behind u_r).
    req: DFF<Bit>,
    /// 2^30 - u_r, low 31 bits (free-running): the radicand of Cc one state after S²
    /// (2^30 - S² in (2^29, 2^30]).
    t30: DFF<Bits<31>>,
    /// min(u_mag, smax) (free-running): the clamped |S| one state after its division.
    scl: DFF<Bits<16>>,
    /// min(u_mag, 65535) (free-running): a clamped gain or cross code.
    ngf: DFF<Bits<16>>,
    /// amp_s < min_amplitude 2^8 (free-running).
    lo_s: DFF<Bit>,
    /// amp_c < min_amplitude 2^8 (free-running).
    lo_c: DFF<Bit>,
    /// o_s below / at or above the A-bit range (free-running).
    oor_sl: DFF<Bit>,
    oor_sh: DFF<Bit>,
    /// o_c below / at or above the A-bit range (free-running).
    oor_cl: DFF<Bit>,
    oor_ch: DFF<Bit>,
    /// u_x bits 31..16 not all zero (free-running; with the seven below, u_mag's compares
    /// two clocks ahead, from the quotient that u_mag = u_x + adj rounds).
    xh1: DFF<Bit>,
    /// u_x bits 47..32 not all zero (free-running).
    xh2: DFF<Bit>,
    /// u_x bits 63..48 not all zero (free-running).
    xh3: DFF<Bit>,
    /// u_x bits 15..0 not all zero (free-running).
    xl: DFF<Bit>,
    /// A solve starts in this clock (idle and `start`).
    go: Signal<Local, Bit>,
    /// Sn passes the amplitude check.
    ok_sn: Signal<Local, Bit>,
    /// Q1 passes the offset range check.
    ok_q1: Signal<Local, Bit>,
    /// A run is under way (a mode flag is set).
    run: Signal<Local, Bit>,
    /// A run's B clock that is not its last: the next clock is an A clock.
    step: Signal<Local, Bit>,
    /// u_x's next value when x_en: its selected sources ORed (each zero unless selected).
    uxn: Signal<Local, Bits<64>>,
    /// udr's next value: its selected sources ORed.
    udn: Signal<Local, Bits<52>>,
    /// u_d's next value when d_en: its selected sources ORed.
    udn2: Signal<Local, Bits<52>>,
    /// uxa's next value: its selected sources ORed.
    uxan: Signal<Local, Bits<64>>,
    /// uxb's next value.
    uxbn: Signal<Local, Bits<64>>,
    /// uxc's next value.
    uxcn: Signal<Local, Bits<64>>,
    /// u_x bits 15..0 > smax (free-running).
    xgt_s: DFF<Bit>,
    /// u_x bits 15..0 >= smax (free-running).
    xge_s: DFF<Bit>,
    /// u_x bits 15..0 all ones (free-running).
    xff: DFF<Bit>,
    /// u_mag > smax, a clock after u_mag (free-running: xh | (adj ? xge_s : xgt_s)).
    big_s: DFF<Bit>,
    /// u_mag > 65535, a clock after u_mag (free-running: xh | (adj & xff)).
    big_c: DFF<Bit>,
    /// u_mag != 0, a clock after u_mag (free-running: xh | xl | adj).
    mnz: DFF<Bit>,
    /// u_x bits 63..16 not all zero: xh1 | xh2 | xh3.
    xh: Signal<Local, Bit>,
    /// u_r < 0 (the non-restoring remainder's sign: add the divisor / trial back).
    rneg: Signal<Local, Bit>,
    /// The chain's first operand: 2 u_r (+ msb(u_x) in a division step) or
    /// 4 u_r + top2(u_x) in a square root.
    opa: Signal<Local, Bits<52>>,
    /// Add (u_r < 0, or the multiplier's bit is one), else subtract.
    up: Signal<Local, Bit>,
    /// The chain's second operand: u_d / the trial when adding, its complement otherwise.
    opb: Signal<Local, Bits<52>>,
    /// The minuend of `vd`: v_c while M3 is pending, else v_s (free-running, a clock
    /// behind p_m3, v_s and v_c, so vd's chain starts at registers: M2 and M3 read vd long
    /// after their minuend settles, v_s and v_c being loaded states earlier and p_m3
    /// rising 65 clocks before M3).
    vsel: DFF<Bits<49>>,
    /// u_adj as a 24-bit addend (of u_mag).
    adjw: Signal<Local, Bits<24>>,
    /// u_adjq as a 64-bit addend.
    adjqw: Signal<Local, Bits<64>>,
    /// The rounding increment DivTst writes into u_adj.
    adjn: Signal<Local, Bit>,
    /// min_amplitude 2^8 (< 2^23).
    minamp: Constant<Bits<25>>,
    /// T 2^(GF+8): dividend of g_s.
    tgs: Constant<Bits<64>>,
    /// T 2^(GF+23): dividend of g_c.
    tgc: Constant<Bits<64>>,
    /// GF + 8: shift of T |S|.
    kshift: Constant<Bits<32>>,
    /// 2^30 in 31 bits.
    two30: Constant<Bits<31>>,
    /// 0 in 50 bits.
    zero50: Constant<Bits<50>>,
    /// u_adj as a 24-bit addend when set.
    one24: Constant<Bits<24>>,
    /// 0 in 24 bits.
    zero24: Constant<Bits<24>>,
    /// 2^(A-1) - 2^31 ... the offset range limits with the sign bit flipped: b < lo_f or
    /// b >= hi_f (unsigned, flipped) is out of range.
    lo_f: Constant<Bits<32>>,
    hi_f: Constant<Bits<32>>,
    /// Bit 31.
    sign32: Constant<Bits<32>>,
    /// Bit 63.
    sign63: Constant<Bits<64>>,
    /// Shifts by 63 and 3.
    s63: Constant<Bits<32>>,
    s3: Constant<Bits<32>>,
    /// 52-bit constants: all ones, 0, 1, 9, bits 1 and 2, and masks without bit 1 / bit 2.
    ones52: Constant<Bits<52>>,
    zero52: Constant<Bits<52>>,
    one52: Constant<Bits<52>>,
    nine52: Constant<Bits<52>>,
    b1: Constant<Bits<52>>,
    b2: Constant<Bits<52>>,
    nb1: Constant<Bits<52>>,
    nb2: Constant<Bits<52>>,
    /// 1 in 53 bits.
    one53: Constant<Bits<53>>,
    /// 128: the rounding half of a division by 2^8.
    half8: Constant<Bits<32>>,
    /// Step counts and shifts.
    i32c: Constant<Bits<8>>,
    i64c: Constant<Bits<8>>,
    i80c: Constant<Bits<8>>,
    one8: Constant<Bits<8>>,
    one32: Constant<Bits<32>>,
    s32: Constant<Bits<32>>,
    /// T 2^32: the multiplier operand of T |S|.
    tamp32: Constant<Bits<64>>,
    /// 65535 as a gain code.
    cmax16: Constant<Bits<16>>,
    /// Upper bound of |S|, round(2^15 sin 15 deg), in 16 bits: the clamp of scl and the low
    /// half of u_x's compare.
    smax16: Constant<Bits<16>>,
    two32: Constant<Bits<32>>,
    s8: Constant<Bits<32>>,
    s16: Constant<Bits<32>>,
    s48: Constant<Bits<32>>,
    s62: Constant<Bits<32>>,
    one64: Constant<Bits<64>>,
    zero64: Constant<Bits<64>>,
    /// 28: the shift of asc's high half.
    s28: Constant<Bits<32>>,
    /// 0, 28-bit.
    zero28: Constant<Bits<28>>,
    zero16: Constant<Bits<16>>,
    /// Configured (reset) offsets and gains.
    b0_s: Constant<Bits<32>>,
    b0_c: Constant<Bits<32>>,
    g0_s: Constant<Bits<16>>,
    g0_c: Constant<Bits<16>>,
}

/// The fit's settings as the solver needs them.
#[derive(Clone, Copy, Debug)]
pub struct SolveConsts {
    /// ADC width A.
    pub adc_width: u32,
    /// Gain fraction bits GF.
    pub gain_frac_bits: u32,
    /// Target amplitude T (LSB).
    pub target_amplitude: u32,
    /// No update below this amplitude (LSB).
    pub min_amplitude: u32,
}

impl FitSolve {
    /// Solver for `k` starting from (and reset to) the offsets and gains of `p`.
    pub fn new(p: &CorrectionParams, k: SolveConsts) -> Self {
        let a = k.adc_width;
        let gf = k.gain_frac_bits;
        let t = k.target_amplitude as u64;
        let lim = 1i64 << (a - 1);
        let flip = |v: i64| (v as u64 & mask(32)) ^ (1 << 31);
        let sext = |v: i32| v as i64 as u64 & mask(32);
        Self {
            clk: Default::default(),
            rst: Default::default(),
            start: Default::default(),
            n: Default::default(),
            s1_s: Default::default(),
            s1_c: Default::default(),
            s2_s: Default::default(),
            s2_c: Default::default(),
            ssc: Default::default(),
            bref_s: Default::default(),
            bref_c: Default::default(),
            busy: Default::default(),
            done: Default::default(),
            off_s: Default::default(),
            off_c: Default::default(),
            g_s: Default::default(),
            g_c: Default::default(),
            k_mag: Default::default(),
            k_neg: Default::default(),
            busy_r: Default::default(),
            s_ms: Default::default(),
            s_mc: Default::default(),
            s_vs: Default::default(),
            s_vc: Default::default(),
            s_cq: Default::default(),
            s_m1: Default::default(),
            s_m2: Default::default(),
            s_m3: Default::default(),
            s_cv: Default::default(),
            s_sqs: Default::default(),
            s_sqc: Default::default(),
            s_chk: Default::default(),
            s_sn: Default::default(),
            s_sn2: Default::default(),
            s_offa: Default::default(),
            s_cs: Default::default(),
            s_offb: Default::default(),
            s_offc: Default::default(),
            s_q1: Default::default(),
            s_gc: Default::default(),
            s_q2: Default::default(),
            s_ts: Default::default(),
            s_kd: Default::default(),
            s_load: Default::default(),
            s_dadj: Default::default(),
            s_dtst: Default::default(),
            s_dinc: Default::default(),
            p_mc: Default::default(),
            p_vs: Default::default(),
            p_vc: Default::default(),
            p_cq: Default::default(),
            p_m1: Default::default(),
            p_m2: Default::default(),
            p_m3: Default::default(),
            p_cv: Default::default(),
            p_sqc: Default::default(),
            p_chk: Default::default(),
            p_sn: Default::default(),
            p_sn2: Default::default(),
            p_offa: Default::default(),
            p_offb: Default::default(),
            p_q1: Default::default(),
            p_gc: Default::default(),
            p_q2: Default::default(),
            p_ts: Default::default(),
            p_kd: Default::default(),
            p_load: Default::default(),
            f_ret: Default::default(),
            u_x: Default::default(),
            u_d: Default::default(),
            u_r: Default::default(),
            u_mag: Default::default(),
            u_q: Default::default(),
            u_neg: Default::default(),
            u_rnd: Default::default(),
            u_adj: Default::default(),
            u_adjq: Default::default(),
            uxs: Default::default(),
            it: Default::default(),
            sn: Default::default(),
            a1_s: Default::default(),
            a1_c: Default::default(),
            n1_s: Default::default(),
            n1_c: Default::default(),
            a2_s: Default::default(),
            a2_c: Default::default(),
            asc: Default::default(),
            asc_h: Default::default(),
            asl: Default::default(),
            ash: Default::default(),
            alz: Default::default(),
            nsc: Default::default(),
            br_s: Default::default(),
            br_c: Default::default(),
            m_s: Default::default(),
            m_c: Default::default(),
            v_s: Default::default(),
            v_c: Default::default(),
            cc: Default::default(),
            cmag: Default::default(),
            cpos: Default::default(),
            amp_s: Default::default(),
            amp_c: Default::default(),
            smag: Default::default(),
            sneg: Default::default(),
            cs: Default::default(),
            t_s: Default::default(),
            t_c: Default::default(),
            o_s: Default::default(),
            o_c: Default::default(),
            ng_s: Default::default(),
            ng_c: Default::default(),
            q2: Default::default(),
            r_os: DFFWithInit::new(Bits::<32>::from(sext(p.offset()[SIN]))),
            r_oc: DFFWithInit::new(Bits::<32>::from(sext(p.offset()[COS]))),
            r_gs: DFFWithInit::new(Bits::<16>::from(p.gain()[SIN] as u64)),
            r_gc: DFFWithInit::new(Bits::<16>::from(p.gain()[COS] as u64)),
            r_km: Default::default(),
            r_kn: Default::default(),
            r_done: Default::default(),
            f_div: Default::default(),
            f_sq: Default::default(),
            f_mul: Default::default(),
            f_add: Default::default(),
            f_sh1: Default::default(),
            f_sh2: Default::default(),
            f_qx: Default::default(),
            f_qd: Default::default(),
            f_last: Default::default(),
            f_ld: Default::default(),
            f_80: Default::default(),
            neg_n: Default::default(),
            oa: Default::default(),
            ob: Default::default(),
            x_a1s: Default::default(),
            x_uxr: Default::default(),
            x_scl: Default::default(),
            x_t30: Default::default(),
            x_urk: Default::default(),
            x_q: Default::default(),
            x_en: Default::default(),
            d_sn: Default::default(),
            d_udr: Default::default(),
            d_uq: Default::default(),
            d_ur: Default::default(),
            d_scl: Default::default(),
            d_one: Default::default(),
            d_en: Default::default(),
            clr_r: Default::default(),
            rx_uxr: Default::default(),
            rx_scl: Default::default(),
            rx_urk: Default::default(),
            rx_a1c8: Default::default(),
            rx_a2s: Default::default(),
            rx_a2c: Default::default(),
            rx_asc: Default::default(),
            rx_vs2: Default::default(),
            rx_tgs: Default::default(),
            rx_ms32: Default::default(),
            rx_mc32: Default::default(),
            rx_vc2: Default::default(),
            rx_amps32: Default::default(),
            rx_ampc32: Default::default(),
            rx_cmag16: Default::default(),
            rx_tgc: Default::default(),
            rx_tamp32: Default::default(),
            uxr: Default::default(),
            uxa: Default::default(),
            uxb: Default::default(),
            uxc: Default::default(),
            rd_st: Default::default(),
            rd_uq: Default::default(),
            rd_ur: Default::default(),
            rd_scl: Default::default(),
            rd_one: Default::default(),
            rd_sn: Default::default(),
            rd_ms: Default::default(),
            rd_mc: Default::default(),
            rd_cs: Default::default(),
            rd_smag: Default::default(),
            rd_q2: Default::default(),
            rd_amps: Default::default(),
            udr: Default::default(),
            vd: Default::default(),
            ccp: Default::default(),
            ccm: Default::default(),
            ccn: Default::default(),
            xr: Default::default(),
            rz: Default::default(),
            req: Default::default(),
            t30: Default::default(),
            scl: Default::default(),
            ngf: Default::default(),
            lo_s: Default::default(),
            lo_c: Default::default(),
            oor_sl: Default::default(),
            oor_sh: Default::default(),
            oor_cl: Default::default(),
            oor_ch: Default::default(),
            xh1: Default::default(),
            xh2: Default::default(),
            xh3: Default::default(),
            xl: Default::default(),
            go: Default::default(),
            ok_sn: Default::default(),
            ok_q1: Default::default(),
            run: Default::default(),
            step: Default::default(),
            uxn: Default::default(),
            udn: Default::default(),
            udn2: Default::default(),
            uxan: Default::default(),
            uxbn: Default::default(),
            uxcn: Default::default(),
            xgt_s: Default::default(),
            xge_s: Default::default(),
            xff: Default::default(),
            big_s: Default::default(),
            big_c: Default::default(),
            mnz: Default::default(),
            xh: Default::default(),
            rneg: Default::default(),
            opa: Default::default(),
            up: Default::default(),
            opb: Default::default(),
            vsel: Default::default(),
            adjw: Default::default(),
            adjqw: Default::default(),
            adjn: Default::default(),
            minamp: cw((k.min_amplitude as u64) << 8),
            tgs: c64(t << (gf + 8)),
            tgc: c64(t << (gf + 23)),
            kshift: c32((gf + 8) as u64),
            two30: cw(1 << 30),
            zero50: cw(0),
            one24: cw(1),
            zero24: cw(0),
            lo_f: c32(flip(-lim)),
            hi_f: c32(flip(lim)),
            sign32: c32(1 << 31),
            sign63: c64(1 << 63),
            s63: c32(63),
            s3: c32(3),
            ones52: cw(mask(52)),
            zero52: cw(0),
            one52: cw(1),
            nine52: cw(9),
            b1: cw(2),
            b2: cw(4),
            nb1: cw(mask(52) ^ 2),
            nb2: cw(mask(52) ^ 4),
            one53: cw(1),
            half8: c32(128),
            i32c: c8(32),
            i64c: c8(64),
            i80c: c8(80),
            one8: c8(1),
            one32: c32(1),
            s32: c32(32),
            tamp32: c64(t << 32),
            cmax16: c16(0xffff),
            smax16: c16((32768.0 * 15f64.to_radians().sin()).round() as u64),
            two32: c32(2),
            s8: c32(8),
            s16: c32(16),
            s48: c32(48),
            s62: c32(62),
            one64: c64(1),
            zero64: c64(0),
            s28: c32(28),
            zero28: cw(0),
            zero16: c16(0),
            b0_s: c32(sext(p.offset()[SIN])),
            b0_c: c32(sext(p.offset()[COS])),
            g0_s: c16(p.gain()[SIN] as u64),
            g0_c: c16(p.gain()[COS] as u64),
        }
    }
}

impl crate::cosim::step::Clocked for FitSolve {
    fn set_clock(&mut self, high: bool) {
        self.clk.next = Clock::from(high);
    }
}

/// The solver on its own in the co-simulation harness (`tests/blocks/correction_fit_solver.rs`
/// feeds it window sums at the limits of the module doc's bounds).
impl crate::cosim::CosimBlock for FitSolve {
    fn input_ports(&self) -> Vec<crate::cosim::Port> {
        use crate::cosim::Port;
        vec![
            Port::new("rst", 1),
            Port::new("start", 1),
            Port::new("n", 32),
            Port::new("s1_s", 64),
            Port::new("s1_c", 64),
            Port::new("s2_s", 64),
            Port::new("s2_c", 64),
            Port::new("ssc", 64),
            Port::new("bref_s", 32),
            Port::new("bref_c", 32),
        ]
    }
    fn output_ports(&self) -> Vec<crate::cosim::Port> {
        use crate::cosim::Port;
        vec![
            Port::new("busy", 1),
            Port::new("done", 1),
            Port::new("off_s", 32),
            Port::new("off_c", 32),
            Port::new("g_s", 16),
            Port::new("g_c", 16),
            Port::new("k_mag", 16),
            Port::new("k_neg", 1),
        ]
    }
    fn apply(&mut self, r: &[u64]) {
        self.rst.next = r[0] != 0;
        self.start.next = r[1] != 0;
        self.n.next = Bits::<32>::from(r[2] & mask(32));
        self.s1_s.next = Bits::<64>::from(r[3]);
        self.s1_c.next = Bits::<64>::from(r[4]);
        self.s2_s.next = Bits::<64>::from(r[5]);
        self.s2_c.next = Bits::<64>::from(r[6]);
        self.ssc.next = Bits::<64>::from(r[7]);
        self.bref_s.next = Bits::<32>::from(r[8] & mask(32));
        self.bref_c.next = Bits::<32>::from(r[9] & mask(32));
    }
    fn sample(&self) -> Vec<u64> {
        vec![
            self.busy.val() as u64,
            self.done.val() as u64,
            self.off_s.val().to_u64(),
            self.off_c.val().to_u64(),
            self.g_s.val().to_u64(),
            self.g_c.val().to_u64(),
            self.k_mag.val().to_u64(),
            self.k_neg.val() as u64,
        ]
    }
}

mod update;
