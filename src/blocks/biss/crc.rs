//! The BiSS single-cycle-data CRC: CRC6, polynomial x^6 + x + 1 (0x43), start value 0,
//! computed MSB first over the data bits, nE and nW (never over Ack, Start or CDS), and sent
//! inverted, MSB first.
//!
//! The hardware computes it serially, one bit per MA rising edge, with the 6-bit linear
//! feedback shift register below; [`crc6_bits`] is the same register in software.
//!
//! ```text
//!          fb ───────┬──────────────┐
//!                    ▼              ▼
//!                  ┌────┐          (+)    ┌────┐   ┌────┐   ┌────┐   ┌────┐
//!                  │ c0 ├──────────►├────►│ c1 ├──►│ c2 ├──►│ c3 ├──►│ c4 ├──┐
//!                  └────┘                 └────┘   └────┘   └────┘   └────┘  │
//!                                                             ┌────┐         │
//!   in ──►(+)──► fb                                           │ c5 │◄────────┘
//!          ▲                                                  └─┬──┘
//!          └────────────────────────────────────────────────────┘
//!  per bit: fb = in ^ c5;  c = (c << 1) & 0x3f;  if fb { c ^= 0x03 }   (taps x^1, x^0)
//! ```
//!
//! After the last message bit the register holds the remainder of
//! `message(x) * x^6 mod (x^6 + x + 1)`; the slave sends `!c & 0x3f`, MSB (c5) first.

/// The generator polynomial x^6 + x + 1 with its x^6 term (iC-Haus notation 0x43).
pub const POLY: u8 = 0x43;

/// The polynomial without its x^6 term: the feedback taps of the 6-bit register.
pub const TAPS: u8 = POLY & 0x3f;

/// Mask of the six CRC bits.
pub const MASK: u8 = 0x3f;

/// One step of the CRC register: shifts in `bit`.
#[inline]
pub fn crc6_step(crc: u8, bit: bool) -> u8 {
    let fb = bit ^ (crc & 0x20 != 0);
    let c = (crc << 1) & MASK;
    if fb {
        c ^ TAPS
    } else {
        c
    }
}

/// CRC6 (start 0, not inverted) of a bit sequence, first bit first.
pub fn crc6_bits<I: IntoIterator<Item = bool>>(bits: I) -> u8 {
    bits.into_iter().fold(0, crc6_step)
}

/// CRC6 (start 0, not inverted) of the `nbits` low bits of `value`, MSB first.
pub fn crc6(value: u64, nbits: u32) -> u8 {
    crc6_bits((0..nbits).rev().map(|i| value >> i & 1 != 0))
}

/// The six CRC bits a BiSS-C slave sends after `data` (`data_bits` wide, MSB first), nE and
/// nW: the inverted CRC6 over data, nE, nW.
pub fn biss_crc(data: u64, data_bits: u32, n_e: bool, n_w: bool) -> u8 {
    let msg = (data << 2) | ((n_e as u64) << 1) | n_w as u64;
    !crc6(msg, data_bits + 2) & MASK
}
