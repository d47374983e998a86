//! The wording of configuration errors: type errors in plain words at the value, naming the
//! key (never Rust's or serde's words), and control characters from the config escaped in
//! the library's message and on stderr.
//!
//! The helpers are in `tests/cli/config_errors_util/`.
use crate::config_errors_util;
use config_errors_util::*;
use sinedec::config::{Loaded, DEFAULT_CONFIG};

/// Type errors used Rust's words ("expected u32", "as i128", "invalid type: map", "untagged
/// enum PinValue"): they are said in plain words, at the value, naming the key.
#[test]
fn type_errors_are_said_in_plain_words() {
    let pins = |v: &str| {
        format!("{DEFAULT_CONFIG}\n[board]\npreset = \"spartan3an-starter-kit\"\n[board.pins]\nbiss_ma = {v}\n")
    };
    let cases: Vec<(String, &str, &str)> = vec![
        (
            default_with(&[("iterations = 14", "iterations = \"x\"")]),
            "iterations = \"x\"",
            "a whole number",
        ),
        (
            default_with(&[("iterations = 14", "iterations = -3")]),
            "iterations = -3",
            "a whole number",
        ),
        (
            default_with(&[("iterations = 14", "iterations = 99999999999999999999")]),
            "iterations = 99999999999999999999",
            "a whole number",
        ),
        (
            default_with(&[("iterations = 14", "iterations = { a = 1 }")]),
            "iterations = { a = 1 }",
            "a whole number",
        ),
        (
            default_with(&[("iterations = 14", "iterations = [1]")]),
            "iterations = [1]",
            "a whole number",
        ),
        (
            default_with(&[("gain_a = -1", "gain_a = 1.5")]),
            "gain_a = 1.5",
            "a whole number",
        ),
        (
            default_with(&[("gain_sin = 1.0", "gain_sin = \"one\"")]),
            "gain_sin = \"one\"",
            "a number",
        ),
        (
            default_with(&[("gray = false\n# MA", "gray = 1\n# MA")]),
            "gray = 1\n# MA",
            "true or false",
        ),
        (
            pins("5"),
            "biss_ma = 5",
            "a pin name such as \"E12\" or a list of them",
        ),
        (
            pins("{ a = 1 }"),
            "biss_ma = { a = 1 }",
            "a pin name such as \"E12\" or a list of them",
        ),
    ];
    let rust_words = [
        "u8", "u16", "u32", "u64", "i32", "i64", "i128", "f64", "usize", "map", "sequence",
        "untagged", "PinValue", "struct", "enum ", "Option",
    ];
    for (t, needle, plain) in cases {
        let e = match Loaded::parse(&t, SRC) {
            Ok(_) => panic!("{needle} accepted"),
            Err(e) => e.to_string(),
        };
        for w in rust_words {
            assert!(
                !e.split(|c: char| !c.is_alphanumeric() && c != '_')
                    .any(|x| x == w.trim()),
                "{needle}: Rust term {w:?} in {e:?}"
            );
        }
        assert!(e.contains(plain), "{needle}: {e:?} should say {plain:?}");
        let (line, _) = at(&t, needle);
        assert!(e.starts_with(&format!("{SRC}:{line}:")), "{needle}: {e:?}");
    }
    // A section given as a value.
    let t = default_with(&[("[clock]\n", "clock = 5\n[clock_]\n")]);
    let e = Loaded::parse(&t, SRC)
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default();
    assert!(!e.contains("struct") && !e.contains("ClockConfig"), "{e}");
}

/// ESC and other control characters from the config (an unknown key, an enum value, a pin
/// key or value, the I/O standard, the board preset) reached the terminal raw: they are
/// escaped everywhere, in the library's message and on stderr.
#[test]
fn control_characters_from_the_config_are_escaped() {
    let board = |extra: &str| {
        format!("{DEFAULT_CONFIG}\n[board]\npreset = \"spartan3an-starter-kit\"\n{extra}")
    };
    let cases = [
        default_with(&[("ppr = 2048", "ppr = 2048\n\"a\\u001b[31mb\" = 1")]),
        default_with(&[(
            "architecture = \"unrolled\"",
            "architecture = \"\\u001b[31mx\"",
        )]),
        default_with(&[("target = \"spartan3an\"", "target = \"\\u001b[2J\"")]),
        default_with(&[("mode = \"static\"", "mode = \"\\u001b[2Jx\"")]),
        default_with(&[("name = \"sd\"", "name = \"s\\u001bd\"")]),
        board("[board.pins]\nbiss_ma = \"\\u001b[31mA1\"\n"),
        board("[board.pins]\n\"q\\u001bx\" = \"A1\"\n"),
        board("[board.pins]\nbiss_ma = \"\\u0007\"\n"),
        format!("{DEFAULT_CONFIG}\n[board]\niostandard = \"LV\\u001bCMOS\"\n"),
        format!("{DEFAULT_CONFIG}\n[board]\npreset = \"kit\\u001b\"\n"),
        default_with(&[(
            "gray = false\n# MA",
            "gray = false\ndevice_id = \"\\u001b\"\ncontrol = true\n# MA",
        )]),
    ];
    for t in cases {
        let e = match Loaded::parse(&t, SRC) {
            Ok(_) => panic!("accepted:\n{t}"),
            Err(e) => e.to_string(),
        };
        assert!(
            !e.chars().any(char::is_control),
            "raw control character in {e:?}"
        );
        assert!(
            e.contains("\\u{1b}") || e.contains("\\u{7}"),
            "not shown escaped: {e:?}"
        );
        let tmp = tempfile::tempdir().unwrap();
        std::fs::write(tmp.path().join(SRC), &t).unwrap();
        let o = run(tmp.path(), &["check", SRC]);
        assert!(!o.status.success());
        assert!(
            !o.stderr.iter().any(|&b| b == 0x1b || b == 0x07),
            "raw control byte on stderr: {:?}",
            stderr(&o)
        );
    }
}
