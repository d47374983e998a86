//! rust-hdl description of the QEP fallback.
use crate::blocks::params::Derived;
use crate::blocks::{c32, mask};
use rust_hdl::prelude::*;

mod update;

/// See the module docs.
#[derive(LogicBlock)]
pub struct Fallback {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high.
    pub rst: Signal<In, Bit>,
    /// Enable (0: never active, no mismatch, no loads).
    pub enable: Signal<In, Bit>,
    /// The QEP decoder's count stepped +1 at the last clock edge (its registered `up`).
    pub qep_up: Signal<In, Bit>,
    /// The QEP decoder's count stepped -1 at the last clock edge (its registered `down`).
    pub qep_down: Signal<In, Bit>,
    /// The ADC's conversion start, high from its sampling edge on: the CONV pin, or the
    /// inverse of an active-low chip select (the top inverts it: [`conv_inverted`]). Its
    /// rising edge is the sampling instant.
    pub conv: Signal<In, Bit>,
    /// ADC sample strobe.
    pub adc_valid: Signal<In, Bit>,
    /// Core output strobe.
    pub core_valid: Signal<In, Bit>,
    /// Core sample rejected.
    pub core_error: Signal<In, Bit>,
    /// Core overspeed warning.
    pub core_warning: Signal<In, Bit>,
    /// Core coarse count.
    pub core_qc: Signal<In, Bits<32>>,
    /// Core turn count (M bits).
    pub core_turns: Signal<In, Bits<32>>,
    /// Resynchronise the core (one-cycle pulse).
    pub load: Signal<Out, Bit>,
    /// Coarse count for the core.
    pub load_qc: Signal<Out, Bits<32>>,
    /// Turn count for the core.
    pub load_turns: Signal<Out, Bits<32>>,
    /// QEP and CORDIC disagree by more than one quadrant (warning).
    pub mismatch: Signal<Out, Bit>,
    /// Fallback mode.
    pub active: Signal<Out, Bit>,
    conv_prev: DFF<Bit>,
    qq: DFF<Bits<32>>,
    qt: DFF<Bits<32>>,
    /// qq == 4PPR - 1, registered with qq (power-up 0, as qq = 0).
    qlf: DFF<Bit>,
    /// qq != 0, registered with qq (power-up 0, as qq = 0).
    qnz: DFF<Bit>,
    c1q: DFF<Bits<32>>,
    c1t: DFF<Bits<32>>,
    c2q: DFF<Bits<32>>,
    c2t: DFF<Bits<32>>,
    /// Capture depth K = 2 ([`capture_depth`]): one more capture before c1 (one entry),
    /// else none.
    c0q: Vec<DFF<Bits<32>>>,
    c0t: Vec<DFF<Bits<32>>>,
    /// Capture depth K = 0: one entry (the capture goes straight to c2), else none.
    direct: Vec<Constant<Bit>>,
    prevq: DFF<Bits<32>>,
    sq: DFF<Bits<32>>,
    st: DFF<Bits<32>>,
    /// sq - 4PPR and st + 1: the capture with the wrap of dq applied in advance.
    sqm: DFFWithInit<Bits<32>>,
    stp: DFFWithInit<Bits<32>>,
    /// The previous sample's capture (deep mode: two samples in flight), and the same
    /// with the wrap applied.
    sq2: DFF<Bits<32>>,
    st2: DFF<Bits<32>>,
    sq2m: DFFWithInit<Bits<32>>,
    st2p: DFFWithInit<Bits<32>>,
    /// Deep mode: a load waits for the previous sample to leave the core.
    lpend: DFF<Bit>,
    /// Capture of the sample leaving the core now (and with the wrap applied).
    csq: Signal<Local, Bits<32>>,
    cst: Signal<Local, Bits<32>>,
    csqm: Signal<Local, Bits<32>>,
    cstp: Signal<Local, Bits<32>>,
    /// Deep mode: a sample takes longer from the ADC's out_valid to the core's out_valid
    /// (correction + core latency) than one ADC period, so the next sample's out_valid comes
    /// first (the digit-serial iterative core).
    deep: Constant<Bit>,
    fast: DFF<Bit>,
    busy: DFF<Bit>,
    aligned: DFF<Bits<2>>,
    act: DFF<Bit>,
    quiet: DFF<Bits<8>>,
    load_r: DFF<Bit>,
    lqc: DFF<Bits<32>>,
    lturns: DFF<Bits<32>>,
    mis: DFF<Bit>,
    oq: DFF<Bits<32>>,
    ot: DFF<Bits<32>>,
    /// oq - 4PPR and ot + 1: the offset with the wrap of the load value applied.
    oqm: DFFWithInit<Bits<32>>,
    otp: DFFWithInit<Bits<32>>,
    /// Stage k: a good core sample (valid, no error), registered.
    kv: DFF<Bit>,
    /// Stage k: its overspeed warning.
    kw: DFF<Bit>,
    /// Stage k: its offset core - capture in 0..4PPR-1, and the turns.
    kq: DFF<Bits<32>>,
    kt: DFF<Bits<32>>,
    /// Stage k2: the good sample and its warning one clock later, with dd = kq - oq.
    kv2: DFF<Bit>,
    kw2: DFF<Bit>,
    /// dd = kq - oq tested against -1, 0, 1 modulo 4PPR: chunk compares registered from the
    /// subtraction, combined after the register (see [`NearSet`]).
    ddn: NearSet,
    /// kv2 & aligned == 3 & !act: the gate of the mismatch, registered beside kv2 (aligned
    /// and act change only at a kv2 pulse or the reset, and kv2 pulses are a sample apart).
    gk: DFF<Bit>,
    /// The tracker's motion mv = c2q - prevq tested against -1, 0, 1 (`mvn1`) and -2, 2
    /// (`mvn2`) modulo 4PPR, chunk compares registered from the subtraction, and the tests
    /// registered after them: read at the ADC's out_valid, at least three clocks after c2q
    /// and prevq last changed (a conversion start, the previous out_valid).
    mvn1: NearSet,
    mvn2: NearSet,
    fast_n: DFF<Bit>,
    busy_n: DFF<Bit>,
    lq0: Signal<Local, Bits<32>>,
    lq1: Signal<Local, Bits<32>>,
    lq: Signal<Local, Bits<32>>,
    lt: Signal<Local, Bits<32>>,
    /// All ones when lq1 is negative, else 0 (the select of the load's two turn sums).
    lsel: Signal<Local, Bits<32>>,
    /// The load's turn sums: capture plus the offset, and plus the offset + 1.
    lt0: Signal<Local, Bits<32>>,
    lt1: Signal<Local, Bits<32>>,
    /// All ones when dq0 is negative, else 0 (the select of kt's two differences).
    ksel: Signal<Local, Bits<32>>,
    /// kt's candidates: core turns minus the capture's, and minus the capture's + 1.
    kt0: Signal<Local, Bits<32>>,
    kt1: Signal<Local, Bits<32>>,
    /// QEP count step: +1 / -1 (the count moves by at most one per clock).
    inc: Signal<Local, Bit>,
    dec: Signal<Local, Bit>,
    dq0: Signal<Local, Bits<32>>,
    dq1: Signal<Local, Bits<32>>,

