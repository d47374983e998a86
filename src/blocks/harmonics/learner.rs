//! rust-hdl description of the table's online learner: [`super::sequencer::Sequencer`]
//! register for register, one state of [`LearnState`] per state of the model's
//! [`super::sequencer::State`] (formats, bit growth and clocks in the module doc of
//! [`super::sequencer`]; docs/correction.md, "Learning the table online").
//!
//! ```text
//!   strobe, angle ──► delta = angle - prev (F+2 bits) ──► pos (w+F+2 bits)
//!        │
//!        ▼  Collect, one sample (s + 9 clocks):
//!   Wait ─► ReadI ─► ReadJ ─► LatJ ─► Diff ─► Mult x s ─► Corr ─► Bin ─► ReadBin ─► LatBin ─►
//!    ▲ │    c_i      c_(i+1)          D       D f, one    c(m)    bin, q  n,sk,sp   Acc ─► Sum ─┐
//!    │ │                                                                        +q, Sp  PS, k  │
//!    │ └► LoadA ─► LoadB (ld: entry into both banks)  bit of f                         │
//!    └────────────────────────────────────────────────────────────────────── k < N ◄────────┘
//!   k = N: LineN1 ─► LineU ─► LineW1 ─► LineW2 ─► LineW3 ─► LineLoad ─► LineDiv x Kb ─►
//!          PS += Sp  (N+1)Sp           U, -U       |U|       U's load    b's bits
//!          LineRnd ─► LineRnd2 ─► LineB ─► LineA1 ─► LineA2 ─► LineA3
//!          (q+1)>>1, (-q)>>1      ±        Sp 2^5 + b  moving   a
//!   per bin: ResRead ─► ResLatch ─► ResMul x 2w ─► ResZa ─► ResZb ─► ResX ─► ResW1 ─►
//!            ResW2 ─► ResW3 ─► ResAbs ─► ResLoad ─► ResDiv x Kr ─► ResEnd ─► ResEnd2 ─►
//!            ResWrite ─► ResSum    (Z1 - pb settles in ResX, ResW1; x, -x in ResW2, ResW3)
//!   MeanAbs ─► MeanLoad ─► MeanDiv x Kr ─► MeanEnd ─► MeanEnd2 ─► MeanSign
//!   per bin: UpdRead ─► UpdLat ─► UpdDiff ─► UpdAbs ─► UpdStep ─► UpdAdd ─► UpdWrite (other bank)
//!   Apply (bank flips) ─► Wait;   rst / power-up: Clear (start table into both banks) ─► Wait
//!
//!   RAMs: the table (both banks, bank b's entry i at b P + i, read in the active bank;
//!   data two clocks after the address, [`PipedLutRam`]: c_i's address goes out in Wait or
//!   LoadB, c_(i+1)'s in ReadI, entry idx's in UpdRead for UpdDiff); n_i, sk_i, sp_i (r_i
//!   after Residual; two RAMs of 32 bits), P words each, also read over two clocks, from
//!   four arrays each ([`PipedLutRam`], each its own address register): a
//!   sample's bin goes out from its register in ReadBin, its words latch in Acc, and its
//!   new sums go back two clocks after Sum (bw2); bin idx's goes out in LineA3 or ResSum,
//!   MeanSign or UpdWrite, the state before ResRead or UpdRead, and its words latch in
//!   ResLatch, UpdLat; one write port each; none initialised (Clear writes them first).
//!   The RAMs are sized for P = 128; their addresses go out in p bits (the table's in
//!   p + 1), so that below 128 entries synthesis drops the arrays no address reaches (a
//!   64-entry learner keeps two of each RAM's four). LoadA writes the active bank, so
//!   that a sample's c_i read from LoadB on sees the load. The start table: a ROM of compares, registered (romq), none for a zero
//!   table. Divider (non-restoring, while dstep): rem (2w + 2 bits, two's complement), dvd
//!   (the dividend's bits, MSB first), quo, dsr and -dsr; t = 2 rem + msb(dvd), rem = rem <
//!   0 ? t + dsr : t - dsr, quo = 2 quo + (rem >= 0): the restoring division's quotient
//!   bits (its remainder is rem, or rem + dsr when rem < 0); both t + dsr and t - dsr are
//!   built and rem's sign selects after them. The loads (ldr, ldd) are prepared a state
//!   before the load (LineW3, ResAbs, MeanAbs), and `dload` flags the load a clock ahead.
//! ```
//!
//! Words: signed values are 64-bit two's complement (`Bits<64>`), except the residuals'
//! r, r_i and Update's words (32 bits: |r_i - r| < 2^(F+T-1), entries <= 24 bits) and sum
//! r ([`SUMR_BITS`]); unsigned counts are `Bits<32>`. No word is wider than 64 bits
//! ([`super::sequencer::WORD_MAX`]). `pos` wraps at the model's width, as the model's does
//! (strobes outside Collect move it too); every word computed from it stays within the
//! model's width by the bounds of the model's table (q, Sp, PS, U, b, a: [`super::sequencer`]),
//! so the RTL adds them in 64 bits without re-wrapping, and equals the model.
//!
//! Timing: every register-to-register path holds at most one carry chain (a compare beside
//! it), and a sum goes into a register of its own with no select after its chain but the
//! divider's (its two sums, selected by a registered sign); no sum is wider than 40 bits
//! (sum r), and the longer chains left are compares into one-bit registers (ovf, cpos, cneg). A
//! 64-bit sum is a [`SplitAdd`] (two 32-bit chains, the high one a
//! clock after the low one) of operands that hold still, or a [`SplitAcc`] (Sp += q in Acc,
//! PS += Sp the clock after Sum, the four products in ResMul): q, sp1 = sp_i + q, (N + 1)
//! Sp (un1), U and -U (unum, unn), +-round(quo / 2) (rm, rmn), Sp 2^5 + b (asp), a, sp_i -
//! a_h n_i (z0), Z1, Z2, x and -x (xres, xng), Z1 + H (zh). Each is right two clocks after
//! its operands (a SplitAcc a clock after its last add), and the model's states count
//! these clocks (LineW1-3, LineRnd2, LineA3, ResMul's last clock, ResW1-3, ResEnd2,
//! MeanEnd2). Other free-running registers: b's one-period tests of its bits (mpos,
//! mneg), the products' add flags a clock ahead (fpa, fla, fpb, flb), Clear's write
//! address (cwa), |Z1| >= H as a test of Z1 + H's top bits (big, zneg), quo > 2 lim as
//! a test of its bits (qov), idx + 1 (idx1), k's last-sample test (klast). c(m)'s product runs from f's LSB in 32 bits
//! (acc = (acc + f_j D) >> 1). A RAM's output is registered before an adder (LatJ, UpdLat,
//! ResLatch, Acc), `pos` moves a clock after its strobe (dl), sum r's negation is summed
//! beside it (srn), r_i saturates in ResWrite and reaches sp_i's word from its register in
//! ResSum.
//!
//! Resources alone in Yosys 0.23 at F = 14, 128 entries, N = 4096 (a zero start table;
//! tests/blocks/harmonics_learner.rs): xc3sa 3831 LUT4 (1000 of them RAM16X1D), 3741 FF,
//! no block RAM, no MULT18X18; cycloneive 6142 LE, 3282 FF, 20 M9K (four arrays each for
//! the table, n_i, sk_i and sp_i's two halves), no multiplier; at 64 entries half the RAM
//! (500 RAM16X1D, 10 M9K): xc3sa 3314 LUT4, 3515 FF, cycloneive 5907 LE, 3266 FF. The
//! RAMs are distributed on ECP5 and xc3sa, read in the widths their words hold (the entry
//! width, w + 1 bits of n_i, 2w - 1 of sk_i, sp_i's), so that synthesis drops
//! the other columns. The state is one-hot in synthesis ([`FsmReg`]); the counters' end
//! tests compare p bits, the loops count down to a registered zero flag (`dn`, `dz`), the
//! sample counts' tests compare w + 1 bits; the divider keeps 2w + 1
//! remainder bits and max(Kb, Kr) quotient bits. The other 64-bit registers hold narrower
//! values that Yosys does not trim.
//!
//! Timing (docs/timing.md's ECP5 flow at 133.33 MHz, seeds 1 / 2 / 3): the default top with
//! a 64-point learned table 158.63 / 137.27 / 152.95 MHz, with 128 points and `[registers]`
//! 143.00 / 151.03 / 156.89 MHz ([`super::block::LEARNED_TOPS`]), short of the rule's
//! 166.7 MHz median; the worst paths are 3.7 to 5.6 ns of routing. Placed alone the learner
//! reaches 171.44 / 166.06 MHz (seeds 1 / 2). Both tops meet the rule up to 119 MHz, the
//! highest clock a learned table is built for ([`super::block::learned_clock_mhz`]);
//! `tests/timing.rs` holds the default top learning at 100 MHz.
//!
//! Ports:
//!
//! | port | dir | width | meaning |
//! |---|---|---|---|
//! | `clk` | in | 1 | system clock |
//! | `rst` | in | 1 | synchronous reset: Clear, empty sums, no load pending, bank 0 |
//! | `strobe` | in | 1 | a sample this clock (the CORDIC's valid) |
//! | `angle` | in | F+2 | its raw fine angle within the period, LSB |
//! | `update` | in | 1 | 1: entries move; 0: every entry written back unchanged |
//! | `ld` | in | 1 | a one-clock request to set entry `ld_addr` to `ld_data` |
//! | `ld_addr` | in | p | the entry |
//! | `ld_data` | in | entry width | its value, q units, two's complement |
//! | `tw` | out | 1 | a table write was made (registered: the clock after the RAM's) |
//! | `tw_addr` | out | p+1 | its address, bank * P + i |
//! | `tw_data` | out | entry width | its entry, q units, two's complement |
//! | `bank` | out | 1 | the bank the correction reads (flips at Apply) |
//! | `ld_busy` | out | 1 | a load is pending (a new `ld` is dropped) |
//! | `clearing` | out | 1 | the state was Clear a clock ago: with `tw`, the Clear's writes (registered) |
use super::sequencer::{LearnParams, TABLE_FRAC};
use crate::blocks::fsmreg::FsmReg;
use crate::blocks::init_bit::InitBit;
use crate::blocks::lutram::PipedLutRam;
use crate::blocks::splitadd::{SplitAcc, SplitAdd};
use crate::blocks::{c32, mask};
use crate::cosim::Port;
use rust_hdl::prelude::*;

/// Address bits of the learner's RAMs (P <= 128 words each: a bank of the table, the bins'
/// sums). Distributed RAM read over two clocks ([`PipedLutRam`]): a block RAM's read alone
/// misses the timing rule on ECP5 (docs/timing.md).
pub const LEARN_ADDR_BITS: usize = 7;

/// Address bits of the table's RAM: the bank, then the entry.
pub const TAB_ADDR_BITS: usize = LEARN_ADDR_BITS + 1;

/// Bits of `sum_r`, the residuals' sum over at most P bins: F - 2 + T + 1 + p <= 34 at
/// F <= 20, p <= 7.
pub const SUMR_BITS: usize = 40;

/// Bits of the learner's clock counter: Clear's 2P + 1 clocks (P <= 128) and the longest
/// division's quotient bits (at most 64) fit.
pub const CNT_BITS: usize = 10;

