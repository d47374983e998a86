//! `simulate` tells the truth (issue 13, section E), at the library level: meaningless
//! options are rejected with the option's name and allowed range, a run without a decoded
//! sample is an error, single-turn positions compare modulo one turn, a decoder started
//! above the unwrap limit with the QEP fallback keeps a consistent count, the capacitive
//! path rejects the track imperfections it cannot model, `check` and `simulate` name their
//! latencies alike, and the capacitive `check` prints one speed limit (the CSV and VCD
//! outputs are in `tests/system/simulate_outputs.rs`).
use sinedec::config::{Loaded, DEFAULT_CONFIG};
use sinedec::sim::encoder::Profile;
use sinedec::simulate::{run, run_capacitive, SimOptions};

const CAP: &str = include_str!("../../configs/cyclone3_capacitive.toml");

pub(crate) fn default() -> Loaded {
    Loaded::default_config().expect("default config")
}

pub(crate) fn cap() -> Loaded {
    Loaded::parse(CAP, "cyclone3_capacitive.toml").expect("capacitive config")
}

fn err_of<T>(r: sinedec::error::Result<T>) -> String {
    match r {
        Ok(_) => panic!("accepted"),
        Err(e) => e.to_string(),
    }
}

/// Every meaningless option is rejected before the simulation runs, naming the option and
/// its allowed range.
#[test]
fn meaningless_options_are_rejected_by_name() {
    let l = default();
    let base = SimOptions {
        duration_s: 1e-3,
        ..Default::default()
    };
    let cases: Vec<(SimOptions, &str, &str)> = vec![
        (
            SimOptions {
                profile: Profile::Constant { rpm: f64::NAN },
                ..base.clone()
            },
            "--profile",
            "rpm",
        ),
        (
            SimOptions {
                profile: Profile::Constant { rpm: f64::INFINITY },
                ..base.clone()
            },
            "--profile",
            "rpm",
        ),
        (
            SimOptions {
                profile: Profile::Constant { rpm: 1e12 },
                ..base.clone()
            },
            "--profile",
            "1000000",
        ),
        (
            SimOptions {
                profile: Profile::Ramp {
                    from: 0.0,
                    to: 3000.0,
                    over: 0.0,
                },
                ..base.clone()
            },
            "--profile",
            "ramp time",
        ),
        (
            SimOptions {
                profile: Profile::Ramp {
                    from: 0.0,
                    to: 3000.0,
                    over: -1.0,
                },
                ..base.clone()
            },
            "--profile",
            "ramp time",
        ),
        (
            SimOptions {
                profile: Profile::Reversal {
                    rpm: 300.0,
                    at: 1e-4,
                    over: 0.0,
                },
                ..base.clone()
            },
            "--profile",
            "reversal time",
        ),
        (
            SimOptions {
                profile: Profile::Reversal {
                    rpm: 300.0,
                    at: f64::NAN,
                    over: 1e-4,
                },
                ..base.clone()
            },
            "--profile",
            "reversal start",
        ),
        (
            SimOptions {
                noise_lsb: -1.0,
                ..base.clone()
            },
            "--noise-lsb",
            "0..=10000",
        ),
        (
            SimOptions {
                noise_lsb: f64::NAN,
                ..base.clone()
            },
            "--noise-lsb",
            "0..=10000",
        ),
        (
            SimOptions {
                amplitude: 0.0,
                ..base.clone()
            },
            "--amplitude",
            "0 < amplitude <= 1",
        ),
        (
            SimOptions {
                amplitude: 1.5,
                ..base.clone()
            },
            "--amplitude",
            "0 < amplitude <= 1",
        ),
        (
            SimOptions {
                amplitude: f64::NAN,
                ..base.clone()
            },
            "--amplitude",
            "0 < amplitude <= 1",
        ),
        (
            SimOptions {
                offset: (f64::NAN, 0.0),
                ..base.clone()
            },
            "--offset-sin",
            "-1..=1",
        ),
        (
            SimOptions {
                offset: (0.0, 2.0),
                ..base.clone()
            },
            "--offset-cos",
            "-1..=1",
        ),
        (
            SimOptions {
                gain_mismatch: f64::NAN,
                ..base.clone()
            },
            "--gain-mismatch",
            "-1..=1",
        ),
        (
            SimOptions {
                phase_error_deg: f64::NAN,
                ..base.clone()
            },
            "--phase-error",
            "-45..=45",
        ),
        (
            SimOptions {
                third_harmonic: f64::INFINITY,
                ..base.clone()
            },
            "--harmonic3",
            "-0.5..=0.5",
        ),
        (
            SimOptions {
                duration_s: 0.0,
                ..base.clone()
            },
            "--duration",
            "0 < seconds <= 10",
        ),
        (
            SimOptions {
                second_harmonic: -0.6,
                ..base.clone()
            },
            "--harmonic2",
            "-0.5..=0.5",
        ),
        (
            SimOptions {
                fifth_harmonic: f64::NAN,
                ..base.clone()
            },
            "--harmonic5",
            "-0.5..=0.5",
        ),
        (
            SimOptions {
                harmonic_phase_deg: [0.0, 361.0, 0.0],
                ..base.clone()
            },
            "--harmonic3-phase",
            "-360..=360 degrees",
        ),
        (
            SimOptions {
                eccentricity_arcsec: 3601.0,
                ..base.clone()
            },
            "--eccentricity",
            "-3600..=3600 arc-seconds",
        ),
        (
            SimOptions {
                settle_s: -1e-3,
                ..base.clone()
            },
            "--settle",
            "0 <= seconds < --duration",
        ),
        (
            SimOptions {
                settle_s: 1e-3,
                ..base.clone()
            },
            "--settle",
            "leaves no sample",
        ),
    ];
    for (o, opt, allowed) in cases {
        let t0 = std::time::Instant::now();
        let e = err_of(run(&l, &o, |_, _| {}));
        assert!(e.contains(&format!("`{opt}`")), "{o:?}: {e}");
        assert!(e.contains(allowed), "{o:?}: {e}");
        // Rejected up front: a 1 ms run takes seconds of simulation.
        assert!(t0.elapsed().as_secs_f64() < 0.5, "{o:?} ran before failing");
    }
}

