//! Front-end correction: per-channel offset and gain correction
//! x' = (x - b) * g with g = 1/m (the thesis's two-point calibration, eqs. 3.3-3.6),
//! static from the config or updated online by an automatic calibration that tracks the
//! peaks of each channel over whole signal periods (as interpolator ICs do), and an
//! optional static correction of the cos track's phase error. Mode `auto` is the
//! least-squares ellipse fit (offset, gain and phase at any speed): model [`fit`], RTL
//! [`fit_hdl`] and [`fit_solve`]; mode `peak` is the peak tracker below ([`autocal`]).
//! Figures in docs/correction.md.
//!
//! ```text
//!            stage 1 (reg)              stage 2 (reg)        stage 3 (reg)
//!  in_sin ─►[sext]─► d = x - b ─► sign ─────────► sign ──► r = (P + 2^(GF-1)) >> GF
//!                         │       |d| ─┐                    saturate to A bits,
//!                         │       g ───┴─► P = |d| * g ───► apply sign ──────────► out_sin
//!  (same for in_cos)      │                  16x16->32
//!                         ▼  u = x + 2^(A-1), sign(d) of both channels
//!              ┌──────────────────────────────────────────────────────┐
//!              │ AutoCal (only in auto mode)                          │
//!              │  quadrant tracker: net +-1 per adjacent step,        │
//!              │  period = net reaches +-4; max/min of u per channel  │
//!              │  window of K periods -> snapshot -> serial divider   │
//!              │  (sin then cos, 32 + 32 clocks) -> b, g registers ───┼──► b, g (stage 1)
//!              └──────────────────────────────────────────────────────┘
//!
//!  Phase correction (only when k != 0; PhaseCos replaces the cos track after stage 1):
//!            stage 2 (reg)            stage 3 (reg)            stage 4 (reg)          stage 5 (reg)
//!  |d_c|,g_c ─► P_c = |d_c| g_c >> s ─┐
//!                         sign(d_c) ──┤ S' = (P_c or !P_c) ─► r = floor((S' + n + ─► hi ? max :
//!  |d_s|, k ──► Q = |d_s| |k| >> s ───┤     + (Q or !Q)          2^(F-1)) / 2^F)    lo ? min :
//!               sign(d_s) ^ sign(k) ──┘ n = number of !     hi = S' >= H_n,        r ──► out_cos
//!                                                           lo = S' < L_n
//!  stage-3 sine result ──────────────────────────────────────► register ─────► register ► out_sin
//!
//!  Shift-add products (modes auto and peak, and static mode with a code not 0 or a power of
//!  two): every `*` above becomes
//!  |d|, code ─► MulTree: 3 register levels of pairwise sums ─► (x + y) into the product
//!  register; sign and valid delayed 3 clocks beside it (multree.rs; the code is the
//!  constant, or in auto/peak mode the register g (|k| from the fit) beside |d|).
//! ```
//!
//! # Datapath and bit growth (A = ADC width 10..=16, GF = gain fraction bits 8..=15)
//! * x, b in [-2^(A-1), 2^(A-1)-1] (b is an integer offset in LSB).
//!   d = x - b in [-(2^A - 1), 2^A - 1]: A+1 bits signed, exact in a 32-bit word; its sign
//!   is bit A, so the sign test needs a carry chain of A+1 bits, not 32.
//! * Sign/magnitude: |d| <= 2^A - 1 <= 2^16 - 1 fits the unsigned 16-bit multiplier operand
//!   (rust-hdl's only multiply is `Bits<16> * Bits<16> -> Bits<32>`, emitted as a Verilog
//!   `*` with a 32-bit destination, so the product is never truncated). Signed operands are
//!   never multiplied: the sign bypasses the multiplier.
//! * g: 16-bit unsigned, UQ(16-GF).GF, value g / 2^GF in [0, 2^(16-GF)) (GF = 14: [0, 4)).
//! * P = |d| * g <= (2^16 - 1)^2 = 2^32 - 2^17 + 1, and P + 2^(GF-1) <= 2^32 - 2^17 + 1 +
//!   2^14 < 2^32: the rounding add cannot overflow the 32-bit word.
//! * r = floor((P + 2^(GF-1)) / 2^GF) = |d| g / 2^GF rounded half up; with the sign applied
//!   afterwards the rule is **round half away from zero**:
//!   `x' = sgn(d) * floor(|d| g / 2^GF + 1/2)`.
//! * Saturation (never wraps): d >= 0: x' = min(r, 2^(A-1) - 1); d < 0:
//!   x' = -min(r, 2^(A-1)).
//! * Products ([`CorrectionParams::shift_add`]): pipelined shift-add trees ([`multree`]:
//!   partial products (|d| << i) AND bit i of the code, three register levels of pairwise
//!   sums, the last sum into the product register), exact (the same 32-bit word as
//!   `|d| * g`), one carry chain per register stage (with a run-time code one LUT level
//!   ahead of the first), 3 more clocks. In modes `auto` and `peak` the codes are run-time
//!   registers (g, and the fit's |k|), so every product is a run-time tree; in static mode
//!   a constant code (g_s, g_c, or |k| of the phase stage) that is neither 0 nor a power
//!   of two gets a constant tree (only its one bits cost adders). An inferred multiplier
//!   would be a combinational hard block: on the ECP5 proxy flow Yosys leaves MULT18X18D's
//!   own registers unused, so a register -> multiplier -> register path alone stays near
//!   141-147 MHz (docs/correction.md), below the timing rule's 1.25 x 133.33 MHz
//!   (docs/timing.md). Static codes 0 and powers
//!   of two are wiring, so static unity-gain designs keep the one-stage product
//!   `|d| * g` (a Verilog `*` of a constant, a shift), bit for bit.
//! * Latency: 3 clocks (5 with phase correction, below; 3 more with shift-add products,
//!   so 6 in mode `peak` and 8 in mode `auto`).
//!   A sample presented with
//!   `in_valid` before rising edge k appears on `out_*` with `out_valid` after edge
//!   k + latency - 1 (k+2 at 3 clocks); one sample per clock (back-to-back) is fine
//!   (in `auto` mode the fit's tracker needs them three clocks apart: `fit_hdl.rs`).
//!   `g` travels with the sample through stage 1, so a calibration update never mixes an
//!   old offset with a new gain within one sample.
//!
//! # Phase correction of the cos track (static mode, `phase_deg`)
//! * Signal model: sin = A_s sin(t) + b_s, cos = A_c cos(t + phi) + b_c (phi > 0: the cos
//!   track leads). After offset and gain, sin' = g_s d_s = T sin(t) and
//!   cos' = g_c d_c = T cos(t + phi) = T (cos t cos phi - sin t sin phi), so
//!   T cos t = (cos' + sin' sin phi) / cos phi. Written with the raw differences:
//!   **x_c' = (g_c / cos phi) d_c + (g_s tan phi) d_s**: the factor 1 / cos phi folds into the
//!   cos gain code and the sine term needs one more coefficient, k = g_s tan phi. So the
//!   datapath is two products and one signed sum with a single rounding, not a product
//!   of the sum. The config computes both codes once ([`phase_codes`]):
//!   g_c = round(2^GF gain_cos / cos phi) (must fit 16 bits) and
//!   k = round(2^GF gain_sin tan phi), signed, |k| <= 65535 (|phi| <= 15 deg and
//!   gain_sin < 4 give |k| < 0.27 * 2^16). Code rounding: relative errors <= 2^-(GF+1)
//!   of each coefficient (GF = 14: 3e-5, 0.2 LSB at 6000 LSB).
//! * Products (stage 2): P_c = floor(|d_c| g_c / 2^s), Q = floor(|d_s| |k| / 2^s), both
//!   unsigned 16 x 16 -> 32, with s = max(0, A - 14): each is <= (2^A - 1)(2^16 - 1) / 2^s
//!   < 2^(A+16-s) <= 2^30, so |S| <= P_c + Q < 2^31 and the signed sum fits the 32-bit word.
//!   A <= 14: s = 0 and the sum is exact; A = 15, 16: the truncation costs less than
//!   2 / 2^F LSB. F = GF - s >= 6 fraction bits remain.
//! * Sum (stage 3): the signs are applied as ones' complements, -X = !X + 1, so
//!   S' = (P_c or !P_c) + (Q or !Q) = S - n is one adder, n = [d_c < 0] + [d_s k < 0]
//!   (0..=2) is carried to stage 4. |S| + 2 < 2^31, so S' never wraps.
//! * Round and saturate (stages 4 and 5): **x_c' = clamp(floor((S + 2^(F-1)) / 2^F), -2^(A-1),
//!   2^(A-1) - 1)**: round half up (ties towards +infinity; the other channel and the path
//!   without phase round half away from zero; the two differ only on exact ties). One
//!   adder S' + (2^(F-1) + n), the three constants for n = 0, 1, 2 selected by the two sign
//!   bits; the result is bits F..F+A-1 of the 32-bit word (A + F <= 31, so a wrapped word
//!   still gives the right A bits). Saturation is two compares of S' beside the adder, no
//!   carry chain after another: high when S >= 2^(A-1+F) - 2^(F-1), low when
//!   S < -2^(A-1+F) - 2^(F-1), each constant moved by -n (H_n, L_n) and compared with the
//!   sign bits flipped (two's complement order as unsigned order).
//! * The stage-4 constants for n are selected in stage 3 from the registered negation bits
//!   and registered, so the adder and the two compares of stage 4 see only registers.
//! * Why the compares stay 32 bits wide and are registered instead: S' uses the whole word
//!   (P_c and Q each reach 2^30 - 2^17 + 1 with A = 14 and the largest codes, so
//!   |S'| < 2^31 needs all 32 bits; only a static design with known codes has spare top
//!   bits, 2 at gains near 1). The limits' low F bits (2^(F-1) + n below a multiple of 2^F)
//!   differ with n, so the carry out of the low F bits decides a sample exactly at a limit
//!   and a shorter compare still needs an F-bit chain plus wide AND/OR terms of the upper
//!   32 - F bits and one more LUT level to combine them. So stage 4 registers the rounded
//!   code r (A bits) and the two compare results straight from their carry chains, and
//!   stage 5 only selects (low wins; the two exclude each other since L_n < H_n). Each
//!   path is one carry chain between registers, or one LUT.
//! * The sine track is not changed; its stage-3 result is delayed two registers. Latency:
//!   5 clocks with phase correction ([`PHASE_EXTRA_CYCLES`]), 8 with shift-add products
//!   (the static codes g_c / cos phi and k are rarely powers of two; mode `auto` always,
//!   its codes being run-time); the one place it is
//!   derived is [`CorrectionParams::latency_cycles`]. k = 0 (phase_deg = 0) builds no phase
//!   stage at all: the block is the 3-clock block above, bit for bit.
//! * Not with the automatic calibration: its peak-derived g_c would drop 1 / cos phi.
//!
//! # Peak-tracking calibration (mode `peak`; the ellipse fit of mode `auto` is documented in
//! [`fit`], [`fit_hdl`] and [`fit_solve`])
//! * Offset binary u = x + 2^(A-1) (sign bit flipped): u in [0, 2^A - 1], so max/min are
//!   unsigned compares.
//! * Period detection: the quadrant of each sample from the signs of d = x - b of both
//!   channels (the current offset estimate centres it), with the CORDIC mapper's convention
//!   q = {sign(sin), sign(sin) ^ sign(cos)}. step = (q - q_prev) mod 4: 1 -> net += 1,
//!   3 -> net -= 1, 0 -> nothing, 2 (ambiguous, both signs flipped) -> the window is
//!   discarded. After reset or a discard the tracker waits for the next quadrant boundary
//!   (a +-1 step) and opens the window at that sample, so every window runs from boundary
//!   to boundary. A period is complete when net reaches +4 or -4: the vector has gone
//!   once around in either direction, so both channels have passed their positive and
//!   negative peaks (the peaks of one channel are the other's zero crossings, i.e. the
//!   boundaries). Chatter at a zero crossing (noise) only adds +1 -1; no hysteresis is
//!   needed because only the net count matters.
//! * Window: K periods (`periods`, 1..=256). max/min of u per channel over the window
//!   (the sample that completes a window also starts the next one). At the window's end,
//!   if the divider is idle, max/min are copied to snapshot registers; if it is busy (only
//!   when K periods take fewer than 66 clocks) the window is dropped.
//! * From the snapshot: S = max - min (span, 0..2^A - 1), centre
//!   b = floor((max_u + min_u + 1) / 2) - 2^(A-1) (the mean of the peaks rounded half up),
//!   and g = min(2^16 - 1, floor((T 2^(GF+1) + floor(S/2)) / S)), i.e. T / (S/2) in
//!   UQ.GF rounded to nearest, T = `target_amplitude` in LSB. Dividend
//!   T 2^(GF+1) + S/2 <= (2^15 - 1) 2^16 + 2^15 < 2^32: a 32-bit restoring divider, one
//!   quotient bit per clock, remainder < S < 2^16. One divider serves both channels.
//! * The update is skipped (values kept) unless S >= 2 `min_amplitude` on both channels
//!   (loss of signal, or a window that did not see the peaks).
//! * Timing: a window that completes with the input sample presented before edge k gives
//!   new b and g (both channels at once, `cal_update` high for one clock) after edge
//!   k + 66: 1 (stage 1) + 1 (tracker/snapshot) + 1 (divider set-up) + 32 (sin) + 32 (cos)
//!   - 1. Samples presented from edge k + 67 on use them.
//! * Convergence: b and g come straight from the raw peaks (open loop), so the first
//!   complete window after reset (at most one quadrant to the first boundary, then K
//!   periods, then 66 clocks) already gives the final estimate; later windows track
//!   drift. Peak sampling with n samples per period underestimates each peak by at most
//!   amp (1 - cos(pi/n)) (n = 100: 0.05%, i.e. g 0.05% high); the offset is unaffected
//!   to first order; b is rounded to 1 LSB, so the residual offset is <= 0.5 LSB times g.
//! * Reset (synchronous, active high) restores the configured offsets and gains (they are
//!   also the power-up values) and restarts the tracker; it aborts a division.
pub mod autocal;
pub mod codes;
pub mod fit;
pub mod fit_hdl;
pub mod fit_solve;
pub mod hdl;
pub mod model;
pub mod multree;
pub mod phase;