fn cc(v: u64) -> Constant<Bits<CNT_BITS>> {
    Constant::new(Bits::<CNT_BITS>::from(v))
}

fn ci(v: u64) -> Constant<Bits<LEARN_ADDR_BITS>> {
    Constant::new(Bits::<LEARN_ADDR_BITS>::from(v))
}

fn c64(v: u64) -> Constant<Bits<64>> {
    Constant::new(Bits::<64>::from(v))
}

/// The learner's states, which the model ([`super::sequencer::Sequencer`]) steps through too.
#[derive(Copy, Clone, PartialEq, Eq, Debug, LogicState)]
pub enum LearnState {
    /// The start table into both banks, the bins cleared (power-up and reset).
    Clear,
    /// Collect: waiting for a sample or a pending load.
    Wait,
    /// The load into the active bank.
    LoadA,
    /// The load into the other bank.
    LoadB,
    /// c_i read.
    ReadI,
    /// c_(i+1) read.
    ReadJ,
    /// c_(i+1) latched (a RAM's output goes to a register before an adder).
    LatJ,
    /// D = c_(i+1) - c_i.
    Diff,
    /// D f, one bit of f a clock.
    Mult,
    /// c(m).
    Corr,
    /// The bin and q.
    Bin,
    /// The bin's sums read.
    ReadBin,
    /// The bin's sums latched.
    LatBin,
    /// The bin's sums and Sp.
    Acc,
    /// PS and k.
    Sum,
    /// (N + 1) Sp.
    LineN1,
    /// U.
    LineU,
    /// U settles (its two-clock sums, [`SplitAdd`]).
    LineW1,
    /// See LineW1.
    LineW2,
    /// |U| settles.
    LineW3,
    /// b's division loaded.
    LineLoad,
    /// b's quotient bits.
    LineDiv,
    /// b's magnitude rounded.
    LineRnd,
    /// See LineRnd (its two-clock sums).
    LineRnd2,
    /// b signed.
    LineB,
    /// Sp 2^5 + b, the one-period test.
    LineA1,
    /// a's first sum settles; the one-period test.
    LineA2,
    /// a settles.
    LineA3,
    /// Bin idx's sums read.
    ResRead,
    /// Latched; the products set up.
    ResLatch,
    /// The four products, one multiplier bit a clock.
    ResMul,
    /// Z1 = sp - a_h n, Z2.
    ResZa,
    /// Z1 -= b_h sk.
    ResZb,
    /// Z2 and sp_i - a_h n_i settle.
    ResX,
    /// Z1 settles.
    ResW1,
    /// See ResW1.
    ResW2,
    /// x, -x and Z1 + H settle.
    ResW3,
    /// |x|.
    ResAbs,
    /// r_i's division loaded.
    ResLoad,
    /// r_i's quotient bits.
    ResDiv,
    /// r_i's magnitude.
    ResEnd,
    /// See ResEnd (its two-clock sums).
    ResEnd2,
    /// r_i into sp_i's word.
    ResWrite,
    /// sum r, bins.
    ResSum,
    /// |sum r|.
    MeanAbs,
    /// r's division loaded.
    MeanLoad,
    /// r's quotient bits.
    MeanDiv,
    /// r's magnitude.
    MeanEnd,
    /// See MeanEnd (its two-clock sums).
    MeanEnd2,
    /// r signed.
    MeanSign,
    /// Entry idx, n_i, r_i read.
    UpdRead,
    /// Latched.
    UpdLat,
    /// r_i - r.
    UpdDiff,
    /// |r_i - r|.
    UpdAbs,
    /// The step.
    UpdStep,
    /// c_i + the step.
    UpdAdd,
    /// The new entry into the other bank; the bin cleared.
    UpdWrite,
    /// The bank flips.
    Apply,
}

