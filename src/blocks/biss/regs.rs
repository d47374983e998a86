//! The BiSS C register file behind the control channel (docs/biss_control.md): 128 bytes,
//! the standard map of the BiSS C protocol description at 0x40..0x7F, and the CRC4 that
//! protects control frames.
//!
//! | address     | content                                   | access     |
//! |-------------|-------------------------------------------|------------|
//! | 0x00..0x3F  | user registers (bank 0, the only bank)    | read/write |
//! | 0x40        | bank select (stored; one bank exists)     | read/write |
//! | 0x41        | EDS bank (`eds_bank`; 0 = no EDS)         | read only  |
//! | 0x42..0x43  | profile ID (`profile_id`, low byte first) | read only  |
//! | 0x44..0x47  | serial number (`serial_number`, LSB first)| read only  |
//! | 0x48..0x77  | reserved, read as 0                       | read only  |
//! | 0x78..0x7D  | device ID (`device_id`, 6 ASCII bytes)    | read only  |
//! | 0x7E..0x7F  | manufacturer ID (`manufacturer_id`, 2)    | read only  |
//!
//! CRC4: polynomial x^4 + x + 1 (0x13), start value 0, computed MSB first, sent inverted,
//! MSB first; over CTS, the three ID bits and the seven address bits of a control frame
//! (never the start bit), and over the eight bits of each data byte.
//!
//! ```text
//!  per bit: fb = in ^ c3;  c = (c << 1) & 0xf;  if fb { c ^= 0x3 }   (taps x^1, x^0)
//! ```

/// The CRC4 generator x^4 + x + 1 with its x^4 term.
pub const POLY4: u8 = 0x13;

/// First read-only address: 0x00..=0x40 are writable.
pub const FIRST_READ_ONLY: u8 = 0x41;

/// Bank select register.
pub const BSEL: u8 = 0x40;
/// EDS bank register.
pub const EDS_BANK: u8 = 0x41;
/// First profile ID byte.
pub const PROFILE_ID: u8 = 0x42;
/// First serial number byte.
pub const SERIAL_NUMBER: u8 = 0x44;
/// First device ID byte.
pub const DEVICE_ID: u8 = 0x78;
/// First manufacturer ID byte.
pub const MANUFACTURER_ID: u8 = 0x7E;

/// One step of the CRC4 register: shifts in `bit`.
#[inline]
pub fn crc4_step(crc: u8, bit: bool) -> u8 {
    let fb = bit ^ (crc & 0x8 != 0);
    let c = (crc << 1) & 0xf;
    if fb {
        c ^ (POLY4 & 0xf)
    } else {
        c
    }
}

/// CRC4 (start 0, not inverted) of the `nbits` low bits of `value`, MSB first.
pub fn crc4(value: u64, nbits: u32) -> u8 {
    (0..nbits)
        .rev()
        .fold(0, |c, i| crc4_step(c, value >> i & 1 != 0))
}

/// Whether a write to `addr` is performed (0x00..=0x40).
pub fn writable(addr: u8) -> bool {
    addr & 0x7f < FIRST_READ_ONLY
}

/// The identification registers of the standard map (0x41..0x47, 0x78..0x7F).
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct BissIdent {
    /// Device ID, 0x78..0x7D (first byte at 0x78).
    pub device_id: [u8; 6],
    /// Manufacturer ID, 0x7E..0x7F (first byte at 0x7E).
    pub manufacturer_id: [u8; 2],
    /// Profile ID, 0x42 (low byte) and 0x43 (high byte).
    pub profile_id: u16,
    /// Serial number, 0x44 (least significant byte) .. 0x47.
    pub serial_number: u32,
    /// First EDS bank, 0x41 (0: no EDS).
    pub eds_bank: u8,
}

impl Default for BissIdent {
    /// Device ID "SINDEC", manufacturer ID "SD", profile 0, serial 0, no EDS.
    fn default() -> Self {
        Self {
            device_id: *b"SINDEC",
            manufacturer_id: *b"SD",
            profile_id: 0,
            serial_number: 0,
            eds_bank: 0,
        }
    }
}

impl BissIdent {
    /// The 128 bytes of the register file after power-up.
    pub fn image(&self) -> [u8; 128] {
        let mut m = [0u8; 128];
        m[EDS_BANK as usize] = self.eds_bank;
        m[PROFILE_ID as usize..PROFILE_ID as usize + 2]
            .copy_from_slice(&self.profile_id.to_le_bytes());
        m[SERIAL_NUMBER as usize..SERIAL_NUMBER as usize + 4]
            .copy_from_slice(&self.serial_number.to_le_bytes());
        m[DEVICE_ID as usize..DEVICE_ID as usize + 6].copy_from_slice(&self.device_id);
        m[MANUFACTURER_ID as usize..MANUFACTURER_ID as usize + 2]
            .copy_from_slice(&self.manufacturer_id);
        m
    }

    /// An ASCII ID of at most `n` printable characters, padded with 0 bytes.
    pub fn ascii_id<const N: usize>(s: &str) -> Option<[u8; N]> {
        if s.len() > N || !s.bytes().all(|b| (0x20..0x7f).contains(&b)) {
            return None;
        }
        let mut a = [0u8; N];
        a[..s.len()].copy_from_slice(s.as_bytes());
        Some(a)
    }
}
