//! Velocity block: each estimator's lag behind a speed ramp, the figure `check` prints
//! (`VelocityParams::lag_periods`, plus the output latency), measured on the bit-accurate
//! model (equal to the RTL cycle for cycle: `tests/outputs/velocity.rs`) fed a parabola
//! theta(k) = c k^2, whose true speed at update k is 2 c k position LSB per period.
use sinedec::blocks::velocity::model::Estimator;
use sinedec::blocks::velocity::{Method, VelocityParams, VelocitySpec};

/// The default configuration's velocity constants (F = 14, 7.5 kHz, the default decoder's
/// maximum speed) for method `m`, at the default 133.33 MHz clock.
fn params(m: Method) -> VelocityParams {
    let mut s = VelocitySpec::defaults(133.33e6, 14, 4_997_175);
    s.method = m;
    VelocityParams::new(&s).expect("default parameters are valid")
}

/// The lag in update periods measured on the model: the mean of k - y / (2^S 2 c) over the
/// last 100 of `n` updates of theta(k) = c k^2.
fn measured_lag(p: &VelocityParams, c: u64, n: u64) -> f64 {
    let mut est = Estimator::new(p);
    let one = (1u64 << p.spec.frac_bits) as f64;
    let mut sum = 0.0;
    for k in 0..n {
        let y = est.update(c * k * k);
        if k >= n - 100 {
            sum += k as f64 - y as f64 / one / (2.0 * c as f64);
        }
    }
    sum / 100.0
}

#[test]
fn every_method_lags_a_speed_ramp_as_check_says() {
    for m in [
        Method::Tracking,
        Method::Kalman,
        Method::Lsq,
        Method::DiffLpf,
    ] {
        let p = params(m);
        // 3000 updates: past every start transient (kalman's gain table, the tracking
        // loop's 34-update settling); the speed stays below the decoder's maximum step.
        let (c, n) = (100u64, 3000u64);
        assert!(
            2 * c * n < p.spec.max_step,
            "{m}: ramp above the maximum speed"
        );
        let got = measured_lag(&p, c, n);
        let want = p.lag_periods();
        assert!(
            (got - want).abs() < 0.01,
            "{m}: measured lag {got:.4} updates, check says {want:.4}"
        );
    }
}

#[test]
fn the_lags_match_their_textbook_values() {
    // Independent of the quantized constants: a 4-point least-squares line is the speed
    // at the middle of its window, (M - 1) / 2 = 1.5 updates back; the type-II loop trails
    // by 2 zeta / w_n - T / 2 (zeta = 1/sqrt 2, w_n = 2 pi 200 Hz, T = 1 / 7.5 kHz): 7.94
    // updates; the first-order filter by (1 - a) / a + 1/2 with a = T / (tau + T).
    let lsq = params(Method::Lsq).lag_periods();
    assert!((lsq - 1.5).abs() < 1e-12, "lsq {lsq}");
    let p = params(Method::Tracking);
    let rate = p.spec.clock_hz / p.period_clocks as f64;
    let wn = std::f64::consts::TAU * p.spec.bandwidth_hz;
    let ideal = std::f64::consts::SQRT_2 / wn * rate - 0.5;
    let got = p.lag_periods();
    assert!(
        (got - ideal).abs() < 0.01 * ideal,
        "tracking {got} vs {ideal}"
    );
    let p = params(Method::DiffLpf);
    let t = 1.0 / rate;
    let tau = 1.0 / (std::f64::consts::TAU * p.spec.cutoff_hz);
    let ideal = tau / t + 0.5;
    let got = p.lag_periods();
    assert!(
        (got - ideal).abs() < 0.01 * ideal,
        "diff_lpf {got} vs {ideal}"
    );
}

#[test]
fn check_prints_each_methods_lag() {
    let text = format!(
        "{}\n[velocity]\nenabled = true\n",
        sinedec::config::DEFAULT_CONFIG
    );
    let l = sinedec::config::Loaded::parse(&text, "velocity.toml").expect("config");
    let out = l.derived.describe();
    let line = out
        .lines()
        .find(|l| l.starts_with("velocity lag"))
        .unwrap_or_else(|| panic!("no velocity lag line:\n{out}"));
    let v = l.derived.velocity.as_ref().expect("enabled");
    let ms = format!("tracking {:.3} ms", v.lag_s() * 1e3);
    assert!(line.contains(&ms), "{ms} missing: {line}");
    for m in ["kalman", "lsq", "diff_lpf"] {
        assert!(line.contains(&format!("{m} ")), "{m} missing: {line}");
    }
}
