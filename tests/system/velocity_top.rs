//! The velocity estimator inside the rust-hdl `<name>_top` (`[velocity] enabled`): the
//! closed loop (encoder -> LTC1407A-1 model -> top) replayed in Icarus and Verilator equals
//! rust-hdl on every pin including `par_velocity_0` / `par_velocity_valid_0`; those equal the
//! bit-accurate `VelocityModel` fed with the top's own parallel bus; at constant speed every
//! estimate lies within a bound derived from the decoder's position error of the true speed;
//! the compiled engine gives the same velocity records as rust-hdl; `simulate` reports it.
use crate::common;

use common::replay_top_in_simulators;
use sinedec::blocks::mask;
use sinedec::blocks::top::hdl::{TopRtl, BLOCK_RESET_CLOCKS};
use sinedec::blocks::velocity::model::{VelIn, VelocityModel};
use sinedec::config::{Loaded, DEFAULT_CONFIG};
use sinedec::cosim::CosimBlock;

/// The default configuration with the tracking estimator at 200 kHz (667 clocks per update)
/// and a 20 kHz loop bandwidth (the defaults' 7.5 kHz and 200 Hz scaled by about 27 and
/// 100, so that the loop settles within 9 updates and a run stays short).
pub fn config() -> Loaded {
    let text = format!(
        "{DEFAULT_CONFIG}\n[velocity]\nenabled = true\nrate_hz = 200e3\nbandwidth_hz = 20000.0\n"
    );
    Loaded::parse(&text, "velocity_top.toml").expect("config")
}

/// The column of output `name` in the top's co-simulation rows.
fn col(top: &TopRtl, name: &str) -> usize {
    top.output_ports()
        .iter()
        .position(|p| p.name == name)
        .unwrap_or_else(|| panic!("no output {name}"))
}

#[test]
fn top_velocity_equals_the_model_in_rust_hdl_icarus_and_verilator() {
    let l = config();
    let d = &l.derived;
    let p = d.velocity.as_ref().expect("enabled");
    // 20,000 clocks at 3000 rpm: about 30 updates, the loop settled after 9.
    let r = replay_top_in_simulators(&l, 3000.0, 20_000, "velocity_top");
    let top = TopRtl::new(d).expect("top");
    let (cv, cvv) = (
        col(&top, "par_velocity_0"),
        col(&top, "par_velocity_valid_0"),
    );
    let (cvalid, cqc, cfine) = (
        col(&top, "par_valid"),
        col(&top, "par_qc"),
        col(&top, "par_fine"),
    );
    let rst_col = top
        .input_ports()
        .iter()
        .position(|p| p.name == "rst")
        .expect("rst");
    // The estimator takes the top's parallel bus (the core's registered outputs) at the next
    // edge: the model steps on the previous row's bus. Its reset is the top's `rst`
    // registered (`BLOCK_RESET_CLOCKS`), asserted from power-up.
    let mut model = VelocityModel::new(p);
    let f2 = mask(d.fine_bits + 2);
    let mut prev = (false, 0u64);
    let mut updates = 0;
    for (k, outs) in r.outputs.iter().enumerate() {
        let rst = k
            .checked_sub(BLOCK_RESET_CLOCKS as usize)
            .is_none_or(|j| r.inputs[j][rst_col] != 0);
        let v = model.step(VelIn {
            rst,
            valid: prev.0,
            p: prev.1 & f2,
        });
        assert_eq!(
            (outs[cv], outs[cvv]),
            (v.velocity, v.valid as u64),
            "cycle {k}: rtl vs model"
        );
        updates += v.valid as usize;
        prev = (outs[cvalid] != 0, (outs[cqc] << d.fine_bits) | outs[cfine]);
    }
    assert!(updates >= 25, "{updates} updates");
    // The closed loop's own records: one per strobe, with the model's values.
    assert_eq!(r.velocity.len(), updates);
    let last = r.velocity.last().expect("updates");
    assert!(last.raw > 0, "forward rotation, {last:?}");
}

