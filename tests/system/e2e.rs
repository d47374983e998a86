//! End to end in the Rust simulation (encoder model -> LTC1407A-1 model -> `<name>_top`),
//! default configuration: position error against the true angle under noise, and creep.
use sinedec::config::Loaded;
use sinedec::sim::dut::EngineKind;
use sinedec::sim::encoder::Profile;
use sinedec::simulate::{run, SimOptions};
use std::f64::consts::FRAC_PI_2;

/// Default options on the compiled engine: these tests check the decoder's figures in its
/// closed loop, not rust-hdl's simulation, and tests/system/engine_loop.rs proves the two equal.
fn compiled() -> SimOptions {
    SimOptions {
        engine: EngineKind::Compiled,
        ..Default::default()
    }
}

/// Error bounds in fine LSB for ADC noise of `noise_lsb` RMS per channel at amplitude
/// `amp` (fraction of full scale), derived from the noise and the quantization:
/// * angle noise: sigma_n / A rad for a vector of amplitude A LSB (noise perpendicular to
///   the vector), plus the ADC's own quantization (1/sqrt(12) LSB per channel) the same way;
/// * output rounding: uniform +-1/2 LSB (1/sqrt(12));
/// * the CORDIC's systematic residual at N = 14: at most 2.27 - 1 = 1.27 LSB
///   (tests/blocks/accuracy.rs bound minus its rounding allowance).
///
/// RMS <= sqrt(noise^2 + adc_q^2 + 1/12) + 1.27; max <= 5.5 sigma(noise + adc_q) + 0.5 + 1.27
/// (5.5 sigma: a Gaussian exceeds it with probability 4e-8 per sample, over ~2000 samples).
fn bounds(l: &Loaded, noise_lsb: f64, amp: f64) -> (f64, f64) {
    let d = &l.derived;
    let a = amp * ((1u64 << (d.adc_width - 1)) - 1) as f64;
    let per_rad = (1u64 << d.fine_bits) as f64 / FRAC_PI_2;
    let s_noise = noise_lsb / a * per_rad;
    let s_q = (1.0f64 / 12.0).sqrt() / a * per_rad;
    let s = (s_noise * s_noise + s_q * s_q).sqrt();
    let rms = (s * s + 1.0 / 12.0).sqrt() + 1.27;
    let max = 5.5 * s + 0.5 + 1.27;
    (rms, max)
}

#[test]
fn error_within_the_noise_bound_at_10_300_3000_rpm() {
    let l = Loaded::default_config().expect("default");
    let (rms_b, max_b) = bounds(&l, 1.0, 0.8);
    for rpm in [10.0, 300.0, 3000.0] {
        let o = SimOptions {
            profile: Profile::Constant { rpm },
            duration_s: 1.5e-3,
            amplitude: 0.8,
            noise_lsb: 1.0,
            seed: rpm as u64,
            ..compiled()
        };
        let r = run(&l, &o, |_, _| {}).expect("simulation runs");
        let s = r.stats;
        eprintln!(
            "{rpm} rpm: {} samples, max {:.2} LSB (bound {max_b:.2}), RMS {:.2} LSB (bound {rms_b:.2})",
            s.samples, s.max_lsb, s.rms_lsb
        );
        assert!(s.samples > 1800);
        assert_eq!(r.result.latency_mismatches, 0);
        assert!(r.result.adc_violations.is_empty());
        assert_eq!(s.errors + s.warnings, 0);
        assert!(s.max_lsb <= max_b, "{rpm} rpm: {s:?}");
        assert!(s.rms_lsb <= rms_b, "{rpm} rpm: {s:?}");
    }
}

