//! The compiled path's code generator: the levelized netlist (src/engine/netlist/) as
//! one straight-line Rust source file, a `cdylib` with a small C ABI (see
//! src/engine/compiled.rs for the loader):
//!
//! ```text
//!  sdeng_new() -> *mut St        registers and memories at their initial values
//!  sdeng_set(st, k, v)           input k (in the netlist's input order) := v (masked)
//!  sdeng_tick(st)                next-state cone, registers and memory writes load,
//!                                output cone (one rising edge, the co-simulation cycle)
//!  sdeng_eval(st)                output cone only (after inputs changed, no edge)
//!  sdeng_get(st, k) -> u64       output k
//!  sdeng_run(st, rows, n, outs)  n cycles: set every input from rows, tick, copy outputs
//!  sdeng_free(st)
//! ```
//!
//! Each combinational cell is a `let` of a `u64` computed by the functions of
//! src/engine/ops.rs (pasted in as `mod ops`) with constant widths, which rustc folds into
//! a few instructions; registers live in `St::r`, memories in `St::m<k>`.
use super::netlist::{Cell, Netlist, Op, Operand, SigKind};
use std::fmt::Write as _;

/// Bumped when the generated ABI changes.
pub const ABI_VERSION: u64 = 1;

fn sig_expr(nl: &Netlist, s: usize) -> String {
    match nl.signals[s].kind {
        SigKind::Input(k) => format!("s.i[{k}]"),
        SigKind::Reg(k) => format!("s.r[{k}]"),
        SigKind::Comb(k) => format!("c{k}"),
    }
}

fn operand(nl: &Netlist, o: &Operand) -> String {
    let mut parts = Vec::new();
    for c in &o.chunks {
        let full = c.lo == 0 && c.width == nl.signals[c.sig].width;
        let mut e = sig_expr(nl, c.sig);
        if c.lo > 0 {
            e = format!("({e} >> {})", c.lo);
        }
        if !full {
            e = format!("({e} & {:#x})", mask(c.width));
        }
        if c.at > 0 {
            e = format!("({e} << {})", c.at);
        }
        parts.push(e);
    }
    if o.konst != 0 || parts.is_empty() {
        parts.push(format!("{:#x}u64", o.konst));
    }
    parts.join(" | ")
}

fn mask(w: u32) -> u64 {
    if w >= 64 {
        u64::MAX
    } else {
        (1u64 << w) - 1
    }
}

fn cell_expr(nl: &Netlist, c: &Cell) -> String {
    let a = operand(nl, &c.a);
    let b = || operand(nl, &c.b);
    let (aw, asg, bw, bsg, yw) = (c.a.width, c.a_signed, c.b.width, c.b_signed, c.y_width);
    match c.op {
        Op::Unary(op) => format!("unary({op}, {a}, {aw}, {asg}, {yw})"),
        Op::Arith(op) => format!("arith({op}, {a}, {aw}, {asg}, {}, {bw}, {bsg}, {yw})", b()),
        Op::Compare(op) => format!("compare({op}, {a}, {aw}, {asg}, {}, {bw}, {bsg})", b()),
        Op::Logic(op) => format!("logic({op}, {a}, {aw}, {})", b()),
        Op::Shift(op) => format!("shift({op}, {a}, {aw}, {asg}, {}, {bw}, {bsg}, {yw})", b()),
        Op::Mux => format!(
            "if ({}) != 0 {{ {} }} else {{ {a} }}",
            operand(nl, &c.s),
            b()
        ),
        Op::Pmux => {
            let mut e = format!("{{ let sel = {}; ", operand(nl, &c.s));
            for (i, w) in c.words.iter().enumerate() {
                let _ = write!(
                    e,
                    "if sel & {:#x} != 0 {{ {} }} else ",
                    1u64 << i,
                    operand(nl, w)
                );
            }
            let _ = write!(e, "{{ {a} }} }}");
            e
        }
        Op::MemRead(k) => {
            let m = &nl.mems[k];
            format!(
                "{{ let i = ({a}) as i64 - ({}i64); if i >= 0 && (i as usize) < {} {{ s.m{k}[i as usize] }} else {{ 0 }} }}",
                m.offset,
                m.init.len()
            )
        }
    }
}

