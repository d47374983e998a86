//! The simulation side of sinedec: closed-loop systems stepped cycle by cycle (`system`,
//! `cap_system`), the chip and encoder models they close the loop with (LTC1407A-1,
//! ADS8354, AD7380, LTC6912-1, a generic SPI ADC, the sine/cosine and capacitive encoders and the encoder's SSI digital channel, the BiSS-C and
//! SSI masters on one master core, `serial_master`, and the SPI master, all three over the
//! line model `serial_line`) and the VCD of the top's pins.
//!
//! Dependencies run one way: `sim` uses the blocks (their rtl and models) and
//! [`crate::cosim`] (hand-stepping, stimulus generators, port descriptions); nothing in the
//! library's core (errors, emit, synth, report, blocks, verify) uses `sim`. Only the
//! `simulate` command and the tests do.
//!
//! `sim/` is a module of the `sinedec` crate (included from `src/lib.rs` with `#[path]`), not
//! a workspace crate: the `simulate` command in the library runs its closed loops, and its
//! models use the blocks' Params and rtl, so a separate crate would either depend on
//! `sinedec` while `sinedec` depends on it (a cycle Cargo rejects) or force the `simulate`
//! command out of the library. The one-way rule above is what keeps it separable.
pub mod ad7380;
pub mod adc_chip;
pub mod adc_pins;
pub mod ads8354;
pub mod biss_control;
pub mod biss_master;
pub mod cap_system;
pub mod capacitive;
pub mod cs_adc;
pub mod dut;
pub mod encoder;
pub mod ltc1407a;
pub mod ltc6912;
pub mod serial_line;
pub mod serial_master;
pub mod spi_adc;
pub mod spi_master;
pub mod ssi_encoder;
pub mod ssi_master;
pub mod system;
pub mod vcd;
pub mod velocity_table;
