//! Excitation NCO for the capacitive path: a phase accumulator and a quarter-wave
//! sine table giving the two DAC words A sin(wt) and A cos(wt), plus the phase and a strobe
//! so the demodulator gets the carrier value that belongs to each ADC sample.
//!
//! ```text
//!                tick                          ┌────────────┐
//!   rst ─┐        │                   ┌──────┐ │ octant ROM │ tab[j]  ┌────────────────┐
//!        ▼        ▼                   │ fold ├►│ 2^(T-1) x  ├────────►│ unfold swap,   │─►[out_sin]
//!   ┌►[phase reg]─┬── k = top T+2 ───►│ i->j │ │ 2 words    ├────────►│ mirror by q0,  │─►[out_cos]
//!   │   (P bits)  │       bits        └──────┘ └────────────┘ tab[~j] │ negate by q    │
//!   └──── + fw ◄──┘                   └── q = 2 MSBs, octant bit ────►└────────────────┘
//!                 └──────────────────────────────────────────────────────────────────►[out_phase]
//!   tick ────────────────────────────────────────────────────────────────────────────►[out_valid]
//! ```
//!
//! # Stepping: once per `tick`
//! The accumulator advances by the frequency word once per clock in which the `tick` input
//! is high, not every clock. Tie `tick` to the ADC's sample strobe (e.g. 400 kHz out of
//! 50 MHz) and the n-th tick after reset produces exactly the carrier value of sample n, so
//! excitation and demodulation stay synchronous by construction; tie `tick` high to step
//! every clock (`update_hz = clock_hz`). `update_hz` is the tick rate and sets the
//! frequency word.
//!
//! # Exact behaviour
//! * Phase: P-bit accumulator (`phase_bits`, T+2..=32), reset to 0. On a tick:
//!   `phase <= (phase + fw) mod 2^P` with `fw = round(carrier_hz / update_hz * 2^P)`
//!   ([`NcoParams::freq_word`]); the achieved carrier is `fw * update_hz / 2^P`.
//! * Look-up: the top T+2 phase bits `k = phase >> (P - T - 2)` are the quadrant
//!   `q = k >> T` and the index `i = k mod 2^T`. The table holds the first quarter sampled
//!   half a step off the axes, `tab[i] = round(A (2^(W-1) - 1) sin(pi/2 (i + 1/2) / 2^T))`,
//!   so the represented angle is `phi(k) = 2 pi (k + 1/2) / 2^(T+2)` and the four quadrants
//!   follow exactly by mirroring the index (`~i`) and negating:
//!   `sin: q0 +tab[i], q1 +tab[~i], q2 -tab[i], q3 -tab[~i]`,
//!   `cos: q0 +tab[~i], q1 -tab[i], q2 -tab[~i], q3 +tab[i]`.
//!   Hence sin(k) = sin(2^(T+1) - 1 - k) (sin(pi - x)), sin(k + 2^(T+1)) = -sin(k) and
//!   cos(k) = sin(k + 2^T) hold exactly, and sin/cos of one output belong to one angle:
//!   `|sqrt(sin^2 + cos^2) - A (2^(W-1) - 1)| <= sqrt(2)/2` LSB (each word is within
//!   0.5 LSB of the exact value).
//! * Table values are computed exactly with `num-bigint` ([`sine_table`]): pi from
//!   [`crate::exact::pi_fixed`], sin by its Taylor series in 192-bit fixed point (each term
//!   floored, error below 2^-180), the amplitude A taken exactly from its f64 bits, and one
//!   final rounding to nearest with ties away from zero (a tie would need a
//!   transcendental value within 2^-150 of a half integer). No `f64` sin is involved, so
//!   the table is the same on every machine.
//! * Timing (one register stage): the clock edge that samples `tick` loads `out_sin`,
//!   `out_cos`, `out_phase` with the words of the phase *before* the increment and
//!   `out_valid` with 1, so the words and the strobe are valid together during the clock
//!   cycle after that edge ([`LATENCY`] = 1 register). The n-th tick since reset
//!   (n = 0, 1, ...) gives the words of phase `n * fw mod 2^P`. Between strobes the
//!   outputs hold (they drive the DACs). Reset (synchronous) clears phase, strobes and
//!   outputs; a tick in a reset clock is ignored.
//!
//! # Widths
//! Phase P <= 32 bits in a `Bits<32>` word (masked); table T = 4..=12 address bits with
//! W-1 magnitude bits (W = 4..=16); the outputs are W-bit two's complement in the low bits
//! of a `Bits<32>` word (upper bits 0), max magnitude A (2^(W-1) - 1) < 2^(W-1), so
//! negation never overflows.
//!
//! # Table storage (octant fold)
//! Both tab[i] and tab[~i] are needed for every output. Instead of two quarter-table
//! ports, [`hdl::SineRom`] holds the first octant as 2^(T-1) two-word entries
//! (tab[j], tab[2^T-1-j]), j < 2^(T-1): for i < 2^(T-1) it is read at j = i, otherwise at
//! j = ~i (T-1 bits) with the two words swapped. Same words, half the table. The ROM is
//! combinational (an `always @(*) case`, modelled on rust-hdl's `ROM` widget with a
//! run-time address width) and built from logic; see [`hdl::SineRom`] for why not a block
//! RAM. Critical path: phase register -> fold -> table -> swap and quadrant muxes ->
//! W-bit negation -> output register.
//!
//! # Ports of [`hdl::Nco`]
//! ```text
//! clk        in   system clock
//! rst        in   synchronous reset, active high
//! tick       in   advance strobe (one update of the NCO; tie high to run every clock)
//! out_valid  out  high for one clock after each tick (registered with the words)
//! out_sin    out  A sin(phi), W-bit two's complement in Bits<32>
//! out_cos    out  A cos(phi), W-bit two's complement in Bits<32>
//! out_phase  out  the P-bit phase the words belong to (n * fw mod 2^P after tick n)
//! ```
pub mod hdl;
pub mod model;