    nq: Signal<Local, Bits<32>>,
    nt: Signal<Local, Bits<32>>,
    bad: Signal<Local, Bit>,
    /// 4 PPR.
    qturn: Constant<Bits<32>>,
    /// 4 PPR - 1 (the last quadrant of a turn).
    qlast: Constant<Bits<32>>,
    /// 4 PPR - 2 (the quadrant before the last).
    qlast_m1: Constant<Bits<32>>,
    /// Minus 4 PPR.
    mqturn: Constant<Bits<32>>,
    /// Mask of quadrant_bits + 1 bits: the differences of two counts in 0..4PPR-1 are
    /// unique modulo 2^(quadrant_bits + 1) >= 8PPR, so the equality tests use these bits.
    dmask: Constant<Bits<32>>,
    /// Turn mask (M bits).
    tmask: Constant<Bits<32>>,
    /// Bit quadrant_bits: the sign of a difference of two counts in 0..4PPR-1 taken
    /// modulo 2^(quadrant_bits + 1) (every such difference lies in -4PPR+1..4PPR-1).
    dsign: Constant<Bits<32>>,
    /// Mask of quadrant_bits bits: the tracker's count stays in 0..4PPR-1.
    qmask: Constant<Bits<32>>,
    /// 1.
    one: Constant<Bits<32>>,
    /// 0.
    zero: Constant<Bits<32>>,
    /// All ones.
    ones: Constant<Bits<32>>,
    /// 3: aligned samples before the checks start (the captures of the two conversions in
    /// flight predate the first alignment).
    three: Constant<Bits<2>>,
    /// 0 and 1 on the 2-bit aligned counter.
    azero: Constant<Bits<2>>,
    aone: Constant<Bits<2>>,
    /// Quiet samples before leaving fallback mode, minus one (the 8-bit quiet counter
    /// stops at QUIET_SAMPLES <= 255).
    quiet_last: Constant<Bits<8>>,
    /// 0 and 1 on the quiet counter.
    qzero: Constant<Bits<8>>,
    qone: Constant<Bits<8>>,
}

/// Quiet samples before the fallback mode ends.
pub const QUIET_SAMPLES: u32 = 8;

