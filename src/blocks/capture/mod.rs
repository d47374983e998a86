//! Synchronous capture: a rising edge of the `capture` input (a drive's PWM centre, say)
//! latches the position every output takes, the velocity estimate, and the age of that
//! position in clocks, from the CONV edge that sampled it to the capture. With
//! `extrapolate` the position is carried forward to the capture instant by velocity x age.
//!
//! ```text
//!  capture ─►[c1]─►[c2]─►[c3]   edge = c2 & !c3 (two synchronizer flops, edge register)
//!                          │
//!  in_valid ─┬─► held (hq, hf, ht) ───────────┐
//!  in_qc/fine/turns ─┘                        │  latch at the edge
//!  in_valid ──► since := L + 1 - 2, else +1 ──┤  (saturating, A bits): the held sample's
//!               (ager := R since, up to H)    │   age at the synchronizer's input
//!  in_velocity (held between strobes) ────────┤
//!                                             ▼
//!   without extrapolate:  out_* := held, age, velocity; out_valid one clock later
//!   with extrapolate:     Start ─► Wait (n + 1) ─► Add ─► Wrap ─► out_*, out_valid
//!                         VelMul: d = q(v ager / 2^(S + B))   (Booth, adds only)
//!                         s = (hq 2^F + hf) + d, wrapped into [0, Q 2^F) with the turns
//! ```
//!
//! # The age
//! * In-valid comes L clocks after the CONV (chip-select) assertion edge that sampled its
//!   sample: L = [`crate::blocks::top::hdl::conv_to_position_cycles`], the one derivation
//!   `check`, `simulate` and the reference's Z tag use. With `in_valid` in clock v the
//!   sample's CONV edge begins clock v - L.
//! * `since` counts the clocks from that edge, less the synchronizer's
//!   [`SYNC_CLOCKS`]: loaded with L + 1 - 2 after `in_valid`, incremented every clock,
//!   saturating at 2^[`AGE_BITS`] - 1 (also its value from reset until the first sample).
//! * A capture pin that rises in clock x is in `c1` from clock x + 1 and in `c2` from
//!   x + 2, where the edge register `c3` still holds 0: the latch happens in clock x + 2
//!   and reads since = (x + 2) - (v - L) - 2 = x - (v - L). So `age` is the number of clock
//!   edges from the sampling CONV edge to the capture, and the capture instant lies in
//!   [age, age + 1) clock periods after the sampling edge (plus the pins' own delays).
//! * A sample that arrives in the two synchronizer clocks is the one latched, with its own
//!   (smaller) age: it is always older than the capture, since L > 2.
//! * An edge while an extrapolation is running ([`CaptureParams::busy_clocks`]) is ignored;
//!   `out_valid` marks every capture taken.
//!
//! # Extrapolation (bit growth)
//! The velocity v (`out_velocity` of `crate::blocks::velocity`) is in 2^-S position LSB per
//! update period of D clocks, so the position moves by v age / (2^S D) LSB in `age` clocks.
//! * The pin rose within the clock after `age` clock edges: the position is carried to
//!   the middle of that clock, age + 1/2 clocks after the sampling edge, so that it is at
//!   most half a clock's motion from the pin's instant.
//! * R = round(2^B / D), |R / 2^B - 1 / D| <= 2^-(B+1); `ager` = R min(since, H) +
//!   floor(R / 2) is kept beside `since` (+R per clock, one adder), H = L + P the horizon
//!   (the oldest a sample gets while the ADC runs, P its period): beyond it the position is
//!   carried H + 1/2 clocks.
//! * v' = floor(v / 2^t), an arithmetic shift (wiring), and d = q(ager v' / 2^(S+B-t))
//!   (round half up) by [`crate::blocks::velocity::VelMul`], the estimator's own
//!   sequential multiplier (n + 1 clocks for n = ceil(Wb / 2) Booth digits of v').
//! * Error against v (age + 1/2) / (2^S D), three parts: the rounding's 1/2; the shift's
//!   floor, below 2^(t-S) (H + 1) / D <= 1/8 LSB with t = floor(log2(2^S D / (8 (H + 1))));
//!   the reciprocal's, |ager - (age + 1/2) 2^B / D| <= (H + 2) / 2 gives |v| 2^-S (H + 2)
//!   2^-(B+1) <= 1/8 LSB with B = ceil(log2(4 Vmax (H + 2))), Vmax = `max_output` / 2^S
//!   (LSB per period). So |error| <= 3/4 LSB, bit-exact in the model and the RTL.
//! * Widths: ager <= H R + R / 2 (operand a, bits(H R + R / 2) + 1); |v| <= `max_output`,
//!   so v' fits min(bits(max_output) + 2, W) - t bits (operand b; W the velocity's width);
//!   |d| <= Dmax = ceil(Vmax (H + 1) / D) + 1 in bits(Dmax) + 2. The multiplier's register, max(Wa, k + 1) + 3 + 2n bits
//!   ([`crate::blocks::velocity::VelMul::register_bits`]), must fit the compiled engine's 64
//!   (57 on the kit with the default velocity). Dmax must stay
//!   below one turn, Q 2^F LSB, so that one wrap step suffices: s = p + d lies in
//!   (-Q 2^F, 2 Q 2^F) in max(pw, bits(Dmax) + 2) + 2 bits (pw = position bits), then
//!   s < 0 takes s + Q 2^F and turns - 1, s >= Q 2^F takes s - Q 2^F and turns + 1 (both
//!   from the registered s, one adder each, then a select).
//!
//! # Latency
//! `out_valid` comes [`CaptureParams::capture_latency`] clocks after the clock in which the
//! pin rises: the two synchronizer clocks, then [`CaptureParams::busy_clocks`] (1 without
//! extrapolation: the latch; n + 5 with it).
//!
//! # Ports
//! | port | dir | width | meaning |
//! |---|---|---|---|
//! | `clk`, `rst` | in | 1 | system clock; synchronous reset, active high |
//! | `capture` | in | 1 | capture request (asynchronous: synchronized here) |
//! | `in_valid`, `in_qc`, `in_fine`, `in_turns` | in | 1, 32 | the position every output takes |
//! | `in_velocity` | in | 64 | the velocity estimate, held between strobes (0 without `[velocity]`) |
//! | `out_valid` | out | 1 | one clock: a capture's values are on `out_*` |
//! | `out_qc`, `out_fine`, `out_turns` | out | 32 | the captured (extrapolated) position |
//! | `out_velocity` | out | 64 | the captured velocity |
//! | `out_age` | out | 32 | clocks from the sample's CONV edge to the capture ([`AGE_BITS`] bits, saturating) |
pub mod block;
pub mod hdl;
pub mod model;