#[test]
fn creep_at_0_3_rpm_is_monotonic_in_the_mean_without_quadrant_jumps() {
    let l = Loaded::default_config().expect("default");
    let o = SimOptions {
        profile: Profile::creep(),
        duration_s: 2e-3,
        amplitude: 0.8,
        noise_lsb: 1.0,
        seed: 5,
        ..compiled()
    };
    let r = run(&l, &o, |_, _| {}).expect("simulation runs");
    let u: Vec<i64> = r.result.records.iter().map(|x| x.unwrapped).collect();
    assert!(u.len() > 2500);
    let q = 1i64 << l.derived.fine_bits;
    for w in u.windows(2) {
        assert!(
            (w[1] - w[0]).abs() < q,
            "a step of a quadrant or more: {w:?}"
        );
    }
    // Means of blocks of 200 samples rise (0.3 rpm = 10.24 periods/s: 1.6 LSB per block).
    let means: Vec<f64> = u
        .chunks(200)
        .filter(|c| c.len() == 200)
        .map(|c| c.iter().sum::<i64>() as f64 / 200.0)
        .collect();
    for m in means.windows(2) {
        assert!(m[1] >= m[0] - 0.5, "block means fall: {means:?}");
    }
    assert!(means.last().unwrap_or(&0.0) > means.first().unwrap_or(&0.0));
    let s = r.stats;
    eprintln!("creep: {:?}", s);
}

/// Automatic calibration: with 5 % offsets and a 5 % gain mismatch, the error of the
/// uncorrected decoder is large; with `correction.mode = "peak"` it comes back within twice
/// the clean figure after the first calibrated periods.
#[test]
fn auto_calibration_removes_offset_and_gain_mismatch() {
    let clean = {
        let l = Loaded::default_config().expect("default");
        let o = SimOptions {
            profile: Profile::Constant { rpm: 300.0 },
            duration_s: 3e-3,
            amplitude: 0.8,
            noise_lsb: 1.0,
            seed: 11,
            ..compiled()
        };
        run(&l, &o, |_, _| {}).expect("runs").stats
    };
    let bad = SimOptions {
        profile: Profile::Constant { rpm: 300.0 },
        duration_s: 3e-3,
        amplitude: 0.8,
        noise_lsb: 1.0,
        offset: (0.05, -0.05),
        gain_mismatch: 0.05,
        seed: 11,
        // 300 rpm = 10.24 periods/ms, 127 samples per period: skip the first 2 periods
        // (the first update comes after one whole period).
        skip: 260,
        ..compiled()
    };
    let uncorrected = run(&Loaded::default_config().expect("default"), &bad, |_, _| {})
        .expect("runs")
        .stats;
    let text = sinedec::config::DEFAULT_CONFIG.replace("mode = \"static\"", "mode = \"peak\"");
    let auto = Loaded::parse(&text, "auto").expect("auto config");
    let corrected = run(&auto, &bad, |_, _| {}).expect("runs").stats;
    eprintln!("clean {clean:?}\nuncorrected {uncorrected:?}\nauto {corrected:?}");
    assert!(
        uncorrected.max_lsb > 4.0 * clean.max_lsb,
        "the fault is visible"
    );
    assert!(
        corrected.max_lsb <= 2.0 * clean.max_lsb,
        "{corrected:?} vs clean {clean:?}"
    );
    assert!(corrected.rms_lsb <= 2.0 * clean.rms_lsb);
}

/// Loss of signal: the amplitude drops to 10 % from 2.0 ms to 2.5 ms. The error flag is up
/// by the sample that completes the monitor's window (the window-th low sample, +1 for the
/// flag register) and clears within a window of the signal's return.
#[test]
fn loss_of_signal_raises_and_clears_the_error_flag() {
    use sinedec::sim::system::System;
    let l = Loaded::default_config().expect("default");
    let d = &l.derived;
    let o = SimOptions {
        profile: Profile::Constant { rpm: 300.0 },
        amplitude: 0.8,
        noise_lsb: 1.0,
        ..compiled()
    };
    let mut enc = sinedec::simulate::encoder(&l, &o);
    let (t0, t1) = (0.5e-3, 1.0e-3);
    enc.fault = Some((t0, t1, 0.1));
    let mut s = System::on(d, enc, EngineKind::Compiled).expect("system");
    s.start().expect("settles");
    s.run((1.5e-3 * d.clock_hz) as u64).expect("runs");
    let r = s.finish();
    let window = 8;
    let conv_t = |x: &sinedec::sim::system::Record| x.conv_cycle as f64 / d.clock_hz;
    let k0 = r
        .records
        .iter()
        .position(|x| conv_t(x) >= t0)
        .expect("fault starts");
    let k1 = r
        .records
        .iter()
        .position(|x| conv_t(x) >= t1)
        .expect("fault ends");
    // Before the fault (after start-up): no error.
    assert!(r.records[20..k0].iter().all(|x| !x.error));
    let first_err = r.records[k0..]
        .iter()
        .position(|x| x.error)
        .expect("error raised");
    eprintln!("error after {first_err} low samples; window {window}");
    assert!(first_err <= window, "raised after {first_err} samples");
    assert!(
        r.records[k0 + window..k1].iter().all(|x| x.error),
        "held during the fault"
    );
    let cleared = r.records[k1..]
        .iter()
        .position(|x| !x.error)
        .expect("cleared");
    eprintln!("cleared after {cleared} good samples");
    assert!(cleared <= window + 1, "cleared after {cleared} samples");
    assert!(r.records[k1 + window + 1..].iter().all(|x| !x.error));
}

