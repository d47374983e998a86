//! Whole tops in closed loop: the encoder, ADC and master models around `<name>_top`,
//! `simulate` on both engines, the compiled engine itself.
//!
//! One test binary per area (`cargo test --test system`; `-- <module>::` narrows it to one
//! file).
#[path = "../common/mod.rs"]
mod common;

mod absolute_top;
mod abz_top;
mod capture_top;
mod correction_fit_loop;
mod e2e;
mod engine;
mod engine_loop;
mod harmonics_learn_top;
mod harmonics_top;
mod outputs_top;
mod reference_top;
mod registers_biss;
mod registers_top;
mod simulate_engine;
mod simulate_outputs;
mod simulate_truth;
mod status_faults;
mod system;
mod top_reset;
mod velocity_top;
