//! Plain-Rust model of the ADC controller's registers, clock for clock (same cycle
//! semantics as the co-simulation harness: inputs applied, clock edge, outputs read).
use super::{AdcParams, SignFormat};
use crate::blocks::mask;

/// Inputs of one clock.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AdcIn {
    /// Synchronous reset.
    pub rst: bool,
    /// Run enable.
    pub enable: bool,
    /// Serial data from the ADC (line A).
    pub miso: bool,
    /// Serial data line B (channel 1 of a two-line frame; ignored with one line).
    pub miso_b: bool,
}

/// Outputs after one clock.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AdcOut {
    /// SCK pin.
    pub sck: bool,
    /// CONV pin.
    pub conv: bool,
    /// Sample strobe.
    pub valid: bool,
    /// Channel 0 (W-bit two's complement in the low bits).
    pub ch0: u16,
    /// Channel 1.
    pub ch1: u16,
    /// The frame check's verdict on the last delivered frame (None without the check).
    pub frame_error: Option<bool>,
}

impl AdcOut {
    /// Trace row in `AdcController` output-port order (with `frame_error_0` when the
    /// check is on).
    pub fn row(&self) -> Vec<u64> {
        vec![
            self.sck as u64,
            self.conv as u64,
            self.valid as u64,
            self.ch0 as u64,
            self.ch1 as u64,
        ]
        .into_iter()
        .chain(self.frame_error.map(u64::from))
        .collect()
    }
    /// Channel `c` sign-extended from W bits.
    pub fn signed(&self, c: usize, width: u32) -> i32 {
        let v = if c == 0 { self.ch0 } else { self.ch1 } as u64;
        crate::blocks::sext(v, width) as i32
    }
}

/// The frame check's registers (names as in `hdl::FrameChecker`).
#[derive(Clone, Copy, Debug, Default)]
struct CheckRegs {
    hi_a: bool,
    lo_a: bool,
    hi_b: bool,
    lo_b: bool,
    err: bool,
}

/// The controller's state.
#[derive(Clone, Debug)]
pub struct AdcModel {
    p: AdcParams,
    live: bool,
    pc: u32,
    ph: u32,
    cyc: u32,
    warm: u32,
    sr: [u16; 2],
    /// The capture enables of the state entered at the previous step (channel 0, channel 1,
    /// deliver): the bit is the `miso` of the next step, the level the input register takes
    /// at the edge that moves the capture state's pins (`MISO_SAMPLE_LAG_CLOCKS`).
    pend: [bool; 3],
    /// The capture state of a frame's last data slot (delivered or not) was entered at the
    /// previous step.
    pend_last: bool,
    /// The frame check (`with_frame_check`): the registers of `hdl::FrameChecker`.
    check: Option<CheckRegs>,
    out: AdcOut,
    /// The registered pins and data: `out` of the previous clock (the hardware decodes
    /// them from the state one clock after it is entered).
    pins: AdcOut,
}

impl AdcModel {
    /// Model for validated parameters, in the power-up state (all registers zero).
    pub fn new(p: &AdcParams) -> Self {
        AdcModel {
            p: p.clone(),
            live: false,
            pc: 0,
            ph: 0,
            cyc: 0,
            warm: 0,
            sr: [0; 2],
            pend: [false; 3],
            pend_last: false,
            check: None,
            out: AdcOut::default(),
            pins: AdcOut {
                sck: p.frame.cpol,
                conv: !p.frame.conv_active_high,
                ..AdcOut::default()
            },
        }
    }

    /// [`new`](Self::new) with the frame check (`AdcController::with_frame_check`).
    pub fn with_frame_check(p: &AdcParams) -> Self {
        let mut m = Self::new(p);
        m.check = Some(CheckRegs::default());
        m.out.frame_error = Some(false);
        m.pins.frame_error = Some(false);
        m
    }

