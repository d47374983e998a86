//! Iterative CORDIC (`cordic.architecture = "iterative"`): one digit-serial vectoring stage,
//! reused for the N iterations of a sample, [`DIGIT`] bits per clock.
//!
//! ```text
//!              ┌──────────┐ x',y',q  ┌──────────────────────────────────────────────┐
//!  in_sin ────►│ quadrant ├─────────►│ digit j of x',y' (iteration 0)               │
//!  in_cos ────►│ mapper   │          │        │                                     │
//!  in_valid ─┬►│ (gated)  │          │        ▼        4-bit add/sub, carry FF      │ x,z,q,v
//!            │ └──────────┘          │ xr ─► digit ─► ( x ± tap(y>>k) ) ─► xr top ───┼──► combiner
//!            │                       │ yr ─► digit ─► ( y ∓ tap(x>>k) ) ─► yr top  │      ─► counter
//!            │                       │ xr,yr: W'-bit shift registers, 4 bits/clock │
//!            │                       │ z ± atan ROM[k], at digit 1 of each iter.   │
//!            └── & in_ready ◄────────┤ one-hot j/k masks, k, busy, lost mark       │
//!                                    └──────────────────────────────────────────────┘
//! ```
//!
//! Datapath. x and y live in W'-bit shift registers, W' = 4·D with D = ceil(W / 4) digits
//! (W = `xy_width`; the bits W..W'-1 hold copies of the sign). Iteration k takes D clocks;
//! clock j handles bits 4j..4j+3, least significant digit first:
//! * the own operand is the register's bottom digit (in iteration 0 the digit j of the
//!   mapper's x', y', selected by a 4-bit-wide D:1 multiplexer);
//! * the other operand is y >> k (for x) or x >> k (for y): because the register has
//!   already shifted by 4j, bit 4j + k + b of the old word sits at position k + b, a fixed
//!   tap per k (a 4-bit-wide N:1 multiplexer instead of a W-bit barrel shifter). Once
//!   4j + k + b >= W' the tap would read a new digit; there the arithmetic shift's fill is
//!   used instead (y: its sign, which is the direction bit; x: 0, x is never negative);
//! * the tap is fetched one clock ahead into a 4-bit register (`tpx`, `tpy`): the registers
//!   shift by one digit at every edge, so the next clock's bits k + b are bits k + 4 + b now,
//!   or k + 5 + b at the last digit (the next clock is iteration k + 1): an AND-OR of
//!   five-bit windows over the registered one-hot iteration masks, then a one-bit shift. The
//!   adder's operands are thus registers or one multiplexer of registers. The fill mask is
//!   registered the same way, from a thermometer code of k (bit t: k >= t) and the one-hot
//!   digit masks (tap bit b of digit j' reads fill when k >= W' - b - 4j'): no adder and no
//!   comparator on the way. N = 14 core, ECP5 (docs/timing.md): 121.3 MHz before, 146.9
//!   MHz after; xc3sa 375 -> 354 LUT;
//! * a 4-bit adder with a carry flip-flop adds or subtracts (one's complement plus a carry
//!   in of 1 at j = 0), exactly the one-adder form of the unrolled stages; the new digit
//!   enters the top of the register. At j = D - 1 the bits W..W'-1 of the new word are
//!   replaced by copies of bit W - 1: the result wraps to W bits like the unrolled stage's
//!   `& xmask`.
//! * z (W_z bits, parallel) adds or subtracts atan(2^-k) from a ROM holding
//!   `Derived::atan_table` once per iteration, at j = 1 (D >= 3 since adc.width >= 10);
//!   the first clock of a sample loads its start value (the rounding half plus the
//!   quadrant), whose constant bits synthesis maps to the flip-flops' synchronous set and
//!   reset: xc3sa 382 -> 366 LUT at N = 14.
//! * The direction of iteration k is the sign of y_k: bit W - 1 of the mapper's y' (k = 0)
//!   or of the register (k >= 1) at j = 0, held for the other digits.
//!
//! Bit growth is that of the unrolled stage: the same W-bit x/y words, modulo 2^W, and the
//! same W_z-bit z, so the model of both architectures is [`super::model::cordic`]; only the
//! timing differs.
//!
//! Timing (cycle k = inputs before clock edge k; the edge that captures the input counts
//! as the first): with S = N·D clocks per sample ([`steps`]),
//! * Edge e: the mapper registers an accepted sample (as in the unrolled core).
//! * Edges e+1 .. e+S: the N iterations, D clocks each; the result is held after edge e+S.
//! * Edge e+S+1: combiner; edge e+S+2: counter. Latency S + 2 cycles.
//! * Throughput: one sample per S clocks (the engine starts a new sample at the edge after
//!   its last clock). At the default widths (W = 26, D = 7) and N = 14, S = 98: 1.36 Msps at
//!   133.33 MHz, above the LTC1407A-1's 1.307 Msps at that clock.
//!
//! Handshake: `in_ready` is a function of registers only (no path from the inputs). A sample
//! offered with `in_valid` while `in_ready` is high is accepted. A sample offered while it is
//! low is **dropped**, never silently: the next accepted sample carries a `lost` mark, and
//! when that sample reaches the output (its `out_valid` strobe) `out_warning` is raised and
//! held with it, like the counter's own warning (the core's `out_warning` is the counter's
//! warning OR this mark). This is not an AXI-style handshake: `in_valid` held high while
//! `in_ready` is low counts as one dropped offer per cycle, so a producer honours `in_ready`
//! by asserting `in_valid` only in cycles where `in_ready` is high. Such a producer never
//! loses a sample; in the board top the ADC delivers one sample per ADC period, and
//! `sinedec check` rejects an iterative design whose period is shorter than S clocks.
//!
//! `in_ready` is high in cycle m exactly when the engine will be free at edge m+1: the
//! engine is idle with no sample waiting in the mapper, or it performs its last clock at
//! edge m (or S = 1). Back to back, samples are accepted every S cycles.
use rust_hdl::prelude::*;

