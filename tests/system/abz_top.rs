//! ABZ emulation in `<name>_top` (`[abz] enabled`). The emulator is a block of the rust-hdl
//! top, on its parallel bus: the closed loop (the top rtl's Verilog on the compiled engine,
//! with the encoder and ADC models) records its pins, and the emitted `<name>_top_rtl`
//! replays them in Icarus, Verilator and the engine. All agree with the loop, and an
//! independent quadrature counter on `abz_a`/`abz_b` follows the position through 0 both
//! ways and a reversal, with Z in each zero crossing. The wrapper and the UCF get the three
//! outputs only when enabled.
use sinedec::blocks::abz::AbzParams;
use sinedec::blocks::top::hdl::TopRtl;
use sinedec::config::{Loaded, DEFAULT_CONFIG};
use sinedec::cosim::{
    cosim_engine_kind, first_mismatch, run_engine, run_icarus_expecting, run_verilator_expecting,
    CosimBlock, CosimSpec, Port,
};
use sinedec::emit::{top_name, top_verilog};
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

/// An ideal 2048-line encoder starting `periods` signal periods into the turn.
fn encoder(periods: f64, profile: Profile) -> EncoderModel {
    let mut enc = EncoderModel::ideal(2048, 1.0, 0.0);
    enc.start_turns = periods / 2048.0;
    enc.profile = profile;
    enc
}

/// One row of the replay: (par_valid, single-turn position, A, B, Z, warning).
type Row = (bool, u64, bool, bool, bool, bool);

