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
//!     zcnt (zero run, 0..14)   state (Idle, Cts, Id, Adr, Crc, R, W, Start, Read, Write,
//!     n (bit count, 0..11)            Stop, Next)     crc (CRC4)  addr (7)  sh (8)
//!     regs: RegFile 128 x 8 in eight 16 x 8 banks, registered read at addr, loaded
//!           into sh while a read waits for its first bit; written at P of a write
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
//! The answers are the table of docs/biss_control.md; [`super::control_model`] is the same
//! table in plain Rust.
//!
//! Widths: zcnt, n and crc are 4 bits (at most 14, 11 and 0xf), addr 7 bits (the address
//! increment wraps 0x7f -> 0x00 as the protocol's 7-bit address does), sh and the register
//! data 8 bits. Every constant is sized to the word it meets.
use super::regs::{BissIdent, FIRST_READ_ONLY, POLY4};
use rust_hdl::prelude::*;
use std::collections::BTreeMap;

/// Where the control channel is in a control frame (one step per CDM bit).
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
    regs: RegFile,
    armed: DFF<Bit>,
    stp: DFF<Bit>,
    bq: DFF<Bit>,
    state: DFF<CtlState>,
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
    /// The CDM bit being taken.
    b: Signal<Local, Bit>,
    /// The CRC MSB.
    c3: Signal<Local, Bit>,
    /// A read waits for its first bit (state Read, n = 0, no step this clock): the shift
    /// register takes the register at `addr` (the registered read of the register file).
    ld: Signal<Local, Bit>,
    /// The shift register's MSB: the data bit a read sends.
    dbit: Signal<Local, Bit>,
    /// addr + 1 (7 bits, wraps).
    nadr: Signal<Local, Bits<7>>,
    /// The CDS answer of this step.
    ans: Signal<Local, Bit>,
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
    /// Control channel with the register file's power-up contents from `ident`.
    pub fn new(ident: &BissIdent) -> Self {
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
            regs: RegFile::new(init),
            armed: Default::default(),
            stp: Default::default(),
            bq: Default::default(),
            state: Default::default(),
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
            b: Default::default(),
            c3: Default::default(),
            ld: Default::default(),
            dbit: Default::default(),
            nadr: Default::default(),
            ans: Default::default(),
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

impl Logic for BissControl {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clk, armed, stp, bq, state, zcnt, n, crc, bad, addr, rb, wr, sh, cds_r, nadr_r,
            awr, nwr, zend, zfull, n2, n3, n6, n11, nhi, kupd, kshf, rdl, rdh, kclr, sread, uupd,
            ufb, ushf, uclr
        );
        self.regs.clock.next = self.clk.val();
        self.regs.address.next = self.addr.q.val();
        self.regs.write_data.next = self.sh.q.val();
        // A complete frame arms the sampler; the end of its timeout takes one CDM bit.
        if self.done.val() {
            self.armed.d.next = true;
        }
        self.stp.d.next = self.expire.val() & self.armed.q.val();
        if self.expire.val() {
            self.armed.d.next = false;
        }
        self.bq.d.next = !self.ma.val();
        self.b.next = self.bq.q.val();
        self.c3.next = (self.crc.q.val() & self.msb4.val()).any();
        self.nadr.next = self.addr.q.val() + self.one7.val();
        self.nadr_r.d.next = self.nadr.val();
        self.awr.d.next = self.addr.q.val() < self.ro7.val();
        self.nwr.d.next = self.nadr.val() < self.ro7.val();
        self.zend.d.next = (self.zcnt.q.val() == self.thirteen4.val())
            | (self.zcnt.q.val() == self.fourteen4.val());
        self.zfull.d.next = self.zcnt.q.val() == self.fourteen4.val();
        self.n2.d.next = self.n.q.val() == self.two4.val();
        self.n3.d.next = self.n.q.val() == self.three4.val();
        self.n6.d.next = self.n.q.val() == self.six4.val();
        self.n11.d.next = self.n.q.val() == self.eleven4.val();
        self.nhi.d.next = (self.n.q.val() & self.msb4.val()).any();
        // The CRC register's action at a step, from the state decodes above (the step's
        // case analysis below leaves the CRC alone): the same action the step took before,
        // now one clock later.
        self.kupd.d.next = (self.state.q.val() == CtlState::Cts)
            | (self.state.q.val() == CtlState::Id)
            | (self.state.q.val() == CtlState::Adr)
            | ((self.state.q.val() == CtlState::Write) & !(self.n.q.val() & self.msb4.val()).any());
        self.kshf.d.next = (self.state.q.val() == CtlState::Crc)
            | ((self.state.q.val() == CtlState::Write) & (self.n.q.val() & self.msb4.val()).any());
        self.rdl.d.next =
            (self.state.q.val() == CtlState::Read) & !(self.n.q.val() & self.msb4.val()).any();
        self.rdh.d.next =
            (self.state.q.val() == CtlState::Read) & (self.n.q.val() & self.msb4.val()).any();
        self.sread.d.next = self.state.q.val() == CtlState::Read;
        self.kclr.d.next = ((self.state.q.val() == CtlState::Idle) & self.zfull.q.val())
            | (self.state.q.val() == CtlState::Start)
            | ((self.state.q.val() == CtlState::Next) & (!self.wr.q.val() | self.nwr.q.val()));
        self.uupd.d.next =
            self.stp.q.val() & (self.kupd.q.val() | (self.rdl.q.val() & !self.b.val()));
        self.ushf.d.next =
            self.stp.q.val() & (self.kshf.q.val() | (self.rdh.q.val() & !self.b.val()));
        self.uclr.d.next = self.stp.q.val() & self.kclr.q.val() & self.b.val();
        self.ans.next = false;
        self.we.next = false;
        // The registered read: until a read's first bit, the shift register holds the
        // register at addr (addr is stable from the clock after the step that set it, and
        // steps are a frame apart, so sh holds mem[addr] long before that bit's step).
        self.ld.next = !self.stp.q.val()
            & (self.state.q.val() == CtlState::Read)
            & (self.n.q.val() == self.zero4.val());
        if self.ld.val() {
            self.sh.d.next = self.regs.read_data.val();
        }
        self.dbit.next = (self.sh.q.val() & self.msb8.val()).any();
        self.ufb.d.next = self.b.val() ^ self.c3.val();
        if self.sread.q.val() {
            self.ufb.d.next = self.dbit.val() ^ self.c3.val();
        }
        if self.stp.q.val() {
            match self.state.q.val() {
                CtlState::Idle => {
                    if self.b.val() & self.zfull.q.val() {
                        self.ans.next = true;
                        self.bad.d.next = false;
                        self.state.d.next = CtlState::Cts;
                    }
                }
                CtlState::Cts => {
                    if !self.b.val() {
                        self.bad.d.next = true;
                    }
                    self.n.d.next = self.zero4.val();
                    self.state.d.next = CtlState::Id;
                }
                CtlState::Id => {
                    if self.b.val() {
                        self.bad.d.next = true;
                    }
                    self.n.d.next = self.n.q.val() + self.one4.val();
                    if self.n2.q.val() {
                        self.n.d.next = self.zero4.val();
                        self.state.d.next = CtlState::Adr;
                    }
                }
                CtlState::Adr => {
                    if self.b.val() {
                        self.addr.d.next = (self.addr.q.val() << self.one7.val()) | self.one7.val();
                    } else {
                        self.addr.d.next = self.addr.q.val() << self.one7.val();
                    }
                    self.n.d.next = self.n.q.val() + self.one4.val();
                    if self.n6.q.val() {
                        self.n.d.next = self.zero4.val();
                        self.state.d.next = CtlState::Crc;
                    }
                }
                CtlState::Crc => {
                    if self.b.val() == self.c3.val() {
                        self.bad.d.next = true;
                    }
                    self.n.d.next = self.n.q.val() + self.one4.val();
                    if self.n3.q.val() {
                        self.state.d.next = CtlState::Rb;
                    }
                }
                CtlState::Rb => {
                    self.rb.d.next = self.b.val();
                    self.ans.next = self.b.val() & !self.bad.q.val();
                    self.state.d.next = CtlState::Wb;
                }
                CtlState::Wb => {
                    self.wr.d.next = self.b.val();
                    self.state.d.next = CtlState::Idle;
                    if !self.bad.q.val()
                        & (self.rb.q.val() != self.b.val())
                        & (!self.b.val() | self.awr.q.val())
                    {
                        self.ans.next = self.b.val();
                        self.state.d.next = CtlState::Start;
                    }
                }
                CtlState::Start => {
                    self.state.d.next = CtlState::Idle;
                    if self.b.val() {
                        self.ans.next = true;
                        self.n.d.next = self.zero4.val();
                        self.bad.d.next = false;
                        if self.wr.q.val() {
                            self.state.d.next = CtlState::Write;
                        } else {
                            self.state.d.next = CtlState::Read;
                        }
                    }
                }
                CtlState::Read => {
                    if self.b.val() {
                        self.state.d.next = CtlState::Idle;
                    } else {
                        self.n.d.next = self.n.q.val() + self.one4.val();
                        if self.n11.q.val() {
                            self.state.d.next = CtlState::Stop;
                        }
                        if self.nhi.q.val() {
                            // CRC bits: the inverted CRC4, MSB first.
                            self.ans.next = !self.c3.val();
                        } else {
                            self.ans.next = self.dbit.val();
                            self.sh.d.next = self.sh.q.val() << self.one8.val();
                        }
                    }
                }
                CtlState::Write => {
                    self.n.d.next = self.n.q.val() + self.one4.val();
                    if self.n11.q.val() {
                        self.state.d.next = CtlState::Stop;
                    }
                    if self.nhi.q.val() {
                        // CRC bits: answer the own CRC4 of the received byte.
                        self.ans.next = !self.c3.val();
                        if self.b.val() == self.c3.val() {
                            self.bad.d.next = true;
                        }
                    } else {
                        self.ans.next = self.b.val();
                        if self.b.val() {
                            self.sh.d.next = (self.sh.q.val() << self.one8.val()) | self.one8.val();
                        } else {
                            self.sh.d.next = self.sh.q.val() << self.one8.val();
                        }
                    }
                }
                CtlState::Stop => {
                    if self.b.val() {
                        self.state.d.next = CtlState::Idle;
                    } else {
                        self.we.next = self.wr.q.val() & !self.bad.q.val();
                        self.state.d.next = CtlState::Next;
                    }
                }
                CtlState::Next => {
                    self.state.d.next = CtlState::Idle;
                    if self.b.val() {
                        self.addr.d.next = self.nadr_r.q.val();
                        if !self.wr.q.val() | self.nwr.q.val() {
                            self.ans.next = true;
                            self.n.d.next = self.zero4.val();
                            self.bad.d.next = false;
                            if self.wr.q.val() {
                                self.state.d.next = CtlState::Write;
                            } else {
                                self.state.d.next = CtlState::Read;
                            }
                        }
                    }
                }
            }
            // The zero run: 14 zeros end any control frame.
            if self.b.val() {
                self.zcnt.d.next = self.zero4.val();
            } else if !self.zfull.q.val() {
                self.zcnt.d.next = self.zcnt.q.val() + self.one4.val();
            }
            if !self.b.val() & self.zend.q.val() {
                self.ans.next = false;
                self.state.d.next = CtlState::Idle;
            }
            self.cds_r.d.next = self.ans.val();
        }
        // Serial CRC4 (taps x + 1), one clock after the step that decided it.
        if self.uupd.q.val() {
            if self.ufb.q.val() {
                self.crc.d.next = (self.crc.q.val() << self.one4.val()) ^ self.taps4.val();
            } else {
                self.crc.d.next = self.crc.q.val() << self.one4.val();
            }
        }
        if self.ushf.q.val() {
            self.crc.d.next = self.crc.q.val() << self.one4.val();
        }
        if self.uclr.q.val() {
            self.crc.d.next = self.zero4.val();
        }
        self.regs.write_enable.next = self.we.val();
        if self.rst.val() {
            self.armed.d.next = false;
            self.stp.d.next = false;
            self.state.d.next = CtlState::Idle;
            self.zcnt.d.next = self.zero4.val();
            self.cds_r.d.next = false;
            self.regs.write_enable.next = false;
        }
        self.cds.next = self.cds_r.q.val();
    }
}