pub use block::{CaptureConfig, BLOCK};

/// Synchronizer clocks of the `capture` input (two flops; the edge register follows).
pub const SYNC_CLOCKS: u32 = 2;
/// Bits of the age counter: it saturates at 2^24 - 1 clocks.
pub const AGE_BITS: u32 = 24;

/// [`crate::error::Error::BlockParams`] for this block.
fn invalid(message: String) -> crate::error::Error {
    crate::error::Error::block_params("capture", message)
}

/// Bits of the unsigned magnitude `v`.
fn bits(v: u128) -> u32 {
    128 - v.leading_zeros()
}

/// The extrapolation's constants (module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Extrapolation {
    /// H: the horizon in clocks.
    pub horizon: u32,
    /// R = round(2^B / D).
    pub recip: u64,
    /// B.
    pub recip_bits: u32,
    /// t: the velocity's arithmetic right shift before the multiply.
    pub vshift: u32,
    /// S + B - t: the multiplier's rounding shift.
    pub shift: u32,
    /// Width of operand a (ager, non-negative, with a sign bit).
    pub a_width: u32,
    /// Width of operand b (the shifted velocity, two's complement).
    pub b_width: u32,
    /// Width of the product d (two's complement).
    pub out_width: u32,
    /// Dmax: the largest |d| at the decoder's maximum speed, LSB.
    pub max_step: u64,
}

/// Parameters of [`hdl::Capture`] and [`model::CaptureModel`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct CaptureParams {
    age_bits: u32,
    latency: u32,
    period: u32,
    quadrants_per_turn: u64,
    fine_bits: u32,
    turns_bits: u32,
    velocity_width: u32,
    extrapolation: Option<Extrapolation>,
}