/// Overspeed: a ramp from 0 to 25,000 rpm (2.6 quadrants per sample at the end, beyond
/// the 1.75-quadrant unwrap limit of 16,754 rpm). With the QEP fallback the position stays
/// right all the way (the QEP count resynchronises the CORDIC counter at every sample) and
/// the warning flag is raised above the limit; without it the count is lost.
#[test]
fn overspeed_raises_the_warning_and_the_qep_fallback_keeps_the_count() {
    let o = SimOptions {
        profile: Profile::Ramp {
            from: 0.0,
            to: 25_000.0,
            over: 1.5e-3,
        },
        duration_s: 1.5e-3,
        amplitude: 0.8,
        noise_lsb: 1.0,
        skip: 12,
        ..compiled()
    };
    let l = Loaded::default_config().expect("default");
    let r = run(&l, &o, |_, _| {}).expect("runs");
    let s = r.stats;
    let limit_rpm = l.derived.max_speed_rpm_full_res;
    // Speed at a record's conversion time.
    let rpm_at = |x: &sinedec::sim::system::Record| {
        25_000.0 * (x.conv_cycle as f64 / l.derived.clock_hz) / 1.5e-3
    };
    let warned_fast = r
        .result
        .records
        .iter()
        .filter(|x| rpm_at(x) > limit_rpm + 500.0)
        .all(|x| x.warning);
    let quiet_slow = r.result.records[12..]
        .iter()
        .filter(|x| rpm_at(x) < 0.8 * limit_rpm)
        .all(|x| !x.warning);
    eprintln!("with fallback: {s:?}, limit {limit_rpm:.0} rpm");
    assert!(warned_fast, "warning above the limit");
    assert!(quiet_slow, "no warning well below the limit");
    assert!(s.max_lsb < 20.0, "{s:?}");
    let text = sinedec::config::DEFAULT_CONFIG.replace("enabled = true", "enabled = false");
    let no_qep = Loaded::parse(&text, "no qep").expect("config");
    let s2 = run(&no_qep, &o, |_, _| {}).expect("runs").stats;
    eprintln!("without fallback: {s2:?}");
    assert!(
        s2.max_lsb > 16384.0,
        "without the fallback the count is lost: {s2:?}"
    );
}

