//! Bit-accurate model of the front-end correction and its automatic calibration: the RTL's
//! registers, all next values computed from the current ones, then committed.
use super::codes::CodesModel;
use super::{CorrectionParams, COS, SIN};
use crate::blocks::{mask, sext};

/// Inputs of one clock cycle.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CorrectionIn {
    /// Synchronous reset.
    pub rst: bool,
    /// Sample strobe.
    pub valid: bool,
    /// Sine word (the low 16 bits drive the port; the low A bits are the sample).
    pub sin: i32,
    /// Cosine word.
    pub cos: i32,
    /// Writable codes: one-hot load of the words of [`super::codes::WORDS`].
    pub ld: u8,
    /// Writable codes: the written bits (masked).
    pub ld_bits: u32,
    /// Writable codes: the bits written.
    pub ld_msk: u32,
}

impl CorrectionIn {
    /// Stimulus row in input-port order.
    pub fn row(&self) -> Vec<u64> {
        vec![
            self.rst as u64,
            self.valid as u64,
            self.sin as u64 & 0xffff,
            self.cos as u64 & 0xffff,
        ]
    }
    /// [`Self::row`] with the load port after it (a block with writable codes).
    pub fn row_writable(&self) -> Vec<u64> {
        let mut r = self.row();
        r.extend([self.ld as u64, self.ld_bits as u64, self.ld_msk as u64]);
        r
    }
}

/// Outputs after one clock edge (signed values sign-extended from A bits).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CorrectionOut {
    /// Output strobe.
    pub valid: bool,
    /// Corrected sine.
    pub sin: i64,
    /// Corrected cosine.
    pub cos: i64,
    /// Offsets in use [sin, cos].
    pub offset: [i64; 2],
    /// Gain codes in use [sin, cos].
    pub gain: [u64; 2],
    /// New calibration values applied this clock.
    pub cal_update: bool,
    /// Writable codes: the words the register map reads ([`super::codes::WORDS`]).
    pub words: Option<[u32; 5]>,
}

impl CorrectionOut {
    /// Trace row in output-port order, for A-bit samples.
    pub fn row(&self, a: u32) -> Vec<u64> {
        let m = mask(a);
        let mut r = vec![
            self.valid as u64,
            self.sin as u64 & m,
            self.cos as u64 & m,
            self.offset[SIN] as u64 & m,
            self.offset[COS] as u64 & m,
            self.gain[SIN],
            self.gain[COS],
            self.cal_update as u64,
        ];
        if let Some(w) = self.words {
            r.extend(w.map(u64::from));
        }
        r
    }
}

/// The datapath arithmetic of one channel (stages 1-3 without the registers):
/// sat_A(sgn(x - b) * floor((|x - b| g + 2^(GF-1)) / 2^GF)).
pub fn correct(x: i64, b: i64, g: u64, a: u32, gf: u32) -> i64 {
    let d = x - b;
    let m = (d.unsigned_abs() & 0xffff) * (g & 0xffff);
    let r = ((m + (1 << (gf - 1))) & mask(32)) >> gf;
    let half = 1u64 << (a - 1);
    if d < 0 {
        -(r.min(half) as i64)
    } else {
        r.min(half - 1) as i64
    }
}

/// The phase-corrected cos track's arithmetic (stages 1-4 without the registers): with
/// P_c = floor(|d_c| g_c / 2^s), Q = floor(|d_s| |k| / 2^s), S = sgn(d_c) P_c +
/// sgn(d_s) sgn(k) Q, F = GF - s: sat_A(floor((S + 2^(F-1)) / 2^F)) (round half up).
/// `s` = [`super::CorrectionParams::phase_shift`].
#[allow(clippy::too_many_arguments)]
pub fn correct_phase(
    xs: i64,
    xc: i64,
    bs: i64,
    bc: i64,
    gc: u64,
    k: i64,
    a: u32,
    gf: u32,
    s: u32,
) -> i64 {
    let (ds, dc) = (xs - bs, xc - bc);
    let pc = ((dc.unsigned_abs() & 0xffff) * (gc & 0xffff)) >> s;
    let q = ((ds.unsigned_abs() & 0xffff) * (k.unsigned_abs() & 0xffff)) >> s;
    let sum = if dc < 0 { -(pc as i64) } else { pc as i64 }
        + if (ds < 0) != (k < 0) {
            -(q as i64)
        } else {
            q as i64
        };
    let f = gf - s;
    let r = (sum + (1 << (f - 1))).div_euclid(1 << f);
    r.clamp(-(1 << (a - 1)), (1 << (a - 1)) - 1)
}

/// Divider states (as [`super::hdl::CalState`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Div {
    Idle,
    Sin,
    Cos,
}

