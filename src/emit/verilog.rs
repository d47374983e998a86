//! Verilog text from rust-hdl blocks: checked export, module-name prefixing and identifier
//! cleaning.
//!
//! rust-hdl names modules after their path in the hierarchy (`top`, `top$stages$3`,
//! `top$stages$3$x_reg`) and signals after their path too (`stages$3$x_in`). The emitted
//! file must let two generated cores share one project, so every module is renamed
//! `<prefix>_<path with $ -> _>`, and every other identifier gets `$` -> `_` as well (some
//! vendor tools dislike `$`). The renaming is checked to be one-to-one over the whole file;
//! a clash is an error, never a silent merge.
use crate::error::{Error, Result};
use rust_hdl::core::check_error::{check_all, CheckError, PathedName};
use rust_hdl::prelude::*;
use std::collections::{BTreeMap, BTreeSet};

/// rust-hdl's check result in words (rust-hdl gives it only a `Debug` form): the kind of
/// fault and the signals concerned, `path.name`, sorted.
fn describe_check(e: &CheckError) -> String {
    let list = |names: &mut dyn Iterator<Item = &PathedName>| {
        let mut v: Vec<String> = names.map(|n| format!("{}.{}", n.path, n.name)).collect();
        v.sort();
        v.join(", ")
    };
    match e {
        CheckError::OpenSignal(m) => format!("open (undriven) signals: {}", list(&mut m.values())),
        CheckError::LogicLoops(l) => format!("logic loops through: {}", list(&mut l.iter())),
        CheckError::WritesToInputs(l) => format!("writes to inputs: {}", list(&mut l.iter())),
    }
}

/// Runs rust-hdl's connection/loop/input-write checks and exports the block as Verilog
/// whose top module is `top_name` and every other module `top_name_<path>`.
pub fn export<B: Block>(uut: &B, block: &str, top_name: &str) -> Result<String> {
    check_all(uut).map_err(|e| Error::HdlCheck {
        block: block.to_string(),
        message: describe_check(&e),
    })?;
    let raw = generate_verilog_unchecked(uut);
    rename(&raw, top_name).map(|t| super::lint::clean_widths(&t))
}

/// Splits Verilog text into identifier tokens and everything else, keeping numbers
/// (`32'h1f`) and system names (`$signed`) intact.
fn tokens(text: &str) -> Vec<(bool, &str)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    let mut start = 0;
    while i < b.len() {
        let c = b[i];
        if c.is_ascii_alphabetic() || c == b'_' {
            if start < i {
                out.push((false, &text[start..i]));
            }
            let s = i;
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'_' || b[i] == b'$') {
                i += 1;
            }
            out.push((true, &text[s..i]));
            start = i;
        } else if c.is_ascii_digit() || c == b'$' || c == b'\'' {
            // Number (with base and digits) or system task: not an identifier.
            i += 1;
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'_' || b[i] == b'\'') {
                i += 1;
            }
        } else {
            i += 1;
        }
    }
    if start < b.len() {
        out.push((false, &text[start..]));
    }
    out
}

fn clean(id: &str) -> String {
    id.replace('$', "_")
}

/// Renames modules and cleans identifiers (see the module docs).
pub fn rename(raw: &str, top_name: &str) -> Result<String> {
    let modules: BTreeSet<String> = raw
        .lines()
        .filter_map(|l| l.trim_start().strip_prefix("module "))
        .filter_map(|l| l.split('(').next())
        .map(|s| s.trim().to_string())
        .collect();
    let toks = tokens(raw);
    let mut map: BTreeMap<&str, String> = BTreeMap::new();
    for (is_id, t) in &toks {
        if !is_id || map.contains_key(t) {
            continue;
        }
        let new = if modules.contains(*t) {
            match t.strip_prefix("top") {
                Some("") => top_name.to_string(),
                Some(rest) if rest.starts_with('$') => format!("{top_name}{}", clean(rest)),
                _ => format!("{top_name}_{}", clean(t)),
            }
        } else {
            clean(t)
        };
        map.insert(t, new);
    }
    let mut seen: BTreeMap<&str, &str> = BTreeMap::new();
    for (old, new) in &map {
        if let Some(other) = seen.insert(new.as_str(), old) {
            return Err(Error::Export(format!(
                "identifiers `{other}` and `{old}` would both become `{new}`"
            )));
        }
    }
    let mut out = String::with_capacity(raw.len());
    for (is_id, t) in toks {
        if is_id {
            out.push_str(&map[t]);
        } else {
            out.push_str(t);
        }
    }
    // Trailing spaces and runs of blank lines from rust-hdl's writer.
    let mut tidy = String::with_capacity(out.len());
    let mut blank = 0;
    for line in out.lines() {
        let l = line.trim_end();
        if l.is_empty() {
            blank += 1;
            if blank > 1 {
                continue;
            }
        } else {
            blank = 0;
        }
        tidy.push_str(l);
        tidy.push('\n');
    }
    Ok(tidy)
}

/// Module names declared in a Verilog text.
pub fn module_names(text: &str) -> Vec<String> {
    text.lines()
        .filter_map(|l| l.trim_start().strip_prefix("module "))
        .filter_map(|l| l.split(['(', ' ', ';']).next())
        .map(|s| s.trim().to_string())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn check_errors_are_described_in_words() {
        let n = |path: &str, name: &str| PathedName {
            path: path.into(),
            name: name.into(),
        };
        let e = CheckError::LogicLoops(vec![n("top:b", "y"), n("top:a", "x")]);
        assert_eq!(describe_check(&e), "logic loops through: top:a.x, top:b.y");
        let e = CheckError::OpenSignal([(7, n("top", "clk"))].into_iter().collect());
        assert_eq!(describe_check(&e), "open (undriven) signals: top.clk");
        let e = CheckError::WritesToInputs(vec![n("top", "din")]);
        assert_eq!(describe_check(&e), "writes to inputs: top.din");
    }

    #[test]
    fn renames_modules_and_cleans_identifiers() {
        let raw = "module top(a);\n  top$x x$0(.a(x$0$a));\n  wire [3:0] b = 4'hf & $signed(a);\nendmodule // top\nmodule top$x(a);\nendmodule\n";
        let out = rename(raw, "sd_core").unwrap();
        assert!(out.contains("module sd_core(a);"));
        assert!(out.contains("sd_core_x x_0(.a(x_0_a));"));
        assert!(out.contains("4'hf & $signed(a)"));
        assert!(out.contains("module sd_core_x(a);"));
        assert_eq!(module_names(&out), vec!["sd_core", "sd_core_x"]);
    }

    #[test]
    fn clash_is_an_error() {
        let raw = "module top(a_b, a$b);\nendmodule\n";
        assert!(matches!(rename(raw, "t"), Err(Error::Export(_))));
    }
}