impl CaptureParams {
    /// `latency`: L, clocks from a CONV assertion edge to `in_valid` of its sample;
    /// `period`: P, clocks between conversions; `quadrants_per_turn`: Q = 4 PPR (a multiple
    /// of 4, at most 2^18); `fine_bits`: F (1..=16); `turns_bits`: M (0..=31); `velocity`:
    /// the estimator's parameters when there is one; `extrapolate`: carry the position to
    /// the capture (needs `velocity`).
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        latency: u32,
        period: u32,
        quadrants_per_turn: u64,
        fine_bits: u32,
        turns_bits: u32,
        velocity: Option<&crate::blocks::velocity::VelocityParams>,
        extrapolate: bool,
    ) -> crate::error::Result<Self> {
        if !(4..=1 << 18).contains(&quadrants_per_turn) || !quadrants_per_turn.is_multiple_of(4) {
            return Err(invalid(format!(
                "quadrants per turn {quadrants_per_turn} must be 4 * PPR in 4..=2^18"
            )));
        }
        if !(1..=16).contains(&fine_bits) || turns_bits > 31 {
            return Err(invalid(format!(
                "fine bits {fine_bits} (allowed 1..=16) or turn bits {turns_bits} (allowed 0..=31)"
            )));
        }
        if latency <= SYNC_CLOCKS || period == 0 || latency + period >= 1 << AGE_BITS {
            return Err(invalid(format!(
                "latency {latency} and period {period} clocks: the latency must exceed {SYNC_CLOCKS} and both fit the {AGE_BITS}-bit age"
            )));
        }
        let extrapolation = match (velocity, extrapolate) {
            (_, false) => None,
            (None, true) => {
                return Err(invalid(
                    "extrapolation needs the velocity estimator ([velocity] enabled)".into(),
                ))
            }
            (Some(v), true) => Some(Self::derive_extrapolation(
                latency,
                period,
                quadrants_per_turn,
                fine_bits,
                v,
            )?),
        };
        Ok(Self {
            age_bits: AGE_BITS,
            latency,
            period,
            quadrants_per_turn,
            fine_bits,
            turns_bits,
            velocity_width: velocity.map_or(0, |v| v.spec.width),
            extrapolation,
        })
    }

    /// The extrapolation's constants for the estimator `v` (module docs).
    fn derive_extrapolation(
        latency: u32,
        period: u32,
        quadrants_per_turn: u64,
        fine_bits: u32,
        v: &crate::blocks::velocity::VelocityParams,
    ) -> crate::error::Result<Extrapolation> {
        let horizon = latency + period;
        let d = v.period_clocks;
        let s = v.spec.frac_bits;
        // Vmax in LSB per update period (at least 1).
        let vmax = (v.max_output as f64 / (1u64 << s) as f64).max(1.0);
        // The velocity's pre-shift t: 2^(t-S) (H + 1) / D <= 1/8 LSB.
        let room = (1u64 << s) as f64 * d as f64 / (8.0 * (horizon + 1) as f64);
        let vshift = if room >= 1.0 {
            room.log2().floor() as u32
        } else {
            0
        };
        let vbits = (bits(v.max_output as u128) + 2).min(v.spec.width);
        let vshift = vshift.min(vbits.saturating_sub(2));
        // The reciprocal's bits B: Vmax (H + 2) 2^-(B+1) <= 1/8 LSB.
        let need = (4.0 * vmax * (horizon + 2) as f64).log2().ceil() as u32;
        let recip_bits = need.max(bits(d as u128) + 2);
        if recip_bits > 62 {
            return Err(invalid(format!(
                "the reciprocal of the {d}-clock update period needs {recip_bits} bits: at most 62"
            )));
        }
        let recip = ((1u128 << recip_bits) as f64 / d as f64).round() as u64;
        let max_step = (vmax * (horizon + 1) as f64 / d as f64).ceil() as u64 + 1;
        let turn = quadrants_per_turn << fine_bits;
        if max_step >= turn {
            return Err(invalid(format!(
                "at the maximum speed the position moves {max_step} LSB in the {horizon}-clock horizon: more than a turn ({turn} LSB)"
            )));
        }
        let shift = s + recip_bits - vshift;
        let a_width = bits(horizon as u128 * recip as u128 + recip as u128 / 2) + 1;
        let b_width = vbits - vshift;
        let reg = crate::blocks::velocity::VelMul::register_bits(a_width, b_width, shift);
        if reg > 64 {
            return Err(invalid(format!(
                "the extrapolation's multiplier needs a {reg}-bit register (operands of {a_width} and {b_width} bits, shift {shift}); the compiled engine handles 64: use fewer velocity.frac_bits or extrapolate = false"
            )));
        }
        Ok(Extrapolation {
            horizon,
            recip,
            recip_bits,
            vshift,
            shift,
            a_width,
            b_width,
            out_width: bits(max_step as u128) + 2,
            max_step,
        })
    }

    /// With an age counter of `bits` bits instead of [`AGE_BITS`] (tests reach its
    /// saturation this way): it must hold L + P, and at most 31 bits.
    pub fn with_age_bits(mut self, bits: u32) -> crate::error::Result<Self> {
        if bits > 31 || (self.latency + self.period) as u64 >= 1u64 << bits {
            return Err(invalid(format!(
                "a {bits}-bit age cannot hold {} clocks (at most 31 bits)",
                self.latency + self.period
            )));
        }
        self.age_bits = bits;
        Ok(self)
    }
    /// Bits of the age counter ([`AGE_BITS`] unless set by `with_age_bits`).
    pub fn age_bits(&self) -> u32 {
        self.age_bits
    }
    /// L: clocks from a CONV assertion edge to `in_valid` of its sample.
    pub fn latency(&self) -> u32 {
        self.latency
    }
    /// P: clocks between conversions.
    pub fn adc_period(&self) -> u32 {
        self.period
    }
    /// Q = 4 PPR.
    pub fn quadrants_per_turn(&self) -> u64 {
        self.quadrants_per_turn
    }
    /// F: fine bits.
    pub fn fine_bits(&self) -> u32 {
        self.fine_bits
    }
    /// M: bits of the turn count.
    pub fn turns_bits(&self) -> u32 {
        self.turns_bits
    }
    /// Bits of the quadrant count.
    pub fn quadrant_bits(&self) -> u32 {
        64 - (self.quadrants_per_turn - 1).leading_zeros()
    }
    /// The block latches a velocity (the top has an estimator).
    pub fn velocity(&self) -> bool {
        self.velocity_width > 0
    }
    /// Width of the velocity word (0 without an estimator): the latch keeps these bits.
    pub fn velocity_width(&self) -> u32 {
        self.velocity_width
    }
    /// The extrapolation's constants, with `extrapolate`.
    pub fn extrapolation(&self) -> Option<&Extrapolation> {
        self.extrapolation.as_ref()
    }
    /// `since` after `in_valid`: L + 1 - [`SYNC_CLOCKS`].
    pub fn since_load(&self) -> u64 {
        (self.latency + 1 - SYNC_CLOCKS) as u64
    }
    /// `ager` for a `since` of `since`: R min(since, H) + floor(R / 2) (0 without
    /// extrapolation).
    pub fn ager_for(&self, since: u64) -> u64 {
        self.extrapolation
            .map_or(0, |e| e.recip * since.min(e.horizon as u64) + e.recip / 2)
    }
    /// Booth digits of the extrapolation's multiply (0 without).
    pub fn mul_steps(&self) -> u32 {
        self.extrapolation
            .map_or(0, |e| crate::blocks::velocity::VelMul::steps(e.b_width))
    }
    /// Clocks from the latch to `out_valid`: 1 without extrapolation; with it the start,
    /// n + 1 multiplier clocks, the add and the wrap (n + 5).
    pub fn busy_clocks(&self) -> u32 {
        match self.extrapolation {
            None => 1,
            Some(_) => self.mul_steps() + 5,
        }
    }
    /// Clocks from the clock in which the pin rises to `out_valid`.
    pub fn capture_latency(&self) -> u32 {
        SYNC_CLOCKS + self.busy_clocks()
    }
    /// Bits of the sum s = p + d (module docs).
    pub fn sum_bits(&self) -> u32 {
        let pw = self.quadrant_bits() + self.fine_bits;
        let ow = self.extrapolation.map_or(0, |e| e.out_width);
        pw.max(ow) + 2
    }
}
