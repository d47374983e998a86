//! Automatic offset, gain and phase calibration by a least-squares ellipse fit over whole
//! signal periods (`correction.mode = "auto"`): the bit-accurate integer specification of
//! the RTL in [`super::fit_hdl`] (tracker, sums) and [`super::fit_solve`] (one serial
//! multiplier, one serial divider / square root), which `tests/blocks/correction_fit_rtl.rs`
//! checks update by update.
//!
//! ```text
//!  x_s, x_c ─► d = x - b_ref ─► quadrant tracker (signs of d; +-1 steps, a 2-step counts
//!  (raw A-bit)   (b_ref = b at      twice in the direction of the last 1-step)
//!                 window start)  ─► sums over the window: N, Σd_s, Σd_c, Σd_s², Σd_c², Σd_s d_c
//!  window = from a quadrant boundary to the first sample past the boundary 4K' quadrants
//!  later, K' >= K periods and N >= min_samples ──► solve (below) ──► b, g_s, g_c, k
//! ```
//!
//! # Maths (signal sin = A_s sin t + b_s, cos = A_c cos(t + phi) + b_c)
//! Over whole periods, uniformly sampled: mean(d) = b - b_ref, var_s = A_s^2 / 2,
//! var_c = A_c^2 / 2, cov = E[(d_s - m_s)(d_c - m_c)] = A_s A_c E[sin t cos(t + phi)]
//! = -A_s A_c sin(phi) / 2, so **sin(phi) = -cov / sqrt(var_s var_c)** (the minus: phi is
//! the cos track's lead). Then g_s = T / A_s, g_c = T / (A_c cos phi), k = g_s tan phi
//! (the codes of the phase-corrected datapath, module doc of [`super`]).
//!
//! # Fixed point (all integer; divisions round half away from zero unless "floor")
//! * Sums: |d| < 2^A, so |Σd| < N 2^A and Σd² < N 2^(2A) (A = 14, N = 2^20: 2^48; an RTL
//!   keeps them as two 32-bit words with a delayed carry).
//! * Means, Q.8: m = round(Σd 2^8 / N).
//! * Variances and covariance, Q.16: V = floor(Σd² 2^16 / N) - m², C = floor(Σd_s d_c 2^16 /
//!   N) - m_s m_c.
//! * Amplitudes, Q.8: Amp = isqrt(2 V) (floor). No update unless Amp >= min_amplitude 2^8
//!   on both tracks.
//! * sin(phi), Q.15: S = round(-2 C 2^15 / (Amp_s Amp_c)), clamped to +-round(2^15 sin 15°);
//!   cos(phi), Q.15: Cc = isqrt(2^30 - S²).
//! * Offsets: b = b_ref + round(m / 2^8) (integer LSB, as the datapath takes them).
//! * Codes: g_s = round(T 2^(GF+8) / Amp_s), g_c = round(T 2^(GF+8+15) / (Amp_c Cc)),
//!   k = round(T S 2^(GF+8) / (Amp_s Cc)); gains clamped to 65535, |k| to 65535.
//! * Accuracy of a window: a window spans whole periods only to within one sample, which
//!   leaves |mean error| <= A / N (the partial period's sum is at most one amplitude); this
//!   is why N >= `min_samples` and not only K periods (at 3.8 samples per period, K = 1 gives
//!   4 samples). Amplitude and phase errors are of the same relative order, 1 / N.
use super::{COS, SIN};

/// Most samples in one window (hardware counter and sum widths, see the module doc of
/// [`super::fit_hdl`]): an open window that reaches it without closing is abandoned.
pub const N_MAX: u32 = 1 << 24;

/// Parameters of the ellipse fit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FitParams {
    /// ADC width A (10..=16).
    pub adc_width: u32,
    /// Gain fraction bits GF (8..=15).
    pub gain_frac_bits: u32,
    /// Target amplitude T (LSB).
    pub target_amplitude: u32,
    /// Least whole periods per window, K.
    pub periods: u32,
    /// Least samples per window.
    pub min_samples: u32,
    /// No update below this amplitude (LSB) on either track.
    pub min_amplitude: u32,
}

