//! The synchronous capture in `<name>_top` (`[capture] enabled`), in the closed loop with
//! the encoder and the ADC chip models: the age a capture reports is the time from the
//! chip's own sampling instant to the capture pin, and the extrapolated position is the
//! encoder's true angle at the pin.
//!
//! The expectations come from the models, not from the block: the chip model stamps each
//! conversion with its own time (the loop's `Record::conv_cycle`, the instant whose encoder
//! angle it converts), and the loop knows when it raised `capture`; the encoder model gives
//! the true angle at that instant.
use sinedec::config::{Loaded, DEFAULT_CONFIG};
use sinedec::sim::encoder::{EncoderModel, Profile};
use sinedec::sim::system::{CaptureRecord, SimResult, System};

const VELOCITY: &str = "[velocity]\nenabled = true\nmethod = \"lsq\"\n";

fn config(base: &str, extra: &str) -> Loaded {
    let text = format!("{base}\n{extra}\n");
    Loaded::parse(&text, "capture_top.toml").expect("config")
}

/// Runs an ideal 2048-line encoder at `rpm` for `seconds` in the loop (rust-hdl), raising
/// `capture` for 1 us every `every` seconds from `from`.
fn run(l: &Loaded, rpm: f64, seconds: f64, from: f64, every: f64) -> SimResult {
    let d = &l.derived;
    let mut enc = EncoderModel::ideal(2048, 1.0, 0.0);
    enc.start_turns = 0.3;
    enc.profile = Profile::Constant { rpm };
    let mut s = System::new(d, enc).expect("system");
    let n = ((seconds - from) / every) as usize;
    let pulses: Vec<(f64, f64)> = (0..n)
        .map(|i| {
            let t = from + i as f64 * every;
            (t, t + 1e-6)
        })
        .collect();
    s.capture_pulses(&pulses);
    s.start().expect("settles");
    s.run((seconds * d.clock_hz) as u64).expect("runs");
    let r = s.finish();
    assert_eq!(r.captures.len(), n, "one capture per pulse");
    r
}

/// The decoded sample a capture without extrapolation took: the latest record with its
/// position and turns before the capture.
fn taken<'a>(r: &'a SimResult, c: &CaptureRecord) -> &'a sinedec::sim::system::Record {
    r.records
        .iter()
        .rev()
        .filter(|x| x.cycle <= c.cycle)
        .find(|x| x.position == c.position && x.turns == c.turns)
        .unwrap_or_else(|| panic!("no sample matches the capture at cycle {}", c.cycle))
}

#[test]
fn the_age_is_the_time_from_the_chips_sample_to_the_pin() {
    // The kit (LTC1407A-1, CONV pulse) and a chip-select ADC (ADS8354, sampling at CS
    // fall), each with pulses at many phases of the ADC period (23.37 us is no multiple of
    // it).
    for (base, name) in [
        (DEFAULT_CONFIG.to_string(), "ltc1407a"),
        (
            std::fs::read_to_string("configs/ads8354_100mhz.toml").expect("config"),
            "ads8354",
        ),
    ] {
        let l = config(&base, "[capture]\nenabled = true\n");
        let d = &l.derived;
        let r = run(&l, 3000.0, 700e-6, 20e-6, 23.37e-6);
        assert_eq!(r.latency_mismatches, 0, "{name}");
        let p = d.capture.expect("capture");
        let mut ages = vec![];
        for c in &r.captures {
            let s = taken(&r, c);
            // The chip converts the encoder's angle at conv_cycle; the loop raised the pin
            // for cycle pin_cycle, so it rose in the clock before: the true age lies in
            // (pin - conv - 1, pin - conv] clocks, and the block reports its lower end.
            assert_eq!(
                c.age,
                c.pin_cycle - s.conv_cycle - 1,
                "{name}: capture at cycle {} (pin {}, sample of conv {})",
                c.cycle,
                c.pin_cycle,
                s.conv_cycle
            );
            assert_eq!(
                c.cycle - c.pin_cycle,
                p.capture_latency() as u64,
                "{name}: cap_valid after the pin"
            );
            ages.push(c.age);
        }
        let (lo, hi) = (ages.iter().min().copied(), ages.iter().max().copied());
        let l0 = p.latency() as u64;
        let per = d.adc.period_clocks as u64;
        // The ages span the period (to within an eighth of it), and stay in L - 1 ..= L + P - 2
        // as `check` prints.
        let slack = per / 8;
        assert!(
            lo.is_some_and(|a| a <= l0 - 1 + slack)
                && hi.is_some_and(|a| a + slack >= l0 + per - 2),
            "{name}: ages {lo:?}..{hi:?} do not span L - 1 = {} ..= L + P - 2 = {}",
            l0 - 1,
            l0 + per - 2
        );
        assert!(lo.is_some_and(|a| a >= l0 - 1) && hi.is_some_and(|a| a <= l0 + per - 2));
    }
}