/// Runs the closed loop for `seconds` (the top rtl's Verilog on the compiled engine: the
/// ABZ output is under test, not rust-hdl; tests/system/engine_loop.rs proves the loop equal to
/// rust-hdl's), then the emitted `<name>_top` on its recorded inputs in Icarus, Verilator and
/// the engine; checks the simulators against each other and the wrapper's parallel bus
/// against the loop's top, and returns the rows.
fn replay(l: &Loaded, enc: EncoderModel, seconds: f64, tag: &str) -> Vec<Row> {
    let d = &l.derived;
    let mut s = System::on(d, enc, sinedec::sim::dut::EngineKind::Compiled).expect("system");
    s.record_inputs();
    s.start().expect("settles");
    s.run((seconds * d.clock_hz) as u64).expect("runs");
    let r = s.finish();
    let rtl = TopRtl::new(d).expect("top");
    let rtl_in = rtl.input_ports();
    let rtl_out = rtl.output_ports();
    let verilog = top_verilog(l).expect("export").expect("a sinewave top");
    let top = top_name(l);
    // Every input of the rtl but the clock (the harness's), as the loop recorded them.
    let cols: Vec<usize> = (0..rtl_in.len())
        .filter(|&i| rtl_in[i].name != "clk")
        .collect();
    let ins: Vec<Port> = cols.iter().map(|&i| rtl_in[i].clone()).collect();
    let rows: Vec<Vec<u64>> = r
        .inputs
        .iter()
        .map(|row| cols.iter().map(|&i| row[i]).collect())
        .collect();
    let f = d.fine_bits;
    let names = [
        "par_valid",
        "par_qc",
        "par_fine",
        "abz_a_0",
        "abz_b_0",
        "abz_z_0",
        "par_warning",
    ];
    let outs: Vec<Port> = names
        .iter()
        .map(|n| {
            rtl_out
                .iter()
                .find(|p| p.name == *n)
                .unwrap_or_else(|| panic!("the rtl has no output {n}"))
                .clone()
        })
        .collect();
    let rtl_name = format!("{top}_rtl");
    let spec = CosimSpec {
        verilog: &verilog,
        top: &rtl_name,
        clock: "clk",
        inputs: &ins,
        outputs: &outs,
    };
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("abz_top_{tag}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("dir");
    let kind = cosim_engine_kind().expect("engine choice");
    let engine = run_engine(&spec, &rows, kind).expect("engine ran");
    // The simulators' verdicts are cached against the engine's trace (src/cosim/cache.rs):
    // a hit means each printed exactly it; a miss runs the tool and compares below.
    let icarus = run_icarus_expecting(&spec, &rows, &dir, &engine).expect("icarus ran");
    let verilator = run_verilator_expecting(&spec, &rows, &dir, &engine).expect("verilator ran");
    for (name, t) in [("verilator", &verilator), ("engine", &engine)] {
        if let Some(m) = first_mismatch("icarus", &icarus, name, t, &outs) {
            panic!("{m}");
        }
    }
    // The simulators' outputs are the loop's (rust-hdl's netlist on the compiled engine).
    let col = |n: &str| rtl_out.iter().position(|p| p.name == n).expect("output");
    let loop_cols: Vec<usize> = names.iter().map(|n| col(n)).collect();
    assert_eq!(icarus.len(), r.outputs.len(), "rows");
    for (k, (v, o)) in icarus.iter().zip(&r.outputs).enumerate() {
        let want: Vec<u64> = loop_cols.iter().map(|&c| o[c]).collect();
        assert_eq!(v, &want, "{names:?} at clock {k}");
    }
    let qmask = (1u64 << (d.position_width - f)) - 1;
    icarus
        .iter()
        .map(|v| {
            let p = ((v[1] & qmask) << f) | (v[2] & ((1 << f) - 1));
            (v[0] == 1, p, v[3] == 1, v[4] == 1, v[5] == 1, v[6] == 1)
        })
        .collect()
}

#[test]
fn quadrature_counter_follows_the_parallel_position_through_zero_and_a_reversal() {
    let l = config("");
    let d = &l.derived;
    let a = d.abz.expect("enabled");
    let e = a.edges() as i64;
    // The decoder counts from the first sample's angle within its signal period, so its
    // position starts at 0.9 period = 3.6 quadrants. Backward at 3000 rpm (6.55 M edges/s
    // with 16 x 2048 lines, below the 12.1 M edges/s the default spacing allows) it passes
    // position 0 after about 9 us, reverses between 60 and 160 us and passes 0 forward
    // again at about 215 us.
    let profile = Profile::Reversal {
        rpm: -3000.0,
        at: 60e-6,
        over: 100e-6,
    };
    let rows = replay(&l, encoder(0.9, profile), 260e-6, "reversal");
    let n = rows.len();
    // A sample on the bus at clock v enters the emulator at edge v + 1; its count is on A/B
    // from clock v + latency on (the emitter idle: one sample's counts take at most 5 edges
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
fn catching_up_raises_the_warning_and_loses_no_count() {
    // 1000 lines (4000 edges per turn) at most 100 k edges/s (S = 1334 clocks). The encoder
    // brakes from -6000 rpm (400 k edges/s) to rest in 100 us: 20 counts, twice what the
    // emitter may give in that time. It falls behind and raises the warning, catches up
    // after the encoder stopped, and then shows exactly the counts of the final position.
    let l = config("lines = 1000\nmax_edge_hz = 100000.0");
    let d = &l.derived;
    let a = d.abz.expect("enabled");
    let e = a.edges() as i64;
    let profile = Profile::Ramp {
        from: -6000.0,
        to: 0.0,
        over: 100e-6,
    };
    let rows = replay(&l, encoder(0.5, profile), 300e-6, "catch_up");
    let samples: Vec<usize> = (0..rows.len()).filter(|&v| rows[v].0).collect();
    assert!(samples.len() > 100, "{} samples", samples.len());
    let k0 = samples[0] + a.latency() as usize;
    let mut count = exact_count(&a, rows[samples[0]].1);
    let mut state = gray_index(rows[k0].2, rows[k0].3);
    let mut warned = 0;
    for (k, r) in rows.iter().enumerate().skip(k0) {
        let g = gray_index(r.2, r.3);
        match (g - state).rem_euclid(4) {
            0 => {}
            1 => count += 1,
            3 => count -= 1,
            _ => panic!("double transition at clock {k}"),
        }
        state = g;
        warned += r.5 as usize;
    }
    assert!(warned > 0, "no warning while the position ran ahead");
    let last = exact_count(&a, rows[*samples.last().expect("samples")].1);
    assert_eq!(fold(count - last, e), 0, "final count {count} vs {last}");
    assert!(
        !rows.last().expect("rows").5,
        "the warning falls once caught up"
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