/// A run too short for any decoded sample past the settling ones is an error naming
/// `--duration` and the shortest run that works, not "max |error| 0.00 LSB".
#[test]
fn a_run_without_a_decoded_sample_is_an_error() {
    let l = default();
    let o = SimOptions {
        duration_s: 2e-6,
        ..Default::default()
    };
    let e = err_of(run(&l, &o, |_, _| {}));
    assert!(
        e.contains("`--duration`") && e.contains("no decoded sample"),
        "{e}"
    );
    // The capacitive path refuses such a run before simulating: its filters settle for a
    // fixed window that no run this short can pass.
    let c = cap();
    let e = err_of(run_capacitive(&c, &o, |_, _| {}));
    assert!(
        e.contains("`--duration`") && e.contains("settle") && e.contains("use at least"),
        "{e}"
    );
}

/// `--settle` within the run but after its last decoded sample is an error naming it,
/// on both paths, not "max |error| 0.00 LSB".
#[test]
fn a_settle_time_that_leaves_no_sample_is_an_error() {
    // The statistics would start within the run's last clock cycle: no sample leaves then.
    let l = default();
    let o = SimOptions {
        duration_s: 0.3e-3,
        settle_s: 0.3e-3 - 3e-9,
        ..Default::default()
    };
    let e = err_of(run(&l, &o, |_, _| {}));
    assert!(
        e.contains("`--settle`") && e.contains("leaves no sample"),
        "{e}"
    );
    let c = cap();
    let o = SimOptions {
        duration_s: 1.6e-3,
        settle_s: 1.6e-3 - 3e-9,
        ..Default::default()
    };
    let e = err_of(run_capacitive(&c, &o, |_, _| {}));
    assert!(
        e.contains("`--settle`") && e.contains("leaves no sample"),
        "{e}"
    );
}

/// `--settle S` counts exactly the samples that leave the top at S or later (past the
/// first 12): the streamed statistics (no CSV) equal the ones computed from the kept
/// records by that rule.
#[test]
fn settle_drops_the_samples_before_it() {
    let l = default();
    let d = &l.derived;
    let base = SimOptions {
        duration_s: 1e-3,
        profile: Profile::Constant { rpm: 3000.0 },
        third_harmonic: 0.02,
        ..Default::default()
    };
    let all = run(&l, &base, |_, _| {}).expect("run");
    let settle = 0.6e-3;
    let o = SimOptions {
        settle_s: settle,
        keep_records: false,
        ..base.clone()
    };
    let late = run(&l, &o, |_, _| {}).expect("settled run");
    let first = (settle * d.clock_hz).ceil() as u64;
    let kept: Vec<_> = all.result.records.iter().skip(base.skip).collect();
    let want = kept.iter().filter(|r| r.cycle >= first).count();
    assert!(
        want > 100 && want < kept.len() - 100,
        "{want} of {}",
        kept.len()
    );
    assert_eq!(late.stats.samples, want);
    let offset = all.result.offset_lsb(d);
    let max = kept
        .iter()
        .filter(|r| r.cycle >= first)
        .map(|r| sinedec::sim::system::SimResult::error_lsb(d, r, offset).abs())
        .fold(0.0, f64::max);
    assert!(
        (late.stats.max_lsb - max).abs() < 1e-9,
        "{} {max}",
        late.stats.max_lsb
    );
    assert!(late.summary(&l).contains("statistics from"));
}

