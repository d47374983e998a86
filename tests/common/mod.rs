//! Helpers shared by the integration tests.
#![allow(dead_code)]
use sinedec::config::{Loaded, DEFAULT_CONFIG};

/// Runs `uut` on `rows`; asserts rust-hdl == `model` row by row and the Verilog simulators
/// (those `sims` selects) == rust-hdl; returns the rust-hdl trace.
pub fn check_against_model<B: sinedec::cosim::CosimBlock>(
    uut: B,
    tag: &str,
    rows: &[Vec<u64>],
    model: &[Vec<u64>],
    sims: sinedec::verify::Simulators,
) -> Vec<Vec<u64>> {
    let t = simulators_agree(uut, tag, tag, rows, sims);
    for (k, (r, m)) in t.iter().zip(model).enumerate() {
        assert_eq!(
            r, m,
            "{tag} row {k}: rust-hdl vs model (inputs {:?})",
            rows[k]
        );
    }
    assert_eq!(t.len(), model.len());
    t
}

/// Runs `uut` (top module `top`, work directory `tag`) on `rows` in rust-hdl and the
/// Verilog simulators `sims` selects; panics unless they agree on every output at every
/// clock; returns the rust-hdl trace.
pub fn simulators_agree<B: sinedec::cosim::CosimBlock>(
    uut: B,
    top: &str,
    tag: &str,
    rows: &[Vec<u64>],
    sims: sinedec::verify::Simulators,
) -> Vec<Vec<u64>> {
    let dir = workdir(tag);
    let t =
        sinedec::verify::block_traces(uut, top, "clk", rows, sims, &dir).expect("simulators ran");
    if let Some(m) = t.mismatch() {
        panic!("{tag}: {m}");
    }
    t.rust_hdl
}

/// Parses `text` as a config named `bad.toml` and asserts that it is rejected with an
/// error starting `bad.toml:line:col: ` at the unique `needle` and mentioning each of
/// `mentions`.
pub fn assert_config_error(text: &str, needle: &str, mentions: &[&str]) {
    let (line, col) = line_col(text, needle);
    let e = Loaded::parse(text, "bad.toml").unwrap_err().to_string();
    assert!(e.starts_with(&format!("bad.toml:{line}:{col}: ")), "{e}");
    for m in mentions {
        assert!(e.contains(m), "{e} should mention {m}");
    }
}

/// The default config with `[table]` and `body` appended.
pub fn with_section(table: &str, body: &str) -> String {
    format!("{DEFAULT_CONFIG}\n[{table}]\n{body}\n")
}

/// 1-based (line, column) of the unique `needle` in `text` (where a config error about it
/// must point).
pub fn line_col(text: &str, needle: &str) -> (usize, usize) {
    assert_eq!(text.matches(needle).count(), 1, "{needle:?} must be unique");
    let before = &text[..text.find(needle).unwrap()];
    (
        before.split('\n').count(),
        before.split('\n').next_back().unwrap().chars().count() + 1,
    )
}

/// The default config with the given core parameters (A != 14 switches to the generic ADC).
pub fn cfg(n: u32, f: u32, a: u32, ppr: u32, mt: u32) -> Loaded {
    cfg_named("sd", n, f, a, ppr, mt)
}

/// As [`cfg`] with a module-name prefix.
pub fn cfg_named(name: &str, n: u32, f: u32, a: u32, ppr: u32, mt: u32) -> Loaded {
    let mut text = DEFAULT_CONFIG
        .replace("name = \"sd\"", &format!("name = \"{name}\""))
        .replace("iterations = 14", &format!("iterations = {n}"))
        .replace("fine_bits = 14", &format!("fine_bits = {f}"))
        .replace("width = 14", &format!("width = {a}"))
        .replace("ppr = 2048", &format!("ppr = {ppr}"))
        .replace("multiturn_bits = 12", &format!("multiturn_bits = {mt}"));
    if a != 14 {
        text = text.replace(
            "preset = \"ltc1407a-1\"",
            "preset = \"generic\"\nmax_sample_rate_hz = 2e6",
        )
        .replace("[preamp]\n# LTC6912-1 gains (inverting): -1, -2, -5, -10, -20, -50 or -100. A feeds sin, B cos.\ngain_a = -1\ngain_b = -1\n", "");
    }
    Loaded::parse(&text, "test").expect("test config parses")
}

/// `text` with the commit sinedec was built from, which the header of every generated file
/// names, replaced by `-`: a verdict-cache key (`sinedec::cosim::passed_once`) of generated
/// files must not change with every commit when the design does not.
pub fn without_commit(text: &str) -> String {
    let built = format!("(commit {})", sinedec::emit::commit());
    text.replace(&built, "(commit -)")
}

