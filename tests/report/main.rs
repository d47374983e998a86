//! `sinedec report`: the sweep, the tables and plots, the per-block rows, missing tools.
//!
//! One test binary per area (`cargo test --test report`; `-- <module>::` narrows it to one
//! file).
#[path = "../common/mod.rs"]
mod common;
mod report_util;

mod datasheet;
mod report;
mod report_blocks;
