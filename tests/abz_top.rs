//! ABZ emulation in `<name>_top` (`[abz] enabled`): the closed loop (encoder model -> ADC
//! model -> the top in rust-hdl) through position 0 both ways and a reversal, with an independent
//! quadrature counter on `abz_a`/`abz_b` checked against the position the top reports on
//! its parallel bus; the top replays bit-exactly in Icarus and Verilator; the wrapper and
//! the UCF get the three outputs only when enabled.
use sinedec::blocks::abz::AbzParams;
use sinedec::config::{Loaded, DEFAULT_CONFIG};
use sinedec::sim::encoder::{EncoderModel, Profile};
use sinedec::sim::system::System;

fn config(extra: &str) -> Loaded {
    let text = format!("{DEFAULT_CONFIG}\n[abz]\nenabled = true\n{extra}\n");
    Loaded::parse(&text, "abz_top.toml").expect("config")
}

/// floor(p * E / P) for the single-turn position p, from the definition in 128-bit integers.
fn exact_count(a: &AbzParams, p: u64) -> i64 {
    let e = 4 * a.lines() as u128;
    ((p as u128 * e) / a.positions() as u128) as i64
}

/// Gray index of (A, B): 00 -> 0, 10 -> 1, 11 -> 2, 01 -> 3 (A leads B forward).
fn gray_index(a: bool, b: bool) -> i64 {
    match (a, b) {
        (false, false) => 0,
        (true, false) => 1,
        (true, true) => 2,
        (false, true) => 3,
    }
}

/// `x` folded into (-e/2, e/2].
fn fold(x: i64, e: i64) -> i64 {
    let r = x.rem_euclid(e);
    if r > e / 2 {
        r - e
    } else {
        r
    }
}

#[test]
fn quadrature_counter_follows_the_parallel_position_through_zero_and_a_reversal() {
    let l = config("");
    let d = &l.derived;
    let a = d.abz.expect("enabled");
    let e = a.edges() as i64;
    let f = d.fine_bits;
    // The decoder counts from the first sample's angle within its signal period, so its
    // position starts at 0.9 period = 3.6 quadrants. Backward at 3000 rpm (6.55 M edges/s
    // with 16 x 2048 lines, below the 12.1 M edges/s the default spacing allows) it passes
    // position 0 after about 9 us, reverses between 60 and 160 us and passes 0 forward
    // again at about 215 us.
    let mut enc = EncoderModel::ideal(2048, 1.0, 0.0);
    enc.start_turns = 0.9 / 2048.0;
    enc.profile = Profile::Reversal {
        rpm: -3000.0,
        at: 60e-6,
        over: 100e-6,
    };
    let mut s = System::new(d, enc).expect("system");
    s.start().expect("settles");
    let n = (260e-6 * d.clock_hz) as usize;
    // Per clock: (par_valid, single-turn position, A, B, Z, warning).
    let mut rows = Vec::with_capacity(n);
    for _ in 0..n {
        s.run(1).expect("runs");
        let t = s.top();
        let p = (t.par_qc.val().to_u64() << f) | t.par_fine.val().to_u64();
        rows.push((
            t.par_valid.val(),
            p,
            t.abz_a.val(),
            t.abz_b.val(),
            t.abz_z.val(),
            t.par_warning.val(),
        ));
    }
    // A sample read after edge v enters the emulator at edge v + 1; its count is on A/B
    // from edge v + latency on (the emitter idle: one sample's counts take at most 5 edges
    // of 11 clocks, well within the sample period).
    let lat = a.latency() as usize;
    let samples: Vec<usize> = (0..n).filter(|&v| rows[v].0).collect();
    assert!(samples.len() > 300, "{} samples", samples.len());
    let k0 = samples[0] + lat;
    let t0 = exact_count(&a, rows[samples[0]].1);
    let (_, _, a0, b0, _, _) = rows[k0];
    assert_eq!(gray_index(a0, b0), t0.rem_euclid(4), "initial A/B state");
    let mut count = t0;
    let mut state = gray_index(a0, b0);
    let (mut ups, mut downs, mut zeros, mut checked) = (0, 0, 0, 0);
    let (mut z_runs, mut z_prev) = (0, false);
    let mut next = 1;
    for (k, &(_, _, ak, bk, zk, wk)) in rows.iter().enumerate().skip(k0) {
        let g = gray_index(ak, bk);
        match (g - state).rem_euclid(4) {
            0 => {}
            1 => {
                count += 1;
                ups += 1;
            }
            3 => {
                count -= 1;
                downs += 1;
            }
            _ => panic!("double transition at clock {k}"),
        }
        state = g;
        // Z exactly in the count-0 state of each turn.
        assert_eq!(
            zk,
            count.rem_euclid(e) == 0,
            "Z at clock {k}, count {count}"
        );
        zeros += zk as usize;
        z_runs += (zk && !z_prev) as usize;
        z_prev = zk;
        assert!(
            !wk,
            "warning at clock {k}: the emulator keeps up at 3000 rpm"
        );
        // Just before sample `next` can move the output, the count is sample next-1's.
        if next < samples.len() && k == samples[next] + lat - 1 {
            let want = exact_count(&a, rows[samples[next - 1]].1);
            assert_eq!(
                fold(count - want, e),
                0,
                "count at sample {next} (clock {k}): {count} vs {want}"
            );
            checked += 1;
            next += 1;
        }
    }
    assert!(checked > 300, "{checked} samples checked");
    // Both directions were seen, and Z in both zero crossings (separate runs of Z).
    assert!(ups > 100 && downs > 100, "{ups} up, {downs} down");
    assert!(z_runs >= 2, "Z came {z_runs} times ({zeros} clocks)");
}

