//! Bit-accurate model of the velocity block: [`Estimator`] is one update of the chosen
//! method on an unwrapped position (what the Table 4-1 reproduction runs), and
//! [`VelocityModel`] the clocked block around it (position front end, divider, latency), one
//! step per clock edge. Every quantity is an integer; the maths is in the module docs of
//! `crate::blocks::velocity`.
use super::{qround, MethodConsts, VelocityParams};
use crate::blocks::{mask, sext};

/// One update of the estimator, on positions modulo 2^Wp.
#[derive(Clone, Debug)]
pub struct Estimator {
    p: VelocityParams,
    /// The history has been loaded.
    primed: bool,
    /// Positions (mod 2^Wp), oldest first: lsq keeps M, the others 1.
    hist: Vec<u64>,
    /// X (diff_lpf, kalman) or W (tracking), S+G fractional bits.
    x: i64,
    /// Tracking: predicted position Theta modulo 2^(Wp+S+G).
    theta_hat: u64,
    /// Kalman: updates since the history was loaded (index into the gain table).
    k: usize,
}

impl Estimator {
    /// A fresh (reset) estimator.
    pub fn new(p: &VelocityParams) -> Self {
        Estimator {
            p: p.clone(),
            primed: false,
            hist: Vec::new(),
            x: 0,
            theta_hat: 0,
            k: 0,
        }
    }

    /// Back to the reset state.
    pub fn reset(&mut self) {
        *self = Estimator::new(&self.p);
    }

    /// The internal velocity state (X or W, S+G fractional bits); 0 for lsq.
    pub fn state(&self) -> i64 {
        self.x
    }

    /// One update with the unwrapped position `theta` (only its low Wp bits are used);
    /// returns the velocity in output LSB (2^-S position LSB per period).
    pub fn update(&mut self, theta: u64) -> i64 {
        let wp = self.p.pos_width;
        let theta = theta & mask(wp);
        let sg = self.p.state_frac();
        let c = super::COEF_FRAC;
        let g = self.p.guard;
        if !self.primed {
            self.primed = true;
            let len = match &self.p.consts {
                MethodConsts::Lsq { n, .. } => n.len(),
                _ => 1,
            };
            self.hist = vec![theta; len];
            self.x = 0;
            self.k = 0;
            self.theta_hat = (theta << sg) & mask(wp + sg);
            return 0;
        }
        match &self.p.consts {
            MethodConsts::DiffLpf { .. } | MethodConsts::Kalman { .. } => {
                let gain = match &self.p.consts {
                    MethodConsts::DiffLpf { a } => *a,
                    MethodConsts::Kalman { gains } => gains[self.k.min(gains.len() - 1)],
                    _ => unreachable!("first-order methods only"),
                };
                self.k = (self.k + 1).min(super::MAX_GAIN_TABLE);
                let delta = sext(theta.wrapping_sub(self.hist[0]) & mask(wp), wp);
                self.hist[0] = theta;
                let u = (delta as i128) << sg;
                self.x += qround(gain as i128 * (u - self.x as i128), c) as i64;
                qround(self.x as i128, g) as i64
            }
            MethodConsts::Lsq {
                n, recip, shift, ..
            } => {
                self.hist.remove(0);
                self.hist.push(theta);
                let m = n.len();
                let newest = self.hist[m - 1];
                let sum: i128 = (0..m - 1)
                    .map(|i| {
                        let r = sext(self.hist[i].wrapping_sub(newest) & mask(wp), wp);
                        n[i] as i128 * r as i128
                    })
                    .sum();
                qround(sum * *recip as i128, *shift) as i64
            }
            MethodConsts::Tracking { alpha, beta } => {
                let tw = wp + sg;
                let meas = (theta << sg) & mask(tw);
                let e = sext(meas.wrapping_sub(self.theta_hat) & mask(tw), tw) as i128;
                self.x += qround(*beta as i128 * e, c) as i64;
                let step = self.x as i128 + qround(*alpha as i128 * e, c);
                self.theta_hat = (self.theta_hat as i128 + step) as u64 & mask(tw);
                qround(self.x as i128, g) as i64
            }
        }
    }
}

