//! The ADC frame check (`[registers] enabled`: STATUS.ADC_FRAME), derived per chip here and
//! nowhere else: the RTL ([`super::hdl::FrameChecker`]), the model
//! ([`super::model::AdcModel::with_frame_check`]), the docs (docs/registers.md) and the
//! chip models' fault (`sim::adc_pins::DataLine::stick`) all follow [`FrameCheck`].
//!
//! # The rule: every data line stuck for a whole frame
//! A frame is in error when each of its data lines carried one level only over every data
//! bit the controller shifted in from it: all zeros or all ones. That is what a stuck SDO
//! gives (a driver or a trace shorted to a rail, or a broken trace held by the input's pull
//! resistor). The check adds no latency: the verdict is registered at the clock edge that
//! shifts the frame's last data bit in, the edge that raises `out_valid` for that frame,
//! and holds until the next delivered frame.
//!
//! ```text
//!  line A bit ─┬─► seen 1 (A) ──┐ both seen:    ┌───────────┐
//!              └─► seen 0 (A) ──┴─ A toggled ──►│ stuck =   │ frame's last bit
//!  line B bit ─┬─► seen 1 (B) ──┐               │ !A & !B   ├──[reg on delivery]──► frame_error
//!              └─► seen 0 (B) ──┴─ B toggled ──►│           │
//!  (seen flags cleared after every frame's last bit; with one line B never toggles)
//! ```
//!
//! # Per chip (what the data sheets fix, and why the rule cannot fire on a good frame)
//! No preset chip's data sheet, as far as it could be consulted, fixes a driven level in
//! a slot of the frame besides the data bits: the LTC1407A-1's idle slots are Hi-Z
//! (datasheet 14071fb, SDO pin function and timing diagram; the chip model reads them as
//! random bits), the ADS8354's slots before its MSB are not specified by the sources cited
//! for it (`AdcTiming::ADS8354`; its chip model reads them as undefined), and the AD7380's
//! 16-SCLK frame is all data. So the check is on the data
//! bits themselves, and what makes it sound is which codes a stuck frame gives:
//! * LTC1407A-1 (one line, two 14-bit two's-complement words, datasheet 14071fb): both
//!   words 0, or both -1 (all ones). A sin/cos pair with both channels within one LSB of
//!   zero has a magnitude under 1.5 LSB, far below any loss-of-signal threshold; a frame
//!   with a signal cannot give it, so ADC_FRAME is a stuck SDO. With no signal at all (both
//!   inputs at mid-scale, LOS set) a noisy frame can read 0/0 or -1/-1 and raise it too.
//! * AD7380 (two lines, 16-bit two's complement): both lines stuck gives both words 0 or
//!   -1, as above. One stuck line gives one channel at 0 or -1, a code a live channel takes
//!   at every zero crossing: no per-frame check can tell it, so a single stuck line is left
//!   to the monitor (the magnitude follows the other channel: LOS, CLIP).
//! * ADS8354 (two lines, 16-bit straight binary, SBAS931B for its interface): both lines
//!   stuck gives both channels at the same full-scale code, +FS/+FS or -FS/-FS; a live
//!   signal reaches that only when both channels clip at once, and then FULL_SCALE and CLIP
//!   are set with it. One stuck line gives one channel at full scale: FULL_SCALE.
//! * Generic: the same rule on the configured frame's lines.
use super::AdcParams;

/// What the frame check compares, per frame (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct FrameCheck {
    /// Data lines: 1 (line A carries every channel) or 2 (A: channel 0, B: channel 1).
    pub lines: u32,
    /// Data bits each line carries per frame.
    pub bits_per_line: u32,
}

impl FrameCheck {
    /// The two-line layout (line B checked).
    pub fn two_lines(&self) -> bool {
        self.lines >= 2
    }

    /// Whether a frame whose lines carried these bits (`lines[k]`: line k's data bits in
    /// order) is in error: every line showed one level only.
    pub fn stuck(lines: &[&[bool]]) -> bool {
        lines
            .iter()
            .all(|l| l.iter().all(|&b| b) || l.iter().all(|&b| !b))
    }

    /// One line for `check`.
    pub fn describe(&self) -> String {
        format!(
            "adc frame check             every data line stuck over a frame ({} line{}, {} data bits each) -> STATUS.ADC_FRAME\n",
            self.lines,
            if self.lines == 1 { "" } else { "s" },
            self.bits_per_line
        )
    }
}

impl AdcParams {
    /// The frame check of this chip and frame (see the module docs of `frame_check`).
    pub fn frame_check(&self) -> FrameCheck {
        let f = &self.frame;
        let lines = f.lines.clamp(1, 2);
        let channels = f.channels.clamp(1, 2);
        FrameCheck {
            lines,
            bits_per_line: f.width * if lines == 1 { channels } else { 1 },
        }
    }
}