/// The closed loop shows the encoder's distortion as its formulas give it: a 2 % third
/// harmonic as about 0.02 rad electrical (asin(h), 2^F / (pi / 2) LSB per rad), and 20
/// arc-seconds of eccentricity as a once-per-turn error of 20 arc-seconds, which the
/// summary names as one no per-period correction removes.
#[test]
fn the_closed_loop_shows_harmonics_and_eccentricity_at_their_size() {
    let l = default();
    let d = &l.derived;
    let lsb_per_rad = (1u64 << d.fine_bits) as f64 / std::f64::consts::FRAC_PI_2;
    let base = SimOptions {
        profile: Profile::Constant { rpm: 3000.0 },
        duration_s: 2e-3,
        keep_records: false,
        ..Default::default()
    };
    let clean = run(&l, &base, |_, _| {}).expect("clean").stats;
    let h3 = run(
        &l,
        &SimOptions {
            third_harmonic: 0.02,
            ..base.clone()
        },
        |_, _| {},
    )
    .expect("h3")
    .stats;
    let want = 0.02f64.asin() * lsb_per_rad;
    assert!(
        (h3.max_lsb - want).abs() < clean.max_lsb + 1.0,
        "h3 0.02: {} LSB, formula {want}, clean {}",
        h3.max_lsb,
        clean.max_lsb
    );
    // One whole turn at 3000 rpm: 20 ms.
    let arcsec = 20.0;
    let o = SimOptions {
        duration_s: 20e-3,
        eccentricity_arcsec: arcsec,
        ..base.clone()
    };
    let r = run(&l, &o, |_, _| {}).expect("eccentric");
    let per_lsb = 360.0 * 3600.0 / (d.quadrants_per_turn as f64 * (1u64 << d.fine_bits) as f64);
    let want = arcsec / per_lsb;
    assert!(
        (r.stats.max_lsb - want).abs() < clean.max_lsb + 1.0,
        "eccentricity {arcsec}\": {} LSB, formula {want}",
        r.stats.max_lsb
    );
    // A sine over whole turns: RMS = amplitude / sqrt 2.
    assert!(
        (r.stats.rms_lsb - want / 2f64.sqrt()).abs() < 0.01 * want,
        "{} against {}",
        r.stats.rms_lsb,
        want / 2f64.sqrt()
    );
    let s = r.summary(&l);
    assert!(
        s.contains("eccentricity") && s.contains("no per-period correction"),
        "{s}"
    );
}

/// Single-turn: the position wraps every turn, and the comparison does too. Reversing at
/// 3000 rpm through position 0 with multiturn_bits = 0 used to report 134,217,730 LSB.
#[test]
fn single_turn_configs_compare_modulo_one_turn() {
    let text = DEFAULT_CONFIG.replacen("multiturn_bits = 12", "multiturn_bits = 0", 1);
    let l = Loaded::parse(&text, "single.toml").expect("single-turn config");
    assert_eq!(l.derived.multiturn_bits, 0);
    let o = SimOptions {
        // Forward for 0.3 ms (0.015 turn), then back through 0 to about -0.03 turn.
        profile: Profile::Reversal {
            rpm: 3000.0,
            at: 3e-4,
            over: 2e-4,
        },
        duration_s: 1.2e-3,
        ..Default::default()
    };
    let r = run(&l, &o, |_, _| {}).expect("runs");
    // The decoded position did wrap (so the test exercises the wrap).
    let turn = l.derived.quadrants_per_turn << l.derived.fine_bits;
    assert!(
        r.result.records.iter().any(|x| x.position > turn / 2),
        "never wrapped"
    );
    eprintln!("single-turn reversal: max {:.2} LSB", r.stats.max_lsb);
    assert!(r.stats.max_lsb < 10.0, "{:?}", r.stats);
}

