//! The velocity datapath's derived widths and constants ([`Layout`]), from
//! [`VelocityParams`] for the rust-hdl block ([`super::hdl::Velocity`]) and for
//! [`VelocityParams::latency`].
use super::parts::VelMul;
use super::{MethodConsts, VelocityParams, COEF_FRAC};
use crate::error::{Error, Result};

/// Derived widths and constants of the datapath (all from [`VelocityParams`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Layout {
    /// Width of the multiplier's operand a (signed).
    pub a_width: u32,
    /// Width of the coefficients (signed).
    pub b_width: u32,
    /// Width of the accumulator X / W / P and of the multiplier's result (signed).
    pub acc_width: u32,
    /// Width of tracking's predicted position Theta (Wp + S + G).
    pub theta_width: u32,
    /// Multiplies per update m.
    pub mults: u32,
    /// Rounding shift of every multiply: C, or B for lsq (whose integer taps are stored
    /// as n_i 2^B, so that n_i r_i comes out exact with the reciprocal's shift).
    pub shift: u32,
    /// The coefficient ROM (kalman: the gain table; else one word per multiply).
    pub coefs: Vec<i64>,
}

fn unsigned_bits(v: u128) -> u32 {
    128 - v.leading_zeros()
}

impl Layout {
    /// The datapath of `p`; an error if a word would not fit the 64-bit containers (checked
    /// by [`VelocityParams::new`] too, so only hand-made parameters fail here).
    pub fn new(p: &VelocityParams) -> Result<Layout> {
        let l = Layout::build(p);
        l.check()?;
        if p.latency() >= p.period_clocks {
            return Err(Error::block_params(
                "velocity",
                format!(
                    "an update takes {} clocks, the update period only {}",
                    p.latency(),
                    p.period_clocks
                ),
            ));
        }
        Ok(l)
    }

    /// An error if a word would not fit the 64-bit containers.
    pub(super) fn check(&self) -> Result<()> {
        let l = self;
        if l.a_width > 64 || l.acc_width > 64 || l.theta_width > 64 || l.b_width > 64 {
            return Err(Error::block_params(
                "velocity",
                format!(
                    "internal words of {} / {} / {} / {} bits (operand, accumulator, Theta, \
                     coefficient) exceed 64: lower frac_bits or the maximum speed",
                    l.a_width, l.acc_width, l.theta_width, l.b_width
                ),
            ));
        }
        Ok(())
    }

    /// Booth digits n of one multiply ([`VelMul::steps`]): the multiplier runs n + 1
    /// clocks after its start.
    pub fn mul_steps(&self) -> u32 {
        VelMul::steps(self.b_width)
    }

    /// The datapath of `p`, unchecked (widths may exceed 64 bits).
    pub(super) fn build(p: &VelocityParams) -> Layout {
        let wp = p.pos_width;
        let ws = p.state_width;
        let tw = wp + p.state_frac();
        let c = COEF_FRAC;
        let wide = |v: &[i64]| v.iter().map(|&k| k as i128).collect::<Vec<i128>>();
        let (a_width, acc_width, mults, shift, coefs) = match &p.consts {
            MethodConsts::DiffLpf { a } => (ws, ws, 1, c, vec![*a as i128]),
            MethodConsts::Kalman { gains } => (ws, ws, 1, c, wide(gains)),
            MethodConsts::Tracking { alpha, beta } => {
                (tw, ws, 2, c, vec![*beta as i128, *alpha as i128])
            }
            MethodConsts::Lsq {
                n, recip, shift, ..
            } => {
                let pw = shift + 1;
                let b = (*shift).min(64);
                let mut k: Vec<i128> = n[..n.len() - 1]
                    .iter()
                    .map(|&v| (v as i128).saturating_mul(1i128 << b))
                    .collect();
                k.push(*recip as i128);
                (wp.max(pw), ws.max(pw), n.len() as u32, *shift, k)
            }
        };
        let b_width = coefs
            .iter()
            .map(|&k| unsigned_bits(k.unsigned_abs()) + 1)
            .max()
            .unwrap_or(2)
            .max(2);
        // Stored as i64: exact whenever b_width <= 64 (`check`).
        let coefs = coefs.iter().map(|&k| k as i64).collect();
        Layout {
            a_width,
            b_width,
            acc_width,
            theta_width: tw,
            mults,
            shift,
            coefs,
        }
    }
}
