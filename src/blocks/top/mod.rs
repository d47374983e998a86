//! `<name>_top` for the sinewave path on the Spartan-3AN Starter Kit: pre-amplifier set-up,
//! SPI ADC controller, decoder core, and the drive-side outputs.
//!
//! ```text
//!            ┌─────────┐ done  ┌───────────────┐ ch0=sin ┌────────┐ position ┌──────────┐
//! SPI_SCK ◄──┤ preamp  ├──────►│ ADC controller├────────►│  core  ├─────────►│ parallel │─► par_*
//! SPI_MOSI◄──┤ set-up  │◄──────┤ (LTC1407A-1)  │ ch1=cos │ CORDIC │ turns    │ bus      │
//! AMP_CS  ◄──┤ LTC6912 │adc_sck└──┬─────────▲──┘ valid   │ counter│ flags    └──────────┘
//!            └─────────┘  AD_CONV ◄┘ AD_DOUT ┘           └────────┘
//! ```
//!
//! * At reset the preamp block shifts the LTC6912-1 gain word out on the shared SPI bus
//!   (holding the kit's other SPI devices disabled) and then hands SPI_SCK to the ADC
//!   controller, which converts continuously; each sample pair goes to the core.
//! * The LTC6912-1 inverts (gains -1..-100): the ADC codes are -(v_sin - 1.65 V) and
//!   -(v_cos - 1.65 V) scaled, i.e. the vector is turned by exactly pi. The position is
//!   therefore offset by a constant two quadrants from the encoder's electrical angle;
//!   direction and resolution are unchanged (an incremental position has no absolute zero).
//! * Latency from the CONV edge that samples the inputs to `par_valid`: the ADC's
//!   CONV-to-`out_valid` latency plus the core's N + 2 cycles.
pub mod hdl;
pub mod ports;

/// The block's entry in the registry (`crate::blocks::registry`).
pub const BLOCK: crate::blocks::registry::BlockDef = crate::blocks::registry::BlockDef::report_only(
    "top",
    "whole top",
    crate::report::jobs::top_job,
);