/// Parameters of the automatic calibration.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct AutoCalParams {
    target_amplitude: u32,
    periods: u32,
    min_amplitude: u32,
}

/// [`crate::error::Error::BlockParams`] for this block: `message` says what is wrong and what
/// is allowed.
fn invalid(message: String) -> crate::error::Error {
    crate::error::Error::block_params("correction", message)
}

impl AutoCalParams {
    /// Target amplitude T (LSB) the corrected signals get.
    pub fn target_amplitude(&self) -> u32 {
        self.target_amplitude
    }
    /// Periods K per window.
    pub fn periods(&self) -> u32 {
        self.periods
    }
    /// Smallest peak amplitude (LSB) that allows an update.
    pub fn min_amplitude(&self) -> u32 {
        self.min_amplitude
    }
}

/// Parameters of the automatic calibration by ellipse fit ([`fit_hdl::FitCal`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct FitCalParams {
    target_amplitude: u32,
    periods: u32,
    min_amplitude: u32,
    min_samples: u32,
}

impl FitCalParams {
    /// Target amplitude T (LSB).
    pub fn target_amplitude(&self) -> u32 {
        self.target_amplitude
    }
    /// Least whole periods K per window.
    pub fn periods(&self) -> u32 {
        self.periods
    }
    /// No update below this amplitude (LSB) on either track.
    pub fn min_amplitude(&self) -> u32 {
        self.min_amplitude
    }
    /// Least samples per window.
    pub fn min_samples(&self) -> u32 {
        self.min_samples
    }
}

