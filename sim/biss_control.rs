//! BiSS C control master (register access over CDM/CDS), written from the protocol
//! description cited in docs/biss_control.md, not from the slave: it plans the CDM bit of
//! every frame for a list of register commands and reads the commands' results from the
//! CDS bits the frames returned. The CDS bit read in frame j + 1 is the slave's answer to
//! the CDM bit of frame j.
//!
//! A register command, bit by bit (CDM; the expected CDS answer in brackets):
//!
//! ```text
//!  >= 14 x 0 | S [1: IDL] | CTS=1 | ID2 ID1 ID0 | A6..A0 | ~CRC4(CTS,ID,A) | R | W |   [0 .. 0, R, W]
//!  per byte: S [1] | read: 12 x 0 [D7..D0, ~CRC4(D)] / write: D7..D0 ~CRC4(D) [echo] | P=0 [0]
//! ```
//!
//! A following start bit right after P continues at the next address (sequential access);
//! 14 zeros end or cancel a command at any point.

/// What a command does.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Access {
    /// Read `count` registers from `addr` on.
    Read {
        /// First address (7 bits).
        addr: u8,
        /// Registers to read (sequential access after the first).
        count: usize,
    },
    /// Write `data` from `addr` on.
    Write {
        /// First address (7 bits).
        addr: u8,
        /// Bytes to write.
        data: Vec<u8>,
    },
}

/// One register command.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Command {
    /// Slave ID (0..7; a point-to-point slave is 0).
    pub id: u8,
    /// The access.
    pub access: Access,
    /// Flip the last bit of the address CRC (a transmission error).
    pub corrupt_crc: bool,
    /// Send only this many bits of the command (a master that stops mid-command).
    pub truncate: Option<usize>,
}

impl Command {
    /// Read `count` registers from `addr` of slave 0.
    pub fn read(addr: u8, count: usize) -> Self {
        Self {
            id: 0,
            access: Access::Read { addr, count },
            corrupt_crc: false,
            truncate: None,
        }
    }
    /// Write `data` from `addr` on, slave 0.
    pub fn write(addr: u8, data: &[u8]) -> Self {
        Self {
            id: 0,
            access: Access::Write {
                addr,
                data: data.to_vec(),
            },
            corrupt_crc: false,
            truncate: None,
        }
    }
}

/// CRC4 x^4 + x + 1 of the `bits` low bits of `msg` by long division (remainder of
/// msg(x) x^4 over 10011), inverted as sent.
pub fn sent_crc4(msg: u64, bits: u32) -> u8 {
    let mut r = (msg as u128) << 4;
    for i in (4..bits + 4).rev() {
        if r >> i & 1 == 1 {
            r ^= 0x13u128 << (i - 4);
        }
    }
    !(r as u8) & 0xf
}

/// The name of each bit of a command (for transcripts).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Bit {
    /// Field name: "S", "CTS", "ID2", "A6", "C3", "R", "W", "S(data)", "D7", "P", ...
    pub field: String,
    /// The CDM bit.
    pub cdm: bool,
}

fn bits_of(v: u64, n: u32) -> impl Iterator<Item = bool> {
    (0..n).rev().map(move |i| v >> i & 1 != 0)
}

impl Command {
    /// The command's bits (without the leading zeros), truncated if asked.
    pub fn bits(&self) -> Vec<Bit> {
        let mut out = Vec::new();
        let mut put = |f: String, v: bool| out.push(Bit { field: f, cdm: v });
        let (addr, write) = match &self.access {
            Access::Read { addr, .. } => (*addr, false),
            Access::Write { addr, .. } => (*addr, true),
        };
        let head = (1u64 << 10) | ((self.id as u64 & 7) << 7) | (addr as u64 & 0x7f);
        let mut crc = sent_crc4(head, 11);
        if self.corrupt_crc {
            crc ^= 1;
        }
        put("S".into(), true);
        put("CTS".into(), true);
        for (i, v) in bits_of(self.id as u64 & 7, 3).enumerate() {
            put(format!("ID{}", 2 - i), v);
        }
        for (i, v) in bits_of(addr as u64 & 0x7f, 7).enumerate() {
            put(format!("A{}", 6 - i), v);
        }
        for (i, v) in bits_of(crc as u64, 4).enumerate() {
            put(format!("C{}", 3 - i), v);
        }
        put("R".into(), !write);
        put("W".into(), write);
        match &self.access {
            Access::Read { count, .. } => {
                for _ in 0..*count {
                    put("S(data)".into(), true);
                    for i in 0..8 {
                        put(format!("D{}", 7 - i), false);
                    }
                    for i in 0..4 {
                        put(format!("C{}", 3 - i), false);
                    }
                    put("P".into(), false);
                }
            }
            Access::Write { data, .. } => {
                for &d in data {
                    put("S(data)".into(), true);
                    for (i, v) in bits_of(d as u64, 8).enumerate() {
                        put(format!("D{}", 7 - i), v);
                    }
                    for (i, v) in bits_of(sent_crc4(d as u64, 8) as u64, 4).enumerate() {
                        put(format!("C{}", 3 - i), v);
                    }
                    put("P".into(), false);
                }
            }
        }
        if let Some(k) = self.truncate {
            out.truncate(k);
        }
        out
    }
}

