//! The capacitive path: filter design, the NCO, the time-multiplexed biquad engine, the front
//! end and `cap_top`.
//!
//! One test binary per area (`cargo test --test capacitive`; `-- <module>::` narrows it to one
//! file).
mod biquad_util;
#[path = "../common/mod.rs"]
mod common;

mod biquad;
mod biquad_cosim;
mod capacitive;
mod capacitive_model;
mod filter_design;
mod nco;
