//! Ideal vs quantized magnitude response.

use super::{cascade_gain, FilterSpec, IdealSection, Sos};

/// Number of points of the uniform pass-band grid (end points included) on which the
/// maximum deviation is measured.
pub const PASSBAND_GRID: usize = 4097;

/// Gain of both cascades at one probe frequency.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Probe {
    /// Frequency in Hz.
    pub freq_hz: f64,
    /// Attenuation of the ideal cascade, dB (`-20 log10 |H|`, positive = attenuated).
    pub ideal_atten_db: f64,
    /// Attenuation of the quantized cascade, dB.
    pub quantized_atten_db: f64,
}

/// Response figures of a designed filter (ideal f64 vs quantized integer cascade).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Response {
    /// Pass band `[lo, hi]` in Hz over which the deviation is measured.
    pub passband_hz: [f64; 2],
    /// Points of the uniform pass-band grid ([`PASSBAND_GRID`]).
    pub grid_points: usize,
    /// Maximum over the grid of `|20 log10 |Hq| - 20 log10 |Hi||`, dB.
    pub max_passband_dev_db: f64,
    /// Frequency (Hz) where that maximum occurs.
    pub max_passband_dev_hz: f64,
    /// Pass-band centre (Hz) where every ideal section has unity gain.
    pub centre_hz: f64,
    /// Ideal cascade gain at the centre, dB (0 by construction, up to rounding).
    pub centre_gain_ideal_db: f64,
    /// Quantized cascade gain at the centre, dB.
    pub centre_gain_quantized_db: f64,
    /// Ideal cascade gain at DC (linear; 1 for a low-pass, 0 for high-/band-pass).
    pub dc_gain_ideal: f64,
    /// Quantized cascade gain at DC (linear; exactly 0 for high-/band-pass: exact zeros).
    pub dc_gain_quantized: f64,
    /// Largest pole radius over the ideal sections.
    pub max_pole_radius_ideal: f64,
    /// Largest pole radius over the quantized sections.
    pub max_pole_radius_quantized: f64,
    /// Attenuation at the probe frequencies.
    pub probes: Vec<Probe>,
}

fn db(g: f64) -> f64 {
    20.0 * g.log10()
}

impl Response {
    /// Evaluates `ideal` and `sos` for the validated `spec` (probes in `[0, fs/2]`).
    pub fn compute(
        spec: &FilterSpec,
        ideal: &[IdealSection],
        sos: &Sos,
        probes_hz: &[f64],
    ) -> Response {
        let fs = spec.sample_rate_hz;
        let quant = sos.to_ideal();
        let [lo, hi] = spec.passband_hz();
        let mut max_dev = 0.0f64;
        let mut max_dev_hz = lo;
        for i in 0..PASSBAND_GRID {
            let f = lo + (hi - lo) * i as f64 / (PASSBAND_GRID - 1) as f64;
            let gi = cascade_gain(ideal, f, fs);
            let gq = cascade_gain(&quant, f, fs);
            let d = (db(gq) - db(gi)).abs();
            // The pass band contains no zero of either cascade (zeros only at z = +-1,
            // outside the open bands), so both dB values are finite.
            if d > max_dev {
                max_dev = d;
                max_dev_hz = f;
            }
        }
        let centre = spec.centre_hz();
        Response {
            passband_hz: [lo, hi],
            grid_points: PASSBAND_GRID,
            max_passband_dev_db: max_dev,
            max_passband_dev_hz: max_dev_hz,
            centre_hz: centre,
            centre_gain_ideal_db: db(cascade_gain(ideal, centre, fs)),
            centre_gain_quantized_db: db(cascade_gain(&quant, centre, fs)),
            dc_gain_ideal: cascade_gain(ideal, 0.0, fs),
            dc_gain_quantized: cascade_gain(&quant, 0.0, fs),
            max_pole_radius_ideal: ideal.iter().map(|s| s.pole_radius()).fold(0.0, f64::max),
            max_pole_radius_quantized: sos
                .sections
                .iter()
                .map(|s| s.pole_radius(sos.format))
                .fold(0.0, f64::max),
            probes: probes_hz
                .iter()
                .map(|&f| Probe {
                    freq_hz: f,
                    ideal_atten_db: -db(cascade_gain(ideal, f, fs)),
                    quantized_atten_db: -db(cascade_gain(&quant, f, fs)),
                })
                .collect(),
        }
    }

    /// Markdown table: quantity | ideal | quantized.
    pub fn to_markdown(&self) -> String {
        let mut s = String::from("| quantity | ideal | quantized |\n|---|---|---|\n");
        s += &format!(
            "| max pass-band deviation, quantized vs ideal ({} points, {:.1}-{:.1} Hz) | - | {:.6} dB at {:.1} Hz |\n",
            self.grid_points,
            self.passband_hz[0],
            self.passband_hz[1],
            self.max_passband_dev_db,
            self.max_passband_dev_hz
        );
        s += &format!(
            "| gain at centre {:.1} Hz | {:.6} dB | {:.6} dB |\n",
            self.centre_hz, self.centre_gain_ideal_db, self.centre_gain_quantized_db
        );
        s += &format!(
            "| DC gain (linear) | {:.6} | {:.6} |\n",
            self.dc_gain_ideal, self.dc_gain_quantized
        );
        for p in &self.probes {
            s += &format!(
                "| attenuation at {:.1} Hz | {:.3} dB | {:.3} dB |\n",
                p.freq_hz, p.ideal_atten_db, p.quantized_atten_db
            );
        }
        s += &format!(
            "| max pole radius | {:.9} | {:.9} |\n",
            self.max_pole_radius_ideal, self.max_pole_radius_quantized
        );
        s
    }
}