/// The largest |estimate - truth| the tracking loop can give at constant speed when the
/// position it takes at every tick is off by at most `e_max` LSB from a ramp: the loop is
/// linear and has no steady-state error on a ramp, so the velocity error is the loop's
/// response to the position error sequence, at most e_max times the L1 norm of its
/// impulse response from position to velocity (an f64 run of the ideal loop with the
/// configured gains).
fn tracking_bound(alpha: f64, beta: f64, e_max: f64) -> f64 {
    let (mut theta, mut w) = (0.0f64, 0.0f64);
    let mut l1 = 0.0;
    for k in 0..10_000 {
        let x = if k == 0 { 1.0 } else { 0.0 };
        let e = x - theta;
        w += beta * e;
        theta += w + alpha * e;
        l1 += w.abs();
    }
    e_max * l1
}

#[test]
fn constant_speed_estimate_is_within_the_position_error_bound_on_both_engines() {
    use sinedec::sim::dut::EngineKind;
    use sinedec::sim::encoder::EncoderModel;
    use sinedec::sim::system::System;
    let l = config();
    let d = &l.derived;
    let p = d.velocity.as_ref().expect("enabled");
    let rpm = 1234.5;
    let mut runs = vec![];
    for engine in [EngineKind::Compiled, EngineKind::RustHdl] {
        let cycles = if engine == EngineKind::Compiled {
            400_000
        } else {
            30_000
        };
        let mut s = System::on(d, EncoderModel::ideal(2048, 1.0, rpm), engine).expect("system");
        s.start().expect("settles");
        s.run(cycles).expect("runs");
        runs.push(s.finish());
    }
    // Both engines: the same updates, bit for bit, over the rust-hdl run.
    let n = runs[1].velocity.len();
    assert!(n >= 30, "{n} updates");
    assert_eq!(runs[0].velocity[..n], runs[1].velocity[..]);
    let r = &runs[0];
    let pos = r.stats(d, 12);
    let s = r.velocity_stats(d).expect("updates after the warm-up");
    assert!(s.updates > 500, "{} updates", s.updates);
    let (alpha, beta) = match &p.consts {
        sinedec::blocks::velocity::MethodConsts::Tracking { alpha, beta } => (
            *alpha as f64 / (1u64 << 18) as f64,
            *beta as f64 / (1u64 << 18) as f64,
        ),
        c => panic!("tracking expected, got {c:?}"),
    };
    let truth = rpm / 60.0 * d.quadrants_per_turn as f64 * (1u64 << d.fine_bits) as f64
        / (d.clock_hz / p.period_clocks as f64);
    // The position error at a tick: the decoder's error about its mean (the constant
    // offset does not move the speed), plus the age of the latest decoded sample, which
    // varies over one ADC sample period from tick to tick: within +-v Ts / 2 of its mean
    // at v LSB per sample. Then the loop's response, plus one output LSB of rounding.
    let per_sample = truth / (p.period_clocks as f64 / d.adc.period_clocks as f64);
    let e_max = pos.max_lsb + pos.mean_lsb.abs() + per_sample / 2.0;
    let bound = tracking_bound(alpha, beta, e_max) + 2f64.powi(-(p.spec.frac_bits as i32));
    assert!(
        (s.last_truth - truth).abs() < 1e-6 * truth,
        "{} vs {truth}",
        s.last_truth
    );
    assert!(
        s.max_err <= bound,
        "max |error| {} LSB/period above the bound {bound} (position max {} LSB)",
        s.max_err,
        pos.max_lsb
    );
    // No steady-state error: the mean over the run is far inside the per-update bound
    // (the sample-age term averages out over the run).
    assert!(
        s.mean_err.abs() < bound / 50.0,
        "mean {} vs bound {bound}",
        s.mean_err
    );
    eprintln!(
        "velocity at {rpm} rpm: truth {truth:.3} LSB/period, mean error {:.4}, std {:.4}, max {:.4}, bound {bound:.4} (position max {:.2} LSB)",
        s.mean_err, s.std_err, s.max_err, pos.max_lsb
    );
}

