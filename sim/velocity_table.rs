//! Table 4-1 of the thesis by simulation: the encoder model at a constant speed, its
//! position sampled at the 7.5 kHz servo rate with white position noise, truncated to
//! 16 bits per turn, through the bit-accurate velocity estimators
//! (`crate::blocks::velocity::model::Estimator`) with the thesis's parameters; measured
//! mean and variance next to the thesis's and to the variance each estimator's impulse
//! response predicts (`docs/velocity.md`, "Table 4-1").
//!
//! The noise stands in for what the thesis's recorded motor data had (speed ripple and
//! decoder noise): its level sigma_n is set so that the 19-bit difference has the thesis's
//! variance, 0.3102 counts^2 (16-bit counts per sample): 2 sigma_n^2 + 2 (1/8)^2 / 12 = 0.3102.
//!
//! Prediction: every estimator is linear in the position (Kalman after its 12 transient
//! gains), y = sum_j g_j theta_q(k - j), and theta_q = theta + n - e with white n (variance
//! sigma_n^2) and a truncation error e that the noise (sigma_n = 0.39 counts) makes close to
//! uniform and white (variance 1/12). The constant speed passes with gain 1, so
//! mean = v and var = (sigma_n^2 + 1/12) sum g_j^2, with g from an f64 run of the
//! estimator's ideal recursion (the same quantized coefficients, no rounding) on a unit
//! impulse: an independent computation from the fixed-point model's.
use crate::blocks::velocity::model::Estimator;
use crate::blocks::velocity::{Method, MethodConsts, VelocityParams, VelocitySpec, COEF_FRAC};
use crate::cosim::stimulus::SplitMix64;
use crate::error::Result;
use crate::sim::encoder::EncoderModel;

/// The thesis's Table 4-1: (column, variance, mean) in 16-bit counts per sample.
pub const THESIS: [(&str, f64, f64); 4] = [
    ("diff + LPF", 1.5625, 4.6855),
    ("least squares", 0.8578, 4.6851),
    ("Kalman", 0.0616, 4.6872),
    ("19-bit diff", 0.3102, 4.6855),
];

/// One row of the reproduction.
#[derive(Clone, Debug)]
pub struct Row {
    /// Column name (as in the thesis) or the method.
    pub name: String,
    /// The thesis's variance (counts^2), when it has the column.
    pub thesis_var: Option<f64>,
    /// The thesis's mean (counts per sample).
    pub thesis_mean: Option<f64>,
    /// Measured mean.
    pub mean: f64,
    /// Measured variance.
    pub var: f64,
    /// Predicted variance (linear estimators).
    pub predicted: Option<f64>,
}

/// What to run.
#[derive(Clone, Debug)]
pub struct Setup {
    /// Fine bits of the estimators' position (the position LSB).
    pub fine_bits: u32,
    /// Signal periods per turn.
    pub ppr: u32,
    /// Speed in rpm.
    pub rpm: f64,
    /// White position noise, rms, in position LSB.
    pub noise_lsb: f64,
    /// Updates measured (after 500 of warm-up).
    pub updates: usize,
    /// Noise seed.
    pub seed: u64,
}

impl Setup {
    /// The thesis's run: 2048 PPR, 16-bit position (F = 3), the speed that gives the
    /// thesis's 19-bit mean 4.6855 counts per sample at 7.5 kHz, noise calibrated to the
    /// 19-bit difference's variance.
    pub fn thesis(updates: usize, seed: u64) -> Self {
        Setup {
            fine_bits: 3,
            ppr: 2048,
            rpm: 4.6855 * 7500.0 / 65536.0 * 60.0,
            noise_lsb: ((0.3102 - 2.0 / 64.0 / 12.0) / 2.0f64).sqrt(),
            updates,
            seed,
        }
    }

    /// Position LSB per turn.
    pub fn lsb_per_turn(&self) -> f64 {
        4.0 * self.ppr as f64 * 2f64.powi(self.fine_bits as i32)
    }

    /// The true speed in LSB per 7.5 kHz period.
    pub fn speed(&self) -> f64 {
        self.rpm / 60.0 / 7500.0 * self.lsb_per_turn()
    }
}

/// The thesis's estimator parameters (the `[velocity]` defaults) for `method`, F fine bits.
pub fn spec(method: Method, fine_bits: u32) -> VelocitySpec {
    let mut s = VelocitySpec::defaults(133.33e6, fine_bits, 1 << 20);
    s.method = method;
    s
}