/// Registers of the automatic calibration.
#[derive(Clone, Debug)]
struct Cal {
    tinit: bool,
    wopen: bool,
    tq: u64,
    net: u64,
    nper: u64,
    mx: [u64; 2],
    mn: [u64; 2],
    go: bool,
    sx: [u64; 2],
    sn: [u64; 2],
    state: Div,
    it: u64,
    rem: u64,
    dq: u64,
    dv: u64,
    ng_s: u64,
    b: [u64; 2],
    g: [u64; 2],
    upd: bool,
}

/// Registers of the pipeline.
#[derive(Clone, Debug, Default)]
struct Pipe {
    v1: bool,
    sg1: [bool; 2],
    m1: [u64; 2],
    g1: [u64; 2],
    /// The cross code in use with the stage-1 sample (a run-time k: [`CodeRegs`]'s delayed
    /// copy).
    ///
    /// [`CodeRegs`]: super::codes::CodeRegs
    k1: i64,
    u1: [u64; 2],
    v2: bool,
    sg2: [bool; 2],
    p2: [u64; 2],
    v3: bool,
    o3: [u64; 2],
    /// Phase stage ([`super::phase::PhaseCos`]): shifted products, negation bits, sum, and
    /// the fourth stage.
    pc2: u64,
    q2: u64,
    na2: bool,
    nb2: bool,
    s3: u64,
    /// The stage-4 constants (rounding addend, high and low limits) selected by n = na2 +
    /// nb2 a clock ahead; 0 at power-up.
    k3: [u64; 3],
    v4: bool,
    /// Stage 4: the sine, the rounded cos code and the two compares (S' >= high limit,
    /// S' < low limit); stage 5 the selected codes.
    o4: [u64; 2],
    hi4: bool,
    lo4: bool,
    v5: bool,
    o5: [u64; 2],
    /// Shift-add products ([`super::multree::MulTree`]): the stage-1 values (valid, signs,
    /// magnitudes, gains) through the tree's levels; the last one feeds stage 2.
    tree: [S1; TREE],
}

/// Levels of the shift-add tree ahead of the product registers.
const TREE: usize = super::multree::TREE_LEVELS as usize;

/// The stage-1 values a product stage reads.
#[derive(Clone, Copy, Debug, Default)]
struct S1 {
    v: bool,
    sg: [bool; 2],
    m: [u64; 2],
    g: [u64; 2],
    k: i64,
}

/// Model of [`super::hdl::Correction`].
#[derive(Clone, Debug)]
pub struct CorrectionModel {
    p: CorrectionParams,
    pipe: Pipe,
    cal: Option<Cal>,
    /// The writable codes ([`super::codes::CodeRegs`]), if any.
    codes: Option<CodesModel>,
}

impl CorrectionModel {
    /// Model at power-up (pipeline registers 0; offsets and gains at their configured
    /// values, as the RTL's initialized registers).
    pub fn new(p: &CorrectionParams) -> Self {
        let a = p.adc_width();
        let cal = p.auto().map(|_| Cal {
            tinit: false,
            wopen: false,
            tq: 0,
            net: 0,
            nper: 0,
            mx: [0; 2],
            mn: [0; 2],
            go: false,
            sx: [0; 2],
            sn: [0; 2],
            state: Div::Idle,
            it: 0,
            rem: 0,
            dq: 0,
            dv: 0,
            ng_s: 0,
            b: [
                p.offset()[SIN] as u64 & mask(a),
                p.offset()[COS] as u64 & mask(a),
            ],
            g: [p.gain()[SIN] as u64, p.gain()[COS] as u64],
            upd: false,
        });
        Self {
            p: *p,
            pipe: Pipe::default(),
            cal,
            codes: p.writable().then(|| CodesModel::new(p)),
        }
    }

    /// Offsets (A-bit raw) and gains in use now.
    fn in_use(&self) -> ([u64; 2], [u64; 2], bool) {
        let a = self.p.adc_width();
        if let Some(c) = &self.codes {
            let upd = self.cal.as_ref().is_some_and(|c| c.upd);
            return (c.b.map(|b| b as u64 & mask(a)), c.g.map(u64::from), upd);
        }
        match &self.cal {
            Some(c) => (c.b, c.g, c.upd),
            None => (
                [
                    self.p.offset()[SIN] as u64 & mask(a),
                    self.p.offset()[COS] as u64 & mask(a),
                ],
                [self.p.gain()[SIN] as u64, self.p.gain()[COS] as u64],
                false,
            ),
        }
    }

