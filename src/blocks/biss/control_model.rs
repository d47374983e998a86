//! Bit-accurate model of the slave's control channel ([`super::control::BissControl`]): one
//! call per complete frame, with the CDM bit the master held during that frame's timeout,
//! returns the CDS bit the slave sends in the next frame. The rules are the table of
//! docs/biss_control.md ("Slave answers").
use super::regs::{crc4_step, writable, BissIdent};

/// Where the slave is in a control frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// Waiting for a start bit after at least 14 zeros.
    Idle,
    /// Next bit: CTS.
    Cts,
    /// Next bits: ID2..ID0 (count in `n`).
    Id,
    /// Next bits: A6..A0.
    Adr,
    /// Next bits: the inverted CRC4 over CTS, ID and address.
    Crc,
    /// Next bit: R.
    R,
    /// Next bit: W.
    W,
    /// Next bit: the start bit of the data part.
    Start,
    /// The 12 bits of a read (the slave answers D7..D0 and its inverted CRC4).
    Read,
    /// The 12 bits of a write (D7..D0 and the inverted CRC4 from the master).
    Write,
    /// Next bit: the stop bit P (0).
    Stop,
    /// After P: a start bit continues at the next address, a 0 ends the frame.
    Next,
}

/// The register map behind addresses 0x00..0x3F (`[registers]` with the control channel):
/// the channel reads and writes the map's byte bank * 64 + address, bank being the byte at
/// 0x40 (docs/registers.md).
pub trait UserBus {
    /// A read of the map's byte `addr` begins (at POSITION's byte 0 the channel's
    /// POSITION / TURNS / VELOCITY snapshot is taken); returns the byte sent.
    fn read(&mut self, addr: u32) -> u8;
    /// A byte write to the map's byte `addr`.
    fn write(&mut self, addr: u32, value: u8);
}

/// The slave's control channel and its register file.
#[derive(Clone, Debug)]
pub struct ControlModel {
    /// The 128 registers.
    pub regs: [u8; 128],
    phase: Phase,
    zeros: u32,
    n: u32,
    crc: u8,
    bad: bool,
    addr: u8,
    r: bool,
    write: bool,
    byte: u8,
}

impl ControlModel {
    /// The slave after power-up or reset with the given identification registers.
    pub fn new(ident: &BissIdent) -> Self {
        Self {
            regs: ident.image(),
            phase: Phase::Idle,
            zeros: 0,
            n: 0,
            crc: 0,
            bad: false,
            addr: 0,
            r: false,
            write: false,
            byte: 0,
        }
    }

    /// Reset: back to idle, zero count 0 (the registers keep their values).
    pub fn reset(&mut self) {
        let regs = self.regs;
        *self = Self {
            regs,
            ..Self::new(&BissIdent::default())
        };
    }

    /// Current phase.
    pub fn phase(&self) -> Phase {
        self.phase
    }

    /// Takes one CDM bit; returns the CDS bit of the next frame.
    pub fn step(&mut self, cdm: bool) -> bool {
        self.step_with(cdm, None)
    }

    /// The map's byte behind address `addr` (0x00..0x3F) in the selected bank.
    fn user_addr(&self, addr: u8) -> u32 {
        self.regs[0x40] as u32 * crate::blocks::regmap::BISS_BANK_BYTES + (addr & 0x3f) as u32
    }

