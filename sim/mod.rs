//! Simulation support: co-simulation in Icarus Verilog and Verilator, hand-stepping of
//! rust-hdl designs, encoder, ADC and amplifier models, stimulus.
pub mod biss_master;
pub mod cap_system;
pub mod capacitive;
pub mod cosim;
pub mod encoder;
pub mod ltc1407a;
pub mod ltc6912;
pub mod spi_adc;
pub mod ssi_master;
pub mod step;
pub mod stimulus;
pub mod system;
pub mod vcd;