    fn outputs(&self) -> CorrectionOut {
        let a = self.p.adc_width();
        let (b, g, upd) = self.in_use();
        let (valid, o) = if self.p.has_phase() {
            (self.pipe.v5, self.pipe.o5)
        } else {
            (self.pipe.v3, self.pipe.o3)
        };
        CorrectionOut {
            valid,
            sin: sext(o[SIN], a),
            cos: sext(o[COS], a),
            offset: [sext(b[SIN], a), sext(b[COS], a)],
            gain: g,
            cal_update: upd,
            words: self.codes.map(|c| c.words()),
        }
    }

    /// One clock edge.
    pub fn step(&mut self, i: CorrectionIn) -> CorrectionOut {
        let a = self.p.adc_width();
        let gf = self.p.gain_frac_bits();
        let am = mask(a);
        let m32 = mask(32);
        let (b, g, _) = self.in_use();
        let old = self.pipe.clone();
        let mut n = old.clone();
        // Stage 1.
        let raw = [i.sin as u64 & am, i.cos as u64 & am];
        for c in [SIN, COS] {
            let d = (sext(raw[c], a) - sext(b[c], a)) as u64 & m32;
            let neg = d >> 31 != 0;
            let md = if neg { d.wrapping_neg() & m32 } else { d };
            n.sg1[c] = neg;
            n.m1[c] = md & am;
            n.g1[c] = g[c];
            n.k1 = self.codes.map_or(self.p.cross(), |c| c.k) as i64;
            n.u1[c] = raw[c] ^ (1 << (a - 1));
        }
        n.v1 = i.valid && !i.rst;
        // The products' inputs: stage 1, or with shift-add products stage 1 three clocks
        // earlier (the tree's levels; their sums are exact, so only the delay shows).
        let s1 = S1 {
            v: old.v1,
            sg: old.sg1,
            m: old.m1,
            g: old.g1,
            k: old.k1,
        };
        let s1 = if self.p.shift_add() {
            n.tree[0] = S1 {
                v: s1.v && !i.rst,
                ..s1
            };
            for l in 1..TREE {
                n.tree[l] = S1 {
                    v: old.tree[l - 1].v && !i.rst,
                    ..old.tree[l - 1]
                };
            }
            old.tree[TREE - 1]
        } else {
            s1
        };
        // Stage 2.
        n.v2 = s1.v && !i.rst;
        for c in [SIN, COS] {
            n.sg2[c] = s1.sg[c];
            n.p2[c] = s1.m[c] * s1.g[c];
        }
        // Stage 3.
        n.v3 = old.v2 && !i.rst;
        for c in [SIN, COS] {
            let r = ((old.p2[c] + (1 << (gf - 1))) & m32) >> gf;
            let half = 1u64 << (a - 1);
            let o = if old.sg2[c] {
                if r >= half {
                    half
                } else {
                    r.wrapping_neg() & am
                }
            } else {
                r.min(half - 1)
            };
            n.o3[c] = o & 0xffff;
        }
        // Phase stage (built only when k != 0; computed always, it is not observed otherwise).
        let k = s1.k;
        let sh = self.p.phase_shift();
        n.pc2 = (s1.m[COS] * s1.g[COS]) >> sh;
        n.q2 = (s1.m[SIN] * k.unsigned_abs()) >> sh;
        n.na2 = s1.sg[COS];
        n.nb2 = s1.sg[SIN] ^ (k < 0);
        let ma = if old.na2 { m32 } else { 0 };
        let mb = if old.nb2 { m32 } else { 0 };
        n.s3 = ((old.pc2 ^ ma) + (old.q2 ^ mb)) & m32;
        let (rnd, hi, lo) = super::phase::constants(&self.p);
        let nn = old.na2 as usize + old.nb2 as usize;
        n.k3 = [rnd[nn], hi[nn], lo[nn]];
        let [rnd3, hi3, lo3] = old.k3;
        let sf = old.s3 ^ (1 << 31);
        n.lo4 = sf < lo3;
        n.hi4 = sf >= hi3;
        n.o4[COS] = (((old.s3 + rnd3) & m32) >> (gf - sh)) & am;
        n.o4[SIN] = old.o3[SIN];
        // Stage 5, the RTL's order: the low limit's test is the later assignment.
        n.o5[COS] = if old.lo4 {
            1 << (a - 1)
        } else if old.hi4 {
            mask(a - 1)
        } else {
            old.o4[COS]
        };
        n.o5[SIN] = old.o4[SIN];
        n.v5 = old.v4 && !i.rst;
        n.v4 = old.v3 && !i.rst;
        // Calibration (sees the old stage-1 registers), then the writable codes (see the
        // calibration's outputs before this edge).
        let cal_out = self.cal.as_ref().filter(|c| c.upd).map(|c| (c.b, c.g, 0));
        if let Some(cal) = self.cal.as_mut() {
            cal_step(cal, &self.p, &old, i.rst);
        }
        if let Some(c) = self.codes.as_mut() {
            c.step(&self.p, i.rst, i.ld, i.ld_bits, i.ld_msk, cal_out);
        }
        self.pipe = n;
        self.outputs()
    }
}

