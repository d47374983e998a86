//! Register map: an AXI4-Lite slave on `<name>_top` (`[registers] enabled = true`) with the
//! decoder's status, latched faults, position, velocity, index, capture and preset, in one
//! table ([`REGISTERS`]) from which the RTL's decode, the model, the SystemRDL, the JSON and
//! the Markdown table all come.
//!
//! ```text
//!  AW ─► [aw_full, aw_addr] ─┐                       ┌─► B: bvalid until bready
//!  W ──► [w_full, w_data,   ─┴─ both held, no B ────►│   write: STATUS w1c, PRESET pulse
//!         w_strb]                 pending: write     └──────────────────────────────
//!  AR ─► [ar_full, ar_addr] ──► next clock: rdata := reg(ar_addr), rvalid until rready
//!                                   reading POSITION latches TURNS, VELOCITY (shadows)
//!  live flags ─► status |= faults (set wins over a clear in the same clock)
//!  learner's writes (h_tw) ─► mirror RAM [2P] ─► HARM_ENTRY (read at {h_bank, index'},
//!                              two clocks: HARM_ENTRY's rdata a clock later than the others)
//!  HARM_ENTRY write of byte 3 ─► h_ld, h_ld_addr, h_ld_data (two clocks after handshake)
//! ```
//!
//! # Protocol (AXI4-Lite, 32-bit data, byte addresses, [`ADDR_BITS`] bits)
//! * Write: `s_axi_awready` = the address holder is empty, `s_axi_wready` = the data holder
//!   is empty: either channel may come first, or both in the same clock. When both are held
//!   and no response is pending, the write is taken and acts a clock later from registers
//!   (`wq_*`; byte strobes honoured on RW registers;
//!   a W1C or WO register acts on the bits written with their strobe), both holders empty,
//!   and `s_axi_bvalid` rises and stays until `s_axi_bready`. Every response is OKAY.
//! * Read: `s_axi_arready` = no address held and no data pending. The address is held for a
//!   clock, then `s_axi_rdata` is loaded and `s_axi_rvalid` stays until `s_axi_rready`
//!   (HARM_ENTRY's is held two clocks: its mirror RAM reads in two). Every response is
//!   OKAY; an address with no register reads 0.
//! * Reads and writes are independent: a write and a read in the same clock both proceed.
//! * Every output is a register (the ready signals are the holders' empty flags).
//!
//! # Registers
//! See [`REGISTERS`] (and `docs/registers.md`). POSITION is the single-turn position every
//! output takes, (quadrant count << F) | fine, at most 32 bits; reading it latches TURNS
//! and VELOCITY in the same clock, so the three belong to one instant (read POSITION
//! first). STATUS holds the faults latched since they were last cleared: a fault that is
//! still present when it is cleared is set again in the next clock. Writing 1 to PRESET bit
//! 0 gives the position reference's `preset` a one-clock pulse (as a rising edge of the
//! `preset` pin).
//!
//! With a learned harmonic table ([`RegmapParams::with_harmonics`]; docs/registers.md, "The
//! harmonic table") HARM_CONTROL, HARM_INDEX and HARM_ENTRY read and load it: a mirror RAM
//! of the learner's 2P entries, written by each write the learner publishes, cleared over
//! 2P clocks after reset, and read at {bank in use, index'} where index' is HARM_INDEX's next
//! value. The RAM's read register is one clock, so its output in any clock is the entry at
//! the index in force then: a read taken in the clock the index write's response shows is
//! fresh. A HARM_ENTRY write stages its bytes; one that takes byte 3 sends the staged word's
//! low E bits and the index to the learner's load port, two clocks after its handshake.
//! Without a learned table the three words read 0, writes do nothing, and none of this
//! logic exists (its registers are `Vec`s of length 0).
//!
//! # Widths
//! Turn counts are M-bit words sign-extended to 32 bits; velocities are the estimator's
//! `width`-bit words sign-extended to 32 bits (or their low 32 bits when wider); the age is
//! the capture's 24-bit count. Table entries are E-bit two's complement (2^-8 LSB)
//! sign-extended to 32 bits; a load keeps the written word's low E bits.
pub mod block;
pub mod hdl;
pub mod model;