fn gauss(r: &mut SplitMix64) -> f64 {
    let u1 = r.unit().max(1e-300);
    let u2 = r.unit();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// sum g_j^2 of the estimator's ideal recursion on a unit position impulse (f64).
pub fn impulse_energy(p: &VelocityParams) -> f64 {
    let one = (1u64 << COEF_FRAC) as f64;
    let n = 20_000;
    let theta = |k: usize| if k == 0 { 1.0 } else { 0.0 };
    let mut e = 0.0;
    match &p.consts {
        MethodConsts::DiffLpf { a } => {
            let a = *a as f64 / one;
            let mut y = 0.0;
            let mut prev = 0.0;
            for k in 0..n {
                let d = theta(k) - prev;
                prev = theta(k);
                y += a * (d - y);
                e += y * y;
            }
        }
        MethodConsts::Kalman { gains } => {
            let a = *gains.last().unwrap_or(&0) as f64 / one;
            let mut y = 0.0;
            let mut prev = 0.0;
            for k in 0..n {
                let d = theta(k) - prev;
                prev = theta(k);
                y += a * (d - y);
                e += y * y;
            }
        }
        MethodConsts::Lsq { n, d, .. } => {
            e = n.iter().map(|&x| (x as f64 / *d as f64).powi(2)).sum();
        }
        MethodConsts::Tracking { alpha, beta } => {
            let (a, b) = (*alpha as f64 / one, *beta as f64 / one);
            let (mut th, mut w) = (0.0, 0.0);
            for k in 0..n {
                let err = theta(k) - th;
                w += b * err;
                th += w + a * err;
                e += w * w;
            }
        }
    }
    e
}

fn stats(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n;
    (mean, var)
}

/// Runs every method (and, when F = 3, the 19-bit difference) on the setup. Means and
/// variances in position LSB per period.
pub fn run(setup: &Setup) -> Result<Vec<Row>> {
    let enc = EncoderModel::ideal(setup.ppr, 1.0, setup.rpm);
    let lsb = setup.lsb_per_turn();
    let mut r = SplitMix64(setup.seed);
    let warm = 500;
    let total = warm + setup.updates;
    // True positions (LSB, unquantized) with noise at the update instants.
    let truth: Vec<f64> = (0..total)
        .map(|k| enc.turns(k as f64 / 7500.0) * lsb + 1000.5 + setup.noise_lsb * gauss(&mut r))
        .collect();
    let methods = [
        Method::DiffLpf,
        Method::Lsq,
        Method::Kalman,
        Method::Tracking,
    ];
    let names = [
        "diff + LPF",
        "least squares",
        "Kalman",
        "tracking (sinedec)",
    ];
    let scale = 1.0 / 256.0;
    let mut rows = Vec::new();
    for (m, name) in methods.iter().zip(names) {
        let p = VelocityParams::new(&spec(*m, setup.fine_bits))?;
        let mut est = Estimator::new(&p);
        let out: Vec<f64> = truth
            .iter()
            .map(|&t| est.update(t.floor() as i64 as u64) as f64 * scale)
            .collect();
        let (mean, var) = stats(&out[warm..]);
        let th = THESIS
            .iter()
            .find(|t| t.0 == name)
            .filter(|_| setup.fine_bits == 3);
        rows.push(Row {
            name: name.to_string(),
            thesis_var: th.map(|t| t.1),
            thesis_mean: th.map(|t| t.2),
            mean,
            var,
            predicted: Some((setup.noise_lsb.powi(2) + 1.0 / 12.0) * impulse_energy(&p)),
        });
    }
    if setup.fine_bits == 3 {
        // The 19-bit difference: 8 x finer quantization, in 16-bit counts.
        let d: Vec<f64> = truth
            .windows(2)
            .map(|w| ((w[1] * 8.0).floor() - (w[0] * 8.0).floor()) / 8.0)
            .collect();
        let (mean, var) = stats(&d[warm..]);
        rows.push(Row {
            name: "19-bit diff".into(),
            thesis_var: Some(THESIS[3].1),
            thesis_mean: Some(THESIS[3].2),
            mean,
            var,
            predicted: Some(2.0 * (setup.noise_lsb.powi(2) + 1.0 / 64.0 / 12.0)),
        });
    }
    Ok(rows)
}

/// The rows as a Markdown table.
pub fn markdown(rows: &[Row], unit: &str) -> String {
    let f = |x: Option<f64>| x.map_or("-".to_string(), |v| format!("{v:.5}"));
    let mut s =
        "| estimator | thesis variance | thesis mean | measured variance | predicted variance \
                 | measured mean |\n|---|---|---|---|---|---|\n"
            .to_string();
    for r in rows {
        s.push_str(&format!(
            "| {} | {} | {} | {:.5} | {} | {:.4} |\n",
            r.name,
            f(r.thesis_var),
            f(r.thesis_mean),
            r.var,
            f(r.predicted),
            r.mean
        ));
    }
    s.push_str(&format!("\n(units: {unit})\n"));
    s
}
