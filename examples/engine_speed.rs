//! Simulation speed of the compiled engine (src/engine) against its interpreter, rust-hdl
//! stepped by hand and Verilator -O3 driven by a plain C++ loop (no I/O in the timed loop),
//! on `sd_core` (random samples), the default `sd_top` rtl and the capacitive `cap_top` rtl
//! (inputs recorded from their closed loops, replayed round and round). Every simulator
//! applies a row, takes one rising edge and reads every output; the engine and Verilator
//! fold the outputs into a checksum, which must agree. Build times are printed apart.
//! Figures: docs/benchmarks.md.
//! `cargo run --release --example engine_speed [cycles]` (default 2,000,000; rust-hdl and
//! the interpreter run a tenth and a hundredth of that).
use anyhow::{ensure, Context, Result};
use sinedec::config::Loaded;
use sinedec::cosim::step::{prepare, tick};
use sinedec::cosim::{CosimBlock, Port};
use sinedec::engine::{Engine, Kind};
use std::fmt::Write as _;
use std::process::Command;
use std::time::Instant;

struct Case {
    name: String,
    verilog: String,
    inputs: Vec<Port>,
    outputs: Vec<Port>,
    rows: Vec<Vec<u64>>,
    rust_hdl: f64,
}

/// rust-hdl cycles/s of `uut` on `rows` (apply, tick, sample).
fn rust_hdl_speed<B: CosimBlock>(mut uut: B, rows: &[Vec<u64>]) -> Result<f64> {
    prepare(&mut uut).map_err(|e| anyhow::anyhow!("{e}"))?;
    let t0 = Instant::now();
    let mut acc = 0u64;
    for r in rows {
        uut.apply(r);
        tick(&mut uut).map_err(|e| anyhow::anyhow!("{e}"))?;
        acc = acc.wrapping_add(uut.sample().iter().sum::<u64>());
    }
    std::hint::black_box(acc);
    Ok(rows.len() as f64 / t0.elapsed().as_secs_f64())
}

fn top_case<B: CosimBlock>(
    mut uut: B,
    make: impl Fn() -> Result<B>,
    name: &str,
    rows: Vec<Vec<u64>>,
    n: usize,
) -> Result<Case> {
    uut.connect_all();
    let verilog = sinedec::emit::verilog::export(&uut, name, name)?;
    let short: Vec<Vec<u64>> = rows.iter().cycle().take(n).cloned().collect();
    let mut fresh = make()?;
    fresh.connect_all();
    Ok(Case {
        name: name.to_string(),
        verilog,
        inputs: uut.input_ports(),
        outputs: uut.output_ports(),
        rust_hdl: rust_hdl_speed(fresh, &short)?,
        rows,
    })
}

/// Cycles/s and checksum of the engine driven port by port (set, tick, get).
fn engine_speed(e: &mut Engine, c: &Case, cycles: usize) -> (f64, u64) {
    let ni: Vec<usize> = c
        .inputs
        .iter()
        .filter_map(|p| e.input_index(&p.name))
        .collect();
    let no: Vec<usize> = c
        .outputs
        .iter()
        .filter_map(|p| e.output_index(&p.name))
        .collect();
    let t0 = Instant::now();
    let mut acc = 0u64;
    for k in 0..cycles {
        let r = &c.rows[k % c.rows.len()];
        for (i, v) in ni.iter().zip(r) {
            e.set(*i, *v);
        }
        e.tick();
        for &o in &no {
            acc = acc.rotate_left(1) ^ e.get(o);
        }
    }
    (cycles as f64 / t0.elapsed().as_secs_f64(), acc)
}