/// Parameters of [`hdl::Correction`] and [`model::CorrectionModel`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct CorrectionParams {
    adc_width: u32,
    gain_frac_bits: u32,
    offset: [i32; 2],
    gain: [u32; 2],
    auto: Option<AutoCalParams>,
    /// The ellipse fit (mode `auto`), omitted from the listing when off.
    #[serde(skip_serializing_if = "Option::is_none")]
    fit: Option<FitCalParams>,
    /// Cross coefficient k of the phase correction (signed code, see [`phase_codes`]); 0:
    /// no phase correction and no phase hardware (omitted from the parameter listing).
    #[serde(skip_serializing_if = "is_zero")]
    cross: i32,
    /// Offsets, gains and the cross code are run-time registers the register map reads and
    /// writes ([`codes`]); omitted from the listing when off.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    writable: bool,
}

fn is_zero(v: &i32) -> bool {
    *v == 0
}

/// Largest |phase error| (degrees) the static phase correction accepts.
pub const MAX_PHASE_DEG: f64 = 15.0;

/// Channel index of sine in the `[sin, cos]` arrays.
pub const SIN: usize = 0;
/// Channel index of cosine in the `[sin, cos]` arrays.
pub const COS: usize = 1;

/// Clock cycles from a sample at the input to the corrected sample at the output without
/// phase correction and with one-stage products (static mode, codes 0 or powers of two).
/// The latency of a given block is [`CorrectionParams::latency_cycles`], which adds the
/// phase stage and the shift-add trees: use that.
pub const LATENCY_CYCLES: u32 = 3;