/// Coefficients of the correction datapath.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Coefs {
    /// Offsets [sin, cos] in LSB.
    pub offset: [i64; 2],
    /// Gain codes [sin, cos] (cos carries 1 / cos(phi)).
    pub gain: [u64; 2],
    /// Cross code k (signed).
    pub cross: i64,
}

/// Window sums.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Sums {
    /// Samples N.
    pub n: i128,
    /// Σd per track.
    pub s1: [i128; 2],
    /// Σd² per track.
    pub s2: [i128; 2],
    /// Σd_s d_c.
    pub sc: i128,
}

/// round(a / b), half away from zero (b > 0).
fn rdiv(a: i128, b: i128) -> i128 {
    let q = (2 * a.abs() + b) / (2 * b);
    if a < 0 {
        -q
    } else {
        q
    }
}

/// floor(sqrt(v)), v >= 0.
pub fn isqrt(v: i128) -> i128 {
    if v <= 0 {
        return 0;
    }
    let mut x = (v as f64).sqrt() as i128;
    while x * x > v {
        x -= 1;
    }
    while (x + 1) * (x + 1) <= v {
        x += 1;
    }
    x
}

/// The end-of-window computation: new coefficients from the sums taken relative to `b_ref`,
/// or None (amplitude below the minimum, or an offset outside the A-bit range).
pub fn solve(p: &FitParams, b_ref: [i64; 2], s: &Sums) -> Option<Coefs> {
    if s.n <= 0 {
        return None;
    }
    let n = s.n;
    let m = [rdiv(s.s1[0] << 8, n), rdiv(s.s1[1] << 8, n)];
    let v = [
        (s.s2[0] << 16).div_euclid(n) - m[0] * m[0],
        (s.s2[1] << 16).div_euclid(n) - m[1] * m[1],
    ];
    let c = (s.sc << 16).div_euclid(n) - m[0] * m[1];
    let amp = [isqrt(2 * v[0]), isqrt(2 * v[1])];
    let min = (p.min_amplitude as i128) << 8;
    if amp[0] < min || amp[1] < min {
        return None;
    }
    let smax = (32768.0 * 15f64.to_radians().sin()).round() as i128;
    let sn = rdiv((-2 * c) << 15, amp[0] * amp[1]).clamp(-smax, smax);
    let cs = isqrt((1i128 << 30) - sn * sn);
    let lim = 1i64 << (p.adc_width - 1);
    let mut offset = [0i64; 2];
    for ch in [SIN, COS] {
        offset[ch] = b_ref[ch] + rdiv(m[ch], 256) as i64;
        if offset[ch] < -lim || offset[ch] >= lim {
            return None;
        }
    }
    let t = p.target_amplitude as i128;
    let gf = p.gain_frac_bits;
    let gs = rdiv(t << (gf + 8), amp[0]).min(0xffff);
    let gc = rdiv(t << (gf + 8 + 15), amp[1] * cs).min(0xffff);
    let k = rdiv((t * sn) << (gf + 8), amp[0] * cs).clamp(-0xffff, 0xffff);
    Some(Coefs {
        offset,
        gain: [gs as u64, gc as u64],
        cross: k as i64,
    })
}

/// The fit's state: tracker, window sums, coefficients in use.
#[derive(Clone, Debug)]
pub struct EllipseFit {
    p: FitParams,
    coefs: Coefs,
    /// Offsets the window's differences are taken from (latched at the window start).
    b_ref: [i64; 2],
    /// Quadrant of the last sample; None after a restart.
    tq: Option<u8>,
    /// Direction of the last +-1 step (+1, -1; 0: none yet).
    dir: i64,
    /// The window is open.
    open: bool,
    /// Net quadrants since the window opened.
    net: i64,
    sums: Sums,
    /// Windows completed and updates applied.
    windows: u64,
    updates: u64,
}