/// The table learner (ports in the module doc).
#[derive(LogicBlock)]
pub struct HarmonicLearner {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset: Clear, empty sums, no load pending, bank 0.
    pub rst: Signal<In, Bit>,
    /// A sample this clock.
    pub strobe: Signal<In, Bit>,
    /// Its raw fine angle within the period (F + 2 bits), LSB.
    pub angle: Signal<In, Bits<32>>,
    /// 1: entries move at Update; 0: written back unchanged.
    pub update: Signal<In, Bit>,
    /// A request to set entry `ld_addr` to `ld_data`.
    pub ld: Signal<In, Bit>,
    /// The entry of the request (low p bits).
    pub ld_addr: Signal<In, Bits<32>>,
    /// Its value, q units, two's complement in the entry width.
    pub ld_data: Signal<In, Bits<32>>,
    /// A table write was made (the clock after the RAM's).
    pub tw: Signal<Out, Bit>,
    /// Its address, bank * P + i.
    pub tw_addr: Signal<Out, Bits<32>>,
    /// Its entry, two's complement in the entry width.
    pub tw_data: Signal<Out, Bits<32>>,
    /// The bank the correction reads.
    pub bank: Signal<Out, Bit>,
    /// A load is pending.
    pub ld_busy: Signal<Out, Bit>,
    /// The state was Clear a clock ago (aligned with `tw`): the correction reads zeros.
    pub clearing: Signal<Out, Bit>,
    /// See `clearing`.
    clr: DFF<Bit>,
    /// The table: bank b's entry i at word b P + i (the bank an address bit, so that no
    /// select follows the read), entries in the entry width.
    tab: PipedLutRam<Bits<32>, TAB_ADDR_BITS>,
    /// Per bin: n_i. The bins' RAMs read over two clocks in four arrays ([`PipedLutRam`]:
    /// the one-clock read of 128 words, and a one-array read's eight-way select, were the
    /// learner's worst paths): the address goes out in the state before ReadBin, ResRead
    /// and UpdRead.
    rn: PipedLutRam<Bits<32>, LEARN_ADDR_BITS>,
    /// Per bin: sk_i.
    rsk: PipedLutRam<Bits<32>, LEARN_ADDR_BITS>,
    /// Per bin: sp_i, then r_i (64-bit two's complement).
    rsp: PipedLutRam<Bits<32>, LEARN_ADDR_BITS>,
    /// sp_i's high 32 bits: two RAMs of 32 bits, each with its own address register (the
    /// read path's fan-out into the LUT RAM cells).
    rsph: PipedLutRam<Bits<32>, LEARN_ADDR_BITS>,
    /// The start table, entry i XOR-ed with i (the correction block's ROM, super::hdl: a
    /// compare per entry, so that no synthesizer maps it to an initialised block RAM, which
    /// Yosys 0.23 fails to map on Cyclone); none for a zero start table.
    rom: Vec<Constant<Bits<32>>>,
    /// The entry numbers 0..P the start table's index is compared with (none without it).
    seg: Vec<Constant<Bits<32>>>,
    /// All ones with a start table, zero without (undoes the XOR).
    rom_x: Constant<Bits<32>>,
    /// Clear's start entry, read a clock before its write (the pipeline of a RAM read).
    romq: DFF<Bits<32>>,
    /// The start table's index this clock; its entry, still XOR-ed.
    cidx: Signal<Local, Bits<32>>,
    tx: Signal<Local, Bits<32>>,
    /// The state, one-hot in synthesis ([`FsmReg`]: the state's fan-out into every
    /// 64-bit register's select).
    state: FsmReg<LearnState>,
    /// The clock of Clear ([`CNT_BITS`] wide: 2P + 1 clocks).
    cnt: DFF<Bits<CNT_BITS>>,
    /// cnt a clock ago: Clear's write address, cnt - 1 (Timing: cnt -> the table's write
    /// address through a subtraction).
    cwa: DFF<Bits<CNT_BITS>>,
    /// The loops' clocks left (Mult, LineDiv, ResMul, ResDiv, MeanDiv), counting down from
    /// the loop's last index loaded by the state before it, and whether it is 0 (registered:
    /// the path from the count through a compare to the state's every bit).
    dn: DFF<Bits<CNT_BITS>>,
    dz: DFF<Bit>,
    /// The bin of Residual and Update; the next one (registered: the bins' read address).
    idx: DFF<Bits<LEARN_ADDR_BITS>>,
    idx1: DFF<Bits<LEARN_ADDR_BITS>>,
    /// The bank the correction reads.
    active: DFF<Bit>,
    /// The load: pending, its entry, its value (entry width).
    pend: DFF<Bit>,
    ld_i: DFF<Bits<32>>,
    ld_v: DFF<Bits<32>>,
    /// A sample latched during LoadA or LoadB.
    got: DFF<Bit>,
    /// The sample in process: angle, raw position.
    m_s: DFF<Bits<32>>,
    ps: DFF<Bits<64>>,
    /// The previous sample's angle; the raw position since the window's first sample.
    prev: DFF<Bits<32>>,
    pos: DFF<Bits<64>>,
    /// The pos update a clock after its strobe (the path from the angle's port through
    /// two adders is cut here): delta, pending, the window starts, the sample is taken.
    dl: DFF<Bits<64>>,
    dlv: DFF<Bit>,
    dls: DFF<Bit>,
    dla: DFF<Bit>,
    /// m 2^T + 2^(s+T-1): the sample's angle with the bin's rounding half.
    mh: DFF<Bits<64>>,
    /// c_(i+1).
    cj: DFF<Bits<64>>,
    /// c_i; D shifted left a bit a clock; f shifted right; D f.
    ci: DFF<Bits<64>>,
    dd: DFF<Bits<32>>,
    fsh: DFF<Bits<32>>,
    acc: DFF<Bits<32>>,
    /// The sample's c(m), bin, q.
    c: DFF<Bits<64>>,
    sbin: DFF<Bits<32>>,
    q: SplitAdd,
    /// The window's samples k, Sp, PS.
    k: DFF<Bits<32>>,
    sum_p: SplitAcc,
    sum_ps: SplitAcc,
    /// k is the window's last sample (registered: the path from k through a compare to the
    /// state).
    klast: DFF<Bit>,
    /// PS takes Sp (the clock after Sum, when Sp's high half has settled); the bin's new
    /// sums go to its RAMs (two clocks after Sum, when sp1 has settled).
    psa: DFF<Bit>,
    bw1: DFF<Bit>,
    bw2: DFF<Bit>,
    /// The bin's new n_i, sk_i and sp_i, written two clocks after Sum (the path from the
    /// sums' carry chains into the RAMs' write port).
    n1: DFF<Bits<32>>,
    sk1: DFF<Bits<32>>,
    sp1: SplitAdd,
    /// (N + 1) Sp; U and -U.
    un1: SplitAdd,
    unum: SplitAdd,
    unn: SplitAdd,
    /// The divider: the dividend's sign, its magnitude, remainder, dividend bits,
    /// quotient, divisor.
    neg: DFF<Bit>,
    mag: DFF<Bits<64>>,
    rem: DFF<Bits<64>>,
    dvd: DFF<Bits<64>>,
    quo: DFF<Bits<64>>,
    dsr: DFF<Bits<64>>,
    /// -dsr; the divider steps (registered: set in a division's load, cleared at its last
    /// step); the remainder's and the dividend's loads, prepared a state ahead (so that
    /// rem has two sources: the path from the step's chain).
    ndsr: DFF<Bits<64>>,
    dstep: DFF<Bit>,
    /// The state is a division's load (set in the state before it). Timing: the three
    /// load states' bits fanned out to the remainder's, dividend's and quotient's
    /// selects (state -> quo).
    dload: InitBit,
    ldr: DFF<Bits<64>>,
    ldd: DFF<Bits<64>>,
    /// A rounded magnitude (b, r_i, r) and its negation (so that a sign is a select: the
    /// paths from the quotient to b, r_i and r).
    rm: SplitAdd,
    rmn: SplitAdd,
    /// The line; Sp 2^5 + b; b at least one period up, down; the window moved at least one
    /// period.
    b: DFF<Bits<64>>,
    a: SplitAdd,
    asp: SplitAdd,
    mpos: DFF<Bit>,
    mneg: DFF<Bit>,
    moving: DFF<Bit>,
    /// Residual: n_i; n_i and sk_i shifted right; sp_i; a_h, a_l, b_h, b_l shifted left.
    nn: DFF<Bits<32>>,
    nsh: DFF<Bits<32>>,
    sksh: DFF<Bits<32>>,
    spv: DFF<Bits<64>>,
    ahs: DFF<Bits<64>>,
    als: DFF<Bits<64>>,
    bhs: DFF<Bits<64>>,
    bls: DFF<Bits<64>>,
    /// The products' add flags, one per accumulator (a clock ahead: ResMul's next clock
    /// and n_i's or sk_i's next bit). Timing: the state and the multiplier's bit fanned
    /// out to 128 operand gates each (nsh -> pa, la).
    fpa: InitBit,
    fla: InitBit,
    fpb: InitBit,
    flb: InitBit,
    /// The flags' next value from n_i's and from sk_i's bits.
    fn_n: Signal<Local, Bit>,
    fn_sk: Signal<Local, Bit>,
    /// The products a_h n_i, b_h sk_i, a_l n_i, b_l sk_i.
    pa: SplitAcc,
    pb: SplitAcc,
    la: SplitAcc,
    lb: SplitAcc,
    /// sp_i - a_h n_i; Z1, Z2, x = Z1 2^B - Z2; |Z1| >= H and Z1's sign; the division
    /// overflowed.
    z0: SplitAdd,
    z1: SplitAdd,
    z2: SplitAdd,
    xres: SplitAdd,
    /// -x, beside x (ResX), so that ResAbs's |x| is a select (the path x -> mag).
    xng: SplitAdd,
    big: DFF<Bit>,
    zneg: DFF<Bit>,
    /// Z1 + H (big = Z1 + H outside [0, 2H): a chain, then a test of its top bits, the
    /// path from Z1 to big).
    zh: SplitAdd,
    ovf: DFF<Bit>,
    /// r_i's sign; r_i.
    rneg: DFF<Bit>,
    /// The quotient is above 2 lim (registered: the path from quo through the compare to
    /// r); with big or ovf, r_i saturates in ResWrite.
    qov: DFF<Bit>,
    r: DFF<Bits<32>>,
    /// sum r ([`SUMR_BITS`]: F + 7 + p <= 34 bits), the bins with samples, r (32 bits).
    sum_r: DFF<Bits<SUMR_BITS>>,
    /// -sum r, summed beside it (so that MeanAbs's |sum r| is a select).
    srn: DFF<Bits<SUMR_BITS>>,
    nbins: DFF<Bits<32>>,
    /// No bin has samples (registered: the path from nbins through a compare to mean).
    nb0: DFF<Bit>,
    mean: DFF<Bits<32>>,
    /// Update, in 32 bits (|r_i - r| < 2^(F+T-1) <= 2^27, entries E <= 24 bits): c_i,
    /// n_i != 0, r_i - r, its sign and magnitude, the step, c_i + step; the room to the
    /// limit the step moves towards, 2^(F-4) LSB - c_i or c_i + 2^(F-4) LSB, and whether
    /// the step exceeds it (decided with the sum, so that no compare precedes the write).
    ucur: DFF<Bits<32>>,
    unz: DFF<Bit>,
    ux: DFF<Bits<32>>,
    /// r - r_i, beside r_i - r (so that UpdAbs's magnitude is a select).
    uxn: DFF<Bits<32>>,
    uneg: DFF<Bit>,
    /// r_i - r and r - r_i at least the magnitude that clips (free-running from ux and
    /// uxn, read in UpdStep: the path from |r_i - r| through a compare to the step).
    cpos: DFF<Bit>,
    cneg: DFF<Bit>,
    uax: DFF<Bits<32>>,
    udm: DFF<Bits<32>>,
    unw: DFF<Bits<32>>,
    uroom: DFF<Bits<32>>,
    usat: DFF<Bit>,
    /// The window moved and bin idx has samples (registered in UpdAdd: the path from
    /// moving to the table's write data).
    mvz: DFF<Bit>,
    /// The write port's copy, a clock after the RAM write.
    twr: DFF<Bit>,
    twa: DFF<Bits<32>>,
    twd: DFF<Bits<32>>,
    /// Combinational: the table write this clock; a strobe Collect takes; delta; pos + delta;
    /// the new pos; the segment i and i + 1 of the sample; the bank offsets; the
    /// divider's step; sign-extended reads; an absolute value; a sum.
    we: Signal<Local, Bit>,
    wa: Signal<Local, Bits<32>>,
    wd: Signal<Local, Bits<32>>,
    accept: Signal<Local, Bit>,
    delta: Signal<Local, Bits<64>>,
    psum: Signal<Local, Bits<64>>,
    pnew: Signal<Local, Bits<64>>,
    /// The segment of the sample a strobe of this clock or m_s holds (c_i's address,
    /// presented the clock before ReadI: the table's read takes two clocks).
    seg_n: Signal<Local, Bits<32>>,
    /// The bin Bin latches into sbin.
    bin_n: Signal<Local, Bits<32>>,
    /// The bins' RAMs' read address (one for the three RAMs), a state ahead of its data.
    bra: Signal<Local, Bits<LEARN_ADDR_BITS>>,
    seg_i: Signal<Local, Bits<32>>,
    seg_j: Signal<Local, Bits<32>>,
    /// The active bank's and the other bank's offsets.
    off_a: Signal<Local, Bits<32>>,
    off_o: Signal<Local, Bits<32>>,
    dt: Signal<Local, Bits<64>>,
    /// The step's two sums, t + d and t - d, the remainder's sign as a mask, and the sum
    /// it selects. Timing: both chains run while the sign fans out to the select after
    /// them (the path rem -> rem, quo), not in front of one chain.
    drp: Signal<Local, Bits<64>>,
    drm: Signal<Local, Bits<64>>,
    rsm: Signal<Local, Bits<64>>,
    dr: Signal<Local, Bits<64>>,
    tab_s: Signal<Local, Bits<64>>,
    /// The table's read entry; its RAM address with the active bank.
    traddr: Signal<Local, Bits<32>>,
    tra: Signal<Local, Bits<32>>,
    /// n_i and sk_i read, in their widths.
    rn_m: Signal<Local, Bits<32>>,
    rsk_m: Signal<Local, Bits<32>>,
    /// The table's word read, in the entry width.
    trd: Signal<Local, Bits<32>>,
    /// The bins' RAMs' write address (the same for the three).
    bwa: Signal<Local, Bits<LEARN_ADDR_BITS>>,
    sp_s: Signal<Local, Bits<64>>,
    /// sp_i's word read (both halves) and the word written.
    spr: Signal<Local, Bits<64>>,
    spw: Signal<Local, Bits<64>>,
    t64: Signal<Local, Bits<64>>,
    /// a; +-round(quo / 2) (the two-clock sums' outputs shifted).
    av: Signal<Local, Bits<64>>,
    rmv: Signal<Local, Bits<64>>,
    rmnv: Signal<Local, Bits<64>>,
    t32: Signal<Local, Bits<32>>,
    /// r sign-extended to sum r's width.
    r_x: Signal<Local, Bits<SUMR_BITS>>,
    sr_z: Constant<Bits<SUMR_BITS>>,
    sr_hi: Constant<Bits<SUMR_BITS>>,
    sr_sign: Constant<Bits<SUMR_BITS>>,
    abs: Signal<Local, Bits<64>>,
    ldm: Signal<Local, Bits<32>>,
    /// Constants (64-bit unless marked).
    /// Zero, one.
    z64: Constant<Bits<64>>,
    one64: Constant<Bits<64>>,
    /// Zero, one (32-bit).
    z32: Constant<Bits<32>>,
    one32: Constant<Bits<32>>,
    /// P - 1, P, 2P (32-bit).
    pmask: Constant<Bits<32>>,
    pp: Constant<Bits<32>>,
    p2: Constant<Bits<CNT_BITS>>,
    /// P - 1 (the bin counter's width); zero and one of the counters' widths.
    ilast: Constant<Bits<LEARN_ADDR_BITS>>,
    iz: Constant<Bits<LEARN_ADDR_BITS>>,
    ione: Constant<Bits<LEARN_ADDR_BITS>>,
    cz: Constant<Bits<CNT_BITS>>,
    cone: Constant<Bits<CNT_BITS>>,
    /// Entry width: mask, sign bit (32-bit).
    ew_mask: Constant<Bits<32>>,
    ew_sign: Constant<Bits<32>>,
    /// The sign fill above the entry width (64-bit).
    ew_fill: Constant<Bits<64>>,
    /// The 2w - 1 bits of sk_i.
    skmask: Constant<Bits<32>>,
    /// 2P - 1: the table's RAM address (both banks).
    tmask: Constant<Bits<32>>,
    /// +entry_max, -entry_max as an entry-width code (32-bit).
    emax32: Constant<Bits<32>>,
    emin32: Constant<Bits<32>>,
    /// +entry_max, -entry_max (64-bit).
    /// The angle's F + 2 bits: mask, sign bit, fill.
    am_mask: Constant<Bits<64>>,
    am_sign: Constant<Bits<64>>,
    /// pos's width: mask, sign bit.
    pw_mask: Constant<Bits<64>>,
    pw_sign: Constant<Bits<64>>,
    /// sp_i's width (its RAM's read): mask, sign bit.
    sw_mask: Constant<Bits<64>>,
    sw_sign: Constant<Bits<64>>,
    /// Bit 63.
    sign63: Constant<Bits<64>>,
    /// s (32-bit shift), the mask of f (32-bit), s - 1 (the Mult's last clock).
    s32: Constant<Bits<32>>,
    fmask: Constant<Bits<32>>,
    s_last: Constant<Bits<CNT_BITS>>,
    /// T; s + T; 2^(s + T - 1) (the bin's rounding half).
    tf: Constant<Bits<64>>,
    st: Constant<Bits<64>>,
    st_half: Constant<Bits<64>>,
    /// w; N - 1 (32-bit); 5; 1; 63.
    w64: Constant<Bits<64>>,
    n_last: Constant<Bits<32>>,
    /// The w + 1 bits a count of a window's samples (k, n_i) or of bins has: its tests
    /// compare these only.
    nmask: Constant<Bits<32>>,
    k5: Constant<Bits<64>>,
    k63: Constant<Bits<64>>,
    /// 32 (sp_i's halves).
    k32: Constant<Bits<64>>,
    /// b's division: D, lead Kb - 6 and 64 - lead, the last quotient clock Kb - 1.
    dline: Constant<Bits<64>>,
    lb_lead: Constant<Bits<64>>,
    lb_up: Constant<Bits<64>>,
    lb_last: Constant<Bits<CNT_BITS>>,
    /// The divider's widths: the remainder's 2w + 1 bits (rem < dsr <= D < 2^(2w-1) when
    /// the quotient fits; an r_i division that does not saturates r_i whatever its
    /// quotient), the quotient's max(Kb, Kr) bits (a bit a clock from zero), the divisor's
    /// 2w bits. Narrow words keep the divider's compare and subtract short (timing).
    rem_mask: Constant<Bits<64>>,
    /// The remainder's sign bit (2w + 1); -D.
    rem_sgn: Constant<Bits<64>>,
    ndline: Constant<Bits<64>>,
    quo_mask: Constant<Bits<64>>,
    dsr_mask: Constant<Bits<64>>,
    /// One period of |b|: b >= it, b <= its negative.
    op_hi: Constant<Bits<64>>,
    op_lo: Constant<Bits<64>>,
    /// B; the mask of B bits; the sign fill of >> B; 2w - 1 (ResMul's last clock).
    bf: Constant<Bits<64>>,
    bf_mask: Constant<Bits<64>>,
    bf_fill: Constant<Bits<64>>,
    mul_last: Constant<Bits<CNT_BITS>>,
    /// H = 2^(62-B); the bits of Z1 + H from 63 - B up.
    h_pos: Constant<Bits<64>>,
    h2_hi: Constant<Bits<64>>,
    /// r_i's division: lead Kr + B - 1 and 64 - lead, the last quotient clock; 2 lim + 1 =
    /// 2^Kr - 1 (Kr ones).
    lr_lead: Constant<Bits<64>>,
    lr_up: Constant<Bits<64>>,
    lr_last: Constant<Bits<CNT_BITS>>,
    q_over: Constant<Bits<64>>,
    /// lim and -lim in 32 bits (r_i's saturated values).
    lim32: Constant<Bits<32>>,
    nlim32: Constant<Bits<32>>,
    /// r's division: lead Kr - 1 and 64 - lead.
    lm_lead: Constant<Bits<64>>,
    lm_up: Constant<Bits<64>>,
    /// The update: g, 2^(g-1), the step, the magnitude that clips.
    g_half: Constant<Bits<32>>,
    stepc: Constant<Bits<32>>,
    clip_at: Constant<Bits<32>>,
    g32: Constant<Bits<32>>,
    sign31: Constant<Bits<32>>,
    hi32: Constant<Bits<64>>,
}

