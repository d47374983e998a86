//! rust-hdl description of the end-of-window solve of the ellipse fit: the integer
//! specification [`super::fit::solve`] as a program, [`TABLE`], that a small sequencer
//! executes row by row on one serial shift-add multiplier and one serial non-restoring
//! divider / square root, all three on one shared adder.
//!
//! ```text
//!  start ─► snapshot N, Σd (|Σd| a clock later), Σd², Σd_s d_c (its magnitude two clocks
//!   │       later), b_ref; pc = 0; launch: the first set-up a clock later
//!   ▼
//!  ┌─► ROM: TABLE[pc] ─► dn (the row, registered) ─► pl (dn for one clock at the set-up)
//!  │     row = (op, u_x source, u_d source, destination, options)
//!  │   SetUp: u_x, u_d ◄─ sources (AND-OR of pl's one-hot selects), u_r = 0, the row
//!  │          before writes its result (pl's destination select), pc += 1
//!  │   Run:   DIV (64 or 80 steps) | MUL (32) | SQRT (32) on the shared adder
//!  │   RoundSum, RoundTst, RoundInc, RoundNeg (a division): round or floor, sign
//!  └── next row;  a row marked `check` refuses (amplitude, offset range; registered in
//!                 `refuse` while the row before runs) ─► Load ─► Idle
//!                 after the last row ─► Load: every coefficient at once, `done`
//!
//!  shared adder, one 53-bit carry chain, each step over two clocks:
//!    B clock: oa = opa, ob = {opb, cin}: opa = 2 u_r (+ msb(u_x)) or 4 u_r + top2(u_x);
//!             opb = up ? u_d : !u_d (!0 in a MUL), cin = !up, up = u_r < 0 (MUL: msb(u_x));
//!             one LUT a bit from registers; the previous step's bit (!sign of u_r) into
//!             u_x bit 0 (DIV) or into u_d (SQRT)
//!    A clock: u_r = ({oa, 1} + ob) >> 1 (the chain and nothing else); u_x <<= 1 (2 in a SQRT)
//!    ┌───────────┐  B   ┌────────┐  A   ┌────────────┐
//!    │u_r u_x u_d├─LUT─►│ oa  ob ├─+───►│ u_r (52 b) │── sign ──► next B
//!    └───────────┘      └────────┘      └────────────┘
//!  DIV (non-restoring, dividend and quotient share u_x):  SQRT (non-restoring, 2 bits a step):
//!    t = 2 u_r + msb(u_x)                                   t = 4 u_r + top2(u_x)
//!    u_r = u_r < 0 ? t + u_d : t - u_d                      u_r = u_r < 0 ? t + (4q+3) : t - (4q+1)
//!    u_x = 2 u_x + (u_r >= 0)                               q = 2 q + (u_r >= 0); u_d = 8 q + 1
//!  (the quotient bits equal the restoring ones; the true remainder is u_r, or u_r + u_d
//!  when u_r < 0, zero when u_r + u_d = 0: (u_r ^ u_d) == (u_r | u_d) << 1, no chain)
//!  then RoundSum: 2 u_r -+ u_d (rounding); RoundTst: adj = round ? 2 r >= u_d : neg & r != 0;
//!  RoundInc: u_mag = u_x + adj and u_q = uxs + (adj ^ neg), uxs = neg ? !u_x : u_x, i.e.
//!  -(u_x + adj) = !u_x + !adj, one chain from registers; RoundNeg: u_x = u_q
//!  MUL (MSB first, multiplier a < 2^32 in the top half of u_x, 32 steps):
//!    u_r = 2 u_r + (msb(u_x) ? u_d : 0); u_x <<= 1
//! ```
//!
//! The sources a set-up loads are registers: those written rows earlier reach u_x / u_d
//! through free-running registers (uxa, uxb, uxc ─► uxr; udr) that the held row `dn`
//! selects; a result of the row just before (its product, root or clamped quotient) goes
//! straight in. Sums, compares and negations the rows read (V - m², Cq -+ |m_s m_c|, |C|,
//! 2^30 - S², the clamps, round(|m| / 2^8), b_ref +- that, the checks, the remainder's zero
//! tests) are free-running registers, settled long before a set-up reads them.
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
//! * Stored values at the widths these bounds give: N 25 bits, |Σd| 40, Σd² and |Σd_s d_c|
//!   56, |m| 24 (|Σd| 2^8 / N <= (2^16 - 1) 2^8 < 2^24, and the rounding stays below), V 49
//!   (two's complement: floor(Σd² 2^16 / N) < 2^48 less m² < 2^48), C 50 (|Cq| < 2^48 plus
//!   |m_s m_c| < 2^48), |C| 48 (the bits |C| 2^16 keeps), Amp 25, |S| and Cc 16, Amp_s Cc
//!   40, 2^30 - S² 31, the quotient's magnitude u_mag 24 (read as m, or under a clamp below
//!   2^16). A difference such as V - m² is taken in the narrow width: its low bits are
//!   exact, and the true value fits. `tests/blocks/correction_fit_solver.rs` drives the
//!   solver at these bounds (N = 2^24, |d| = 2^16 - 1, full correlation) and runs the table
//!   with exact integers against [`super::fit::solve`], holding every value to its width.
//! * Each clock writes a register through at most one adder or compare (the timing rule
//!   of docs/correction.md): abs, add, round and negate are separate clocks or free-running
//!   registers; the table's decode is registered twice (`dn`, `pl`) before a datapath
//!   select reads it, and the state's next value depends on registers only (`launch`,
//!   `f_ret`, `refuse`, dn's end bit, the run's flags).
//! * The root has 32 bits (32 steps, one bit each; in u_d as 8 q + 1 while it grows);
//!   `it` counts at most 80 steps: 8 bits.
//!
//! # Timing
//! [`SOLVE_CYCLES`] clocks from `start` to an accepted update's `done`, summed from [`TABLE`]
//! by [`row_cycles`]; the config makes the next window longer; one ending while busy is dropped.
use super::autocal::c16;
use super::{CorrectionParams, COS, SIN};
use crate::blocks::{c32, mask};
use rust_hdl::prelude::*;
pub use table::{row_cycles, Dst, Op, Row, Sign, Src, SOLVE_CYCLES, TABLE, UPDATE_LATENCY};
use table::{sel, Sel, TableRom};
pub use update::SolveState;

