//! rust-hdl description of the BiSS C control channel (`[biss] control = true`): the CDM
//! sampler, the control-frame state machine and the 128-byte register file. It is a
//! sub-block of [`super::hdl::BissSlave`], present only when the control channel is on
//! (a `Vec` of zero or one), so the slave without it exports the same Verilog as before.
//!
//! ```text
//!  BissSlave                                   BissControl
//!  frame's final pulse answered ── done ──> armed ─┐
//!  timeout over (SLO -> 1)  ────── expire ─────────┴─&─> stp (registered) ─┐
//!  filtered MA level ───────────── ma ──> !ma ──────────> b  (registered) ─┤ one CDM bit
//!                                                                         v
//!     zcnt (zero run, 0..14)   state, one-hot q_* (Idle, Cts, Id, Adr, Crc, R, W, Start,
//!     n (bit count, 0..11)     Read, Write, Stop, Next)  crc (CRC4)  addr (7)  sh (8)
//!     step actions for b = 1 and b = 0 (answer, next state, bad, n): registered from the
//!           state flags and decodes between steps, selected by b at the step
//!     regs: RegFile 128 x 8 in eight 16 x 8 banks, registered read at addr (one-hot bank
//!           select), registered again (rdq) and loaded into sh while a read waits for
//!           its first bit; written at P of a write
//!                                                                         │
//!  Start bit of the next frame: SLO <- cds <──────────────────────────────┘ (registered)
//! ```
//!
//! One CDM bit is taken per complete frame, in the clock after the timeout ends, and its
//! answer is ready long before the next frame's CDS slot (at least four MA edges later).
//! The CRC4 register takes the step's action one clock after the step (update with or
//! without feedback, shift, clear: four flip-flops set from the step's inputs and the
//! registered state decodes), so the state decode ends in those flip-flops and the CRC's
//! next value is one LUT of registers; the CRC is read only at a step, a frame later.
//! The step itself is a select: the state is one-hot (`q_*`), and everything a step does
//! that depends on more than a few flags (the answer, the next Idle, Start, Read, Write
//! and Stop flags, bad, the bit count's clear and count) is registered twice between
//! steps, once for each value of the CDM bit b, so that the step takes b ? x1 : x0, one
//! LUT on flip-flops. These are valid from the fifth clock after a step (they read the
//! CRC, one clock late, and the shift register's reload); the next step is a frame away.
//! The answers are the table of docs/biss_control.md; [`super::control_model`] is the same
//! table in plain Rust.
//!
//! Widths: zcnt, n and crc are 4 bits (at most 14, 11 and 0xf), addr 7 bits (the address
//! increment wraps 0x7f -> 0x00 as the protocol's 7-bit address does), sh and the register
//! data 8 bits. Every constant is sized to the word it meets.
use super::regs::{BissIdent, FIRST_READ_ONLY, POLY4};
use rust_hdl::prelude::*;
use std::collections::BTreeMap;

mod update;

/// Where the control channel is in a control frame (one step per CDM bit). The hardware
/// holds it one-hot, one flag per state (`q_idle` .. `q_next` of [`BissControl`]).
#[derive(Copy, Clone, PartialEq, Eq, Debug, LogicState)]
pub enum CtlState {
    /// Waiting for a start bit after at least 14 zeros.
    Idle,
    /// Next bit: CTS.
    Cts,
    /// Next bits: ID2..ID0.
    Id,
    /// Next bits: A6..A0.
    Adr,
    /// Next bits: the inverted CRC4.
    Crc,
    /// Next bit: R.
    Rb,
    /// Next bit: W.
    Wb,
    /// Next bit: the start bit of the data part.
    Start,
    /// The 12 bits of a read.
    Read,
    /// The 12 bits of a write.
    Write,
    /// Next bit: the stop bit.
    Stop,
    /// After the stop bit: start = next address, 0 = end.
    Next,
}

