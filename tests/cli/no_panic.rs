//! No panic anywhere in `check` and `generate` (library calls) on mutated copies of the
//! shipped configurations (`configs/*.toml`), and one validation path: whatever `check`
//! accepts (`Loaded::parse`), `generate` builds.
//!
//! Mutations: a value replaced by an edge value of its own type (0, -1, 2^31, 2^63, NaN,
//! inf, empty or odd strings, the other enum names) or of another type, a key removed, an
//! optional key added, an element of an array changed, or the text itself cut or given a
//! stray character. Every case runs `Loaded::parse` and `Derived::describe`; generation
//! (which includes rust-hdl's Verilog export, the slow part) runs for every case the
//! configuration accepts, and most mutants are rejected, so the time stays bounded: 256
//! cases, a fixed seed (the same cases on every run, in CI too).
use proptest::prelude::*;
use proptest::test_runner::{Config as PtConfig, RngSeed};
use sinedec::config::Loaded;
use std::panic::{catch_unwind, AssertUnwindSafe};

const CONFIGS: [(&str, &str); 2] = [
    (
        "spartan3an.toml",
        include_str!("../../configs/spartan3an.toml"),
    ),
    (
        "cyclone3_capacitive.toml",
        include_str!("../../configs/cyclone3_capacitive.toml"),
    ),
];

/// Keys a config may hold that the shipped files leave out (or hold elsewhere), with a
/// plausible value; a mutation adds one.
const OPTIONAL: &[(&str, &str)] = &[
    ("cordic.guard_bits", "10"),
    ("adc.sck_period_clocks", "3"),
    ("adc.sample_rate_hz", "1e6"),
    ("adc.max_sample_rate_hz", "1e6"),
    ("adc.frame.channels", "2"),
    ("adc.frame.pipeline", "1"),
    ("adc.frame.sign", "\"offset-binary\""),
    ("adc.timing.sck_min_period_ns", "20.0"),
    ("monitor.los_window", "8"),
    ("monitor.clip_hold", "4"),
    ("monitor.los_release", "0.3"),
    ("correction.mode", "\"auto\""),
    ("qep.enabled", "true"),
    ("ssi.enabled", "true"),
    ("spi.enabled", "true"),
    ("biss.position_bits", "19"),
    ("biss.multiturn_bits", "4"),
    ("board.preset", "\"spartan3an-starter-kit\""),
    ("board.iostandard", "\"LVCMOS33\""),
    ("board.pins.biss_ma", "\"A1\""),
    ("preamp.gain_a", "-2"),
    ("capacitive.guard_frac", "4"),
];

/// Strings worth trying anywhere a string goes.
const STRINGS: &[&str] = &[
    "",
    "lowpass",
    "highpass",
    "bandpass",
    "generic",
    "ltc1407a-1",
    "static",
    "auto",
    "cyclone3",
    "spartan3an",
    "iterative",
    "unrolled",
    "spartan3an-starter-kit",
    "offset-binary",
    "twos-complement",
    "x y",
    "é\u{2028}",
    "A",
    "sd_",
];

/// Every leaf of the TOML tree as a key path (array elements by index).
fn leaves(v: &toml::Value, path: &mut Vec<String>, out: &mut Vec<Vec<String>>) {
    match v {
        toml::Value::Table(t) => {
            for (k, x) in t {
                path.push(k.clone());
                leaves(x, path, out);
                path.pop();
            }
        }
        toml::Value::Array(a) => {
            out.push(path.clone());
            for (i, x) in a.iter().enumerate() {
                path.push(i.to_string());
                leaves(x, path, out);
                path.pop();
            }
        }
        _ => out.push(path.clone()),
    }
}

fn get_mut<'a>(v: &'a mut toml::Value, path: &[String]) -> Option<&'a mut toml::Value> {
    let mut cur = v;
    for p in path {
        cur = match cur {
            toml::Value::Table(t) => t.get_mut(p)?,
            toml::Value::Array(a) => a.get_mut(p.parse::<usize>().ok()?)?,
            _ => return None,
        };
    }
    Some(cur)
}

