//! Helpers shared by the tests of bad configurations: `tests/cli/config_errors.rs` (syntax,
//! schema, types), `tests/cli/config_wording.rs` (message wording), `tests/config_blame.rs` (the key an error names),
//! `tests/config_ranges.rs` (ranges) and `tests/config_scope.rs` (what applies to which
//! design).
#![allow(dead_code)]
use sinedec::config::{Loaded, DEFAULT_CONFIG};
use sinedec::error::Error;
use std::path::Path;
use std::process::{Command, Output};

pub const BIN: &str = env!("CARGO_BIN_EXE_sinedec");
/// Source name used for the library calls and file name used for the CLI runs, so both print
/// the same `bad.toml:LINE:COL: ` prefix.
pub const SRC: &str = "bad.toml";

/// `text` with the single occurrence of `old` replaced by `new` (fails if `old` is not unique,
/// so an edit can never silently miss).
pub fn edit(text: &str, old: &str, new: &str) -> String {
    assert_eq!(
        text.matches(old).count(),
        1,
        "{old:?} must occur exactly once"
    );
    text.replacen(old, new, 1)
}

/// The default config with a sequence of unique edits applied.
pub fn default_with(edits: &[(&str, &str)]) -> String {
    edits
        .iter()
        .fold(DEFAULT_CONFIG.to_string(), |t, (old, new)| {
            edit(&t, old, new)
        })
}

/// Generic ADC preset with a rate limit, so that widths other than 14 are accepted.
pub const GENERIC: (&str, &str) = (
    "preset = \"ltc1407a-1\"",
    "preset = \"generic\"\nmax_sample_rate_hz = 2e6",
);

/// The generic preset has no LTC6912-1: its `[preamp]` section goes.
pub const NO_PREAMP: (&str, &str) = (
    "[preamp]\n# LTC6912-1 gains (inverting): -1, -2, -5, -10, -20, -50 or -100. A feeds sin, B cos.\ngain_a = -1\ngain_b = -1\n",
    "",
);

/// The generic-preset default config with `section` (e.g. "[adc.frame]\nframe_sck = 20")
/// inserted before `[cordic]`.
pub fn generic_with(section: &str) -> String {
    default_with(&[
        GENERIC,
        NO_PREAMP,
        ("\n[cordic]", &format!("\n{section}\n\n[cordic]")),
    ])
}

/// 1-based (line, column) of byte offset `off`, counted independently of the crate.
pub fn line_col_of(text: &str, off: usize) -> (usize, usize) {
    let before = &text[..off];
    let line = before.split('\n').count();
    let col = before.split('\n').next_back().unwrap().chars().count() + 1;
    (line, col)
}

/// Offset of the unique occurrence of `needle`.
pub fn offset(text: &str, needle: &str) -> usize {
    assert_eq!(
        text.matches(needle).count(),
        1,
        "{needle:?} must occur exactly once in the test text"
    );
    text.find(needle).unwrap()
}

/// Position of the first character of `needle` (a key: `needle` starts with the key).
pub fn at(text: &str, needle: &str) -> (usize, usize) {
    line_col_of(text, offset(text, needle))
}

/// Position of the value in `needle` = "key = value": the first character after "= ".
pub fn value_at(text: &str, needle: &str) -> (usize, usize) {
    let eq = needle.find("= ").expect("needle has `= `") + 2;
    line_col_of(text, offset(text, needle) + eq)
}

/// Position just after `needle` (where an unterminated construct is detected: end of line).
pub fn after(text: &str, needle: &str) -> (usize, usize) {
    line_col_of(text, offset(text, needle) + needle.len())
}

/// What kind of error the library must return.
#[derive(Clone, Copy, Debug)]
pub enum Kind {
    /// `Error::ConfigSyntax` (parse, schema, type and per-key range errors).
    Syntax,
    /// `Error::ConfigValue` for this dotted key (cross-field checks).
    Value(&'static str),
}

pub fn run(dir: &Path, args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run sinedec")
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

pub fn listing(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// The full acceptance check for one bad config: library error variant and position, message
/// contents, and `check` / `generate` behaviour on the command line.
pub fn expect_bad(text: &str, kind: Kind, (line, col): (usize, usize), mentions: &[&str]) {
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
// Per-key ranges (checked while deserializing: the position is the offending value).

pub fn range_case(old: &str, new: &str, extra: &[(&str, &str)], mentions: &[&str]) {
    let mut edits = vec![(old, new)];
    edits.extend_from_slice(extra);
    let t = default_with(&edits);
    expect_bad(&t, Kind::Syntax, value_at(&t, new), mentions);
}

// ---------------------------------------------------------------------------------------
// Validation gaps and messages (issue 13, sections C and D): one validation path for every
// command, documented ranges equal to the accepted ones, the key at fault named.

/// The shipped capacitive configuration.
pub const CAP: &str = include_str!("../../../configs/cyclone3_capacitive.toml");

/// The capacitive configuration with unique edits applied.
pub fn cap_with(edits: &[(&str, &str)]) -> String {
    edits
        .iter()
        .fold(CAP.to_string(), |t, (old, new)| edit(&t, old, new))
}

/// The docs/cli.md's "Supported ranges" table for `key`: the `lo..=hi` it documents.
pub fn documented_range(key: &str) -> (i64, i64) {
    let readme = include_str!("../../../docs/cli.md");
    let row = readme
        .lines()
        .find(|l| l.starts_with(&format!("| `{key}` |")))
        .unwrap_or_else(|| panic!("docs/cli.md has no range row for `{key}`"));
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
pub type RangeCase<'a> = (&'a str, &'a str, &'a str, Vec<(&'a str, &'a str)>);
