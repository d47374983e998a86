//! The solver's program: [`TABLE`], one row per operation of [`crate::blocks::correction::fit::solve`],
//! its latency, and its decode into the one-hot selects of [`super::FitSolve`].
use crate::blocks::correction::fit::N_MAX;
use crate::blocks::correction::fit_hdl::FIT_STAGES;
use rust_hdl::prelude::*;

/// The operation of a row on the shared units.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    /// u_x / u_d over `steps` (64: u_x / u_d; 80: u_x 2^16 / u_d); rounded half away from
    /// zero (`round`) or floored; negated when `neg` holds.
    Div {
        /// Quotient bits: 64 or 80.
        steps: u32,
        /// Round (else floor).
        round: bool,
        /// The sign of the result.
        neg: Sign,
    },
    /// (u_x >> 32) u_d, one multiplier bit a step (32 steps).
    Mul,
    /// isqrt(u_x), two radicand bits a step (32 steps); u_d starts at 1.
    Sqrt,
}

/// The sign a division gives its quotient.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sign {
    /// Non-negative.
    Pos,
    /// Σd_s < 0.
    SumS,
    /// Σd_c < 0.
    SumC,
    /// Σd_s d_c < 0.
    SumSc,
    /// C >= 0 (S = rdiv(-C 2^16, ...)).
    CPos,
    /// The sign S was given.
    SNeg,
}

/// A value a row loads into u_x (dividend, multiplier 2^32, radicand) or u_d (divisor,
/// multiplicand, first trial). The last six are the row before's result, loaded directly.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Src {
    /// |Σd_s| 2^8 (u_x).
    A1s8,
    /// |Σd_c| 2^8 (u_x).
    A1c8,
    /// Σd_s² (u_x).
    A2s,
    /// Σd_c² (u_x).
    A2c,
    /// |Σd_s d_c| (u_x).
    Asc,
    /// |m_s| 2^32 (u_x).
    Ms32,
    /// |m_c| 2^32 (u_x).
    Mc32,
    /// 2 V_s, 0 if V_s < 0 (u_x).
    Vs2,
    /// 2 V_c, 0 if V_c < 0 (u_x).
    Vc2,
    /// Amp_s 2^32 (u_x).
    AmpS32,
    /// Amp_c 2^32 (u_x).
    AmpC32,
    /// |C| 2^16 (u_x).
    Cmag16,
    /// T 2^(GF+8) (u_x).
    Tgs,
    /// T 2^(GF+23) (u_x).
    Tgc,
    /// T 2^32 (u_x).
    T32,
    /// N (u_d).
    N,
    /// |m_s| (u_d).
    Ms,
    /// |m_c| (u_d).
    Mc,
    /// Amp_s (u_d).
    AmpS,
    /// Cc (u_d).
    Cs,
    /// |S| (u_d).
    Smag,
    /// Amp_s Cc (u_d).
    Q2,
    /// 1, a square root's first trial 8 q + 1 (u_d).
    One,
    /// The row before's root (u_d).
    Root,
    /// The row before's product (u_d).
    Prod,
    /// The row before's product 2^(GF+8) (u_x).
    ProdK,
    /// 2^30 - the row before's product (u_x).
    T30,
    /// The row before's |quotient| clamped to round(2^15 sin 15°) (u_d).
    Scl,
    /// That, 2^32 (u_x).
    Scl32,
}

/// Where a row's result goes (written at the next row's set-up, or at Load).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dst {
    /// Nowhere: the next row loads it directly.
    Next,
    /// m_s (magnitude; its sign is Σd_s's).
    Ms,
    /// m_c.
    Mc,
    /// V_s.
    Vs,
    /// V_c.
    Vc,
    /// C (Cq for now).
    Cq,
    /// V_s -= the product.
    VsLessProd,
    /// V_c -= the product.
    VcLessProd,
    /// C = Cq - m_s m_c (the product's sign from Σd_s's and Σd_c's).
    C,
    /// Amp_s.
    AmpS,
    /// Amp_c.
    AmpC,
    /// S, clamped to +-round(2^15 sin 15°).
    S,
    /// Cc.
    Cs,
    /// g_s, clamped to 65535.
    Gs,
    /// g_c, clamped to 65535.
    Gc,
    /// Amp_s Cc.
    Q2,
    /// k, |k| clamped to 65535; then every coefficient loads.
    K,
}

/// One step of the solve.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Row {
    /// Operation.
    pub op: Op,
    /// u_x's source.
    pub x: Src,
    /// u_d's source.
    pub d: Src,
    /// Destination of the result.
    pub dst: Dst,
    /// Before this row: refuse (no update) if an amplitude is below min_amplitude 2^8 or an
    /// offset b_ref + round(m / 2^8) is outside the A-bit range.
    pub check: bool,
}