/// For each cell, the register whose data operand alone needs it, when that register has
/// an enable or a reset: such cells are computed only in the branch that loads the data
/// (most registers hold most cycles), the others before every register.
fn owners(nl: &Netlist) -> Vec<Option<usize>> {
    const SHARED: usize = usize::MAX;
    let mut own: Vec<Option<usize>> = vec![None; nl.cells.len()];
    let note = |own: &mut Vec<Option<usize>>, sig: usize, who: usize| {
        if let SigKind::Comb(i) = nl.signals[sig].kind {
            own[i] = match own[i] {
                None => Some(who),
                Some(x) if x == who => Some(x),
                _ => Some(SHARED),
            };
        }
    };
    for (k, r) in nl.regs.iter().enumerate() {
        let gated = r.en.is_some() || r.srst.is_some();
        for sig in r.d.sources() {
            note(&mut own, sig, if gated { k } else { SHARED });
        }
        let ctl =
            r.en.iter()
                .map(|(o, _)| o)
                .chain(r.srst.iter().map(|(o, _, _)| o));
        for sig in ctl.flat_map(|o| o.sources()) {
            note(&mut own, sig, SHARED);
        }
    }
    for w in &nl.writes {
        for sig in w
            .addr
            .sources()
            .chain(w.data.sources())
            .chain(w.en.sources())
        {
            note(&mut own, sig, SHARED);
        }
    }
    // Cells are in topological order: every user of cell i comes after it.
    for &i in nl.next_cone.iter().rev() {
        let who = own[i].unwrap_or(SHARED);
        for sig in nl.cells[i].operands().flat_map(|o| o.sources()) {
            note(&mut own, sig, who);
        }
    }
    own.into_iter()
        .map(|o| o.filter(|&x| x != SHARED))
        .collect()
}

fn cone(nl: &Netlist, out: &mut String, cells: &[usize]) {
    for &i in cells {
        let c = &nl.cells[i];
        let _ = writeln!(out, "    let c{i}: u64 = {};", cell_expr(nl, c));
    }
}

