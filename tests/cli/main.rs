//! The command line and the config: errors with line and column, the output-directory rule and
//! its robustness, no panic on any input, `[board]` files, snapshots of the emitted files.
//!
//! One test binary per area (`cargo test --test cli`; `-- <module>::` narrows it to one
//! file).
mod board_util;
#[path = "../common/mod.rs"]
mod common;
mod config_errors_util;
mod output_safety_util;

mod board;
mod board_clock_pins;
mod cli;
mod config_blame;
mod config_errors;
mod config_ranges;
mod config_scope;
mod config_wording;
mod io_constraints;
mod no_panic;
mod output_robustness;
mod output_safety;
mod signals;
mod simulate_options;
mod snapshots;