const fn div(steps: u32, round: bool, neg: Sign, x: Src, d: Src, dst: Dst) -> Row {
    let op = Op::Div { steps, round, neg };
    Row {
        op,
        x,
        d,
        dst,
        check: false,
    }
}

const fn mul(x: Src, d: Src, dst: Dst) -> Row {
    Row {
        op: Op::Mul,
        x,
        d,
        dst,
        check: false,
    }
}

const fn sqrt(x: Src, dst: Dst) -> Row {
    Row {
        op: Op::Sqrt,
        x,
        d: Src::One,
        dst,
        check: false,
    }
}

const fn checked(r: Row) -> Row {
    Row { check: true, ..r }
}

const RND: bool = true;
const FLOOR: bool = false;

/// The solve, beside the lines of [`crate::blocks::correction::fit::solve`] it computes (s = the sums, m, v, c,
/// amp, sn, cs, gs, gc, k as there).
#[rustfmt::skip]
pub const TABLE: [Row; 20] = {
    use {Dst as D, Sign as G, Src as S};
    [
        div(64, RND, G::SumS, S::A1s8, S::N, D::Ms),      // m[0] = rdiv(s1[0] << 8, n)
        div(64, RND, G::SumC, S::A1c8, S::N, D::Mc),      // m[1] = rdiv(s1[1] << 8, n)
        div(80, FLOOR, G::Pos, S::A2s, S::N, D::Vs),      // v[0] = (s2[0] << 16).div_euclid(n)
        div(80, FLOOR, G::Pos, S::A2c, S::N, D::Vc),      // v[1] = (s2[1] << 16).div_euclid(n)
        div(80, FLOOR, G::SumSc, S::Asc, S::N, D::Cq),    // c = (sc << 16).div_euclid(n)
        mul(S::Ms32, S::Ms, D::VsLessProd),               //   v[0] -= m[0] * m[0]
        mul(S::Mc32, S::Mc, D::VcLessProd),               //   v[1] -= m[1] * m[1]
        mul(S::Ms32, S::Mc, D::C),                        //   c -= m[0] * m[1]
        sqrt(S::Vs2, D::AmpS),                            // amp[0] = isqrt(2 * v[0])
        sqrt(S::Vc2, D::AmpC),                            // amp[1] = isqrt(2 * v[1])
        mul(S::AmpS32, S::Root, D::Next),                 // amp[0] * amp[1]
        checked(div(64, RND, G::CPos, S::Cmag16, S::Prod, D::S)), // amp < min, offset: None;
                                                          // sn = rdiv(-2c << 15, ..).clamp(..)
        mul(S::Scl32, S::Scl, D::Next),                   // sn * sn
        sqrt(S::T30, D::Cs),                              // cs = isqrt((1 << 30) - sn * sn)
        div(64, RND, G::Pos, S::Tgs, S::AmpS, D::Gs),     // gs = rdiv(t << (gf + 8), amp[0])
        mul(S::AmpC32, S::Cs, D::Next),                   // amp[1] * cs
        div(64, RND, G::Pos, S::Tgc, S::Prod, D::Gc),     // gc = rdiv(t << (gf + 23), ..)
        mul(S::AmpS32, S::Cs, D::Q2),                     // amp[0] * cs
        mul(S::T32, S::Smag, D::Next),                    // t * sn
        div(64, RND, G::SNeg, S::ProdK, S::Q2, D::K),     // k = rdiv((t * sn) << (gf + 8), ..)
    ]
};

/// Clocks a row takes: its set-up, 2 n + 1 for n steps (B, then A and B a step), and a
/// division's RoundSum, RoundTst, RoundInc and RoundNeg.
pub const fn row_cycles(r: &Row) -> u32 {
    match r.op {
        Op::Div { steps, .. } => 1 + (2 * steps + 1) + 4,
        Op::Mul | Op::Sqrt => 1 + (2 * 32 + 1),
    }
}

/// Clocks from the rising edge that takes `start` to the one that loads the coefficients
/// of an accepted solve: the launch clock, every row of [`TABLE`], then Load.
pub const SOLVE_CYCLES: u32 = {
    let (mut c, mut i) = (2, 0);
    while i < TABLE.len() {
        c += row_cycles(&TABLE[i]);
        i += 1;
    }
    c
};

/// Clocks from a window's first sample after its closing boundary (the sample presented
/// before rising edge j) to the new coefficients (on the outputs after edge j +
/// UPDATE_LATENCY): the fit's pipeline stages ([`FIT_STAGES`]), then
/// [`SOLVE_CYCLES`]; `tests/blocks/correction_fit_rtl.rs` checks every update against it.
pub const UPDATE_LATENCY: u32 = SOLVE_CYCLES + FIT_STAGES;