impl HarmonicLearner {
    /// The learner for `p` with the start table `start` (q units, P entries within
    /// +-2^(F-4) LSB, [`super::sequencer::Sequencer::with_table`] checks them).
    pub fn new(p: &LearnParams, start: &[i64]) -> Self {
        let pp = p.points() as u64;
        let ew = p.entry_width();
        let s = p.seg_bits();
        let bfr = p.line_frac();
        let kb = p.line_div_bits();
        let kr = p.res_div_bits();
        let em = p.entry_max() as u64;
        let sign = |w: u32| 1u64 << (w - 1);
        let neg = |v: u64| v.wrapping_neg();
        let fill = |n: u32| !(u64::MAX >> n);
        let g = p.gain_shift;
        let zero = start.iter().all(|&c| c == 0);
        let rom: Vec<Constant<Bits<32>>> = if zero {
            Vec::new()
        } else {
            start
                .iter()
                .enumerate()
                .map(|(i, &c)| c32((c as u64 & mask(ew)) ^ i as u64))
                .collect()
        };
        let seg = if zero {
            Vec::new()
        } else {
            (0..pp).map(c32).collect()
        };
        HarmonicLearner {
            clk: Default::default(),
            rst: Default::default(),
            strobe: Default::default(),
            angle: Default::default(),
            update: Default::default(),
            ld: Default::default(),
            ld_addr: Default::default(),
            ld_data: Default::default(),
            tw: Default::default(),
            tw_addr: Default::default(),
            tw_data: Default::default(),
            bank: Default::default(),
            ld_busy: Default::default(),
            clearing: Default::default(),
            clr: Default::default(),
            tab: Default::default(),
            rn: Default::default(),
            rsk: Default::default(),
            rsp: Default::default(),
            rsph: Default::default(),
            rom,
            seg,
            rom_x: c32(if zero { 0 } else { u64::MAX }),
            romq: Default::default(),
            cidx: Default::default(),
            tx: Default::default(),
            state: Default::default(),
            cnt: Default::default(),
            cwa: Default::default(),
            dn: Default::default(),
            dz: Default::default(),
            idx: Default::default(),
            idx1: Default::default(),
            active: Default::default(),
            pend: Default::default(),
            ld_i: Default::default(),
            ld_v: Default::default(),
            got: Default::default(),
            m_s: Default::default(),
            ps: Default::default(),
            prev: Default::default(),
            pos: Default::default(),
            dl: Default::default(),
            dlv: Default::default(),
            dls: Default::default(),
            dla: Default::default(),
            mh: Default::default(),
            cj: Default::default(),
            ci: Default::default(),
            dd: Default::default(),
            fsh: Default::default(),
            acc: Default::default(),
            c: Default::default(),
            sbin: Default::default(),
            q: SplitAdd::sub(),
            k: Default::default(),
            sum_p: Default::default(),
            sum_ps: Default::default(),
            klast: Default::default(),
            psa: Default::default(),
            bw1: Default::default(),
            bw2: Default::default(),
            n1: Default::default(),
            sk1: Default::default(),
            sp1: SplitAdd::add(),
            un1: SplitAdd::add(),
            unum: SplitAdd::sub(),
            unn: SplitAdd::sub(),
            neg: Default::default(),
            mag: Default::default(),
            rem: Default::default(),
            dvd: Default::default(),
            quo: Default::default(),
            dsr: Default::default(),
            ndsr: Default::default(),
            dstep: Default::default(),
            dload: InitBit::kept(false),
            ldr: Default::default(),
            ldd: Default::default(),
            rm: SplitAdd::add(),
            rmn: SplitAdd::sub(),
            b: Default::default(),
            a: SplitAdd::sub(),
            asp: SplitAdd::add(),
            mpos: Default::default(),
            mneg: Default::default(),
            moving: Default::default(),
            nn: Default::default(),
            nsh: Default::default(),
            sksh: Default::default(),
            spv: Default::default(),
            ahs: Default::default(),
            als: Default::default(),
            bhs: Default::default(),
            bls: Default::default(),
            fpa: InitBit::kept(false),
            fn_n: Default::default(),
            fn_sk: Default::default(),
            fla: InitBit::kept(false),
            fpb: InitBit::kept(false),
            flb: InitBit::kept(false),
            pa: Default::default(),
            pb: Default::default(),
            la: Default::default(),
            lb: Default::default(),
            z0: SplitAdd::sub(),
            z1: SplitAdd::sub(),
            z2: SplitAdd::add(),
            xres: SplitAdd::sub(),
            xng: SplitAdd::sub(),
            big: Default::default(),
            zneg: Default::default(),
            zh: SplitAdd::add(),
            ovf: Default::default(),
            rneg: Default::default(),
            qov: Default::default(),
            r: Default::default(),
            sum_r: Default::default(),
            srn: Default::default(),
            nbins: Default::default(),
            nb0: Default::default(),
            mean: Default::default(),
            ucur: Default::default(),
            unz: Default::default(),
            ux: Default::default(),
            uxn: Default::default(),
            uneg: Default::default(),
            cpos: Default::default(),
            cneg: Default::default(),
            uax: Default::default(),
            udm: Default::default(),
            unw: Default::default(),
            uroom: Default::default(),
            usat: Default::default(),
            mvz: Default::default(),
            twr: Default::default(),
            twa: Default::default(),
            twd: Default::default(),
            we: Default::default(),
            wa: Default::default(),
            wd: Default::default(),
            accept: Default::default(),
            delta: Default::default(),
            psum: Default::default(),
            pnew: Default::default(),
            seg_n: Default::default(),
            bin_n: Default::default(),
            bra: Default::default(),
            seg_i: Default::default(),
            seg_j: Default::default(),
            off_a: Default::default(),
            off_o: Default::default(),
            dt: Default::default(),
            drp: Default::default(),
            drm: Default::default(),
            rsm: Default::default(),
            dr: Default::default(),
            tab_s: Default::default(),
            traddr: Default::default(),
            tra: Default::default(),
            rn_m: Default::default(),
            rsk_m: Default::default(),
            trd: Default::default(),
            bwa: Default::default(),
            sp_s: Default::default(),
            spr: Default::default(),
            spw: Default::default(),
            t64: Default::default(),
            av: Default::default(),
            rmv: Default::default(),
            rmnv: Default::default(),
            t32: Default::default(),
            r_x: Default::default(),
            sr_z: Constant::new(Bits::<SUMR_BITS>::from(0u64)),
            sr_hi: Constant::new(Bits::<SUMR_BITS>::from(mask(SUMR_BITS as u32) & !mask(32))),
            sr_sign: Constant::new(Bits::<SUMR_BITS>::from(1u64 << (SUMR_BITS - 1))),
            abs: Default::default(),
            ldm: Default::default(),
            z64: c64(0),
            one64: c64(1),
            z32: c32(0),
            one32: c32(1),
            pmask: c32(pp - 1),
            pp: c32(pp),
            p2: cc(2 * pp),
            ilast: ci(pp - 1),
            iz: ci(0),
            ione: ci(1),
            cz: cc(0),
            cone: cc(1),
            ew_mask: c32(mask(ew)),
            ew_sign: c32(sign(ew)),
            ew_fill: c64(!mask(ew)),
            skmask: c32(mask(2 * p.window_log2 - 1)),
            tmask: c32(2 * pp - 1),
            emax32: c32(em),
            emin32: c32(neg(em) & mask(ew)),
            am_mask: c64(mask(p.fine_bits + 2)),
            am_sign: c64(sign(p.fine_bits + 2)),
            pw_mask: c64(mask(p.pos_width())),
            pw_sign: c64(sign(p.pos_width())),
            sw_mask: c64(mask(p.sum_p_width())),
            sw_sign: c64(sign(p.sum_p_width())),
            sign63: c64(1 << 63),
            s32: c32(u64::from(s)),
            fmask: c32(mask(s)),
            s_last: cc(u64::from(s - 1)),
            tf: c64(u64::from(TABLE_FRAC)),
            st: c64(u64::from(s + TABLE_FRAC)),
            st_half: c64(1 << (s + TABLE_FRAC - 1)),
            w64: c64(u64::from(p.window_log2)),
            n_last: c32(p.window() - 1),
            nmask: c32(mask(p.window_log2 + 1)),
            k5: c64(5),
            k63: c64(63),
            k32: c64(32),
            dline: c64(p.line_divisor()),
            lb_lead: c64(u64::from(kb - 6)),
            lb_up: c64(u64::from(64 - (kb - 6))),
            lb_last: cc(u64::from(kb - 1)),
            rem_mask: c64(mask(2 * p.window_log2 + 2)),
            rem_sgn: c64(1 << (2 * p.window_log2 + 1)),
            ndline: c64(neg(p.line_divisor())),
            quo_mask: c64(mask(kb.max(kr))),
            dsr_mask: c64(mask(2 * p.window_log2)),
            op_hi: c64(mask(63) & !(p.one_period() as u64 - 1)),
            op_lo: c64(p.one_period() as u64 - 1),
            bf: c64(u64::from(bfr)),
            bf_mask: c64(mask(bfr)),
            bf_fill: c64(fill(bfr)),
            mul_last: cc(u64::from(2 * p.window_log2 - 1)),
            h_pos: c64(p.big_limit() as u64),
            h2_hi: c64(!(2 * p.big_limit() as u64 - 1)),
            lr_lead: c64(u64::from(kr + bfr - 1)),
            lr_up: c64(u64::from(64 - (kr + bfr - 1))),
            lr_last: cc(u64::from(kr - 1)),
            q_over: c64(2 * p.residual_max() as u64 + 1),
            lim32: c32(p.residual_max() as u64),
            nlim32: c32(neg(p.residual_max() as u64) & mask(32)),
            lm_lead: c64(u64::from(kr - 1)),
            lm_up: c64(u64::from(64 - (kr - 1))),
            g_half: c32(1 << (g - 1)),
            stepc: c32(p.step as u64),
            clip_at: c32((((p.step + 1) << g) - (1 << (g - 1))) as u64),
            g32: c32(u64::from(g)),
            sign31: c32(1 << 31),
            hi32: c64(0xffff_ffff_0000_0000),
        }
    }
}

