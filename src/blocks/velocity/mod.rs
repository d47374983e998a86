//! Velocity estimation from the decoded position (the thesis's chapter 4, "4.1 低速估測",
//! plus a type-II tracking loop): four estimators behind one front end, run once every
//! D = round(clock_hz / rate_hz) clocks. Design notes and the Table 4-1 discussion:
//! `docs/velocity.md`. The RTL is [`hdl::Velocity`] (its schedule in the docs of [`hdl`]),
//! bit- and cycle-exact with [`model::VelocityModel`].
//!
//! ```text
//!              every decoded sample                 every D clocks (one update)
//! in_p ──┐  ┌──────────────────────────┐  theta  ┌───────────────────────────────┐
//! (F+2 b)└─►│ pos += sext(in_p - pos   ├────────►│ estimator (method)            ├─► out_velocity
//! in_valid─►│        mod 2^(F+2))      │ (Wp b)  │  diff_lpf  X += a (U - X)     │   (width b,
//!           │ unwrapped, mod 2^Wp      │         │  kalman    X += K_k (U - X)   │    S frac)
//!           └──────────────────────reg─┘         │  lsq       y = R sum n_i r_i  ├─► out_velocity_valid
//!                 ┌─────────┐ tick               │  tracking  alpha-beta loop    │   (1 clock)
//!                 │ /D      ├───────────────────►│  one multiplier, time-shared  │
//!                 └─────────┘                    └───────────────────────────reg─┘
//! ```
//!
//! # Front end: the unwrapped position
//! The block needs only the low F+2 bits of the decoded position, p = position mod 2^(F+2)
//! (the electrical angle: 4 PPR 2^F is a multiple of 2^(F+2), whatever the PPR). The decoder
//! never steps by 2 quadrants or more between samples (it warns from 1.75), so the true
//! step is sext((p - pos) mod 2^(F+2), F+2) and `pos` accumulates the unwrapped position
//! modulo 2^Wp. A wrap of the single-turn position and an overflow of the turn counter are
//! therefore invisible here, by construction: only steps enter. The first sample after
//! reset loads pos = p. Every estimator uses differences of `pos` only, never its absolute
//! value, so the modulo is harmless as long as Wp holds the largest difference taken
//! (below).
//!
//! # Sampling
//! A free-running counter ticks every D clocks. At a tick the estimator takes theta = pos
//! (the register's value before that edge's own sample) if a sample has been seen; the
//! first such update loads the estimator's history with theta (as if the shaft had been at
//! rest there) and outputs 0. The result appears with `out_velocity_valid` [`VelocityParams::latency`]
//! clocks after the tick; `out_velocity` holds between strobes. Reset clears everything.
//!
//! # Units
//! theta in position LSB (2^-F quadrant); the velocity in LSB per update period; S =
//! `frac_bits`. `out_velocity` = the velocity times 2^S, rounded half up, so
//! 2^S is one position LSB per period: 2^-(F+S) quadrant per period.
//! Internal states keep S + G fractional bits (G guard bits per method, below).
//!
//! # Methods and their fixed point (C = [`COEF_FRAC`] coefficient fraction bits)
//! Every quantization is round half up: q(x / 2^k) = floor((x + 2^(k-1)) / 2^k), whose
//! deterministic error is at most half its LSB and whose mean error on uniformly spread
//! residues is 2^-(k+1) of its LSB (the exact-half case only).
//! * `diff_lpf` (eq. 4.1-4.3): Delta = theta(k) - theta(k-1), U = Delta 2^(S+G),
//!   X += q(a_q (U - X) / 2^C), y = q(X / 2^G), a = T / (tau_c + T), tau_c = 1 / (2 pi f_c),
//!   a_q = round(a 2^C). The form X + a (U - X) has DC gain exactly 1 for any a_q, so the
//!   coefficient's quantization moves the cut-off slightly but adds no bias. Rounding: at a
//!   constant input the state stops where q(a_q (U - X) / 2^C) = 0, |U - X| <= 2^C / (2 a_q)
//!   internal LSB (the dead band of a first-order filter in fixed point); G =
//!   ceil(log2(2^(C+1) / a_q)) puts that below 1/4 output LSB.
//! * `kalman` (eq. 4.16 on the scalar model of eq. 4.17): z(k) = Delta, x_0 = 0, P_0 = 1,
//!   P^- = P + Q, K = P^- / (P^- + R), x += K (z - x), P = (1 - K) P^-, Q = `kalman_q`, R =
//!   `kalman_r` in (LSB per period)^2. The gain sequence K_k does not depend on the data (a
//!   scalar model with constant Q and R), so the full recursion is run offline in f64 and
//!   its gains are quantized K_q[k] = round(K_k 2^C); K_k falls monotonically to K_inf, and
//!   from step n_0 on round(K_k 2^C) = round(K_inf 2^C) (checked over 64 further steps, and
//!   monotonic convergence keeps it there). The hardware holds the n_0 transient gains in a
//!   table and K_inf after it: this is the full recursion, bit for bit its quantized gains,
//!   without a divider; the steady-state gain alone would differ in the first n_0 updates
//!   only. The datapath is diff_lpf's with K_q[k] for a_q; G from K_inf as above.
//! * `lsq` (eq. 4.4-4.9): the M newest positions x_1..x_M (x_M = theta(k)) at t = 1..M,
//!   the order-N least-squares polynomial, its derivative at t = M + 1:
//!   v = H_{M+1} X = q_{M+1} (A^T A)^-1 A^T X. H is computed exactly in rationals,
//!   h_i = n_i / d with integers n_i and a common denominator d (M = 4, N = 1:
//!   (-3, -1, 1, 3) / 10). Since sum h_i = 0, v = sum h_i r_i with r_i = x_i - x_M
//!   (|r_i| <= (M - i) V: small words). The hardware forms P = sum n_i r_i exactly (M - 1
//!   multiplies by the integers n_i) and y = q(P R / 2^B) with R = round(2^(S+B) / d): the
//!   reciprocal's error is at most 1/2 of 2^-B, so the output's is |P| 2^-(B+1); B =
//!   ceil(log2(2 P_max)) with P_max = V sum |n_i| (M - i) keeps it below 1/4 LSB at every
//!   speed up to V. No state, G = 0.
//! * `tracking` (type II, the AD2S1210 idea): predicted position Theta (S+G fractional
//!   bits, modulo 2^(Wp+S+G)), velocity W (S+G fractional bits);
//!   e = theta 2^(S+G) - Theta, W += q(beta_q e / 2^C), Theta += W + q(alpha_q e / 2^C),
//!   y = q(W / 2^G). alpha = 2 zeta w_n T, beta = (w_n T)^2, w_n = 2 pi `bandwidth_hz`,
//!   zeta = 1/sqrt(2): the discretized PI loop. It is stable iff (Jury) 0 < beta_q and
//!   2 alpha_q + beta_q < 4 (alpha_q, beta_q in units of 2^-C), checked on the quantized
//!   gains. At a constant speed the loop has no error: W = v exactly up to rounding. The
//!   rounding offsets r1 (in W's update) and r2 (in Theta's) leave at most
//!   |alpha r1 / beta - r2| <= (alpha / beta + 1) / 2 internal LSB on W;
//!   G = ceil(log2(2 (alpha/beta + 1))) + 1 puts it below 1/4 output LSB.
//!   Settling: the error envelope of the continuous loop falls as exp(-zeta w_n t), to 2 %
//!   in 4 / (zeta w_n) (4.5 ms at 200 Hz); [`VelocityParams::settle_updates`].
//!
//! # Widths (all checked in [`VelocityParams::new`])
//! V = `max_step`, the largest position change per update period at the encoder's maximum
//! speed (LSB). For each method the impulse response g from Delta to y (LSB per period)
//! gives |y| <= V ||g||_1 (diff_lpf, kalman: g >= 0 with sum 1, so ||g||_1 = 1; lsq,
//! tracking: computed, the tracking loop overshoots). Output: V ||g||_1 2^S + 1 < 2^(width-1)
//! (no overflow at the maximum speed, after rounding). Position words: Wp holds the largest
//! difference taken (lsq (M-1) V, tracking the largest error V ||g_e||_1 + 1, else V) with a
//! sign bit and one bit of margin. States: V ||g||_1 2^(S+G) with a sign bit, at most 62
//! bits; tracking's Theta is Wp + S + G <= 62 bits.
//! Rounding bias: the output's own rounding is at most 1/2 LSB in the worst case and
//! 2^-(k+1) on average; with the internal error below 1/4 LSB the bias stays below
//! 2^-frac_bits LSB per period (one output LSB).
mod design;
pub mod hdl;
mod layout;
pub mod model;
mod parts;

