//! Bad configurations: the library reports `ConfigSyntax` / `ConfigValue` with 1-based line
//! and column, and the command line (`check` and `generate`) exits non-zero with a message
//! naming the key, the position and what is allowed, without writing or touching any output.
//!
//! Every expected position is computed here from the text the test wrote (byte offset of a
//! unique needle -> line and column), never copied from a run.
//!
//! The helpers are in `tests/cli/config_errors_util/`; which key an error blames is tested in
//! `tests/config_blame.rs`, ranges in `tests/config_ranges.rs`, what applies to which design
//! in `tests/config_scope.rs`, the wording of the messages in `tests/cli/config_wording.rs`.
use crate::config_errors_util;
use config_errors_util::*;
use sinedec::config::DEFAULT_CONFIG;

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
            "expected a whole number (0 or more)",
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