/// The 128 x 8 register file: eight banks of 16 x 8 (address bits 6..4 select the bank),
/// written at the clock edge with `write_enable`, with initial contents, and a registered
/// read: at every clock edge each bank's byte at address bits 3..0 goes into that bank's
/// output register (the value before a write at the same edge), and `read_data` is the
/// output register of the bank that `address` selects now. With the address stable for
/// two clocks, `read_data` is the register at that address.
///
/// ```text
///  address[3:0] ──► bank 0..7 (16 x 8, LUT RAM) ──► bq 0..7 (8 x 8 FF) ──┐
///  address[6:4] ─────────────────────────────────────────────────► 8:1 mux ──► read_data
/// ```
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
            if self.write_enable.val() {
                self._sim.insert(self.address.val(), self.write_data.val());
            }
        }
        self.read_data.next = self._bq[a >> 4];
    }

    fn connect(&mut self) {
        self.read_data.connect();
    }

    fn hdl(&self) -> Verilog {
        let mut v = String::new();
        for b in 0..8usize {
            v += &format!("reg [7:0] mem{b} [15:0];\nreg [7:0] bq{b};\n");
        }
        v += "\ninitial begin\n";
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
        v += "end\n\nalways @(*) begin\n   case (address[6:4])\n";
        for b in 0..8usize {
            v += &format!("      3'd{b}: read_data = bq{b};\n");
        }
        v += "      default: read_data = bq0;\n   endcase\nend\n";
        Verilog::Custom(v)
    }
}