/// The text of the repository's source files under `paths` (files, or directories walked
/// in name order), each preceded by its path: the part of a verdict-cache key
/// (`sinedec::cosim::passed_once`) that covers the models and tools a check depends on.
pub fn sources(paths: &[&str]) -> Vec<String> {
    fn walk(p: &std::path::Path, root: &std::path::Path, out: &mut Vec<String>) {
        if p.is_dir() {
            let mut entries: Vec<_> = std::fs::read_dir(p)
                .unwrap_or_else(|e| panic!("{}: {e}", p.display()))
                .filter_map(|e| e.ok().map(|e| e.path()))
                .collect();
            entries.sort();
            for e in entries {
                walk(&e, root, out);
            }
        } else {
            let text =
                std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            let rel = p.strip_prefix(root).unwrap_or(p);
            out.push(format!("{}\n{text}", rel.display()));
        }
    }
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut out = Vec::new();
    for p in paths {
        walk(&root.join(p), root, &mut out);
    }
    out
}

/// Compiles `files` in `dir` with Icarus (`iverilog -g2005`, top module `top`), runs the
/// result with `vvp` and returns what it prints; a compile error fails with its message.
pub fn icarus_output(dir: &std::path::Path, top: &str, files: &[&str]) -> String {
    let out = std::process::Command::new("iverilog")
        .args(["-g2005", "-o", "tb.vvp", "-s", top])
        .args(files)
        .current_dir(dir)
        .output()
        .expect("iverilog runs");
    assert!(
        out.status.success(),
        "iverilog: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let out = std::process::Command::new("vvp")
        .args(["-n", "tb.vvp"])
        .current_dir(dir)
        .output()
        .expect("vvp runs");
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// A fresh work directory for tool runs (kept under target/ for inspection).
pub fn workdir(tag: &str) -> std::path::PathBuf {
    let p = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(tag);
    let _ = std::fs::remove_dir_all(&p);
    std::fs::create_dir_all(&p).expect("create work dir");
    p
}

/// Replays the stimulus `rows` of a block's closed-loop test in rust-hdl, Icarus and
/// Verilator (top module and work directory named `top` and `tag`): the three traces must
/// agree, and the rust-hdl replay must equal `recorded`, the outputs the test's own loop saw.
pub fn replay_in_all_simulators<B: sinedec::cosim::CosimBlock>(
    uut: B,
    top: &str,
    rows: &[Vec<u64>],
    recorded: &[Vec<u64>],
    tag: &str,
) {
    let t = simulators_agree(uut, top, tag, rows, sinedec::verify::Simulators::ALL);
    assert!(
        t == recorded,
        "{tag}: the replay differs from the closed loop"
    );
}

/// The closed loop (encoder -> LTC1407A-1 model -> `<name>_top`) at a constant `rpm` for
/// `cycles` clocks, its recorded inputs replayed through the exported top in Icarus and
/// Verilator: panics unless all three give the same pin and position trace. Returns the
/// closed loop's result.
pub fn replay_top_in_simulators(
    l: &Loaded,
    rpm: f64,
    cycles: usize,
    tag: &str,
) -> sinedec::sim::system::SimResult {
    use sinedec::blocks::top::hdl::TopRtl;
    use sinedec::sim::encoder::EncoderModel;
    use sinedec::sim::system::System;
    use sinedec::verify::{block_traces, Simulators};
    let d = &l.derived;
    let enc = EncoderModel::ideal(2048, 1.0, rpm).with_seed(3);
    // The loop on the compiled engine; the replay below runs rust-hdl (and Icarus,
    // Verilator, the engine again) on its recorded inputs and must give its outputs.
    let mut s = System::on(d, enc, sinedec::sim::dut::EngineKind::Compiled).expect("system");
    s.record_inputs();
    s.start().expect("settles");
    let mut rust = vec![];
    for _ in 0..cycles {
        s.run(1).expect("runs");
        rust.push(s.sample());
    }
    let r = s.finish();
    assert!(r.records.len() > 50, "{} records", r.records.len());
    let dir = workdir(tag);
    let top = TopRtl::new(d).expect("top");
    let name = format!("{}_top_rtl", l.config.name);
    let t =
        block_traces(top, &name, "clk", &r.inputs, Simulators::ALL, &dir).expect("simulators ran");
    assert_eq!(
        t.rust_hdl, rust,
        "block_traces' own rust-hdl run equals the closed loop (compiled engine)"
    );
    if let Some(m) = t.mismatch() {
        panic!("{m}");
    }
    r
}

/// The capacitive config on Cyclone III with a `[board]`: balls of the EP3C40F324 package
/// (rows A..V, columns 1..18), the Quartus I/O standard names, and an ALTPLL when the
/// board's oscillator is not the system clock.
pub fn cap_board(osc: Option<&str>, first_ball: &str) -> String {
    let cfg = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/configs/cyclone3_capacitive.toml"
    ))
    .expect("capacitive config");
    let mut t = cfg + "\n[board]\niostandard = \"3.3-V LVTTL\"\n";
    if let Some(o) = osc {
        t.push_str(&format!("clock_hz = {o}\n"));
    }
    t.push_str("[board.pins]\n");
    let mut balls = (0..18 * 18).map(|i| {
        let rows = [
            "A", "B", "C", "D", "E", "F", "G", "H", "J", "K", "L", "M", "N", "P", "R", "T", "U",
            "V",
        ];
        format!("{}{}", rows[i / 18], i % 18 + 1)
    });
    balls.next();
    for (i, p) in sinedec::config::CAP_TOP_PINS.iter().enumerate() {
        let ball = if i == 0 {
            first_ball.to_string()
        } else {
            balls.next().expect("ball")
        };
        t.push_str(&format!("{p} = \"{ball}\"\n"));
    }
    for bus in sinedec::config::CAP_TOP_BUSES {
        let v: Vec<String> = (0..16)
            .map(|_| format!("\"{}\"", balls.next().expect("ball")))
            .collect();
        t.push_str(&format!("{bus} = [{}]\n", v.join(", ")));
    }
    t
}