use num_bigint::BigInt;
use num_traits::{One, ToPrimitive, Zero};

/// Register stages from `tick` to `out_valid` and the words: 1 (they load on the edge that
/// samples `tick`).
pub const LATENCY: u32 = 1;
/// Lowest supported carrier (Hz).
pub const MIN_CARRIER_HZ: f64 = 10e3;
/// Highest supported carrier (Hz).
pub const MAX_CARRIER_HZ: f64 = 1e6;

/// Parameters of [`hdl::Nco`] and [`model::NcoModel`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NcoParams {
    clock_hz: f64,
    update_hz: f64,
    carrier_hz: f64,
    phase_bits: u32,
    table_bits: u32,
    width: u32,
    amplitude: f64,
}

/// [`crate::error::Error::BlockParams`] for this block: `message` says what is wrong and what
/// is allowed.
fn invalid(message: String) -> crate::error::Error {
    crate::error::Error::block_params("nco", message)
}

impl NcoParams {
    /// `clock_hz`: system clock; `update_hz`: tick rate (<= clock_hz, e.g. the ADC sample
    /// rate); `carrier_hz`: 10 kHz..=1 MHz and below update_hz/2; `phase_bits` P:
    /// table_bits+2..=32; `table_bits` T: 4..=12 (2^T entries per quarter wave); `width`
    /// W: 4..=16 bits of the signed output words; `amplitude` A: (0, 1] of full scale
    /// 2^(W-1)-1.
    pub fn new(
        clock_hz: f64,
        update_hz: f64,
        carrier_hz: f64,
        phase_bits: u32,
        table_bits: u32,
        width: u32,
        amplitude: f64,
    ) -> crate::error::Result<Self> {
        let p = NcoParams {
            clock_hz,
            update_hz,
            carrier_hz,
            phase_bits,
            table_bits,
            width,
            amplitude,
        };
        p.validate()?;
        Ok(p)
    }

    /// The paper's excitation: 20 kHz carrier updated at the 400 kHz sample rate, 32-bit
    /// phase, 2^10-entry quarter table, 16-bit words at full scale, at `clock_hz`.
    pub fn paper(clock_hz: f64) -> crate::error::Result<Self> {
        Self::new(clock_hz, 400e3, 20e3, 32, 10, 16, 1.0)
    }

