//! Signal monitor: loss of signal, clipping and ADC full scale drive `error`;
//! overspeed and QEP disagreement drive `warning`.
//!
//! ```text
//!  mag_valid ─┐  ┌───────────────────────────────┐ los
//!  magnitude ─┴─►│ mag < los_threshold: low       ├───────┐
//!                │ mag >= los_release:  good      │       │
//!                │ N consecutive low  -> los = 1  │       │
//!                │ N consecutive good -> los = 0  │       ├──OR──► error
//!                │ mag > clip_threshold: clip = 1 │ clip  │
//!                │ H clean samples     -> clip = 0├───────┤
//!                └───────────────────────────reg──┘       │
//!  in_valid ──┐  ┌───────────────────────────────┐ fs     │
//!  in_sin ────┼─►│ sin or cos = -2^(A-1) or      ├───────┘
//!  in_cos ────┘  │ 2^(A-1)-1 -> fs = 1; H clean   │
//!                │ raw samples -> fs = 0          │
//!                └──sin reg | cos reg | hold reg──┘
//!  overspeed ────┐
//!  qep_mismatch ─┴──OR──►[reg]──► warning
//! ```
//!
//! # Exact rules
//! Units: `magnitude` is the CORDIC magnitude, a W-bit unsigned word (W = 1..=32, e.g. the
//! core's x output, |v| K_N 2^G); every threshold is in the same units. All flags are
//! registers updated at the clock edge of the sample that decides them, so an output
//! changes in the output cycle of that sample (one clock after the input is presented).
//! * Loss of signal (`los`): a magnitude sample is *low* if `mag < los_threshold` and *good*
//!   if `mag >= los_release` (`los_release >= los_threshold`: hysteresis in amplitude). A
//!   counter counts consecutive low samples while `los = 0` and consecutive good samples
//!   while `los = 1`; any other sample clears it. `los` sets on the N-th consecutive low
//!   sample and clears on the N-th consecutive good sample (N = `window`). So when the
//!   amplitude drops (e.g. to 10%) at magnitude sample k0, `error` rises at the edge of
//!   sample k0+N-1 (the window's end), never earlier; when it returns at sample k1, `error`
//!   falls at the edge of sample k1+N-1 (if no other flag is set).
//! * After reset `los = 1` (no signal confirmed yet): the first N good samples clear it.
//! * Run-time thresholds (`[registers]`, [`MonitorParams::with_run_time_thresholds`]): the
//!   three thresholds come in on `thr_los`, `thr_rel` and `thr_clip` (the register map's
//!   LOS_THRESHOLD, LOS_RELEASE, CLIP_THRESHOLD, reset to the configured values) and each
//!   magnitude sample is tested against their low W bits in its own clock; the same carry
//!   chains, with a register instead of a constant operand.
//! * Clipping (`clip`): a magnitude sample with `mag > clip_threshold` sets it at once; it
//!   clears on the H-th consecutive magnitude sample at or below the threshold
//!   (H = `hold`).
//! * Full scale (`full_scale`): a raw sample (`in_valid`) with sin or cos at the most
//!   negative (-2^(A-1)) or most positive (2^(A-1)-1) A-bit code sets it at once; it clears
//!   on the H-th consecutive raw sample with neither.
//! * `error = los | clip | full_scale` (combinational OR of registers: `clip` is itself
//!   the OR of two and `full_scale` of three, see below).
//! * `warning` = `overspeed | qep_mismatch`, registered (one clock).
//!
//! # Registers (timing)
//! Every flag changes at the edge of the sample that decides it, but the logic after the
//! inputs is kept short (at most one LUT after a threshold test's or a code test's carry
//! chain; docs/timing.md explains why):
//! * `los` is one register; the window counter and its flags (`los_cnt`, N-1 and N-2
//!   flags) apply each sample's step one clock later from two pending registers (sample
//!   taken, sample counted), so the threshold tests reach only `los` and the pending bit.
//!   `los` is cleared through the flip-flop's synchronous reset (its power-up value 0).
//! * `clip` = (the last magnitude sample over the threshold) | (held by the counter), two
//!   registers loaded on `mag_valid`: the threshold test's carry chain reaches one
//!   flip-flop and nothing else. The hold counter and its H-1 flag apply each magnitude
//!   sample's step one clock later, from registers (as `full_scale`'s below).
//! * `full_scale` = (sine at a full-scale code) | (cosine at one) | (held by the counter),
//!   three registers loaded on `in_valid`. A word is at a full-scale code when its low A-1
//!   bits are all ones (low + 1 carries into bit A-1) and its top bit is 0, or all zeros
//!   (low + 2^(A-1) - 1 does not carry) and its top bit is 1: two carry chains per word and
//!   one LUT of three inputs, a fixed structure Yosys cannot stretch over more levels.
//!   The hold counter applies each raw sample's step one clock later, as the window
//!   counter does.
//!
//! # In the register map (`[registers] enabled`, docs/registers.md)
//! `los`, `clip` and `full_scale` are the live flags LOS, CLIP and FULL_SCALE that STATUS
//! latches (bits 0, 1, 2); the core's overspeed warning and the fallback's disagreement are
//! OVERSPEED and QEP_MISMATCH (bits 3, 4). The ADC frame error is not the monitor's: it is
//! the ADC controller's frame check (`crate::blocks::adc::frame_check`, bit 9), which the
//! top ORs into the outputs' error beside this block's `error`.
//!
//! # Widths
//! Magnitude and thresholds are W-bit unsigned (compared in 32-bit words whose upper bits
//! are masked to 0); the three counters hold 0..N-1, 0..H-1 and 0..H-1 (ceil(log2) bits,
//! masked, so Yosys keeps only those bits). A raw sample is masked to A bits before the code compare.
pub mod hdl;
pub mod model;