/// Started already turning above the unwrap limit (16,754 rpm for 2048 PPR at 1.307 Msps),
/// the QEP fallback used to freeze an offset taken from an aliased CORDIC count: a constant
/// whole-period error (65,538 LSB at 20,000 rpm, 196,610 at 22,000-26,000). The decoder
/// must report a position consistent with the count it resynchronises from.
#[test]
fn starting_above_the_unwrap_limit_keeps_a_consistent_count() {
    let l = default();
    let period = 4u64 << l.derived.fine_bits;
    for rpm in [17_000.0, 20_000.0, 22_000.0, 24_000.0, 26_000.0] {
        let o = SimOptions {
            profile: Profile::Constant { rpm },
            duration_s: 2.5e-4,
            ..Default::default()
        };
        let r = run(&l, &o, |_, _| {}).expect("runs");
        let s = r.stats;
        eprintln!(
            "start at {rpm} rpm: {} samples, max {:.2} LSB, mean {:.2} LSB",
            s.samples, s.max_lsb, s.mean_lsb
        );
        assert!(s.samples > 250);
        // Far below a period: the noise-free error of the fallback (the ramp test's 5.9 LSB
        // with noise).
        assert!(
            s.max_lsb < 8.0,
            "{rpm} rpm: {s:?} (one period = {period} LSB)"
        );
    }
}

/// The capacitive encoder model has no sin/cos tracks: the track imperfections are
/// rejected by name instead of being silently ignored.
#[test]
fn capacitive_path_rejects_track_imperfections() {
    let c = cap();
    let base = SimOptions {
        duration_s: 3e-3,
        ..Default::default()
    };
    for (o, opt) in [
        (
            SimOptions {
                phase_error_deg: 1.0,
                ..base.clone()
            },
            "--phase-error",
        ),
        (
            SimOptions {
                fifth_harmonic: 0.01,
                ..base.clone()
            },
            "--harmonic5",
        ),
        (
            SimOptions {
                eccentricity_arcsec: 10.0,
                ..base.clone()
            },
            "--eccentricity",
        ),
        (
            SimOptions {
                third_harmonic: 0.01,
                ..base.clone()
            },
            "--harmonic3",
        ),
        (
            SimOptions {
                offset: (0.05, 0.0),
                ..base.clone()
            },
            "--offset-sin",
        ),
        (
            SimOptions {
                offset: (0.0, 0.05),
                ..base.clone()
            },
            "--offset-cos",
        ),
        (
            SimOptions {
                gain_mismatch: 0.05,
                ..base.clone()
            },
            "--gain-mismatch",
        ),
    ] {
        let e = err_of(run_capacitive(&c, &o, |_, _| {}));
        assert!(
            e.contains(&format!("`{opt}`")) && e.contains("capacitive"),
            "{e}"
        );
    }
}

/// A `name  value` line of the describe text.
fn value_of(text: &str, label: &str) -> Option<f64> {
    let l = text.lines().find(|l| l.starts_with(label))?;
    l[label.len()..].split_whitespace().next()?.parse().ok()
}

/// `check` and `simulate` name the same latency the same way with the same value, and the
/// ADC's own latency (201 clocks) is named differently.
#[test]
fn check_and_simulate_name_their_latencies_alike() {
    let l = default();
    let check = format!("{}{}", l.derived.describe(), l.derived.adc.describe());
    let o = SimOptions {
        duration_s: 1e-4,
        ..Default::default()
    };
    let r = run(&l, &o, |_, _| {}).expect("runs");
    let sim = r.summary(&l);
    let label = "latency CONV -> position";
    let c = value_of(&check, label).expect("check prints the CONV -> position latency");
    let s = value_of(&sim, label).expect("simulate prints it");
    assert_eq!(c, s);
    // The records confirm it: every sample matched its conversion at that latency.
    assert_eq!(r.result.latency_mismatches, 0);
    // Any latency label both print has one value.
    for line in check.lines().filter(|l| l.contains("latency")) {
        let label = line[..28.min(line.len())].trim_end();
        if let (Some(a), Some(b)) = (value_of(&check, label), value_of(&sim, label)) {
            assert_eq!(a, b, "{label}");
        }
        // No bare "latency" label: each says what it spans.
        assert!(label.contains("->"), "{line}");
    }
}

/// The capacitive `check` printed two different speed limits (the CORDIC's unwrap limit,
/// 656,227 rpm, and the low-pass's 15,000 rpm): it prints one, the lower.
#[test]
fn capacitive_check_prints_one_speed_limit() {
    let c = cap();
    let text = c.derived.describe();
    let speed_lines: Vec<&str> = text.lines().filter(|l| l.contains(" rpm")).collect();
    assert_eq!(speed_lines.len(), 1, "{speed_lines:?}");
    // The low-pass corner (4 kHz) over 16 periods per turn: 15,000 rpm.
    let k = c.derived.capacitive.as_ref().unwrap();
    let want = k.config.lowpass.corner_hz.unwrap() / 16.0 * 60.0;
    assert_eq!(value_of(&text, "max speed"), Some(want.round()), "{text}");
}