/// The shipped configurations of the current dual SAR ADCs (`configs/ads8354_100mhz.toml`,
/// `configs/ad7380_100mhz.toml`: no `[board]`, 100 MHz, velocity, ABZ and BiSS-C) run end
/// to end like the default: the whole top against the chip's timed model decodes within the
/// noise bound at 300 and 3000 rpm, with every sample at the derived latency, every BiSS-C
/// frame good and equal to the parallel bus, and the ABZ count exact at every sample. The
/// chip models see no timing violation from power-up on (CS and SCK rest idle through
/// reset: `adc::adc_pins_rest_idle_from_power_up`).
#[test]
fn shipped_dual_sar_adc_configs_decode_and_read_back_end_to_end() {
    for file in ["ads8354_100mhz.toml", "ad7380_100mhz.toml"] {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("configs")
            .join(file);
        let l = Loaded::from_file(&path).unwrap_or_else(|e| panic!("{file}: {e}"));
        let (rms_b, max_b) = bounds(&l, 1.0, 0.8);
        for rpm in [300.0, 3000.0] {
            let o = SimOptions {
                profile: Profile::Constant { rpm },
                duration_s: 3e-3,
                amplitude: 0.8,
                noise_lsb: 1.0,
                seed: rpm as u64,
                ..compiled()
            };
            let r = run(&l, &o, |_, _| {}).unwrap_or_else(|e| panic!("{file}: {e}"));
            let (s, res) = (r.stats, &r.result);
            eprintln!(
                "{file} {rpm} rpm: {} samples, max {:.2} LSB (bound {max_b:.2}), RMS {:.2} LSB (bound {rms_b:.2})",
                s.samples, s.max_lsb, s.rms_lsb
            );
            assert!(s.samples > 1500, "{file}: {s:?}");
            assert_eq!(res.latency_mismatches, 0, "{file}");
            assert!(
                res.adc_violations.is_empty(),
                "{file}: {:?}",
                res.adc_violations
            );
            assert_eq!(s.errors + s.warnings, 0, "{file}");
            assert!(
                s.max_lsb <= max_b && s.rms_lsb <= rms_b,
                "{file} {rpm} rpm: {s:?}"
            );
            let b = res.biss.expect("BiSS-C master");
            assert!(b.frames > 50, "{file}: {b:?}");
            assert_eq!(
                (b.good, b.position_mismatches),
                (b.frames, 0),
                "{file}: {b:?}"
            );
            let a = res.abz.expect("ABZ counter");
            assert!(a.checked as usize + 2 >= s.samples, "{file}: {a:?}");
            assert_eq!((a.illegal, a.max_lag), (0, 0), "{file}: {a:?}");
            assert!(!res.velocity.is_empty(), "{file}: no velocity update");
        }
    }
}

/// The chip-select ADCs above the unwrap limit, where the QEP fallback loads the core's
/// counter at every sample: the QEP count it loads must be the one at the sample's own
/// conversion start, the chip select's fall (src/blocks/fallback/hdl.rs, `capture_depth`
/// and `conv_inverted`). It used to be captured at the CONV pin's rise with one frame of
/// pipeline (the LTC1407A-1's timing); for these chips that rise ends the frame, a period
/// and 4 clocks before the ADS8354's sample (no pipeline) and 33 clocks after the AD7380's,
/// and the position lost whole periods (65,536 LSB and more) at 20,000, 21,000 and
/// 60,000 rpm (ADS8354) and from 73,697 rpm on (AD7380). Noise-free constant speeds and a
/// ramp from rest through the limit: within a few LSB, with the warning raised.
#[test]
fn chip_select_adcs_keep_the_count_in_the_qep_fallback() {
    for (file, rpms, ramp_to) in [
        (
            "ads8354_100mhz.toml",
            [20_000.0, 21_000.0, 60_000.0],
            70_000.0,
        ),
        (
            "ad7380_100mhz.toml",
            [73_697.0, 80_000.0, 90_000.0],
            160_000.0,
        ),
    ] {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("configs")
            .join(file);
        let l = Loaded::from_file(&path).unwrap_or_else(|e| panic!("{file}: {e}"));
        let limit = l.derived.max_speed_rpm_full_res;
        let mut profiles: Vec<(Profile, f64)> = rpms
            .iter()
            .map(|&rpm| (Profile::Constant { rpm }, 3e-4))
            .collect();
        profiles.push((
            Profile::Ramp {
                from: 0.0,
                to: ramp_to,
                over: 2e-3,
            },
            2e-3,
        ));
        for (profile, duration_s) in profiles {
            let o = SimOptions {
                profile: profile.clone(),
                duration_s,
                ..compiled()
            };
            let s = run(&l, &o, |_, _| {})
                .unwrap_or_else(|e| panic!("{file}: {e}"))
                .stats;
            eprintln!("{file} {profile:?}: {s:?} (limit {limit:.0} rpm)");
            assert!(s.samples > 150, "{file} {profile:?}: {s:?}");
            // The run is in the fallback: the warning flags its samples above the limit.
            assert!(s.warnings > 0, "{file} {profile:?}: {s:?}");
            assert!(
                s.max_lsb < 4.0,
                "{file} {profile:?}: {s:?} (one period = 65,536 LSB)"
            );
        }
    }
}