/// How a command ended, as the master reads it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// No IDL answer to the start bit: no slave took the command.
    NoAck,
    /// R, W or the data start bit not echoed: the slave refused the command (address CRC
    /// error, wrong ID, or a write to a read-only register).
    Refused,
    /// Read: the bytes, every CRC4 good.
    Read(Vec<u8>),
    /// Read: byte `index` arrived with a bad CRC4 (`got` = data, received and expected CRC).
    ReadCrc {
        /// Byte index.
        index: usize,
        /// (data, received CRC, expected CRC).
        got: (u8, u8, u8),
    },
    /// Write: every byte's echo (data, CRC, P) confirmed.
    Written(usize),
    /// Write: byte `index` (or its next start bit) not confirmed.
    WriteUnconfirmed {
        /// Byte index.
        index: usize,
    },
    /// The command was truncated on purpose (not decoded).
    Truncated,
}

/// A session: the CDM bit of every frame, and where each command sits in it.
#[derive(Clone, Debug, Default)]
pub struct Session {
    /// CDM bit per frame, in order.
    pub cdm: Vec<bool>,
    /// Bit names per frame ("0" for the idle zeros).
    pub fields: Vec<String>,
    /// (first frame, command) for each command.
    pub commands: Vec<(usize, Command)>,
}

impl Session {
    /// An empty session.
    pub fn new() -> Self {
        Self::default()
    }

    /// Zeros since the last 1.
    fn zero_run(&self) -> usize {
        self.cdm.iter().rev().take_while(|&&b| !b).count()
    }

    /// `n` CDM zeros.
    pub fn zeros(&mut self, n: usize) -> &mut Self {
        for _ in 0..n {
            self.cdm.push(false);
            self.fields.push("0".into());
        }
        self
    }

    /// Appends a command, preceded by zeros up to the 14 the protocol asks for.
    pub fn command(&mut self, c: Command) -> &mut Self {
        let run = self.zero_run();
        self.zeros(14usize.saturating_sub(run));
        self.commands.push((self.cdm.len(), c.clone()));
        for b in c.bits() {
            self.cdm.push(b.cdm);
            self.fields.push(b.field);
        }
        self
    }

    /// Frames to clock: every CDM bit, 14 closing zeros, and one more frame for the last
    /// answer.
    pub fn frames(&mut self) -> usize {
        let run = self.zero_run();
        self.zeros(14usize.saturating_sub(run));
        self.cdm.len() + 1
    }

    /// The answer to CDM bit `j` from the CDS bits read per frame.
    fn ans(cds: &[bool], j: usize) -> bool {
        cds.get(j + 1).copied().unwrap_or(false)
    }

    /// Every command's outcome from the CDS bit of every frame (`cds[j]` read in frame j).
    pub fn outcomes(&self, cds: &[bool]) -> Vec<Outcome> {
        self.commands
            .iter()
            .map(|(j0, c)| Self::outcome(c, *j0, cds))
            .collect()
    }

    fn outcome(c: &Command, j0: usize, cds: &[bool]) -> Outcome {
        if c.truncate.is_some() {
            return Outcome::Truncated;
        }
        let a = |k: usize| Self::ans(cds, j0 + k);
        // S=0, CTS=1, ID 2..4, A 5..11, C 12..15, R=16, W=17, first data start 18.
        if !a(0) {
            return Outcome::NoAck;
        }
        let write = matches!(c.access, Access::Write { .. });
        // R and W echoed as sent (R = !write), then the data start bit.
        let (r_echo, w_echo) = (a(16), a(17));
        if r_echo == write || w_echo != write || !a(18) {
            return Outcome::Refused;
        }
        let bits = c.bits();
        let word = |from: usize, n: usize| (0..n).fold(0u8, |v, i| (v << 1) | a(from + i) as u8);
        match &c.access {
            Access::Read { count, .. } => {
                let mut bytes = Vec::new();
                for i in 0..*count {
                    let s = 18 + 14 * i;
                    if i > 0 && !a(s) {
                        return Outcome::Refused;
                    }
                    let (d, crc) = (word(s + 1, 8), word(s + 9, 4));
                    let want = sent_crc4(d as u64, 8);
                    if crc != want {
                        return Outcome::ReadCrc {
                            index: i,
                            got: (d, crc, want),
                        };
                    }
                    bytes.push(d);
                }
                Outcome::Read(bytes)
            }
            Access::Write { data, .. } => {
                for i in 0..data.len() {
                    let s = 18 + 14 * i;
                    // S, D7..D0, C3..C0 echoed, P answered 0.
                    let echo_ok = (0..13).all(|k| a(s + k) == bits[s + k].cdm) && !a(s + 13);
                    if !echo_ok {
                        return Outcome::WriteUnconfirmed { index: i };
                    }
                }
                Outcome::Written(data.len())
            }
        }
    }

    /// A transcript of frames `from..to`: frame, field, CDM, and the CDS answer (read in
    /// the next frame).
    pub fn transcript(&self, cds: &[bool], from: usize, to: usize) -> String {
        let mut s = String::from("frame  field    CDM  CDS(answer, next frame)\n");
        for j in from..to.min(self.cdm.len()) {
            s += &format!(
                "{j:5}  {:8} {:3}  {}\n",
                self.fields[j],
                self.cdm[j] as u8,
                Self::ans(cds, j) as u8
            );
        }
        s
    }
}
