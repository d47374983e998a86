//! Width clean-up of rust-hdl's Verilog, so that `verilator --lint-only` passes with its
//! default warnings on every emitted module.
//!
//! rust-hdl writes two constructs whose operand widths differ from their context; both
//! simulate as intended but draw Verilator's WIDTH warning:
//!
//! * `bit_cast::<W, M>(x)` becomes `((x) & W'hff..f)`. With M < W this widens `x` by
//!   context; with M > W the 32-bit result is assigned to a W-bit variable. It is rewritten
//!   as `{(W-M)'d0, x}` (widening, an explicit zero-extension) or `x[W-1:0]` (narrowing an
//!   identifier) or `sinedec_trunc_M_W(x)` (narrowing an expression through a function
//!   declared in the module), and as `(x)` when M = W.
//! * A constant assigned to a narrower variable (`state = 32'h2;` with `reg [1:0] state`)
//!   gets the variable's width (`2'h2`) when its value fits.
//! * A `LogicStruct` field read, `x[(64'h39)+:(1)]` (its offset a 64-bit literal, which
//!   `-Wall` flags as an index wider than the variable needs), becomes `x[57]`, or
//!   `x[57 +: W]` for a field of W bits: the same bits.
//!
//! Only expressions whose width is known for certain are touched: identifiers declared in
//! the module, sized literals and the operators `~ & | ^ + -` (whose result has the width
//! of the widest operand). The rewritten text is exactly equivalent to the original in
//! Verilog's semantics for identifiers, and for expressions it computes what rust-hdl's own
//! simulation computes (the expression wraps at its own width, as in Rust); the co-simulation
//! tests (rust-hdl == Icarus == Verilator on the same stimulus) check that the output is
//! unchanged.
//!
//! Hand-written here: this is a rewrite of rust-hdl's own fixed output patterns, for which
//! no Verilog crate offers a transform.
use std::collections::{BTreeMap, BTreeSet};

mod widths;

use widths::{declarations, expr_width};

/// Is `lit` a sized hex literal of all ones (`16'hffff`, `14'h3fff`), and of what width?
fn all_ones(lit: &str) -> Option<u32> {
    let (n, v) = lit.split_once("'h")?;
    let n: u32 = n.parse().ok()?;
    let value = u128::from_str_radix(v, 16).ok()?;
    (n > 0 && n < 128 && value == (1u128 << n) - 1).then_some(n)
}

/// Index of the `(` matching the `)` at `close`.
fn matching_open(s: &[u8], close: usize) -> Option<usize> {
    let mut depth = 0i32;
    for i in (0..=close).rev() {
        match s[i] {
            b')' => depth += 1,
            b'(' => {
                depth -= 1;
                if depth == 0 {
                    return Some(i);
                }
            }
            _ => {}
        }
    }
    None
}

/// Rewrites the bit casts in one line; `funcs` collects the truncation functions needed.
fn bit_casts(
    line: &str,
    widths: &BTreeMap<String, u32>,
    funcs: &mut BTreeMap<(u32, u32), ()>,
) -> String {
    let mut out = line.to_string();
    // Innermost first: repeat until no pattern is left that can be rewritten.
    let mut from = 0;
    while let Some(rel) = out[from..].find(") & ") {
        let close = from + rel;
        let lit_start = close + 4;
        let lit_end = lit_start
            + out[lit_start..]
                .find(|c: char| !(c.is_ascii_alphanumeric() || c == '\''))
                .unwrap_or(out.len() - lit_start);
        let bytes = out.as_bytes();
        let outer_close = lit_end;
        let (Some(w), true) = (
            all_ones(&out[lit_start..lit_end]),
            bytes.get(outer_close) == Some(&b')'),
        ) else {
            from = close + 1;
            continue;
        };
        let Some(open) = matching_open(bytes, close) else {
            from = close + 1;
            continue;
        };
        if open == 0 || bytes[open - 1] != b'(' {
            from = close + 1;
            continue;
        }
        let expr = out[open + 1..close].to_string();
        let Some(m) = expr_width(&expr, widths) else {
            from = close + 1;
            continue;
        };
        let ident = expr
            .trim()
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_');
        let new = if m == w {
            format!("({expr})")
        } else if m < w {
            format!("{{{}'d0, {expr}}}", w - m)
        } else if ident {
            format!("{}[{}:0]", expr.trim(), w - 1)
        } else {
            funcs.insert((m, w), ());
            format!("sinedec_trunc_{m}_{w}({expr})")
        };
        out.replace_range(open - 1..=outer_close, &new);
        from = open - 1 + new.len();
    }
    out
}

