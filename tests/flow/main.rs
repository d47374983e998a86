//! The emitted files in the tools users run: Verilator lint, the self-checking testbench,
//! FuseSoC, Yosys synthesis for both families.
//!
//! One test binary per area (`cargo test --test flow`; `-- <module>::` narrows it to one
//! file).
#[path = "../common/mod.rs"]
mod common;

mod flow;
mod lint;
mod synth;
mod testbench;
