//! `[velocity]`: the velocity estimator's parameters built from the config and the
//! decoder's figures (`crate::blocks::velocity`, docs/velocity.md). Errors name the key.

use super::params::ErrFn;
use super::*;

/// `[velocity]`: the estimator's parameters when enabled (None otherwise; the keys are
/// checked only then, so a configuration without velocity never fails on them). The
/// encoder's maximum speed is the decoder's full-resolution limit: `warn_step` - 1 fine LSB
/// per ADC sample, so the largest step per update period is
/// ceil((warn_step - 1) x sample_rate / rate_hz) LSB.
pub(super) fn velocity_params(
    c: &Config,
    text: &str,
    fine_bits: u32,
    sample_rate_hz: f64,
    warn_step: u64,
    err: &ErrFn,
) -> Result<Option<VelocityParams>> {
    use crate::blocks::velocity::{Method, VelocitySpec};
    let v = &c.velocity;
    if !v.enabled {
        return Ok(None);
    }
    if c.capacitive.is_some() {
        return Err(err(
            "velocity",
            "enabled",
            "velocity estimation is built into the sinewave core only; set enabled = false with [capacitive]".into(),
        ));
    }
    if !(v.rate_hz.is_finite() && v.rate_hz > 0.0 && v.rate_hz <= sample_rate_hz) {
        return Err(err(
            "velocity",
            "rate_hz",
            format!(
                "{} Hz: allowed above 0 and at most the ADC's sample rate {sample_rate_hz:.0} Hz (the position changes once per sample)",
                v.rate_hz
            ),
        ));
    }
    method_checks(v, text, err)?;
    let max_step = ((warn_step - 1) as f64 * sample_rate_hz / v.rate_hz).ceil() as u64;
    let spec = VelocitySpec {
        method: v.method,
        clock_hz: c.clock.frequency_hz,
        rate_hz: v.rate_hz,
        fine_bits,
        max_step,
        frac_bits: v.frac_bits,
        width: v.width,
        cutoff_hz: v.cutoff_hz,
        lsq_points: v.lsq_points,
        lsq_order: v.lsq_order,
        kalman_q: v.kalman_q,
        kalman_r: v.kalman_r,
        bandwidth_hz: v.bandwidth_hz,
    };
    // The key a message of the block's own checks belongs to: the range checks by their
    // subject, the rest to the selected method's own key.
    let given = |k: &str| written(text, "velocity", k);
    let method_key = match v.method {
        Method::DiffLpf => "cutoff_hz",
        Method::Lsq => "lsq_points",
        // A gain below 2^-18: kalman_q too small for kalman_r; the one in the file.
        Method::Kalman if !given("kalman_q") && given("kalman_r") => "kalman_r",
        Method::Kalman => "kalman_q",
        Method::Tracking => "bandwidth_hz",
    };
    VelocityParams::new(&spec).map(Some).map_err(|e| {
        let m = e.detail();
        let key = if m.starts_with("update period")
            || m.starts_with("update rate")
            || m.starts_with("maximum step")
        {
            "rate_hz"
        } else if m.starts_with("frac_bits") || m.starts_with("internal words") {
            "frac_bits"
        } else if m.starts_with("width") || m.starts_with("out_velocity overflows") {
            "width"
        } else {
            method_key
        };
        err("velocity", key, m)
    })
}

/// `[velocity] in_frames`: bits of the velocity word appended to the serial frames (its
/// `width`), 0 without. `in_frames = true` needs the estimator (`enabled = true`).
pub(super) fn velocity_frame_bits(
    c: &Config,
    velocity: Option<&VelocityParams>,
    err: &ErrFn,
) -> Result<u32> {
    if !c.velocity.in_frames {
        return Ok(0);
    }
    match velocity {
        Some(v) => Ok(v.spec.width),
        None => Err(err(
            "velocity",
            "in_frames",
            "in_frames = true sends the estimator's output in the BiSS, SSI and SPI frames; it needs enabled = true".into(),
        )),
    }
}

