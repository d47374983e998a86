//! `[harmonics]` in the config: bad values name the key, its line and column and what is
//! allowed; `check` prints the table's lines and the core's latency with its five clocks;
//! off (the default) nothing changes.
use crate::common;
use sinedec::blocks::harmonics::block::HELD_CASE;
use sinedec::blocks::harmonics::HarmonicParams;
use sinedec::config::{Loaded, DEFAULT_CONFIG};

fn with(body: &str) -> String {
    common::with_section("harmonics", body)
}

/// A table of `n` entries, each `v`, as TOML.
fn table(n: usize, v: f64) -> String {
    let e: Vec<String> = (0..n).map(|_| format!("{v:.1}")).collect();
    format!("table = [{}]", e.join(", "))
}

#[test]
fn bad_values_name_the_key_the_position_and_what_is_allowed() {
    let long = table(32, 0.0);
    let big = table(16, 1100.0);
    let cases: Vec<(String, &str, Vec<&str>)> = vec![
        (
            "enabled = true\npoints = 48".into(),
            "points = 48",
            vec!["`harmonics.points`", "48", "power of two from 16 to 256"],
        ),
        (
            "enabled = true\npoints = 512".into(),
            "points = 512",
            vec!["`harmonics.points`", "power of two"],
        ),
        (
            "enabled = true\nmode = \"static\" # the table".into(),
            "mode = \"static\" # the table",
            vec!["`harmonics.mode`", "needs `table`", "\"learn\""],
        ),
        (
            "enabled = true\npoints = 16\ntable = [0.0]".into(),
            "table = [0.0]",
            vec![
                "`harmonics.table`",
                "starts from zeros",
                "mode = \"static\"",
            ],
        ),
        (
            "enabled = true\npoints = 256".into(),
            "points = 256",
            vec![
                "`harmonics.points`",
                "at most 128 points",
                "mode = \"static\"",
            ],
        ),
        (
            "enabled = true\nwindow = 1000".into(),
            "window = 1000",
            vec![
                "`harmonics.window`",
                "1000",
                "power of two from 256 to 65536",
            ],
        ),
        (
            "enabled = true\nwindow = 128".into(),
            "window = 128",
            vec!["`harmonics.window`", "power of two from 256"],
        ),
        (
            "enabled = true\nstep = 0".into(),
            "step = 0",
            vec!["`harmonics.step`", "allowed 1 to 2^(F-4) = 1024 LSB"],
        ),
        (
            "enabled = true\nstep = 1025".into(),
            "step = 1025",
            vec!["`harmonics.step`", "1025 LSB"],
        ),
        (
            format!("enabled = true\nmode = \"static\"\npoints = 16\n{long}"),
            "table = [",
            vec!["`harmonics.table`", "32 entries", "exactly `points` = 16"],
        ),
        (
            format!("enabled = true\nmode = \"static\"\npoints = 16\n{big}"),
            "table = [",
            vec!["`harmonics.table`", "entry 0", "-1024..=1024 LSB"],
        ),
    ];
    for (body, needle, mentions) in &cases {
        common::assert_config_error(&with(body), needle, mentions);
    }
    // The iterative CORDIC has no table.
    let text = with(&format!(
        "enabled = true # it\nmode = \"static\"\npoints = 16\n{}",
        table(16, 0.0)
    ))
    .replace(
        "architecture = \"unrolled\"",
        "architecture = \"iterative\"",
    );
    common::assert_config_error(
        &text,
        "enabled = true # it",
        &["`harmonics.enabled`", "unrolled"],
    );
    // An unknown key is refused by the schema.
    let e = Loaded::parse(&with("point = 64"), "bad.toml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("point"), "{e}");
    let e = Loaded::parse(&with("enabled = true\nmode = \"learned\""), "bad.toml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("learned") && e.contains("static"), "{e}");
}

#[test]
fn check_prints_the_table_and_the_latency() {
    let on = Loaded::parse(&format!("{DEFAULT_CONFIG}\n{HELD_CASE}"), "h.toml").expect("on");
    let off = Loaded::default_config().expect("off");
    let (d, d0) = (&on.derived, &off.derived);
    // The one derivation: the core's latency grows by the block's, and CONV -> position
    // with it.
    assert_eq!(
        d.latency_cycles,
        d0.latency_cycles + HarmonicParams::LATENCY
    );
    assert_eq!(
        sinedec::blocks::top::hdl::conv_to_position_cycles(d),
        sinedec::blocks::top::hdl::conv_to_position_cycles(d0) + HarmonicParams::LATENCY
    );
    let s = d.describe();
    let line = |k: &str| {
        s.lines()
            .find(|l| l.starts_with(k))
            .unwrap_or_else(|| panic!("no {k:?} in\n{s}"))
            .to_string()
    };
    assert!(line("harmonic correction ").contains("64 points"), "{s}");
    assert!(
        line("harmonic correction latency").contains("5 clocks"),
        "{s}"
    );
    assert!(
        line("core latency in -> out").contains(&format!("{} cycles", d0.latency_cycles + 5)),
        "{s}"
    );
    // The held table's largest entry, 208.6 LSB, in 2^-6 LSB units.
    assert!(
        line("harmonic correction ").contains("largest 208.59 LSB"),
        "{s}"
    );
    assert!(!d0.describe().contains("harmonic"));
    // Off, the section's keys are not checked beyond their types (docs/cli.md) and the
    // design has no table.
    let quiet = Loaded::parse(&with("enabled = false\npoints = 100"), "q.toml").expect("off");
    assert!(quiet.derived.harmonics.is_none());
}

/// The default config at `hz` (TOML) with `body` in `[harmonics]`.
fn at_clock(hz: &str, body: &str) -> String {
    let text = sinedec::blocks::harmonics::block::with_clock(&with(body), hz);
    assert_eq!(text.matches(&format!("frequency_hz = {hz}")).count(), 1);
    text
}

/// A learned table: the core's latency grows by the RAM lookup's clocks, and `check` gives
/// the clock up to which a learned table is built (the highest at which the learned tops'
/// figures meet the timing rule) and those figures at 133.33 MHz, where each misses it (or
/// the line would be wrong); a static table gets no such line.
#[test]
fn check_says_up_to_which_clock_a_learned_table_meets_the_timing_rule() {
    use sinedec::blocks::harmonics::block::{
        learned_median_mhz, LEARNED_CLOCK_TOML, LEARNED_TOPS, LEARNED_TOPS_CLOCK_MHZ as CLK,
    };
    use sinedec::report::nextpnr::check_rule;
    let learn = Loaded::parse(
        &at_clock(LEARNED_CLOCK_TOML, "enabled = true\npoints = 128"),
        "l.toml",
    )
    .expect("learn");
    let off =
        Loaded::parse(&at_clock(LEARNED_CLOCK_TOML, "enabled = false"), "o.toml").expect("off");
    let on = Loaded::parse(&format!("{DEFAULT_CONFIG}\n{HELD_CASE}"), "h.toml").expect("on");
    let (d, d0) = (&learn.derived, &off.derived);
    assert_eq!(
        d.latency_cycles,
        d0.latency_cycles + HarmonicParams::LATENCY_RAM
    );
    let s = d.describe();
    let line = s
        .lines()
        .find(|l| l.starts_with("harmonic correction timing"))
        .unwrap_or_else(|| panic!("no timing line in\n{s}"));
    // The learning line gives a window's time and the solve's clocks (the model's count,
    // harmonics_learn::the_solve_takes_the_documented_clocks) at the design's rates.
    let lp = d.harmonics.as_ref().and_then(|h| h.learn).expect("learned");
    let learning = s
        .lines()
        .find(|l| l.starts_with("harmonic correction  "))
        .unwrap_or_else(|| panic!("no harmonic correction line in\n{s}"));
    let window = format!(
        "windows of 4096 samples = {:.2} ms, each followed by a solve of {} clocks = {:.1} us",
        4096.0 / d.sample_rate_hz * 1e3,
        lp.solve_clocks(),
        f64::from(lp.solve_clocks()) / d.clock_hz * 1e6
    );
    assert!(learning.contains(&window), "{learning}");
    for t in LEARNED_TOPS {
        let median = learned_median_mhz(t.seeds_mhz);
        assert!(
            check_rule(&t.seeds_mhz.map(Some), CLK).is_err(),
            "the figures meet the rule: {line}"
        );
        let [a, b, c] = t.seeds_mhz;
        let figures = format!(
            "{}: {a:.2} / {b:.2} / {c:.2} MHz (median {median:.2} MHz, {:.3} x)",
            t.design,
            median / CLK
        );
        assert!(line.contains(&figures), "{line}");
    }
    // The clock it gives meets the rule on every top's figures (`check_rule`, the rule
    // `tests/timing.rs` holds the designs to), and a megahertz more fails it on one.
    let most: f64 = line
        .split("built up to ")
        .nth(1)
        .and_then(|t| t.split(" MHz").next())
        .and_then(|t| t.parse().ok())
        .unwrap_or_else(|| panic!("no clock in {line}"));
    let meets = |f: f64| {
        LEARNED_TOPS
            .iter()
            .all(|t| check_rule(&t.seeds_mhz.map(Some), f).is_ok())
    };
    assert!(meets(most), "{line}");
    assert!(!meets(most + 1.0), "{line}");
    assert!(!on.derived.describe().contains("harmonic correction timing"));
}

/// Every emitted design meets its configured clock: a learned table above the clock its
/// tops meet the timing rule at (119 MHz) is refused, naming `[harmonics] enabled`, the
/// clock and what is allowed; at that clock it is built, and a static table at any.
#[test]
fn a_learned_table_above_the_rules_clock_is_refused() {
    use sinedec::blocks::harmonics::block::learned_clock_mhz;
    let most = learned_clock_mhz();
    assert_eq!(
        most, 119.0,
        "the measured tops moved: update docs/timing.md"
    );
    common::assert_config_error(
        &with("enabled = true # learn"),
        "enabled = true # learn",
        &[
            "`harmonics.enabled`",
            "up to 119 MHz",
            "clock.frequency_hz is 133.33 MHz",
            "mode = \"static\"",
        ],
    );
    common::assert_config_error(
        &at_clock("119_500_000.0", "enabled = true # learn"),
        "enabled = true # learn",
        &["`harmonics.enabled`", "clock.frequency_hz is 119.50 MHz"],
    );
    Loaded::parse(&at_clock("119_000_000.0", "enabled = true"), "ok.toml")
        .expect("a learned table at 119 MHz");
    Loaded::parse(&format!("{DEFAULT_CONFIG}\n{HELD_CASE}"), "static.toml")
        .expect("a static table at 133.33 MHz");
}