/// The generated crate's source.
pub fn generate(nl: &Netlist) -> String {
    let mut o = String::with_capacity(64 * nl.cells.len() + 4096);
    let _ = writeln!(
        o,
        "// Generated by sinedec's simulation engine (src/engine/codegen.rs). Do not edit."
    );
    let _ = writeln!(
        o,
        "#![allow(unused, clippy::all, non_snake_case, unused_parens, unused_braces)]"
    );
    let _ = writeln!(o, "mod ops {{\n{}\n}}\nuse ops::*;", include_str!("ops.rs"));
    let (ni, nr, no) = (nl.inputs.len(), nl.regs.len(), nl.outputs.len());
    let _ = writeln!(
        o,
        "pub struct St {{\n    i: [u64; {ni}],\n    r: [u64; {nr}],\n    o: [u64; {no}],"
    );
    for (k, m) in nl.mems.iter().enumerate() {
        let _ = writeln!(o, "    m{k}: [u64; {}],", m.init.len());
    }
    let _ = writeln!(o, "}}");
    // Initial state.
    let _ = writeln!(o, "fn init() -> St {{\n    St {{\n        i: [0; {ni}],");
    let inits: Vec<String> = nl.regs.iter().map(|r| format!("{:#x}", r.init)).collect();
    let _ = writeln!(o, "        r: [{}],", inits.join(", "));
    let _ = writeln!(o, "        o: [0; {no}],");
    for (k, m) in nl.mems.iter().enumerate() {
        let words: Vec<String> = m.init.iter().map(|w| format!("{w:#x}")).collect();
        let _ = writeln!(o, "        m{k}: [{}],", words.join(", "));
    }
    let _ = writeln!(o, "    }}\n}}");
    // Output cone.
    let _ = writeln!(o, "#[inline(always)]\nfn outs(s: &mut St) {{");
    cone(nl, &mut o, &nl.out_cone);
    for (k, (_, op)) in nl.outputs.iter().enumerate() {
        let _ = writeln!(o, "    s.o[{k}] = {};", operand(nl, op));
    }
    let _ = writeln!(o, "}}");
    // Next state.
    let _ = writeln!(o, "#[inline(always)]\nfn edge(s: &mut St) {{");
    let own = owners(nl);
    let mut owned: Vec<Vec<usize>> = vec![vec![]; nl.regs.len()];
    let mut shared = vec![];
    for &i in &nl.next_cone {
        match own[i] {
            Some(k) => owned[k].push(i),
            None => shared.push(i),
        }
    }
    cone(nl, &mut o, &shared);
    for (k, r) in nl.regs.iter().enumerate() {
        let q = format!("s.r[{k}]");
        let mut d = String::from("{\n");
        cone(nl, &mut d, &owned[k]);
        let _ = write!(d, "    {} }}", operand(nl, &r.d));
        let en =
            r.en.as_ref()
                .map(|(e, pol)| format!("(({}) != 0) == {pol}", operand(nl, e)));
        let rst = r
            .srst
            .as_ref()
            .map(|(e, pol, v)| (format!("(({}) != 0) == {pol}", operand(nl, e)), *v));
        let e = match (en, rst) {
            (None, None) => d,
            (Some(en), None) => format!("if {en} {{ {d} }} else {{ {q} }}"),
            (None, Some((rs, v))) => format!("if {rs} {{ {v:#x} }} else {{ {d} }}"),
            (Some(en), Some((rs, v))) if r.ce_over_srst => {
                format!("if {en} {{ if {rs} {{ {v:#x} }} else {{ {d} }} }} else {{ {q} }}")
            }
            (Some(en), Some((rs, v))) => {
                format!("if {rs} {{ {v:#x} }} else if {en} {{ {d} }} else {{ {q} }}")
            }
        };
        let _ = writeln!(o, "    let n{k}: u64 = {e};");
    }
    for w in &nl.writes {
        let m = &nl.mems[w.mem];
        let _ = writeln!(
            o,
            "    {{ let i = ({}) as i64 - ({}i64); let d = {}; let e = {}; \
             if i >= 0 && (i as usize) < {} {{ let x = &mut s.m{}[i as usize]; *x = (*x & !e) | (d & e); }} }}",
            operand(nl, &w.addr),
            m.offset,
            operand(nl, &w.data),
            operand(nl, &w.en),
            m.init.len(),
            w.mem
        );
    }
    for k in 0..nr {
        let _ = writeln!(o, "    s.r[{k}] = n{k};");
    }
    let _ = writeln!(o, "}}");
    let masks: Vec<String> = nl
        .inputs
        .iter()
        .map(|(_, s)| format!("{:#x}", mask(nl.signals[*s].width)))
        .collect();
    let _ = writeln!(o, "const IN_MASK: [u64; {ni}] = [{}];", masks.join(", "));
    let _ = write!(
        o,
        r#"
#[no_mangle]
pub extern "C" fn sdeng_abi() -> u64 {{ {ABI_VERSION} }}
#[no_mangle]
pub extern "C" fn sdeng_shape() -> u64 {{ ({ni}u64 << 32) | {no}u64 }}
#[no_mangle]
pub extern "C" fn sdeng_new() -> *mut St {{
    let mut s = Box::new(init());
    outs(&mut s);
    Box::into_raw(s)
}}
#[no_mangle]
pub unsafe extern "C" fn sdeng_free(s: *mut St) {{
    if !s.is_null() {{ drop(Box::from_raw(s)); }}
}}
#[no_mangle]
pub unsafe extern "C" fn sdeng_set(s: *mut St, k: u32, v: u64) {{
    let s = &mut *s;
    if (k as usize) < {ni} {{ s.i[k as usize] = v & IN_MASK[k as usize]; }}
}}
#[no_mangle]
pub unsafe extern "C" fn sdeng_get(s: *const St, k: u32) -> u64 {{
    let s = &*s;
    if (k as usize) < {no} {{ s.o[k as usize] }} else {{ 0 }}
}}
#[no_mangle]
pub unsafe extern "C" fn sdeng_eval(s: *mut St) {{ outs(&mut *s); }}
#[no_mangle]
pub unsafe extern "C" fn sdeng_tick(s: *mut St) {{
    let s = &mut *s;
    edge(s);
    outs(s);
}}
#[no_mangle]
pub unsafe extern "C" fn sdeng_run(s: *mut St, rows: *const u64, n: u64, out: *mut u64) {{
    let s = &mut *s;
    let rows = core::slice::from_raw_parts(rows, n as usize * {ni});
    let out = core::slice::from_raw_parts_mut(out, n as usize * {no});
    for c in 0..n as usize {{
        for k in 0..{ni} {{ s.i[k] = rows[c * {ni} + k] & IN_MASK[k]; }}
        edge(s);
        outs(s);
        out[c * {no}..(c + 1) * {no}].copy_from_slice(&s.o);
    }}
}}
"#
    );
    o
}