/// Gives a constant assigned to a narrower variable that variable's width.
fn narrow_constant(line: &str, widths: &BTreeMap<String, u32>) -> String {
    let t = line.trim_start();
    let indent = &line[..line.len() - t.len()];
    let Some(body) = t.strip_suffix(';') else {
        return line.to_string();
    };
    let (lhs, op, rhs) = match (body.split_once(" <= "), body.split_once(" = ")) {
        (Some((l, r)), _) => (l, "<=", r),
        (None, Some((l, r))) => (l, "=", r),
        _ => return line.to_string(),
    };
    let Some(&w) = widths.get(lhs.trim()) else {
        return line.to_string();
    };
    let Some((n, v)) = rhs.trim().split_once("'h") else {
        return line.to_string();
    };
    let (Ok(n), Ok(value)) = (n.parse::<u32>(), u128::from_str_radix(v, 16)) else {
        return line.to_string();
    };
    if n <= w || w >= 128 || value >> w != 0 {
        return line.to_string();
    }
    format!("{indent}{} {op} {w}'h{value:x};", lhs.trim())
}

/// Replaces `(x >= P)` by `1'b1` and `(x < P)` by `1'b0` where the localparam P is 0
/// (always true or false for an unsigned `x`: Verilator's UNSIGNED warning).
fn zero_compares(line: &str, zeros: &[String]) -> String {
    let mut out = line.to_string();
    for p in zeros {
        for (op, value) in [(">=", "1'b1"), ("<", "1'b0")] {
            let tail = format!(" {op} {p})");
            while let Some(at) = out.find(&tail) {
                let Some(open) = out[..at].rfind('(') else {
                    break;
                };
                let x = &out[open + 1..at];
                if x.is_empty() || !x.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
                    break;
                }
                out.replace_range(open..at + tail.len(), value);
            }
        }
    }
    out
}

/// Names of the modules in `text` without a clock input (rust-hdl ROMs): a block that
/// drives such a module's address and reads its data in one `always @(*)` looks like a
/// combinational loop to Verilator (UNOPTFLAT) although none exists.
fn clockless_modules(text: &str) -> Vec<String> {
    text.lines()
        .filter_map(|l| l.strip_prefix("module "))
        .filter_map(|l| {
            let (name, ports) = l.split_once('(')?;
            let ports = ports.split(')').next()?;
            if ports.trim().is_empty() {
                // An ANSI header (`module x (` with the ports below): the wrappers, clocked.
                return None;
            }
            let clocked = ports
                .split(',')
                .any(|p| matches!(p.trim(), "clock" | "clk"));
            (!clocked).then(|| name.trim().to_string())
        })
        .collect()
}