use design::*;
pub use design::{kalman_gains, lsq_coefficients, tracking_gains};
pub use parts::VelMul;

use crate::error::{Error, Result};

/// Coefficient fraction bits C: gains are round(g 2^C).
pub const COEF_FRAC: u32 = 18;
/// Longest Kalman gain table (transient updates before K_inf holds to the bit).
pub const MAX_GAIN_TABLE: usize = 256;
/// Widest internal word in bits.
pub const MAX_STATE_BITS: u32 = 62;

/// `velocity.method`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Method {
    /// Type-II position/velocity tracking loop (alpha-beta).
    #[default]
    Tracking,
    /// Scalar Kalman filter on the difference (eq. 4.16/4.17).
    Kalman,
    /// Least-squares polynomial fit, FIR (eq. 4.9).
    Lsq,
    /// Difference plus first-order low-pass (eq. 4.3).
    DiffLpf,
}

impl std::fmt::Display for Method {
    /// The spelling of `velocity.method`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Method::Tracking => "tracking",
            Method::Kalman => "kalman",
            Method::Lsq => "lsq",
            Method::DiffLpf => "diff_lpf",
        })
    }
}

/// What the block is built from (the config's `[velocity]` plus the decoder's figures).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct VelocitySpec {
    /// Estimator.
    pub method: Method,
    /// System clock in Hz.
    pub clock_hz: f64,
    /// Update rate in Hz.
    pub rate_hz: f64,
    /// Fine bits F of the position (LSB = 2^-F quadrant).
    pub fine_bits: u32,
    /// Largest position change per update period at the maximum speed, in position LSB.
    pub max_step: u64,
    /// Fractional bits S of `out_velocity`.
    pub frac_bits: u32,
    /// Width of `out_velocity`.
    pub width: u32,
    /// diff_lpf cut-off in Hz.
    pub cutoff_hz: f64,
    /// lsq points M.
    pub lsq_points: u32,
    /// lsq order N.
    pub lsq_order: u32,
    /// Kalman process-noise variance Q, (LSB per period)^2.
    pub kalman_q: f64,
    /// Kalman measurement-noise variance R, (LSB per period)^2.
    pub kalman_r: f64,
    /// Tracking loop natural frequency in Hz.
    pub bandwidth_hz: f64,
}