    fn validate(&self) -> crate::error::Result<()> {
        let pos = |v: f64| v.is_finite() && v > 0.0;
        if !pos(self.clock_hz) {
            return Err(invalid(format!(
                "NCO clock {} Hz is not a positive frequency",
                self.clock_hz
            )));
        }
        if !pos(self.update_hz) || self.update_hz > self.clock_hz {
            return Err(invalid(format!(
                "NCO update rate {} Hz must be positive and at most the clock {} Hz \
                 (the NCO advances at most once per clock)",
                self.update_hz, self.clock_hz
            )));
        }
        if !(self.carrier_hz.is_finite()
            && (MIN_CARRIER_HZ..=MAX_CARRIER_HZ).contains(&self.carrier_hz))
        {
            return Err(invalid(format!(
                "NCO carrier {} Hz is out of range: 10 kHz..=1 MHz",
                self.carrier_hz
            )));
        }
        if self.carrier_hz >= self.update_hz / 2.0 {
            return Err(invalid(format!(
                "NCO carrier {} Hz must be below half the update rate ({} Hz / 2 = {} Hz, \
                 Nyquist): raise update_hz or lower carrier_hz",
                self.carrier_hz,
                self.update_hz,
                self.update_hz / 2.0
            )));
        }
        if !(4..=12).contains(&self.table_bits) {
            return Err(invalid(format!(
                "NCO table address bits {} out of range: 4..=12",
                self.table_bits
            )));
        }
        if !(self.table_bits + 2..=32).contains(&self.phase_bits) {
            return Err(invalid(format!(
                "NCO phase accumulator width {} bits out of range: {}..=32 (table bits + 2)",
                self.phase_bits,
                self.table_bits + 2
            )));
        }
        if !(4..=16).contains(&self.width) {
            return Err(invalid(format!(
                "NCO output width {} bits out of range: 4..=16",
                self.width
            )));
        }
        if !(self.amplitude.is_finite() && self.amplitude > 0.0 && self.amplitude <= 1.0) {
            return Err(invalid(format!(
                "NCO amplitude {} out of range: (0, 1] of full scale",
                self.amplitude
            )));
        }
        let fw = self.freq_word();
        if fw == 0 || fw >= 1u64 << (self.phase_bits - 1) {
            return Err(invalid(format!(
                "NCO frequency word {fw} for {} Hz at {} Hz updates with a {}-bit phase \
                 is out of range 1..2^{}: use more phase bits",
                self.carrier_hz,
                self.update_hz,
                self.phase_bits,
                self.phase_bits - 1
            )));
        }
        Ok(())
    }

    /// System clock (Hz).
    pub fn clock_hz(&self) -> f64 {
        self.clock_hz
    }
    /// Tick (update) rate (Hz).
    pub fn update_hz(&self) -> f64 {
        self.update_hz
    }
    /// Requested carrier (Hz).
    pub fn carrier_hz(&self) -> f64 {
        self.carrier_hz
    }
    /// Phase accumulator width P.
    pub fn phase_bits(&self) -> u32 {
        self.phase_bits
    }
    /// Quarter-table address bits T.
    pub fn table_bits(&self) -> u32 {
        self.table_bits
    }
    /// Output word width W.
    pub fn width(&self) -> u32 {
        self.width
    }
    /// Amplitude A as a fraction of full scale.
    pub fn amplitude(&self) -> f64 {
        self.amplitude
    }
    /// Full-scale magnitude 2^(W-1) - 1.
    pub fn full_scale(&self) -> u64 {
        (1u64 << (self.width - 1)) - 1
    }
    /// Ideal peak A (2^(W-1) - 1) in LSB.
    pub fn peak(&self) -> f64 {
        self.amplitude * self.full_scale() as f64
    }
    /// Frequency word fw = round(carrier_hz / update_hz * 2^P) (the quotient is the
    /// correctly rounded f64 one; scaling by 2^P is exact).
    pub fn freq_word(&self) -> u64 {
        let x = self.carrier_hz / self.update_hz * (1u64 << self.phase_bits) as f64;
        x.round().max(0.0) as u64
    }
    /// Achieved carrier fw * update_hz / 2^P (Hz).
    pub fn achieved_hz(&self) -> f64 {
        self.freq_word() as f64 * self.update_hz / (1u64 << self.phase_bits) as f64
    }
    /// Achieved minus requested carrier (Hz); |error| <= resolution / 2.
    pub fn error_hz(&self) -> f64 {
        self.achieved_hz() - self.carrier_hz
    }
    /// Frequency resolution update_hz / 2^P (Hz).
    pub fn resolution_hz(&self) -> f64 {
        self.update_hz / (1u64 << self.phase_bits) as f64
    }
    /// System clocks per update, clock_hz / update_hz (the tick spacing when it is an
    /// integer).
    pub fn clocks_per_update(&self) -> f64 {
        self.clock_hz / self.update_hz
    }
    /// Angle (rad) the words of phase word `phase` represent: 2 pi (k + 1/2) / 2^(T+2)
    /// with k the top T+2 bits.
    pub fn angle_of_phase(&self, phase: u64) -> f64 {
        let k = (phase & crate::blocks::mask(self.phase_bits))
            >> (self.phase_bits - self.table_bits - 2);
        std::f64::consts::TAU * (k as f64 + 0.5) / (1u64 << (self.table_bits + 2)) as f64
    }
    /// The quarter-wave table (see [`sine_table`]).
    pub fn table(&self) -> Vec<u64> {
        sine_table(self.table_bits, self.width, self.amplitude)
    }
}