pub use block::{RegistersConfig, BLOCK};

/// Bits of the byte address (`s_axi_awaddr`, `s_axi_araddr`): 64 words.
pub const ADDR_BITS: u32 = 8;

/// Bytes of the map behind one bank of the BiSS control channel (its addresses 0x00..0x3F;
/// the bank select at 0x40 picks bank n = map bytes 64 n .. 64 n + 63, so banks 0..=3 cover
/// the map's 256 bytes and higher banks read 0).
pub const BISS_BANK_BYTES: u32 = 64;

/// `ID`: "SDEC" in ASCII.
pub const ID: u32 = 0x5344_4543;

/// How software may access a register.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Access {
    /// Read only.
    Ro,
    /// Read and write.
    Rw,
    /// Read; writing 1 clears a bit.
    W1c,
    /// Write only (reads 0): a write acts at once.
    Wo,
}

impl Access {
    /// The JSON spelling.
    pub fn as_str(self) -> &'static str {
        match self {
            Access::Ro => "ro",
            Access::Rw => "rw",
            Access::W1c => "w1c",
            Access::Wo => "wo",
        }
    }
}

/// One field of a register (SystemRDL field; a register has at least one).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Field {
    /// Upper-case name.
    pub name: &'static str,
    /// Lowest bit.
    pub lsb: u32,
    /// Width in bits.
    pub width: u32,
    /// One line.
    pub description: &'static str,
}

/// One register of the map.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct RegDef {
    /// Upper-case name.
    pub name: &'static str,
    /// Byte address.
    pub address: u32,
    /// Width in bits (32 for every register here).
    pub width: u32,
    /// Software access.
    pub access: Access,
    /// Value of the register's flip-flops after reset (0 for a live value: its source's).
    pub reset: u32,
    /// One line.
    pub description: &'static str,
    /// Its fields.
    pub fields: &'static [Field],
}

const fn whole(name: &'static str, description: &'static str) -> [Field; 1] {
    [Field {
        name,
        lsb: 0,
        width: 32,
        description,
    }]
}

/// Bits of STATUS (latched faults), in bit order: STATUS bit k latches FLAGS bit k, so
/// each fault sits at the bit of its live twin in [`FLAGS`]. Bits 5..=8 are FLAGS's
/// non-fault flags, reserved (0) in STATUS; later faults are appended above them.
pub const FAULTS: [Field; 7] = [
    Field {
        name: "LOS",
        lsb: 0,
        width: 1,
        description: "loss of signal: the CORDIC magnitude stayed below monitor.min_amplitude for the monitor's window",
    },
    Field {
        name: "CLIP",
        lsb: 1,
        width: 1,
        description: "clipping: the CORDIC magnitude above the monitor's clip threshold",
    },
    Field {
        name: "FULL_SCALE",
        lsb: 2,
        width: 1,
        description: "an ADC code at full scale",
    },
    Field {
        name: "OVERSPEED",
        lsb: 3,
        width: 1,
        description: "a step of 1.75 quadrants or more between samples (the unwrap limit)",
    },
    Field {
        name: "QEP_MISMATCH",
        lsb: 4,
        width: 1,
        description: "the QEP fallback's count and the CORDIC's disagree",
    },
    Field {
        name: "ADC_FRAME",
        lsb: 9,
        width: 1,
        description: "ADC frame error: every data line held one level over a whole frame (a stuck or broken SDO; docs/registers.md)",
    },
    Field {
        name: "NOT_REFERENCED",
        lsb: 10,
        width: 1,
        description: "the position is not referenced (not yet homed on the index or preset); never without [reference]",
    },
];