mod build;

/// An 8-bit constant (digit-level signals).
fn c8(v: u64) -> Constant<Bits<8>> {
    Constant::new(Bits::<8>::from(v & 0xff))
}

/// Bits per clock of the digit-serial engine.
pub const DIGIT: u32 = 4;

/// Digits per x/y word: D = ceil(W / DIGIT).
pub fn digits(xy_width: u32) -> u32 {
    xy_width.div_ceil(DIGIT)
}

/// Clocks per sample of the iterative engine: S = N·D.
pub fn steps(iterations: u32, xy_width: u32) -> u32 {
    iterations * digits(xy_width)
}

/// The iterative engine: takes the mapper's registered outputs, returns what the last
/// unrolled stage would (x, z, q, valid), plus `in_ready` and the `lost` warning mark.
#[derive(LogicBlock)]
pub struct IterativeCordic {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high: engine idle, marks cleared.
    pub rst: Signal<In, Bit>,
    /// The core's raw `in_valid` (before gating with `in_ready`): counts dropped samples.
    pub in_valid: Signal<In, Bit>,
    /// Mapped x' from the mapper (W-bit).
    pub x_in: Signal<In, Bits<32>>,
    /// Mapped y' from the mapper (W-bit).
    pub y_in: Signal<In, Bits<32>>,
    /// Quadrant from the mapper.
    pub q_in: Signal<In, Bits<2>>,
    /// Mapper valid bit (the mapper's `in_valid` must be `in_valid & in_ready`).
    pub v_in: Signal<In, Bit>,
    /// The core accepts a sample in this cycle.
    pub in_ready: Signal<Out, Bit>,
    /// Final x (W-bit), valid with `v_out`.
    pub x_out: Signal<Out, Bits<32>>,
    /// Final z (ZW-bit), valid with `v_out`.
    pub z_out: Signal<Out, Bits<32>>,
    /// Quadrant, valid with `v_out`.
    pub q_out: Signal<Out, Bits<2>>,
    /// One-cycle strobe: the N iterations of a sample are done.
    pub v_out: Signal<Out, Bit>,
    /// A sample was dropped before the one the counter output last: OR into out_warning.
    pub lost: Signal<Out, Bit>,
    rom: ROM<Bits<32>, 5>,
    /// x shift register (W' bits, new digits enter at the top).
    xr: DFF<Bits<32>>,
    /// y shift register (W' bits).
    yr: DFF<Bits<32>>,
    /// z accumulator (W_z bits).
    zr: DFF<Bits<32>>,
    q_reg: DFF<Bits<2>>,
    /// Iteration index k.
    k_reg: DFF<Bits<5>>,
    /// Thermometer code of the iteration index: bit t set when k >= t (t >= 1; bit 0
    /// stays 0), for the fill mask.
    kge: DFF<Bits<32>>,
    /// Carry between the digits of x and of y.
    cx_reg: DFF<Bit>,
    cy_reg: DFF<Bit>,
    /// Fill mask of the taps for this clock (bit b set once 4j + k + b >= W'), computed
    /// the clock before from the next (j, k).
    fill_reg: DFF<Bits<8>>,
    /// Direction (sign of y_k) of the current iteration.
    dir_reg: DFF<Bit>,
    /// The taps of the next clock (bits k + b, b = 0..3, of x and of y as they will be
    /// then), fetched one clock ahead from the registers as they are now: bits k + 4 + b,
    /// or k + 5 + b at the last digit, whose next clock is iteration k + 1.
    tpx: DFF<Bits<8>>,
    tpy: DFF<Bits<8>>,
    busy_reg: DFF<Bit>,
    done_reg: DFF<Bit>,
    drop_reg: DFF<Bit>,
    lostm_reg: DFF<Bit>,
    loste_reg: DFF<Bit>,
    donec_reg: DFF<Bit>,
    lostc_reg: DFF<Bit>,
    hold_reg: DFF<Bit>,
    /// One-hot iteration masks: hot[k] = 0x1F during iteration k (hot[0]: iteration 0,
    /// whose operands come from the mapper), else 0 (five bits: the tap windows).
    hot: Vec<DFF<Bits<8>>>,
    /// One-hot digit masks: jhot[j] = 0xF at digit j, else 0.
    jhot: Vec<DFF<Bits<8>>>,
    /// The mapper's x', y', latched at the first clock of a sample (the mapper's registers
    /// load every clock; iteration 0 reads digits 1.. from here).
    xl: DFF<Bits<32>>,
    yl: DFF<Bits<32>>,
    /// First clock of a sample (a mapped sample waits, the engine is free).
    start: Signal<Local, Bit>,
    /// Shifted copies of a register or of a mapper word while the taps are gathered.
    shx: Signal<Local, Bits<32>>,
    shy: Signal<Local, Bits<32>>,
    /// Digit j of the mapper's x', y'.
    xm: Signal<Local, Bits<8>>,
    /// Five-bit windows (bits k + 4 .. k + 8) of x and y, and the next clock's taps.
    wx: Signal<Local, Bits<8>>,
    wy: Signal<Local, Bits<8>>,
    tx: Signal<Local, Bits<8>>,
    ty: Signal<Local, Bits<8>>,
    ym: Signal<Local, Bits<8>>,
    /// The masks advance (not idle, not the last clock of a sample).
    adv: Signal<Local, Bit>,
    kin: Signal<Local, Bits<5>>,
    /// Next iteration index.
    kn: Signal<Local, Bits<5>>,
    /// The thermometer code shifted by 4(j + 1) per digit j, and the AND-OR of those
    /// selected by the digit masks: bit W' - b set when tap bit b reads fill next clock.
    ge: Signal<Local, Bits<64>>,
    acc: Signal<Local, Bits<64>>,
    /// The next clock's fill mask.
    fnx: Signal<Local, Bits<8>>,
    active: Signal<Local, Bit>,
    first: Signal<Local, Bit>,
    j0: Signal<Local, Bit>,
    jlast: Signal<Local, Bit>,
    last: Signal<Local, Bit>,
    rdy: Signal<Local, Bit>,
    dir: Signal<Local, Bit>,
    xa: Signal<Local, Bits<8>>,
    ya: Signal<Local, Bits<8>>,
    xb: Signal<Local, Bits<8>>,
    yb: Signal<Local, Bits<8>>,
    fillm: Signal<Local, Bits<8>>,
    mm: Signal<Local, Bits<8>>,
    nmm: Signal<Local, Bits<8>>,
    cxi: Signal<Local, Bits<8>>,
    cyi: Signal<Local, Bits<8>>,
    sx: Signal<Local, Bits<8>>,
    sy: Signal<Local, Bits<8>>,
    dx: Signal<Local, Bits<8>>,
    dy: Signal<Local, Bits<8>>,
    m: Signal<Local, Bits<32>>,
    c: Signal<Local, Bits<32>>,
    /// All ones.
    ones: Constant<Bits<32>>,
    /// One.
    one: Constant<Bits<32>>,
    /// Zero.
    zero: Constant<Bits<32>>,
    /// Zero (digit width).
    zero8: Constant<Bits<8>>,
    /// Zero (64 bits).
    zero64: Constant<Bits<64>>,
    /// One (digit width).
    one8: Constant<Bits<8>>,
    /// Digit mask (DIGIT ones).
    dmask: Constant<Bits<8>>,
    /// Iteration mask (DIGIT + 1 ones: a digit and the bit above it).
    hmask: Constant<Bits<8>>,
    /// Bit 4 of a digit sum: the carry out.
    dcarry: Constant<Bits<8>>,
    /// Sign bit of a W-bit word.
    xsign: Constant<Bits<32>>,
    /// Mask of W bits.
    xmask: Constant<Bits<32>>,
    /// Mask of ZW bits.
    zmask: Constant<Bits<32>>,
    /// 2^(Gz-1): the rounding half in the initial angle (see the combiner).
    zhalf: Constant<Bits<32>>,
    /// F + Gz: the shift of the quadrant in the initial angle.
    zqshift: Constant<Bits<32>>,
    /// Shift of a digit to the top of the W'-bit register: W' - DIGIT.
    topsh: Constant<Bits<32>>,
    /// Shift of the register by one digit.
    dsh: Constant<Bits<32>>,
    /// Shift by one bit (the next tap).
    bsh: Constant<Bits<32>>,
    /// In the top digit: bit W - 1 - (W' - DIGIT), the sign of the W-bit word.
    tsign: Constant<Bits<8>>,
    /// In the top digit: the bits above the sign (W..W'-1), zero when W = W'.
    text: Constant<Bits<8>>,
    /// Bit W' - b (tap bit b reads fill) of `acc`, b = 0..3.
    fw0: Constant<Bits<64>>,
    fw1: Constant<Bits<64>>,
    fw2: Constant<Bits<64>>,
    fw3: Constant<Bits<64>>,
    /// Shifts of the thermometer code: a digit (4) and one bit (64-bit words).
    dsh64: Constant<Bits<64>>,
    bsh64: Constant<Bits<64>>,
    /// Bit 1 of the thermometer code (k >= 1).
    kge1: Constant<Bits<32>>,
    /// Mask of the thermometer code's N bits (k <= N - 1), so that synthesis keeps no
    /// flip-flop above them.
    kmask: Constant<Bits<32>>,
    /// The bits k can use: k < N, so ceil(log2 N) bits.
    kamask: Constant<Bits<5>>,
    /// Fill bit b of a tap digit.
    fb0: Constant<Bits<8>>,
    fb1: Constant<Bits<8>>,
    fb2: Constant<Bits<8>>,
    fb3: Constant<Bits<8>>,
    /// Index 0 (k and 4j).
    kzero: Constant<Bits<5>>,
    /// Iteration increment 1.
    kone: Constant<Bits<5>>,
}

