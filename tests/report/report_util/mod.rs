//! Helpers shared by `tests/report/report.rs` and `tests/report/report_blocks.rs` (moved out of `tests/report/report.rs` so that
//! no test file is longer than about 600 lines).
#![allow(dead_code)]
use crate::common;
use sinedec::blocks::cordic::model::{map, quadrant};
use sinedec::blocks::mask;
use sinedec::report::sweep::Kernel;
use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;

pub const BIN: &str = env!("CARGO_BIN_EXE_sinedec");

/// Every input pair of magnitude at least 1/8 of full scale, row by row.
pub fn pairs(a: u32) -> Vec<(i32, i32)> {
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
pub fn kernel_p(k: &Kernel, f: u32, s: i32, c: i32) -> (u64, bool) {
    let (mx, my) = map(s, c);
    let mut out = Vec::new();
    k.run(&[mx as i32], &[my as i32], &mut out);
    let (fine, ok) = out[0];
    (
        (fine as u64 + ((quadrant(s, c) as u64) << f)) & mask(f + 2),
        ok,
    )
}

/// The Markdown tables of `md`: (header cells, body rows), separator rows left out.
fn markdown_tables(md: &str) -> Vec<(Vec<String>, Vec<Vec<String>>)> {
    let mut out: Vec<(Vec<String>, Vec<Vec<String>>)> = Vec::new();
    let mut inside = false;
    for line in md.lines() {
        if !line.starts_with('|') {
            inside = false;
            continue;
        }
        let cells: Vec<String> = line
            .trim_matches('|')
            .split('|')
            .map(|c| c.trim().to_string())
            .collect();
        if !inside {
            out.push((cells, Vec::new()));
            inside = true;
        } else if !cells.iter().all(|c| c.chars().all(|ch| ch == '-')) {
            if let Some(t) = out.last_mut() {
                t.1.push(cells);
            }
        }
    }
    out
}

/// Cells of the Markdown tables whose first column is N: (title, N, cell).
pub fn markdown_cells(md: &str) -> Vec<(String, u32, String)> {
    let mut out = Vec::new();
    for (h, rows) in markdown_tables(md).into_iter().filter(|t| t.0[0] == "N") {
        for cells in rows {
            let n: u32 = cells[0].parse().expect("N column");
            for (t, c) in h.iter().zip(&cells) {
                out.push((t.clone(), n, c.clone()));
            }
        }
    }
    out
}

/// The report's files in `dir` (the manifest of what sinedec wrote, `.sinedec-manifest`,
/// left out).
pub fn read_dir(dir: &Path) -> BTreeMap<String, String> {
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
pub const OWN_N: u32 = 3;

/// The design of the report tests: the LTC1407A-1 preset (A = 14, so the board top and the
/// pre-amplifier exist), F = 10, 2048 PPR, no turn bits, N = 3.
pub fn small_config() -> sinedec::config::Loaded {
    common::cfg(OWN_N, 10, 14, 2048, 0)
}

/// Place-and-route results of this file's report, as `sinedec report` caches them (one JSON
/// per design, named by the SHA-256 of the Verilog, top, tool versions and flow;
/// `sinedec::report::nextpnr`), for the tool versions scripts/test.sh pins. Seeding the
/// report's cache with them keeps about 19 nextpnr runs out of every test run. They are the
/// tools' own results, not expected values: a design or tool change changes the hash, the
/// entry is not found and the tools run (then refresh the directory from
/// `target/tmp/report_cli_<pid>/cache`, the entries holding `fmax_mhz`).
pub const ECP5_SEED: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/ecp5-cache");

/// Copies the [`ECP5_SEED`] entries, and the Yosys entries of the directory
/// `SINEDEC_SYNTH_CACHE` names (`tests/data/yosys-cache` under scripts/test.sh; the report's
/// Yosys runs use the keys of `sinedec::synth::synthesize`), into the cache directory `cache`.
pub fn seed_report_cache(cache: &Path) {
    std::fs::create_dir_all(cache).unwrap();
    let mut seeds = vec![std::path::PathBuf::from(ECP5_SEED)];
    seeds.extend(synth_cache());
    for seed in seeds {
        let Ok(entries) = std::fs::read_dir(&seed) else {
            continue;
        };
        for e in entries {
            let p = e.unwrap().path();
            if p.extension().is_some_and(|x| x == "json") {
                std::fs::copy(&p, cache.join(p.file_name().unwrap())).unwrap();
            }
        }
    }
}

/// The directory `SINEDEC_SYNTH_CACHE` names, if any.
fn synth_cache() -> Option<std::path::PathBuf> {
    std::env::var_os(sinedec::synth::SYNTH_CACHE_ENV)
        .filter(|v| !v.is_empty())
        .map(std::path::PathBuf::from)
}

/// Adds the Yosys entries the report stored in `cache` (every entry without a place-and-route
/// `fmax_mhz`) to the directory `SINEDEC_SYNTH_CACHE` names, as `synthesize` itself does.
fn keep_yosys_entries(cache: &Path) {
    let Some(dir) = synth_cache() else {
        return;
    };
    for e in std::fs::read_dir(cache).expect("report cache") {
        let p = e.unwrap().path();
        let Some(name) = p.file_name() else { continue };
        if p.extension().is_none_or(|x| x != "json") || dir.join(name).exists() {
            continue;
        }
        let text = std::fs::read_to_string(&p).unwrap();
        if !text.contains("\"fmax_mhz\"") {
            std::fs::write(dir.join(name), text).unwrap();
        }
    }
}

/// Runs `sinedec report` on [`small_config`] for N = 2..=4 into `work/out` with the cache
/// `work/cache` (seeded by [`seed_report_cache`]).
pub fn run_report(work: &Path, out: &str) {
    seed_report_cache(&work.join("cache"));
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
    keep_yosys_entries(&work.join("cache"));
}

/// One report shared by the tests of this file (the Yosys runs of the whole top dominate):
/// (work directory, files of the first run).
pub fn shared_report() -> &'static (std::path::PathBuf, BTreeMap<String, String>) {
    static R: std::sync::OnceLock<(std::path::PathBuf, BTreeMap<String, String>)> =
        std::sync::OnceLock::new();
    R.get_or_init(|| {
        // One directory per process: the test runner may run this file's tests in
        // parallel processes, each with its own report.
        let work = common::workdir(&format!("report_cli_{}", std::process::id()));
        run_report(&work, "r");
        let files = read_dir(&work.join("r"));
        (work, files)
    })
}

/// Rows of the Markdown table whose first column title is `block`: (titles, cells).
pub fn markdown_block_rows(md: &str) -> Vec<(Vec<String>, Vec<String>)> {
    markdown_tables(md)
        .into_iter()
        .filter(|t| t.0[0] == "block")
        .flat_map(|(h, rows)| rows.into_iter().map(move |r| (h.clone(), r)))
        .collect()
}

/// JSON value equals a table cell: null for an empty cell ("-" in Markdown), the number
/// for a numeric cell, the text otherwise.
pub fn same_value(key: &str, cell: &str, j: &serde_json::Value) -> bool {
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
