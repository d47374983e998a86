//! SPI ADC controller: drives CONV and SCK of a simultaneous-sampling serial ADC, shifts in
//! one frame per conversion and delivers the samples with a one-clock strobe.
//!
//! Two presets build an [`AdcParams`]: [`AdcParams::ltc1407a`] (the LTC1407A-1 of the
//! Spartan-3A/3AN Starter Kit) and [`AdcParams::generic`] (any SPI ADC described by frame
//! length, channels, bit offsets, width, sign format, CPOL/CPHA). The rust-hdl block is
//! [`hdl::AdcController`]; [`model::AdcModel`] is a plain-Rust model of the same registers.
//!
//! # LTC1407A-1 frame (preset `ltc1407a-1`, D = 3 system clocks per SCK shown)
//!
//! ```text
//! pc (clk)   0  1  2  3  4  5  6  7  8     ...    96 97 98 99 100 101 | 0  1  2
//! CONV     __/‾‾\_______________________   ...   ______________________/‾‾\____
//! SCK      ______/‾\__/‾\__/‾\__/‾\__/‾\   ...   /‾\__/‾\__/‾\__/‾\____/‾\__/‾\
//! SCK cycle  |  0  |  1  |  2  |  3  |     ...   | 31  | 32  | 33  |  0  |  1 ...
//! SDO      ---- Z --|-- Z --|D13 (ch0)|D12 ... D0|Z|Z|D13 (ch1) ... D0 | Z | Z |
//!                      slots: 0,1 idle | 2..15 ch0 | 16,17 idle | 18..31 ch1 | 32,33 idle
//! capture           ^ slot k is sampled (input register miso_d) at the clock edge that
//!                     launches the rising SCK edge of cycle k+1: D clocks after the edge
//!                     that shifted it out (`AdcParams::capture_distance_clocks`)
//! ```
//!
//! The pc row is the controller's state; every pin is a register loaded one clock after
//! its state is entered ([`PIN_LAG_CLOCKS`]), so the pins above show one clock later than
//! pc. `miso_d` samples `adc_miso` at the edge that moves the capture state's pins
//! ([`MISO_SAMPLE_LAG_CLOCKS`]); the registered capture enables shift that bit in, and
//! raise `out_valid` for the last one, one clock later:
//!
//! ```text
//! edge            e      e+1             e+D     e+D+1                e+D+2
//! state entered   S_k    .               S_cap   .                    .
//! adc_sck pin     .      shifts slot k   .       next shifting edge   .
//! miso_d          .      .               .       samples slot k       .
//! sr, out_valid   .      .               .       .                    slot k shifted in
//! ```
//!
//! * The chip samples both inputs on the rising CONV edge and converts during the next 32
//!   SCK rising edges (CONV edges are ignored until then). The data shifted out in a frame
//!   are those of the *previous* conversion (datasheet pin function of SDO), so the
//!   controller runs one flush frame (SCK without CONV, which completes any conversion left
//!   running by a reset) and discards the first `pipeline` frames after reset or enable:
//!   every sample delivered belongs to a CONV edge this controller issued.
//! * SDO changes after each rising SCK edge (new bit valid within t8 = 8 ns, old bit held
//!   for t10 = 2 ns). Sampling D clocks after the system clock edge that moves the SCK
//!   pin, at the edge that launches the next rising SCK edge, leaves the whole SCK period
//!   for the round trip: D*T >= t_co + 2 t_trace + t8 + t_su (`crate::board`, printed by
//!   `check`: 22.50 ns against 19.00 ns at the kit defaults, slack 3.50 ns), and
//!   t_co + 2 t_trace + t10 of hold, so odd dividers work: D = 3 at 133.33 MHz is
//!   SCK = 44.4 MHz (22.5 ns >= tSCK,min = 19.6 ns).
//!
//! # Timing maths (T = 1/f_clk, D = SCK period, H = high clocks, L = D - H low clocks)
//!
//! * SCK cycle j (0-based) occupies pc = lead + j*D .. lead + (j+1)*D - 1: idle level (CPOL)
//!   for L clocks, then the active level for H clocks. Leading edge at lead + j*D + L,
//!   trailing edge at lead + (j+1)*D.
//! * Slot k (the k-th bit of the frame) has its capture state at pc = lead + (k+1)*D + c
//!   with c = L for CPHA = 1 (the slave shifts on leading edges) and c = 0 for CPHA = 0 (it
//!   shifts on trailing edges): in both cases one full SCK period after the shifting state.
//!   Capture distance C = (capture state + [`MISO_SAMPLE_LAG_CLOCKS`]) - (shifting state +
//!   [`PIN_LAG_CLOCKS`]) = D clocks from the SCK pin edge to the `adc_miso` sample.
//! * CONV (or chip select) is active for pc = 0 .. conv_clocks - 1 of every period of P
//!   clocks. Sample rate per channel = f_clk / P.
//! * Latency from the CONV edge that samples the inputs (first clock it is active) to the
//!   `out_valid` strobe carrying that sample: pipeline*P + lead + (s_last+1)*D + c + 1
//!   clocks, where s_last is the last slot holding a data bit (+ 1: the bit is shifted in
//!   one clock after it is sampled). LTC1407A-1 at D = 3, P = 102: 102 + 32*3 + 2 + 1 =
//!   201 clocks (1.51 us at 133.33 MHz).
//! * Checks (see [`AdcParams::validate`]): D*T >= tSCK,min; H*T, L*T >= SCK pulse minimum;
//!   D*T >= SDO valid delay; conv_clocks*T >= CONV pulse minimum and the inactive part of
//!   the period >= CONV low minimum; (lead + L)*T >= CONV-to-SCK set-up; the time from the
//!   rising edge that ends the conversion to the next CONV >= acquisition minimum;
//!   P >= lead + frame*D; P <= 65535; f_clk / P <= the chip's per-channel rate.
//!
//! | f_clk | D | SCK | P (clocks) | rate per channel | latency |
//! |---|---|---|---|---|---|
//! | 133.33 MHz | 3 | 44.4 MHz | 102 | 1.307 Msps | 201 clk = 1.51 us |
//! | 50 MHz | 2 | 25 MHz | 68 | 735 ksps | 134 clk = 2.68 us |
//!
//! # Ports of [`hdl::AdcController`]
//!
//! ```text
//! clk       in   system clock
//! rst       in   synchronous reset, active high: pins idle, counters cleared
//! enable    in   run; low = idle like reset (held low until the preamp set-up is done)
//! adc_miso  in   serial data from the ADC (SDO / AD_DOUT)
//! adc_sck   out  serial clock to the ADC (idle at CPOL)
//! adc_conv  out  CONV pulse (LTC1407A-1) or chip select (generic, polarity configurable)
//! out_valid out  one-clock strobe: out_ch0/out_ch1 hold a new sample pair
//! out_ch0   out  Bits<16>: channel 0, W-bit two's complement in the low bits, upper 0
//! out_ch1   out  Bits<16>: channel 1 (0 with one channel)
//! frame_error_0 out  frame check (`with_frame_check` only, `[registers] enabled`): the last
//!           delivered frame had every data line stuck ([`frame_check`]), with out_valid
//! ```
//!
//! # Frame check
//! With the register map the controller also checks every delivered frame for a stuck data
//! line (STATUS.ADC_FRAME); the rule, per chip, is in [`frame_check`]. It is a separate
//! sub-block ([`hdl::FrameChecker`]) that exists only then, so a design without the
//! register map has none of its logic.
mod chips;
pub mod frame_check;
pub mod hdl;
pub mod model;
mod params;
mod validate;

pub use frame_check::FrameCheck;
pub use params::*;

/// The block's entry in the registry (`crate::blocks::registry`).
pub const BLOCK: crate::blocks::registry::BlockDef = crate::blocks::registry::BlockDef::report_only(
    "adc",
    "ADC controller",
    crate::report::jobs::adc_job,
);