// The engine's logic in named stages, run in this order (`logic_stages!`).
crate::blocks::logic_stages!(IterativeCordic: Place, Digits, DigitAdd, FillMask);

/// The position (iteration k, digit j), its flags and the direction.
impl stages::Place for IterativeCordic {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clk, xr, yr, zr, xl, yl, q_reg, k_reg, kge, cx_reg, cy_reg, fill_reg, dir_reg,
            tpx, tpy, busy_reg, done_reg, drop_reg, lostm_reg, loste_reg, donec_reg, lostc_reg,
            hold_reg
        );
        // Position: iteration k, digit j (a new sample starts at 0, 0).
        // The iteration index: k_reg is 0 whenever the engine is idle (it is cleared at the
        // edge after a sample's last clock and by reset), so it needs no select by busy.
        // k < N: the bits above ceil(log2 N) are zero, and masking them tells synthesis so
        // (the ROM's and the increment's functions lose an input).
        self.kin.next = self.k_reg.q.val() & self.kamask.val();
        self.q_reg.d.next = self.q_in.val();
        self.loste_reg.d.next = self.lostm_reg.q.val();
        if self.busy_reg.q.val() {
            self.q_reg.d.next = self.q_reg.q.val();
            self.loste_reg.d.next = self.loste_reg.q.val();
        }
        self.active.next = self.busy_reg.q.val() | self.v_in.val();
        // Position flags from the one-hot masks (registers; they show (0, 0) when idle).
        self.first.next = self.hot[0].q.val().get_bit(0);
        self.j0.next = self.jhot[0].q.val().get_bit(0);
        // The last mask of each list (the loops leave the last index's bit).
        for i in 0..self.jhot.len() {
            self.jlast.next = self.jhot[i].q.val().get_bit(0);
        }
        for i in 0..self.hot.len() {
            self.last.next = self.hot[i].q.val().get_bit(0);
        }
        self.last.next = self.last.val() & self.jlast.val();
        self.rdy.next = !(self.active.val() & !self.last.val());
        self.rom.address.next = self.kin.val();
        // Direction: sign of y_k, taken at the first digit and held for the others.
        self.dir.next = self.dir_reg.q.val();
        if self.j0.val() {
            if self.first.val() {
                self.dir.next = (self.y_in.val() & self.xsign.val()).any();
            } else {
                self.dir.next = (self.yr.q.val() & self.xsign.val()).any();
            }
        }
    }
}