/// FLAGS: the live flags (the faults of [`FAULTS`] at the same bits, and these).
pub const FLAGS: [Field; 11] = [
    FAULTS[0],
    FAULTS[1],
    FAULTS[2],
    FAULTS[3],
    FAULTS[4],
    Field {
        name: "FALLBACK",
        lsb: 5,
        width: 1,
        description: "the position follows the QEP fallback",
    },
    Field {
        name: "REFERENCED",
        lsb: 6,
        width: 1,
        description: "the position is referenced (homed or preset); 1 without [reference]",
    },
    Field {
        name: "ERROR",
        lsb: 7,
        width: 1,
        description: "the error flag of the outputs",
    },
    Field {
        name: "WARNING",
        lsb: 8,
        width: 1,
        description: "the warning flag of the outputs",
    },
    FAULTS[5],
    FAULTS[6],
];

/// The bits of `fields` (one-bit fields) as a mask.
pub const fn fields_mask(fields: &[Field]) -> u32 {
    let mut m = 0;
    let mut i = 0;
    while i < fields.len() {
        m |= (((1u64 << fields[i].width) - 1) as u32) << fields[i].lsb;
        i += 1;
    }
    m
}

/// STATUS's fault bits.
pub const STATUS_MASK: u32 = fields_mask(&FAULTS);

/// FLAGS's bits.
pub const FLAGS_MASK: u32 = fields_mask(&FLAGS);

/// Bits up to FLAGS's highest (the width of `<name>_top`'s `flags` port).
pub const FLAGS_WIDTH: u32 = 32 - FLAGS_MASK.leading_zeros();

/// The bit of FLAGS named `name` (a field of [`FLAGS`]), at compile time; panics (a
/// compile error in a const) for a name that is not one.
pub const fn flag_bit(name: &str) -> u32 {
    let mut i = 0;
    while i < FLAGS.len() {
        if str_eq(FLAGS[i].name, name) {
            return 1 << FLAGS[i].lsb;
        }
        i += 1;
    }
    panic!("no such FLAGS field")
}

