//! Exhaustive sweep of the emitted `<name>_core` RTL (issue 17 item 5): every 14-bit input
//! pair (sin, cos) whose magnitude is at least 1/8 of full scale (|v| >= 2^13 / 8 = 1024 LSB:
//! about 265 M of the 268 M pairs) goes through the Verilog that `generate` writes, simulated
//! by the compiled engine (src/engine, proven equal to rust-hdl, Icarus and Verilator by
//! tests/system/engine.rs), one sample per clock, and every output of every clock must equal the
//! bit-accurate model (`CoreModel`). Rows of constant sin sweep cos upward, so the angle
//! moves smoothly within a row and jumps between rows: the counter, its warning and its
//! unwrap see both. The rows are split into chunks run in parallel, each from a reset.
use rayon::prelude::*;
use sinedec::blocks::core::model::{CoreIn, CoreModel};
use sinedec::config::Loaded;
use sinedec::emit::{core_input_ports, core_name, core_output_ports, core_verilog};
use sinedec::engine::{Engine, Kind};

/// Runs sin rows `rows` (values) through a fresh engine and model; returns the number of
/// samples compared, or the first mismatch.
fn chunk(l: &Loaded, verilog: &str, rows: std::ops::Range<i32>) -> Result<u64, String> {
    let d = &l.derived;
    let a = d.adc_width;
    let half = 1i32 << (a - 1);
    let min2 = ((half / 8) as i64).pow(2);
    let am = (1u64 << a) - 1;
    let mut e = Engine::new(verilog, &core_name(l), "clk", Kind::Compiled)
        .map_err(|err| format!("engine: {err}"))?;
    let idx = |n: &str| e.input_index(n).ok_or(format!("no input {n}"));
    let (ir, iv, is, ic) = (
        idx("rst")?,
        idx("in_valid")?,
        idx("in_sin")?,
        idx("in_cos")?,
    );
    let outs: Vec<usize> = core_output_ports(d)
        .iter()
        .map(|p| {
            e.output_index(&p.name)
                .ok_or(format!("no output {}", p.name))
        })
        .collect::<Result<_, _>>()?;
    let mut m = CoreModel::new(d);
    let mut step = |e: &mut Engine, i: CoreIn| -> Result<(), String> {
        e.set(ir, i.rst as u64);
        e.set(iv, i.valid as u64);
        e.set(is, i.sin as u64 & am);
        e.set(ic, i.cos as u64 & am);
        e.tick();
        let want = m.step(i).row();
        for (k, &o) in outs.iter().enumerate() {
            if e.get(o) != want[k] {
                let got: Vec<u64> = outs.iter().map(|&o| e.get(o)).collect();
                return Err(format!(
                    "sin {} cos {}: engine {got:?}, model {want:?} ({:?})",
                    i.sin,
                    i.cos,
                    core_output_ports(d)
                        .iter()
                        .map(|p| p.name.clone())
                        .collect::<Vec<_>>()
                ));
            }
        }
        Ok(())
    };
    let idle = |rst: bool| CoreIn {
        rst,
        valid: false,
        sin: 0,
        cos: 0,
        load: None,
    };
    step(&mut e, idle(true))?;
    step(&mut e, idle(true))?;
    let mut n = 0;
    for s in rows {
        for c in -half..half {
            if (s as i64).pow(2) + (c as i64).pow(2) < min2 {
                continue;
            }
            step(
                &mut e,
                CoreIn {
                    rst: false,
                    valid: true,
                    sin: s,
                    cos: c,
                    load: None,
                },
            )?;
            n += 1;
        }
    }
    // Drain the pipeline: the last samples' outputs are compared too.
    for _ in 0..d.latency_cycles + 4 {
        step(&mut e, idle(false))?;
    }
    Ok(n)
}

#[test]
fn every_input_pair_above_an_eighth_of_full_scale_equals_the_model() {
    let l = Loaded::default_config().expect("default config");
    let d = &l.derived;
    assert_eq!(d.adc_width, 14, "the sweep is of the 14-bit default");
    assert_eq!(core_input_ports(d).len(), 4);
    let verilog = core_verilog(&l).expect("export");
    // The sweep's verdict is cached (src/cosim/cache.rs, `passed_once`) by everything it
    // depends on: the Verilog, the parameters, this file, the model's sources (core,
    // CORDIC, counter and their shared helpers) and the engine's sources, with the versions
    // of Yosys (the engine's front end) and rustc (its compiler). Any change runs it.
    let params = format!("{d:?}");
    let srcs = crate::common::sources(&[
        "src/blocks/core/model.rs",
        "src/blocks/cordic/model.rs",
        "src/blocks/counter/model.rs",
        "src/blocks/mod.rs",
        "src/blocks/params.rs",
        "src/engine",
    ]);
    let mut parts = vec![include_str!("core_sweep.rs"), verilog.as_str(), &params];
    parts.extend(srcs.iter().map(String::as_str));
    sinedec::cosim::passed_once("core sweep", &["yosys", "rustc"], &parts, || {
        sweep(&l, &verilog)
    })
    .expect("yosys and rustc installed");
}

/// The sweep itself: 16 chunks of 1024 sin rows, in parallel.
fn sweep(l: &Loaded, verilog: &str) {
    let half = 1i32 << 13;
    let chunks: Vec<std::ops::Range<i32>> = (0..16)
        .map(|k| (-half + k * 1024)..(-half + (k + 1) * 1024))
        .collect();
    let t0 = std::time::Instant::now();
    let counts: Vec<Result<u64, String>> = chunks
        .into_par_iter()
        .map(|r| chunk(l, verilog, r))
        .collect();
    let mut total = 0;
    for c in counts {
        match c {
            Ok(n) => total += n,
            Err(m) => panic!("{m}"),
        }
    }
    // Pairs of magnitude >= 1024 among the 2^28, counted independently.
    let mut want = 0u64;
    for s in -half as i64..half as i64 {
        for c in -half as i64..half as i64 {
            want += (s * s + c * c >= 1024 * 1024) as u64;
        }
    }
    assert_eq!(total, want, "samples compared");
    assert!(total > 260_000_000, "{total}");
    eprintln!(
        "core sweep: {total} input pairs compared in {:.1} s",
        t0.elapsed().as_secs_f64()
    );
}