/// The selected method's own keys, each blamed on itself: a finite cut-off, variances and
/// bandwidth above 0, the least-squares sizes, and the tracking loop's stability (see
/// [`tracking_check`]). The other methods' keys have no effect and are not checked.
fn method_checks(v: &VelocityConfig, text: &str, err: &ErrFn) -> Result<()> {
    use crate::blocks::velocity::Method;
    let given = |k: &str| written(text, "velocity", k);
    let positive = |key: &str, x: f64, what: &str| -> Result<()> {
        if x.is_finite() && x > 0.0 {
            Ok(())
        } else {
            Err(err(
                "velocity",
                key,
                format!("{x}: must be > 0 and finite (a {what})"),
            ))
        }
    };
    match v.method {
        Method::DiffLpf => positive("cutoff_hz", v.cutoff_hz, "frequency in Hz"),
        Method::Kalman => {
            positive("kalman_q", v.kalman_q, "variance")?;
            positive("kalman_r", v.kalman_r, "variance")
        }
        Method::Lsq => {
            let (m, n) = (v.lsq_points, v.lsq_order);
            if !(2..=16).contains(&m) {
                return Err(err(
                    "velocity",
                    "lsq_points",
                    format!("{m} points: allowed 2..=16"),
                ));
            }
            if !(1..=3).contains(&n) {
                return Err(err(
                    "velocity",
                    "lsq_order",
                    format!("{n}: allowed 1..=3, and below lsq_points"),
                ));
            }
            if n >= m {
                let key = if given("lsq_order") || !given("lsq_points") {
                    "lsq_order"
                } else {
                    "lsq_points"
                };
                return Err(err(
                    "velocity",
                    key,
                    format!("lsq_order = {n} with lsq_points = {m}: the order must be below the number of points"),
                ));
            }
            Ok(())
        }
        Method::Tracking => {
            positive("bandwidth_hz", v.bandwidth_hz, "frequency in Hz")?;
            tracking_check(v, given("bandwidth_hz"), given("rate_hz"), err)
        }
    }
}

/// `x` to 3 significant digits, rounded up or down (so that advice stays inside a range),
/// printed without an exponent.
fn sig3(x: f64, up: bool) -> String {
    if !(x.is_finite() && x > 0.0) {
        return format!("{x}");
    }
    let e = x.log10().floor() as i32;
    let p = 10f64.powi(e - 2);
    let q = x / p;
    let v = if up { q.ceil() } else { q.floor() } * p;
    format!("{v:.*}", (2 - e).max(0) as usize)
}

/// The tracking loop's stability after quantization (beta >= 1 code of 2^-C and
/// 2 alpha + beta < 4) with wT = 2 pi bandwidth_hz / rate_hz, alpha = sqrt(2) wT and
/// beta = (wT)^2: stable for about sqrt(2^-C) <= wT < sqrt(6) - sqrt(2). The key the user wrote
/// is blamed (bandwidth_hz when it is in the file, else rate_hz with the default bandwidth
/// named as such), and the advice gives values inside that range.
fn tracking_check(v: &VelocityConfig, bw_given: bool, rate_given: bool, err: &ErrFn) -> Result<()> {
    use crate::blocks::velocity::{tracking_gains, COEF_FRAC};
    let one = 1i64 << COEF_FRAC;
    let (alpha, beta) = tracking_gains(v.bandwidth_hz, v.rate_hz);
    if beta >= 1 && alpha >= 1 && 2 * alpha + beta < 4 * one {
        return Ok(());
    }
    let tau = std::f64::consts::TAU;
    let (wt_lo, wt_hi) = (
        (1.0 / one as f64).sqrt() * 1.001,
        (6f64.sqrt() - 2f64.sqrt()) * 0.999,
    );
    let too_fast = 2 * alpha + beta >= 4 * one;
    let shown = |key: &str, x: f64, given: bool| {
        if given {
            format!("{key} = {x} Hz")
        } else {
            format!("{key} (default {x} Hz)")
        }
    };
    let why = format!(
        "the tracking loop is unstable with {} at {} (alpha = {:.6}, beta = {:.3e}; it needs beta >= 2^-{COEF_FRAC} and 2 alpha + beta < 4)",
        shown("bandwidth_hz", v.bandwidth_hz, bw_given),
        shown("rate_hz", v.rate_hz, rate_given),
        alpha as f64 / one as f64,
        beta as f64 / one as f64,
    );
    let bw_advice = format!(
        "set bandwidth_hz between {} and {} Hz",
        sig3(v.rate_hz / tau * wt_lo, true),
        sig3(v.rate_hz / tau * wt_hi, false)
    );
    let rate_advice = if too_fast {
        format!(
            "use rate_hz of at least {} Hz",
            sig3(v.bandwidth_hz * tau / wt_hi, true)
        )
    } else {
        format!(
            "use rate_hz of at most {} Hz",
            sig3(v.bandwidth_hz * tau / wt_lo, false)
        )
    };
    if bw_given || !rate_given {
        Err(err(
            "velocity",
            "bandwidth_hz",
            format!("{why}; {bw_advice}, or {rate_advice}"),
        ))
    } else {
        Err(err(
            "velocity",
            "rate_hz",
            format!("{why}; {rate_advice}, or {bw_advice}"),
        ))
    }
}