/// The BiSS C control channel with its register file.
#[derive(LogicBlock)]
pub struct BissControl {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high (the registers keep their contents).
    pub rst: Signal<In, Bit>,
    /// Filtered, synchronized MA level.
    pub ma: Signal<In, Bit>,
    /// The frame's final clock pulse has been answered (the frame is complete).
    pub done: Signal<In, Bit>,
    /// The timeout ends this clock (SLO returns high).
    pub expire: Signal<In, Bit>,
    /// The CDS bit for the next frame (registered).
    pub cds: Signal<Out, Bit>,
    /// With the register map (`user_map`; 0 and unused without): the map's byte that
    /// addresses 0x00..0x3F read and write, bank * 64 + address (bank = the byte at 0x40).
    /// Plain ports, not `Vec`s: rust-hdl names a port of a `Vec` element of a `Vec` wrongly.
    pub ext_addr: Signal<Out, Bits<32>>,
    /// One clock: a write of `ext_wdata` to the map's byte at `ext_addr`.
    pub ext_we: Signal<Out, Bit>,
    /// The byte written.
    pub ext_wdata: Signal<Out, Bits<8>>,
    /// One clock: a read begins at `ext_addr` (the map's POSITION snapshot).
    pub ext_snap: Signal<Out, Bit>,
    /// The map's byte at `ext_addr`, a few clocks behind the address.
    pub ext_rdata: Signal<In, Bits<8>>,
    /// The bank select's byte (written with 0x40; kept by the reset, as the file is).
    bank: Vec<DFF<Bits<32>>>,
    /// `ldq` a clock before: its rise is the snapshot pulse.
    snp: Vec<DFF<Bit>>,
    /// 0x40 (the user area's end and the bank select) at 7 bits, 0x3f and 6 at 32 bits.
    k40: Vec<Constant<Bits<7>>>,
    k3f: Vec<Constant<Bits<32>>>,
    k6: Vec<Constant<Bits<32>>>,
    regs: RegFile,
    armed: DFF<Bit>,
    stp: DFF<Bit>,
    bq: DFF<Bit>,
    /// The control-frame state (see [`CtlState`]), one-hot: one flag per state, Idle set
    /// at power-up and by the reset.
    q_idle: DFFWithInit<Bit>,
    q_cts: DFF<Bit>,
    q_id: DFF<Bit>,
    q_adr: DFF<Bit>,
    q_crc: DFF<Bit>,
    q_rb: DFF<Bit>,
    q_wb: DFF<Bit>,
    q_start: DFF<Bit>,
    q_read: DFF<Bit>,
    q_write: DFF<Bit>,
    q_stop: DFF<Bit>,
    q_next: DFF<Bit>,
    zcnt: DFF<Bits<4>>,
    n: DFF<Bits<4>>,
    crc: DFF<Bits<4>>,
    bad: DFF<Bit>,
    addr: DFF<Bits<7>>,
    rb: DFF<Bit>,
    wr: DFF<Bit>,
    sh: DFF<Bits<8>>,
    cds_r: DFF<Bit>,
    /// Registered decodes of the registers above (they change only in a step, and steps
    /// are a frame apart, so each decode is valid from the clock after a step on; this
    /// keeps carry chains and compares out of the step's logic): addr + 1, addr writable,
    /// addr + 1 writable, zero run at 13 or 14, at 14, n = 2, 3, 6, 11, n >= 8.
    nadr_r: DFF<Bits<7>>,
    awr: DFF<Bit>,
    nwr: DFF<Bit>,
    zend: DFF<Bit>,
    zfull: DFF<Bit>,
    n2: DFF<Bit>,
    n3: DFF<Bit>,
    n6: DFF<Bit>,
    n11: DFF<Bit>,
    nhi: DFF<Bit>,
    /// Registered decodes of the state for the CRC register (valid from the second clock
    /// after a step, as they read n, zcnt and the flags above): a step updates the CRC with
    /// the CDM bit or the data bit (Cts, Id, Adr, a write's data bits; `rdl`: a read's data
    /// bits, when b = 0), shifts it (Crc, a write's CRC bits; `rdh`: a read's CRC bits, when
    /// b = 0), clears it when b = 1 (`kclr`: Idle at 14 zeros, Start, Next with the next
    /// address allowed); `sread`: the data bit, not b, enters it (state Read).
    kupd: DFF<Bit>,
    kshf: DFF<Bit>,
    rdl: DFF<Bit>,
    rdh: DFF<Bit>,
    kclr: DFF<Bit>,
    sread: DFF<Bit>,
    /// The CRC register's action of the last step, applied one clock after it (nothing reads
    /// the CRC between steps, which are a frame apart): update with feedback `ufb`, update
    /// without it, shift, clear. Registered from the step's inputs, so the CRC register's
    /// next value is one LUT of flip-flops and the step's state decode ends in these four.
    uupd: DFF<Bit>,
    ufb: DFF<Bit>,
    ushf: DFF<Bit>,
    uclr: DFF<Bit>,
    /// What a step does, registered from the state flags and the decodes above (valid from
    /// the third clock after a step; steps are a frame apart), in two versions where it
    /// depends on the CDM bit: `..1` for b = 1, `..0` for b = 0. The step then selects with
    /// b, one LUT on flip-flops. The answer (`ans1`, `ans0`; a 0 at the zero run's end
    /// answers 0 whatever `ans0` says).
    ans1: DFF<Bit>,
    ans0: DFF<Bit>,
    /// The state flags' next values that depend on more than a few flags: Idle, Start,
    /// Read, Write, Stop (a 0 at the zero run's end goes to Idle whatever these say).
    idle1: DFF<Bit>,
    idle0: DFF<Bit>,
    start1: DFF<Bit>,
    start0: DFF<Bit>,
    read1: DFF<Bit>,
    read0: DFF<Bit>,
    write1: DFF<Bit>,
    write0: DFF<Bit>,
    stop1: DFF<Bit>,
    stop0: DFF<Bit>,
    /// `bad` after the step.
    bad1: DFF<Bit>,
    bad0: DFF<Bit>,
    /// The bit count after the step clears (`nclr..`) or counts up (`ninc..`).
    nclr1: DFF<Bit>,
    nclr0: DFF<Bit>,
    ninc1: DFF<Bit>,
    ninc0: DFF<Bit>,
    /// A read's data bit (Read, n < 8: sh shifts when b = 0) and a write's data bit
    /// (Write, n < 8: sh shifts b in), registered.
    rdsh: DFF<Bit>,
    wrsh: DFF<Bit>,
    /// A write is performed at a step with b = 0 (Stop, W set, no error).
    stwe: DFF<Bit>,
    /// A read waits for its first bit (Read, n = 0, no step), registered: the shift
    /// register takes `rdq` while it is set and no step is taken.
    ldq: DFF<Bit>,
    /// The register file's read data, registered.
    rdq: DFF<Bits<8>>,
    /// The CDM bit being taken.
    b: Signal<Local, Bit>,
    /// The CRC MSB.
    c3: Signal<Local, Bit>,
    /// A 0 at the zero run's end (b = 0 with 13 or 14 zeros before it): the frame ends.
    zk: Signal<Local, Bit>,
    /// The shift register's MSB: the data bit a read sends.
    dbit: Signal<Local, Bit>,
    /// addr + 1 (7 bits, wraps).
    nadr: Signal<Local, Bits<7>>,
    /// A write is performed this clock.
    we: Signal<Local, Bit>,
    /// 1, 2, 3, 6, 11, 13, 14 at 4 bits; 3 (the CRC taps) and 8 (its MSB) at 4 bits.
    one4: Constant<Bits<4>>,
    two4: Constant<Bits<4>>,
    six4: Constant<Bits<4>>,
    three4: Constant<Bits<4>>,
    eleven4: Constant<Bits<4>>,
    thirteen4: Constant<Bits<4>>,
    fourteen4: Constant<Bits<4>>,
    zero4: Constant<Bits<4>>,
    taps4: Constant<Bits<4>>,
    msb4: Constant<Bits<4>>,
    /// 1 at 7 bits and the first read-only address.
    one7: Constant<Bits<7>>,
    ro7: Constant<Bits<7>>,
    /// 1 and 0x80 at 8 bits.
    one8: Constant<Bits<8>>,
    msb8: Constant<Bits<8>>,
}