/// Builds Verilator -O3 with a C++ loop like `engine_speed`'s; returns (build s, cycles/s,
/// checksum).
fn verilator_speed(c: &Case, cycles: usize) -> Result<(f64, f64, u64)> {
    let dir = std::env::temp_dir().join(format!("sinedec_engine_speed_{}", c.name));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir)?;
    std::fs::write(dir.join("design.v"), &c.verilog)?;
    let mut stim = String::new();
    for r in &c.rows {
        for v in r {
            let _ = write!(stim, "{v:x} ");
        }
        stim.push('\n');
    }
    std::fs::write(dir.join("stim.hex"), stim)?;
    let mut m = String::from(
        "#include \"Vbench.h\"\n#include \"verilated.h\"\n#include <chrono>\n#include <cstdio>\n\
         #include <cstdlib>\n#include <vector>\nint main(int argc, char** argv) {\n\
         VerilatedContext ctx; Vbench top{&ctx, \"TOP\"};\n\
         std::FILE* f = std::fopen(\"stim.hex\", \"r\"); if (!f) return 2;\n\
         std::vector<unsigned long long> rows; unsigned long long v;\n\
         while (std::fscanf(f, \"%llx\", &v) == 1) rows.push_back(v);\n",
    );
    let ni = c.inputs.len();
    let _ = writeln!(
        m,
        "const size_t NI = {ni}; const size_t n = rows.size() / NI;"
    );
    let _ = writeln!(
        m,
        "long long cycles = std::atoll(argv[1]); unsigned long long acc = 0;"
    );
    let _ = writeln!(
        m,
        "top.clk = 0; top.eval();\nauto t0 = std::chrono::steady_clock::now();"
    );
    let _ = writeln!(m, "for (long long k = 0; k < cycles; ++k) {{\n const unsigned long long* r = &rows[(k % n) * NI];");
    for (i, p) in c.inputs.iter().enumerate() {
        let _ = writeln!(m, " top.{} = r[{i}];", p.name);
    }
    let _ = writeln!(m, " top.clk = 1; top.eval();");
    for p in &c.outputs {
        let _ = writeln!(
            m,
            " acc = ((acc << 1) | (acc >> 63)) ^ (unsigned long long)top.{};",
            p.name
        );
    }
    let _ = writeln!(m, " top.clk = 0; top.eval();\n}}");
    let _ = writeln!(
        m,
        "double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();"
    );
    let _ = writeln!(m, "std::printf(\"%.6f %llu\\n\", s, acc); return 0;\n}}");
    std::fs::write(dir.join("main.cpp"), m)?;
    let t0 = Instant::now();
    let st = Command::new("verilator")
        .current_dir(&dir)
        .args([
            "--cc",
            "--exe",
            "--build",
            "-O3",
            "--no-timing",
            "--x-assign",
            "0",
            "--x-initial",
            "0",
        ])
        .args([
            "-Wno-fatal",
            "-Wno-WIDTH",
            "-Wno-UNOPTFLAT",
            "-Wno-CASEINCOMPLETE",
            "-Wno-UNUSED",
        ])
        .args(["--prefix", "Vbench", "-o", "bench", "--top-module", &c.name])
        .args([
            "-MAKEFLAGS",
            "OPT_FAST=-O3 OPT_SLOW=-O3 OPT_GLOBAL=-O3",
            "-j",
            "2",
        ])
        .args(["design.v", "main.cpp"])
        .output()
        .context("verilator (apt-get install -y verilator)")?;
    ensure!(
        st.status.success(),
        "verilator: {}",
        String::from_utf8_lossy(&st.stderr)
    );
    let build = t0.elapsed().as_secs_f64();
    let out = Command::new(dir.join("obj_dir").join("bench"))
        .current_dir(&dir)
        .arg(cycles.to_string())
        .output()?;
    let text = String::from_utf8_lossy(&out.stdout);
    let mut it = text.split_whitespace();
    let secs: f64 = it.next().context("verilator bench output")?.parse()?;
    let acc: u64 = it.next().context("verilator checksum")?.parse()?;
    Ok((build, cycles as f64 / secs, acc))
}

