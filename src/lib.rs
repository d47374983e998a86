//! sinedec: generator of verified Verilog for a sine/cosine encoder decoder.
pub mod blocks;
pub mod board;
pub mod cleanup;
pub mod config;
pub mod cosim;
pub mod csv_out;
pub mod emit;
pub mod engine;
pub mod error;
pub mod exact;
pub mod filter;
pub mod report;
#[path = "../sim/mod.rs"]
pub mod sim;
pub mod simulate;
pub mod synth;
pub mod verify;