    /// [`Self::step`] with the register map behind 0x00..0x3F when `bus` is given.
    pub fn step_with(&mut self, cdm: bool, mut bus: Option<&mut dyn UserBus>) -> bool {
        let b = cdm;
        let mut cds = false;
        use Phase::*;
        match self.phase {
            Idle => {
                if b && self.zeros >= 14 {
                    cds = true;
                    self.crc = 0;
                    self.bad = false;
                    self.phase = Cts;
                }
            }
            Cts => {
                self.crc = crc4_step(self.crc, b);
                self.bad |= !b;
                self.n = 0;
                self.phase = Id;
            }
            Id => {
                self.crc = crc4_step(self.crc, b);
                self.bad |= b;
                self.n += 1;
                if self.n == 3 {
                    self.n = 0;
                    self.phase = Adr;
                }
            }
            Adr => {
                self.crc = crc4_step(self.crc, b);
                self.addr = ((self.addr << 1) | b as u8) & 0x7f;
                self.n += 1;
                if self.n == 7 {
                    self.n = 0;
                    self.phase = Crc;
                }
            }
            Crc => {
                self.bad |= b == (self.crc & 8 != 0);
                self.crc = (self.crc << 1) & 0xf;
                self.n += 1;
                if self.n == 4 {
                    self.phase = R;
                }
            }
            R => {
                self.r = b;
                cds = b && !self.bad;
                self.phase = W;
            }
            W => {
                let ok = !self.bad && self.r != b && (!b || writable(self.addr));
                self.write = b;
                cds = b && ok;
                self.phase = if ok { Start } else { Idle };
            }
            Start => {
                if b {
                    cds = true;
                    let ext = self.ext_read(&mut bus);
                    self.begin_byte(ext);
                } else {
                    self.phase = Idle;
                }
            }
            Read => {
                if b {
                    self.phase = Idle;
                } else {
                    cds = self.data_bit(None);
                }
            }
            Write => cds = self.data_bit(Some(b)),
            Stop => {
                if b {
                    self.phase = Idle;
                } else {
                    if self.write && !self.bad {
                        self.regs[self.addr as usize] = self.byte;
                        if let (Some(b), true) = (bus.as_mut(), self.addr < 0x40) {
                            b.write(self.user_addr(self.addr), self.byte);
                        }
                    }
                    self.phase = Next;
                }
            }
            Next => {
                if b {
                    self.addr = (self.addr + 1) & 0x7f;
                    if self.write && !writable(self.addr) {
                        self.phase = Idle;
                    } else {
                        cds = true;
                        let ext = self.ext_read(&mut bus);
                        self.begin_byte(ext);
                    }
                } else {
                    self.phase = Idle;
                }
            }
        }
        // Zero run: 14 zeros end any control frame.
        self.zeros = if b { 0 } else { (self.zeros + 1).min(14) };
        if self.zeros >= 14 && self.phase != Idle {
            self.phase = Idle;
            cds = false;
        }
        cds
    }

    /// A read's byte from the register map (`bus`, user area), else None.
    fn ext_read(&self, bus: &mut Option<&mut dyn UserBus>) -> Option<u8> {
        match bus {
            Some(b) if self.addr < 0x40 && !self.write => Some(b.read(self.user_addr(self.addr))),
            _ => None,
        }
    }

    /// Start of a data byte after a start bit (`ext`: a read's byte from the register map).
    fn begin_byte(&mut self, ext: Option<u8>) {
        self.n = 0;
        self.crc = 0;
        self.bad = false;
        self.byte = ext.unwrap_or(self.regs[self.addr as usize]);
        self.phase = if self.write {
            Phase::Write
        } else {
            Phase::Read
        };
    }

    /// One of the 12 bits of a data byte: the answer (a read sends D7..D0 then the inverted
    /// CRC4; a write echoes D7..D0 then sends the inverted CRC4 of what it received).
    fn data_bit(&mut self, wbit: Option<bool>) -> bool {
        let k = self.n;
        self.n += 1;
        if self.n == 12 {
            self.phase = Phase::Stop;
        }
        if k < 8 {
            let d = match wbit {
                Some(b) => {
                    self.byte = (self.byte << 1) | b as u8;
                    b
                }
                None => self.byte >> (7 - k) & 1 != 0,
            };
            self.crc = crc4_step(self.crc, d);
            d
        } else {
            let c = self.crc & 8 == 0;
            if let Some(b) = wbit {
                self.bad |= b != c;
            }
            self.crc = (self.crc << 1) & 0xf;
            c
        }
    }
}