const fn str_eq(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

/// Word index of POSITION (its read latches TURNS and VELOCITY).
pub const POSITION_WORD: u32 = 5;
/// Word index of STATUS.
pub const STATUS_WORD: u32 = 2;
/// Word index of PRESET.
pub const PRESET_WORD: u32 = 10;

/// The register map, in address order.
pub const REGISTERS: &[RegDef] = &[
    RegDef {
        name: "ID",
        address: 0x00,
        width: 32,
        access: Access::Ro,
        reset: ID,
        description: "identification: 0x53444543, \"SDEC\"",
        fields: &whole("ID", "0x53444543"),
    },
    RegDef {
        name: "VERSION",
        address: 0x04,
        width: 32,
        access: Access::Ro,
        reset: VERSION,
        description: "sinedec version that generated the design: major << 16 | minor << 8 | patch",
        fields: &whole("VERSION", "major << 16 | minor << 8 | patch"),
    },
    RegDef {
        name: "STATUS",
        address: 0x08,
        width: 32,
        access: Access::W1c,
        reset: 0,
        description: "faults latched since they were last cleared (write 1 to clear; a fault still present sets again)",
        fields: &FAULTS,
    },
    RegDef {
        name: "FLAGS",
        address: 0x0c,
        width: 32,
        access: Access::Ro,
        reset: 0,
        description: "live flags (not registered here: their values now)",
        fields: &FLAGS,
    },
    RegDef {
        name: "AMPLITUDE",
        address: 0x10,
        width: 32,
        access: Access::Ro,
        reset: 0,
        description: "the latest CORDIC magnitude (the monitor's units: |v| K_N 2^G)",
        fields: &whole("AMPLITUDE", "CORDIC magnitude"),
    },
    RegDef {
        name: "POSITION",
        address: 0x14,
        width: 32,
        access: Access::Ro,
        reset: 0,
        description: "single-turn position, 2^-F quadrant units; reading it latches TURNS and VELOCITY",
        fields: &whole("POSITION", "(quadrant count << F) | fine"),
    },
    RegDef {
        name: "TURNS",
        address: 0x18,
        width: 32,
        access: Access::Ro,
        reset: 0,
        description: "turn count latched by the last POSITION read, sign-extended",
        fields: &whole("TURNS", "signed turn count"),
    },
    RegDef {
        name: "VELOCITY",
        address: 0x1c,
        width: 32,
        access: Access::Ro,
        reset: 0,
        description: "velocity latched by the last POSITION read, as par_velocity, sign-extended (0 without [velocity])",
        fields: &whole("VELOCITY", "2^-(F + frac_bits) quadrant per update period"),
    },
    RegDef {
        name: "INDEX_POSITION",
        address: 0x20,
        width: 32,
        access: Access::Ro,
        reset: 0,
        description: "position of the last index (0 without [reference])",
        fields: &whole("INDEX_POSITION", "(quadrant count << F), fine part 0"),
    },
    RegDef {
        name: "INDEX_TURNS",
        address: 0x24,
        width: 32,
        access: Access::Ro,
        reset: 0,
        description: "turn count of the last index, sign-extended (0 without [reference])",
        fields: &whole("INDEX_TURNS", "signed turn count"),
    },
    RegDef {
        name: "PRESET",
        address: 0x28,
        width: 32,
        access: Access::Wo,
        reset: 0,
        description: "write 1 to bit 0: the position reference loads its preset count at the next sample (no effect without [reference])",
        fields: &[Field {
            name: "PRESET",
            lsb: 0,
            width: 1,
            description: "1: preset",
        }],
    },
    RegDef {
        name: "CAPTURE_POSITION",
        address: 0x2c,
        width: 32,
        access: Access::Ro,
        reset: 0,
        description: "position of the last capture (0 without [capture])",
        fields: &whole("CAPTURE_POSITION", "(quadrant count << F) | fine"),
    },
    RegDef {
        name: "CAPTURE_TURNS",
        address: 0x30,
        width: 32,
        access: Access::Ro,
        reset: 0,
        description: "turn count of the last capture, sign-extended (0 without [capture])",
        fields: &whole("CAPTURE_TURNS", "signed turn count"),
    },
    RegDef {
        name: "CAPTURE_VELOCITY",
        address: 0x34,
        width: 32,
        access: Access::Ro,
        reset: 0,
        description: "velocity at the last capture, sign-extended (0 without [capture] and [velocity])",
        fields: &whole("CAPTURE_VELOCITY", "as VELOCITY"),
    },
    RegDef {
        name: "CAPTURE_AGE",
        address: 0x38,
        width: 32,
        access: Access::Ro,
        reset: 0,
        description: "clocks from the captured sample's CONV edge to the capture (0 without [capture])",
        fields: &whole("CAPTURE_AGE", "clocks"),
    },
    RegDef {
        name: "LOS_THRESHOLD",
        address: 0x3c,
        width: 32,
        access: Access::Rw,
        reset: 0,
        description: "loss of signal: a CORDIC magnitude below it is low (reset: the configured monitor threshold)",
        fields: &whole("LOS_THRESHOLD", "magnitude units, the low W bits used"),
    },
    RegDef {
        name: "LOS_RELEASE",
        address: 0x40,
        width: 32,
        access: Access::Rw,
        reset: 0,
        description: "loss of signal: a magnitude at or above it is good (reset: the configured release level)",
        fields: &whole("LOS_RELEASE", "magnitude units, the low W bits used"),
    },
    RegDef {
        name: "CLIP_THRESHOLD",
        address: 0x44,
        width: 32,
        access: Access::Rw,
        reset: 0,
        description: "clipping: a magnitude above it clips (reset: the configured clipping threshold)",
        fields: &whole("CLIP_THRESHOLD", "magnitude units, the low W bits used"),
    },
    RegDef {
        name: "OFFSET_SIN",
        address: 0x48,
        width: 32,
        access: Access::Rw,
        reset: 0,
        description: "sine offset b in use, LSB, sign-extended: written in static mode, a start value in modes auto and peak (the calibration's next update replaces it); reset: the configured offset",
        fields: &whole("OFFSET_SIN", "signed LSB; a write keeps the low A bits as an A-bit signed number"),
    },
    RegDef {
        name: "OFFSET_COS",
        address: 0x4c,
        width: 32,
        access: Access::Rw,
        reset: 0,
        description: "cosine offset b in use, as OFFSET_SIN",
        fields: &whole("OFFSET_COS", "signed LSB; a write keeps the low A bits as an A-bit signed number"),
    },
    RegDef {
        name: "GAIN_SIN",
        address: 0x50,
        width: 32,
        access: Access::Rw,
        reset: 0,
        description: "sine gain code g in use: x' = g (x - b) / 2^GF; written, start value and reset as OFFSET_SIN",
        fields: &[Field {
            name: "GAIN_SIN",
            lsb: 0,
            width: 16,
            description: "UQ(16-GF).GF",
        }],
    },
    RegDef {
        name: "GAIN_COS",
        address: 0x54,
        width: 32,
        access: Access::Rw,
        reset: 0,
        description: "cosine gain code g_c in use (with phase correction it carries 1 / cos(phase)); as GAIN_SIN",
        fields: &[Field {
            name: "GAIN_COS",
            lsb: 0,
            width: 16,
            description: "UQ(16-GF).GF",
        }],
    },
    RegDef {
        name: "PHASE",
        address: 0x58,
        width: 32,
        access: Access::Rw,
        reset: 0,
        description: "cross code k in use: x_c' = (g_c d_c + k d_s) / 2^GF, k = 2^GF g_s tan(phase), sign and magnitude; the fit's in mode auto; 0 in mode peak (writes ignored)",
        fields: &[
            Field {
                name: "K_MAG",
                lsb: 0,
                width: 16,
                description: "|k|, UQ(16-GF).GF",
            },
            Field {
                name: "K_NEG",
                lsb: 16,
                width: 1,
                description: "k < 0",
            },
        ],
    },
    RegDef {
        name: "HARM_CONTROL",
        address: 0x5c,
        width: 32,
        access: Access::Rw,
        reset: 1,
        description: "learned harmonic table: LEARN lets learning move the entries, LOAD_BUSY a load pending (reads 0, writes ignored without a learned table)",
        fields: &[
            Field {
                name: "LEARN",
                lsb: 0,
                width: 1,
                description: "1: learning moves the entries (reset); 0: the table is frozen",
            },
            Field {
                name: "LOAD_BUSY",
                lsb: 1,
                width: 1,
                description: "read only: 1 while a load of HARM_ENTRY is pending (a write to HARM_ENTRY meanwhile is dropped)",
            },
        ],
    },
    RegDef {
        name: "HARM_INDEX",
        address: 0x60,
        width: 32,
        access: Access::Rw,
        reset: 0,
        description: "learned harmonic table: the entry i that HARM_ENTRY reads and loads (reads 0, writes ignored without a learned table)",
        fields: &[Field {
            name: "INDEX",
            lsb: 0,
            width: 8,
            description: "entry i, 0..P-1 (the low p = log2 P bits kept)",
        }],
    },
    RegDef {
        name: "HARM_ENTRY",
        address: 0x64,
        width: 32,
        access: Access::Rw,
        reset: 0,
        description: "learned harmonic table: entry HARM_INDEX of the bank in use, 2^-8 LSB, sign-extended; writing byte 3 loads the word's low E bits into that entry of both banks (docs/registers.md, \"The harmonic table\")",
        fields: &whole(
            "HARM_ENTRY",
            "signed, 2^-8 LSB; a write of byte 3 (with the bytes staged before it) keeps the low E bits as an E-bit signed number",
        ),
    },
];

/// Read-only fields inside a read-write register (register, field): their value is the
/// hardware's, a write leaves them.
pub const RO_FIELDS: &[(&str, &str)] = &[("HARM_CONTROL", "LOAD_BUSY")];

/// Word indices of the correction's codes (OFFSET_SIN, OFFSET_COS, GAIN_SIN, GAIN_COS,
/// PHASE, in [`crate::blocks::correction::codes::WORDS`] order): live values of the
/// correction, written through its load port; their reset values are the config's
/// ([`RegmapParams::reset`]).
pub const CODE_WORDS: [u32; 5] = [18, 19, 20, 21, 22];

/// Word indices of the run-time monitor thresholds (LOS_THRESHOLD, LOS_RELEASE,
/// CLIP_THRESHOLD), whose reset values are the config's ([`RegmapParams::reset`]).
pub const THRESHOLD_WORDS: [u32; 3] = [15, 16, 17];

/// Word indices of the learned harmonic table's registers (HARM_CONTROL, HARM_INDEX,
/// HARM_ENTRY): decoded only with [`RegmapParams::with_harmonics`], else they read 0 and
/// writes do nothing.
pub const HARM_WORDS: [u32; 3] = [23, 24, 25];

/// The sinedec version as VERSION holds it: major << 16 | minor << 8 | patch (each part
/// modulo 256), from the package version at compile time.
pub const VERSION: u32 = {
    let v = env!("CARGO_PKG_VERSION").as_bytes();
    let mut parts = [0u32; 3];
    let (mut i, mut k) = (0, 0);
    while i < v.len() && k < 3 {
        match v[i] {
            b'.' => k += 1,
            c @ b'0'..=b'9' => parts[k] = (parts[k] * 10 + (c - b'0') as u32) & 0xff,
            _ => k = 3,
        }
        i += 1;
    }
    parts[0] << 16 | parts[1] << 8 | parts[2]
};

/// Parameters of [`hdl::RegisterMap`] and [`model::RegisterModel`]: the widths of the
/// words it reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct RegmapParams {
    fine_bits: u32,
    turns_bits: u32,
    velocity_width: u32,
    referenced_always: bool,
    biss_port: bool,
    thresholds: [u32; 3],
    codes: [u32; 5],
    /// log2 P of the learned table (0: no learned table) and its entries' width E.
    harm_points_log2: u32,
    harm_entry_width: u32,
}