impl VelocitySpec {
    /// The issue's defaults (`[velocity]` contract) for a decoder with F fine bits, clock and
    /// maximum step; `method` tracking.
    pub fn defaults(clock_hz: f64, fine_bits: u32, max_step: u64) -> Self {
        VelocitySpec {
            method: Method::Tracking,
            clock_hz,
            rate_hz: 7500.0,
            fine_bits,
            max_step,
            frac_bits: 8,
            width: 32,
            cutoff_hz: 900.0,
            lsq_points: 4,
            lsq_order: 1,
            kalman_q: 0.01,
            kalman_r: 0.03,
            bandwidth_hz: 200.0,
        }
    }
}

/// Per-method constants (all integers the hardware uses).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub enum MethodConsts {
    /// diff_lpf: a_q (units 2^-C).
    DiffLpf {
        /// round(a 2^C).
        a: i64,
    },
    /// Kalman: gains K_q[k] for the first updates, the last entry K_inf held after.
    Kalman {
        /// round(K_k 2^C), k = 1..=n_0, then round(K_inf 2^C) (the last entry).
        gains: Vec<i64>,
    },
    /// lsq: exact H = n / d, reciprocal R = round(2^(S+B) / d).
    Lsq {
        /// Integer numerators n_1..n_M (oldest first).
        n: Vec<i64>,
        /// Common denominator d.
        d: i64,
        /// round(2^(S+B) / d).
        recip: i64,
        /// B.
        shift: u32,
    },
    /// Tracking: alpha_q, beta_q (units 2^-C).
    Tracking {
        /// round(alpha 2^C).
        alpha: i64,
        /// round(beta 2^C).
        beta: i64,
    },
}