/// Deep mode: correction + core latency longer than one ADC period (see `Fallback::deep`).
/// At most two samples are ever in flight: the iterative core takes at most one ADC period
/// per sample (`sinedec check`), so its latency is below two periods.
pub fn deep(d: &Derived) -> bool {
    d.correction.latency_cycles() + d.latency_cycles > d.adc.period_clocks
}

/// Capture depth K = floor((V - 1) / P): the conversion starts that come after a sample's
/// own and before the ADC's `out_valid` of it, V clocks after its own
/// ([`crate::blocks::adc::AdcParams::conv_to_valid_clocks`]) with starts P clocks apart (the
/// same count as the position reference's Z tag, `crate::blocks::reference`). It is the
/// ADC's `pipeline` (0..=2): each frame is read within its period.
pub fn capture_depth(d: &Derived) -> u32 {
    d.adc.conv_to_valid_clocks().saturating_sub(1) / d.adc.period_clocks.max(1)
}

/// The ADC's conversion start is an active-low chip select (`adc.frame.conv_active_high`
/// false: ADS8354, AD7380): the top gives the fallback its inverse, so that the fallback's
/// `conv` rises at the sampling edge, the chip select's fall.
pub fn conv_inverted(d: &Derived) -> bool {
    !d.adc.frame.conv_active_high
}

impl Fallback {
    /// Fallback for the derived parameters.
    pub fn new(d: &Derived) -> Self {
        let q = d.quadrants_per_turn;
        let dm = mask(d.quadrant_bits + 1);
        // The differences of two counts in 0..4PPR-1 (in -4PPR+1..4PPR-1) that are -1, 0, 1
        // modulo 4PPR, and those that are -2, 2, modulo 2^(quadrant_bits + 1).
        let near1 = [0, 1, dm, (q - 1) & dm, 1u64.wrapping_sub(q) & dm];
        let near2 = [2, dm - 1, q.wrapping_sub(2) & dm, 2u64.wrapping_sub(q) & dm];
        // The motion's chunk compares and its tests take two clocks: the ADC's out_valid must come at least three
        // clocks after a conversion start (it comes in the frame's last SCK cycles).
        debug_assert!(d.adc.conv_to_valid_clocks() % d.adc.period_clocks >= 3);
        let depth = capture_depth(d);
        debug_assert!(depth <= 2);
        Self {
            clk: Default::default(),
            rst: Default::default(),
            enable: Default::default(),
            qep_up: Default::default(),
            qep_down: Default::default(),
            conv: Default::default(),
            adc_valid: Default::default(),
            core_valid: Default::default(),
            core_error: Default::default(),
            core_warning: Default::default(),
            core_qc: Default::default(),
            core_turns: Default::default(),
            load: Default::default(),
            load_qc: Default::default(),
            load_turns: Default::default(),
            mismatch: Default::default(),
            active: Default::default(),
            conv_prev: Default::default(),
            qq: Default::default(),
            qt: Default::default(),
            qlf: Default::default(),
            qnz: Default::default(),
            c1q: Default::default(),
            c1t: Default::default(),
            c2q: Default::default(),
            c2t: Default::default(),
            c0q: (0..usize::from(depth >= 2))
                .map(|_| Default::default())
                .collect(),
            c0t: (0..usize::from(depth >= 2))
                .map(|_| Default::default())
                .collect(),
            direct: (0..usize::from(depth == 0))
                .map(|_| Constant::new(true))
                .collect(),
            prevq: Default::default(),
            sq: Default::default(),
            st: Default::default(),
            sqm: DFFWithInit::new(Bits::<32>::from(q.wrapping_neg() & mask(32))),
            stp: DFFWithInit::new(Bits::<32>::from(1)),
            sq2: Default::default(),
            st2: Default::default(),
            sq2m: DFFWithInit::new(Bits::<32>::from(q.wrapping_neg() & mask(32))),
            st2p: DFFWithInit::new(Bits::<32>::from(1)),
            lpend: Default::default(),
            csq: Default::default(),
            cst: Default::default(),
            csqm: Default::default(),
            cstp: Default::default(),
            deep: Constant::new(deep(d)),
            fast: Default::default(),
            busy: Default::default(),
            aligned: Default::default(),
            act: Default::default(),
            quiet: Default::default(),
            load_r: Default::default(),
            lqc: Default::default(),
            lturns: Default::default(),
            mis: Default::default(),
            oq: Default::default(),
            ot: Default::default(),
            oqm: DFFWithInit::new(Bits::<32>::from(q.wrapping_neg() & mask(32))),
            otp: DFFWithInit::new(Bits::<32>::from(1)),
            kv: Default::default(),
            kw: Default::default(),
            kq: Default::default(),
            kt: Default::default(),
            kv2: Default::default(),
            kw2: Default::default(),
            ddn: NearSet::new(&near1, d.quadrant_bits + 1),
            gk: Default::default(),
            mvn1: NearSet::new(&near1, d.quadrant_bits + 1),
            mvn2: NearSet::new(&near2, d.quadrant_bits + 1),
            fast_n: Default::default(),
            busy_n: Default::default(),
            lq0: Default::default(),
            lq1: Default::default(),
            lq: Default::default(),
            lt: Default::default(),
            lsel: Default::default(),
            lt0: Default::default(),
            lt1: Default::default(),
            ksel: Default::default(),
            kt0: Default::default(),
            kt1: Default::default(),
            inc: Default::default(),
            dec: Default::default(),
            dq0: Default::default(),
            dq1: Default::default(),
            nq: Default::default(),
            nt: Default::default(),
            bad: Default::default(),
            qturn: c32(q),
            dmask: c32(dm),
            qlast: c32(q - 1),
            qlast_m1: c32(q - 2),
            mqturn: c32(q.wrapping_neg() & mask(32)),
            tmask: c32(mask(d.multiturn_bits)),
            dsign: c32(1 << d.quadrant_bits),
            qmask: c32(mask(d.quadrant_bits)),
            one: c32(1),
            zero: c32(0),
            ones: c32(mask(32)),
            three: Constant::new(Bits::<2>::from(3u64)),
            azero: Constant::new(Bits::<2>::from(0u64)),
            aone: Constant::new(Bits::<2>::from(1u64)),
            quiet_last: Constant::new(Bits::<8>::from(QUIET_SAMPLES as u64 - 1)),
            qzero: Constant::new(Bits::<8>::from(0u64)),
            qone: Constant::new(Bits::<8>::from(1u64)),
        }
    }
}

