//! Offline design of the estimators' constants: the tracking loop's gains, the exact
//! least-squares taps, the Kalman gain table, and the L1 norms that bound their internal
//! words (maths in the module docs of [`super`]).

use super::{invalid, COEF_FRAC, MAX_GAIN_TABLE};
use crate::error::Result;

/// G for a first-order update with gain `a` (units 2^-C): the dead band 2^C / (2 a) internal
/// LSB below 1/4 output LSB.
pub(super) fn guard_for(a: i64) -> u32 {
    let band = (1u64 << (COEF_FRAC + 1)) as f64 / a as f64;
    band.log2().ceil().max(0.0) as u32
}

/// The tracking gains round(alpha 2^C), round(beta 2^C).
pub fn tracking_gains(bandwidth_hz: f64, rate_hz: f64) -> (i64, i64) {
    let one = (1i64 << COEF_FRAC) as f64;
    let wt = std::f64::consts::TAU * bandwidth_hz / rate_hz;
    let alpha = 2.0 * std::f64::consts::FRAC_1_SQRT_2 * wt;
    let beta = wt * wt;
    ((alpha * one).round() as i64, (beta * one).round() as i64)
}

/// ||g||_1 of the tracking loop from the increment Delta to W (velocity) and to the error e,
/// with the quantized gains (f64, summed until the response has decayed).
pub(super) fn tracking_l1(alpha: i64, beta: i64) -> (f64, f64) {
    let one = (1i64 << COEF_FRAC) as f64;
    let (a, b) = (alpha as f64 / one, beta as f64 / one);
    // theta: a unit step at k = 0 (Delta = impulse).
    let (mut th, mut w) = (0.0f64, 0.0f64);
    let (mut lw, mut le) = (0.0, 0.0);
    for k in 0..1_000_000 {
        let e = 1.0 - th;
        w += b * e;
        th += w + a * e;
        lw += w.abs();
        le += e.abs();
        if k > 100 && w.abs() < 1e-15 && e.abs() < 1e-15 {
            break;
        }
    }
    (lw, le)
}

/// ||g||_1 of the lsq FIR from Delta to y: y = sum h_i x_i, x_M newest.
pub(super) fn lsq_l1(n: &[i64], d: i64) -> f64 {
    // With x_i = theta(k - (M - i)), y = sum_j g_j Delta(k - j), g_j = -sum_{i <= M-1-j} h_i.
    let m = n.len();
    let mut l1 = 0.0;
    for j in 0..m - 1 {
        let s: i64 = n[..m - 1 - j].iter().sum();
        l1 += (s as f64 / d as f64).abs();
    }
    l1
}

/// The Kalman gains of eq. 4.16 on eq. 4.17 (x_0 = 0, P_0 = `p0`), quantized to C bits: the
/// transient entries until round(K_k 2^C) equals round(K_inf 2^C), then K_inf (last).
pub fn kalman_gains(q: f64, r: f64, p0: f64) -> Result<Vec<i64>> {
    if !(q.is_finite() && q > 0.0 && r.is_finite() && r > 0.0) {
        return Err(invalid(format!(
            "kalman_q = {q} and kalman_r = {r} must be finite and > 0"
        )));
    }
    let one = (1i64 << COEF_FRAC) as f64;
    // K_inf: the recursion's own limit in f64 (the closed form of the Riccati fixed point,
    // P^- = (Q + sqrt(Q^2 + 4 Q R)) / 2, can differ from it in the last bit).
    let mut p = p0;
    let mut k = 0.0;
    for _ in 0..1_000_000 {
        let pminus = p + q;
        let kn = pminus / (pminus + r);
        p = (1.0 - kn) * pminus;
        if kn == k {
            break;
        }
        k = kn;
    }
    let kinf = (k * one).round() as i64;
    let mut p = p0;
    let mut gains = Vec::new();
    let mut same = 0;
    for _ in 0..MAX_GAIN_TABLE + 64 {
        let pminus = p + q;
        let k = pminus / (pminus + r);
        p = (1.0 - k) * pminus;
        let kq = (k * one).round() as i64;
        if kq == kinf {
            same += 1;
            if same >= 64 {
                // Keep the first of the trailing K_inf entries (63 are in the table).
                gains.truncate(gains.len() + 2 - same);
                return Ok(gains);
            }
        } else {
            same = 0;
        }
        gains.push(kq);
    }
    Err(invalid(format!(
        "the Kalman gain with Q = {q}, R = {r} does not settle to the bit within \
         {MAX_GAIN_TABLE} updates"
    )))
}