/// Validated parameters of the velocity block and its model.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct VelocityParams {
    /// The specification it was built from.
    pub spec: VelocitySpec,
    /// Clocks per update D.
    pub period_clocks: u64,
    /// Guard bits G of the internal states.
    pub guard: u32,
    /// Width Wp of the unwrapped position register.
    pub pos_width: u32,
    /// Width of the internal states (signed).
    pub state_width: u32,
    /// ||g||_1 of the method's impulse response from Delta to y.
    pub gain_l1: f64,
    /// Largest |out_velocity| at the maximum speed (output LSB).
    pub max_output: u64,
    /// The method's constants.
    pub consts: MethodConsts,
}

fn invalid(message: String) -> Error {
    Error::block_params("velocity", message)
}

/// Bits of the unsigned magnitude `v` (0 for 0).
fn bits(v: u128) -> u32 {
    128 - v.leading_zeros()
}

/// Round half up of x / 2^k for k >= 1 (k = 0: x).
#[inline]
pub fn qround(x: i128, k: u32) -> i128 {
    if k == 0 {
        x
    } else {
        (x + (1i128 << (k - 1))) >> k
    }
}

impl VelocityParams {
    /// Validates `spec` and derives every constant and width.
    pub fn new(spec: &VelocitySpec) -> Result<Self> {
        let s = spec;
        if !(s.rate_hz.is_finite() && s.rate_hz > 0.0) {
            return Err(invalid(format!("update rate {} Hz must be > 0", s.rate_hz)));
        }
        if !(s.clock_hz.is_finite() && s.clock_hz > 0.0) {
            return Err(invalid(format!("clock {} Hz must be > 0", s.clock_hz)));
        }
        let d = (s.clock_hz / s.rate_hz).round();
        if !(d >= 64.0 && d <= (1u64 << 32) as f64) {
            return Err(invalid(format!(
                "update period round({} / {}) = {d} clocks is out of range: 64..=2^32 \
                 (the estimator needs its schedule between two updates)",
                s.clock_hz, s.rate_hz
            )));
        }
        if !(2..=16).contains(&s.fine_bits) {
            return Err(invalid(format!(
                "fine bits {} out of range 2..=16",
                s.fine_bits
            )));
        }
        if !(0..=16).contains(&s.frac_bits) {
            return Err(invalid(format!(
                "frac_bits {} out of range 0..=16",
                s.frac_bits
            )));
        }
        if !(8..=62).contains(&s.width) {
            return Err(invalid(format!("width {} out of range 8..=62", s.width)));
        }
        if s.max_step == 0 || s.max_step >= 1 << 40 {
            return Err(invalid(format!(
                "maximum step {} LSB per period out of range 1..2^40",
                s.max_step
            )));
        }
        let v = s.max_step as f64;
        let c = COEF_FRAC;
        let one = (1i64 << c) as f64;
        let t = 1.0 / s.rate_hz;
        let (consts, guard, gain_l1, err_l1) = match s.method {
            Method::DiffLpf => {
                if !(s.cutoff_hz.is_finite() && s.cutoff_hz > 0.0) {
                    return Err(invalid(format!("cutoff {} Hz must be > 0", s.cutoff_hz)));
                }
                let tau = 1.0 / (std::f64::consts::TAU * s.cutoff_hz);
                let a = (t / (tau + t) * one).round() as i64;
                if a < 1 {
                    return Err(invalid(format!(
                        "cutoff {} Hz is too low for {} coefficient bits at {} Hz",
                        s.cutoff_hz, c, s.rate_hz
                    )));
                }
                let g = guard_for(a);
                (MethodConsts::DiffLpf { a }, g, 1.0, 0.0)
            }
            Method::Kalman => {
                let gains = kalman_gains(s.kalman_q, s.kalman_r, 1.0)?;
                let kinf = *gains.last().unwrap_or(&0);
                if kinf < 1 {
                    return Err(invalid(format!(
                        "kalman_q / kalman_r = {} / {} gives a steady-state gain below \
                         2^-{c}",
                        s.kalman_q, s.kalman_r
                    )));
                }
                let g = guard_for(kinf);
                (MethodConsts::Kalman { gains }, g, 1.0, 0.0)
            }
            Method::Lsq => {
                let m = s.lsq_points;
                let n = s.lsq_order;
                if !(2..=16).contains(&m) || !(1..=3).contains(&n) || n >= m {
                    return Err(invalid(format!(
                        "lsq_points = {m}, lsq_order = {n}: allowed 2..=16 points and order \
                         1..=3 below the points"
                    )));
                }
                let (num, den) = lsq_coefficients(m, n)?;
                let pmax: u128 = num
                    .iter()
                    .enumerate()
                    .map(|(i, &k)| k.unsigned_abs() as u128 * (m as u128 - 1 - i as u128))
                    .sum::<u128>()
                    * s.max_step as u128;
                let shift = bits(2 * pmax.max(1));
                let recip = ((1u128 << (s.frac_bits + shift)) as f64 / den as f64).round() as i64;
                let l1 = lsq_l1(&num, den);
                (
                    MethodConsts::Lsq {
                        n: num,
                        d: den,
                        recip,
                        shift,
                    },
                    0,
                    l1,
                    0.0,
                )
            }
            Method::Tracking => {
                if !(s.bandwidth_hz.is_finite() && s.bandwidth_hz > 0.0) {
                    return Err(invalid(format!(
                        "bandwidth {} Hz must be > 0",
                        s.bandwidth_hz
                    )));
                }
                let (alpha, beta) = tracking_gains(s.bandwidth_hz, s.rate_hz);
                if beta < 1 || alpha < 1 || 2 * alpha + beta >= 4 << c {
                    return Err(invalid(format!(
                        "tracking loop with bandwidth {} Hz at {} Hz is unstable: \
                         alpha = {:.6}, beta = {:.3e} (needs beta > 0 and 2 alpha + beta < 4; \
                         use a bandwidth below about {:.0} Hz and at least {:.3} Hz)",
                        s.bandwidth_hz,
                        s.rate_hz,
                        alpha as f64 / one,
                        beta as f64 / one,
                        1.07 * s.rate_hz / std::f64::consts::TAU,
                        s.rate_hz / std::f64::consts::TAU * (1.0 / one).sqrt()
                    )));
                }
                let ratio = alpha as f64 / beta as f64 + 1.0;
                let g = (2.0 * ratio).log2().ceil() as u32 + 1;
                let (l1, el1) = tracking_l1(alpha, beta);
                (MethodConsts::Tracking { alpha, beta }, g, l1, el1)
            }
        };
        let sg = s.frac_bits + guard;
        let max_out = (v * gain_l1 * (1u64 << s.frac_bits) as f64).ceil() as u64 + 1;
        if bits(max_out as u128) + 1 > s.width {
            return Err(invalid(format!(
                "out_velocity overflows at the maximum speed: {} LSB per period with {} \
                 fractional bits needs {} bits, width is {}",
                s.max_step,
                s.frac_bits,
                bits(max_out as u128) + 1,
                s.width
            )));
        }
        let max_diff = match &consts {
            MethodConsts::Lsq { .. } => v * (s.lsq_points - 1) as f64,
            MethodConsts::Tracking { .. } => v * err_l1 + 2.0,
            _ => v,
        };
        let pos_width = (bits(max_diff.ceil() as u128) + 2).max(s.fine_bits + 3);
        let state_width = bits((v * gain_l1 * 2f64.powi(sg as i32)).ceil() as u128 + 1) + 2;
        let theta_width = pos_width + sg;
        let widest = state_width.max(if matches!(consts, MethodConsts::Tracking { .. }) {
            theta_width
        } else {
            0
        });
        if widest > MAX_STATE_BITS || pos_width > MAX_STATE_BITS {
            return Err(invalid(format!(
                "internal words of {widest} bits exceed {MAX_STATE_BITS}: lower frac_bits \
                 or the maximum speed"
            )));
        }
        let p = VelocityParams {
            spec: s.clone(),
            period_clocks: d as u64,
            guard,
            pos_width,
            state_width: widest,
            gain_l1,
            max_output: max_out,
            consts,
        };
        layout::Layout::build(&p).check()?;
        if p.latency() >= p.period_clocks {
            return Err(invalid(format!(
                "update period round({} / {}) = {d} clocks is not longer than an update \
                 ({} clocks for the {} multiplies of {}): lower the update rate",
                s.clock_hz,
                s.rate_hz,
                p.latency(),
                layout::Layout::build(&p).mults,
                s.method
            )));
        }
        Ok(p)
    }