/// A registered test of whether a (quadrant_bits + 1)-bit difference x is one of a few
/// constants, with no wide compare behind a register: each 4-bit chunk of x is compared
/// with the chunks the constants have there (one LUT behind x's subtraction), the distinct
/// chunk compares are registered as bits of `f`, and `hit` is the OR over the constants of
/// the AND of their chunk bits (masks of `f`), one or two LUTs of flip-flops. `hit` is the
/// test of the x presented one clock earlier.
#[derive(LogicBlock)]
pub struct NearSet {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// The difference to test (upper bits 0).
    pub x: Signal<In, Bits<32>>,
    /// x of the previous clock was one of the constants.
    pub hit: Signal<Out, Bit>,
    /// The registered chunk compares, one bit per distinct (chunk, value).
    f: DFF<Bits<32>>,
    /// Per distinct chunk compare: the chunk's value in place, its mask, its bit in `f`.
    pv: Vec<Constant<Bits<32>>>,
    pm: Vec<Constant<Bits<32>>>,
    pb: Vec<Constant<Bits<32>>>,
    /// Per constant: the bits of `f` that must all be set.
    cm: Vec<Constant<Bits<32>>>,
    /// The chunk compares being collected.
    acc: Signal<Local, Bits<32>>,
    /// 0.
    zero: Constant<Bits<32>>,
}

impl NearSet {
    /// Test against `consts` (each below 2^bits, bits <= 20: at most 32 distinct chunk
    /// compares for the at most five constants of a set).
    pub fn new(consts: &[u64], bits: u32) -> Self {
        let chunks = bits.div_ceil(4);
        let mut pairs: Vec<(u32, u64)> = Vec::new();
        let mut cm = Vec::new();
        for &c in consts {
            let mut m = 0u64;
            for k in 0..chunks {
                let key = (k, (c >> (4 * k)) & 0xf);
                let j = match pairs.iter().position(|p| *p == key) {
                    Some(j) => j,
                    None => {
                        pairs.push(key);
                        pairs.len() - 1
                    }
                };
                m |= 1 << j;
            }
            cm.push(c32(m));
        }
        debug_assert!(pairs.len() <= 32);
        Self {
            clk: Default::default(),
            x: Default::default(),
            hit: Default::default(),
            f: Default::default(),
            pv: pairs.iter().map(|&(k, v)| c32(v << (4 * k))).collect(),
            pm: pairs
                .iter()
                .map(|&(k, _)| c32((0xf << (4 * k)) & mask(bits)))
                .collect(),
            pb: (0..pairs.len()).map(|j| c32(1 << j)).collect(),
            cm,
            acc: Default::default(),
            zero: c32(0),
        }
    }
}

impl Logic for NearSet {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clk, f);
        self.acc.next = self.zero.val();
        for i in 0..self.pv.len() {
            if !((self.x.val() ^ self.pv[i].val()) & self.pm[i].val()).any() {
                self.acc.next = self.acc.val() | self.pb[i].val();
            }
        }
        self.f.d.next = self.acc.val();
        self.hit.next = false;
        for i in 0..self.cm.len() {
            if (self.f.q.val() & self.cm[i].val()) == self.cm[i].val() {
                self.hit.next = true;
            }
        }
    }
}
