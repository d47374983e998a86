//! QEP fallback and cross-check: a quadrant count kept from the external QEP A/B signals,
//! aligned with the CORDIC counter at low speed and used to resynchronise it at high speed.
//!
//! ```text
//!  qep count ──step──► tracker (qq 0..4PPR-1, qt turns) ──┬─ captured at every conversion
//!   offset (oq, ot) = core - capture (normal mode)        │  start (c1 -> c2, K = 1; the
//!                                                         │  sample the ADC delivers next
//!  conv: CONV, or the inverse of a chip select ───────────┘  is in c2 at its out_valid)
//!                                                         ▼
//!  ADC out_valid ── (sq, st) = c2 ──► at core out_valid: dd = qc - sq (mod 4PPR, signed)
//!                                       active: load core with (sq, st) at every sample
//! ```
//!
//! * Tracker: every clock qq += step (the QEP decoder's registered `up` / `down`: its count's
//!   step at the last edge, -1/0/+1), wrapped into 0..4PPR-1 with the turn count qt.
//! * Each sample is matched to the tracker value at its conversion start, the edge at which
//!   the ADC samples: the rise of the `conv` input, which is the CONV pin (LTC1407A-1,
//!   `adc.frame.conv_active_high`) or the inverse of an active-low chip select (ADS8354,
//!   AD7380: the top inverts it, [`hdl::conv_inverted`], so the capture is at the chip
//!   select's fall, not at its rise, which ends the frame). The ADC's `out_valid` of a
//!   sample comes V clocks after its start ([`crate::blocks::adc::AdcParams::conv_to_valid_clocks`])
//!   and starts come every P clocks, so K = floor((V - 1) / P) later starts have come by
//!   then ([`hdl::capture_depth`]: the ADC's `pipeline`, as the position reference counts its
//!   Z tag, `crate::blocks::reference`). The captures shift through a chain that ends in c2,
//!   K + 1 long: K = 1 (LTC1407A-1, AD7380: one frame of pipeline), (qq, qt) into c1 and c1
//!   into c2 at every start; K = 0 (ADS8354: no pipeline), straight into c2 (c1 is unused
//!   and removed by synthesis); K = 2, through one more register (c0) in front of c1. So
//!   at the ADC's `out_valid` the sample's capture is c2. It waits in (sq, st) for the sample to leave the
//!   core (correction + core latency: 3 + N + 2 clocks unrolled, far shorter than a sample
//!   period). Deep mode (the digit-serial iterative core, whose latency exceeds one ADC
//!   period): the next sample's out_valid comes first, so the capture moves on to
//!   (sq2, st2) and is used from there, and a fallback load is issued when the previous
//!   sample leaves the core, so that the counter applies it to the right sample.
//! * The tracker runs free on the QEP steps; an offset (oq, ot) relates it to the CORDIC
//!   count. Normal mode: at each good core sample the offset is set to (qc - sq, turns - st),
//!   so the QEP count follows the CORDIC count (exact at low speed). After the first
//!   sample, a sample with the overspeed warning or with 2 or more QEP quadrants since the
//!   previous conversion does not set the offset (its CORDIC count may be aliased by whole
//!   periods), so a decoder that starts above the unwrap limit keeps the offset of its first
//!   sample and its position stays consistent with the QEP count; dd = qc - sq - oq with
//!   |dd| > 1 quadrant (after three aligned samples, so that the captures in flight are
//!   consistent) is a QEP/CORDIC disagreement: `mismatch` (a warning). The offset is
//!   assigned, not accumulated, so stale captures cannot add up.
//! * Fallback mode (`active`): entered on the core's overspeed warning or when the tracker
//!   moved 3 or more quadrants between two conversions (speed seen on the QEP lines). A
//!   mismatch alone only raises the warning: at low speed the CORDIC count from good signals
//!   is right, and a faulty comparator line must not move the position; left after
//!   `QUIET_SAMPLES` samples with none of these and with the tracker moving less than 2
//!   quadrants per sample (so the mode never ends above the unwrap limit). While active the offset is frozen, and every sample loads
//!   the core's counter with the capture plus the offset: the core takes the nearest count congruent with
//!   its own quadrant, so the position keeps the CORDIC's fine resolution and the QEP's
//!   count, and the core is in step when the speed falls again.
//! * Compares behind registers: the tests of the motion mv = c2q - prevq and of
//!   dd = kq - oq against the few values that are within 1 (2) of 0 modulo 4PPR are
//!   [`hdl::NearSet`]s: 4-bit chunk compares registered one LUT behind the subtraction, then
//!   an AND per value and an OR over the values (one or two LUTs of flip-flops), the same
//!   results in the same clocks as registering the difference and comparing it. The
//!   mismatch's gate kv2 & aligned == 3 & !act is the register gk beside kv2 (aligned and act
//!   change only at a kv2 pulse or the reset, and the core's out_valid pulses are a sample
//!   apart).
//! * Timing of the capture: c2 changes one clock after a conversion start (the edge is
//!   `conv` against the registered `conv_prev`), and the motion test below has its result
//!   two clocks after that, so the ADC's `out_valid` must come at least three clocks after
//!   a start: V mod P >= 3, refused otherwise by the configuration
//!   (`src/config/derived.rs`). K = 0 puts a 2:1 select (qq or c1) in front of c2; the
//!   chip select's inversion is an inverter in front of `conv_prev` and the edge test.
//! * Widths: 32-bit words holding qq (< 4PPR <= 2^18) and qt (M bits); the captures
//!   (c0, c1, c2) hold the same.
pub mod hdl;

/// The block's entry in the registry (`crate::blocks::registry`).
pub const BLOCK: crate::blocks::registry::BlockDef = crate::blocks::registry::BlockDef::report_only(
    "fallback",
    "QEP fallback",
    crate::report::jobs::fallback_job,
);