impl Logic for HarmonicLearner {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clk, romq, dl, dlv, dls, dla, mh, cj, cnt, cwa, dn, dz, idx, active, pend, ld_i,
            ld_v, got, m_s, ps, prev, pos, ci, dd, fsh, acc, c, sbin, k, neg, mag, rem, dvd, quo,
            dsr, b, moving, nn, nsh, sksh, spv, ahs, als, bhs, bls, big, zneg, ovf, rneg, qov, r,
            sum_r, nbins, mean, ucur, unz, ux, uneg, cpos, cneg, uax, udm, unw, uroom, usat, twr,
            twa, twd, clr, klast, n1, sk1, mpos, mneg, srn, uxn, idx1, mvz, psa, bw1, bw2, nb0,
            dstep, ndsr, ldr, ldd
        );
        self.state.clock.next = self.clk.val();
        self.state.d.next = self.state.q.val();
        self.tab.clock.next = self.clk.val();
        self.rn.clock.next = self.clk.val();
        self.rsk.clock.next = self.clk.val();
        self.rsp.clock.next = self.clk.val();
        self.rsph.clock.next = self.clk.val();
        // Defaults: no writes, reads at 0.
        self.we.next = false;
        self.wa.next = self.z32.val();
        self.wd.next = self.z32.val();
        self.traddr.next = self.z32.val();
        self.bin_n.next = self.z32.val();
        self.bra.next = self.iz.val();
        self.bwa.next = bit_cast::<LEARN_ADDR_BITS, 32>(self.z32.val());
        self.rn.write_data.next = self.z32.val();
        self.rsk.write_data.next = self.z32.val();
        self.spw.next = self.z64.val();
        self.rn.write_enable.next = false;
        self.rsk.write_enable.next = false;
        self.rsp.write_enable.next = false;
        // Sign-extended reads of the table and of sp_i.
        // Reads keep the bits a word can hold, so that synthesis drops the RAMs' other
        // columns (fewer cells around each read address: the read paths).
        self.trd.next = self.tab.read_data.val() & self.ew_mask.val();
        self.tab_s.next = bit_cast::<64, 32>(self.trd.val());
        if (self.trd.val() & self.ew_sign.val()).any() {
            self.tab_s.next = bit_cast::<64, 32>(self.trd.val()) | self.ew_fill.val();
        }
        self.rn_m.next = self.rn.read_data.val() & self.nmask.val();
        self.rsk_m.next = self.rsk.read_data.val() & self.skmask.val();
        self.spr.next = (bit_cast::<64, 32>(self.rsph.read_data.val()) << self.k32.val())
            | bit_cast::<64, 32>(self.rsp.read_data.val());
        self.sp_s.next = self.spr.val() & self.sw_mask.val();
        if (self.spr.val() & self.sw_sign.val()).any() {
            self.sp_s.next = self.spr.val() | !self.sw_mask.val();
        }
        // The sample's segment and the banks' offsets.
        self.seg_i.next = (self.m_s.q.val() >> self.s32.val()) & self.pmask.val();
        self.seg_j.next = (self.seg_i.val() + self.one32.val()) & self.pmask.val();
        self.seg_n.next = (self.m_s.q.val() >> self.s32.val()) & self.pmask.val();
        if self.accept.val() {
            self.seg_n.next = (self.angle.val() >> self.s32.val()) & self.pmask.val();
        }
        self.off_a.next = self.z32.val();
        self.off_o.next = self.pp.val();
        if self.active.q.val() {
            self.off_a.next = self.pp.val();
            self.off_o.next = self.z32.val();
        }
        // The load request, held while one is pending: the entry width's value, saturated.
        self.ldm.next = self.ld_data.val() & self.ew_mask.val();
        if self.ld.val() & !self.pend.q.val() {
            self.ld_i.d.next = self.ld_addr.val() & self.pmask.val();
            self.ld_v.d.next = self.ldm.val();
            if (self.ldm.val() & self.ew_sign.val()).any() {
                if self.ldm.val() < self.emin32.val() {
                    self.ld_v.d.next = self.emin32.val();
                }
            } else if self.ldm.val() > self.emax32.val() {
                self.ld_v.d.next = self.emax32.val();
            }
        }
        // Every strobe moves pos by the angle's change; one Collect takes at k = 0 starts
        // the window's.
        self.accept.next = self.strobe.val()
            & ((self.state.q.val() == LearnState::Wait)
                | (self.state.q.val() == LearnState::LoadA)
                | (self.state.q.val() == LearnState::LoadB));
        self.delta.next = (bit_cast::<64, 32>(self.angle.val())
            - bit_cast::<64, 32>(self.prev.q.val()))
            & self.am_mask.val();
        if (self.delta.val() & self.am_sign.val()).any() {
            self.delta.next = self.delta.val() | !self.am_mask.val();
        }
        self.psum.next = self.pos.q.val() + self.dl.q.val();
        self.pnew.next = self.psum.val() & self.pw_mask.val();
        if (self.psum.val() & self.pw_sign.val()).any() {
            self.pnew.next = self.psum.val() | !self.pw_mask.val();
        }
        if self.dls.q.val() {
            self.pnew.next = self.z64.val();
        }
        if self.dlv.q.val() {
            self.pos.d.next = self.pnew.val();
        }
        if self.dla.q.val() {
            self.ps.d.next = self.pnew.val();
        }
        self.dl.d.next = self.delta.val();
        self.dlv.d.next = self.strobe.val();
        self.dls.d.next =
            self.accept.val() & ((self.k.q.val() & self.nmask.val()) == self.z32.val());
        self.dla.d.next = self.accept.val();
        if self.strobe.val() {
            self.prev.d.next = self.angle.val();
        }
        if self.accept.val() {
            self.m_s.d.next = self.angle.val();
        }
        // The start table's entry for Clear (cnt mod P), registered.
        self.cidx.next = bit_cast::<32, CNT_BITS>(self.cnt.q.val()) & self.pmask.val();
        self.tx.next = self.z32.val();
        for i in 0..self.seg.len() {
            if self.cidx.val() == self.seg[i].val() {
                self.tx.next = self.rom[i].val();
            }
        }
        self.romq.d.next = self.tx.val() ^ (self.cidx.val() & self.rom_x.val());
        // The divider's step (LineDiv, ResDiv, MeanDiv).
        self.dt.next =
            (self.rem.q.val() << self.one64.val()) | (self.dvd.q.val() >> self.k63.val());
        self.t64.next = self.z64.val();
        self.t32.next = self.z32.val();
        self.r_x.next = bit_cast::<SUMR_BITS, 32>(self.r.q.val());
        if (self.r.q.val() & self.sign31.val()).any() {
            self.r_x.next = bit_cast::<SUMR_BITS, 32>(self.r.q.val()) | self.sr_hi.val();
        }
        self.abs.next = self.z64.val();
        // Free-running registers and two-clock sums ([`SplitAdd`], [`SplitAcc`]): each one
        // carry chain or one select from registers that hold still until the state that
        // reads the result (the module doc gives the clocks).
        self.klast.d.next = (self.k.q.val() & self.nmask.val()) == self.n_last.val();
        self.nb0.d.next = (self.nbins.q.val() & self.nmask.val()) == self.z32.val();
        self.idx1.d.next = self.idx.q.val() + self.ione.val();
        // |r_i - r| clips: UpdStep takes cpos or cneg by r_i - r's sign (uneg), the one
        // whose operand is |r_i - r|.
        self.cpos.d.next = self.ux.q.val() >= self.clip_at.val();
        self.cneg.d.next = self.uxn.q.val() >= self.clip_at.val();
        // The sample's q = pos 2^T - c; the bin's new sp_i.
        self.q.clock.next = self.clk.val();
        self.q.a.next = self.ps.q.val() << self.tf.val();
        self.q.b.next = self.c.q.val();
        self.sp1.clock.next = self.clk.val();
        self.sp1.a.next = self.spv.q.val();
        self.sp1.b.next = self.q.s.val();
        // Sp += q in Acc; PS += Sp the clock after Sum; both cleared at Apply.
        self.sum_p.clock.next = self.clk.val();
        self.sum_p.add.next = self.state.q.val() == LearnState::Acc;
        self.sum_p.x.next = self.q.s.val();
        self.sum_p.clear.next = (self.state.q.val() == LearnState::Apply) | self.rst.val();
        self.sum_ps.clock.next = self.clk.val();
        self.sum_ps.add.next = self.psa.q.val();
        self.sum_ps.x.next = self.sum_p.s.val();
        self.sum_ps.clear.next = (self.state.q.val() == LearnState::Apply) | self.rst.val();
        // (N + 1) Sp; U = un1 - 2 PS and -U; |U|.
        self.un1.clock.next = self.clk.val();
        self.un1.a.next = self.sum_p.s.val() << self.w64.val();
        self.un1.b.next = self.sum_p.s.val();
        self.unum.clock.next = self.clk.val();
        self.unum.a.next = self.un1.s.val();
        self.unum.b.next = self.sum_ps.s.val() << self.one64.val();
        self.unn.clock.next = self.clk.val();
        self.unn.a.next = self.sum_ps.s.val() << self.one64.val();
        self.unn.b.next = self.un1.s.val();
        // round(quo / 2) = (quo + 1) >> 1 and its negation, (-quo) >> 1 (arithmetic).
        self.rm.clock.next = self.clk.val();
        self.rm.a.next = self.quo.q.val();
        self.rm.b.next = self.one64.val();
        self.rmn.clock.next = self.clk.val();
        self.rmn.a.next = self.z64.val();
        self.rmn.b.next = self.quo.q.val();
        self.rmv.next = self.rm.s.val() >> self.one64.val();
        self.rmnv.next =
            (self.rmn.s.val() >> self.one64.val()) | (self.rmn.s.val() & self.sign63.val());
        // quo >= 2 lim + 1 = 2^Kr - 1: its low Kr bits all ones, or a bit above them (tests
        // of bits, no compare's chain: the path quo -> qov).
        self.qov.d.next = ((self.quo.q.val() & self.q_over.val()) == self.q_over.val())
            | (self.quo.q.val() & !self.q_over.val()).any();
        // a = (Sp 2^5 + b - b 2^w) >> 1 (arithmetic); b's one-period compares.
        self.asp.clock.next = self.clk.val();
        self.asp.a.next = self.sum_p.s.val() << self.k5.val();
        self.asp.b.next = self.b.q.val();
        self.a.clock.next = self.clk.val();
        self.a.a.next = self.asp.s.val();
        self.a.b.next = self.b.q.val() << self.w64.val();
        self.av.next = (self.a.s.val() >> self.one64.val()) | (self.a.s.val() & self.sign63.val());
        // b >= 2^k (b >= 0) and b <= -2^k (b < 0) for the one period 2^k: tests of b's bits
        // k..62 and k-1..0, no compare's chain (b -> mneg).
        self.mpos.d.next = (self.b.q.val() & self.op_hi.val()).any();
        self.mneg.d.next = ((self.b.q.val() & self.op_hi.val()) != self.op_hi.val())
            | !(self.b.q.val() & self.op_lo.val()).any();
        // The four products, a multiplier bit a clock in ResMul, cleared in ResLatch. The
        // add flags are (state = ResMul) & the multiplier's bit 0, registered a clock
        // ahead: ResLatch loads n_i and sk_i, ResMul shifts them right until its last clock.
        self.fpa.clock.next = self.clk.val();
        self.fla.clock.next = self.clk.val();
        self.fpb.clock.next = self.clk.val();
        self.flb.clock.next = self.clk.val();
        self.fn_n.next = ((self.state.q.val() == LearnState::ResLatch)
            & self.rn_m.val().get_bit(0))
            | ((self.state.q.val() == LearnState::ResMul)
                & !self.dz.q.val()
                & self.nsh.q.val().get_bit(1));
        self.fn_sk.next = ((self.state.q.val() == LearnState::ResLatch)
            & self.rsk_m.val().get_bit(0))
            | ((self.state.q.val() == LearnState::ResMul)
                & !self.dz.q.val()
                & self.sksh.q.val().get_bit(1));
        self.fpa.d.next = self.fn_n.val() & !self.rst.val();
        self.fla.d.next = self.fn_n.val() & !self.rst.val();
        self.fpb.d.next = self.fn_sk.val() & !self.rst.val();
        self.flb.d.next = self.fn_sk.val() & !self.rst.val();
        self.pa.clock.next = self.clk.val();
        self.pa.add.next = self.fpa.q.val();
        self.pa.x.next = self.ahs.q.val();
        self.pa.clear.next = self.state.q.val() == LearnState::ResLatch;
        self.la.clock.next = self.clk.val();
        self.la.add.next = self.fla.q.val();
        self.la.x.next = self.als.q.val();
        self.la.clear.next = self.state.q.val() == LearnState::ResLatch;
        self.pb.clock.next = self.clk.val();
        self.pb.add.next = self.fpb.q.val();
        self.pb.x.next = self.bhs.q.val();
        self.pb.clear.next = self.state.q.val() == LearnState::ResLatch;
        self.lb.clock.next = self.clk.val();
        self.lb.add.next = self.flb.q.val();
        self.lb.x.next = self.bls.q.val();
        self.lb.clear.next = self.state.q.val() == LearnState::ResLatch;
        // Z1 = sp_i - a_h n_i - b_h sk_i, Z2, x = Z1 2^B - Z2 and -x (|x| < 2^63 unless
        // Z1 >= H or Z1 < -H, which saturates r_i whatever x is: Z1 + H outside [0, 2H)).
        self.z0.clock.next = self.clk.val();
        self.z0.a.next = self.spv.q.val();
        self.z0.b.next = self.pa.s.val();
        self.z1.clock.next = self.clk.val();
        self.z1.a.next = self.z0.s.val();
        self.z1.b.next = self.pb.s.val();
        self.z2.clock.next = self.clk.val();
        self.z2.a.next = self.la.s.val();
        self.z2.b.next = self.lb.s.val();
        self.xres.clock.next = self.clk.val();
        self.xres.a.next = self.z1.s.val() << self.bf.val();
        self.xres.b.next = self.z2.s.val();
        self.xng.clock.next = self.clk.val();
        self.xng.a.next = self.z2.s.val();
        self.xng.b.next = self.z1.s.val() << self.bf.val();
        self.zh.clock.next = self.clk.val();
        self.zh.a.next = self.z1.s.val();
        self.zh.b.next = self.h_pos.val();
        self.big.d.next = (self.zh.s.val() & self.h2_hi.val()).any();
        self.zneg.d.next = (self.z1.s.val() & self.sign63.val()).any();
        // The bin's new sums into its RAMs two clocks after Sum (sp1 settled).
        self.psa.d.next = false;
        self.bw1.d.next = false;
        self.bw2.d.next = self.bw1.q.val();
        if self.bw2.q.val() {
            self.bwa.next = bit_cast::<LEARN_ADDR_BITS, 32>(self.sbin.q.val());
            self.rn.write_enable.next = true;
            self.rsk.write_enable.next = true;
            self.rsp.write_enable.next = true;
            self.rn.write_data.next = self.n1.q.val();
            self.rsk.write_data.next = self.sk1.q.val();
            self.spw.next = self.sp1.s.val();
        }
        self.cwa.d.next = self.cnt.q.val();
        // The loops' count runs down in every state; the state before a loop loads it.
        self.dn.d.next = self.dn.q.val() - self.cone.val();
        self.dz.d.next = self.dn.q.val() == self.cone.val();
        match self.state.q.val() {
            LearnState::Clear => {
                if self.cnt.q.val().any() {
                    self.we.next = true;
                    self.wa.next = bit_cast::<32, CNT_BITS>(self.cwa.q.val());
                    self.wd.next = self.romq.q.val();
                }
                self.bwa.next = bit_cast::<LEARN_ADDR_BITS, 32>(self.cidx.val());
                self.rn.write_enable.next = true;
                self.rsk.write_enable.next = true;
                self.rsp.write_enable.next = true;
                self.cnt.d.next = self.cnt.q.val() + self.cone.val();
                if self.cnt.q.val() == self.p2.val() {
                    self.cnt.d.next = self.cz.val();
                    self.state.d.next = LearnState::Wait;
                }
            }
            LearnState::Wait => {
                // c_i's address a clock ahead (the table's read takes two).
                self.traddr.next = self.seg_n.val();
                if self.strobe.val() {
                    self.state.d.next = LearnState::ReadI;
                } else if self.pend.q.val() {
                    self.state.d.next = LearnState::LoadA;
                }
            }
            LearnState::LoadA => {
                // The active bank first: a sample's c_i read from LoadB on sees it.
                self.we.next = true;
                self.wa.next = self.off_a.val() | self.ld_i.q.val();
                self.wd.next = self.ld_v.q.val();
                if self.strobe.val() {
                    self.got.d.next = true;
                }
                self.state.d.next = LearnState::LoadB;
            }
            LearnState::LoadB => {
                self.traddr.next = self.seg_n.val();
                self.we.next = true;
                self.wa.next = self.off_o.val() | self.ld_i.q.val();
                self.wd.next = self.ld_v.q.val();
                self.pend.d.next = false;
                self.got.d.next = false;
                if self.got.q.val() | self.strobe.val() {
                    self.state.d.next = LearnState::ReadI;
                } else {
                    self.state.d.next = LearnState::Wait;
                }
            }
            LearnState::ReadI => {
                self.traddr.next = self.seg_j.val();
                self.state.d.next = LearnState::ReadJ;
            }
            LearnState::ReadJ => {
                self.ci.d.next = self.tab_s.val();
                self.state.d.next = LearnState::LatJ;
            }
            LearnState::LatJ => {
                self.cj.d.next = self.tab_s.val();
                self.state.d.next = LearnState::Diff;
            }
            LearnState::Diff => {
                // D = c_(i+1) - c_i in 32 bits (|D| <= 2^(F-3+T) <= 2^25).
                self.dd.d.next =
                    bit_cast::<32, 64>(self.cj.q.val()) - bit_cast::<32, 64>(self.ci.q.val());
                self.mh.d.next =
                    (bit_cast::<64, 32>(self.m_s.q.val()) << self.tf.val()) + self.st_half.val();
                self.fsh.d.next = self.m_s.q.val() & self.fmask.val();
                self.acc.d.next = self.z32.val();
                self.dn.d.next = self.s_last.val();
                self.dz.d.next = self.s_last.val() == self.cz.val();
                self.state.d.next = LearnState::Mult;
            }
            LearnState::Mult => {
                // acc = floor(D (f mod 2^j) / 2^j): (acc + f_j D) >> 1, arithmetic, f's bits
                // from the LSB (exact: an integer's floor halving ignores a fraction below
                // one), in 32 bits (|acc| <= |D|).
                self.t32.next = self.acc.q.val();
                if self.fsh.q.val().get_bit(0) {
                    self.t32.next = self.acc.q.val() + self.dd.q.val();
                }
                self.acc.d.next =
                    (self.t32.val() >> self.one32.val()) | (self.t32.val() & self.sign31.val());
                self.fsh.d.next = self.fsh.q.val() >> self.one32.val();
                if self.dz.q.val() {
                    self.state.d.next = LearnState::Corr;
                }
            }
            LearnState::Corr => {
                // c = (c_i 2^s + D f) >> s = c_i + floor(D f / 2^s), in 32 bits.
                self.t32.next = bit_cast::<32, 64>(self.ci.q.val()) + self.acc.q.val();
                self.c.d.next = bit_cast::<64, 32>(self.t32.val());
                if (self.t32.val() & self.sign31.val()).any() {
                    self.c.d.next = bit_cast::<64, 32>(self.t32.val()) | self.hi32.val();
                }
                self.state.d.next = LearnState::Bin;
            }
            LearnState::Bin => {
                // The bin: round((m 2^T - c) / 2^(s+T)) mod P (q = pos 2^T - c settles).
                self.t64.next = self.mh.q.val() - self.c.q.val();
                self.bin_n.next =
                    bit_cast::<32, 64>(self.t64.val() >> self.st.val()) & self.pmask.val();
                self.sbin.d.next = self.bin_n.val();
                self.state.d.next = LearnState::ReadBin;
            }
            LearnState::ReadBin => {
                // The bin's address from its register (the bins' RAMs read over two clocks:
                // the words come out in Acc).
                self.bra.next = bit_cast::<LEARN_ADDR_BITS, 32>(self.sbin.q.val());
                self.state.d.next = LearnState::LatBin;
            }
            LearnState::LatBin => {
                self.state.d.next = LearnState::Acc;
            }
            LearnState::Acc => {
                // The bin's words latched (Sp += q, sum_p).
                self.nn.d.next = self.rn_m.val();
                self.sksh.d.next = self.rsk_m.val();
                self.spv.d.next = self.sp_s.val();
                self.state.d.next = LearnState::Sum;
            }
            LearnState::Sum => {
                // n_i + 1 and sk_i + k (k before its step); sp1 = sp_i + q settles. PS takes
                // Sp the next clock (psa), the RAMs the new sums the clock after (bw2).
                self.n1.d.next = self.nn.q.val() + self.one32.val();
                self.sk1.d.next = self.sksh.q.val() + self.k.q.val();
                self.psa.d.next = true;
                self.bw1.d.next = true;
                self.k.d.next = self.k.q.val() + self.one32.val();
                if self.klast.q.val() {
                    self.state.d.next = LearnState::LineN1;
                } else {
                    self.state.d.next = LearnState::Wait;
                }
            }
            LearnState::LineN1 => {
                // Sp has settled (its high half in Sum); PS takes it (psa).
                self.state.d.next = LearnState::LineU;
            }
            LearnState::LineU => {
                // un1 = (N + 1) Sp settles here and in LineW1, PS in LineW1.
                self.state.d.next = LearnState::LineW1;
            }
            LearnState::LineW1 => {
                self.state.d.next = LearnState::LineW2;
            }
            LearnState::LineW2 => {
                // U = un1 - 2 PS and -U settle here and in LineW3.
                self.state.d.next = LearnState::LineW3;
            }
            LearnState::LineW3 => {
                // |U| split into the remainder's and the dividend's loads; U's sign.
                self.abs.next = self.unum.s.val();
                if (self.unum.s.val() & self.sign63.val()).any() {
                    self.abs.next = self.unn.s.val();
                }
                self.neg.d.next = (self.unum.s.val() & self.sign63.val()).any();
                self.ldr.d.next = (self.abs.val() >> self.lb_lead.val()) & self.rem_mask.val();
                self.ldd.d.next = self.abs.val() << self.lb_up.val();
                self.state.d.next = LearnState::LineLoad;
            }
            LearnState::LineLoad => {
                self.dsr.d.next = self.dline.val();
                self.ndsr.d.next = self.ndline.val();
                self.dstep.d.next = true;
                self.dn.d.next = self.lb_last.val();
                self.dz.d.next = self.lb_last.val() == self.cz.val();
                self.state.d.next = LearnState::LineDiv;
            }
            LearnState::LineDiv => {
                if self.dz.q.val() {
                    self.dstep.d.next = false;
                    self.state.d.next = LearnState::LineRnd;
                }
            }
            LearnState::LineRnd => {
                // +-round(quo / 2) settle here and in LineRnd2.
                self.state.d.next = LearnState::LineRnd2;
            }
            LearnState::LineRnd2 => {
                self.state.d.next = LearnState::LineB;
            }
            LearnState::LineB => {
                self.b.d.next = self.rmv.val();
                if self.neg.q.val() {
                    self.b.d.next = self.rmnv.val();
                }
                self.state.d.next = LearnState::LineA1;
            }
            LearnState::LineA1 => {
                // Sp 2^5 + b settles here and in LineA2; b's one-period compares here.
                self.state.d.next = LearnState::LineA2;
            }
            LearnState::LineA2 => {
                // One period per window: |b| >= 2^(F+2+T+B-w).
                self.moving.d.next = self.mpos.q.val();
                if (self.b.q.val() & self.sign63.val()).any() {
                    self.moving.d.next = self.mneg.q.val();
                }
                self.state.d.next = LearnState::LineA3;
            }
            LearnState::LineA3 => {
                // a = (Sp 2^5 + b - b 2^w) >> 1 settles here and in ResRead.
                self.idx.d.next = self.iz.val();
                self.bra.next = self.iz.val();
                self.state.d.next = LearnState::ResRead;
            }
            LearnState::ResRead => {
                self.state.d.next = LearnState::ResLatch;
            }
            LearnState::ResLatch => {
                self.nn.d.next = self.rn_m.val();
                self.nsh.d.next = self.rn_m.val();
                self.sksh.d.next = self.rsk_m.val();
                self.spv.d.next = self.sp_s.val();
                // The products cleared (pa, pb, la, lb); a = a_h 2^B + a_l, b = b_h 2^B + b_l
                // (arithmetic >> B).
                self.ahs.d.next = self.av.val() >> self.bf.val();
                if (self.av.val() & self.sign63.val()).any() {
                    self.ahs.d.next = (self.av.val() >> self.bf.val()) | self.bf_fill.val();
                }
                self.bhs.d.next = self.b.q.val() >> self.bf.val();
                if (self.b.q.val() & self.sign63.val()).any() {
                    self.bhs.d.next = (self.b.q.val() >> self.bf.val()) | self.bf_fill.val();
                }
                self.als.d.next = self.av.val() & self.bf_mask.val();
                self.bls.d.next = self.b.q.val() & self.bf_mask.val();
                self.dn.d.next = self.mul_last.val();
                self.dz.d.next = self.mul_last.val() == self.cz.val();
                self.state.d.next = LearnState::ResMul;
            }
            LearnState::ResMul => {
                // pa += a_h 2^j, la += a_l 2^j when n_i's bit j is set; pb, lb with sk_i's
                // (the last clock adds nothing and lets the last add settle).
                self.nsh.d.next = self.nsh.q.val() >> self.one32.val();
                self.sksh.d.next = self.sksh.q.val() >> self.one32.val();
                self.ahs.d.next = self.ahs.q.val() << self.one64.val();
                self.als.d.next = self.als.q.val() << self.one64.val();
                self.bhs.d.next = self.bhs.q.val() << self.one64.val();
                self.bls.d.next = self.bls.q.val() << self.one64.val();
                if self.dz.q.val() {
                    self.state.d.next = LearnState::ResZa;
                }
            }
            LearnState::ResZa => {
                // n_i != 0, registered for ResWrite and ResSum (the path to sum r's enable);
                // sp_i - a_h n_i and Z2 settle here and in ResZb.
                self.unz.d.next = (self.nn.q.val() & self.nmask.val()) != self.z32.val();
                self.state.d.next = LearnState::ResZb;
            }
            LearnState::ResZb => {
                self.state.d.next = LearnState::ResX;
            }
            LearnState::ResX => {
                // Z1 = (sp_i - a_h n_i) - b_h sk_i settles here and in ResW1.
                self.state.d.next = LearnState::ResW1;
            }
            LearnState::ResW1 => {
                self.state.d.next = LearnState::ResW2;
            }
            LearnState::ResW2 => {
                // x, -x and Z1 + H settle here and in ResW3 (big a clock later).
                self.state.d.next = LearnState::ResW3;
            }
            LearnState::ResW3 => {
                self.state.d.next = LearnState::ResAbs;
            }
            LearnState::ResAbs => {
                self.neg.d.next = (self.xres.s.val() & self.sign63.val()).any();
                self.abs.next = self.xres.s.val();
                if (self.xres.s.val() & self.sign63.val()).any() {
                    self.abs.next = self.xng.s.val();
                }
                self.mag.d.next = self.abs.val();
                self.ldr.d.next = (self.abs.val() >> self.lr_lead.val()) & self.rem_mask.val();
                self.ldd.d.next = self.abs.val() << self.lr_up.val();
                self.state.d.next = LearnState::ResLoad;
            }
            LearnState::ResLoad => {
                self.ndsr.d.next =
                    self.z64.val() - (bit_cast::<64, 32>(self.nn.q.val()) & self.dsr_mask.val());
                self.dstep.d.next = true;
                self.ovf.d.next =
                    (self.mag.q.val() >> self.lr_lead.val()) >= bit_cast::<64, 32>(self.nn.q.val());
                self.dsr.d.next = bit_cast::<64, 32>(self.nn.q.val()) & self.dsr_mask.val();
                self.dn.d.next = self.lr_last.val();
                self.dz.d.next = self.lr_last.val() == self.cz.val();
                self.state.d.next = LearnState::ResDiv;
            }
            LearnState::ResDiv => {
                if self.dz.q.val() {
                    self.dstep.d.next = false;
                    self.state.d.next = LearnState::ResEnd;
                }
            }
            LearnState::ResEnd => {
                // +-round(quo / 2) settle here and in ResEnd2, qov here.
                self.rneg.d.next = self.neg.q.val();
                if self.big.q.val() {
                    self.rneg.d.next = self.zneg.q.val();
                }
                self.state.d.next = LearnState::ResEnd2;
            }
            LearnState::ResEnd2 => {
                self.state.d.next = LearnState::ResWrite;
            }
            LearnState::ResWrite => {
                // r_i in 32 bits (|r_i| < 2^(F+T-2) <= 2^26), or +-lim when it saturates.
                self.t32.next = bit_cast::<32, 64>(self.rmv.val());
                if self.rneg.q.val() {
                    self.t32.next = bit_cast::<32, 64>(self.rmnv.val());
                }
                if self.big.q.val() | self.ovf.q.val() | self.qov.q.val() {
                    self.t32.next = self.lim32.val();
                    if self.rneg.q.val() {
                        self.t32.next = self.nlim32.val();
                    }
                }
                self.r.d.next = self.t32.val();
                self.state.d.next = LearnState::ResSum;
            }
            LearnState::ResSum => {
                // r_i sign-extended into sp_i's word (written from its register: the path
                // from rm through r_i's negation ends at r).
                self.bwa.next = self.idx.q.val();
                self.spw.next = bit_cast::<64, 32>(self.r.q.val());
                if (self.r.q.val() & self.sign31.val()).any() {
                    self.spw.next = bit_cast::<64, 32>(self.r.q.val()) | self.hi32.val();
                }
                self.rsp.write_enable.next = self.unz.q.val();
                // The next bin's address a clock ahead.
                self.bra.next = self.idx1.q.val();
                if self.unz.q.val() {
                    self.sum_r.d.next = self.sum_r.q.val() + self.r_x.val();
                    self.srn.d.next = self.srn.q.val() - self.r_x.val();
                    self.nbins.d.next = self.nbins.q.val() + self.one32.val();
                }
                self.idx.d.next = self.idx.q.val() + self.ione.val();
                if self.idx.q.val() == self.ilast.val() {
                    self.idx.d.next = self.iz.val();
                    self.state.d.next = LearnState::MeanAbs;
                } else {
                    self.state.d.next = LearnState::ResRead;
                }
            }
            LearnState::MeanAbs => {
                self.neg.d.next = (self.sum_r.q.val() & self.sr_sign.val()).any();
                self.abs.next = bit_cast::<64, SUMR_BITS>(self.sum_r.q.val());
                if (self.sum_r.q.val() & self.sr_sign.val()).any() {
                    self.abs.next = bit_cast::<64, SUMR_BITS>(self.srn.q.val());
                }
                self.ldr.d.next = (self.abs.val() >> self.lm_lead.val()) & self.rem_mask.val();
                self.ldd.d.next = self.abs.val() << self.lm_up.val();
                self.state.d.next = LearnState::MeanLoad;
            }
            LearnState::MeanLoad => {
                self.ndsr.d.next =
                    self.z64.val() - (bit_cast::<64, 32>(self.nbins.q.val()) & self.dsr_mask.val());
                self.dstep.d.next = true;
                self.dsr.d.next = bit_cast::<64, 32>(self.nbins.q.val()) & self.dsr_mask.val();
                self.dn.d.next = self.lr_last.val();
                self.dz.d.next = self.lr_last.val() == self.cz.val();
                self.state.d.next = LearnState::MeanDiv;
            }
            LearnState::MeanDiv => {
                if self.dz.q.val() {
                    self.dstep.d.next = false;
                    self.state.d.next = LearnState::MeanEnd;
                }
            }
            LearnState::MeanEnd => {
                // +-round(quo / 2) settle here and in MeanEnd2.
                self.state.d.next = LearnState::MeanEnd2;
            }
            LearnState::MeanEnd2 => {
                self.state.d.next = LearnState::MeanSign;
            }
            LearnState::MeanSign => {
                self.mean.d.next = bit_cast::<32, 64>(self.rmv.val());
                if self.neg.q.val() {
                    self.mean.d.next = bit_cast::<32, 64>(self.rmnv.val());
                }
                if self.nb0.q.val() {
                    self.mean.d.next = self.z32.val();
                }
                self.idx.d.next = self.iz.val();
                self.bra.next = self.iz.val();
                self.state.d.next = LearnState::UpdRead;
            }
            LearnState::UpdRead => {
                self.traddr.next = bit_cast::<32, LEARN_ADDR_BITS>(self.idx.q.val());
                self.state.d.next = LearnState::UpdLat;
            }
            LearnState::UpdLat => {
                self.nn.d.next = self.rn_m.val();
                self.spv.d.next = self.sp_s.val();
                self.state.d.next = LearnState::UpdDiff;
            }
            LearnState::UpdDiff => {
                // The entry, two clocks after its address (the table's read).
                self.ucur.d.next = bit_cast::<32, 64>(self.tab_s.val());
                self.ux.d.next = bit_cast::<32, 64>(self.spv.q.val()) - self.mean.q.val();
                self.uxn.d.next = self.mean.q.val() - bit_cast::<32, 64>(self.spv.q.val());
                // n_i, registered a clock before its test (the RAM's read path).
                self.unz.d.next = (self.nn.q.val() & self.nmask.val()) != self.z32.val();
                self.state.d.next = LearnState::UpdAbs;
            }
            LearnState::UpdAbs => {
                self.uneg.d.next = (self.ux.q.val() & self.sign31.val()).any();
                self.uax.d.next = self.ux.q.val();
                self.uroom.d.next = self.emax32.val() - self.ucur.q.val();
                if (self.ux.q.val() & self.sign31.val()).any() {
                    self.uroom.d.next = self.ucur.q.val() + self.emax32.val();
                    self.uax.d.next = self.uxn.q.val();
                }
                self.state.d.next = LearnState::UpdStep;
            }
            LearnState::UpdStep => {
                // 2^-g |r_i - r| rounded half up, clipped at the step.
                self.udm.d.next = (self.uax.q.val() + self.g_half.val()) >> self.g32.val();
                if (self.uneg.q.val() & self.cneg.q.val())
                    | (!self.uneg.q.val() & self.cpos.q.val())
                {
                    self.udm.d.next = self.stepc.val();
                }
                self.state.d.next = LearnState::UpdAdd;
            }
            LearnState::UpdAdd => {
                self.unw.d.next = self.ucur.q.val() + self.udm.q.val();
                // In the entry width: udm <= step < 2^(E-1), 0 <= room <= 2 entry_max < 2^E.
                self.usat.d.next = (self.udm.q.val() & self.ew_mask.val())
                    > (self.uroom.q.val() & self.ew_mask.val());
                if self.uneg.q.val() {
                    self.unw.d.next = self.ucur.q.val() - self.udm.q.val();
                }
                self.mvz.d.next = self.moving.q.val() & self.unz.q.val();
                self.state.d.next = LearnState::UpdWrite;
            }
            LearnState::UpdWrite => {
                // The new entry saturated at +-2^(F-4) LSB (the limit its step passed), or
                // the old one; in the entry width.
                self.wd.next = self.unw.q.val() & self.ew_mask.val();
                if self.usat.q.val() {
                    self.wd.next = self.emax32.val();
                    if self.uneg.q.val() {
                        self.wd.next = self.emin32.val();
                    }
                }
                if !(self.update.val() & self.mvz.q.val()) {
                    self.wd.next = self.ucur.q.val() & self.ew_mask.val();
                }
                self.we.next = true;
                self.wa.next = self.off_o.val() | bit_cast::<32, LEARN_ADDR_BITS>(self.idx.q.val());
                self.bwa.next = self.idx.q.val();
                self.rn.write_enable.next = true;
                self.rsk.write_enable.next = true;
                self.rsp.write_enable.next = true;
                // The next bin's address a clock ahead.
                self.bra.next = self.idx1.q.val();
                self.idx.d.next = self.idx1.q.val();
                if self.idx.q.val() == self.ilast.val() {
                    self.idx.d.next = self.iz.val();
                    self.state.d.next = LearnState::Apply;
                } else {
                    self.state.d.next = LearnState::UpdRead;
                }
            }
            LearnState::Apply => {
                self.active.d.next = !self.active.q.val();
                self.k.d.next = self.z32.val();
                self.sum_r.d.next = self.sr_z.val();
                self.srn.d.next = self.sr_z.val();
                self.nbins.d.next = self.z32.val();
                self.state.d.next = LearnState::Wait;
            }
        }
        // The divider steps in its three states (dstep), non-restoring: r' = 2 r + bit -+ d
        // as r >= 0 or r < 0, the quotient bit r' >= 0 (the restoring division's bits: its
        // remainder is r, or r + d when r < 0); r in 2w + 2 bits, -d <= r < d.
        self.drp.next = (self.dt.val() + self.dsr.q.val()) & self.rem_mask.val();
        self.drm.next = (self.dt.val() + self.ndsr.q.val()) & self.rem_mask.val();
        self.rsm.next = self.z64.val();
        if (self.rem.q.val() & self.rem_sgn.val()).any() {
            self.rsm.next = !self.z64.val();
        }
        self.dr.next = (self.drp.val() & self.rsm.val()) | (self.drm.val() & !self.rsm.val());
        // A division's load (LineLoad, ResLoad, MeanLoad, flagged a state ahead): the
        // remainder, the dividend's bits, the quotient cleared.
        self.dload.clock.next = self.clk.val();
        self.dload.d.next = ((self.state.q.val() == LearnState::LineW3)
            | (self.state.q.val() == LearnState::ResAbs)
            | (self.state.q.val() == LearnState::MeanAbs))
            & !self.rst.val();
        if self.dload.q.val() {
            self.rem.d.next = self.ldr.q.val();
            self.dvd.d.next = self.ldd.q.val();
            self.quo.d.next = self.z64.val();
        }
        if self.dstep.q.val() {
            self.dvd.d.next = self.dvd.q.val() << self.one64.val();
            self.rem.d.next = self.dr.val();
            self.quo.d.next = (self.quo.q.val() << self.one64.val()) & self.quo_mask.val();
            if !(self.dr.val() & self.rem_sgn.val()).any() {
                self.quo.d.next = ((self.quo.q.val() << self.one64.val()) | self.one64.val())
                    & self.quo_mask.val();
            }
        }
        if self.ld.val() & !self.pend.q.val() {
            self.pend.d.next = true;
        }
        // The table's ports and the copy of its write on tw; bank b's entry i at word
        // b P + i, in p + 1 bits.
        self.tra.next = (self.traddr.val() | self.off_a.val()) & self.tmask.val();
        self.tab.read_address.next = bit_cast::<TAB_ADDR_BITS, 32>(self.tra.val());
        // The bins' RAMs' addresses in p bits (below P: Yosys drops the arrays a smaller
        // table leaves unused).
        self.rn.read_address.next = self.bra.val() & self.ilast.val();
        self.rsk.read_address.next = self.bra.val() & self.ilast.val();
        self.rsp.read_address.next = self.bra.val() & self.ilast.val();
        self.rsph.read_address.next = self.bra.val() & self.ilast.val();
        self.rsp.write_data.next = bit_cast::<32, 64>(self.spw.val());
        self.rsph.write_data.next = bit_cast::<32, 64>(self.spw.val() >> self.k32.val());
        self.rn.write_address.next = self.bwa.val() & self.ilast.val();
        self.rsk.write_address.next = self.bwa.val() & self.ilast.val();
        self.rsp.write_address.next = self.bwa.val() & self.ilast.val();
        self.rsph.write_address.next = self.bwa.val() & self.ilast.val();
        self.rsph.write_enable.next = self.rsp.write_enable.val();
        self.tab.write_address.next =
            bit_cast::<TAB_ADDR_BITS, 32>(self.wa.val() & self.tmask.val());
        self.tab.write_enable.next = self.we.val();
        self.tab.write_data.next = self.wd.val();
        // wa and wd are zero without a write.
        self.twr.d.next = self.we.val();
        self.twa.d.next = self.wa.val();
        self.twd.d.next = self.wd.val();
        if self.rst.val() {
            self.state.d.next = LearnState::Clear;
            self.cnt.d.next = self.cz.val();
            self.idx.d.next = self.iz.val();
            self.active.d.next = false;
            self.pend.d.next = false;
            self.got.d.next = false;
            self.prev.d.next = self.z32.val();
            self.pos.d.next = self.z64.val();
            self.dlv.d.next = false;
            self.dls.d.next = false;
            self.dla.d.next = false;
            self.k.d.next = self.z32.val();
            self.psa.d.next = false;
            self.bw1.d.next = false;
            self.bw2.d.next = false;
            self.dstep.d.next = false;
            self.sum_r.d.next = self.sr_z.val();
            self.srn.d.next = self.sr_z.val();
            self.nbins.d.next = self.z32.val();
            self.twr.d.next = false;
            self.twa.d.next = self.z32.val();
            self.twd.d.next = self.z32.val();
            self.tab.write_enable.next = false;
            self.rn.write_enable.next = false;
            self.rsk.write_enable.next = false;
            self.rsp.write_enable.next = false;
        }
        self.tw.next = self.twr.q.val();
        self.tw_addr.next = self.twa.q.val();
        self.tw_data.next = self.twd.q.val();
        self.bank.next = self.active.q.val();
        self.ld_busy.next = self.pend.q.val();
        self.clr.d.next = self.state.q.val() == LearnState::Clear;
        self.clearing.next = self.clr.q.val();
    }
}

