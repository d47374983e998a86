//! The chip model for a configuration's ADC preset: [`adc_chip_model`] returns the
//! LTC1407A-1, ADS8354, AD7380 or generic SPI ADC model behind the config's board pins,
//! each stepped the same way ([`AdcChipModel::step`]: the CONV / CS and SCK levels the
//! design drives, the levels its `adc_miso` / `adc_miso_b` registers read at the next
//! edge).
use super::adc_pins::PinTiming;
use super::cs_adc::CsAdc;
use super::ltc1407a::Ltc1407a;
use super::spi_adc::SpiAdc;
use crate::blocks::adc::AdcChip;
use crate::config::Derived;

/// Codes of channel 0 and 1 for conversion `k` started at `t` seconds: two's-complement
/// values in the ADC's width, as the controller delivers them.
pub type AdcCodeFn = Box<dyn FnMut(u64, f64) -> [i32; 2]>;

/// One of the chip models.
pub enum AdcChipModel {
    /// LTC1407A-1 (one data line).
    Ltc1407a(Box<Ltc1407a>),
    /// ADS8354 (SDO-A, SDO-B).
    Ads8354(Box<CsAdc>),
    /// AD7380 (SDOA, SDOB).
    Ad7380(Box<CsAdc>),
    /// A generic SPI ADC described by its frame, and the start clock of the last
    /// conversion [`AdcChipModel::take_conversion`] saw.
    Generic(Box<SpiAdc>, Option<usize>),
}

impl AdcChipModel {
    /// One system clock: `conv` (CONV or chip select) and `sck` as the design drives them
    /// at this edge; returns what `adc_miso` and `adc_miso_b` read at the next edge (line
    /// B is low for a one-line chip).
    pub fn step(&mut self, conv: bool, sck: bool) -> [bool; 2] {
        match self {
            AdcChipModel::Ltc1407a(m) => [m.step(conv, sck), false],
            AdcChipModel::Ads8354(m) | AdcChipModel::Ad7380(m) => m.step(conv, sck),
            AdcChipModel::Generic(m, _) => m.step_lines(conv, sck),
        }
    }

    /// A fault of the data lines at the FPGA's pads from now on (None: none): every line
    /// reads `level` (`sim::adc_pins::DataLine::stick`: SDO shorted, or broken with the
    /// input's pull resistor; on the two-line chips both lines, a connector fault).
    pub fn set_sdo_stuck(&mut self, level: Option<bool>) {
        match self {
            AdcChipModel::Ltc1407a(m) => m.set_sdo_stuck(level),
            AdcChipModel::Ads8354(m) | AdcChipModel::Ad7380(m) => m.set_sdo_stuck(level),
            AdcChipModel::Generic(m, _) => m.set_sdo_stuck(level),
        }
    }

    /// Whether a conversion started since the last call (then forgotten: a long run keeps
    /// no history).
    pub fn take_conversion(&mut self) -> bool {
        match self {
            AdcChipModel::Ltc1407a(m) => {
                let any = !m.conversions().is_empty();
                m.clear_conversions();
                any
            }
            AdcChipModel::Ads8354(m) | AdcChipModel::Ad7380(m) => {
                let any = !m.conversions().is_empty();
                m.clear_conversions();
                any
            }
            AdcChipModel::Generic(m, seen) => {
                let last = m.taken().last().map(|t| t.0);
                let new = last != *seen;
                *seen = last;
                m.forget_old();
                new
            }
        }
    }

    /// The protocol violations recorded so far, as messages (none for the generic model,
    /// which has no limits of its own).
    pub fn violation_messages(&self) -> Vec<String> {
        match self {
            AdcChipModel::Ltc1407a(m) => m
                .violations()
                .iter()
                .map(|v| format!("clock {}: {}", v.clock, v.message))
                .collect(),
            AdcChipModel::Ads8354(m) | AdcChipModel::Ad7380(m) => m
                .violations()
                .iter()
                .map(|v| format!("clock {}: {}", v.clock, v.message))
                .collect(),
            AdcChipModel::Generic(..) => Vec::new(),
        }
    }

    /// The number of protocol violations recorded so far (0 for the generic model, which
    /// has no limits of its own).
    pub fn violation_count(&self) -> usize {
        match self {
            AdcChipModel::Ltc1407a(m) => m.violations().len(),
            AdcChipModel::Ads8354(m) | AdcChipModel::Ad7380(m) => m.violations().len(),
            AdcChipModel::Generic(..) => 0,
        }
    }
}

/// The chip model for the preset of `d` (`adc.preset`), behind the board pins of `d`
/// (`[board]` budget of `check`), with random bits from `seed` and codes from `codes`.
pub fn adc_chip_model(d: &Derived, seed: u64, mut codes: AdcCodeFn) -> AdcChipModel {
    let pins = PinTiming::from_io(&d.io_timing);
    let clock_hz = d.adc.clock_hz;
    match d.adc.chip {
        AdcChip::Ltc1407a1 => AdcChipModel::Ltc1407a(Box::new(
            Ltc1407a::new(clock_hz, seed)
                .with_pins(pins)
                .with_codes(move |k, t| {
                    let c = codes(k, t);
                    [
                        c[0].clamp(-8192, 8191) as i16,
                        c[1].clamp(-8192, 8191) as i16,
                    ]
                }),
        )),
        AdcChip::Ads8354 => AdcChipModel::Ads8354(Box::new(
            super::ads8354::ads8354(clock_hz, seed)
                .with_pins(pins)
                .with_codes(codes),
        )),
        AdcChip::Ad7380 => AdcChipModel::Ad7380(Box::new(
            super::ad7380::ad7380(clock_hz, seed)
                .with_pins(pins)
                .with_codes(codes),
        )),
        AdcChip::Generic => {
            let period_s = 1.0 / clock_hz.max(1.0);
            let mut k = 0u64;
            AdcChipModel::Generic(
                Box::new(SpiAdc::new(
                    &d.adc,
                    pins,
                    Box::new(move |clock| {
                        let c = codes(k, clock as f64 * period_s);
                        k += 1;
                        c
                    }),
                )),
                None,
            )
        }
    }
}
