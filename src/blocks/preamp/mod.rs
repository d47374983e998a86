//! LTC6912-1 programmable pre-amplifier set-up over the Starter Kit's shared SPI bus, and
//! the hand-over of the shared SPI_SCK line to the ADC controller.
//!
//! After reset [`hdl::PreampSetup`] shifts one 8-bit gain word into the LTC6912-1 (MSB
//! first: the channel B nibble, then the channel A nibble; UG334 Figure 9-3 and the
//! LTC6912 datasheet: "the upper nibble configures the B-channel, the lower nibble the
//! A-channel"), raises `done`, and from then on passes the ADC controller's SCK to the
//! shared SPI_SCK pin. Amplifier A feeds ADC channel 0 (VINA), B feeds channel 1 (VINB).
//!
//! # Transfer (one step = `half_period_clocks` system clocks, >= 50 ns)
//!
//! ```text
//! step      0 | 1  | 2  | 3  | 4  | ... | 15 | 16 | 17 | 18 | 19 ...
//! AMP_CS  ‾‾‾‾‾\____________________________________________/‾‾‾‾‾‾‾‾‾‾‾
//! SPI_SCK ___________/‾‾‾\____/‾‾‾\__ ... ____/‾‾‾\_____________ (ADC's SCK)
//! SPI_MOSI ----< B3      >< B2      > ... < A0           >---- 0 --------
//! done    ________________________________________________________/‾‾‾‾
//!                  ^ the LTC6912 shifts DIN in on each rising SCK edge
//! ```
//!
//! * Step 1: CS falls with SCK low (an SCK high at the CS fall would clock an extra bit,
//!   LTC6912 datasheet) and MOSI = bit 7; CS-to-SCK set-up = 1 step >= 30 ns (UG334 Figure
//!   9-4). Steps 2k+2 (k = 0..7) hold SCK high, steps 2k+1 low; MOSI changes only when
//!   SCK falls, so set-up and hold are one step each (>= 50 ns, above the 30 ns set-up).
//! * Step 17 keeps SCK low and CS low (SCK-to-CS hold), step 18 raises CS (the LTC6912
//!   latches the word on the rising CS edge), step 19 raises `done` (CS high >= 1 step).
//! * SCK = f_clk / (2 * half_period_clocks): 9.52 MHz at 133.33 MHz (7 clocks),
//!   8.33 MHz at 50 MHz (3 clocks), below the amplifier's ~10 MHz.
//! * `done` rises 19 * half_period_clocks - 1 clocks after the first clock out of reset
//!   (132 clocks = 0.99 us at 133.33 MHz; 56 clocks = 1.12 us at 50 MHz).
//!
//! # SCK sharing
//!
//! The kit has one SPI_SCK pin for the amplifier and the ADC (and the DAC and SPI flash).
//! The block owns it: `spi_sck` = the set-up SCK until `done`, then the `adc_sck` input
//! (a 2:1 mux selected by the registered `done`; both sources are registered and both are
//! low at the switch, so there is no glitch). The top wires
//! `adc.enable = preamp.done`, `preamp.adc_sck = adc.adc_sck`, SPI_SCK = `preamp.spi_sck`.
//! Once `done`, AMP_CS stays high, so the ADC's SCK edges do not reach the amplifier.
//!
//! # Other devices on the bus (UG334)
//!
//! SPI_MOSI and SPI_SCK also reach the LTC2624 DAC and the SPI serial flash; each device
//! has its own data-out pin (AD_DOUT, AMP_DOUT, DAC_OUT), so they only need to stay
//! deselected: DAC_CS high, DAC_CLR high (no clear), SPI_SS_B high; AMP_SHDN low (the
//! amplifier is on; high is its hardware shutdown); SF_CE0 high keeps the parallel flash
//! off the shared lines as in the kit's reference designs.
//!
//! # Ports of [`hdl::PreampSetup`]
//!
//! ```text
//! clk       in   system clock
//! rst       in   synchronous reset, active high: restarts the set-up (done low)
//! adc_sck   in   the ADC controller's SCK, passed to spi_sck once done
//! spi_sck   out  shared SPI_SCK pin
//! spi_mosi  out  shared SPI_MOSI pin (0 when idle)
//! amp_cs    out  AMP_CS, active low
//! amp_shdn  out  AMP_SHDN, constant 0 (amplifier on)
//! dac_cs    out  DAC_CS, constant 1 (DAC deselected)
//! dac_clr   out  DAC_CLR, constant 1 (no DAC clear)
//! spi_ss_b  out  SPI_SS_B, constant 1 (SPI flash deselected)
//! sf_ce0    out  SF_CE0, constant 1 (parallel flash disabled)
//! done      out  high once the gains are latched: enables the ADC controller
//! ```
pub mod hdl;

/// Gains of the LTC6912-1 the set-up accepts (inverting, V/V).
pub const GAINS: [i32; 7] = [-1, -2, -5, -10, -20, -50, -100];