/// One edge of the calibration.
fn cal_step(c: &mut Cal, p: &CorrectionParams, s1: &Pipe, rst: bool) {
    let a = p.adc_width();
    let gf = p.gain_frac_bits();
    let ac = p.auto().expect("auto");
    let m32 = mask(32);
    let kmask = mask(crate::blocks::monitor::count_bits(ac.periods()));
    let num = (ac.target_amplitude() as u64) << (gf + 1);
    let minspan = 2 * ac.min_amplitude() as u64;
    let old = c.clone();
    // Quadrant and step.
    let q: u64 = match (s1.sg1[SIN], s1.sg1[COS]) {
        (false, false) => 0,
        (false, true) => 1,
        (true, true) => 2,
        (true, false) => 3,
    };
    let stp = q.wrapping_sub(old.tq) & 3;
    let netn = match stp {
        1 => (old.net + 1) & 15,
        3 => (old.net + 15) & 15,
        _ => old.net,
    };
    let am = mask(a);
    let u = [s1.u1[0] & am, s1.u1[1] & am];
    let mxn = [old.mx[0].max(s1.u1[0]), old.mx[1].max(s1.u1[1])];
    let mnn = [old.mn[0].min(s1.u1[0]), old.mn[1].min(s1.u1[1])];
    let (mxn, mnn) = ([mxn[0] & am, mxn[1] & am], [mnn[0] & am, mnn[1] & am]);
    // Divider.
    let span = [
        old.sx[0].wrapping_sub(old.sn[0]) & m32,
        old.sx[1].wrapping_sub(old.sn[1]) & m32,
    ];
    let t = ((old.rem << 1) | (old.dq >> 31)) & m32;
    let (remn, dqn) = if t >= old.dv {
        (t - old.dv, ((old.dq << 1) | 1) & m32)
    } else {
        (t, (old.dq << 1) & m32)
    };
    let gsat = dqn.min(0xffff);
    c.upd = false;
    match old.state {
        Div::Idle => {
            if old.go {
                c.go = false;
                if span[0] >= minspan && span[1] >= minspan {
                    c.dv = span[0] & am;
                    c.rem = 0;
                    c.dq = (num + (span[0] >> 1)) & m32;
                    c.it = 0;
                    c.state = Div::Sin;
                }
            }
        }
        Div::Sin => {
            c.rem = remn & am;
            c.dq = dqn;
            c.it = (old.it + 1) & 31;
            if old.it == 31 {
                c.ng_s = gsat;
                c.dv = span[1] & am;
                c.rem = 0;
                c.dq = (num + (span[1] >> 1)) & m32;
                c.state = Div::Cos;
            }
        }
        Div::Cos => {
            c.rem = remn & am;
            c.dq = dqn;
            c.it = (old.it + 1) & 31;
            if old.it == 31 {
                c.g[COS] = gsat;
                c.g[SIN] = old.ng_s;
                for ch in [SIN, COS] {
                    c.b[ch] = ((((old.sx[ch] + old.sn[ch] + 1) & m32) >> 1)
                        .wrapping_sub(1 << (a - 1)))
                        & mask(a);
                }
                c.upd = true;
                c.state = Div::Idle;
            }
        }
    }
    // Tracker.
    if s1.v1 {
        c.tq = q;
        if !old.tinit || stp == 2 {
            c.tinit = true;
            c.wopen = false;
        } else if !old.wopen {
            if stp == 1 || stp == 3 {
                c.wopen = true;
                c.net = 0;
                c.nper = 0;
                c.mx = u;
                c.mn = u;
            }
        } else if netn == 4 || netn == 12 {
            c.net = 0;
            if old.nper == ac.periods() as u64 - 1 {
                c.nper = 0;
                c.mx = u;
                c.mn = u;
                if old.state == Div::Idle && !old.go {
                    c.go = true;
                    c.sx = mxn;
                    c.sn = mnn;
                }
            } else {
                c.nper = (old.nper + 1) & kmask;
                c.mx = mxn;
                c.mn = mnn;
            }
        } else {
            c.net = netn;
            c.mx = mxn;
            c.mn = mnn;
        }
    }
    if rst {
        c.tinit = false;
        c.wopen = false;
        c.net = 0;
        c.nper = 0;
        c.go = false;
        c.state = Div::Idle;
        c.it = 0;
        c.b = [
            p.offset()[SIN] as u64 & mask(a),
            p.offset()[COS] as u64 & mask(a),
        ];
        c.g = [p.gain()[SIN] as u64, p.gain()[COS] as u64];
        c.upd = false;
    }
}
