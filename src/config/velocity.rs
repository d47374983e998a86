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
    let method_key = match v.method {
        Method::DiffLpf => "cutoff_hz",
        Method::Lsq => "lsq_points",
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