fn main() -> Result<()> {
    let cycles: usize = std::env::args()
        .nth(1)
        .map(|s| s.parse())
        .transpose()?
        .unwrap_or(2_000_000);
    let l = Loaded::default_config()?;
    let d = &l.derived;
    let mut cases = vec![];
    // sd_core: random samples.
    {
        use sinedec::blocks::core::hdl::simulate_rtl;
        use sinedec::cosim::stimulus;
        let s = stimulus::random(d.adc_width, 20_000, 0.25, 9);
        let t0 = Instant::now();
        let o = simulate_rtl(d, &s).map_err(|e| anyhow::anyhow!("{e}"))?;
        let rust_hdl = o.len() as f64 / t0.elapsed().as_secs_f64();
        cases.push(Case {
            name: sinedec::emit::core_name(&l),
            verilog: sinedec::emit::core_verilog(&l)?,
            inputs: sinedec::emit::core_input_ports(d),
            outputs: sinedec::emit::core_output_ports(d),
            rows: sinedec::verify::stimulus_rows(&l, &s),
            rust_hdl,
        });
    }
    let n_rh = (cycles / 100).max(2000);
    {
        use sinedec::blocks::top::hdl::TopRtl;
        use sinedec::sim::encoder::EncoderModel;
        use sinedec::sim::system::System;
        let mut s = System::new(d, EncoderModel::ideal(2048, 1.0, 3000.0).with_seed(5))?;
        s.record_inputs();
        s.start().map_err(|e| anyhow::anyhow!("{e}"))?;
        s.run(100_000).map_err(|e| anyhow::anyhow!("{e}"))?;
        let r = s.finish();
        let name = format!("{}_top_rtl", l.config.name);
        cases.push(top_case(
            TopRtl::new(d)?,
            || Ok(TopRtl::new(d)?),
            &name,
            r.inputs,
            n_rh,
        )?);
    }
    {
        use sinedec::blocks::captop::hdl::CapTopRtl;
        use sinedec::sim::cap_system::CapSystem;
        use sinedec::sim::capacitive::CapParams;
        let text = std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/configs/cyclone3_capacitive.toml"
        ))?;
        let lc = Loaded::parse(&text, "cyclone3_capacitive.toml")?;
        let dc = &lc.derived;
        let mut s = CapSystem::new(dc, CapParams::paper())?;
        s.record_inputs();
        s.start().map_err(|e| anyhow::anyhow!("{e}"))?;
        s.run(100_000).map_err(|e| anyhow::anyhow!("{e}"))?;
        let rows = s.inputs.take().context("recorded rows")?;
        let name = format!("{}_top_rtl", lc.config.name);
        cases.push(top_case(
            CapTopRtl::new(dc)?,
            || Ok(CapTopRtl::new(dc)?),
            &name,
            rows,
            n_rh,
        )?);
    }
    println!("| design | cells / regs | rust-hdl | interpreter | compiled (set/tick/get) | compiled (batch) | Verilator -O3 | compiled / Verilator | build: Yosys + rustc (compiled) | build: Verilator |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for c in &cases {
        // A fresh cache directory so that the build is timed.
        let cache = std::env::temp_dir().join("sinedec_engine_speed_cache");
        let _ = std::fs::remove_dir_all(&cache);
        std::env::set_var("SINEDEC_ENGINE_CACHE", &cache);
        let mut e = Engine::new(&c.verilog, &c.name, "clk", Kind::Compiled)?;
        let info = e.info().clone();
        let (comp, acc_e) = engine_speed(&mut e, c, cycles);
        let mut e2 = Engine::new(&c.verilog, &c.name, "clk", Kind::Compiled)?;
        ensure!(e2.info().cached, "second build came from the cache");
        let batch_rows: Vec<Vec<u64>> = c.rows.iter().cycle().take(cycles).cloned().collect();
        let t0 = Instant::now();
        let t = e2.trace(&c.inputs, &c.outputs, &batch_rows)?;
        let batch = cycles as f64 / t0.elapsed().as_secs_f64();
        std::hint::black_box(t);
        let mut ei = Engine::new(&c.verilog, &c.name, "clk", Kind::Interpreted)?;
        let (interp, _) = engine_speed(&mut ei, c, (cycles / 100).max(10_000));
        let (vbuild, ver, acc_v) = verilator_speed(c, cycles)?;
        ensure!(
            acc_e == acc_v,
            "{}: checksums differ: engine {acc_e:#x}, Verilator {acc_v:#x}",
            c.name
        );
        println!(
            "| {} | {} / {} | {:.0} k | {:.2} M | {:.2} M | {:.2} M | {:.2} M | {:.2} | {:.1} s + {:.1} s | {:.1} s |",
            c.name,
            info.cells,
            info.regs,
            c.rust_hdl / 1e3,
            interp / 1e6,
            comp / 1e6,
            batch / 1e6,
            ver / 1e6,
            comp / ver,
            info.yosys_s,
            info.rustc_s,
            vbuild
        );
    }
    Ok(())
}