    /// S + G: fractional bits of the internal states.
    pub fn state_frac(&self) -> u32 {
        self.spec.frac_bits + self.guard
    }

    /// Clocks from a tick to its `out_velocity_valid`: n + 3 per multiply (operand
    /// register and multiplier start, n + 1 multiplier clocks, accumulate) plus two
    /// (snapshot, differences); n = ceil(Wb / 2) Booth digits of the widest coefficient
    /// (9 or 10 at the defaults, 17 for lsq's reciprocal). The one place the latency is
    /// derived: the model, the RTL's schedule and the config's check follow it.
    pub fn latency(&self) -> u64 {
        let l = layout::Layout::build(self).mul_steps() as u64;
        let mults = match &self.consts {
            MethodConsts::DiffLpf { .. } | MethodConsts::Kalman { .. } => 1,
            MethodConsts::Lsq { n, .. } => n.len() as u64,
            MethodConsts::Tracking { .. } => 2,
        };
        (3 + l) * mults + 2
    }

    /// Velocity LSB in rpm for a decoder with `quadrants_per_turn` quadrants per turn.
    pub fn lsb_rpm(&self, quadrants_per_turn: f64) -> f64 {
        self.spec.rate_hz * 60.0
            / (quadrants_per_turn * 2f64.powi((self.spec.fine_bits + self.spec.frac_bits) as i32))
    }