/// Extra clocks of the phase correction (the signed sum of the two cos-track products gets
/// its own stage, and the saturation is decided a stage ahead of its select; module doc).
pub const PHASE_EXTRA_CYCLES: u32 = 2;

/// Extra clocks of the shift-add products (modes `auto` and `peak`, and static mode with a
/// code that is not a power of two, [`CorrectionParams::shift_add`]): the tree's levels
/// ahead of the product register.
pub const SHIFT_ADD_EXTRA_CYCLES: u32 = multree::TREE_LEVELS;

impl CorrectionParams {
    /// Static correction: `adc_width` A = 10..=16; `gain_frac_bits` GF = 8..=15;
    /// `offset` = [b_sin, b_cos] in LSB within the A-bit range; `gain` = [g_sin, g_cos] as
    /// UQ(16-GF).GF codes 0..=65535 (g = round(2^GF / m), see [`gain_code`]).
    pub fn new(
        adc_width: u32,
        gain_frac_bits: u32,
        offset: [i32; 2],
        gain: [u32; 2],
    ) -> crate::error::Result<Self> {
        if !(10..=16).contains(&adc_width) {
            return Err(invalid(format!(
                "correction ADC width {adc_width} bits is out of range: 10..=16"
            )));
        }
        if !(8..=15).contains(&gain_frac_bits) {
            return Err(invalid(format!(
                "gain fraction bits {gain_frac_bits} out of range: 8..=15 (16-bit gain word)"
            )));
        }
        let lim = 1i32 << (adc_width - 1);
        for (name, b) in [("sin", offset[SIN]), ("cos", offset[COS])] {
            if b < -lim || b >= lim {
                return Err(invalid(format!(
                    "{name} offset {b} LSB is outside the {adc_width}-bit range {}..={}",
                    -lim,
                    lim - 1
                )));
            }
        }
        for (name, g) in [("sin", gain[SIN]), ("cos", gain[COS])] {
            if g > 0xffff {
                return Err(invalid(format!(
                    "{name} gain code {g} does not fit 16 bits (max 65535 = {:.5})",
                    65535.0 / (1u32 << gain_frac_bits) as f64
                )));
            }
        }
        Ok(Self {
            adc_width,
            gain_frac_bits,
            offset,
            gain,
            auto: None,
            fit: None,
            cross: 0,
            writable: false,
        })
    }

