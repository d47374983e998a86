//! Capacitive-encoder front end (docs/capacitive.md): excitation NCO, band-pass,
//! synchronous quadrature demodulation and low-pass, feeding the full-circle CORDIC core.
//!
//! ```text
//!                 tick                       exc_sin, exc_cos, exc_strobe ──► DACs
//!  in_valid ──┬──────────► ┌─────┐ s_n, c_n (words on the DACs while sample n converted)
//!             │            │ NCO ├──────────────┐ (latched at in_valid: ref_s, ref_c)
//!             │            └─────┘              ▼
//!  in_sample ─┴► sext ─► ┌──────────────────────────────┐ y_n (band-passed)  ┌─────────┐
//!               x_n      │ biquad engine, ONE multiplier│──────────────────►│ demod   │
//!                        │ branch 0: band-pass  (x)     │                   │ ONE mul │
//!     I_{n-1}, Q_{n-1} ─►│ branch 1: low-pass   (I)     │◄── I_n, Q_n ──────┤ 2 clocks│
//!                        │ branch 2: low-pass   (Q)     │                   └─────────┘
//!                        └──────────────┬───────────────┘
//!                                       └─► out_i = LP(I) ~ (A g/2) cos(theta),
//!                                           out_q = LP(Q) ~ (A g/2) sin(theta) ─► core
//! ```
//!
//! Demodulation: the receiver signal is r = A sin(wt + theta). Multiplied by the NCO's
//! sin(wt): (A/2)(cos theta - cos(2wt + theta)); by cos(wt): (A/2)(sin theta +
//! sin(2wt + theta)). The low-pass removes 2w, so atan2(Q, I) = theta, the electrical angle
//! within the signal period, which the full-circle CORDIC core (quadrant mapper + counter)
//! turns into position = period count x 2^(F+2) + angle.
//!
//! Phase: the NCO advances at each ADC sample strobe, so the words on the DACs while
//! conversion n ran are the words before the strobe of sample n; they are latched with the
//! sample (ref_s, ref_c) and used for its demodulation. The filters' group delays appear as
//! a lag of theta that is constant at constant speed.
//!
//! Bit growth (D = capacitive.data_width, W = capacitive.dac_width, A = adc.width):
//! * The ADC sample (A bits) is sign-extended to D bits (D - A bits of headroom for the
//!   band-pass's overshoot).
//! * Demodulation: y (D bits) x s (W bits, |s| <= amplitude (2^(W-1) - 1)) = D + W bits,
//!   shifted right by W - 1 (floor): |I| <= |y| amplitude < 2^(D-1), then saturated to D
//!   bits anyway (a flagged overflow).
//! * The engine (see [`crate::blocks::biquad`]) keeps D + guard_frac bits of state and
//!   saturates; its overflow flag is this block's.
//!
//! Timing per sample: the engine's 8 J + 3 clocks (J sections over all branches), then 2
//! clocks of demodulation; `check` rejects an ADC period shorter than that plus 2.
//!
//! Ports of [`hdl::CapFront`]:
//! ```text
//! clk, rst      in   system clock, synchronous reset (active high)
//! in_valid      in   ADC sample strobe (one per conversion)
//! in_sample     in   ADC sample, A-bit two's complement
//! exc_sin/cos   out  excitation DAC words, W-bit two's complement
//! exc_strobe    out  one clock when new excitation words are out
//! out_valid     out  one clock: new out_i / out_q for the core
//! out_i, out_q  out  low-passed I (~cos theta) and Q (~sin theta), D-bit two's complement
//! overflow      out  with out_valid: a section or the demodulator saturated this sample
//! dropped       out  one clock: a sample came while the engine was busy (lost)
//! ```
pub mod hdl;
pub mod model;

use crate::blocks::biquad::BiquadParams;
use crate::blocks::nco::NcoParams;
use crate::blocks::params::Derived;
use crate::error::{Error, Result};

/// Parameters of the capacitive front end.
#[derive(Clone, Debug)]
pub struct CapFrontParams {
    /// ADC sample width A.
    pub adc_width: u32,
    /// Excitation NCO.
    pub nco: NcoParams,
    /// Biquad engine: branch 0 band-pass, branches 1, 2 low-pass.
    pub engine: BiquadParams,
}

impl CapFrontParams {
    /// From the derived configuration (needs `[capacitive]`).
    pub fn new(d: &Derived) -> Result<Self> {
        let bad = |key: &str, message: String| Error::ConfigValue {
            source_name: "config".into(),
            location: String::new(),
            key: format!("capacitive.{key}"),
            message,
        };
        let k = d
            .capacitive
            .as_ref()
            .ok_or_else(|| bad("", "the capacitive front end needs [capacitive]".into()))?;
        let c = &k.config;
        let nco = NcoParams::new(
            d.clock_hz,
            k.sample_rate_hz,
            c.carrier_hz,
            c.phase_bits,
            c.table_bits,
            c.dac_width,
            c.amplitude,
        )
        .map_err(|m| bad("carrier_hz", m.detail()))?;
        let secs = |s: &crate::filter::Sos| -> Vec<[i64; 5]> {
            s.sections
                .iter()
                .map(|x| [x.b[0], x.b[1], x.b[2], x.a[0], x.a[1]])
                .collect()
        };
        let lp = secs(&k.lowpass.sos);
        let engine = BiquadParams::new(
            c.data_width,
            c.coef.width,
            c.coef.frac,
            c.guard_frac,
            vec![secs(&k.bandpass.sos), lp.clone(), lp],
        )
        .map_err(|e| match e {
            // The engine names its own parameter: map it onto the config key.
            Error::ConfigValue { key, message, .. } => {
                let key = match key.as_str() {
                    "coef_width" => "coef.width",
                    "coef_frac" => "coef.frac",
                    "data_width" => "data_width",
                    "guard_frac" => "guard_frac",
                    k if k.starts_with("branches[0]") => "bandpass",
                    k if k.starts_with("branches[") => "lowpass",
                    _ => "coef",
                };
                bad(key, message)
            }
            e => e,
        })?;
        let p = CapFrontParams {
            adc_width: d.adc.frame.width,
            nco,
            engine,
        };
        if p.cycles_per_sample() + 2 > d.adc.period_clocks {
            return Err(bad(
                "lowpass.order",
                format!(
                    "the filters need {} clocks per sample (biquad engine {} + demodulation 2) but the ADC delivers one every {} clocks: use fewer sections (`capacitive.lowpass.order`, `capacitive.bandpass.order`) or a faster clock (`clock.frequency_hz`)",
                    p.cycles_per_sample(),
                    p.engine.cycles_per_sample(),
                    d.adc.period_clocks
                ),
            ));
        }
        Ok(p)
    }

    /// Clocks the front end needs per sample: the engine's plus the demodulation.
    pub fn cycles_per_sample(&self) -> u32 {
        self.engine.cycles_per_sample() + 2
    }

    /// Data width D.
    pub fn data_width(&self) -> u32 {
        self.engine.data_width
    }

    /// Clocks from in_valid to out_valid (the engine's latency).
    pub fn latency(&self) -> u32 {
        self.engine.latency()
    }
}

/// The block's entry in the registry (`crate::blocks::registry`).
pub const BLOCK: crate::blocks::registry::BlockDef = crate::blocks::registry::BlockDef::report_only(
    "capfront",
    "capacitive front end (NCO + engine + demod)",
    crate::report::jobs::capfront_job,
);
