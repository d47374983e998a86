//! `<name>_top` for the capacitive path (target `cyclone3`, docs/capacitive.md): SPI ADC controller
//! (one channel), capacitive front end (NCO, band-pass, demodulation, low-pass), the
//! full-circle QEP-CORDIC core and the drive-side outputs (BiSS-C, parallel bus).
//!
//! ```text
//!  exc_sin/cos ◄──────────── NCO ◄── tick ──┐
//!  exc_strobe                               │
//!            ┌───────────────┐ sample ┌─────┴──────────┐ I, Q ┌────────┐ position ┌──────┐
//! adc_miso ─►│ ADC controller├───────►│ front end      ├─────►│  core  ├─────────►│ BiSS │─► biss_slo
//! adc_sck  ◄─┤ (generic, 1ch)│ valid  │ BP, demod, LP  │      │ CORDIC │          ├──────┤
//! adc_conv ◄─┘               │        └────────────────┘      │ counter│          │ par_*│
//!            └───────────────┘                                └────────┘          └──────┘
//! ```
//!
//! Flags: `par_error` = the core's error (magnitude below `monitor.min_amplitude`, e.g. a
//! lost receiver signal) OR a filter/demodulator saturation of the last sample; `par_warning`
//! = the core's warning (a jump of two quadrants) OR a sample lost because the engine was
//! busy. The position counts `encoder.ppr` signal periods per turn, 2^(F+2) per period.
pub mod hdl;
