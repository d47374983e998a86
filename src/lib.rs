//! sinedec: generator of verified Verilog for a sine/cosine encoder decoder.
#[path = "../sim/mod.rs"]
pub mod sim;
pub mod config;
pub mod error;
pub mod exact;
pub mod blocks;
pub mod emit;
pub mod verify;
pub mod synth;