#[test]
fn simulate_reports_the_velocity_only_when_enabled() {
    use sinedec::simulate::{run, SimOptions};
    let on = config();
    let o = SimOptions {
        duration_s: 0.003,
        engine: sinedec::sim::dut::EngineKind::Compiled,
        ..Default::default()
    };
    let rep = run(&on, &o, |_, _| {}).expect("runs");
    let text = rep.summary(&on);
    for line in [
        "velocity updates",
        "velocity error mean",
        "velocity error std",
        "velocity at the end",
    ] {
        assert!(text.contains(line), "{line} missing:\n{text}");
    }
    let csv = rep.csv(&on, o.skip);
    let header = csv.lines().next().expect("header");
    assert!(
        header.ends_with(",velocity_lsb,velocity_truth_lsb"),
        "{header}"
    );
    // A row after the first update carries the estimate.
    let last = csv.lines().last().expect("rows");
    assert!(!last.ends_with(",,"), "{last}");
    let off = Loaded::parse(DEFAULT_CONFIG, "d.toml").expect("default");
    let rep = run(&off, &o, |_, _| {}).expect("runs");
    assert!(!rep.summary(&off).contains("velocity"));
    assert!(!rep.csv(&off, o.skip).contains("velocity"));
}

/// The number after `label` (after the line's start when empty) in the summary line that
/// starts with `line`.
fn number_after(text: &str, line: &str, label: &str) -> f64 {
    let l = text
        .lines()
        .find(|l| l.starts_with(line))
        .unwrap_or_else(|| panic!("no `{line}` line in:\n{text}"));
    let rest = &l[line.len()..];
    let rest = &rest[rest
        .find(label)
        .unwrap_or_else(|| panic!("no `{label}` in `{l}`"))
        + label.len()..];
    let word = rest.split_whitespace().next().expect("a number");
    word.trim_matches(|c| c == '(' || c == ')')
        .parse()
        .unwrap_or_else(|e| panic!("`{word}` in `{l}`: {e}"))
}

