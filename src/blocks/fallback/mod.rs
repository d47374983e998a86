//! QEP fallback and cross-check: a quadrant count kept from the external QEP A/B signals,
//! aligned with the CORDIC counter at low speed and used to resynchronise it at high speed.
//!
//! ```text
//!  qep count ──step──► tracker (qq 0..4PPR-1, qt turns) ──┬─ captured at every CONV rise
//!   offset (oq, ot) = core - capture (normal mode)        │  (c1 -> c2: the conversion whose
//!                                                         │   data the ADC delivers next)
//!                                                         ▼
//!  ADC out_valid ── (sq, st) = c2 ──► at core out_valid: dd = qc - sq (mod 4PPR, signed)
//!                                       active: load core with (sq, st) at every sample
//! ```
//!
//! * Tracker: every clock qq += step (the QEP decoder's registered `up` / `down`: its count's
//!   step at the last edge, -1/0/+1), wrapped into 0..4PPR-1 with the turn count qt.
//! * Each sample is matched to the tracker value at its conversion: (qq, qt) is captured at
//!   every CONV rise into c1, c1 moves to c2, and the ADC delivers the data of the
//!   conversion before the last CONV (LTC1407A-1: one frame of pipeline), so at the ADC's
//!   `out_valid` the sample's capture is c2. It waits in (sq, st) for the sample to leave the
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
//! * Widths: 32-bit words holding qq (< 4PPR <= 2^18) and qt (M bits).
pub mod hdl;

/// The block's entry in the registry (`crate::blocks::registry`).
pub const BLOCK: crate::blocks::registry::BlockDef = crate::blocks::registry::BlockDef::report_only(
    "fallback",
    "QEP fallback",
    crate::report::jobs::fallback_job,
);