#[test]
fn the_extrapolated_capture_is_the_true_angle_at_the_pin_forward() {
    extrapolated_capture_at(3000.0);
}

#[test]
fn the_extrapolated_capture_is_the_true_angle_at_the_pin_backward() {
    extrapolated_capture_at(-3000.0);
}

/// Captures with extrapolation at `rpm`: each is the true angle at its pin.
fn extrapolated_capture_at(rpm: f64) {
    {
        let l = config(
            DEFAULT_CONFIG,
            &format!("{VELOCITY}\n[capture]\nenabled = true\nextrapolate = true\n"),
        );
        let d = &l.derived;
        // The lsq estimator has settled once 4 updates have run (0.53 ms).
        let r = run(&l, rpm, 0.85e-3, 0.6e-3, 17.3e-6);
        // The decoder's own alignment to the encoder (the kit's inverting amplifier, the
        // turn count's start): the median of decoded - true over the samples.
        let mut off: Vec<f64> = r
            .records
            .iter()
            .skip(20)
            .map(|x| x.unwrapped as f64 - x.truth)
            .collect();
        off.sort_by(f64::total_cmp);
        let offset = off[off.len() / 2];
        let decoder = off.last().copied().unwrap_or(0.0) - off[0];
        let lsb_per_clock =
            rpm.abs() / 60.0 * d.quadrants_per_turn as f64 * (1u64 << d.fine_bits) as f64
                / d.clock_hz;
        let v = d.velocity.as_ref().expect("velocity");
        let per_clock =
            |raw: i64| raw as f64 / (1u64 << v.spec.frac_bits) as f64 / v.period_clocks as f64;
        let sign = rpm.signum();
        for c in &r.captures {
            let e = c.unwrapped as f64 - c.truth - offset;
            // The estimate's own error (the lsq fit of positions taken at the update ticks
            // jitters by about 0.1 %) moves the extrapolation by its error times the age.
            let ev = (per_clock(c.velocity) - sign * lsb_per_clock) * (c.age as f64 + 0.5);
            // Within the decoder's own spread, half a clock's motion (the pin rose somewhere
            // in the clock whose middle the block carries the position to) and 2 LSB (the
            // extrapolation's 3/4 LSB, the velocity's rounding).
            assert!(
                (e - ev).abs() <= decoder + 2.0 + lsb_per_clock / 2.0,
                "{rpm} rpm: capture at cycle {} is {e:.2} LSB from the truth at the pin, {ev:.2} of it the velocity's error (decoder spread {decoder:.2})",
                c.cycle
            );
            // Without the extrapolation it would trail by the age's motion: the test can
            // fail.
            assert!(
                lsb_per_clock * c.age as f64 > 10.0 * (decoder + 2.0 + lsb_per_clock / 2.0),
                "{rpm} rpm: the age's motion is too small for the test to tell"
            );
        }
    }
}