/// The identifiers in `text` (Verilog names; the digits of a literal's value are skipped
/// only when they cannot start a name, which is harmless here: the callers keep declared
/// names alone).
fn identifiers(text: &str) -> impl Iterator<Item = &str> {
    text.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .filter(|t| t.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_'))
}

/// The variables of `module` to mark with `/*verilator isolate_assignments*/`: the `reg`s
/// connected to an instance of a clockless module (a ROM's address) and, transitively, the
/// `reg`s their assignments read. rust-hdl computes these in the block's one
/// `always @(*)`, which also reads the ROM's data; Verilator then sees a combinational loop
/// through the block (UNOPTFLAT, e.g. `iter_0.rom_address` and `kin` in the iterative
/// CORDIC) although none exists. The hint, documented by Verilator for exactly this case,
/// moves these assignments into their own block; the logic is unchanged. Only the address
/// cone is marked, never a clock or a register's next value.
fn isolated_regs(module: &[&str], clockless: &[String]) -> BTreeSet<String> {
    let regs: BTreeSet<&str> = module
        .iter()
        .filter_map(|l| l.trim().strip_prefix("reg "))
        .filter_map(|l| l.trim_end_matches(';').split_whitespace().last())
        .collect();
    let mut marked = BTreeSet::new();
    let mut k = 0;
    while k < module.len() {
        let t = module[k].trim_start();
        let instance = clockless.iter().any(|m| {
            t.strip_prefix(m.as_str())
                .is_some_and(|r| r.starts_with(' ') && r.trim_end().ends_with('('))
        });
        k += 1;
        if !instance {
            continue;
        }
        // `.port(signal),` lines up to `);`.
        while k < module.len() && !module[k].trim().starts_with(");") {
            let c = module[k].trim();
            if let Some((_, sig)) = c
                .trim_end_matches(',')
                .strip_suffix(')')
                .and_then(|c| c.split_once('('))
            {
                if regs.contains(sig.trim()) {
                    marked.insert(sig.trim().to_string());
                }
            }
            k += 1;
        }
    }
    // The cone of the marked variables: what their assignments read, and the conditions
    // of the `if`s around those assignments (an `else` branch also depends on the
    // conditions before it).
    loop {
        let before = marked.len();
        let mut frames: Vec<Vec<&str>> = Vec::new();
        let mut popped: Vec<&str> = Vec::new();
        for l in module {
            let t = l.trim();
            let cond = || {
                let open = t.find('(')?;
                let close = t.rfind(')')?;
                (open < close).then(|| &t[open + 1..close])
            };
            if t.starts_with("if (") && t.ends_with("begin") {
                frames.push(cond().into_iter().collect());
            } else if t.starts_with("else") && t.ends_with("begin") {
                let mut f = std::mem::take(&mut popped);
                f.extend(cond());
                frames.push(f);
            } else if t.starts_with("case (") {
                frames.push(cond().into_iter().collect());
            } else if t.ends_with("begin") {
                frames.push(Vec::new());
            } else if t == "end" || t == "endcase" {
                popped = frames.pop().unwrap_or_default();
            } else if let Some((lhs, rhs)) = t.strip_suffix(';').and_then(|b| b.split_once(" = ")) {
                if marked.contains(lhs.trim()) {
                    let read: Vec<&str> = frames
                        .iter()
                        .flatten()
                        .copied()
                        .chain([rhs])
                        .flat_map(identifiers)
                        .filter(|id| regs.contains(id))
                        .collect();
                    marked.extend(read.into_iter().map(String::from));
                }
            }
        }
        if marked.len() == before {
            return marked;
        }
    }
}

/// `[(64'hK)+:(W)]` (a `LogicStruct` field) as `[K]` (W = 1) or `[K +: W]`, K in decimal.
fn field_slices(l: &str) -> String {
    let mut out = String::with_capacity(l.len());
    let mut rest = l;
    while let Some(a) = rest.find("[(64'h") {
        let tail = &rest[a + 6..];
        let parsed = tail.split_once(")+:(").and_then(|(k, t)| {
            let (w, after) = t.split_once(")]")?;
            let k = u64::from_str_radix(k, 16).ok()?;
            let w: u64 = w.parse().ok()?;
            Some((k, w, after))
        });
        let Some((k, w, after)) = parsed else {
            out.push_str(&rest[..a + 6]);
            rest = tail;
            continue;
        };
        out.push_str(&rest[..a]);
        if w == 1 {
            out.push_str(&format!("[{k}]"));
        } else {
            out.push_str(&format!("[{k} +: {w}]"));
        }
        rest = after;
    }
    out.push_str(rest);
    out
}

/// Applies the rewrites to every module of `text` (see the module doc), and marks the
/// variables of [`isolated_regs`] with Verilator's `isolate_assignments` hint (no warning is
/// waived).
pub fn clean_widths(text: &str) -> String {
    let lines: Vec<&str> = text.lines().collect();
    let clockless = clockless_modules(text);
    let mut out = String::with_capacity(text.len() + 1024);
    let mut i = 0;
    while i < lines.len() {
        if !lines[i].trim_start().starts_with("module ") {
            out.push_str(lines[i]);
            out.push('\n');
            i += 1;
            continue;
        }
        let end = (i..lines.len())
            .find(|&k| lines[k].trim_start().starts_with("endmodule"))
            .unwrap_or(lines.len() - 1);
        let module = &lines[i..=end];
        let widths = declarations(module);
        let zeros: Vec<String> = module
            .iter()
            .filter_map(|l| l.trim().strip_prefix("localparam"))
            .filter_map(|l| l.trim_end_matches(';').split_once('='))
            .filter(|(_, v)| {
                v.trim()
                    .split_once('\'')
                    .is_some_and(|(_, d)| d.len() > 1 && d[1..].chars().all(|c| c == '0'))
            })
            .map(|(n, _)| n.trim().to_string())
            .collect();
        let isolate = isolated_regs(module, &clockless);
        let mut funcs = BTreeMap::new();
        let body: Vec<String> = module
            .iter()
            .map(|l| {
                let l = narrow_constant(&bit_casts(l, &widths, &mut funcs), &widths);
                let l = field_slices(&zero_compares(&l, &zeros));
                let name = l
                    .strip_prefix("    reg  ")
                    .and_then(|r| r.strip_suffix(';'))
                    .and_then(|r| r.split_whitespace().last());
                match name {
                    Some(n) if isolate.contains(n) => format!(
                        "{} /*verilator isolate_assignments*/;",
                        l.trim_end_matches(';')
                    ),
                    _ => l,
                }
            })
            .collect();
        // The truncation functions go just before `endmodule`.
        for l in &body[..body.len() - 1] {
            out.push_str(l);
            out.push('\n');
        }
        for (m, w) in funcs.keys() {
            out.push_str(&format!(
                "    // Low {w} bits of a {m}-bit value (rust-hdl bit_cast).\n    function [{}:0] sinedec_trunc_{m}_{w};\n        input [{}:0] v;\n        sinedec_trunc_{m}_{w} = v[{}:0];\n    endfunction\n",
                w - 1,
                m - 1,
                w - 1
            ));
        }
        out.push_str(&body[body.len() - 1]);
        out.push('\n');
        i = end + 1;
    }
    if !text.ends_with('\n') {
        out.pop();
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn struct_field_slices_lose_their_64_bit_offsets() {
        assert_eq!(
            field_slices("a = dn_q[(64'h39)+:(1)] & b[(64'h4)+:(3)] | c[3];"),
            "a = dn_q[57] & b[4 +: 3] | c[3];"
        );
        assert_eq!(field_slices("x[(64'hzz)+:(1)]"), "x[(64'hzz)+:(1)]");
    }

    const M: &str = "module m (\n    input wire  [15:0] in_cos,\n    input wire  [31:0] big\n);\n    reg  [1:0] q;\n    reg  [31:0] sx;\n    reg  [15:0] n;\n    localparam  amask = 32'h3fff;\n    always @(*) begin\n        sx = ((in_cos) & 32'hffffffff) & amask;\n        n = ((big) & 16'hffff);\n        n = ((big & amask) & 16'hffff);\n        q = 32'h2;\n        q <= 32'h7;\n        sx = ((sx) & 32'hffffffff);\n    end\nendmodule\n";

    #[test]
    fn widen_narrow_and_constants() {
        let c = clean_widths(M);
        assert!(c.contains("sx = {16'd0, in_cos} & amask;"), "{c}");
        assert!(c.contains("n = big[15:0];"), "{c}");
        assert!(c.contains("n = sinedec_trunc_32_16(big & amask);"), "{c}");
        assert!(c.contains("function [15:0] sinedec_trunc_32_16;"), "{c}");
        assert!(c.contains("q = 2'h2;"), "{c}");
        // 7 does not fit in 2 bits: left alone (Verilator then reports it, as it should).
        assert!(c.contains("q <= 32'h7;"), "{c}");
        assert!(c.contains("sx = (sx);"), "{c}");
    }

    /// The patterns of the correction fit's RTL: a cast of a part select, casts of shifted
    /// words, and a shift of a sum of a concatenation (its width is the sum's, 53 bits).
    #[test]
    fn selects_shifts_and_concatenations() {
        let t = "module m (\n    input wire  [63:0] e,\n    input wire  [31:0] l,\n    input wire  [51:0] b\n);\n    localparam  s32 = 64'h20;\n    localparam  one53 = 53'h1;\n    reg  [32:0] w;\n    reg  [31:0] x;\n    reg  [27:0] z;\n    reg  [51:0] r;\n    always @(*) begin\n        w = {1'd0, l} + ((e[31:0]) & 33'h1ffffffff);\n        x = ((e >> s32) & 32'hffffffff);\n        z = z - ((e >> s32) & 28'hfffffff);\n        r = (((({1'd0, b} << s32) | one53) >> s32) & 52'hfffffffffffff);\n        x = ((l + e >> s32) & 32'hffffffff);\n    end\nendmodule\n";
        let c = clean_widths(t);
        assert!(c.contains("w = {1'd0, l} + {1'd0, e[31:0]};"), "{c}");
        assert!(c.contains("x = sinedec_trunc_64_32(e >> s32);"), "{c}");
        assert!(c.contains("z = z - sinedec_trunc_64_28(e >> s32);"), "{c}");
        assert!(
            c.contains("r = sinedec_trunc_53_52((({1'd0, b} << s32) | one53) >> s32);"),
            "{c}"
        );
        // A cast of a truncation this rewrite wrote (the fit's `~` of a high half).
        let t2 = t.replace(
            "        x = ((l + e >> s32) & 32'hffffffff);\n",
            "        x = ((l + e >> s32) & 32'hffffffff);\n        r = (((~((e >> s32) & 28'hfffffff)) & 52'hfffffffffffff) << s32);\n",
        );
        let c2 = clean_widths(&t2);
        assert!(
            c2.contains("r = ({24'd0, ~sinedec_trunc_64_28(e >> s32)} << s32);"),
            "{c2}"
        );
        // A shift next to another operator at one level: precedence decides, left alone.
        assert!(c.contains("x = ((l + e >> s32) & 32'hffffffff);"), "{c}");
    }

    #[test]
    fn zero_compares_and_rom_users() {
        let t = "module m_rom(addr,data);\n    input wire  [3:0] addr;\n    output reg  [3:0] data;\nendmodule\nmodule w (\n    input wire clk\n);\nendmodule\nmodule m(clk,x);\n    input wire  clk;\n    input wire  [7:0] x;\n    localparam  z = 8'h0;\n    reg  [3:0] a;\n    reg  [3:0] b;\n    reg  [3:0] other;\n    reg  s;\n    reg  r_clock;\n    wire  [3:0] d;\n    m_rom rom(\n        .addr(a),\n        .data(d)\n    );\n    always @(*) begin\n        r_clock = clk;\n        b = x[3:0] + 4'h1;\n        s = x[0];\n        if (s) begin\n        end\n        else begin\n            b = 4'h0;\n        end\n        a = b;\n        other = d;\n        if (c & (x >= z) & (x < z)) begin\n        end\n    end\nendmodule\n";
        let c = clean_widths(t);
        assert!(c.contains("if (c & 1'b1 & 1'b0) begin"), "{c}");
        // The ROM's address and the variables it is computed from, nothing else.
        assert!(
            c.contains("reg  [3:0] a /*verilator isolate_assignments*/;"),
            "{c}"
        );
        assert!(
            c.contains("reg  [3:0] b /*verilator isolate_assignments*/;"),
            "{c}"
        );
        // `s` is the condition of the `else` around an assignment to `b`.
        assert!(
            c.contains("reg  s /*verilator isolate_assignments*/;"),
            "{c}"
        );
        assert_eq!(c.matches("isolate_assignments").count(), 3, "{c}");
        // `w` has an ANSI header (a wrapper): not taken for a clockless module.
        assert_eq!(clockless_modules(t), vec!["m_rom".to_string()]);
    }

    #[test]
    fn uncertain_widths_are_left_alone() {
        let t = "module m (\n    input wire  [15:0] a\n);\n    reg  [31:0] x;\n    always @(*) begin\n        x = ((a << 2) & 32'hffffffff);\n        x = ((u) & 32'hffffffff);\n        x = ((a) & 32'h00ff);\n    end\nendmodule\n";
        assert_eq!(clean_widths(t), t);
    }
}