/// The digits of the operands and the next clock's taps.
impl stages::Digits for IterativeCordic {
    #[hdl_gen]
    fn update(&mut self) {
        // Digit j of the mapper's words (AND-OR over the one-hot digit masks; x', y' are
        // W-bit words in 0..2^(A-1), so their bits W..W'-1 are already the sign, 0).
        // Digit 0 comes straight from the mapper (the first clock), digits 1.. from the
        // latched copy.
        self.start.next = self.v_in.val() & !self.busy_reg.q.val();
        self.xl.d.next = self.xl.q.val();
        self.yl.d.next = self.yl.q.val();
        if self.start.val() {
            self.xl.d.next = self.x_in.val();
            self.yl.d.next = self.y_in.val();
        }
        self.xm.next = bit_cast::<8, 32>(self.x_in.val()) & self.jhot[0].q.val();
        self.ym.next = bit_cast::<8, 32>(self.y_in.val()) & self.jhot[0].q.val();
        self.shx.next = self.xl.q.val();
        self.shy.next = self.yl.q.val();
        for i in 1..self.jhot.len() {
            self.shx.next = self.shx.val() >> self.dsh.val();
            self.shy.next = self.shy.val() >> self.dsh.val();
            self.xm.next =
                self.xm.val() | (bit_cast::<8, 32>(self.shx.val()) & self.jhot[i].q.val());
            self.ym.next =
                self.ym.val() | (bit_cast::<8, 32>(self.shy.val()) & self.jhot[i].q.val());
        }
        // Own digits: the mapper's in iteration 0 (hot[0]), else the register's bottom digit.
        self.xa.next =
            (bit_cast::<8, 32>(self.xr.q.val()) & self.dmask.val() & !self.hot[0].q.val())
                | (self.xm.val() & self.hot[0].q.val());
        self.ya.next =
            (bit_cast::<8, 32>(self.yr.q.val()) & self.dmask.val() & !self.hot[0].q.val())
                | (self.ym.val() & self.hot[0].q.val());
        // Shifted operands: tap k of the other register, fetched the clock before (tpx,
        // tpy); in iteration 0 the shift is 0 and the operand is the mapper's other digit.
        self.xb.next =
            (self.xm.val() & self.hot[0].q.val()) | (self.tpx.q.val() & !self.hot[0].q.val());
        self.yb.next =
            (self.ym.val() & self.hot[0].q.val()) | (self.tpy.q.val() & !self.hot[0].q.val());
        // The next clock's taps: the registers shift by a digit at this edge, so bit k + b
        // then is bit k + 4 + b now (k + 5 + b at the last digit: the next clock is
        // iteration k + 1). Bits that would come from the digit written at this edge lie
        // past the old word and are replaced by the fill then. AND-OR over the one-hot
        // iteration masks of five-bit windows, then a one-bit shift at the last digit.
        self.wx.next = self.zero8.val();
        self.wy.next = self.zero8.val();
        self.shx.next = self.xr.q.val() >> self.dsh.val();
        self.shy.next = self.yr.q.val() >> self.dsh.val();
        for i in 0..self.hot.len() {
            self.wx.next =
                self.wx.val() | (bit_cast::<8, 32>(self.shx.val()) & self.hot[i].q.val());
            self.wy.next =
                self.wy.val() | (bit_cast::<8, 32>(self.shy.val()) & self.hot[i].q.val());
            self.shx.next = self.shx.val() >> self.bsh.val();
            self.shy.next = self.shy.val() >> self.bsh.val();
        }
        self.tx.next = self.wx.val() & self.dmask.val();
        self.ty.next = self.wy.val() & self.dmask.val();
        if self.jlast.val() {
            self.tx.next = (self.wx.val() >> self.one8.val()) & self.dmask.val();
            self.ty.next = (self.wy.val() >> self.one8.val()) & self.dmask.val();
        }
        self.tpx.d.next = self.tx.val();
        self.tpy.d.next = self.ty.val();
        // Bits past the old word take the fill (y: its sign = dir; x: 0); never in
        // iteration 0 (4j + b < W' there). The mask is registered (see fill_reg).
        self.fillm.next = self.fill_reg.q.val();
        self.xb.next = self.xb.val() & !self.fillm.val();
        self.yb.next = self.yb.val() & !self.fillm.val();
        if self.dir.val() {
            self.yb.next = self.yb.val() | self.fillm.val();
        }
        // One-hot masks: back to (k, j) = (0, 0) when idle or at the last clock of a sample;
        // else the next digit, and at the last digit the next iteration.
        self.adv.next = self.active.val() & !self.last.val() & !self.rst.val();
        for i in 0..self.hot.len() {
            self.hot[i].clock.next = self.clk.val();
            self.hot[i].d.next = self.hot[i].q.val();
        }
        for i in 0..self.jhot.len() {
            self.jhot[i].clock.next = self.clk.val();
            self.jhot[i].d.next = self.zero8.val();
        }
        if self.adv.val() {
            self.jhot[0].d.next = self.zero8.val();
            for i in 1..self.jhot.len() {
                self.jhot[i].d.next = self.jhot[i - 1].q.val();
            }
            if self.jlast.val() {
                self.jhot[0].d.next = self.dmask.val();
                self.hot[0].d.next = self.zero8.val();
                for i in 1..self.hot.len() {
                    self.hot[i].d.next = self.hot[i - 1].q.val();
                }
            }
        } else {
            self.jhot[0].d.next = self.dmask.val();
            self.hot[0].d.next = self.hmask.val();
            for i in 1..self.hot.len() {
                self.hot[i].d.next = self.zero8.val();
            }
        }
    }
}