impl EllipseFit {
    /// Fit starting from `start` (the configured coefficients).
    pub fn new(p: FitParams, start: Coefs) -> Self {
        Self {
            p,
            coefs: start,
            b_ref: start.offset,
            tq: None,
            dir: 0,
            open: false,
            net: 0,
            sums: Sums::default(),
            windows: 0,
            updates: 0,
        }
    }

    /// Coefficients in use.
    pub fn coefs(&self) -> Coefs {
        self.coefs
    }

    /// Windows completed and updates applied so far.
    pub fn counts(&self) -> (u64, u64) {
        (self.windows, self.updates)
    }

    fn add(&mut self, d: [i64; 2]) {
        let s = &mut self.sums;
        s.n += 1;
        for ch in [SIN, COS] {
            s.s1[ch] += d[ch] as i128;
            s.s2[ch] += (d[ch] * d[ch]) as i128;
        }
        s.sc += (d[SIN] * d[COS]) as i128;
    }

    fn start_window(&mut self, d: [i64; 2]) {
        self.open = true;
        self.net = 0;
        self.sums = Sums::default();
        self.add(d);
    }

    /// One sample (raw A-bit values); returns the new coefficients when a window ends with
    /// an accepted update (they apply from the next sample on).
    pub fn sample(&mut self, xs: i64, xc: i64) -> Option<Coefs> {
        let d = [xs - self.b_ref[SIN], xc - self.b_ref[COS]];
        let (ns, nc) = (d[SIN] < 0, d[COS] < 0);
        // CORDIC mapper convention: q = {sign(sin), sign(sin) ^ sign(cos)}.
        let q = match (ns, nc) {
            (false, false) => 0u8,
            (false, true) => 1,
            (true, true) => 2,
            (true, false) => 3,
        };
        let Some(tq) = self.tq else {
            self.tq = Some(q);
            self.open = false;
            return None;
        };
        self.tq = Some(q);
        let step = match (q + 4 - tq) % 4 {
            0 => 0,
            1 => 1,
            3 => -1,
            _ if self.dir != 0 => 2 * self.dir,
            _ => {
                // A two-quadrant step with no known direction: restart.
                self.open = false;
                return None;
            }
        };
        if step == 1 || step == -1 {
            self.dir = step;
        }
        if !self.open {
            if step != 0 {
                self.b_ref = self.coefs.offset;
                let d = [xs - self.b_ref[SIN], xc - self.b_ref[COS]];
                self.start_window(d);
            }
            return None;
        }
        self.net += step;
        let whole = 4 * self.p.periods as i64;
        // Only a boundary crossing can close the window (net stays a multiple of 4 for a
        // whole quadrant after it).
        let done = step != 0
            && self.net.abs() >= whole
            && self.net % 4 == 0
            && self.sums.n >= self.p.min_samples as i128;
        if !done {
            if self.sums.n >= N_MAX as i128 {
                // A window that has not closed after N_MAX samples (a standing or crawling
                // shaft) is abandoned: the next boundary opens a new one.
                self.open = false;
                return None;
            }
            self.add(d);
            return None;
        }
        // This sample is the first past the closing boundary: it ends this window and
        // opens the next. The next window's reference is the offsets in use *before* this
        // window's update: in hardware the solve takes about a thousand clocks, so the new
        // window has started long before the new offsets exist (the offsets found are
        // b_ref + mean either way, so only the reference lags one window).
        self.windows += 1;
        let r = solve(&self.p, self.b_ref, &self.sums);
        self.b_ref = self.coefs.offset;
        if let Some(c) = r {
            self.coefs = c;
            self.updates += 1;
        }
        let d = [xs - self.b_ref[SIN], xc - self.b_ref[COS]];
        self.start_window(d);
        r
    }
}