/// Fractional bits of the exact computation.
const WORK: u32 = 192;

/// sin(x) * 2^WORK for x * 2^WORK given, 0 <= x <= pi/2, by the Taylor series (each term
/// floored; the error is below one unit per term).
fn sin_fixed(x: &BigInt) -> BigInt {
    let x2: BigInt = (x * x) >> WORK;
    let mut term = x.clone();
    let mut sum = x.clone();
    let mut k: u64 = 1;
    while !term.is_zero() {
        term = ((&term * &x2) >> WORK) / BigInt::from((2 * k) * (2 * k + 1));
        if k % 2 == 1 {
            sum -= &term;
        } else {
            sum += &term;
        }
        k += 1;
    }
    sum
}

/// The quarter-wave table: `tab[i] = round(A (2^(W-1) - 1) sin(pi/2 (i + 1/2) / 2^T))` for
/// i in 0..2^T, rounded to nearest (ties away from zero), computed exactly (see the module
/// docs). `amplitude` in (0, 1], `width` 2..=32.
pub fn sine_table(table_bits: u32, width: u32, amplitude: f64) -> Vec<u64> {
    let pi = crate::exact::pi_fixed();
    let full = BigInt::from((1u64 << (width - 1)) - 1);
    // amplitude = mant * 2^exp exactly (a positive normal or subnormal f64).
    let bits = amplitude.to_bits();
    let raw_exp = ((bits >> 52) & 0x7ff) as i64;
    let frac = bits & ((1u64 << 52) - 1);
    let (mant, exp) = if raw_exp == 0 {
        (frac, -1074i64)
    } else {
        (frac | (1u64 << 52), raw_exp - 1075)
    };
    let mant = BigInt::from(mant) * &full;
    // value = sin_fixed * mant * 2^exp / 2^WORK = num / den.
    let shift = WORK as i64 - exp;
    (0..(1u64 << table_bits))
        .map(|i| {
            let x: BigInt = (&pi * BigInt::from(2 * i + 1)) >> (table_bits + 2);
            let mut num = sin_fixed(&x) * &mant;
            let den = if shift >= 0 {
                BigInt::one() << (shift as u64)
            } else {
                num <<= (-shift) as u64;
                BigInt::one()
            };
            // Round half up (values are non-negative): floor((2 num + den) / (2 den)).
            let r: BigInt = (num * 2 + &den) / (den * 2);
            r.to_u64().unwrap_or(u64::MAX)
        })
        .collect()
}

/// The block's entry in the registry (`crate::blocks::registry`).
pub const BLOCK: crate::blocks::registry::BlockDef = crate::blocks::registry::BlockDef::report_only(
    "nco",
    "excitation NCO",
    crate::report::jobs::nco_job,
);