/// Inputs of one clock cycle.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct VelIn {
    /// Synchronous reset.
    pub rst: bool,
    /// A decoded sample: `p` holds its position.
    pub valid: bool,
    /// The position modulo 2^(F+2) (higher bits are ignored).
    pub p: u64,
}

/// Outputs after one clock edge.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct VelOut {
    /// One-cycle strobe per update.
    pub valid: bool,
    /// Velocity, `width`-bit two's complement (raw bits).
    pub velocity: u64,
}

/// The clocked block.
#[derive(Clone, Debug)]
pub struct VelocityModel {
    p: VelocityParams,
    est: Estimator,
    /// A sample has been seen since reset.
    init: bool,
    /// Unwrapped position modulo 2^Wp.
    pos: u64,
    /// Divider, 0..D-1.
    cnt: u64,
    /// A result on its way: (edges left, value).
    pending: Option<(u64, i64)>,
    /// Output register.
    y: u64,
}

impl VelocityModel {
    /// The block after reset.
    pub fn new(p: &VelocityParams) -> Self {
        VelocityModel {
            p: p.clone(),
            est: Estimator::new(p),
            init: false,
            pos: 0,
            cnt: 0,
            pending: None,
            y: 0,
        }
    }

    /// The unwrapped position register (mod 2^Wp).
    pub fn position(&self) -> u64 {
        self.pos
    }