    /// Updates after which the start transient (every state 0, the first update's output
    /// 0, then a step to the running speed) has decayed to 0.01 % of the step, used to leave
    /// the start out of `simulate`'s statistics: tracking ln(10^4) / (zeta w_n) (the decay
    /// envelope of the second-order loop) in updates; diff_lpf and kalman the first-order
    /// decay (1 - a)^n <= 10^-4 with a the (steady-state) gain; lsq M (its history is full
    /// after M updates); each + 1 for the first update, which only primes the history.
    /// 0.01 %, not the 2 % of [`settle_updates`](Self::settle_updates): at 300 rpm a 2 %
    /// residue is 1,800 LSB per period, far above the noise the statistics are meant to show.
    pub fn warmup_updates(&self) -> u64 {
        let c = (1u64 << COEF_FRAC) as f64;
        let decay = 1e4f64.ln();
        let first_order = |a: i64| {
            let a = (a as f64 / c).clamp(1e-9, 1.0);
            if a >= 1.0 {
                1
            } else {
                (-decay / (1.0 - a).ln()).ceil() as u64
            }
        };
        1 + match &self.consts {
            MethodConsts::DiffLpf { a } => first_order(*a),
            MethodConsts::Kalman { gains } => first_order(gains.last().copied().unwrap_or(0)),
            MethodConsts::Lsq { n, .. } => n.len() as u64,
            MethodConsts::Tracking { .. } => {
                let wn = std::f64::consts::TAU * self.spec.bandwidth_hz;
                (decay / (std::f64::consts::FRAC_1_SQRT_2 * wn) * self.spec.rate_hz).ceil() as u64
            }
        }
    }