    /// Unity correction (b = 0, g = 1).
    pub fn identity(adc_width: u32, gain_frac_bits: u32) -> crate::error::Result<Self> {
        let one = 1u32 << gain_frac_bits.min(15);
        Self::new(adc_width, gain_frac_bits, [0, 0], [one, one])
    }

    /// Turns on the automatic calibration (the static offsets/gains become the values
    /// after reset): `target_amplitude` T = 1..=2^(A-1)-1 LSB; `periods` K = 1..=256 signal
    /// periods per update; `min_amplitude` = 1..=2^(A-1)-1 LSB (no update below it).
    pub fn with_auto(
        self,
        target_amplitude: u32,
        periods: u32,
        min_amplitude: u32,
    ) -> crate::error::Result<Self> {
        if self.cross != 0 {
            return Err(invalid(
                "the automatic calibration cannot be combined with the static phase correction"
                    .to_string(),
            ));
        }
        let max = (1u32 << (self.adc_width - 1)) - 1;
        if !(1..=max).contains(&target_amplitude) {
            return Err(invalid(format!(
                "calibration target amplitude {target_amplitude} LSB is out of range: 1..={max}"
            )));
        }
        if !(1..=256).contains(&periods) {
            return Err(invalid(format!(
                "calibration window of {periods} periods is out of range: 1..=256"
            )));
        }
        if !(1..=max).contains(&min_amplitude) {
            return Err(invalid(format!(
                "calibration minimum amplitude {min_amplitude} LSB is out of range: 1..={max}"
            )));
        }
        Ok(Self {
            auto: Some(AutoCalParams {
                target_amplitude,
                periods,
                min_amplitude,
            }),
            ..self
        })
    }