impl BissControl {
    /// Control channel with the register file's power-up contents from `ident`; with
    /// `user_map`, addresses 0x00..0x3F are the register map's bytes (the `ext_*` ports).
    pub fn new(ident: &BissIdent, user_map: bool) -> Self {
        let n = usize::from(user_map);
        let many = |f: &dyn Fn() -> Constant<Bits<7>>| (0..n).map(|_| f()).collect::<Vec<_>>();
        let image = ident.image();
        let init: BTreeMap<Bits<7>, Bits<8>> = (0..128usize)
            .map(|a| (Bits::<7>::from(a as u64), Bits::<8>::from(image[a] as u64)))
            .collect();
        let c4 = |v: u64| Constant::new(Bits::<4>::from(v));
        Self {
            clk: Default::default(),
            rst: Default::default(),
            ma: Default::default(),
            done: Default::default(),
            expire: Default::default(),
            cds: Default::default(),
            ext_addr: Default::default(),
            ext_we: Default::default(),
            ext_wdata: Default::default(),
            ext_snap: Default::default(),
            ext_rdata: Default::default(),
            bank: (0..n).map(|_| Default::default()).collect(),
            snp: (0..n).map(|_| Default::default()).collect(),
            k40: many(&|| Constant::new(Bits::<7>::from(0x40u64))),
            k3f: (0..n)
                .map(|_| Constant::new(Bits::<32>::from(0x3fu64)))
                .collect(),
            k6: (0..n)
                .map(|_| Constant::new(Bits::<32>::from(6u64)))
                .collect(),
            regs: RegFile::new(init),
            armed: Default::default(),
            stp: Default::default(),
            bq: Default::default(),
            q_idle: DFFWithInit::new(true),
            q_cts: Default::default(),
            q_id: Default::default(),
            q_adr: Default::default(),
            q_crc: Default::default(),
            q_rb: Default::default(),
            q_wb: Default::default(),
            q_start: Default::default(),
            q_read: Default::default(),
            q_write: Default::default(),
            q_stop: Default::default(),
            q_next: Default::default(),
            zcnt: Default::default(),
            n: Default::default(),
            crc: Default::default(),
            bad: Default::default(),
            addr: Default::default(),
            rb: Default::default(),
            wr: Default::default(),
            sh: Default::default(),
            cds_r: Default::default(),
            nadr_r: Default::default(),
            awr: Default::default(),
            nwr: Default::default(),
            zend: Default::default(),
            zfull: Default::default(),
            n2: Default::default(),
            n3: Default::default(),
            n6: Default::default(),
            n11: Default::default(),
            nhi: Default::default(),
            kupd: Default::default(),
            kshf: Default::default(),
            rdl: Default::default(),
            rdh: Default::default(),
            kclr: Default::default(),
            sread: Default::default(),
            uupd: Default::default(),
            ufb: Default::default(),
            ushf: Default::default(),
            uclr: Default::default(),
            ans1: Default::default(),
            ans0: Default::default(),
            idle1: Default::default(),
            idle0: Default::default(),
            start1: Default::default(),
            start0: Default::default(),
            read1: Default::default(),
            read0: Default::default(),
            write1: Default::default(),
            write0: Default::default(),
            stop1: Default::default(),
            stop0: Default::default(),
            bad1: Default::default(),
            bad0: Default::default(),
            nclr1: Default::default(),
            nclr0: Default::default(),
            ninc1: Default::default(),
            ninc0: Default::default(),
            rdsh: Default::default(),
            wrsh: Default::default(),
            stwe: Default::default(),
            ldq: Default::default(),
            rdq: Default::default(),
            b: Default::default(),
            c3: Default::default(),
            zk: Default::default(),
            dbit: Default::default(),
            nadr: Default::default(),
            we: Default::default(),
            one4: c4(1),
            two4: c4(2),
            six4: c4(6),
            three4: c4(3),
            eleven4: c4(11),
            thirteen4: c4(13),
            fourteen4: c4(14),
            zero4: c4(0),
            taps4: c4((POLY4 & 0xf) as u64),
            msb4: c4(8),
            one7: Constant::new(Bits::<7>::from(1u64)),
            ro7: Constant::new(Bits::<7>::from(FIRST_READ_ONLY as u64)),
            one8: Constant::new(Bits::<8>::from(1u64)),
            msb8: Constant::new(Bits::<8>::from(0x80u64)),
        }
    }
}

