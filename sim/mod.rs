//! Simulation support: co-simulation in Icarus Verilog and Verilator, hand-stepping of
//! rust-hdl designs, and (later) encoder, ADC and BiSS master models.
pub mod cosim;
pub mod step;
pub mod stimulus;