impl RegmapParams {
    /// F (1..=16), M (0..=31), the velocity's width (0 without one, else 8..=62), and
    /// whether the position counts as referenced always (no position reference).
    pub fn new(
        position_bits: u32,
        fine_bits: u32,
        turns_bits: u32,
        velocity_width: u32,
        referenced_always: bool,
    ) -> crate::error::Result<Self> {
        if position_bits > 32 || !(1..=16).contains(&fine_bits) || turns_bits > 31 {
            return Err(crate::error::Error::block_params(
                "registers",
                format!(
                    "a {position_bits}-bit position (F = {fine_bits}, {turns_bits} turn bits): POSITION holds at most 32 bits"
                ),
            ));
        }
        Ok(Self {
            fine_bits,
            turns_bits,
            velocity_width,
            referenced_always,
            biss_port: false,
            thresholds: [0; 3],
            codes: [0; 5],
            harm_points_log2: 0,
            harm_entry_width: 0,
        })
    }
    /// With the learned harmonic table of `points` entries (a power of two, 16..=256) of
    /// `entry_width` bits (E, two's complement in 2^-8 LSB, 2..=24): HARM_CONTROL,
    /// HARM_INDEX and HARM_ENTRY decoded, the mirror RAM and the learner's ports used.
    pub fn with_harmonics(mut self, points: u32, entry_width: u32) -> crate::error::Result<Self> {
        // A learned table has at most 128 entries (its two banks in one 256-word RAM).
        let range = *crate::blocks::harmonics::POINTS_RANGE.start()
            ..=crate::blocks::harmonics::hdl_ram::MAX_POINTS;
        let ok = range.contains(&points) && points.is_power_of_two();
        if !(ok && (2..=24).contains(&entry_width)) {
            return Err(crate::error::Error::block_params(
                "registers",
                format!(
                    "a learned table of {points} entries of {entry_width} bits: allowed a power of two from {} to {} entries of 2 to 24 bits",
                    range.start(),
                    range.end()
                ),
            ));
        }
        self.harm_points_log2 = points.trailing_zeros();
        self.harm_entry_width = entry_width;
        Ok(self)
    }
    /// The learned table's (P, E), or None without one.
    pub fn harmonics(&self) -> Option<(u32, u32)> {
        (self.harm_points_log2 > 0).then(|| (1 << self.harm_points_log2, self.harm_entry_width))
    }
    /// The words the map decodes: every register of [`REGISTERS`] with a learned table, all
    /// but HARM_CONTROL, HARM_INDEX and HARM_ENTRY without one.
    pub fn words(&self) -> u32 {
        if self.harmonics().is_some() {
            REGISTERS.len() as u32
        } else {
            HARM_WORDS[0]
        }
    }
    /// With the monitor's configured loss-of-signal threshold, release level and clipping
    /// threshold: the reset values of LOS_THRESHOLD, LOS_RELEASE and CLIP_THRESHOLD.
    pub fn with_thresholds(mut self, thresholds: [u32; 3]) -> Self {
        self.thresholds = thresholds;
        self
    }
    /// The configured thresholds (see [`Self::with_thresholds`]).
    pub fn thresholds(&self) -> [u32; 3] {
        self.thresholds
    }
    /// With the correction's configured codes (`CorrectionParams::reset_words`): the reset
    /// values of OFFSET_SIN, OFFSET_COS, GAIN_SIN, GAIN_COS and PHASE.
    pub fn with_codes(mut self, codes: [u32; 5]) -> Self {
        self.codes = codes;
        self
    }
    /// The configured codes (see [`Self::with_codes`]).
    pub fn codes(&self) -> [u32; 5] {
        self.codes
    }
    /// The value register `r` holds after reset: the table's, or a configured threshold
    /// or code; 0 for a word the map does not decode (the harmonic table's without one).
    pub fn reset(&self, r: &RegDef) -> u32 {
        let at = |words: &[u32]| words.iter().position(|&w| w * 4 == r.address);
        match (at(&THRESHOLD_WORDS), at(&CODE_WORDS)) {
            (Some(k), _) => self.thresholds[k],
            (_, Some(k)) => self.codes[k],
            _ if r.address / 4 >= self.words() => 0,
            _ => r.reset,
        }
    }
    /// With the BiSS control channel's byte port ([`BISS_BANK_BYTES`]-byte banks of the
    /// map behind the channel's addresses 0x00..0x3F).
    pub fn with_biss_port(mut self) -> Self {
        self.biss_port = true;
        self
    }
    /// The map has the BiSS control channel's byte port.
    pub fn biss_port(&self) -> bool {
        self.biss_port
    }
    /// F.
    pub fn fine_bits(&self) -> u32 {
        self.fine_bits
    }
    /// M.
    pub fn turns_bits(&self) -> u32 {
        self.turns_bits
    }
    /// The velocity's width (0: none).
    pub fn velocity_width(&self) -> u32 {
        self.velocity_width
    }
    /// FLAGS.REFERENCED is 1 always (no position reference).
    pub fn referenced_always(&self) -> bool {
        self.referenced_always
    }
    /// A turn word (M bits) sign-extended to 32 bits.
    pub fn turns32(&self, t: u64) -> u32 {
        if self.turns_bits == 0 {
            0
        } else {
            crate::blocks::sext(t, self.turns_bits) as u32
        }
    }
    /// A velocity word sign-extended to 32 bits (its low 32 bits when wider).
    pub fn velocity32(&self, v: u64) -> u32 {
        match self.velocity_width {
            0 => 0,
            w if w >= 32 => v as u32,
            w => crate::blocks::sext(v, w) as u32,
        }
    }
}