/// The 128 x 8 register file: eight banks of 16 x 8 (address bits 6..4 select the bank),
/// written at the clock edge with `write_enable`, with initial contents, and a registered
/// read: at every clock edge each bank's byte at address bits 3..0 goes into that bank's
/// output register (the value before a write at the same edge), and `read_data` is the
/// output register of the bank that `address` selected at the same edge (a registered
/// one-hot bank select `bsel`). With the address stable for two clocks, `read_data` is the
/// register at that address.
///
/// ```text
///  address[3:0] ──► bank 0..7 (16 x 8, LUT RAM) ──► bq 0..7 (8 x 8 FF) ──┐
///  address[6:4] ──► 1 << a ──► bsel (8 FF, one-hot) ──────────────► AND-OR ──► read_data
/// ```
///
/// The AND-OR of eight (select, byte) pairs is two LUT levels on flip-flops; an 8:1
/// multiplexer on the address itself shared the address decode with the write enables and
/// came out four LUTs deep on ECP5.
///
/// Why banks: one 128-deep LUT RAM read is an 8:1 multiplexer tree behind the RAM cells,
/// and with the address fan-out it made the slowest path of the control-enabled top on the
/// ECP5 proxy (docs/biss_control.md). Here the RAM read ends in a flip-flop and the
/// multiplexer starts from flip-flops. The banks are small on purpose: a 16 x 8 memory with
/// a registered read maps to distributed RAM plus flip-flops on xc3sa (no block RAM), LUT
/// RAM on ECP5 and flip-flops in Yosys 0.23's `synth_intel` (which cannot initialise an M9K,
/// and does not choose one for 16 words).
#[derive(LogicBlock, Default)]
pub struct RegFile {
    /// Write and read clock.
    pub clock: Signal<In, Clock>,
    /// Read and write address.
    pub address: Signal<In, Bits<7>>,
    /// The selected bank's output register (the register at `address` one clock ago).
    pub read_data: Signal<Out, Bits<8>>,
    /// Byte to write.
    pub write_data: Signal<In, Bits<8>>,
    /// Write `write_data` to `address` at this clock edge.
    pub write_enable: Signal<In, Bit>,
    _sim: BTreeMap<Bits<7>, Bits<8>>,
    /// The banks' output registers (simulation).
    _bq: [Bits<8>; 8],
    /// The bank `address` selected at the last clock edge (simulation; `bsel` in Verilog).
    _bsel: usize,
}