/// Parameters of [`hdl::Monitor`] and [`model::MonitorModel`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct MonitorParams {
    adc_width: u32,
    mag_width: u32,
    los_threshold: u64,
    los_release: u64,
    window: u32,
    clip_threshold: u64,
    hold: u32,
    /// The three thresholds come in on ports at run time (`[registers]`), the configured
    /// values being their reset values.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    run_time: bool,
}

/// Bits needed for a counter holding 0..n-1 (at least 1).
pub(crate) fn count_bits(n: u32) -> u32 {
    (32 - n.saturating_sub(1).leading_zeros()).max(1)
}

/// [`crate::error::Error::BlockParams`] for this block: `message` says what is wrong and what
/// is allowed.
fn invalid(message: String) -> crate::error::Error {
    crate::error::Error::block_params("monitor", message)
}

impl MonitorParams {
    /// `adc_width` A = 10..=16; `mag_width` W = 1..=32; `los_threshold` (low below it),
    /// `los_release` (good at or above it, >= los_threshold), `clip_threshold` (clipping
    /// above it, >= los_release, < 2^W), all in magnitude units; `window` N = 1..=65535
    /// magnitude samples; `hold` H = 1..=65535 samples to clear clip/full scale.
    pub fn new(
        adc_width: u32,
        mag_width: u32,
        los_threshold: u64,
        los_release: u64,
        window: u32,
        clip_threshold: u64,
        hold: u32,
    ) -> crate::error::Result<Self> {
        if !(10..=16).contains(&adc_width) {
            return Err(invalid(format!(
                "monitor ADC width {adc_width} bits is out of range: 10..=16"
            )));
        }
        if !(1..=32).contains(&mag_width) {
            return Err(invalid(format!(
                "monitor magnitude width {mag_width} bits is out of range: 1..=32"
            )));
        }
        let top = (1u64 << mag_width) - 1;
        if los_threshold == 0 || los_threshold > top {
            return Err(invalid(format!(
                "loss-of-signal threshold {los_threshold} is out of range: 1..={top} \
                 ({mag_width}-bit magnitude)"
            )));
        }
        if los_release < los_threshold || los_release > top {
            return Err(invalid(format!(
                "loss-of-signal release level {los_release} must be in \
                 {los_threshold}..={top} (>= the threshold)"
            )));
        }
        if clip_threshold < los_release || clip_threshold >= top {
            return Err(invalid(format!(
                "clipping threshold {clip_threshold} must be in {los_release}..{top} \
                 (>= the release level, below the magnitude's full scale)"
            )));
        }
        if !(1..=65535).contains(&window) {
            return Err(invalid(format!(
                "loss-of-signal window {window} samples is out of range: 1..=65535"
            )));
        }
        if !(1..=65535).contains(&hold) {
            return Err(invalid(format!(
                "flag hold {hold} samples is out of range: 1..=65535"
            )));
        }
        Ok(Self {
            adc_width,
            mag_width,
            los_threshold,
            los_release,
            window,
            clip_threshold,
            hold,
            run_time: false,
        })
    }
    /// With the thresholds on the ports `thr_los`, `thr_rel`, `thr_clip` (the register
    /// map's LOS_THRESHOLD, LOS_RELEASE and CLIP_THRESHOLD).
    pub fn with_run_time_thresholds(mut self) -> Self {
        self.run_time = true;
        self
    }
    /// The thresholds come in at run time.
    pub fn run_time_thresholds(&self) -> bool {
        self.run_time
    }
    /// ADC width A.
    pub fn adc_width(&self) -> u32 {
        self.adc_width
    }
    /// Magnitude width W.
    pub fn mag_width(&self) -> u32 {
        self.mag_width
    }
    /// Magnitude below this is low.
    pub fn los_threshold(&self) -> u64 {
        self.los_threshold
    }
    /// Magnitude at or above this is good.
    pub fn los_release(&self) -> u64 {
        self.los_release
    }
    /// Window N in magnitude samples.
    pub fn window(&self) -> u32 {
        self.window
    }
    /// Magnitude above this is clipping.
    pub fn clip_threshold(&self) -> u64 {
        self.clip_threshold
    }
    /// Clean samples H that clear clip / full scale.
    pub fn hold(&self) -> u32 {
        self.hold
    }
}

/// The block's entry in the registry (`crate::blocks::registry`).
pub const BLOCK: crate::blocks::registry::BlockDef = crate::blocks::registry::BlockDef::report_only(
    "monitor",
    "monitor",
    crate::report::jobs::monitor_job,
);