/// A 64-bit constant.
pub(super) fn c64(v: u64) -> Constant<Bits<64>> {
    Constant::new(Bits::<64>::from(v))
}

/// An N-bit constant.
fn cw<const N: usize>(v: u64) -> Constant<Bits<N>> {
    Constant::new(Bits::<N>::from(v))
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
    /// A solve is under way (not idle).
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
    // ---- sequencer
    /// Phase.
    state: DFF<SolveState>,
    /// Program counter: the row the next set-up starts (20: Load).
    pc: DFF<Bits<5>>,
    /// The table, one word a row.
    rom: TableRom,
    /// ROM word of pc, registered (held through the row before's run; row 0 after a reset).
    dn: DFF<Sel>,
    /// `dn` for one clock at the set-up (Load), else 0: the datapath's one-hot selects
    /// (timing: a second register keeps the ROM and `ret` off the u_x / u_d mux paths).
    pl: DFF<Sel>,
    /// Idle, no start taken: the snapshot loads (timing: a flip-flop as its 370 enables).
    rdy: DFF<Bit>,
    /// The clock after `go`, set-up next (timing: `start` off the `pl` and state paths).
    launch: DFF<Bit>,
    /// dn's row fails its check (timing: dn & bad registered off the state and `pl` paths).
    refuse: DFF<Bit>,
    /// The next clock is a set-up or Load: an operation's last B clock or RoundNeg.
    f_ret: DFF<Bit>,
    /// An amplitude low or an offset out of range (timing: six compares off `refuse`).
    bad: DFF<Bit>,
    /// A solve starts: `rdy` and `start` (dn holds row 0 whenever `rdy` is set).
    go: Signal<Local, Bit>,
    /// The set-up (or Load) is next: `launch` or `f_ret`.
    ret: Signal<Local, Bit>,
    /// All selects clear.
    nosel: Constant<Sel>,
    /// Row 0's word.
    row0: Constant<Sel>,
    // ---- the shared units
    /// Dividend / quotient, multiplier operand or radicand: shifted out at the top.
    u_x: DFF<Bits<64>>,
    /// Divisor or multiplicand; in a square root the trial 8 q + 1 (q: the root so far).
    u_d: DFF<Bits<52>>,
    /// Remainder, product or root remainder, two's complement (|u_r| < 2^50).
    u_r: DFF<Bits<52>>,
    /// The rounded quotient magnitude u_x + adj, low 24 bits (read as m, or under a clamp).
    u_mag: DFF<Bits<24>>,
    /// The signed quotient: u_mag, or -(u_x + adj) = !u_x + !adj when u_neg (uxs + u_adjq).
    u_q: DFF<Bits<64>>,
    /// The division's quotient is negated (loaded at its set-up).
    u_neg: DFF<Bit>,
    /// The division rounds (else floors), loaded at its set-up.
    u_rnd: DFF<Bit>,
    /// The quotient's increment adj (RoundTst).
    u_adj: DFF<Bit>,
    /// u_adj ^ u_neg, written beside it (timing: the u_q chain starts at registers).
    u_adjq: DFF<Bit>,
    /// u_x, inverted when u_neg (free-running; timing: the u_q chain starts at registers).
    uxs: DFF<Bits<64>>,
    /// Steps left in the run.
    it: DFF<Bits<8>>,
    /// Run is a division (set at the set-up, cleared after the last B clock, like the two
    /// below).
    f_div: DFF<Bit>,
    /// Run is a square root.
    f_sq: DFF<Bit>,
    /// Run is a multiplication.
    f_mul: DFF<Bit>,
    /// An A clock: u_r takes the chain's sum {oa, 1} + ob (also the division's RoundSum).
    f_add: DFF<Bit>,
    /// An A clock of a division or product: u_x shifts by one.
    f_sh1: DFF<Bit>,
    /// An A clock of a square root: u_x shifts by two.
    f_sh2: DFF<Bit>,
    /// A division's B clock after an A clock: the quotient bit !rneg into u_x bit 0.
    f_qx: DFF<Bit>,
    /// A square root's B clock after an A clock: the root bit !rneg into u_d (8 q + 1).
    f_qd: DFF<Bit>,
    /// The run's last B clock.
    f_last: DFF<Bit>,
    /// u_x loads u_q (RoundNeg).
    x_q: DFF<Bit>,
    /// u_x loads (a set-up, a shift, RoundNeg): the registered enable of its AND-OR mux
    /// (timing: no state decode on u_x's enable path; d_en, clr_r, x_q likewise).
    x_en: DFF<Bit>,
    /// u_d loads (a set-up, a root bit).
    d_en: DFF<Bit>,
    /// u_r is cleared (a set-up).
    clr_r: DFF<Bit>,
    /// The chain's first operand, written in a B clock (the chain adds {oa, 1}).
    oa: DFF<Bits<52>>,
    /// {opb, cin}: its second operand and carry in.
    ob: DFF<Bits<53>>,
    /// u_x's source through registers: uxa | uxb | uxc (free-running; timing: with the three
    /// below, the sources written rows earlier stay off the u_x mux path).
    uxr: DFF<Bits<64>>,
    /// The source dn selects among Σd_c 2^8, Σd_s², Σd_c², |Σd_s d_c|, 2 V_s.
    uxa: DFF<Bits<64>>,
    /// The source dn selects among m_s 2^32, m_c 2^32, 2 V_c, Amp_s 2^32.
    uxb: DFF<Bits<64>>,
    /// The source dn selects among Amp_c 2^32, |C| 2^16, T 2^(GF+8), T 2^(GF+23), T 2^32.
    uxc: DFF<Bits<64>>,
    /// u_d's source through a register: the one dn selects among m_s, m_c, Amp_s, Cc, |S|,
    /// Amp_s Cc (timing: off the u_d mux path).
    udr: DFF<Bits<52>>,
    /// (u_r ^ u_d) ^ ((u_r | u_d) << 1), zero exactly when u_r + u_d = 0 (mod 2^52): in a
    /// zero sum the carry into bit i is a_i ^ b_i and out of it a_i | b_i (free-running).
    xr: DFF<Bits<52>>,
    /// u_r == 0 (free-running).
    rz: DFF<Bit>,
    /// xr == 0, i.e. u_r == -u_d (free-running).
    req: DFF<Bit>,
    /// u_r < 0 (the non-restoring remainder's sign).
    rneg: Signal<Local, Bit>,
    /// A run is under way.
    run: Signal<Local, Bit>,
    /// A run's B clock that is not its last: the next clock is an A clock.
    step: Signal<Local, Bit>,
    /// The chain's first operand: 2 u_r (+ msb(u_x)) or 4 u_r + top2(u_x).
    opa: Signal<Local, Bits<52>>,
    /// Add (u_r < 0, or the multiplier's bit is one), else subtract.
    up: Signal<Local, Bit>,
    /// The chain's second operand: u_d / the trial when adding, its complement otherwise.
    opb: Signal<Local, Bits<52>>,
    /// u_adj as a 24-bit addend.
    adjw: Signal<Local, Bits<24>>,
    /// u_adjq as a 64-bit addend.
    adjqw: Signal<Local, Bits<64>>,
    /// The increment RoundTst writes into u_adj.
    adjn: Signal<Local, Bit>,
    /// The sign the row being set up gives its quotient.
    negn: Signal<Local, Bit>,
    /// u_x's next value when x_en: its selected sources ORed.
    uxn: Signal<Local, Bits<64>>,
    /// u_d's next value when d_en.
    udn: Signal<Local, Bits<52>>,
    /// uxa's next value: its selected sources ORed.
    uxan: Signal<Local, Bits<64>>,
    /// uxb's next value.
    uxbn: Signal<Local, Bits<64>>,
    /// uxc's next value.
    uxcn: Signal<Local, Bits<64>>,
    /// udr's next value.
    udrn: Signal<Local, Bits<52>>,
    // ---- the solve's values
    /// N of the window.
    sn: DFF<Bits<25>>,
    /// Σd_s's low 40 bits (the snapshot's registers load while `rdy`; the start's is last).
    d1_s: DFF<Bits<40>>,
    /// Σd_c's low 40 bits.
    d1_c: DFF<Bits<40>>,
    /// |Σd_s|, free-running from d1_s and its sign (a clock after the start).
    a1_s: DFF<Bits<40>>,
    /// |Σd_c|, likewise.
    a1_c: DFF<Bits<40>>,
    /// Σd_s < 0.
    n1_s: DFF<Bit>,
    /// Σd_c < 0.
    n1_c: DFF<Bit>,
    /// Σd_s².
    a2_s: DFF<Bits<56>>,
    /// Σd_c².
    a2_c: DFF<Bits<56>>,
    /// Σd_s d_c's low 56 bits.
    dsc: DFF<Bits<56>>,
    /// |Σd_s d_c| (free-running): dsc, or ~x + 1 from the registered halves below (a select).
    asc: DFF<Bits<56>>,
    /// 0 - dsc's bits 0-27 (free-running; timing: the negation in two 28-bit chains).
    asl: DFF<Bits<28>>,
    /// 0 - dsc's bits 28-55 (free-running): the high half of -x when bits 0-27 are zero.
    ash: DFF<Bits<28>>,
    /// dsc's bits 0-27 are zero (free-running).
    alz: DFF<Bit>,
    /// Σd_s d_c < 0.
    nsc: DFF<Bit>,
    /// Sine b_ref of the window.
    br_s: DFF<Bits<32>>,
    /// Cosine b_ref of the window.
    br_c: DFF<Bits<32>>,
    /// |m_s|.
    m_s: DFF<Bits<24>>,
    /// |m_c|.
    m_c: DFF<Bits<24>>,
    /// floor(Σd_s² 2^16 / N), then V_s, 49-bit two's complement.
    v_s: DFF<Bits<49>>,
    /// floor(Σd_c² 2^16 / N), then V_c.
    v_c: DFF<Bits<49>>,
    /// Cq = floor(Σd_s d_c 2^16 / N), then C, 50-bit two's complement.
    cc: DFF<Bits<50>>,
    /// Amp_s.
    amp_s: DFF<Bits<25>>,
    /// Amp_c.
    amp_c: DFF<Bits<25>>,
    /// |S|, clamped.
    smag: DFF<Bits<16>>,
    /// S < 0 (or S = 0 from C >= 0).
    sneg: DFF<Bit>,
    /// Cc.
    cs: DFF<Bits<16>>,
    /// The new sine gain code, clamped.
    ng_s: DFF<Bits<16>>,
    /// The new cosine gain code, clamped.
    ng_c: DFF<Bits<16>>,
    /// Amp_s Cc.
    q2: DFF<Bits<40>>,
    // ---- free-running: each a clock behind its inputs, read rows later
    /// v_c when the running row subtracts from V_c, else v_s (timing: vd's chain starts at
    /// registers).
    vsel: DFF<Bits<49>>,
    /// vsel - u_r: V - m².
    vd: DFF<Bits<49>>,
    /// cc + u_r: C when the means' signs differ.
    ccp: DFF<Bits<50>>,
    /// cc - u_r: C when they agree.
    ccm: DFF<Bits<50>>,
    /// The low 48 bits of -C.
    ccn: DFF<Bits<48>>,
    /// |C|'s 48 bits (C or ccn by C's sign: a select).
    cmag: DFF<Bits<48>>,
    /// C >= 0.
    cpos: DFF<Bit>,
    /// 2^30 - u_r, low 31 bits: 2^30 - S².
    t30: DFF<Bits<31>>,
    /// round(|m_s| / 2^8).
    t_s: DFF<Bits<32>>,
    /// round(|m_c| / 2^8).
    t_c: DFF<Bits<32>>,
    /// The new sine offset b_ref +- t_s.
    o_s: DFF<Bits<32>>,
    /// The new cosine offset.
    o_c: DFF<Bits<32>>,
    /// Amp_s < min_amplitude 2^8.
    lo_s: DFF<Bit>,
    /// Amp_c < min_amplitude 2^8.
    lo_c: DFF<Bit>,
    /// o_s below the A-bit range (timing: one compare a register, beside its offset).
    oor_sl: DFF<Bit>,
    /// o_s at or above it.
    oor_sh: DFF<Bit>,
    /// o_c below it.
    oor_cl: DFF<Bit>,
    /// o_c at or above it.
    oor_ch: DFF<Bit>,
    /// u_x bits 31..16 not all zero (with the six below, u_mag's compares from the quotient
    /// it rounds, two clocks ahead; timing: no chain in front of scl / ngf / big_*).
    xh1: DFF<Bit>,
    /// u_x bits 47..32 not all zero.
    xh2: DFF<Bit>,
    /// u_x bits 63..48 not all zero.
    xh3: DFF<Bit>,
    /// u_x bits 15..0 not all zero.
    xl: DFF<Bit>,
    /// u_x bits 15..0 > smax.
    xgt_s: DFF<Bit>,
    /// u_x bits 15..0 >= smax.
    xge_s: DFF<Bit>,
    /// u_x bits 15..0 all ones.
    xff: DFF<Bit>,
    /// u_mag > smax.
    big_s: DFF<Bit>,
    /// u_mag > 65535.
    big_c: DFF<Bit>,
    /// u_mag != 0.
    mnz: DFF<Bit>,
    /// u_x bits 63..16 not all zero: xh1 | xh2 | xh3.
    xh: Signal<Local, Bit>,
    /// min(u_mag, smax): the clamped |S|.
    scl: DFF<Bits<16>>,
    /// min(u_mag, 65535): a clamped gain or cross code.
    ngf: DFF<Bits<16>>,
    // ---- the coefficients in use
    /// Sine offset.
    r_os: DFFWithInit<Bits<32>>,
    /// Cosine offset.
    r_oc: DFFWithInit<Bits<32>>,
    /// Sine gain code.
    r_gs: DFFWithInit<Bits<16>>,
    /// Cosine gain code.
    r_gc: DFFWithInit<Bits<16>>,
    /// |k|.
    r_km: DFF<Bits<16>>,
    /// k < 0.
    r_kn: DFF<Bit>,
    /// The coefficients loaded in the clock before.
    r_done: DFF<Bit>,
    // ---- constants
    /// min_amplitude 2^8.
    minamp: Constant<Bits<25>>,
    /// T 2^(GF+8): dividend of g_s.
    tgs: Constant<Bits<64>>,
    /// T 2^(GF+23): dividend of g_c.
    tgc: Constant<Bits<64>>,
    /// T 2^32: the multiplier operand of T |S|.
    tamp32: Constant<Bits<64>>,
    /// GF + 8: the shift of T |S|.
    kshift: Constant<Bits<32>>,
    /// 2^30.
    two30: Constant<Bits<31>>,
    /// The offset range limits -2^(A-1), 2^(A-1) with the sign bit flipped (unsigned
    /// compares).
    lo_f: Constant<Bits<32>>,
    /// See lo_f.
    hi_f: Constant<Bits<32>>,
    /// Bit 31.
    sign32: Constant<Bits<32>>,
    /// Bit 63.
    sign63: Constant<Bits<64>>,
    /// 128: the rounding half of a division by 2^8.
    half8: Constant<Bits<32>>,
    /// 65535.
    cmax16: Constant<Bits<16>>,
    /// round(2^15 sin 15°), the clamp of |S|.
    smax16: Constant<Bits<16>>,
    /// 52-bit constants: all ones, 1, 9, bits 1 and 2, and masks without bit 1 / bit 2.
    ones52: Constant<Bits<52>>,
    /// See ones52.
    one52: Constant<Bits<52>>,
    /// See ones52.
    nine52: Constant<Bits<52>>,
    /// See ones52.
    b1: Constant<Bits<52>>,
    /// See ones52.
    b2: Constant<Bits<52>>,
    /// See ones52.
    nb1: Constant<Bits<52>>,
    /// See ones52.
    nb2: Constant<Bits<52>>,
    /// 1 in 53 bits.
    one53: Constant<Bits<53>>,
    /// 1 in 24 bits.
    one24: Constant<Bits<24>>,
    /// 1 in 64 bits.
    one64: Constant<Bits<64>>,
    /// 1 in 5 bits.
    one5: Constant<Bits<5>>,
    /// 0 in 5 bits.
    zero5: Constant<Bits<5>>,
    /// Zeros: the minuends of negations, the empty AND-OR.
    zero64: Constant<Bits<64>>,
    /// See zero64.
    zero52: Constant<Bits<52>>,
    /// See zero64.
    zero50: Constant<Bits<50>>,
    /// See zero64.
    zero40: Constant<Bits<40>>,
    /// See zero64.
    zero28: Constant<Bits<28>>,
    /// See zero64.
    zero24: Constant<Bits<24>>,
    /// See zero64.
    zero16: Constant<Bits<16>>,
    /// Step counts 32, 64, 80 and 1.
    i32c: Constant<Bits<8>>,
    /// See i32c.
    i64c: Constant<Bits<8>>,
    /// See i32c.
    i80c: Constant<Bits<8>>,
    /// See i32c.
    one8: Constant<Bits<8>>,
    /// Configured (reset) sine offset.
    b0_s: Constant<Bits<32>>,
    /// Configured cosine offset.
    b0_c: Constant<Bits<32>>,
    /// Configured sine gain.
    g0_s: Constant<Bits<16>>,
    /// Configured cosine gain.
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

/// `T { the fields given, every other field named after the braces: Default::default() }`.
macro_rules! with_defaults {
    ($t:ident { $($f:ident: $v:expr,)* } $($d:ident)*) => {
        $t { $($f: $v,)* $($d: Default::default(),)* }
    };
}

impl FitSolve {
    /// Solver for `k` starting from (and reset to) the offsets and gains of `p`.
    pub fn new(p: &CorrectionParams, k: SolveConsts) -> Self {
        let gf = k.gain_frac_bits;
        let t = k.target_amplitude as u64;
        let lim = 1i64 << (k.adc_width - 1);
        let flip = |v: i64| (v as u64 & mask(32)) ^ (1 << 31);
        let sext = |v: i32| v as i64 as u64 & mask(32);
        with_defaults!(Self {
            rom: TableRom::new(),
            nosel: Constant::new(Sel::default()),
            row0: Constant::new(sel(0)),
            r_os: DFFWithInit::new(Bits::<32>::from(sext(p.offset()[SIN]))),
            r_oc: DFFWithInit::new(Bits::<32>::from(sext(p.offset()[COS]))),
            r_gs: DFFWithInit::new(Bits::<16>::from(p.gain()[SIN] as u64)),
            r_gc: DFFWithInit::new(Bits::<16>::from(p.gain()[COS] as u64)),
            minamp: cw((k.min_amplitude as u64) << 8),
            tgs: c64(t << (gf + 8)),
            tgc: c64(t << (gf + 23)),
            tamp32: c64(t << 32),
            kshift: c32((gf + 8) as u64),
            two30: cw(1 << 30),
            lo_f: c32(flip(-lim)),
            hi_f: c32(flip(lim)),
            sign32: c32(1 << 31),
            sign63: c64(1 << 63),
            half8: c32(128),
            cmax16: c16(0xffff),
            smax16: c16((32768.0 * 15f64.to_radians().sin()).round() as u64),
            ones52: cw(mask(52)),
            one52: cw(1),
            nine52: cw(9),
            b1: cw(2),
            b2: cw(4),
            nb1: cw(mask(52) ^ 2),
            nb2: cw(mask(52) ^ 4),
            one53: cw(1),
            one24: cw(1),
            one64: c64(1),
            one5: cw(1),
            zero5: cw(0),
            zero64: c64(0),
            zero52: cw(0),
            zero50: cw(0),
            zero40: cw(0),
            zero28: cw(0),
            zero24: cw(0),
            zero16: c16(0),
            i32c: cw(32),
            i64c: cw(64),
            i80c: cw(80),
            one8: cw(1),
            b0_s: c32(sext(p.offset()[SIN])),
            b0_c: c32(sext(p.offset()[COS])),
            g0_s: c16(p.gain()[SIN] as u64),
            g0_c: c16(p.gain()[COS] as u64),
        }
            clk rst start n s1_s s1_c s2_s s2_c ssc bref_s bref_c busy done off_s off_c g_s
            g_c k_mag k_neg state pc dn pl rdy launch refuse f_ret bad go ret u_x u_d u_r
            u_mag u_q u_neg u_rnd u_adj u_adjq uxs it f_div f_sq f_mul f_add f_sh1 f_sh2
            f_qx f_qd f_last x_q x_en d_en clr_r oa ob uxr uxa uxb uxc udr xr rz req rneg
            run step opa up opb adjw adjqw adjn negn uxn udn uxan uxbn uxcn udrn sn d1_s
            d1_c a1_s a1_c n1_s n1_c a2_s a2_c dsc asc asl ash alz nsc br_s br_c m_s m_c v_s
            v_c cc amp_s amp_c smag sneg cs ng_s ng_c q2 vsel vd ccp ccm ccn cmag cpos t30
            t_s t_c o_s o_c lo_s lo_c oor_sl oor_sh oor_cl oor_ch xh1 xh2 xh3 xl xgt_s xge_s
            xff big_s big_c mnz xh scl ngf r_km r_kn r_done)
    }
}
mod cosim;
mod operands;
mod table;
mod update;
mod values;