/// The digit-serial add and the words' registers.
impl stages::DigitAdd for IterativeCordic {
    #[hdl_gen]
    fn update(&mut self) {
        // x - y>>k when y < 0 (x + |y|>>k), else x + y>>k... in the unrolled stage's form:
        // x + ((y>>k) ^ m) + c and y + ((x>>k) ^ !m) + !c, m = all ones when y < 0.
        self.mm.next = self.zero8.val();
        self.nmm.next = self.dmask.val();
        self.m.next = self.zero.val();
        self.c.next = self.zero.val();
        if self.dir.val() {
            self.mm.next = self.dmask.val();
            self.nmm.next = self.zero8.val();
            self.m.next = self.ones.val();
            self.c.next = self.one.val();
        }
        self.cxi.next = self.zero8.val();
        if self.cx_reg.q.val() {
            self.cxi.next = self.one8.val();
        }
        self.cyi.next = self.zero8.val();
        if self.cy_reg.q.val() {
            self.cyi.next = self.one8.val();
        }
        if self.j0.val() {
            self.cxi.next = self.zero8.val();
            self.cyi.next = self.one8.val();
            if self.dir.val() {
                self.cxi.next = self.one8.val();
                self.cyi.next = self.zero8.val();
            }
        }
        self.sx.next = self.xa.val() + (self.yb.val() ^ self.mm.val()) + self.cxi.val();
        self.sy.next = self.ya.val() + (self.xb.val() ^ self.nmm.val()) + self.cyi.val();
        self.dx.next = self.sx.val() & self.dmask.val();
        self.dy.next = self.sy.val() & self.dmask.val();
        // The top digit wraps the word to W bits: bits W..W'-1 copy bit W - 1.
        if self.jlast.val() {
            self.dx.next = self.dx.val() & !self.text.val();
            if (self.dx.val() & self.tsign.val()).any() {
                self.dx.next = self.dx.val() | self.text.val();
            }
            self.dy.next = self.dy.val() & !self.text.val();
            if (self.dy.val() & self.tsign.val()).any() {
                self.dy.next = self.dy.val() | self.text.val();
            }
        }
        self.xr.d.next = self.xr.q.val();
        self.yr.d.next = self.yr.q.val();
        self.zr.d.next = self.zr.q.val();
        self.cx_reg.d.next = (self.sx.val() & self.dcarry.val()).any();
        self.cy_reg.d.next = (self.sy.val() & self.dcarry.val()).any();
        self.dir_reg.d.next = self.dir.val();
        if self.active.val() {
            self.xr.d.next = (self.xr.q.val() >> self.dsh.val())
                | (bit_cast::<32, 8>(self.dx.val()) << self.topsh.val());
            self.yr.d.next = (self.yr.q.val() >> self.dsh.val())
                | (bit_cast::<32, 8>(self.dy.val()) << self.topsh.val());
            // z: the add of iteration k at its digit 1 (D >= 3: adc.width >= 10), so that
            // the first clock only loads the start value (the rounding half plus the
            // quadrant, see the combiner). That load is written last, as the outermost
            // choice in front of z's register, so synthesis maps its constant bits to the
            // flip-flops' synchronous set and reset: no gating LUT in front of z's adder.
            // z still holds the last sample's result through that first clock.
            if self.jhot[1].q.val().get_bit(0) {
                self.zr.d.next =
                    (self.zr.q.val() + (self.rom.data.val() ^ self.m.val()) + self.c.val())
                        & self.zmask.val();
            }
            if self.j0.val() & self.first.val() {
                self.zr.d.next =
                    self.zhalf.val() | (bit_cast::<32, 2>(self.q_in.val()) << self.zqshift.val());
            }
        }
        self.kn.next = self.kin.val();
        self.kge.d.next = self.kge.q.val();
        if self.jlast.val() {
            self.kn.next = self.kin.val() + self.kone.val();
            self.kge.d.next =
                ((self.kge.q.val() << self.bsh.val()) | self.kge1.val()) & self.kmask.val();
        }
        if !self.adv.val() {
            self.kn.next = self.kzero.val();
            self.kge.d.next = self.zero.val();
        }
        self.k_reg.d.next = self.kn.val();
    }
}

