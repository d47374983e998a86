//! `sinedec report`: the sweep's kernel against the model, the model's accuracy figures
//! against the RTL (on the compiled engine), deterministic and consistent Markdown/CSV/JSON output,
//! and a clear error (with nothing written) without Yosys.
//!
//! (More tests in `tests/report/report_blocks.rs`; the helpers are in `tests/report/report_util/`.)
use crate::common;
use crate::report_util;
use report_util::*;
use sinedec::blocks::cordic::model::{map, quadrant};
use sinedec::blocks::core::model::{sample, CoreIn};
use sinedec::blocks::mask;
use sinedec::report::sweep::{self, ErrAcc, Kernel, SweepPlan};

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
fn model_accuracy_equals_rtl_simulation() {
    // A = 10, N = 6, F = 10: every input pair of at least 1/8 full scale through the RTL
    // of the core (the emitted `<name>_core` on the compiled engine, which the co-simulation
    // tests prove equal to rust-hdl); the error figures from its outputs must be identical
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
    let out = common::core_on_engine(&l, &stim);
    let outs: Vec<_> = out.iter().map(|o| &o.0).filter(|o| o.valid).collect();
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
    assert!(md.contains("proven by tests/blocks/iterative.rs"));
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
    assert_eq!(jblocks.len(), 23);
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