impl crate::cosim::step::Clocked for HarmonicLearner {
    fn set_clock(&mut self, high: bool) {
        self.clk.next = Clock::from(high);
    }
}

impl crate::cosim::CosimBlock for HarmonicLearner {
    fn input_ports(&self) -> Vec<Port> {
        vec![
            Port::new("rst", 1),
            Port::new("strobe", 1),
            Port::new("angle", 32),
            Port::new("update", 1),
            Port::new("ld", 1),
            Port::new("ld_addr", 32),
            Port::new("ld_data", 32),
        ]
    }
    fn output_ports(&self) -> Vec<Port> {
        vec![
            Port::new("tw", 1),
            Port::new("tw_addr", 32),
            Port::new("tw_data", 32),
            Port::new("bank", 1),
            Port::new("ld_busy", 1),
            Port::new("clearing", 1),
        ]
    }
    fn apply(&mut self, r: &[u64]) {
        self.rst.next = r[0] != 0;
        self.strobe.next = r[1] != 0;
        self.angle.next = Bits::<32>::from(r[2]);
        self.update.next = r[3] != 0;
        self.ld.next = r[4] != 0;
        self.ld_addr.next = Bits::<32>::from(r[5]);
        self.ld_data.next = Bits::<32>::from(r[6]);
    }
    fn sample(&self) -> Vec<u64> {
        vec![
            self.tw.val() as u64,
            self.tw_addr.val().to_u64(),
            self.tw_data.val().to_u64(),
            self.bank.val() as u64,
            self.ld_busy.val() as u64,
            self.clearing.val() as u64,
        ]
    }
}