/// The next fill mask and the drop bookkeeping.
impl stages::FillMask for IterativeCordic {
    #[hdl_gen]
    fn update(&mut self) {
        // The next clock's fill mask: tap bit b reads fill once 4j' + k' + b >= W' at the
        // next position (j', k'). From digit j < D - 1 it is (j + 1, k): bit W' - b of the
        // thermometer code shifted by 4(j + 1); from the last digit it is (0, k + 1): bit
        // W' - b of the code shifted by one (k + 1 >= t <=> k >= t - 1). Bit 0 of the code is
        // 0, so the shifted codes never set bits they should not (t = 0 is never a fill
        // threshold: 4j + b < W' for j < D). Registered flags in, one AND-OR out.
        self.acc.next = self.zero64.val();
        self.ge.next = bit_cast::<64, 32>(self.kge.q.val());
        for i in 0..self.jhot.len() {
            self.ge.next = self.ge.val() << self.dsh64.val();
            if self.jhot[i].q.val().get_bit(0) {
                self.acc.next = self.acc.val() | self.ge.val();
            }
        }
        if self.jlast.val() {
            self.acc.next = bit_cast::<64, 32>(self.kge.q.val()) << self.bsh64.val();
        }
        self.fnx.next = self.zero8.val();
        if self.adv.val() {
            if (self.acc.val() & self.fw0.val()).any() {
                self.fnx.next = self.fnx.val() | self.fb0.val();
            }
            if (self.acc.val() & self.fw1.val()).any() {
                self.fnx.next = self.fnx.val() | self.fb1.val();
            }
            if (self.acc.val() & self.fw2.val()).any() {
                self.fnx.next = self.fnx.val() | self.fb2.val();
            }
            if (self.acc.val() & self.fw3.val()).any() {
                self.fnx.next = self.fnx.val() | self.fb3.val();
            }
        }
        self.fill_reg.d.next = self.fnx.val();
        self.busy_reg.d.next = self.active.val() & !self.last.val() & !self.rst.val();
        self.done_reg.d.next = self.active.val() & self.last.val() & !self.rst.val();
        // Drop bookkeeping: a sample offered while not ready marks the next accepted one.
        self.drop_reg.d.next = self.drop_reg.q.val();
        if self.in_valid.val() {
            self.drop_reg.d.next = !self.rdy.val();
        }
        if self.rst.val() {
            self.drop_reg.d.next = false;
        }
        self.lostm_reg.d.next = self.drop_reg.q.val();
        // Delay of the mark through the combiner, then held like the counter's flags.
        self.donec_reg.d.next = self.done_reg.q.val() & !self.rst.val();
        self.lostc_reg.d.next = self.loste_reg.q.val();
        self.hold_reg.d.next = self.hold_reg.q.val();
        if self.donec_reg.q.val() {
            self.hold_reg.d.next = self.lostc_reg.q.val();
        }
        if self.rst.val() {
            self.hold_reg.d.next = false;
        }
        self.in_ready.next = self.rdy.val();
        self.x_out.next = self.xr.q.val() & self.xmask.val();
        self.z_out.next = self.zr.q.val();
        self.q_out.next = self.q_reg.q.val();
        self.v_out.next = self.done_reg.q.val();
        self.lost.next = self.hold_reg.q.val();
    }
}