// The widths of the module doc assume windows of at most 2^24 samples.
const _: () = assert!(N_MAX <= 1 << 24);

/// A row decoded into one-hot selects (`x_*`/`d_*`: u_x / u_d sources that load directly;
/// `xs_*`/`ds_*`: those through uxr / udr; `w_*`: the row before's destination).
#[derive(Clone, Copy, Debug, Default, PartialEq, LogicStruct)]
pub(super) struct Sel {
    /// The operation: a division, root or product (one-clock mode pulses at the set-up).
    pub(super) div: Bit,
    pub(super) sq: Bit,
    pub(super) mul: Bit,
    /// 80 steps (else 64 in a division, 32 otherwise).
    pub(super) n80: Bit,
    /// The division rounds (else floors).
    pub(super) rnd: Bit,
    /// The quotient's sign: Σd_s < 0, Σd_c < 0, Σd_s d_c < 0, C >= 0, S < 0.
    pub(super) ng_s: Bit,
    pub(super) ng_c: Bit,
    pub(super) ng_sc: Bit,
    pub(super) ng_cpos: Bit,
    pub(super) ng_sneg: Bit,
    /// u_x loads directly: |Σd_s| 2^8, the clamped quotient 2^32, 2^30 - u_r, u_r 2^(GF+8), uxr.
    pub(super) x_a1s: Bit,
    pub(super) x_scl: Bit,
    pub(super) x_t30: Bit,
    pub(super) x_urk: Bit,
    pub(super) x_st: Bit,
    /// uxr's source (uxa, uxb, uxc), held through the row before: see `Src`.
    pub(super) xs_a1c: Bit,
    pub(super) xs_a2s: Bit,
    pub(super) xs_a2c: Bit,
    pub(super) xs_asc: Bit,
    pub(super) xs_ms: Bit,
    pub(super) xs_mc: Bit,
    pub(super) xs_vs2: Bit,
    pub(super) xs_vc2: Bit,
    pub(super) xs_amps: Bit,
    pub(super) xs_ampc: Bit,
    pub(super) xs_cmag: Bit,
    pub(super) xs_tgs: Bit,
    pub(super) xs_tgc: Bit,
    pub(super) xs_t32: Bit,
    /// u_d loads directly: N, the root, u_r, the clamped quotient, 1, udr.
    pub(super) d_sn: Bit,
    pub(super) d_root: Bit,
    pub(super) d_prod: Bit,
    pub(super) d_scl: Bit,
    pub(super) d_one: Bit,
    pub(super) d_st: Bit,
    /// udr's source, held: m_s, m_c, Amp_s, Cc, |S|, Amp_s Cc.
    pub(super) ds_ms: Bit,
    pub(super) ds_mc: Bit,
    pub(super) ds_amps: Bit,
    pub(super) ds_cs: Bit,
    pub(super) ds_smag: Bit,
    pub(super) ds_q2: Bit,
    /// The row before's destination: see `Dst` (w_vss, w_vcs: V -= product; w_k: Load).
    pub(super) w_ms: Bit,
    pub(super) w_mc: Bit,
    pub(super) w_vs: Bit,
    pub(super) w_vc: Bit,
    pub(super) w_cq: Bit,
    pub(super) w_vss: Bit,
    pub(super) w_vcs: Bit,
    pub(super) w_c: Bit,
    pub(super) w_amps: Bit,
    pub(super) w_ampc: Bit,
    pub(super) w_s: Bit,
    pub(super) w_cs: Bit,
    pub(super) w_gs: Bit,
    pub(super) w_gc: Bit,
    pub(super) w_q2: Bit,
    pub(super) w_k: Bit,
    /// Before this row: refuse unless the amplitudes and offsets pass.
    pub(super) chk: Bit,
    /// No row: Load.
    pub(super) end: Bit,
}