    /// The estimator's lag behind a speed ramp (constant acceleration), in update periods,
    /// once its start transient has gone: the output at the update of tick k equals the true
    /// speed at k - lag (`theta(k)` is the position register at the tick; the output leaves
    /// [`latency`](Self::latency) clocks later). From the quantized constants:
    /// * diff_lpf, kalman: the difference is the mean speed over the last period (1/2),
    ///   and the first-order filter X += a (U - X) delays a ramp by (1 - a) / a (its group
    ///   delay at DC); kalman with its steady-state gain K_inf.
    /// * lsq: v = sum h_i x_i with sum h_i = 0 and sum h_i t_i = 1 gives, on x = A t^2 / 2,
    ///   A sum h_i t_i^2 / 2: the speed at t* = sum n_i t_i^2 / (2 sum n_i t_i); the lag is
    ///   M - t* ((M - 1) / 2 for a line; -1 for order >= 2, which is exact on a parabola
    ///   and evaluated one period ahead).
    /// * tracking: with a constant acceleration A the error settles at e = A / beta, and
    ///   Theta's step A (k + 1/2) = W + alpha e gives W = A (k + 1/2 - alpha / beta): a lag
    ///   of alpha / beta - 1/2 (2 zeta / w_n - T / 2 in time).
    pub fn lag_periods(&self) -> f64 {
        let c = (1u64 << COEF_FRAC) as f64;
        let first_order = |a: i64| {
            let a = a as f64 / c;
            0.5 + (1.0 - a) / a
        };
        match &self.consts {
            MethodConsts::DiffLpf { a } => first_order(*a),
            MethodConsts::Kalman { gains } => first_order(gains.last().copied().unwrap_or(1)),
            MethodConsts::Lsq { n, .. } => {
                let (s1, s2) = n.iter().enumerate().fold((0.0, 0.0), |(s1, s2), (i, &ni)| {
                    let t = (i + 1) as f64;
                    (s1 + ni as f64 * t, s2 + ni as f64 * t * t)
                });
                n.len() as f64 - s2 / (2.0 * s1)
            }
            MethodConsts::Tracking { alpha, beta } => *alpha as f64 / *beta as f64 - 0.5,
        }
    }

    /// [`lag_periods`](Self::lag_periods) plus the output latency, in seconds: how far
    /// `out_velocity` trails the speed of the position it is given on a ramp.
    pub fn lag_s(&self) -> f64 {
        (self.lag_periods() * self.period_clocks as f64 + self.latency() as f64)
            / self.spec.clock_hz
    }

    /// Updates after a speed step until the tracking loop's velocity stays within 2 % of
    /// the step (from 4 / (zeta w_n)); 0 for the other methods.
    pub fn settle_updates(&self) -> u64 {
        match self.spec.method {
            Method::Tracking => {
                let wn = std::f64::consts::TAU * self.spec.bandwidth_hz;
                (4.0 / (std::f64::consts::FRAC_1_SQRT_2 * wn) * self.spec.rate_hz).ceil() as u64
            }
            _ => 0,
        }
    }
}

/// The block's entry in the registry (`crate::blocks::registry`).
pub const BLOCK: crate::blocks::registry::BlockDef = crate::blocks::registry::BlockDef::report_only(
    "velocity",
    "velocity estimator",
    crate::report::jobs::velocity_job,
);