    /// Turns on the automatic calibration by least-squares ellipse fit (offset, gain and
    /// phase; the static offsets/gains become the values after reset): `target_amplitude`,
    /// `periods` and `min_amplitude` as in [`Self::with_auto`], `min_samples` =
    /// 1..=[`fit::N_MAX`] samples per window at least.
    pub fn with_fit(
        self,
        target_amplitude: u32,
        periods: u32,
        min_amplitude: u32,
        min_samples: u32,
    ) -> crate::error::Result<Self> {
        let a = self.with_auto(target_amplitude, periods, min_amplitude)?;
        if !(1..=fit::N_MAX).contains(&min_samples) {
            return Err(invalid(format!(
                "fit window of at least {min_samples} samples is out of range: 1..={}",
                fit::N_MAX
            )));
        }
        Ok(Self {
            fit: Some(FitCalParams {
                target_amplitude,
                periods,
                min_amplitude,
                min_samples,
            }),
            auto: None,
            ..a
        })
    }

    /// The ellipse fit, if on.
    pub fn fit(&self) -> Option<FitCalParams> {
        self.fit
    }

    /// Turns on the static phase correction of the cos track with the signed cross
    /// coefficient code `cross` = round(2^GF g_s tan(phi)), |cross| <= 65535 (0: off). The
    /// cos gain code should already hold g_c / cos(phi) (both from [`phase_codes`]). Not
    /// with the automatic calibration (its gains would drop the 1 / cos(phi) factor).
    pub fn with_phase(self, cross: i32) -> crate::error::Result<Self> {
        if cross.unsigned_abs() > 0xffff {
            return Err(invalid(format!(
                "phase cross coefficient code {cross} does not fit 16 bits and a sign"
            )));
        }
        if cross != 0 && (self.auto.is_some() || self.fit.is_some()) {
            return Err(invalid(
                "phase correction is for static mode: the automatic calibration would replace \
                 the cos gain that carries 1 / cos(phase)"
                    .to_string(),
            ));
        }
        Ok(Self { cross, ..self })
    }

    /// Cross coefficient code k (0: no phase correction).
    pub fn cross(&self) -> i32 {
        self.cross
    }