/// The emitted `<name>_core` of `l` on the compiled engine (the library co-simulation
/// builds for the same Verilog, so it is built once), one input a cycle: the outputs and
/// in_ready after each edge, as `simulate_rtl_ready` gives them from rust-hdl (the
/// co-simulation checks prove rust-hdl, the engine and the Verilog simulators equal).
/// Counter loads are not ports of `<name>_core`: every input must have `load: None`.
pub fn core_on_engine(
    l: &Loaded,
    inputs: &[sinedec::blocks::core::model::CoreIn],
) -> Vec<(sinedec::blocks::core::model::CoreOut, bool)> {
    use sinedec::blocks::core::model::CoreOut;
    use sinedec::blocks::mask;
    use sinedec::engine::{Engine, Kind};
    let d = &l.derived;
    let v = sinedec::emit::core_verilog(l).expect("core Verilog");
    let mut e = Engine::new(&v, &sinedec::emit::core_name(l), "clk", Kind::Compiled)
        .expect("engine builds");
    let i = |n: &str| e.input_index(n).expect("core input");
    let ins = [i("rst"), i("in_valid"), i("in_sin"), i("in_cos")];
    let o = |n: &str| e.output_index(n).expect("core output");
    let outs = [
        o("out_valid"),
        o("out_position"),
        o("out_turns"),
        o("out_fine"),
        o("out_error"),
        o("out_warning"),
        o("in_ready"),
    ];
    let am = mask(d.adc_width);
    inputs
        .iter()
        .map(|x| {
            assert!(x.load.is_none(), "no load port on <name>_core");
            let row = [
                x.rst as u64,
                x.valid as u64,
                x.sin as u64 & am,
                x.cos as u64 & am,
            ];
            for (k, v) in ins.iter().zip(row) {
                e.set(*k, v);
            }
            e.tick();
            let g = |k: usize| e.get(outs[k]);
            let out = CoreOut {
                valid: g(0) != 0,
                position: g(1),
                turns: g(2),
                fine: g(3),
                error: g(4) != 0,
                warning: g(5) != 0,
            };
            (out, g(6) != 0)
        })
        .collect()
}

/// The executable `tool` of the Python tools' venv (scripts/test.sh installs it there):
/// in `$SINEDEC_YOWASP_BIN`, then `~/.cache/sinedec/venv/bin`, then PATH; fails with
/// `pip_spec`'s install line when none has it.
pub fn venv_tool(tool: &str, pip_spec: &str) -> std::path::PathBuf {
    use std::path::{Path, PathBuf};
    let mut dirs: Vec<PathBuf> = vec![];
    if let Ok(d) = std::env::var("SINEDEC_YOWASP_BIN") {
        dirs.push(d.into());
    }
    if let Ok(h) = std::env::var("HOME") {
        dirs.push(Path::new(&h).join(".cache/sinedec/venv/bin"));
    }
    if let Some(p) = dirs.iter().map(|d| d.join(tool)).find(|p| p.is_file()) {
        return p;
    }
    let on_path = std::process::Command::new(tool).arg("--version").output();
    assert!(
        on_path.is_ok_and(|o| o.status.success()),
        "{tool} not found; install it: python3 -m venv ~/.cache/sinedec/venv && ~/.cache/sinedec/venv/bin/pip install {pip_spec} (scripts/test.sh does this)"
    );
    PathBuf::from(tool)
}