/// `sinedec simulate` without `--csv` keeps no records (bounded memory); the velocity
/// statistics must still print, and equal those of the same run with its records kept
/// (the library's `keep_records`, the path `--csv` takes). At 300 rpm and 667 clocks per
/// update (200 kHz asked) the true speed is 300 / 60 x 8192 x 2^14 x 667 / 133.33e6 =
/// 3357.2 LSB per update period.
#[test]
fn simulate_prints_the_velocity_statistics_without_csv() {
    use sinedec::simulate::{run, SimOptions};
    let dir = tempfile::tempdir().expect("tempdir");
    let text = format!(
        "{DEFAULT_CONFIG}\n[velocity]\nenabled = true\nrate_hz = 200e3\nbandwidth_hz = 20000.0\n"
    );
    std::fs::write(dir.path().join("v.toml"), &text).expect("write");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_sinedec"))
        .args([
            "simulate",
            "v.toml",
            "--duration",
            "0.003",
            "--profile",
            "constant:300",
        ])
        .current_dir(dir.path())
        .output()
        .expect("sinedec runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let cli = String::from_utf8(out.stdout).expect("utf-8");
    assert!(!cli.contains("no update after the warm-up"), "{cli}");
    let l = config();
    let rep = run(
        &l,
        &SimOptions {
            duration_s: 0.003,
            keep_records: true,
            ..Default::default()
        },
        |_, _| {},
    )
    .expect("runs");
    let s = rep.result.velocity_stats(&l.derived).expect("updates");
    let updates = number_after(&cli, "velocity error mean", "rpm (");
    assert_eq!(updates, s.updates as f64, "{cli}");
    assert!(updates > 100.0, "{cli}");
    let mean = number_after(&cli, "velocity error mean", "");
    assert!(
        (mean - s.mean_err).abs() < 1e-4,
        "{mean} vs {}: {cli}",
        s.mean_err
    );
    let std = number_after(&cli, "velocity error std", "");
    assert!(
        (std - s.std_err).abs() < 1e-4,
        "{std} vs {}: {cli}",
        s.std_err
    );
    let v = l.derived.velocity.as_ref().expect("enabled");
    let truth = 300.0 / 60.0 * 8192.0 * 16384.0 * v.period_clocks as f64 / l.derived.clock_hz;
    let last_truth = number_after(&cli, "velocity at the end", "(true ");
    assert!((last_truth - truth).abs() < 1e-3, "{last_truth} vs {truth}");
    let last = number_after(&cli, "velocity at the end", "");
    // The last estimate lies within the run's largest error of the truth, and the mean
    // error is a small fraction of the speed.
    let max = number_after(&cli, "velocity error std", "max |error| ");
    assert!(
        (last - truth).abs() <= max + 1e-3,
        "{last} vs {truth}: {cli}"
    );
    assert!(mean.abs() < 0.01 * truth, "{mean} vs {truth}: {cli}");
}

/// The configuration of [`config`] with the velocity word in the frames, the SSI and SPI
/// slaves on, and 2 us timeouts (many frames in a short run).
fn frames_config() -> Loaded {
    let text = DEFAULT_CONFIG
        .replacen("timeout_us = 20.0", "timeout_us = 2.0", 1)
        .replace(
            "[ssi]\n# SSI slave on ssi_clk/ssi_data, sending the BiSS data word (binary or Gray).\nenabled = false\ngray = false\ntimeout_us = 20.0",
            "[ssi]\nenabled = true\ngray = false\ntimeout_us = 2.0",
        )
        .replace(
            "enc_miso: the BiSS data word, then E and W.\nenabled = false",
            "enc_miso: the BiSS data word, then E and W.\nenabled = true",
        );
    let text = format!(
        "{text}\n[velocity]\nenabled = true\nrate_hz = 200e3\nbandwidth_hz = 20000.0\nin_frames = true\n"
    );
    let l = Loaded::parse(&text, "velocity_frames.toml").expect("config");
    assert!(l.derived.ssi.is_some() && l.derived.spi.is_some());
    assert_eq!(l.derived.biss.velocity_bits, 32);
    l
}

#[test]
fn biss_ssi_and_spi_frames_carry_par_velocity_and_replay_in_icarus_and_verilator() {
    use sinedec::sim::biss_master::{BissMaster, BissMasterConfig};
    use sinedec::sim::encoder::EncoderModel;
    use sinedec::sim::serial_line::{FrameRequest, LineTiming};
    use sinedec::sim::spi_master::{decode_word, SpiMaster, SpiTxn};
    use sinedec::sim::ssi_master::{SsiMaster, SsiMasterConfig, SsiOutcome};
    use sinedec::sim::system::System;
    use sinedec::verify::{block_traces, Simulators};
    use std::cell::RefCell;
    use std::rc::Rc;
    let l = frames_config();
    let d = &l.derived;
    let p = d.velocity.as_ref().expect("enabled");
    let v = p.spec.width;
    let clock = d.clock_hz;
    let rpm = 300.0;
    let mut s = System::new(d, EncoderModel::ideal(2048, 1.0, rpm)).expect("system");
    let timing = LineTiming {
        clock_hz: clock,
        line_delay_ns: 25.0,
    };
    let pb = d.biss.position_bits;
    let bcfg = BissMasterConfig {
        word: sinedec::sim::serial_line::WordFormat::new(pb, 0).with_velocity(v),
        ..BissMasterConfig::new(timing, pb, 0)
    };
    let reqs: Vec<FrameRequest> = (0..40)
        .map(|_| FrameRequest::new(10e6).gap(300.0))
        .collect();
    let biss = Rc::new(RefCell::new(BissMaster::new(bcfg, reqs, 15_000.0)));
    // SSI samples at the next rising edge: the slave's answer (2-4 clocks) plus the round
    // trip must fit one period, so a slower clock.
    let reqs: Vec<FrameRequest> = (0..40).map(|_| FrameRequest::new(5e6).gap(300.0)).collect();
    s.attach_master(Box::new(biss.clone()));
    let mut scfg = SsiMasterConfig::new(timing, pb, 0);
    scfg.word = scfg.word.with_velocity(v);
    let ssi = Rc::new(RefCell::new(SsiMaster::new(scfg, reqs, 17_000.0)));
    s.attach_ssi_master(Box::new(ssi.clone()));
    // SPI mode 0 at 5 MHz: N + W + 2 clocks per word (data, velocity, E, W).
    let txns: Vec<SpiTxn> = (0..12)
        .map(|_| SpiTxn {
            mode: 0,
            sck_hz: 5e6,
            clocks: pb + v + 2,
            gap_ns: 4000.0,
        })
        .collect();
    let spi = Rc::new(RefCell::new(SpiMaster::new(timing, &txns, 16_000.0)));
    s.attach_spi_master(spi.clone());
    s.record_inputs();
    s.start().expect("settles");
    let mut vels = vec![];
    let cycles = (250e-6 * clock) as u64;
    for _ in 0..cycles {
        s.run(1).expect("runs");
        let t = s.top().expect("rust-hdl top");
        vels.push(sinedec::blocks::sext(t.par_velocity[0].val().to_u64(), v));
    }
    let r = s.finish();
    // The frame latches par_velocity with the position at its first clock edge (F1 reaches
    // the slave one line delay after the master sends it, plus the synchronizer).
    let window = |t_start_ns: f64| {
        let c0 = ((t_start_ns + 25.0) * clock / 1e9) as usize;
        vels[c0.saturating_sub(1)..(c0 + 6).min(vels.len())].to_vec()
    };
    let bframes = biss.borrow().frames().to_vec();
    assert!(bframes.len() >= 12, "{} BiSS frames", bframes.len());
    let mut moving = 0;
    for f in &bframes {
        let g = f.good().unwrap_or_else(|| panic!("bad BiSS frame {f:?}"));
        let got = g.velocity.expect("velocity word");
        let w = window(f.t_start_ns);
        assert!(w.contains(&got), "BiSS velocity {got} not among {w:?}");
        moving += (got > 0) as usize;
    }
    // After the first position the estimate is positive (the forward rotation) in every
    // frame: the word is not stuck at 0.
    assert!(moving >= bframes.len() / 2, "{moving} frames with v > 0");
    let sframes = ssi.borrow().frames().to_vec();
    assert!(sframes.len() >= 8, "{} SSI frames", sframes.len());
    for f in &sframes {
        let SsiOutcome::Data(g) = &f.outcome else {
            panic!("bad SSI frame {f:?}")
        };
        let got = g.velocity.expect("velocity word");
        let w = window(f.t_start_ns);
        assert!(w.contains(&got), "SSI velocity {got} not among {w:?}");
    }
    // SPI: chip select latches the word (cs_n reaches the slave one line delay later).
    let spi = spi.borrow();
    let fmt = sinedec::sim::serial_line::WordFormat::new(pb, 0).with_velocity(v);
    let words = spi.words();
    assert_eq!(words.len(), 12);
    for (x, bits) in spi.txns().iter().zip(&words) {
        let w = decode_word(bits, &fmt).expect("whole word");
        let got = w.velocity.expect("velocity word");
        let win = window(x.t_cs_ns);
        assert!(win.contains(&got), "SPI velocity {got} not among {win:?}");
    }
    // The same run's inputs through the exported top in Icarus and Verilator.
    let dir = common::workdir("velocity_frames");
    let t = block_traces(
        TopRtl::new(d).expect("top"),
        "sd_top_rtl",
        "clk",
        &r.inputs,
        Simulators::ALL,
        &dir,
    )
    .expect("simulators ran");
    if let Some(m) = t.mismatch() {
        panic!("{m}");
    }
    assert!(t.rust_hdl == r.outputs, "the replay equals the closed loop");
    // The settled estimate is the true speed within the bound of the constant-speed test.
    let st = r.velocity_stats(d).expect("updates");
    let truth = rpm / 60.0 * d.quadrants_per_turn as f64 * (1u64 << d.fine_bits) as f64
        / (clock / p.period_clocks as f64);
    let last = *bframes
        .last()
        .and_then(|f| f.good())
        .and_then(|g| g.velocity.as_ref())
        .expect("last");
    let (alpha, beta) = match &p.consts {
        sinedec::blocks::velocity::MethodConsts::Tracking { alpha, beta } => (
            *alpha as f64 / (1u64 << 18) as f64,
            *beta as f64 / (1u64 << 18) as f64,
        ),
        c => panic!("tracking expected, got {c:?}"),
    };
    let pos = r.stats(d, 12);
    let per_sample = truth / (p.period_clocks as f64 / d.adc.period_clocks as f64);
    let bound = tracking_bound(
        alpha,
        beta,
        pos.max_lsb + pos.mean_lsb.abs() + per_sample / 2.0,
    ) + 2f64.powi(-(p.spec.frac_bits as i32));
    let est = last as f64 / (1u64 << p.spec.frac_bits) as f64;
    assert!(
        (est - truth).abs() <= bound,
        "last BiSS velocity {est} vs truth {truth}, bound {bound}"
    );
    assert!(st.max_err <= bound, "{st:?} bound {bound}");
}