    /// Makes the offsets, gains and cross code run-time registers ([`codes::CodeRegs`]) that
    /// the register map reads and writes: written values in static mode, start values in
    /// modes `auto` and `peak` (the calibration's next update replaces them). Static mode
    /// then builds the phase stage with a run-time k (whatever `phase_deg` is), so k can be
    /// written; mode `peak` has no phase stage and keeps k = 0.
    pub fn with_writable(self) -> Self {
        Self {
            writable: true,
            ..self
        }
    }

    /// The codes are registers of [`codes::CodeRegs`] (see [`Self::with_writable`]).
    pub fn writable(&self) -> bool {
        self.writable
    }

    /// The cross code k is a run-time value (the fit's, or a writable register), not a
    /// constant of the phase stage.
    pub fn dynamic_cross(&self) -> bool {
        self.fit.is_some() || (self.writable && self.auto.is_none())
    }

    /// The phase stage is built (k != 0, or a run-time k: the ellipse fit's, or a
    /// writable one).
    pub fn has_phase(&self) -> bool {
        self.cross != 0 || self.dynamic_cross()
    }

    /// The codes are run-time values: the calibration (modes `auto` and `peak`) loads the
    /// gains and the fit also the cross code, or the register map writes them
    /// ([`Self::with_writable`]), so every product is a run-time tree
    /// ([`multree::MulTree::run_time`]).
    pub fn run_time_codes(&self) -> bool {
        self.auto.is_some() || self.fit.is_some() || self.writable
    }

    /// The five words of the writable codes after reset, in [`codes::WORDS`] order: the
    /// configured offsets (sign-extended), gains and cross code (sign and magnitude).
    pub fn reset_words(&self) -> [u32; codes::WORDS.len()] {
        let k = if self.auto.is_some() { 0 } else { self.cross };
        [
            self.offset[SIN] as u32,
            self.offset[COS] as u32,
            self.gain[SIN],
            self.gain[COS],
            codes::phase_word(k),
        ]
    }

    /// The products are shift-add trees ([`multree::MulTree`]) instead of multipliers: in
    /// modes `auto` and `peak` (run-time codes, [`Self::run_time_codes`]), and in static
    /// mode (every code a constant) with a gain code, or the phase stage's |k|, that is
    /// neither 0 nor a power of two. A product with a run-time or such a constant code
    /// would map to a hard multiplier, a combinational path that does not meet the timing
    /// rule on the ECP5 proxy flow (docs/correction.md); 0 and powers of two are wiring, so
    /// static unity-gain designs keep the one-stage product.
    pub fn shift_add(&self) -> bool {
        let not_shift = |c: u32| c != 0 && !c.is_power_of_two();
        self.run_time_codes()
            || not_shift(self.gain[SIN])
            || not_shift(self.gain[COS])
            || not_shift(self.cross.unsigned_abs())
    }

    /// Clock cycles from `in_valid` to `out_valid`: [`LATENCY_CYCLES`], plus
    /// [`PHASE_EXTRA_CYCLES`] with phase correction, plus [`SHIFT_ADD_EXTRA_CYCLES`] with
    /// shift-add products. The one place the block's latency is derived; the top, the
    /// fallback, `check` and the reports take it from here.
    pub fn latency_cycles(&self) -> u32 {
        LATENCY_CYCLES
            + if self.has_phase() {
                PHASE_EXTRA_CYCLES
            } else {
                0
            }
            + if self.shift_add() {
                SHIFT_ADD_EXTRA_CYCLES
            } else {
                0
            }
    }

    /// Right shift of the two cos-track products before their signed sum:
    /// max(0, A - 14), so that |sum| < 2^31 (see the module doc).
    pub fn phase_shift(&self) -> u32 {
        self.adc_width.saturating_sub(14)
    }

    /// ADC width A.
    pub fn adc_width(&self) -> u32 {
        self.adc_width
    }
    /// Gain fraction bits GF.
    pub fn gain_frac_bits(&self) -> u32 {
        self.gain_frac_bits
    }
    /// Offsets [sin, cos] in LSB (after reset).
    pub fn offset(&self) -> [i32; 2] {
        self.offset
    }
    /// Gain codes [sin, cos] (after reset).
    pub fn gain(&self) -> [u32; 2] {
        self.gain
    }
    /// Automatic calibration, if on.
    pub fn auto(&self) -> Option<AutoCalParams> {
        self.auto
    }
}

