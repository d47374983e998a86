//! rust-hdl description of the automatic calibration by least-squares ellipse fit (mode
//! `auto`): the quadrant tracker and the window sums of [`super::fit::EllipseFit`], one
//! sample every third clock at most (the ADC delivers one per frame), feeding the serial
//! solver [`super::fit_solve::FitSolve`], which loads offsets, gains and the phase cross
//! code together.
//!
//! ```text
//!           stage A (reg,     Q (reg) stage B1 (reg)       stage B2 (reg)        stage C (reg)
//!            held per sample)
//!  x ─►sext─► d  = x - b_ref ─┐                    ┌────────► entry d or e, |.|, ─► |e_s|, |e_c|,
//!            -d  = b_ref - x  ├─► q, step ─► net += s, N += 1, cmd (add/restart/    e_s, e_c,
//!  (both      e  = x - b_cur  │   (signs of  decision flags    snapshot); at a      flags
//!  tracks)   -e  = b_cur - x ─┘   d, or e    (add / restart /  restart b_ref :=        │
//!                                 while b_ref snapshot / use e) b_cur, net := 0,        │
//!                                 is loaded)   from registered   N := 1                 │
//!                                 from A's     compares of net, N                       │
//!                                 registers)   a clock earlier)                         ▼
//!  phases 0-2 (reg ta, tc, one a clock): (|e_s|, |e_s|), (|e_c|, |e_c|), (|e_s|, |e_c|)
//!  stages C1-C3 (reg): one run-time shift-add tree (multree.rs), one product a clock;
//!           valid, restart, snapshot in shift lines (ln_*), e_s, e_c held (e1, e2)
//!  stage D (reg): each product as its phase leaves the tree (phase 0: |e_s|², 1: |e_c|²,
//!           2: |e_s e_c| as a 64-bit ones' complement when negative, its +1 kept as
//!           stage E's carry-in), e sign-extended to 64 bits; the closing sample's
//!           phase 2 leaving the tree starts FitSolve (if idle) on the sums (they hold the
//!           window's samples by then) and the window's b_ref
//!  stage E: N, and the low 32 bits of Σe_s, Σe_c, Σe_s², Σe_c², Σe_s e_c (33-bit sums,
//!           carries registered); a restart clears the sums and N a clock earlier (as the
//!           registers' synchronous reset, in the snapshot's clock), so they restart from
//!           the sample
//!  stage E2 (a clock later): their high 32 bits (high addend + carry): 64-bit sums
//!           FitSolve ─► b_cur, g, k (all at once)
//! ```
//!
//! # Widths and bit growth (A = 10..=16)
//! * x, b in [-2^(A-1), 2^(A-1)): d = x - b in (-2^A, 2^A), 18-bit two's complement (the
//!   low 18 bits of the 32-bit difference, exact); |d| is
//!   the select of d or -d (two subtractors side by side), at most 2^A - 1 <= 65535, the
//!   unsigned 16-bit operand of a shift-add tree; products <= (2^16 - 1)^2 < 2^32 in 32-bit
//!   words, exact (each tree level is a 32-bit sum of partial products of the same
//!   product, [`super::multree`]).
//! * N <= N_MAX = 2^24 (a longer window is abandoned, [`super::fit::N_MAX`]): |Σd| < 2^40,
//!   Σd² and |Σd_s d_c| < 2^56, so the 64-bit sums never wrap; each is two adders: its
//!   low 32 bits plus the entry's in stage E (33 bits, the carry registered), its high 32
//!   bits plus the entry's bits 63..32 and that carry a clock later (stage E2), so no path
//!   holds a 64-bit chain. A
//!   negative cross product is added as !|p| + 1 (64-bit ones' complement registered in
//!   stage D, the +1 the sum's carry-in), which equals -|p| in a 64-bit word.
//! * net (the quadrants since the window opened) changes by at most 2 per sample and is
//!   bounded by 2 N_MAX: 32 bits. The window-closing test |net + s| >= 4K is done as compares
//!   of the registered net against constants, beside the adder net + s, so each path has one
//!   carry chain; (net + s) mod 4 = 0 is a 2-bit match. Where it holds, net + s is 4 (q + 1)
//!   for s = +1, +2 and 4 q for s = -1, -2 (q = floor(net / 4), net's bits 31..2), so two
//!   registered tests of q, |q + 1| >= K and |q| >= K (two 30-bit compares each), serve
//!   the four steps.
//!
//! # Timing and semantics
//! * The tracker and the sums follow the model sample for sample. Samples must be at least
//!   three clocks apart (the ADC controller delivers one per frame, tens of clocks; the
//!   tests every 3 to 12): stage A of the next sample runs with stage B2 of this one or
//!   later, and its stage B1 reads the step-class flags formed after this one's (above).
//! * Stage B1 decides (the window-closing compares of `net` and N are free-running
//!   registers, so they describe the last sample's state two clocks after it), and only a
//!   handful of flags wait for the decision: net and N count every sample in B1, and
//!   stage B2 acts a clock later on the registered flags: it clears net and N and loads
//!   b_ref at a restart, and writes the sums' command (about 230 register bits, driven by
//!   four flags instead of by the compares through the decision). While a restart clears
//!   net and N the compares are forced to describe net = 0, N = 1.
//! * The registered compares, N's flags and the decision's other operands (`p_*`, from
//!   the tracker's state and net mod 4, registered beside the compares) are combined a
//!   clock later into one register per
//!   step class and outcome (`cl*` closes, `rs*` restarts, `av*` takes the sample), final
//!   three clocks after the previous sample's stage B1; stage B1 reads only registers: the
//!   step and these ten flags (about six inputs per decision).
//! * b_ref of a new window is b_cur at its first sample, i.e. the offsets before the update
//!   its predecessor triggers (the model does the same, [`super::fit`]). b_ref is loaded in
//!   stage B2, while stage A may already take the next sample: that sample's quadrant
//!   comes from the signs of e = x - b_cur (the new b_ref) and its entry is e (`fresh`).
//! * Stage A registers the signs the quadrant is taken from (of e when the sample is
//!   `fresh`: one LUT after the subtractors' top bits); stage Q, a clock later, forms the
//!   quadrant and the step from them and the previous quadrant (one LUT of four
//!   registers), so no carry chain precedes stage Q's LUTs.
//! * The three products share one run-time shift-add tree (three register levels, C1-C3,
//!   then the product registers of stage D: one LUT level and one carry chain per path, no
//!   hard multiplier), one product a clock from the operand registers `ta`, `tc` (a mux
//!   of registers in front of them, none in front of the tree): |e_s|² a clock after
//!   stage C, |e_c|² and |e_s e_c| in the two clocks after that. Samples at least three
//!   clocks apart never meet in the tree. Stage C's flags follow in shift lines and the
//!   entries in two hold registers, so stage E adds all five sums in the clock after phase
//!   2's product is registered (six clocks after stage C). The solve starts as the closing
//!   sample's phase 2 leaves the tree, 10 clocks after the sample (the
//!   sums are complete: the window's last sample, at least three clocks earlier, has left
//!   stage E2, and the closing sample's stage E comes two clocks later). One tree instead
//!   of three: 3 more clocks.
//! * The outputs (offsets, gains, cross code, update) are copies of the solver's registers
//!   a clock later, so the datapath reads registers placed beside it (the tracker reads
//!   the solver's own): [`FIT_STAGES`] = 11 and [`super::fit_solve::UPDATE_LATENCY`] =
//!   [`super::fit_solve::SOLVE_CYCLES`] + [`FIT_STAGES`].
//! * The window's b_ref snapshot (`bs_*`, loaded in stage B2) cannot change before the
//!   start: the next window needs at least two more samples.
//! * A window that ends while the solver is still busy is dropped (the model has no such
//!   case: the config requires `min_samples` x clocks per sample > [`super::fit_solve::SOLVE_CYCLES`]).
//! * Reset (synchronous, active high): configured offsets and gains, k = 0, tracker waiting
//!   for its first sample, solver idle.
use super::fit::N_MAX;
use super::fit_solve::{c64, FitSolve, SolveConsts};
use super::multree::{MulTree, TREE_LEVELS};
use super::{CorrectionParams, COS, SIN};
use crate::blocks::{c32, fill, mask};
use rust_hdl::prelude::*;

