//! Bad configurations: the library reports `ConfigSyntax` / `ConfigValue` with 1-based line
//! and column, and the command line (`check` and `generate`) exits non-zero with a message
//! naming the key, the position and what is allowed, without writing or touching any output.
//!
//! Every expected position is computed here from the text the test wrote (byte offset of a
//! unique needle -> line and column), never copied from a run.
use sinedec::config::{Loaded, DEFAULT_CONFIG};
use sinedec::error::Error;
use std::path::Path;
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_sinedec");
/// Source name used for the library calls and file name used for the CLI runs, so both print
/// the same `bad.toml:LINE:COL: ` prefix.
const SRC: &str = "bad.toml";

/// `text` with the single occurrence of `old` replaced by `new` (fails if `old` is not unique,
/// so an edit can never silently miss).
fn edit(text: &str, old: &str, new: &str) -> String {
    assert_eq!(
        text.matches(old).count(),
        1,
        "{old:?} must occur exactly once"
    );
    text.replacen(old, new, 1)
}

/// The default config with a sequence of unique edits applied.
fn default_with(edits: &[(&str, &str)]) -> String {
    edits
        .iter()
        .fold(DEFAULT_CONFIG.to_string(), |t, (old, new)| {
            edit(&t, old, new)
        })
}

/// Generic ADC preset with a rate limit, so that widths other than 14 are accepted.
const GENERIC: (&str, &str) = (
    "preset = \"ltc1407a-1\"",
    "preset = \"generic\"\nmax_sample_rate_hz = 2e6",
);

/// The generic preset has no LTC6912-1: its `[preamp]` section goes.
const NO_PREAMP: (&str, &str) = (
    "[preamp]\n# LTC6912-1 gains (inverting): -1, -2, -5, -10, -20, -50 or -100. A feeds sin, B cos.\ngain_a = -1\ngain_b = -1\n",
    "",
);

/// 1-based (line, column) of byte offset `off`, counted independently of the crate.
fn line_col_of(text: &str, off: usize) -> (usize, usize) {
    let before = &text[..off];
    let line = before.split('\n').count();
    let col = before.split('\n').next_back().unwrap().chars().count() + 1;
    (line, col)
}

/// Offset of the unique occurrence of `needle`.
fn offset(text: &str, needle: &str) -> usize {
    assert_eq!(
        text.matches(needle).count(),
        1,
        "{needle:?} must occur exactly once in the test text"
    );
    text.find(needle).unwrap()
}

/// Position of the first character of `needle` (a key: `needle` starts with the key).
fn at(text: &str, needle: &str) -> (usize, usize) {
    line_col_of(text, offset(text, needle))
}

/// Position of the value in `needle` = "key = value": the first character after "= ".
fn value_at(text: &str, needle: &str) -> (usize, usize) {
    let eq = needle.find("= ").expect("needle has `= `") + 2;
    line_col_of(text, offset(text, needle) + eq)
}

/// Position just after `needle` (where an unterminated construct is detected: end of line).
fn after(text: &str, needle: &str) -> (usize, usize) {
    line_col_of(text, offset(text, needle) + needle.len())
}