#[test]
fn top_with_the_capture_replays_in_icarus_verilator_and_the_engine() {
    use sinedec::blocks::top::hdl::TopRtl;
    use sinedec::cosim::CosimBlock;
    use sinedec::verify::{block_traces, Simulators};
    let l = config(
        DEFAULT_CONFIG,
        &format!("{VELOCITY}\n[capture]\nenabled = true\nextrapolate = true\n"),
    );
    let d = &l.derived;
    let mut enc = EncoderModel::ideal(2048, 1.0, 0.0);
    enc.profile = Profile::Constant { rpm: 3000.0 };
    let mut s = System::new(d, enc).expect("system");
    s.capture_pulses(&[(5e-6, 6e-6), (12.3e-6, 13e-6), (20.1e-6, 21e-6)]);
    s.record_inputs();
    s.start().expect("settles");
    s.run(3500).expect("runs");
    let r = s.finish();
    assert_eq!(r.captures.len(), 3);
    let top = TopRtl::new(d).expect("top");
    let outs = top.output_ports();
    assert!(top.input_ports().iter().any(|p| p.name == "capture_0"));
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("capture_top");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("dir");
    let t = block_traces(top, "sd_top_rtl", "clk", &r.inputs, Simulators::ALL, &dir)
        .expect("simulators ran");
    if let Some(m) = t.mismatch() {
        panic!("{m}");
    }
    let col = |n: &str| outs.iter().position(|p| p.name == n).expect("port");
    let v = col("cap_valid_0");
    assert_eq!(t.rust_hdl.iter().filter(|row| row[v] == 1).count(), 3);
    assert!(outs.iter().any(|p| p.name == "cap_velocity_0"));
}

#[test]
fn simulate_pulses_the_capture_and_reports_age_and_error() {
    use sinedec::simulate::{run, SimOptions};
    let l = config(DEFAULT_CONFIG, "[capture]\nenabled = true\n");
    let d = &l.derived;
    let o = SimOptions {
        profile: Profile::Constant { rpm: 3000.0 },
        duration_s: 200e-6,
        capture_hz: Some(50_000.0),
        engine: sinedec::sim::dut::EngineKind::RustHdl,
        ..Default::default()
    };
    let r = run(&l, &o, |_, _| {}).expect("runs");
    let s = r.result.capture_stats(d).expect("captures");
    // Pulses at 20, 40, .. 200 us: 9 complete within the run (the 10th answers after it).
    assert_eq!(s.captures, 9);
    let lat = d.capture.expect("capture").latency() as u64;
    let per = d.adc.period_clocks as u64;
    assert!(s.age.0 >= lat - 1 && s.age.1 <= lat + per - 2, "{s:?}");
    // Not extrapolated: each capture trails the pin by the motion during its age, at
    // 3000 rpm 50.3 LSB per clock, so between (L - 1) and (L + P - 1) clocks of it, within
    // the decoder's few LSB.
    let per_clock =
        3000.0 / 60.0 * d.quadrants_per_turn as f64 * (1u64 << d.fine_bits) as f64 / d.clock_hz;
    assert!(
        s.max_lsb > per_clock * (lat - 1) as f64 - 10.0
            && s.max_lsb < per_clock * (lat + per) as f64 + 10.0,
        "{s:?}"
    );
    let text = r.summary(&l);
    assert!(
        text.contains("captures                    9: age"),
        "{text}"
    );
    assert!(text.contains("not extrapolated"), "{text}");
    // Without [capture], --capture-hz is an error naming the option.
    let plain = config(DEFAULT_CONFIG, "");
    let e = run(&plain, &o, |_, _| {})
        .err()
        .expect("rejected")
        .to_string();
    assert!(e.contains("--capture-hz") && e.contains("[capture]"), "{e}");
    let bad = SimOptions {
        capture_hz: Some(0.0),
        ..o
    };
    let e = run(&l, &bad, |_, _| {})
        .err()
        .expect("rejected")
        .to_string();
    assert!(e.contains("--capture-hz") && e.contains("100000"), "{e}");
}
