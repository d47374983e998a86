//! Pin-level model of the ADI AD7380 (dual simultaneous-sampling 16-bit SAR ADC, 4 Msps,
//! SDOA / SDOB) in 2-wire serial mode, written from its data sheet (ADI AD7380-7381) as
//! the Linux IIO driver `drivers/iio/adc/ad7380.c` and its device-tree binding quote it,
//! not from the controller in `blocks::adc`:
//!
//! * The CS falling edge samples both inputs and starts a conversion of tCONVERT = 190 ns
//!   (the driver's `T_CONVERT_NS`); the words a CS-low frame shifts out are those of the
//!   *previous* conversion (the driver triggers a conversion, waits tCONVERT, and reads
//!   it in the next frame). A CS falling edge before the running conversion ended leaves
//!   the next frame without valid data (recorded).
//! * SPI mode 3 (binding: `spi-cpol`, `spi-cpha`, 80 MHz): SCLK idles high, the chip
//!   launches each bit on a falling edge and the host reads it on the next rising edge;
//!   the MSB leaves on the first falling edge; 16 SCLK per frame (a shorter frame is
//!   recorded as aborted).
//! * Limits checked: SCLK period >= 12.5 ns (80 MHz); SCLK high and low >= 5.625 ns
//!   (not found: 0.45 tSCLK assumed); CS high >= 10 ns (the driver's `t_csh_ns`); CS
//!   falling to the first SCLK edge, and the last SCLK read (rising) edge to CS rising,
//!   at least 10 ns each (not found: assumed); CS falling edges 250 ns apart or more
//!   (4 Msps).
//! * Data valid 6.25 ns after the launching falling edge: not found; half the minimum
//!   SCLK period (the longest delay with which the part's own mode-3 read works); no
//!   hold assumed. Fully differential inputs, two's-complement codes.
use super::cs_adc::{CsAdc, CsAdcSpec};

/// The AD7380 as its data sheet gives it (see the module docs for the sources).
pub const AD7380: CsAdcSpec = CsAdcSpec {
    name: "AD7380",
    sclk_idle_high: true,
    launch_on_rising: false,
    msb_edge: 1,
    width: 16,
    frame_edges: 16,
    pipeline: 1,
    straight_binary: false,
    sclk_min_period_ns: 12.5,
    sclk_min_pulse_ns: 5.625,
    data_valid_ns: 6.25,
    data_hold_ns: 0.0,
    cs_min_high_ns: 10.0,
    cs_to_sclk_ns: 10.0,
    sclk_to_cs_ns: 10.0,
    conversion_ns: 190.0,
    cycle_min_ns: 250.0,
};

/// The AD7380 clocked by an FPGA at `clock_hz` (random bits from `seed`).
pub fn ad7380(clock_hz: f64, seed: u64) -> CsAdc {
    CsAdc::new(AD7380, clock_hz, seed)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::cs_adc::CsViolationKind;

    /// Two frames by hand at 200 MHz (the default board pins need 17.25 ns from launch to
    /// read: half = 4 clocks gives 20 ns): each CS low, 2 idle clocks, 16 SCLK cycles of
    /// `half` clocks high then `half` low, CS high for `gap` clocks. Returns the bits read
    /// on both lines at the rising edges (the host's read edge) of each frame.
    fn frames(half: usize, gap: usize, codes: Vec<[i32; 2]>) -> (Vec<Vec<[bool; 2]>>, CsAdc) {
        let mut k = 0;
        let mut chip = ad7380(200e6, 9).with_codes(move |_, _| {
            k += 1;
            codes[(k - 1) % codes.len()]
        });
        let mut out = vec![];
        for _ in 0..20 {
            chip.step(true, true);
        }
        for _ in 0..2 {
            let mut reads = vec![];
            let mut got = chip.step(false, true);
            for _ in 0..2 {
                got = chip.step(false, true);
            }
            for _ in 0..16 {
                for _ in 0..half {
                    got = chip.step(false, false);
                }
                // Rising edge: the host reads now.
                reads.push(got);
                for _ in 0..half {
                    got = chip.step(false, true);
                }
            }
            for _ in 0..3 {
                chip.step(false, true);
            }
            for _ in 0..gap {
                chip.step(true, true);
            }
            out.push(reads);
        }
        (out, chip)
    }

    fn word(reads: &[[bool; 2]], line: usize) -> i16 {
        reads.iter().fold(0u16, |w, r| (w << 1) | r[line] as u16) as i16
    }

    #[test]
    fn the_second_frame_returns_the_first_conversion() {
        let (f, chip) = frames(4, 40, vec![[-32768, 32767], [5, -6]]);
        assert!(chip.violations().is_empty(), "{:?}", chip.violations());
        assert_eq!([word(&f[1], 0), word(&f[1], 1)], [-32768, 32767]);
        assert_eq!(chip.conversions()[0].codes, [-32768, 32767]);
    }

    #[test]
    fn a_too_fast_sclk_and_a_too_early_frame_are_recorded() {
        // SCLK of 2 x 5 ns = 10 ns < 12.5 ns; CS falling edges 3 + 32 + 3 + 2 = 40 clocks
        // = 200 ns apart: tCONVERT (190 ns) is met, the 250 ns cycle is not.
        let (_, chip) = frames(1, 2, vec![[1234, -4321]]);
        let kinds: Vec<_> = chip.violations().iter().map(|v| v.kind).collect();
        assert!(kinds.contains(&CsViolationKind::SclkTooFast), "{kinds:?}");
        assert!(kinds.contains(&CsViolationKind::CycleTooShort), "{kinds:?}");
        // A frame started before the previous conversion's 190 ns: its data are garbage.
        let mut chip = ad7380(200e6, 4).with_codes(|_, _| [1, 2]);
        chip.step(true, true);
        chip.step(false, true);
        for _ in 0..4 {
            chip.step(true, true);
        }
        chip.step(false, true);
        let kinds: Vec<_> = chip.violations().iter().map(|v| v.kind).collect();
        assert!(
            kinds.contains(&CsViolationKind::ConversionNotDone),
            "{kinds:?}"
        );
    }
}