/// An edge value for a leaf, chosen by `pick`, usually of the leaf's own type.
fn edge_value(old: &toml::Value, pick: u64) -> toml::Value {
    use toml::Value as V;
    let ints: [i64; 14] = [
        0,
        1,
        -1,
        2,
        3,
        7,
        17,
        31,
        33,
        65,
        257,
        65536,
        1 << 31,
        i64::MAX,
    ];
    let floats: [f64; 12] = [
        0.0,
        -0.0,
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        1e-300,
        1e300,
        -1.0,
        0.5,
        1.0,
        1.3000001,
        4.0e9,
    ];
    let k = (pick >> 8) as usize;
    match (old, pick % 8) {
        (_, 7) => match k % 4 {
            // another type
            0 => V::String(STRINGS[k % STRINGS.len()].to_string()),
            1 => V::Boolean(k.is_multiple_of(2)),
            2 => V::Array(vec![V::Integer(1)]),
            _ => V::Float(floats[k % floats.len()]),
        },
        (V::Integer(_), 0..=2) => {
            V::Integer(ints[k % ints.len()] * if k.is_multiple_of(3) { -1 } else { 1 })
        }
        (V::Integer(i), 3..=4) => V::Integer(i.saturating_add((k % 5) as i64 - 2)),
        (V::Integer(i), _) => V::Integer(i.saturating_mul((k % 4) as i64 + 2)),
        (V::Float(_), 0..=3) => V::Float(floats[k % floats.len()]),
        (V::Float(f), 4..=5) => V::Float(f * (0.25 + (k % 16) as f64 * 0.25)),
        (V::Float(f), _) => V::Float(-f),
        (V::String(_), _) => V::String(STRINGS[k % STRINGS.len()].to_string()),
        (V::Boolean(b), _) => V::Boolean(!b),
        (V::Array(a), _) => {
            let mut a = a.clone();
            match k % 3 {
                0 => {
                    a.pop();
                }
                1 => a.push(a.first().cloned().unwrap_or(V::Integer(0))),
                _ => a.clear(),
            }
            V::Array(a)
        }
        (_, _) => V::Integer(ints[k % ints.len()]),
    }
}

/// One mutation of the tree or the text.
#[derive(Clone, Debug)]
enum Mutation {
    /// Replace leaf `leaf % n` with an edge value (selector `pick`).
    Set { leaf: usize, pick: u64 },
    /// Remove leaf `leaf % n`.
    Remove { leaf: usize },
    /// Add optional key `key % OPTIONAL.len()`.
    Add { key: usize },
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        6 => (any::<usize>(), any::<u64>()).prop_map(|(leaf, pick)| Mutation::Set { leaf, pick }),
        2 => any::<usize>().prop_map(|leaf| Mutation::Remove { leaf }),
        2 => any::<usize>().prop_map(|key| Mutation::Add { key }),
    ]
}

/// Applies the mutations to config `which` and returns the text; `text_edit` (position,
/// character) additionally cuts the text or inserts a character into it.
fn mutate(which: usize, muts: &[Mutation], text_edit: Option<(usize, char, bool)>) -> String {
    let base = CONFIGS[which].1;
    let mut v: toml::Value = toml::from_str(base).expect("shipped config parses");
    for m in muts {
        let mut ls = Vec::new();
        leaves(&v, &mut Vec::new(), &mut ls);
        match m {
            Mutation::Set { leaf, pick } => {
                let path = &ls[leaf % ls.len()];
                if let Some(x) = get_mut(&mut v, path) {
                    *x = edge_value(x, *pick);
                }
            }
            Mutation::Remove { leaf } => {
                let path = ls[leaf % ls.len()].clone();
                let (last, head) = path.split_last().expect("non-empty path");
                match get_mut(&mut v, head) {
                    Some(toml::Value::Table(t)) => {
                        t.remove(last);
                    }
                    Some(toml::Value::Array(a)) => {
                        if let Ok(i) = last.parse::<usize>() {
                            if i < a.len() {
                                a.remove(i);
                            }
                        }
                    }
                    _ => {}
                }
            }
            Mutation::Add { key } => {
                let (k, val) = OPTIONAL[key % OPTIONAL.len()];
                let parts: Vec<&str> = k.split('.').collect();
                let mut cur = &mut v;
                for p in &parts[..parts.len() - 1] {
                    let toml::Value::Table(t) = cur else { break };
                    cur = t
                        .entry(p.to_string())
                        .or_insert_with(|| toml::Value::Table(Default::default()));
                }
                if let toml::Value::Table(t) = cur {
                    let parsed: toml::Value = toml::from_str::<toml::Table>(&format!("x = {val}"))
                        .expect("optional value parses")
                        .remove("x")
                        .expect("x");
                    t.insert(parts[parts.len() - 1].to_string(), parsed);
                }
            }
        }
    }
    let mut text = toml::to_string(&v).unwrap_or_else(|_| base.to_string());
    if let Some((pos, ch, cut)) = text_edit {
        let mut at = pos % (text.len() + 1);
        while !text.is_char_boundary(at) {
            at -= 1;
        }
        if cut {
            text.truncate(at);
        } else {
            text.insert(at, ch);
        }
    }
    text
}

/// What happened to one mutant.
#[derive(Debug, PartialEq)]
enum Outcome {
    /// Loaded::parse rejected it.
    Rejected,
    /// Accepted; every block built.
    Built,
    /// Accepted; generate ran.
    Generated,
}

