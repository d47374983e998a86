//! The hand-written text of the emitted files, kept in `rtl-templates/` at the top of the
//! repository where an FPGA engineer can read and review it, and filled in here with
//! [minijinja](https://docs.rs/minijinja) (Jinja syntax, the template language FuseSoC and
//! edalize use; the README says why it was chosen).
//!
//! The templates are compiled into the binary (`include_str!`), so `sinedec` needs no file
//! at run time. Rust computes every value (numbers are formatted before they reach a
//! template) and the templates hold the text around them. Undefined variables are errors,
//! so a template and its context cannot drift apart silently; `tests/cli/snapshots.rs` pins
//! the rendered bytes.
//!
//! Whitespace rules (minijinja's `trim_blocks` and `lstrip_blocks`): a line holding only a
//! `{% ... %}` tag leaves nothing in the output, and a template's final newline is kept.
use crate::error::{Error, Result};
use minijinja::syntax::SyntaxConfig;
use minijinja::{AutoEscape, Environment, UndefinedBehavior, Value};
use std::sync::OnceLock;

/// Every template, by its path under `rtl-templates/`.
const TEMPLATES: &[(&str, &str)] = &[
    ("header.j2", include_str!("../../rtl-templates/header.j2")),
    (
        "params.md.j2",
        include_str!("../../rtl-templates/params.md.j2"),
    ),
    (
        "flow/sinedec.core.j2",
        include_str!("../../rtl-templates/flow/sinedec.core.j2"),
    ),
    (
        "flow/inst.v.j2",
        include_str!("../../rtl-templates/flow/inst.v.j2"),
    ),
    (
        "flow/lint.vlt.j2",
        include_str!("../../rtl-templates/flow/lint.vlt.j2"),
    ),
    (
        "core/core_wrapper.v.j2",
        include_str!("../../rtl-templates/core/core_wrapper.v.j2"),
    ),
    (
        "tb/core_tb.v.j2",
        include_str!("../../rtl-templates/tb/core_tb.v.j2"),
    ),
    (
        "tb/top_tb.v.j2",
        include_str!("../../rtl-templates/tb/top_tb.v.j2"),
    ),
    (
        "top/sinewave_top.v.j2",
        include_str!("../../rtl-templates/top/sinewave_top.v.j2"),
    ),
    (
        "top/rst_sync.v.j2",
        include_str!("../../rtl-templates/top/rst_sync.v.j2"),
    ),
    (
        "top/capacitive_top.v.j2",
        include_str!("../../rtl-templates/top/capacitive_top.v.j2"),
    ),
    (
        "constraints/clock_comment.j2",
        include_str!("../../rtl-templates/constraints/clock_comment.j2"),
    ),
    (
        "constraints/top.ucf.j2",
        include_str!("../../rtl-templates/constraints/top.ucf.j2"),
    ),
    (
        "constraints/top.ut.j2",
        include_str!("../../rtl-templates/constraints/top.ut.j2"),
    ),
    (
        "constraints/top_ise.tcl.j2",
        include_str!("../../rtl-templates/constraints/top_ise.tcl.j2"),
    ),
    (
        "constraints/top.qpf.j2",
        include_str!("../../rtl-templates/constraints/top.qpf.j2"),
    ),
    (
        "constraints/top.qsf.j2",
        include_str!("../../rtl-templates/constraints/top.qsf.j2"),
    ),
    (
        "constraints/top.sdc.j2",
        include_str!("../../rtl-templates/constraints/top.sdc.j2"),
    ),
    (
        "constraints/top_io.j2",
        include_str!("../../rtl-templates/constraints/top_io.j2"),
    ),
    (
        "board/board.v.j2",
        include_str!("../../rtl-templates/board/board.v.j2"),
    ),
    (
        "board/clock_head.v.j2",
        include_str!("../../rtl-templates/board/clock_head.v.j2"),
    ),
    (
        "board/clock_dcm_sp.v.j2",
        include_str!("../../rtl-templates/board/clock_dcm_sp.v.j2"),
    ),
    (
        "board/clock_altpll.v.j2",
        include_str!("../../rtl-templates/board/clock_altpll.v.j2"),
    ),
    (
        "board/clock_sim.v.j2",
        include_str!("../../rtl-templates/board/clock_sim.v.j2"),
    ),
];

/// The environment holding [`TEMPLATES`], built once. A failed build is cached as text, the
/// one `Result<_, String>` kept on purpose: every later caller gets the same failure, and
/// [`render`] turns it into [`Error::Template`].
fn environment() -> &'static std::result::Result<Environment<'static>, String> {
    static ENV: OnceLock<std::result::Result<Environment<'static>, String>> = OnceLock::new();
    ENV.get_or_init(|| {
        let mut env = Environment::new();
        let syntax = SyntaxConfig::builder()
            .trim_blocks(true)
            .lstrip_blocks(true)
            .keep_trailing_newline(true)
            .build()
            .map_err(|e| format!("syntax: {e:#}"))?;
        env.set_syntax(syntax);
        env.set_undefined_behavior(UndefinedBehavior::Strict);
        env.set_auto_escape_callback(|_| AutoEscape::None);
        for (name, text) in TEMPLATES {
            env.add_template(name, text)
                .map_err(|e| format!("{name}: {e:#}"))?;
        }
        Ok(env)
    })
}

/// Renders the template `name` (its path under `rtl-templates/`) with `context`.
pub fn render(name: &str, context: Value) -> Result<String> {
    let err = |message: String| Error::Template {
        template: name.to_string(),
        message,
    };
    let env = environment().as_ref().map_err(|m| err(m.clone()))?;
    env.get_template(name)
        .and_then(|t| t.render(context))
        .map_err(|e| err(format!("{e:#}")))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_template_parses() {
        assert!(environment().is_ok(), "{:?}", environment().as_ref().err());
    }

    #[test]
    fn an_undefined_variable_is_an_error() {
        let e = render("constraints/top.ut.j2", minijinja::context! {}).map(|_| ());
        assert!(e.is_ok());
        let e = render("header.j2", minijinja::context! { c => "//" }).unwrap_err();
        assert!(e.to_string().contains("header.j2"), "{e}");
    }
}