mod build;
mod update;

/// Clocks the fit adds to the solve: from a sample at its input to the solver's start
/// when the sample closes a window (stages A, Q, B1, B2, the tree's operand register, the
/// [`TREE_LEVELS`] levels of the shared product tree and its phases 1 and 2: the solve
/// starts as the closing sample's phase 2 leaves the tree), and the output copies of the
/// coefficients (one clock). [`super::fit_solve::UPDATE_LATENCY`] is
/// [`super::fit_solve::SOLVE_CYCLES`] plus this.
pub const FIT_STAGES: u32 = 4 + 1 + TREE_LEVELS + 2 + 1;

// `nmax` takes N >= N_MAX from N's high bits.
const _: () = assert!(N_MAX.is_power_of_two());

fn c2(v: u64) -> Constant<Bits<2>> {
    Constant::new(Bits::<2>::from(v & 3))
}

/// The ellipse-fit calibration: tracker, sums and solver.
#[derive(LogicBlock)]
pub struct FitCal {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high.
    pub rst: Signal<In, Bit>,
    /// Sample strobe.
    pub valid: Signal<In, Bit>,
    /// Raw sine sample, A-bit two's complement in the low bits (upper bits ignored).
    pub x_sin: Signal<In, Bits<16>>,
    /// Raw cosine sample, A-bit two's complement in the low bits (upper bits ignored).
    pub x_cos: Signal<In, Bits<16>>,
    /// Sine offset in use, 32-bit two's complement.
    pub b_sin: Signal<Out, Bits<32>>,
    /// Cosine offset in use, 32-bit two's complement.
    pub b_cos: Signal<Out, Bits<32>>,
    /// Sine gain code in use, UQ(16-GF).GF.
    pub g_sin: Signal<Out, Bits<16>>,
    /// Cosine gain code in use (carries 1 / cos phi).
    pub g_cos: Signal<Out, Bits<16>>,
    /// |k|, the cross code of the phase correction in use.
    pub k_mag: Signal<Out, Bits<16>>,
    /// k < 0.
    pub k_neg: Signal<Out, Bit>,
    /// One clock when new coefficients have been loaded.
    pub update: Signal<Out, Bit>,
    /// `k_mag` one clock late: the code of the sample in the datapath's stage 1.
    pub k_mag_d: Signal<Out, Bits<16>>,
    /// `k_neg` one clock late.
    pub k_neg_d: Signal<Out, Bit>,
    slv: FitSolve,
    /// Stage C's products on one run-time shift-add tree (multree.rs), one product a clock:
    /// |e_s|² in phase 0, |e_c|² in phase 1, |e_s e_c| in phase 2, carrying the cross
    /// product's sign (`neg`); the phases are the bits of `ln_v`.
    tr: MulTree,
    /// The tree's operand registers: (|e_s|, |e_s|), (|e_c|, |e_c|), (|e_s|, |e_c|) in
    /// phases 0, 1, 2.
    ta: DFF<Bits<16>>,
    tc: DFF<Bits<16>>,
    /// |e_s|, |e_c| and the cross product's sign held from stage C for phases 1 and 2.
    h_ms: DFF<Bits<16>>,
    h_mc: DFF<Bits<16>>,
    h_nsc: DFF<Bit>,
    /// Shift lines of stage C's flags: bit j is the flag of the sample that was in stage C
    /// j + 1 clocks ago: valid (`ln_v`), restart (`ln_rs`), valid and snapshot (`ln_sn`).
    ln_v: DFF<Bits<8>>,
    ln_rs: DFF<Bits<8>>,
    ln_sn: DFF<Bits<8>>,
    /// The tree's sum out_x + out_y: the product of the phase leaving the tree.
    pr: Signal<Local, Bits<32>>,
    /// The entries e_s, e_c held from stage C (e1, loaded with it) and from phase 2 (e2,
    /// loaded from e1 three clocks after stage C) to stage D.
    e1_s: DFF<Bits<18>>,
    e2_s: DFF<Bits<18>>,
    e1_c: DFF<Bits<18>>,
    e2_c: DFF<Bits<18>>,
    /// The coefficients' output copies, a clock behind the solver's registers (reset with
    /// them): the datapath reads registers it can have beside it, not the solver's.
    o_bs: DFFWithInit<Bits<32>>,
    o_bc: DFFWithInit<Bits<32>>,
    o_gs: DFFWithInit<Bits<16>>,
    o_gc: DFFWithInit<Bits<16>>,
    o_km: DFF<Bits<16>>,
    o_kn: DFF<Bit>,
    o_up: DFF<Bit>,
    /// The cross code a clock behind its output copy (`k_mag_d`, `k_neg_d`).
    kd_m: DFF<Bits<16>>,
    kd_n: DFF<Bit>,
    /// The sample's valid in stage Q (registered in stage A) and in stage B1.
    va0: DFF<Bit>,
    va: DFF<Bit>,
    /// Stage A's differences, 18-bit two's complement (|x - b| < 2^A <= 2^16): d = x -
    /// b_ref, -d, e = x - b_cur, -e per track.
    da_s: DFF<Bits<18>>,
    nda_s: DFF<Bits<18>>,
    ea_s: DFF<Bits<18>>,
    nea_s: DFF<Bits<18>>,
    da_c: DFF<Bits<18>>,
    nda_c: DFF<Bits<18>>,
    ea_c: DFF<Bits<18>>,
    nea_c: DFF<Bits<18>>,
    bref_s: DFFWithInit<Bits<32>>,
    bref_c: DFFWithInit<Bits<32>>,
    tinit: DFF<Bit>,
    tq: DFF<Bits<2>>,
    dknown: DFF<Bit>,
    dneg: DFF<Bit>,
    open: DFF<Bit>,
    fresh: DFF<Bit>,
    /// Stage A: the signs the quadrant is taken from (of d, or of e at a restart).
    sg_s: DFF<Bit>,
    sg_c: DFF<Bit>,
    net: DFF<Bits<32>>,
    nb: DFF<Bits<32>>,
    bs_s: DFF<Bits<32>>,
    bs_c: DFF<Bits<32>>,
    c_v: DFF<Bit>,
    c_rs: DFF<Bit>,
    c_snap: DFF<Bit>,
    c_es: DFF<Bits<18>>,
    c_ec: DFF<Bits<18>>,
    c_ms: DFF<Bits<16>>,
    c_mc: DFF<Bits<16>>,
    c_nsc: DFF<Bit>,
    d_v: DFF<Bit>,
    d_es: DFF<Bits<64>>,
    d_ec: DFF<Bits<64>>,
    p_ss: DFF<Bits<32>>,
    p_cc: DFF<Bits<32>>,
    /// |e_s e_c| zero-extended to 64 bits, inverted when e_s e_c < 0 (ones' complement;
    /// the sum adds `d_nsc` as its carry-in), so stage E is one chain from registers.
    p_sc: DFF<Bits<64>>,
    d_nsc: DFF<Bit>,
    cnt: DFF<Bits<32>>,
    /// The window-closing compares |net + s| >= 4K where net + s is a multiple of 4 and
    /// N >= min_samples, registered from `net` and `nb` (free-running; final two clocks
    /// after a sample's stage B1): |q + 1| >= K for s = +1, +2 (`h_up`), |q| >= K for
    /// s = -1, -2 (`h_dn`), q = floor(net / 4).
    h_up: DFF<Bit>,
    h_dn: DFF<Bit>,
    nbge: DFF<Bit>,
    /// N >= N_MAX (N's bits from log2 N_MAX up; while the window is open N <= N_MAX, so
    /// this is N = N_MAX), registered like the compares above.
    nbmx: DFF<Bit>,
    /// Stage B1's operands that do not wait for the compares, registered like them from
    /// the tracker's state (written in stage B1): open at a +-1 step (`p_r1`) or a known
    /// 2-step (`p_r2`); the window is open (`p_o1`; with a known direction `p_o2`).
    p_r1: DFF<Bit>,
    p_r2: DFF<Bit>,
    p_o1: DFF<Bit>,
    p_o2: DFF<Bit>,
    /// The window is open and net + s is a multiple of 4, for s = +1 (`p_w1`), -1 (`p_w3`),
    /// +2 (`p_w2p`) and -2 (`p_w2m`, the known direction chooses s = +-2).
    p_w1: DFF<Bit>,
    p_w3: DFF<Bit>,
    p_w2p: DFF<Bit>,
    p_w2m: DFF<Bit>,
    /// Stage B1's decision for stage B2: add the sample, restart the sums (and b_ref, net,
    /// N), snapshot the window, take the entry from e = x - b_cur.
    a_v: DFF<Bit>,
    a_rs: DFF<Bit>,
    /// The restart again, inverted: b_ref's 64 loads have their own driver.
    a_rb: DFF<Bit>,
    a_snap: DFF<Bit>,
    a_ue: DFF<Bit>,
    /// Stage E: the low 32 bits of the sums Σe_s, Σe_c, Σe_s², Σe_c², Σe_s e_c, and the
    /// carries out of them (each a 33-bit sum on registers).
    l1_s: DFF<Bits<32>>,
    l1_c: DFF<Bits<32>>,
    l2_s: DFF<Bits<32>>,
    l2_c: DFF<Bits<32>>,
    lsc: DFF<Bits<32>>,
    y1_s: DFF<Bit>,
    y1_c: DFF<Bit>,
    y2_s: DFF<Bit>,
    y2_c: DFF<Bit>,
    ysc: DFF<Bit>,
    /// Stage E2, a clock after E: the sums' high 32 bits (high addend plus the carry).
    h1_s: DFF<Bits<32>>,
    h1_c: DFF<Bits<32>>,
    h2_s: DFF<Bits<32>>,
    h2_c: DFF<Bits<32>>,
    hsc: DFF<Bits<32>>,
    /// Stage E2's high addends (bits 63..32 of the entries: sign extensions of e and of
    /// the cross product's ones' complement), its valid flag.
    x1_s: DFF<Bits<32>>,
    x1_c: DFF<Bits<32>>,
    xsc: DFF<Bits<32>>,
    f_v: DFF<Bit>,
    xs: Signal<Local, Bits<32>>,
    xc: Signal<Local, Bits<32>>,
    /// Stage B2: the sample's entry to the sums (d, or e at or right after a restart).
    ds: Signal<Local, Bits<18>>,
    dc: Signal<Local, Bits<18>>,
    /// Stage A: x - b_ref (the quadrant's signs), the quadrant and the step from tq.
    das: Signal<Local, Bits<18>>,
    dac: Signal<Local, Bits<18>>,
    /// Stage A: x - b_cur.
    eas: Signal<Local, Bits<18>>,
    eac: Signal<Local, Bits<18>>,
    q: Signal<Local, Bits<2>>,
    stp: Signal<Local, Bits<2>>,
    /// Stage B: the sample's quadrant and step (registered in stage A).
    qb: DFF<Bits<2>>,
    sb: DFF<Bits<2>>,
    /// Stage B: the step s as a 32-bit word, and the closing tests for it.
    sval: Signal<Local, Bits<32>>,
    netq: Signal<Local, Bits<32>>,
    /// Stage B1's operands per step class (+1, -1, +-2), each one register formed from the
    /// registered compares and the tracker's flags above (final three clocks after a
    /// sample's stage B1, so samples must be at least three clocks apart):
    /// the window closes (`cl*`), restarts (`rs*`), takes the sample (`av*`; `av0` for no
    /// step). Stage B1 then chooses among them by the step: a few inputs per decision.
    cl1: DFF<Bit>,
    cl3: DFF<Bit>,
    cl2: DFF<Bit>,
    rs1: DFF<Bit>,
    rs3: DFF<Bit>,
    rs2: DFF<Bit>,
    av0: DFF<Bit>,
    av1: DFF<Bit>,
    av3: DFF<Bit>,
    av2: DFF<Bit>,
    /// Stage B1: the restart (`rs*` chosen by the step).
    rsd: Signal<Local, Bit>,
    /// Stage E: the low halves' 33-bit sums.
    w1_s: Signal<Local, Bits<33>>,
    w1_c: Signal<Local, Bits<33>>,
    w2_s: Signal<Local, Bits<33>>,
    w2_c: Signal<Local, Bits<33>>,
    wsc: Signal<Local, Bits<33>>,
    /// Quadrant codes.
    q0: Constant<Bits<2>>,
    q1: Constant<Bits<2>>,
    q2: Constant<Bits<2>>,
    q3: Constant<Bits<2>>,
    /// Step words +1, -1, +2, -2.
    sp1: Constant<Bits<32>>,
    sm1: Constant<Bits<32>>,
    sp2: Constant<Bits<32>>,
    sm2: Constant<Bits<32>>,
    /// Closing compares of q = floor(net / 4) (net's sign bit flipped, shifted right by 2,
    /// against constants formed the same way): q >= K - 1 or q < -K (|q + 1| >= K, `*_up`),
    /// q >= K or q < -K + 1 (|q| >= K, `*_dn`).
    ge_up: Constant<Bits<32>>,
    lt_up: Constant<Bits<32>>,
    ge_dn: Constant<Bits<32>>,
    lt_dn: Constant<Bits<32>>,
    /// Shift of 2.
    two32: Constant<Bits<32>>,
    /// net mod 4 that makes net + s a multiple of 4: 3 for +1, 1 for -1, 2 for +-2.
    r3: Constant<Bits<32>>,
    r1: Constant<Bits<32>>,
    r2: Constant<Bits<32>>,
    /// Mask of two bits.
    m2: Constant<Bits<32>>,
    /// min_samples, and the bits of N from log2 N_MAX up (N_MAX is a power of two).
    nmin: Constant<Bits<32>>,
    nmax: Constant<Bits<32>>,
    /// A-bit sample handling.
    amask: Constant<Bits<32>>,
    asign: Constant<Bits<32>>,
    asext: Constant<Bits<32>>,
    /// Bit 31.
    sign32: Constant<Bits<32>>,
    /// Bits 18..63: an 18-bit entry's sign extension to 64 bits.
    sext64: Constant<Bits<64>>,
    one32: Constant<Bits<32>>,
    zero32: Constant<Bits<32>>,
    zero64: Constant<Bits<64>>,
    /// All ones, 64 bits.
    ones64: Constant<Bits<64>>,
    /// -|e_s e_c|'s ones' complement mask in stage D.
    nscm: Signal<Local, Bits<64>>,
    /// The carry-in of the cross sum in stage E (one when e_s e_c < 0).
    nsci: Signal<Local, Bits<33>>,
    /// 32 (the high half's shift), 64 bits.
    s32w: Constant<Bits<64>>,
    /// One, 33 bits.
    one33: Constant<Bits<33>>,
    /// Zero, 8 bits (the flag lines' reset).
    zero8: Constant<Bits<8>>,
    /// Zero, 33 bits.
    zero33: Constant<Bits<33>>,
    /// Configured (reset) offsets, 32-bit two's complement.
    b0_s: Constant<Bits<32>>,
    b0_c: Constant<Bits<32>>,
    /// Configured (reset) gain codes.
    g0_s: Constant<Bits<16>>,
    g0_c: Constant<Bits<16>>,
    /// Zero, 16 bits.
    zero16: Constant<Bits<16>>,
}

/// Settings of the fit besides the datapath's.
#[derive(Clone, Copy, Debug)]
pub struct FitConsts {
    /// The solver's constants.
    pub solve: SolveConsts,
    /// Least whole periods K per window.
    pub periods: u32,
    /// Least samples per window (<= N_MAX).
    pub min_samples: u32,
}

impl FitConsts {
    /// The fit's settings of `p` (None unless `p.fit()` is on).
    pub fn of(p: &CorrectionParams) -> Option<Self> {
        p.fit().map(|f| FitConsts {
            solve: SolveConsts {
                adc_width: p.adc_width(),
                gain_frac_bits: p.gain_frac_bits(),
                target_amplitude: f.target_amplitude(),
                min_amplitude: f.min_amplitude(),
            },
            periods: f.periods(),
            min_samples: f.min_samples(),
        })
    }
}

crate::cosim::cosim_block!(FitCal {
    inputs: [rst: 1, valid: 1, x_sin: 16, x_cos: 16],
    outputs: [b_sin: 32, b_cos: 32, g_sin: 16, g_cos: 16, k_mag: 16, k_neg: 1, update: 1],
});