/// UG334 Figure 9-4 / LTC6912 timing used by the set-up and checked by the chip model.
pub mod timing {
    /// Minimum SCK high and low time (ns): about 10 MHz.
    pub const SCK_MIN_PULSE_NS: f64 = 50.0;
    /// Minimum AMP_CS fall to first rising SCK (ns).
    pub const CS_SETUP_NS: f64 = 30.0;
    /// Minimum SPI_MOSI set-up before a rising SCK (ns).
    pub const DATA_SETUP_NS: f64 = 30.0;
    /// Minimum SPI_MOSI hold after a rising SCK (ns) (assumed, not in UG334).
    pub const DATA_HOLD_NS: f64 = 10.0;
    /// Minimum last rising SCK to AMP_CS rise (ns).
    pub const CS_HOLD_NS: f64 = 30.0;
}

/// 4-bit LTC6912-1 gain code for a gain in [`GAINS`].
pub fn gain_code(gain: i32) -> Option<u8> {
    GAINS.iter().position(|&g| g == gain).map(|i| i as u8 + 1)
}

/// Gain of a 4-bit LTC6912-1 code: 0 for code 0 (input disconnected), the inverting gain
/// for codes 1..=7, None for 8..=15 (shutdown states).
pub fn code_gain(code: u8) -> Option<i32> {
    match code {
        0 => Some(0),
        1..=7 => Some(GAINS[code as usize - 1]),
        _ => None,
    }
}

/// Parameters of the pre-amplifier set-up.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PreampParams {
    /// System clock in Hz.
    pub clock_hz: f64,
    /// Gain of amplifier A (ADC channel 0), one of [`GAINS`].
    pub gain_a: i32,
    /// Gain of amplifier B (ADC channel 1), one of [`GAINS`].
    pub gain_b: i32,
    /// SCK half period in system clocks.
    pub half_period_clocks: u32,
}

fn check_gain(name: &str, g: i32) -> crate::error::Result<u8> {
    gain_code(g).ok_or_else(|| {
        invalid(format!(
            "preamp gain {name} = {g} is not an LTC6912-1 gain; allowed: {}",
            GAINS
                .iter()
                .map(|g| g.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ))
    })
}

/// [`crate::error::Error::BlockParams`] for this block: `message` says what is wrong and what
/// is allowed.
fn invalid(message: String) -> crate::error::Error {
    crate::error::Error::block_params("preamp", message)
}

impl PreampParams {
    /// Gains for amplifiers A and B (each in [`GAINS`]) at `clock_hz`, with the fastest
    /// SCK the amplifier allows (half period >= 50 ns).
    pub fn new(clock_hz: f64, gain_a: i32, gain_b: i32) -> crate::error::Result<Self> {
        if !(clock_hz.is_finite() && clock_hz > 0.0) {
            return Err(invalid(format!(
                "clock {clock_hz} Hz is not a positive frequency"
            )));
        }
        check_gain("A", gain_a)?;
        check_gain("B", gain_b)?;
        let half = ((timing::SCK_MIN_PULSE_NS * clock_hz / 1e9) - 1e-9)
            .ceil()
            .max(1.0) as u32;
        let p = PreampParams {
            clock_hz,
            gain_a,
            gain_b,
            half_period_clocks: half,
        };
        p.validate()?;
        Ok(p)
    }

    /// The same with a slower SCK of at most `sck_hz`.
    pub fn with_max_sck_hz(mut self, sck_hz: f64) -> crate::error::Result<Self> {
        if !(sck_hz.is_finite() && sck_hz > 0.0) {
            return Err(invalid(format!(
                "preamp SCK {sck_hz} Hz is not a positive frequency"
            )));
        }
        let half = (self.clock_hz / (2.0 * sck_hz) - 1e-9).ceil().max(1.0) as u32;
        self.half_period_clocks = self.half_period_clocks.max(half);
        self.validate()?;
        Ok(self)
    }

    /// Checks gains and timing.
    pub fn validate(&self) -> crate::error::Result<()> {
        check_gain("A", self.gain_a)?;
        check_gain("B", self.gain_b)?;
        let step_ns = self.half_period_clocks as f64 * 1e9 / self.clock_hz;
        if step_ns + 1e-9 < timing::SCK_MIN_PULSE_NS {
            return Err(invalid(format!(
                "preamp SCK half period {step_ns:.1} ns is below the LTC6912 minimum of {} ns (about 10 MHz)",
                timing::SCK_MIN_PULSE_NS
            )));
        }
        if !(1..=255).contains(&self.half_period_clocks) {
            return Err(invalid(format!(
                "preamp SCK half period of {} clocks: 1..=255 are supported",
                self.half_period_clocks
            )));
        }
        Ok(())
    }

    /// The 8-bit word: channel B code in the upper nibble (sent first), A in the lower.
    pub fn word(&self) -> u8 {
        let a = gain_code(self.gain_a).unwrap_or(0);
        let b = gain_code(self.gain_b).unwrap_or(0);
        (b << 4) | a
    }

    /// SCK frequency in Hz.
    pub fn sck_hz(&self) -> f64 {
        self.clock_hz / (2.0 * self.half_period_clocks as f64)
    }

    /// Clocks from the first clock out of reset to `done` (the row index at which `done`
    /// is first high when row 0 is the first row with reset low).
    pub fn done_clocks(&self) -> u32 {
        hdl::STEP_DONE * self.half_period_clocks - 1
    }
}

/// The block's entry in the registry (`crate::blocks::registry`).
pub const BLOCK: crate::blocks::registry::BlockDef = crate::blocks::registry::BlockDef::report_only(
    "preamp",
    "pre-amp set-up",
    crate::report::jobs::preamp_job,
);