pub(super) fn gcd(a: i128, b: i128) -> i128 {
    let (mut a, mut b) = (a.abs(), b.abs());
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

/// A reduced fraction.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Frac(i128, i128);

impl Frac {
    fn new(n: i128, d: i128) -> Frac {
        let g = gcd(n, d).max(1);
        let s = if d < 0 { -1 } else { 1 };
        Frac(s * n / g, s * d / g)
    }
    fn sub(self, o: Frac) -> Frac {
        Frac::new(self.0 * o.1 - o.0 * self.1, self.1 * o.1)
    }
    fn mul(self, o: Frac) -> Frac {
        Frac::new(self.0 * o.0, self.1 * o.1)
    }
    fn div(self, o: Frac) -> Frac {
        Frac::new(self.0 * o.1, self.1 * o.0)
    }
    fn add(self, o: Frac) -> Frac {
        Frac::new(self.0 * o.1 + o.0 * self.1, self.1 * o.1)
    }
}

/// Exact H_{M+1} of eq. 4.9 for M points and order N: integer numerators (oldest point
/// first) over a common denominator.
pub fn lsq_coefficients(m: u32, n: u32) -> Result<(Vec<i64>, i64)> {
    let cols = (n + 1) as usize;
    let pow = |t: i128, e: usize| -> i128 { (0..e).fold(1i128, |a, _| a * t) };
    // A^T A (cols x cols) and q_{M+1} = [0, 1, 2 (M+1), ..., N (M+1)^(N-1)].
    let mut g: Vec<Vec<Frac>> = (0..cols)
        .map(|r| {
            (0..cols)
                .map(|c| Frac::new((1..=m as i128).map(|t| pow(t, r + c)).sum(), 1))
                .collect()
        })
        .collect();
    let mut u: Vec<Frac> = (0..cols)
        .map(|j| {
            if j == 0 {
                Frac::new(0, 1)
            } else {
                Frac::new(j as i128 * pow(m as i128 + 1, j - 1), 1)
            }
        })
        .collect();
    // Solve (A^T A) w = q^T (symmetric, positive definite: no pivoting needed).
    for p in 0..cols {
        let piv = g[p][p];
        if piv.0 == 0 {
            return Err(invalid("singular least-squares system".into()));
        }
        let prow = g[p].clone();
        let up = u[p];
        for r in (0..cols).filter(|&r| r != p) {
            let f = g[r][p].div(piv);
            for (x, &y) in g[r].iter_mut().zip(&prow) {
                *x = x.sub(f.mul(y));
            }
            u[r] = u[r].sub(f.mul(up));
        }
    }
    let w: Vec<Frac> = (0..cols).map(|j| u[j].div(g[j][j])).collect();
    // h_t = sum_j t^j w_j.
    let h: Vec<Frac> = (1..=m as i128)
        .map(|t| {
            (0..cols).fold(Frac::new(0, 1), |acc, j| {
                acc.add(w[j].mul(Frac::new(pow(t, j), 1)))
            })
        })
        .collect();
    let den = h.iter().fold(1i128, |l, f| l / gcd(l, f.1) * f.1);
    let num: Vec<i64> = h.iter().map(|f| (f.0 * (den / f.1)) as i64).collect();
    Ok((num, den as i64))
}