/// Runs check (parse, describe) and, when accepted, builds every block `generate` builds
/// (core, board top) and, with `full`, runs `generate` itself (the Verilog export); panics
/// are turned into failures with the offending text.
fn run_case(text: &str, full: bool) -> Result<Outcome, String> {
    let r = catch_unwind(AssertUnwindSafe(|| -> Result<Outcome, String> {
        let loaded = match Loaded::parse(text, "mutant.toml") {
            Ok(l) => l,
            Err(e) => {
                // The message is printable and names the file.
                let m = e.to_string();
                if !m.starts_with("mutant.toml:") {
                    return Err(format!("error without the file name: {m}"));
                }
                return Ok(Outcome::Rejected);
            }
        };
        let d = &loaded.derived;
        let _ = d.describe();
        let _ = d.adc.describe();
        // One validation path: what check accepts, generate builds.
        let _core = sinedec::blocks::core::hdl::CoreRtl::new(d);
        if d.capacitive.is_some() {
            sinedec::blocks::captop::hdl::CapTopRtl::new(d)
                .map_err(|e| format!("check accepted it but the capacitive top fails: {e}"))?;
        } else if d.preamp.is_some() {
            sinedec::blocks::top::hdl::TopRtl::new(d)
                .map_err(|e| format!("check accepted it but the board top fails: {e}"))?;
        }
        if !full {
            return Ok(Outcome::Built);
        }
        sinedec::emit::generate(&loaded, "sinedec generate mutant.toml")
            .map_err(|e| format!("check accepted it but generate failed: {e}"))?;
        Ok(Outcome::Generated)
    }));
    match r {
        Ok(x) => x,
        Err(p) => {
            let what = p
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            Err(format!("panic: {what}"))
        }
    }
}

proptest! {
    #![proptest_config(PtConfig {
        cases: 256,
        rng_seed: RngSeed::Fixed(0x5eed_0013),
        failure_persistence: None,
        max_shrink_iters: 200,
        ..PtConfig::default()
    })]

    #[test]
    fn mutated_configs_never_panic_and_check_equals_generate(
        which in 0usize..CONFIGS.len(),
        muts in proptest::collection::vec(mutation(), 1..4),
        text_edit in proptest::option::weighted(0.15, (any::<usize>(), prop_oneof![
            Just('\n'), Just('"'), Just('['), Just('='), Just('é'), Just('\r'), Just('\u{2028}'), Just('#')
        ], any::<bool>())),
        full in proptest::bool::weighted(0.25),
    ) {
        let text = mutate(which, &muts, text_edit);
        if let Err(e) = run_case(&text, full) {
            prop_assert!(false, "{} mutated by {:?} / {:?}: {}\n--- text ---\n{}", CONFIGS[which].0, muts, text_edit, e, text);
        }
    }
}

/// The mutation machinery itself: an empty mutation list gives back configs that are
/// accepted and generated, and a known bad mutation is rejected (so the property above is
/// not vacuous).
#[test]
fn unmutated_configs_generate_and_a_bad_mutation_is_rejected() {
    for (which, config) in CONFIGS.iter().enumerate() {
        let text = mutate(which, &[], None);
        assert_eq!(
            run_case(&text, true),
            Ok(Outcome::Generated),
            "{}",
            config.0
        );
    }
    let mut v: toml::Value = toml::from_str(CONFIGS[0].1).unwrap();
    *get_mut(&mut v, &["cordic".into(), "iterations".into()]).unwrap() = toml::Value::Integer(0);
    assert_eq!(
        run_case(&toml::to_string(&v).unwrap(), true),
        Ok(Outcome::Rejected)
    );
}

/// The values the sweep tries for a leaf: every edge value of its own type, the leaf
/// plus and minus one, and one value of each other type.
fn edge_values(old: Option<&toml::Value>) -> Vec<toml::Value> {
    use toml::Value as V;
    let mut v: Vec<V> = match old {
        Some(V::Integer(i)) => [
            0,
            1,
            -1,
            2,
            3,
            7,
            15,
            16,
            17,
            19,
            20,
            21,
            30,
            31,
            32,
            33,
            64,
            65,
            256,
            257,
            65535,
            65536,
            1 << 31,
            1 << 32,
            i64::MAX,
            i64::MIN,
            i - 1,
            i + 1,
            i * 2,
        ]
        .into_iter()
        .map(V::Integer)
        .collect(),
        Some(V::Float(f)) => [
            0.0,
            -0.0,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            1e-300,
            1e300,
            -1.0,
            0.5,
            1.0,
            1.3000001,
            4.0e9,
            f * 0.5,
            f * 2.0,
            -f,
        ]
        .into_iter()
        .map(V::Float)
        .collect(),
        Some(V::String(_)) => STRINGS.iter().map(|s| V::String(s.to_string())).collect(),
        Some(V::Boolean(b)) => vec![V::Boolean(!b)],
        Some(V::Array(a)) => vec![
            V::Array(vec![]),
            V::Array(a[..a.len().saturating_sub(1)].to_vec()),
        ],
        _ => vec![],
    };
    v.extend([
        V::String("x".into()),
        V::Boolean(true),
        V::Integer(5),
        V::Float(0.25),
    ]);
    v
}

