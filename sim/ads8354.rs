//! Pin-level model of the TI ADS8354 (dual simultaneous-sampling 16-bit SAR ADC, 700 ksps,
//! SDO-A / SDO-B) in its 32-CLK, dual-SDO mode, written from the data sheets, not from the
//! controller in `blocks::adc`. The ADS8354's own tables could not be consulted; its
//! interface is that of the ADS8353-Q1 (TI SBAS931B), whose figures are used, each the
//! conservative side:
//!
//! * The CS falling edge samples both inputs; the conversion runs on the internal clock
//!   and "is completed during the first 16 periods of SCLK" (SBAS931B 7.5.3.2), within
//!   tCONV = 730 ns (6.6 Timing Requirements). SDO-A and SDO-B then shift out *this*
//!   conversion's words, MSB first, from the 16th SCLK launch (rising) edge; the host reads
//!   on falling edges. SCLK idles high (the first edge after CS falls is a falling one:
//!   tSU_CSCK is "CS falling edge to SCLK falling edge").
//! * A frame is 32 SCLK cycles ("minimum SCLK falling edges N = 32", 7.5.3.2 table); CS
//!   rising earlier aborts it (recorded).
//! * Limits checked (6.6): tCLK >= 50 ns (fCLK <= 20 MHz), tPH_CK and tPL_CK >= 0.4 tCLK
//!   (20 ns at 50 ns), tPH_CS >= 40 ns, tSU_CSCK >= 15 ns, tD_CKCS (last SCLK falling to CS
//!   rising) >= 15 ns, 700 ksps (the ADS8354's rate: CS falling edges >= 1428.6 ns apart).
//! * Data valid 25 ns after the launching rising edge: tD_CKDO not found; half the
//!   minimum SCLK period (the longest delay with which the part's own falling-edge read
//!   works); no hold assumed. Unipolar inputs, straight-binary codes.
use super::cs_adc::{CsAdc, CsAdcSpec};

/// The ADS8354 as its data sheets give it (see the module docs for the sources).
pub const ADS8354: CsAdcSpec = CsAdcSpec {
    name: "ADS8354",
    sclk_idle_high: true,
    launch_on_rising: true,
    msb_edge: 16,
    width: 16,
    frame_edges: 32,
    pipeline: 0,
    straight_binary: true,
    sclk_min_period_ns: 50.0,
    sclk_min_pulse_ns: 20.0,
    data_valid_ns: 25.0,
    data_hold_ns: 0.0,
    cs_min_high_ns: 40.0,
    cs_to_sclk_ns: 15.0,
    sclk_to_cs_ns: 15.0,
    conversion_ns: 730.0,
    cycle_min_ns: 1e9 / 700e3,
};

/// The ADS8354 clocked by an FPGA at `clock_hz` (random bits from `seed`).
pub fn ads8354(clock_hz: f64, seed: u64) -> CsAdc {
    CsAdc::new(ADS8354, clock_hz, seed)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::cs_adc::CsViolationKind;

    /// Drives one frame by hand at 100 MHz (the default board pins need 36 ns from launch
    /// to read: half = 4 clocks gives 40 ns): CS low, 3 idle clocks, 32 SCLK cycles of
    /// `half` clocks low and `half` high, CS high; returns the bits read on both lines at
    /// each falling edge (the host's read edge) and the chip.
    fn frame(half: usize, codes: [i32; 2]) -> (Vec<[bool; 2]>, CsAdc) {
        let mut chip = ads8354(100e6, 3).with_codes(move |_, _| codes);
        let mut reads = vec![];
        // Idle, then CS falls.
        for _ in 0..10 {
            chip.step(true, true);
        }
        let mut got = chip.step(false, true);
        for _ in 0..3 {
            got = chip.step(false, true);
        }
        for _ in 0..32 {
            // Falling edge: the host reads what the line carries now.
            reads.push(got);
            for _ in 0..half {
                got = chip.step(false, false);
            }
            for _ in 0..half {
                got = chip.step(false, true);
            }
        }
        for _ in 0..3 {
            chip.step(false, true);
        }
        for _ in 0..10 {
            chip.step(true, true);
        }
        (reads, chip)
    }

    fn word(reads: &[[bool; 2]], line: usize) -> u16 {
        // The MSB leaves on the 16th rising edge and is read at the 17th falling edge.
        reads[16..32]
            .iter()
            .fold(0u16, |w, r| (w << 1) | r[line] as u16)
    }

    #[test]
    fn a_frame_read_on_time_returns_the_codes() {
        let (reads, chip) = frame(4, [-12345, 321]);
        assert!(chip.violations().is_empty(), "{:?}", chip.violations());
        // Straight binary on the pins: code + 32768.
        assert_eq!(word(&reads, 0), (-12345i32 + 32768) as u16);
        assert_eq!(word(&reads, 1), (321 + 32768) as u16);
        assert_eq!(chip.conversions().len(), 1);
    }

    #[test]
    fn a_too_fast_sclk_is_recorded() {
        // 40 ns SCLK < 50 ns; its 16 periods (640 ns) also end before tCONV = 730 ns.
        let (reads, chip) = frame(2, [1000, -1000]);
        let kinds: Vec<_> = chip.violations().iter().map(|v| v.kind).collect();
        assert!(kinds.contains(&CsViolationKind::SclkTooFast), "{kinds:?}");
        assert!(
            kinds.contains(&CsViolationKind::ConversionNotDone),
            "{kinds:?}"
        );
        // The word is garbage, not the code.
        assert_ne!(
            [word(&reads, 0), word(&reads, 1)],
            [(1000 + 32768) as u16, (32768 - 1000) as u16]
        );
    }

    #[test]
    fn a_short_frame_and_a_short_cs_high_are_recorded() {
        let mut chip = ads8354(100e6, 1);
        chip.step(false, true);
        for _ in 0..5 {
            chip.step(false, false);
            chip.step(false, false);
            chip.step(false, false);
            chip.step(false, true);
            chip.step(false, true);
            chip.step(false, true);
        }
        chip.step(true, true);
        chip.step(true, true);
        chip.step(false, true);
        let kinds: Vec<_> = chip.violations().iter().map(|v| v.kind).collect();
        assert!(kinds.contains(&CsViolationKind::FrameAborted), "{kinds:?}");
        assert!(
            kinds.contains(&CsViolationKind::CsHighTooShort),
            "{kinds:?}"
        );
        assert!(kinds.contains(&CsViolationKind::CycleTooShort), "{kinds:?}");
    }
}