/// Gain code for a correction factor `g` (= 1/m, the inverse of the channel's gain):
/// round(g 2^GF), which must fit 16 bits.
pub fn gain_code(gain_frac_bits: u32, g: f64) -> crate::error::Result<u32> {
    let scale = (1u64 << gain_frac_bits) as f64;
    let c = (g * scale).round();
    // The largest gain whose code fits 16 bits, and the smallest whose code is 1.
    let (max, min) = (65535.5 / scale, 0.5 / scale);
    if c.is_nan() || c < 0.0 {
        return Err(invalid(format!(
            "gain correction {g}: allowed {min} ..< {max} (codes 1..=65535 of 2^-{gain_frac_bits})"
        )));
    }
    if c == 0.0 {
        return Err(invalid(format!(
            "gain correction {g} rounds to code 0 with {gain_frac_bits} fraction bits: every sample would be scaled to 0; use at least {min} (code 1)"
        )));
    }
    if c > 65535.0 {
        return Err(invalid(format!(
            "gain correction {g} rounds to code {c} with {gain_frac_bits} fraction bits, above the 16-bit word's 65535; use less than {max}, or fewer gain_frac_bits"
        )));
    }
    Ok(c as u32)
}

/// Codes of the static phase correction of the cos track by `phase_deg` (phi, the cos
/// track's phase lead: cos = A cos(t + phi)), for the channels' gain corrections `g_sin`,
/// `g_cos` (1/m): returns the cos gain code round(2^GF g_cos / cos(phi)) and the signed cross
/// code round(2^GF g_sin tan(phi)). |phi| <= [`MAX_PHASE_DEG`].
pub fn phase_codes(
    gain_frac_bits: u32,
    g_sin: f64,
    g_cos: f64,
    phase_deg: f64,
) -> crate::error::Result<(u32, i32)> {
    if phase_deg.is_nan() || phase_deg.abs() > MAX_PHASE_DEG {
        return Err(invalid(format!(
            "phase {phase_deg} degrees is out of range: -{MAX_PHASE_DEG}..={MAX_PHASE_DEG}"
        )));
    }
    let phi = phase_deg.to_radians();
    let gc = gain_code(gain_frac_bits, g_cos / phi.cos())?;
    let k = (g_sin * phi.tan() * (1u64 << gain_frac_bits) as f64).round();
    if k.abs() > 65535.0 {
        return Err(invalid(format!(
            "phase cross coefficient {k} (2^GF gain_sin tan(phase)) does not fit 16 bits"
        )));
    }
    Ok((gc, k as i32))
}

/// Two-point calibration (thesis eqs. 3.3-3.6 with the ideal gain mi = 1): reference
/// inputs x_h, x_l (ideal codes) read back as y_h, y_l. ma = (y_h - y_l) / (x_h - x_l),
/// b = y_l - x_l ma; the corrected code is (y - b) / ma. Returns (offset b rounded to an
/// integer LSB, gain code round(2^GF / ma)).
pub fn two_point(
    gain_frac_bits: u32,
    y_h: f64,
    y_l: f64,
    x_h: f64,
    x_l: f64,
) -> crate::error::Result<(i32, u32)> {
    if x_h == x_l || y_h == y_l {
        return Err(invalid(
            "two-point calibration needs two distinct reference points".to_string(),
        ));
    }
    let ma = (y_h - y_l) / (x_h - x_l);
    let b = y_l - x_l * ma;
    Ok((b.round() as i32, gain_code(gain_frac_bits, 1.0 / ma)?))
}

/// The block's entry in the registry (`crate::blocks::registry`).
pub const BLOCK: crate::blocks::registry::BlockDef = crate::blocks::registry::BlockDef::report_only(
    "correction",
    "correction",
    crate::report::jobs::correction_job,
);