    /// One clock edge.
    pub fn step(&mut self, i: VelIn) -> VelOut {
        if i.rst {
            *self = VelocityModel::new(&self.p);
            return VelOut::default();
        }
        let mut valid = false;
        if let Some((left, y)) = self.pending {
            if left == 1 {
                valid = true;
                self.y = y as u64 & mask(self.p.spec.width);
                self.pending = None;
            } else {
                self.pending = Some((left - 1, y));
            }
        }
        let tick = self.cnt == self.p.period_clocks - 1;
        self.cnt = if tick { 0 } else { self.cnt + 1 };
        if tick && self.init {
            let y = self.est.update(self.pos);
            self.pending = Some((self.p.latency(), y));
        }
        if i.valid {
            let f2 = self.p.spec.fine_bits + 2;
            let wp = self.p.pos_width;
            if self.init {
                let d = sext(i.p.wrapping_sub(self.pos) & mask(f2), f2);
                self.pos = (self.pos as i64).wrapping_add(d) as u64 & mask(wp);
            } else {
                self.init = true;
                self.pos = i.p & mask(f2);
            }
        }
        VelOut {
            valid,
            velocity: self.y,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::*;
    use super::*;

    fn params(method: Method, max_step: u64) -> VelocityParams {
        let mut s = VelocitySpec::defaults(133.33e6, 14, max_step);
        s.method = method;
        VelocityParams::new(&s).expect("valid")
    }

    const ALL: [Method; 4] = [
        Method::DiffLpf,
        Method::Kalman,
        Method::Lsq,
        Method::Tracking,
    ];

    #[test]
    fn lsq_coefficients_are_exact() {
        assert_eq!(lsq_coefficients(4, 1).unwrap(), (vec![-3, -1, 1, 3], 10));
        // Independent: f64 normal equations for M = 6, N = 2, derivative at t = 7.
        let (n, d) = lsq_coefficients(6, 2).unwrap();
        let a: Vec<[f64; 3]> = (1..=6).map(|t| [1.0, t as f64, (t * t) as f64]).collect();
        // Fit each unit vector and compare c1 + 2 c2 * 7.
        for (i, &ni) in n.iter().enumerate() {
            let mut ata = [[0.0; 3]; 3];
            let mut atx = [0.0; 3];
            for (k, row) in a.iter().enumerate() {
                for r in 0..3 {
                    for c in 0..3 {
                        ata[r][c] += row[r] * row[c];
                    }
                    atx[r] += row[r] * if k == i { 1.0 } else { 0.0 };
                }
            }
            let c = solve3(ata, atx);
            let h = c[1] + 2.0 * c[2] * 7.0;
            assert!(
                (h - ni as f64 / d as f64).abs() < 1e-9,
                "tap {i}: {h} vs {ni}/{d}"
            );
        }
    }

    fn solve3(mut m: [[f64; 3]; 3], mut b: [f64; 3]) -> [f64; 3] {
        for p in 0..3 {
            for r in 0..3 {
                if r != p {
                    let f = m[r][p] / m[p][p];
                    let prow = m[p];
                    for (x, y) in m[r].iter_mut().zip(prow) {
                        *x -= f * y;
                    }
                    b[r] -= f * b[p];
                }
            }
        }
        [b[0] / m[0][0], b[1] / m[1][1], b[2] / m[2][2]]
    }

    #[test]
    fn kalman_gain_table_ends_at_the_steady_state_gain() {
        let g = kalman_gains(0.01, 0.03, 1.0).unwrap();
        let one = (1u64 << COEF_FRAC) as f64;
        // Closed form of the scalar Riccati fixed point.
        let pm = (0.01 + (0.0001f64 + 4.0 * 0.01 * 0.03).sqrt()) / 2.0;
        let kinf = (pm / (pm + 0.03) * one).round() as i64;
        assert!((*g.last().unwrap() - kinf).abs() <= 1, "{g:?} vs {kinf}");
        // The table: round(K_k 2^C) of the recursion, one K_inf entry at the end, and the
        // recursion's value far out equals it.
        let mut pk = 1.0f64;
        let mut ks = vec![];
        for _ in 0..10_000 {
            let pm = pk + 0.01;
            let k = pm / (pm + 0.03);
            pk = (1.0 - k) * pm;
            ks.push((k * one).round() as i64);
        }
        assert_eq!(&ks[..g.len()], &g[..]);
        assert!(ks[g.len()..].iter().all(|&k| k == *g.last().unwrap()));
        assert_ne!(g[g.len() - 2], g[g.len() - 1], "one K_inf entry");
        assert!(
            (1.01 / 1.04 * one - g[0] as f64).abs() <= 0.5,
            "K_1 = P0+Q / (P0+Q+R)"
        );
        assert!(g.len() > 2 && g.len() < 40, "{} entries", g.len());
        assert!(g.windows(2).all(|w| w[0] >= w[1]), "monotonic");
    }

    /// Positions floor(v k + phi) of a constant speed: mean output within 2^-S of v.
    #[test]
    fn constant_speed_has_no_bias() {
        for m in ALL {
            let p = params(m, 40_000);
            for v in [0.0, 3.0, 4.6855, -17.25, 1234.567, -39_000.3] {
                let mut e = Estimator::new(&p);
                let mut sum = 0i128;
                let n = 4000;
                for k in 0..n + 400 {
                    let th = (v * k as f64 + 0.37).floor() as i64;
                    let y = e.update(th as u64);
                    if k >= 400 {
                        sum += y as i128;
                    }
                }
                let mean = sum as f64 / n as f64 / 256.0;
                assert!((mean - v).abs() < 1.0 / 256.0, "{m}: v = {v}, mean {mean}");
            }
        }
    }

    /// Integer speeds come out exact once settled.
    #[test]
    fn integer_speed_is_exact_after_settling() {
        for m in ALL {
            let p = params(m, 40_000);
            for v in [0i64, 7, -5, 39_999, -40_000] {
                let mut e = Estimator::new(&p);
                let mut last = 0;
                for k in 0..600i64 {
                    last = e.update((v * k + 123_456) as u64);
                }
                assert_eq!(last, v * 256, "{m}: v = {v}");
            }
        }
    }

    #[test]
    fn widths_hold_the_maximum_speed_and_reversals() {
        for m in ALL {
            let v = 40_000i64;
            let p = params(m, v as u64);
            let lim = 1i64 << (p.spec.width - 1);
            let mut e = Estimator::new(&p);
            let mut th = 0i64;
            let mut peak = 0i64;
            // Full speed forward, instant reversal, back: the worst steps.
            for k in 0..2000 {
                th += if (k / 150) % 2 == 0 { v } else { -v };
                let y = e.update(th as u64);
                peak = peak.max(y.abs());
                assert!(y.abs() < lim);
            }
            assert!(
                peak as u64 <= p.max_output,
                "{m}: {peak} > {}",
                p.max_output
            );
        }
    }

    #[test]
    fn tracking_settles_after_a_speed_step() {
        let p = params(Method::Tracking, 40_000);
        let n = p.settle_updates() as usize;
        assert!((30..40).contains(&n), "{n} updates at 200 Hz, 7.5 kHz");
        let mut e = Estimator::new(&p);
        let mut th = 0i64;
        let v = 1000i64;
        for _ in 0..50 {
            e.update(th as u64);
        }
        for k in 0..200 {
            th += v;
            let y = e.update(th as u64) as f64 / 256.0;
            if k >= n {
                assert!((y - v as f64).abs() <= 0.02 * v as f64, "k = {k}: {y}");
            }
        }
    }

    #[test]
    fn front_end_unwraps_steps_and_ticks_every_period() {
        let mut s = VelocitySpec::defaults(1e6, 4, 1000);
        s.rate_hz = 10_000.0;
        s.method = Method::Lsq;
        let p = VelocityParams::new(&s).unwrap();
        assert_eq!(p.period_clocks, 100);
        let mut m = VelocityModel::new(&p);
        m.step(VelIn {
            rst: true,
            ..VelIn::default()
        });
        // One sample per clock, +3 LSB each, modulo 2^6 on the wire.
        let mut strobes = vec![];
        for k in 0..1000u64 {
            let o = m.step(VelIn {
                rst: false,
                valid: true,
                p: (3 * k + 60) & 63,
            });
            if o.valid {
                strobes.push((k, sext(o.velocity, p.spec.width)));
            }
        }
        assert_eq!(m.position(), (3 * 999 + 60) & mask(p.pos_width));
        let gaps: Vec<u64> = strobes.windows(2).map(|w| w[1].0 - w[0].0).collect();
        assert!(gaps.iter().all(|&g| g == 100), "{gaps:?}");
        assert_eq!(strobes[0], (99 + p.latency(), 0));
        assert_eq!(strobes.last().unwrap().1, 300 * 256, "{strobes:?}");
    }

    #[test]
    fn bad_parameters_are_rejected() {
        let ok = VelocitySpec::defaults(133.33e6, 14, 5_000_000);
        assert!(VelocityParams::new(&ok).is_ok());
        let mut s = ok.clone();
        s.bandwidth_hz = 2000.0;
        assert!(VelocityParams::new(&s)
            .unwrap_err()
            .to_string()
            .contains("unstable"));
        let mut s = ok.clone();
        s.max_step = 20_000_000;
        assert!(VelocityParams::new(&s)
            .unwrap_err()
            .to_string()
            .contains("overflows"));
        let mut s = ok.clone();
        s.rate_hz = 3e6;
        assert!(VelocityParams::new(&s).is_err());
        let mut s = ok.clone();
        s.method = Method::Lsq;
        s.lsq_order = 4;
        assert!(VelocityParams::new(&s).is_err());
    }

    #[test]
    fn an_update_must_end_within_its_period() {
        // lsq M = 4 at the defaults: 4 multiplies of n + 3 clocks (n = ceil(33 / 2) Booth
        // digits of the 33-bit reciprocal) and 2 more: 82 clocks, above the 64-clock floor.
        let mut s = VelocitySpec::defaults(133.33e6, 14, 5_000_000);
        s.method = Method::Lsq;
        let lat = VelocityParams::new(&s).unwrap().latency();
        assert_eq!(lat, 4 * (17 + 3) + 2);
        // The clock sets D only (the constants depend on the rate): D = latency is refused,
        // D = latency + 1 accepted, and its schedule then fits the period.
        s.clock_hz = lat as f64 * s.rate_hz;
        let e = VelocityParams::new(&s).unwrap_err().to_string();
        assert!(
            e.contains("update period") && e.contains("lower the update rate"),
            "{e}"
        );
        s.clock_hz = (lat + 1) as f64 * s.rate_hz;
        let p = VelocityParams::new(&s).unwrap();
        assert_eq!((p.period_clocks, p.latency()), (lat + 1, lat));
    }
}
