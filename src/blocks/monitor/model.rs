//! Bit-accurate model of the signal monitor: the RTL's registers, one update per edge.
use super::{count_bits, MonitorParams};
use crate::blocks::mask;

/// Inputs of one clock cycle.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MonitorIn {
    /// Synchronous reset.
    pub rst: bool,
    /// Raw sample strobe.
    pub in_valid: bool,
    /// Raw sine word (the low 16 bits drive the port; the low A bits are used).
    pub sin: i32,
    /// Raw cosine word.
    pub cos: i32,
    /// Magnitude strobe.
    pub mag_valid: bool,
    /// Magnitude word (the low 32 bits drive the port; the low W bits are used).
    pub magnitude: u64,
    /// Overspeed warning input.
    pub overspeed: bool,
    /// QEP mismatch warning input.
    pub qep_mismatch: bool,
    /// Run-time thresholds (with `run_time_thresholds`): loss-of-signal threshold, release
    /// level, clipping threshold (low W bits used).
    pub thresholds: [u64; 3],
}

impl MonitorIn {
    /// Stimulus row in input-port order.
    pub fn row(&self) -> Vec<u64> {
        vec![
            self.rst as u64,
            self.in_valid as u64,
            self.sin as u64 & 0xffff,
            self.cos as u64 & 0xffff,
            self.mag_valid as u64,
            self.magnitude & 0xffff_ffff,
            self.overspeed as u64,
            self.qep_mismatch as u64,
        ]
    }
    /// [`Self::row`] with the run-time thresholds after it.
    pub fn row_with_thresholds(&self) -> Vec<u64> {
        let mut r = self.row();
        r.extend(self.thresholds.map(|t| t & 0xffff_ffff));
        r
    }
}

/// Outputs after one clock edge.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MonitorOut {
    /// los | clip | full_scale.
    pub error: bool,
    /// Registered overspeed | qep_mismatch.
    pub warning: bool,
    /// Loss of signal.
    pub los: bool,
    /// Clipping.
    pub clip: bool,
    /// ADC full scale.
    pub full_scale: bool,
}

impl MonitorOut {
    /// Trace row in output-port order.
    pub fn row(&self) -> Vec<u64> {
        vec![
            self.error as u64,
            self.warning as u64,
            self.los as u64,
            self.clip as u64,
            self.full_scale as u64,
        ]
    }
}

/// Model of [`super::hdl::Monitor`].
#[derive(Clone, Debug)]
pub struct MonitorModel {
    p: MonitorParams,
    los: bool,
    los_cnt: u64,
    clip: bool,
    clip_cnt: u64,
    fs: bool,
    fs_cnt: u64,
    warn: bool,
}

impl MonitorModel {
    /// Model at power-up (every register 0, so `los` = 0 until the first reset).
    pub fn new(p: &MonitorParams) -> Self {
        Self {
            p: *p,
            los: false,
            los_cnt: 0,
            clip: false,
            clip_cnt: 0,
            fs: false,
            fs_cnt: 0,
            warn: false,
        }
    }

    fn outputs(&self) -> MonitorOut {
        MonitorOut {
            error: self.los || self.clip || self.fs,
            warning: self.warn,
            los: self.los,
            clip: self.clip,
            full_scale: self.fs,
        }
    }

    /// One clock edge.
    pub fn step(&mut self, i: MonitorIn) -> MonitorOut {
        let p = &self.p;
        let a = p.adc_width();
        let nlast = p.window() as u64 - 1;
        let nmask = mask(count_bits(p.window()));
        let hlast = p.hold() as u64 - 1;
        let hmask = mask(count_bits(p.hold()));
        if i.rst {
            self.los = true;
            self.los_cnt = 0;
            self.clip = false;
            self.clip_cnt = 0;
            self.fs = false;
            self.fs_cnt = 0;
            self.warn = false;
            return self.outputs();
        }
        if i.mag_valid {
            let w = mask(p.mag_width());
            let mag = i.magnitude & w;
            let (thr, rel, clip) = if p.run_time_thresholds() {
                (
                    i.thresholds[0] & w,
                    i.thresholds[1] & w,
                    i.thresholds[2] & w,
                )
            } else {
                (p.los_threshold(), p.los_release(), p.clip_threshold())
            };
            if !self.los {
                if mag < thr {
                    if self.los_cnt == nlast {
                        self.los = true;
                        self.los_cnt = 0;
                    } else {
                        self.los_cnt = (self.los_cnt + 1) & nmask;
                    }
                } else {
                    self.los_cnt = 0;
                }
            } else if mag >= rel {
                if self.los_cnt == nlast {
                    self.los = false;
                    self.los_cnt = 0;
                } else {
                    self.los_cnt = (self.los_cnt + 1) & nmask;
                }
            } else {
                self.los_cnt = 0;
            }
            if mag > clip {
                self.clip = true;
                self.clip_cnt = 0;
            } else if self.clip {
                if self.clip_cnt == hlast {
                    self.clip = false;
                    self.clip_cnt = 0;
                } else {
                    self.clip_cnt = (self.clip_cnt + 1) & hmask;
                }
            }
        }
        if i.in_valid {
            let am = mask(a);
            let (lo, hi) = (1u64 << (a - 1), mask(a - 1));
            let (s, c) = (i.sin as u64 & am, i.cos as u64 & am);
            if s == lo || s == hi || c == lo || c == hi {
                self.fs = true;
                self.fs_cnt = 0;
            } else if self.fs {
                if self.fs_cnt == hlast {
                    self.fs = false;
                    self.fs_cnt = 0;
                } else {
                    self.fs_cnt = (self.fs_cnt + 1) & hmask;
                }
            }
        }
        self.warn = i.overspeed || i.qep_mismatch;
        self.outputs()
    }
}