impl RegFile {
    /// Register file with initial contents.
    pub fn new(values: BTreeMap<Bits<7>, Bits<8>>) -> Self {
        Self {
            _sim: values,
            ..Default::default()
        }
    }
}

impl Logic for RegFile {
    fn update(&mut self) {
        let a = self.address.val().index();
        if self.clock.pos_edge() {
            // Every bank reads at address bits 3..0 before the write of this edge.
            for (b, q) in self._bq.iter_mut().enumerate() {
                let k = Bits::<7>::from(((b << 4) | (a & 0xf)) as u64);
                *q = self._sim.get(&k).copied().unwrap_or_default();
            }
            self._bsel = a >> 4;
            if self.write_enable.val() {
                self._sim.insert(self.address.val(), self.write_data.val());
            }
        }
        self.read_data.next = self._bq[self._bsel];
    }

    fn connect(&mut self) {
        self.read_data.connect();
    }

    fn hdl(&self) -> Verilog {
        let mut v = String::new();
        for b in 0..8usize {
            v += &format!("reg [7:0] mem{b} [15:0];\nreg [7:0] bq{b};\n");
        }
        v += "reg [7:0] bsel;\n\ninitial begin\n   bsel = 8'h1;\n";
        for b in 0..8usize {
            v += &format!("   bq{b} = 8'h0;\n");
        }
        for (a, d) in &self._sim {
            let a = a.index();
            v += &format!("   mem{}[{}] = {};\n", a >> 4, a & 0xf, d.verilog());
        }
        v += "end\n\nalways @(posedge clock) begin\n";
        for b in 0..8usize {
            v += &format!(
                "   if (write_enable && address[6:4] == 3'd{b}) begin\n      mem{b}[address[3:0]] <= write_data;\n   end\n   bq{b} <= mem{b}[address[3:0]];\n"
            );
        }
        v += "   bsel <= 8'h1 << address[6:4];\nend\n\nalways @(*) begin\n   read_data =";
        for b in 0..8usize {
            let or = if b == 0 { "" } else { "\n      |" };
            v += &format!("{or} (bq{b} & {{8{{bsel[{b}]}}}})");
        }
        v += ";\nend\n";
        Verilog::Custom(v)
    }
}
