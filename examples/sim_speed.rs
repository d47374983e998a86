//! Simulation speed of the whole `<name>_top` (default config) in rust-hdl, Icarus and
//! Verilator on one recorded closed-loop stimulus (figures in docs/benchmarks.md). Each
//! simulator runs N and 2N cycles; the speed is N / (t(2N) - t(N)), which cancels
//! compilation and start-up.
//! `cargo run --release --example sim_speed [N]` (default N = 40,000).
use sinedec::blocks::top::hdl::TopRtl;
use sinedec::config::Loaded;
use sinedec::simulate::{run, SimOptions};
use sinedec::verify::{block_traces, Simulators};
use std::time::Instant;

fn main() -> anyhow::Result<()> {
    let n: usize = std::env::args()
        .nth(1)
        .map(|s| s.parse())
        .transpose()?
        .unwrap_or(40_000);
    let l = Loaded::default_config()?;
    let d = &l.derived;
    let o = SimOptions {
        duration_s: (2 * n) as f64 / d.clock_hz,
        record: true,
        ..Default::default()
    };
    let r = run(&l, &o, |_, _| {})?;
    let rows = r.result.inputs;
    anyhow::ensure!(rows.len() >= 2 * n, "recorded {} rows", rows.len());
    let dir = std::env::temp_dir().join("sinedec_sim_speed");
    let time = |sims: Simulators, len: usize, tag: &str| -> anyhow::Result<f64> {
        let w = dir.join(format!("{tag}_{len}"));
        let _ = std::fs::remove_dir_all(&w);
        std::fs::create_dir_all(&w)?;
        let t0 = Instant::now();
        block_traces(
            TopRtl::new(d).map_err(anyhow::Error::msg)?,
            "sd_top_rtl",
            "clk",
            &rows[..len],
            sims,
            &w,
        )?;
        Ok(t0.elapsed().as_secs_f64())
    };
    let none = Simulators {
        icarus: false,
        verilator: false,
    };
    let ic = Simulators {
        icarus: true,
        verilator: false,
    };
    let ve = Simulators {
        icarus: false,
        verilator: true,
    };
    let rh = (time(none, n, "rh")?, time(none, 2 * n, "rh")?);
    let speed = |a: (f64, f64), base: (f64, f64)| n as f64 / ((a.1 - base.1) - (a.0 - base.0));
    let ic_t = (time(ic, n, "ic")?, time(ic, 2 * n, "ic")?);
    let ve_t = (time(ve, n, "ve")?, time(ve, 2 * n, "ve")?);
    println!("| simulator | cycles/s (whole sd_top, closed-loop stimulus, N = {n}) |");
    println!("|---|---|");
    println!(
        "| rust-hdl (stepped by hand) | {:.0} |",
        n as f64 / (rh.1 - rh.0)
    );
    println!("| Icarus Verilog | {:.0} |", speed(ic_t, rh));
    println!("| Verilator | {:.0} |", speed(ve_t, rh));
    Ok(())
}
