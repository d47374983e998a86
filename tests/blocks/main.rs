//! Blocks of the sinewave path, each against its model and in rust-hdl, Icarus and Verilator:
//! the SPI ADC controller, the pre-amplifier set-up, the correction (static, peak, auto fit),
//! the monitor, the QEP decoder, the core (CORDIC, quadrant counter) and its iterative
//! architecture.
//!
//! One test binary per area (`cargo test --test blocks`; `-- <module>::` narrows it to one
//! file).
mod adc_util;
#[path = "../common/mod.rs"]
mod common;
mod correction_util;

mod absolute;
mod accuracy;
mod adc;
mod adc_closed_loop;
mod adc_frame;
mod capture;
mod core_behaviour;
mod core_sweep;
mod correction;
mod correction_auto;
mod correction_codes;
mod correction_fit;
mod correction_fit_config;
mod correction_fit_rtl;
mod correction_fit_solver;
mod correction_phase;
mod cosim_core;
mod cosim_harness;
mod cosim_stage;
mod counter_load;
mod harmonics;
mod harmonics_config;
mod harmonics_learn;
mod harmonics_learner;
mod harmonics_ram;
mod iterative;
mod monitor;
mod preamp;
mod qep;
mod reference;
mod regmap;
mod regmap_harmonics;
mod rtl_vs_model;