/// What kind of error the library must return.
#[derive(Clone, Copy, Debug)]
enum Kind {
    /// `Error::ConfigSyntax` (parse, schema, type and per-key range errors).
    Syntax,
    /// `Error::ConfigValue` for this dotted key (cross-field checks).
    Value(&'static str),
}

fn run(dir: &Path, args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run sinedec")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn listing(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// The full acceptance check for one bad config: library error variant and position, message
/// contents, and `check` / `generate` behaviour on the command line.
fn expect_bad(text: &str, kind: Kind, (line, col): (usize, usize), mentions: &[&str]) {
    let prefix = format!("{SRC}:{line}:{col}: ");

    // Library.
    let err = match Loaded::parse(text, SRC) {
        Ok(_) => panic!("config was accepted:\n{text}"),
        Err(e) => e,
    };
    let shown = err.to_string();
    match (&err, kind) {
        (
            Error::ConfigSyntax {
                source_name,
                line: l,
                column: c,
                ..
            },
            Kind::Syntax,
        ) => {
            assert_eq!(source_name, SRC);
            assert_eq!(
                (*l, *c),
                (line, col),
                "ConfigSyntax position; message: {shown}"
            );
        }
        (
            Error::ConfigValue {
                source_name,
                location,
                key,
                ..
            },
            Kind::Value(k),
        ) => {
            assert_eq!(source_name, SRC);
            assert_eq!(key, k, "ConfigValue key; message: {shown}");
            assert_eq!(
                location,
                &format!("{line}:{col}: "),
                "ConfigValue location; message: {shown}"
            );
        }
        (e, k) => panic!("expected {k:?}, got {e:?}"),
    }
    assert!(
        shown.starts_with(&prefix),
        "message {shown:?} should start with {prefix:?}"
    );
    for m in mentions {
        assert!(shown.contains(m), "message {shown:?} should mention {m:?}");
    }

    // Command line.
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(dir.join(SRC), text).unwrap();
    let want = |what: &str, o: &Output| {
        let e = stderr(o);
        assert!(!o.status.success(), "{what} succeeded on a bad config");
        assert!(
            e.contains(&format!("error: {prefix}")),
            "{what}: stderr {e:?} should contain {prefix:?}"
        );
        for m in mentions {
            assert!(e.contains(m), "{what}: stderr {e:?} should mention {m:?}");
        }
        assert!(
            !String::from_utf8_lossy(&o.stdout).contains(": ok"),
            "{what} printed ok"
        );
    };

    let o = run(dir, &["check", SRC]);
    want("check", &o);

    let o = run(dir, &["generate", SRC, "-o", "out"]);
    want("generate", &o);
    assert!(
        !dir.join("out").exists(),
        "generate created the output directory"
    );
    assert_eq!(
        listing(dir),
        vec![SRC.to_string()],
        "generate left files behind"
    );

    // A pre-existing output directory is left exactly as it was.
    let keep = dir.join("keep");
    std::fs::create_dir(&keep).unwrap();
    std::fs::write(keep.join("marker.txt"), "do not touch\n").unwrap();
    let o = run(dir, &["generate", SRC, "-o", "keep"]);
    want("generate into existing dir", &o);
    assert_eq!(listing(&keep), vec!["marker.txt".to_string()]);
    assert_eq!(
        std::fs::read_to_string(keep.join("marker.txt")).unwrap(),
        "do not touch\n"
    );
    assert_eq!(listing(dir), vec![SRC.to_string(), "keep".to_string()]);
}

// ---------------------------------------------------------------------------------------
// Malformed TOML.

#[test]
fn malformed_unclosed_string() {
    let t = default_with(&[("name = \"sd\"", "name = \"sd")]);
    // The string runs to the end of its line, where the closing quote is missing.
    expect_bad(
        &t,
        Kind::Syntax,
        after(&t, "name = \"sd"),
        &["invalid basic string", "expected `\"`"],
    );
}

#[test]
fn malformed_unclosed_table_bracket() {
    let t = default_with(&[("[adc]", "[adc")]);
    expect_bad(
        &t,
        Kind::Syntax,
        after(&t, "[adc"),
        &["unclosed table", "`]`"],
    );
}

#[test]
fn malformed_positions_are_one_based() {
    // The very first character is the error: line 1, column 1 (not 0:0).
    let t = format!("= 1\n{DEFAULT_CONFIG}");
    expect_bad(&t, Kind::Syntax, (1, 1), &["keys cannot be empty"]);
}

#[test]
fn malformed_duplicate_key_names_the_key() {
    let t = default_with(&[("ppr = 2048", "ppr = 2048\nppr = 1024")]);
    expect_bad(
        &t,
        Kind::Syntax,
        at(&t, "ppr = 1024"),
        &["duplicate key", "`ppr`"],
    );
}

// ---------------------------------------------------------------------------------------
// Schema: unknown and missing keys, wrong types.

#[test]
fn unknown_key_at_top_level() {
    let t = default_with(&[(
        "target = \"spartan3an\"",
        "target = \"spartan3an\"\nfoo = 1",
    )]);
    expect_bad(
        &t,
        Kind::Syntax,
        at(&t, "foo = 1"),
        &["unknown field `foo`", "`name`", "`cordic`"],
    );
}

#[test]
fn unknown_key_in_a_table() {
    let t = default_with(&[("ppr = 2048", "ppr = 2048\nbar = 1")]);
    // The message names the key and the table it was found in.
    expect_bad(
        &t,
        Kind::Syntax,
        at(&t, "bar = 1"),
        &[
            "unknown field `bar`",
            "encoder",
            "`ppr` or `multiturn_bits`",
        ],
    );
}

#[test]
fn missing_key_names_key_and_table() {
    let t = default_with(&[("ppr = 2048\n", "")]);
    expect_bad(
        &t,
        Kind::Syntax,
        at(&t, "[encoder]"),
        &["missing field `ppr`", "encoder"],
    );
}

#[test]
fn wrong_type_string_for_number() {
    let t = default_with(&[("ppr = 2048", "ppr = \"2048\"")]);
    expect_bad(
        &t,
        Kind::Syntax,
        value_at(&t, "ppr = \"2048\""),
        &[
            "encoder.ppr",
            "invalid type: string \"2048\"",
            "expected u32",
        ],
    );
}

#[test]
fn wrong_type_string_for_float() {
    let t = default_with(&[("frequency_hz = 133_330_000.0", "frequency_hz = \"fast\"")]);
    expect_bad(
        &t,
        Kind::Syntax,
        value_at(&t, "frequency_hz = \"fast\""),
        &["clock.frequency_hz", "invalid type: string \"fast\""],
    );
}

#[test]
fn wrong_type_number_for_name() {
    let t = default_with(&[("name = \"sd\"", "name = 3")]);
    expect_bad(
        &t,
        Kind::Syntax,
        value_at(&t, "name = 3"),
        &["`name`", "invalid type: integer `3`", "expected a string"],
    );
}

// ---------------------------------------------------------------------------------------
// Per-key ranges (checked while deserializing: the position is the offending value).

fn range_case(old: &str, new: &str, extra: &[(&str, &str)], mentions: &[&str]) {
    let mut edits = vec![(old, new)];
    edits.extend_from_slice(extra);
    let t = default_with(&edits);
    expect_bad(&t, Kind::Syntax, value_at(&t, new), mentions);
}

#[test]
fn cordic_iterations_zero() {
    range_case(
        "iterations = 14",
        "iterations = 0",
        &[],
        &["`cordic.iterations` = 0", "1..=20"],
    );
}

#[test]
fn cordic_iterations_21() {
    range_case(
        "iterations = 14",
        "iterations = 21",
        &[],
        &["`cordic.iterations` = 21", "1..=20"],
    );
}

#[test]
fn adc_width_9_generic() {
    range_case(
        "width = 14",
        "width = 9",
        &[GENERIC, NO_PREAMP],
        &["`adc.width` = 9", "10..=16"],
    );
}

#[test]
fn cordic_fine_bits_17() {
    range_case(
        "fine_bits = 14",
        "fine_bits = 17",
        &[],
        &["`cordic.fine_bits` = 17", "2..=16"],
    );
}

#[test]
fn encoder_ppr_zero() {
    range_case(
        "ppr = 2048",
        "ppr = 0",
        &[],
        &["`encoder.ppr` = 0", "1..=65535"],
    );
}

#[test]
fn encoder_ppr_65536() {
    range_case(
        "ppr = 2048",
        "ppr = 65536",
        &[],
        &["`encoder.ppr` = 65536", "1..=65535"],
    );
}

#[test]
fn encoder_multiturn_bits_17() {
    range_case(
        "multiturn_bits = 12",
        "multiturn_bits = 17",
        &[],
        &["`encoder.multiturn_bits` = 17", "0..=16"],
    );
}

/// 20 was documented (0..=20) and always rejected: adc.width >= 10 leaves at most 19 guard
/// bits in the 31-bit datapath, so 20 is now out of the documented range.
#[test]
fn cordic_guard_bits_20() {
    range_case(
        "# guard_bits = 10",
        "guard_bits = 20",
        &[],
        &["`cordic.guard_bits` = 20", "0..=19"],
    );
}

#[test]
fn clock_frequency_below_1_mhz() {
    range_case(
        "frequency_hz = 133_330_000.0",
        "frequency_hz = 999_999.0",
        &[],
        &["`clock.frequency_hz`", "1000000..=500000000 Hz"],
    );
}

/// NaN compares false with everything: it must not slip through the range check (a NaN
/// clock used to be reported against `adc.sample_rate_hz`).
#[test]
fn clock_frequency_nan() {
    range_case(
        "frequency_hz = 133_330_000.0",
        "frequency_hz = nan",
        &[],
        &["`clock.frequency_hz` = NaN", "1000000..=500000000 Hz"],
    );
}

/// A NaN threshold used to be accepted and silently disabled the amplitude monitor.
#[test]
fn monitor_min_amplitude_nan() {
    range_case(
        "min_amplitude = 0.0625",
        "min_amplitude = nan",
        &[],
        &["`monitor.min_amplitude` = NaN", "0..=0.9"],
    );
}

#[test]
fn monitor_min_amplitude_above_0_9() {
    range_case(
        "min_amplitude = 0.0625",
        "min_amplitude = 0.95",
        &[],
        &["`monitor.min_amplitude` = 0.95", "0..=0.9"],
    );
}

#[test]
fn name_starting_with_a_digit() {
    range_case(
        "name = \"sd\"",
        "name = \"3abc\"",
        &[],
        &[
            "`name` = \"3abc\"",
            "[A-Za-z0-9_]",
            "starting with a letter",
        ],
    );
}

#[test]
fn name_with_a_dash() {
    range_case(
        "name = \"sd\"",
        "name = \"a-b\"",
        &[],
        &["`name` = \"a-b\"", "[A-Za-z0-9_]"],
    );
}

#[test]
fn name_too_long() {
    let long = format!("name = \"{}\"", "a".repeat(33));
    range_case(
        "name = \"sd\"",
        &long,
        &[],
        &["`name`", "1 to 32 characters"],
    );
}

// ---------------------------------------------------------------------------------------
// Cross-field checks (after deserializing: the position is the key).

#[test]
fn sample_rate_above_ltc1407a1_limit() {
    let t = default_with(&[(
        "# sample_rate_hz = 1_000_000.0",
        "sample_rate_hz = 1_500_001.0",
    )]);
    expect_bad(
        &t,
        Kind::Value("adc.sample_rate_hz"),
        at(&t, "sample_rate_hz = 1_500_001.0"),
        &[
            "adc.sample_rate_hz",
            "1500001",
            "1500000",
            "per-channel limit",
        ],
    );
}

#[test]
fn sample_rate_above_clock() {
    let t = default_with(&[
        ("frequency_hz = 133_330_000.0", "frequency_hz = 1_000_000.0"),
        (
            "# sample_rate_hz = 1_000_000.0",
            "sample_rate_hz = 1_200_000.0",
        ),
    ]);
    expect_bad(
        &t,
        Kind::Value("adc.sample_rate_hz"),
        at(&t, "sample_rate_hz = 1_200_000.0"),
        &["adc.sample_rate_hz", "the clock"],
    );
}

#[test]
fn ltc1407a1_with_width_12() {
    let t = default_with(&[("width = 14", "width = 12")]);
    expect_bad(
        &t,
        Kind::Value("adc.width"),
        at(&t, "width = 12"),
        &["adc.width", "14-bit", "generic"],
    );
}

#[test]
fn generic_preset_without_max_sample_rate() {
    let t = default_with(&[
        ("preset = \"ltc1407a-1\"", "preset = \"generic\""),
        ("width = 14", "width = 12"),
    ]);
    expect_bad(
        &t,
        Kind::Value("adc.preset"),
        at(&t, "preset = \"generic\""),
        &["adc.preset", "adc.max_sample_rate_hz"],
    );
}

#[test]
fn guard_bits_overflow_31_bit_datapath() {
    let t = default_with(&[
        GENERIC,
        NO_PREAMP,
        ("width = 14", "width = 16"),
        ("# guard_bits = 10", "guard_bits = 19"),
    ]);
    expect_bad(
        &t,
        Kind::Value("cordic.guard_bits"),
        at(&t, "guard_bits = 19"),
        &["cordic.guard_bits", "37 bits", "at most 31"],
    );
}

#[test]
fn iterations_beyond_datapath() {
    let t = default_with(&[
        GENERIC,
        NO_PREAMP,
        ("width = 14", "width = 10"),
        ("iterations = 14", "iterations = 20"),
        ("# guard_bits = 10", "guard_bits = 0"),
    ]);
    expect_bad(
        &t,
        Kind::Value("cordic.iterations"),
        at(&t, "iterations = 20"),
        &["cordic.iterations", "use at most 10"],
    );
}

// ---------------------------------------------------------------------------------------
// Positions of cross-field errors in other valid TOML layouts.

/// A complete config with the LTC1407A-1 and width 12 (a cross-field error on `adc.width`)
/// written with inline tables.
#[test]
fn value_error_position_with_inline_tables() {
    let t = "name = \"sd\"\n\
             target = \"spartan3an\"\n\
             clock = { frequency_hz = 1e8 }\n\
             encoder = { ppr = 2048, multiturn_bits = 0 }\n\
             adc = { preset = \"ltc1407a-1\", width = 12, sample_rate_hz = 1e6 }\n\
             cordic = { iterations = 14, fine_bits = 14 }\n";
    expect_bad(
        t,
        Kind::Value("adc.width"),
        at(t, "width = 12"),
        &["adc.width", "14-bit"],
    );
}

#[test]
fn value_error_position_with_dotted_keys() {
    let t = "name = \"sd\"\n\
             target = \"spartan3an\"\n\
             clock.frequency_hz = 1e8\n\
             encoder.ppr = 2048\n\
             encoder.multiturn_bits = 0\n\
             adc.preset = \"ltc1407a-1\"\n\
             adc.width = 12\n\
             adc.sample_rate_hz = 1e6\n\
             cordic.iterations = 14\n\
             cordic.fine_bits = 14\n";
    // The key inside the dotted path.
    expect_bad(
        t,
        Kind::Value("adc.width"),
        at(t, "width = 12"),
        &["adc.width", "14-bit"],
    );
}

#[test]
fn value_error_position_with_quoted_table_header_and_indent() {
    let t = default_with(&[("[adc]", "[ \"adc\" ]"), ("width = 14", "    width = 12")]);
    expect_bad(
        &t,
        Kind::Value("adc.width"),
        at(&t, "width = 12"),
        &["adc.width"],
    );
}

#[test]
fn value_error_position_with_crlf_line_endings() {
    let t = default_with(&[("width = 14", "width = 12")]).replace('\n', "\r\n");
    expect_bad(
        &t,
        Kind::Value("adc.width"),
        at(&t, "width = 12"),
        &["adc.width"],
    );
}

#[test]
fn value_error_key_named_in_a_comment_first() {
    // A comment mentioning `width = ...` before the real key must not be reported.
    let t = default_with(&[
        (
            "[adc]",
            "[adc]\n# width = 14 is what the LTC1407A-1 delivers",
        ),
        ("width = 14\n", "width = 12\n"),
    ]);
    expect_bad(
        &t,
        Kind::Value("adc.width"),
        at(&t, "width = 12"),
        &["adc.width"],
    );
}

// ---------------------------------------------------------------------------------------
// Sanity: the edits above start from a config that is accepted.

#[test]
fn default_and_generic_base_configs_are_accepted() {
    Loaded::parse(DEFAULT_CONFIG, SRC).expect("default");
    Loaded::parse(
        &default_with(&[GENERIC, NO_PREAMP, ("width = 14", "width = 16")]),
        SRC,
    )
    .expect("generic 16");
    Loaded::parse(
        &default_with(&[
            GENERIC,
            NO_PREAMP,
            ("width = 14", "width = 10"),
            ("iterations = 14", "iterations = 10"),
            ("# guard_bits = 10", "guard_bits = 0"),
        ]),
        SRC,
    )
    .expect("generic 10, guard 0, 10 iterations (the most that fit)");
}

#[test]
fn sck_beyond_the_adc_limit() {
    // 2 clocks at 133.33 MHz = 66.7 MHz, above the LTC1407A-1's 1/19.6 ns = 51 MHz.
    let t = default_with(&[("# sck_period_clocks = 3", "sck_period_clocks = 2")]);
    expect_bad(
        &t,
        Kind::Value("adc.sck_period_clocks"),
        at(&t, "sck_period_clocks = 2"),
        &["adc.sck_period_clocks", "LTC1407A-1", "at least 3 clocks"],
    );
}

#[test]
fn preamp_gain_not_in_the_ltc6912_set() {
    let t = default_with(&[("gain_b = -1", "gain_b = -3")]);
    expect_bad(
        &t,
        Kind::Value("preamp.gain_b"),
        at(&t, "gain_b = -3"),
        &["preamp.gain_b", "-3", "-1, -2, -5, -10, -20, -50, -100"],
    );
}

#[test]
fn preamp_section_with_the_generic_preset() {
    let t = default_with(&[GENERIC, ("width = 14", "width = 12")]);
    expect_bad(
        &t,
        Kind::Value("preamp.gain_a"),
        at(&t, "gain_a = -1"),
        &["preamp", "ltc1407a-1"],
    );
}

// ---------------------------------------------------------------------------------------
// Validation gaps and messages (issue 13, sections C and D): one validation path for every
// command, documented ranges equal to the accepted ones, the key at fault named.

/// The shipped capacitive configuration.
const CAP: &str = include_str!("../configs/cyclone3_capacitive.toml");

/// The capacitive configuration with unique edits applied.
fn cap_with(edits: &[(&str, &str)]) -> String {
    edits
        .iter()
        .fold(CAP.to_string(), |t, (old, new)| edit(&t, old, new))
}

/// A low-pass section declared as a high-pass used to be accepted (simulate then reported
/// 219 degrees of error): the low-pass after the demodulator must be a low-pass.
#[test]
fn capacitive_lowpass_declared_highpass() {
    let t = cap_with(&[("kind = \"lowpass\"", "kind = \"highpass\"")]);
    expect_bad(
        &t,
        Kind::Value("capacitive.lowpass.kind"),
        at(&t, "kind = \"highpass\""),
        &["capacitive.lowpass.kind", "\"highpass\"", "\"lowpass\""],
    );
}

/// The band-pass in front of the demodulator must be a band-pass.
#[test]
fn capacitive_bandpass_declared_lowpass() {
    let t = cap_with(&[(
        "kind = \"bandpass\", order = 2, band_hz = [15_000.0, 25_000.0]",
        "kind = \"lowpass\", order = 2, corner_hz = 25_000.0",
    )]);
    expect_bad(
        &t,
        Kind::Value("capacitive.bandpass.kind"),
        at(&t, "kind = \"lowpass\", order = 2"),
        &["capacitive.bandpass.kind", "\"bandpass\""],
    );
}

/// `target = "spartan3an"` with `[capacitive]` used to write a Quartus QSF.
#[test]
fn spartan3an_target_with_the_capacitive_path() {
    let t = cap_with(&[("target = \"cyclone3\"", "target = \"spartan3an\"")]);
    expect_bad(
        &t,
        Kind::Value("target"),
        at(&t, "target = \"spartan3an\""),
        &["`target`", "\"cyclone3\"", "[capacitive]"],
    );
}

/// `target = "cyclone3"` with the LTC1407A-1 preset used to leave out `<name>_top.v`
/// without a word.
#[test]
fn cyclone3_target_with_the_ltc1407a1_preset() {
    let t = default_with(&[("target = \"spartan3an\"", "target = \"cyclone3\"")]);
    expect_bad(
        &t,
        Kind::Value("target"),
        at(&t, "target = \"cyclone3\""),
        &["`target`", "\"spartan3an\"", "ltc1407a-1"],
    );
}

/// `capacitive.coef.width` 30 and 31 were accepted by `check` and rejected by `generate`
/// with a message without a location: both now fail the same way, at the key.
#[test]
fn capacitive_coef_width_30_and_31_rejected_by_check_too() {
    for w in [30, 31] {
        let t = cap_with(&[(
            "coef = { width = 25, frac = 22 }",
            &format!("coef = {{ width = {w}, frac = 22 }}"),
        )]);
        expect_bad(
            &t,
            Kind::Value("capacitive.coef.width"),
            at(&t, &format!("width = {w}")),
            &["capacitive.coef.width", &format!("{w}")],
        );
    }
}

/// `correction.periods` is documented as 1..=256: 0 and 257 were accepted in static mode.
#[test]
fn correction_periods_out_of_range_in_static_mode() {
    for v in ["0", "257"] {
        let new = format!("\nperiods = {v}");
        let t = default_with(&[("\nperiods = 1", &new)]);
        expect_bad(
            &t,
            Kind::Syntax,
            value_at(&t, new.trim_start()),
            &["`correction.periods`", "1..=256"],
        );
    }
}

/// `gain_frac_bits` = 16 used to be blamed on `gain_sin`.
#[test]
fn gain_frac_bits_named_not_gain_sin() {
    for v in ["16", "7", "64"] {
        let new = format!("gain_frac_bits = {v}");
        let t = default_with(&[("gain_frac_bits = 14", &new)]);
        expect_bad(
            &t,
            Kind::Syntax,
            value_at(&t, &new),
            &["`correction.gain_frac_bits`", "8..=15"],
        );
    }
}

/// Loss-of-signal and clipping settings are blamed on their own key, in fractions of full
/// scale (the user's units), not on `los_amplitude` in internal magnitude units.
#[test]
fn monitor_keys_blamed_on_themselves_in_user_units() {
    let t = default_with(&[("los_release = 0.3", "los_release = 0.2")]);
    expect_bad(
        &t,
        Kind::Value("monitor.los_release"),
        at(&t, "los_release = 0.2"),
        &[
            "monitor.los_release",
            "0.2",
            "0.25",
            "fractions of full scale",
        ],
    );
    let t = default_with(&[("clip_amplitude = 1.0", "clip_amplitude = 0.28")]);
    expect_bad(
        &t,
        Kind::Value("monitor.clip_amplitude"),
        at(&t, "clip_amplitude = 0.28"),
        &["monitor.clip_amplitude", "0.28", "0.3"],
    );
    for (old, new, key) in [
        ("los_window = 8", "los_window = 0", "monitor.los_window"),
        ("los_window = 8", "los_window = 65536", "monitor.los_window"),
        ("clip_hold = 16", "clip_hold = 0", "monitor.clip_hold"),
    ] {
        let t = default_with(&[(old, new)]);
        expect_bad(&t, Kind::Value(key), at(&t, new), &[key, "1..=65535"]);
    }
    // A los_amplitude above the default release level is blamed on los_amplitude, the key in
    // the file, and the message says where the other value comes from.
    let t = default_with(&[
        ("los_amplitude = 0.25", "los_amplitude = 0.5"),
        ("los_release = 0.3\n", ""),
    ]);
    expect_bad(
        &t,
        Kind::Value("monitor.los_amplitude"),
        at(&t, "los_amplitude = 0.5"),
        &[
            "monitor.los_amplitude",
            "0.5",
            "monitor.los_release",
            "default 0.3",
        ],
    );
}

/// `report --angle-n 0` used to be blamed on `cordic.iterations`.
#[test]
fn report_angle_n_zero_names_the_option() {
    let l = Loaded::default_config().unwrap();
    let mut o = sinedec::report::Options::new("test");
    o.iterations = vec![14];
    o.angle_n = Some(0);
    let e = match sinedec::report::build(&l, &o) {
        Ok(_) => panic!("--angle-n 0 accepted"),
        Err(e) => e.to_string(),
    };
    assert!(e.contains("--angle-n"), "{e}");
    assert!(e.contains("1..=20"), "{e}");
    assert!(!e.contains("cordic.iterations"), "{e}");
}

/// The README's "Supported ranges" table for `key`: the `lo..=hi` it documents.
fn documented_range(key: &str) -> (i64, i64) {
    let readme = include_str!("../README.md");
    let row = readme
        .lines()
        .find(|l| l.starts_with(&format!("| `{key}` |")))
        .unwrap_or_else(|| panic!("README has no range row for `{key}`"));
    let cell = row.split('|').nth(2).expect("range cell");
    let range = cell
        .split_whitespace()
        .find(|w| w.contains("..="))
        .unwrap_or_else(|| panic!("no lo..=hi in {row:?}"))
        .trim_end_matches(',');
    let (lo, hi) = range.split_once("..=").unwrap();
    let num = |s: &str| -> i64 {
        s.chars()
            .filter(|c| c.is_ascii_digit() || *c == '-')
            .collect::<String>()
            .parse()
            .unwrap_or_else(|_| panic!("bad bound {s:?} in {row:?}"))
    };
    (num(lo), num(hi))
}

/// One range case: the key, the accepted text to replace, its `{}` template, and the edits
/// that make the bound reachable.
type RangeCase<'a> = (&'a str, &'a str, &'a str, Vec<(&'a str, &'a str)>);

/// Every documented bound is accepted and the value just outside it rejected, each in a
/// configuration where that bound is reachable (`guard_bits` = 20 used to be documented and
/// always rejected; `correction.periods` 0 and 257 accepted).
#[test]
fn documented_ranges_equal_accepted_ones() {
    // (key, line to replace, template with {}, extra edits that make both ends reachable)
    let generic10: Vec<(&str, &str)> = vec![
        GENERIC,
        NO_PREAMP,
        ("width = 14", "width = 10"),
        ("iterations = 14", "iterations = 10"),
    ];
    let cases: Vec<RangeCase> = vec![
        (
            "adc.width",
            "width = 14",
            "width = {}",
            vec![GENERIC, NO_PREAMP],
        ),
        (
            "cordic.iterations",
            "iterations = 14",
            "iterations = {}",
            vec![],
        ),
        (
            "cordic.fine_bits",
            "fine_bits = 14",
            "fine_bits = {}",
            vec![],
        ),
        (
            "cordic.guard_bits",
            "# guard_bits = 10",
            "guard_bits = {}",
            generic10,
        ),
        ("encoder.ppr", "ppr = 2048", "ppr = {}", vec![]),
        (
            "encoder.multiturn_bits",
            "multiturn_bits = 12",
            "multiturn_bits = {}",
            vec![],
        ),
        (
            "correction.periods",
            "\nperiods = 1",
            "\nperiods = {}",
            vec![],
        ),
        (
            "correction.gain_frac_bits",
            "gain_frac_bits = 14",
            "gain_frac_bits = {}",
            vec![],
        ),
        (
            "qep.filter_clocks",
            "filter_clocks = 4",
            "filter_clocks = {}",
            vec![],
        ),
    ];
    for (key, old, template, extra) in cases {
        let (lo, hi) = documented_range(key);
        for (v, ok) in [(lo, true), (hi, true), (lo - 1, false), (hi + 1, false)] {
            if v < 0 {
                continue; // unsigned key: a negative value is a type error, not a range one
            }
            let new = template.replace("{}", &v.to_string());
            let mut edits = vec![(old, new.as_str())];
            edits.extend(extra.iter().copied());
            let t = default_with(&edits);
            let r = Loaded::parse(&t, SRC);
            assert_eq!(
                r.is_ok(),
                ok,
                "`{key}` = {v} (documented {lo}..={hi}): {}",
                match &r {
                    Ok(_) => "accepted".to_string(),
                    Err(e) => e.to_string(),
                }
            );
            if let Err(e) = r {
                assert!(e.to_string().contains(key), "{key} = {v}: {e}");
            }
        }
    }
}