    /// One clock. The state and `out` follow the controller's timing maths (module docs);
    /// the value returned, like the hardware's registered outputs, is one clock later.
    pub fn step(&mut self, i: AdcIn) -> AdcOut {
        let p = &self.p;
        let f = &p.frame;
        let run = i.enable && !i.rst;
        let warm_init = 1 + f.pipeline;
        let (mut pc_n, mut warm_n) = (0, warm_init);
        if run && self.live {
            if self.pc == p.period_clocks - 1 {
                pc_n = 0;
                warm_n = self.warm.saturating_sub(1);
            } else {
                pc_n = (self.pc + 1) & 0xffff;
                warm_n = self.warm;
            }
        }
        let stop = f.frame_sck + 1;
        let (mut ph_n, mut cyc_n) = (0, stop);
        if run {
            if pc_n == f.lead_clocks {
                (ph_n, cyc_n) = (0, 0);
            } else if self.cyc == stop {
                (ph_n, cyc_n) = (self.ph, self.cyc);
            } else if self.ph == p.sck_period_clocks - 1 {
                (ph_n, cyc_n) = (0, (self.cyc + 1) & 0xff);
            } else {
                (ph_n, cyc_n) = ((self.ph + 1) & 0xff, self.cyc);
            }
        }
        let sck_act = run && cyc_n < f.frame_sck && ph_n >= p.sck_low_clocks();
        let conv_act = run && pc_n < p.conv_clocks && warm_n < warm_init;
        let cap = run && ph_n == p.capture_phase() && cyc_n >= 1 && cyc_n <= f.frame_sck;
        let slot = cyc_n.wrapping_sub(1) & 0xff;
        let wmask = mask(f.width) as u16;
        let chans = f.channels.min(2) as usize;
        let mut pend = [false; 3];
        for (c, e) in pend.iter_mut().enumerate().take(chans) {
            *e = cap && slot >= f.offsets[c] && slot < f.offsets[c] + f.width;
        }
        let pend_last = cap && slot == p.data_slots().1;
        pend[2] = pend_last && warm_n == 0;
        // The bits of the capture state entered at the previous step: `i.miso` is the level
        // sampled at the edge that moved its pins.
        // With two lines channel 1 reads line B at the same edge.
        let bits = [i.miso, if f.lines >= 2 { i.miso_b } else { i.miso }];
        let mut sr_n = self.sr;
        for (c, (sr, old)) in sr_n.iter_mut().zip(self.sr).enumerate().take(chans) {
            if self.pend[c] {
                *sr = ((old << 1) | bits[c] as u16) & wmask;
            }
        }
        let flip = match f.sign {
            SignFormat::TwosComplement => 0,
            SignFormat::OffsetBinary => 1u16 << (f.width - 1),
        };
        let mut out = AdcOut {
            sck: sck_act ^ f.cpol,
            conv: conv_act ^ !f.conv_active_high,
            valid: false,
            ch0: self.out.ch0,
            ch1: self.out.ch1,
            frame_error: self.out.frame_error,
        };
        // The frame check: the bits shifted in now, by line; the verdict with a delivered
        // frame's last bit; the seen flags cleared after any frame's last bit.
        if let Some(c) = self.check.as_mut() {
            let two = f.lines >= 2;
            let ea = self.pend[0] || (self.pend[1] && !two);
            let eb = self.pend[1] && two;
            let hi_a = c.hi_a || (ea && bits[0]);
            let lo_a = c.lo_a || (ea && !bits[0]);
            let hi_b = c.hi_b || (eb && i.miso_b);
            let lo_b = c.lo_b || (eb && !i.miso_b);
            if self.pend[2] {
                // Stuck: no line showed both levels.
                let toggled = (hi_a && lo_a) || (hi_b && lo_b);
                c.err = !toggled;
            }
            (c.hi_a, c.lo_a, c.hi_b, c.lo_b) = if self.pend_last {
                (false, false, false, false)
            } else {
                (hi_a, lo_a, hi_b, lo_b)
            };
            if i.rst {
                *c = CheckRegs::default();
            }
            out.frame_error = Some(c.err);
        }
        if self.pend[2] {
            out.valid = true;
            out.ch0 = (sr_n[0] ^ flip) & wmask;
            out.ch1 = if f.channels >= 2 {
                (sr_n[1] ^ flip) & wmask
            } else {
                0
            };
        }
        if i.rst {
            sr_n = [0; 2];
            out.valid = false;
            out.ch0 = 0;
            out.ch1 = 0;
        }
        self.pend = pend;
        self.pend_last = pend_last;
        self.live = run;
        self.pc = pc_n;
        self.ph = ph_n;
        self.cyc = cyc_n;
        self.warm = warm_n;
        self.sr = sr_n;
        self.out = out;
        std::mem::replace(&mut self.pins, out)
    }
}
