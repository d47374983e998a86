//! Outputs to the drive: the BiSS-C slave and its control channel, SSI, the SPI slave, the
//! parallel bus, ABZ emulation and the velocity estimator.
//!
//! One test binary per area (`cargo test --test outputs`; `-- <module>::` narrows it to one
//! file).
mod biss_loop;
#[path = "../common/mod.rs"]
mod common;

mod absolute_config;
mod abz;
mod abz_config;
mod biss;
mod biss_control;
mod biss_corners;
mod capture_config;
mod parallel;
mod reference_config;
mod registers_config;
mod spi_slave;
mod ssi;
mod velocity;
mod velocity_config;
mod velocity_core;
mod velocity_lag;
mod velocity_synth;
mod velocity_table;