/// Every leaf of both shipped configs set, one at a time, to each edge value of its type
/// (deterministic; about 2,000 cases, parse and block construction only, plus `generate`
/// on every 16th accepted one). This sweep found `capacitive.coef.width` = 30 and 31
/// accepted by `check` and rejected by `generate`.
#[test]
fn every_leaf_at_every_edge_value() {
    let mut accepted = 0usize;
    let mut failures = Vec::new();
    for (name, base) in CONFIGS {
        let v0: toml::Value = toml::from_str(base).unwrap();
        let mut ls = Vec::new();
        leaves(&v0, &mut Vec::new(), &mut ls);
        for path in &ls {
            let old = get_mut(&mut v0.clone(), path).cloned();
            for new in edge_values(old.as_ref()) {
                let mut v = v0.clone();
                let Some(x) = get_mut(&mut v, path) else {
                    continue;
                };
                *x = new;
                let text = toml::to_string(&v).unwrap();
                let full = accepted % 16 == 15;
                match run_case(&text, full) {
                    Ok(Outcome::Rejected) => {}
                    Ok(_) => accepted += 1,
                    Err(e) => failures.push(format!("{name} {}: {e}", path.join("."))),
                }
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{} failures:\n{}",
        failures.len(),
        failures.join("\n")
    );
    assert!(
        accepted > 50,
        "only {accepted} mutants accepted: the sweep is too narrow"
    );
}

/// 1-based line and column of the key at `path` (table names, then the key; array indices
/// dropped) in text written by `toml::to_string`: a `[table]` header, then `key = value`
/// lines. Counted here from the text, independently of the crate.
fn key_position(text: &str, path: &[String]) -> Option<(usize, usize)> {
    let path: Vec<&str> = path
        .iter()
        .map(String::as_str)
        .filter(|p| p.parse::<usize>().is_err())
        .collect();
    let (key, table) = path.split_last()?;
    let table = table.join(".");
    let mut current = String::new();
    for (i, line) in text.lines().enumerate() {
        let l = line.trim_start();
        if let Some(h) = l.strip_prefix('[') {
            current = h.trim_end().trim_end_matches(']').to_string();
            continue;
        }
        if current == table && l.starts_with(&format!("{key} = ")) {
            return Some((i + 1, line.len() - l.len() + 1));
        }
    }
    None
}

/// Every leaf of both shipped configs set, one at a time, to each edge value of its type:
/// when the mutant is rejected, the error names the key that was changed (its dotted name
/// in backquotes) with the line of that key, either as the error's own position or as a
/// citation `` `key` (line:col) `` of a key that takes part in the error.
#[test]
fn a_rejected_leaf_mutant_names_the_changed_key_with_its_position() {
    let mut failures = Vec::new();
    let mut rejected = 0usize;
    for (name, base) in CONFIGS {
        let v0: toml::Value = toml::from_str(base).unwrap();
        let mut ls = Vec::new();
        leaves(&v0, &mut Vec::new(), &mut ls);
        for path in &ls {
            let old = get_mut(&mut v0.clone(), path).cloned();
            for new in edge_values(old.as_ref()) {
                let mut v = v0.clone();
                let Some(x) = get_mut(&mut v, path) else {
                    continue;
                };
                *x = new.clone();
                let text = toml::to_string(&v).unwrap();
                let Err(e) = Loaded::parse(&text, "mutant.toml") else {
                    continue;
                };
                rejected += 1;
                let key: Vec<&str> = path
                    .iter()
                    .map(String::as_str)
                    .filter(|p| p.parse::<usize>().is_err())
                    .collect();
                let key = key.join(".");
                let (line, col) = key_position(&text, path)
                    .unwrap_or_else(|| panic!("{key} not found in\n{text}"));
                let m = e.to_string();
                let own = m.starts_with(&format!("mutant.toml:{line}:"))
                    && m.contains(&format!("`{key}`"));
                let cited = m.contains(&format!("`{key}` ({line}:{col})"));
                if !(own || cited) {
                    failures.push(format!("{name} {key} = {new}: {m}"));
                }
            }
        }
    }
    assert!(rejected > 500, "only {rejected} mutants rejected");
    assert!(
        failures.is_empty(),
        "{} of {rejected} rejected mutants do not name the changed key at its line:\n{}",
        failures.len(),
        failures.join("\n")
    );
}