/// ROM word `i`: row i's operation, sources and check, and row i - 1's destination (written
/// at row i's set-up); word 20 ends the program (Load).
pub(super) fn sel(i: usize) -> Sel {
    let mut s = Sel::default();
    match i.checked_sub(1).map(|j| TABLE[j].dst) {
        Some(Dst::Ms) => s.w_ms = true,
        Some(Dst::Mc) => s.w_mc = true,
        Some(Dst::Vs) => s.w_vs = true,
        Some(Dst::Vc) => s.w_vc = true,
        Some(Dst::Cq) => s.w_cq = true,
        Some(Dst::VsLessProd) => s.w_vss = true,
        Some(Dst::VcLessProd) => s.w_vcs = true,
        Some(Dst::C) => s.w_c = true,
        Some(Dst::AmpS) => s.w_amps = true,
        Some(Dst::AmpC) => s.w_ampc = true,
        Some(Dst::S) => s.w_s = true,
        Some(Dst::Cs) => s.w_cs = true,
        Some(Dst::Gs) => s.w_gs = true,
        Some(Dst::Gc) => s.w_gc = true,
        Some(Dst::Q2) => s.w_q2 = true,
        Some(Dst::K) => s.w_k = true,
        Some(Dst::Next) | None => {}
    }
    let Some(r) = TABLE.get(i) else {
        s.end = true;
        return s;
    };
    s.chk = r.check;
    match r.op {
        Op::Div { steps, round, neg } => {
            assert!(
                steps == 64 || steps == 80,
                "row {i}: the divider runs 64 or 80 steps"
            );
            (s.div, s.n80, s.rnd) = (true, steps == 80, round);
            match neg {
                Sign::Pos => {}
                Sign::SumS => s.ng_s = true,
                Sign::SumC => s.ng_c = true,
                Sign::SumSc => s.ng_sc = true,
                Sign::CPos => s.ng_cpos = true,
                Sign::SNeg => s.ng_sneg = true,
            }
        }
        Op::Mul => s.mul = true,
        Op::Sqrt => s.sq = true,
    }
    s.x_st = true;
    match r.x {
        Src::A1s8 => (s.x_a1s, s.x_st) = (true, false),
        Src::Scl32 => (s.x_scl, s.x_st) = (true, false),
        Src::T30 => (s.x_t30, s.x_st) = (true, false),
        Src::ProdK => (s.x_urk, s.x_st) = (true, false),
        Src::A1c8 => s.xs_a1c = true,
        Src::A2s => s.xs_a2s = true,
        Src::A2c => s.xs_a2c = true,
        Src::Asc => s.xs_asc = true,
        Src::Ms32 => s.xs_ms = true,
        Src::Mc32 => s.xs_mc = true,
        Src::Vs2 => s.xs_vs2 = true,
        Src::Vc2 => s.xs_vc2 = true,
        Src::AmpS32 => s.xs_amps = true,
        Src::AmpC32 => s.xs_ampc = true,
        Src::Cmag16 => s.xs_cmag = true,
        Src::Tgs => s.xs_tgs = true,
        Src::Tgc => s.xs_tgc = true,
        Src::T32 => s.xs_t32 = true,
        x => panic!("row {i}: {x:?} is not a u_x source"),
    }
    s.d_st = true;
    match r.d {
        Src::N => (s.d_sn, s.d_st) = (true, false),
        Src::Root => (s.d_root, s.d_st) = (true, false),
        Src::Prod => (s.d_prod, s.d_st) = (true, false),
        Src::Scl => (s.d_scl, s.d_st) = (true, false),
        Src::One => (s.d_one, s.d_st) = (true, false),
        Src::Ms => s.ds_ms = true,
        Src::Mc => s.ds_mc = true,
        Src::AmpS => s.ds_amps = true,
        Src::Cs => s.ds_cs = true,
        Src::Smag => s.ds_smag = true,
        Src::Q2 => s.ds_q2 = true,
        d => panic!("row {i}: {d:?} is not a u_d source"),
    }
    s
}

/// [`TABLE`] as a combinational ROM: `data` is the word [`sel`] of row `address` (0 past
/// the end). Its Verilog ORs the words ANDed with their address compares, no case
/// statement: no synthesis flow infers a memory from it (a block RAM's clock-to-out would
/// sit in front of `dn`, and the Cyclone flow cannot map one).
#[derive(LogicBlock)]
pub(super) struct TableRom {
    /// The program counter.
    pub address: Signal<In, Bits<5>>,
    /// Its row's word.
    pub data: Signal<Out, Sel>,
    _words: Vec<Sel>,
}

impl TableRom {
    /// The ROM of [`TABLE`].
    pub(super) fn new() -> Self {
        Self {
            address: Default::default(),
            data: Default::default(),
            _words: (0..=TABLE.len()).map(sel).collect(),
        }
    }
}

impl Logic for TableRom {
    fn update(&mut self) {
        let i = self.address.val().index();
        self.data.next = self._words.get(i).copied().unwrap_or_default();
    }

    fn connect(&mut self) {
        self.data.connect();
    }

    fn hdl(&self) -> Verilog {
        let w = Sel::BITS;
        let terms = self
            ._words
            .iter()
            .enumerate()
            .map(|(i, s)| format!("({{{w}{{address == 5'd{i}}}}} & {})", s.verilog()));
        let terms: Vec<String> = terms.collect();
        Verilog::Custom(format!("always @* data = {};", terms.join("\n    | ")))
    }
}