#[test]
fn top_with_abz_replays_in_icarus_and_verilator() {
    use sinedec::blocks::top::hdl::TopRtl;
    use sinedec::cosim::CosimBlock;
    use sinedec::verify::{block_traces, Simulators};
    let l = config("lines = 1000");
    let d = &l.derived;
    // The decoder's position starts at half a signal period (2 quadrants) and runs backward
    // through 0 at about 1300 clocks, after the first sample (about 460 clocks).
    let mut enc = EncoderModel::ideal(2048, 1.0, -1500.0);
    enc.start_turns = 0.5 / 2048.0;
    let mut s = System::new(d, enc).expect("system");
    s.record_inputs();
    s.start().expect("settles");
    s.run(5000).expect("runs");
    let r = s.finish();
    let top = TopRtl::new(d).expect("top");
    let outs = top.output_ports();
    let col = |n: &str| outs.iter().position(|p| p.name == n).expect("output");
    let (ca, cz) = (col("abz_a"), col("abz_z"));
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("abz_top");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("dir");
    let t = block_traces(top, "sd_top_rtl", "clk", &r.inputs, Simulators::ALL, &dir)
        .expect("simulators ran");
    if let Some(m) = t.mismatch() {
        panic!("{m}");
    }
    // The emulator did something in the replayed window: A toggled and Z came.
    let a_edges = t
        .rust_hdl
        .windows(2)
        .filter(|w| w[0][ca] != w[1][ca])
        .count();
    assert!(a_edges > 2, "{a_edges} A edges");
    let pv = col("par_valid");
    let first = t.rust_hdl.iter().position(|row| row[pv] == 1);
    assert!(
        t.rust_hdl.iter().any(|row| row[cz] == 1),
        "no Z: {} rows, first sample at {first:?}, {a_edges} A edges",
        t.rust_hdl.len()
    );
}

#[test]
fn wrapper_and_ucf_have_the_abz_outputs_only_when_enabled() {
    let pins = "[board]\npreset = \"spartan3an-starter-kit\"\n[board.pins]\nqep_a = \"H1\"\nqep_b = \"H2\"\nqep_z = \"H3\"\nbiss_ma = \"H4\"\nbiss_slo = \"H5\"";
    let file = |g: &sinedec::emit::Generation, n: &str| {
        g.files
            .iter()
            .find(|f| f.name == n)
            .unwrap_or_else(|| panic!("{n} not generated"))
            .text
            .clone()
    };
    for enabled in [false, true] {
        let text = format!("{DEFAULT_CONFIG}\n[abz]\nenabled = {enabled}\n{pins}\n");
        let g = if enabled {
            // Enabled without pins for the outputs: named as missing.
            let m = match Loaded::parse(&text, "abz_wrapper.toml") {
                Err(e) => e.to_string(),
                Ok(l) => match sinedec::emit::generate(&l, "test") {
                    Err(e) => e.to_string(),
                    Ok(_) => panic!("abz enabled without pins generated"),
                },
            };
            assert!(m.contains("abz_a"), "{m}");
            let text = format!("{text}abz_a = \"J1\"\nabz_b = \"J2\"\nabz_z = \"J3\"\n");
            let l = Loaded::parse(&text, "abz_wrapper.toml").expect("pinned");
            sinedec::emit::generate(&l, "test").expect("generate")
        } else {
            let l = Loaded::parse(&text, "abz_wrapper.toml").expect("off");
            sinedec::emit::generate(&l, "test").expect("generate")
        };
        let top = file(&g, "sd_top.v");
        let ucf = file(&g, "sd_top.ucf");
        let wrapper = &top[..top.find("module sd_top_rtl").expect("rtl module")];
        for p in ["abz_a", "abz_b", "abz_z"] {
            let declared = wrapper
                .lines()
                .any(|l| l.trim_start().starts_with("output") && l.contains(&format!(" {p},")));
            assert_eq!(declared, enabled, "{enabled}: {p} in the wrapper");
            assert_eq!(
                ucf.contains(&format!("NET \"{p}\" LOC")),
                enabled,
                "{enabled}: {p} in the UCF"
            );
        }
    }
}
