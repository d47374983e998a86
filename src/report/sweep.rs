//! Accuracy sweep of the bit-accurate datapath against exact atan2 of the same inputs.
//!
//! # What is swept
//!
//! Every input pair (sin, cos) of the A-bit signed input plane whose magnitude is at least
//! 1/8 of full scale (sin^2 + cos^2 >= (2^(A-1)/8)^2) for A <= [`EXHAUSTIVE_MAX_WIDTH`];
//! above that a stated dense sample (see [`SweepPlan`]).
//!
//! The quadrant mapping (thesis Table 2-3) makes the datapath's fine angle a function of
//! the mapped first-quadrant vector (x', y') alone, and the exact angle of (sin, cos) is
//! q * 90 deg + atan2(y', x') exactly. So the sweep runs over the mapped vectors
//! 0 <= x', y' <= 2^(A-1) once and weighs each by the number of quadrants whose image holds
//! it (1 to 4): that is every input pair, each counted once, at a quarter of the work.
//! [`ErrAcc::add_pair`] does the same for a literal (sin, cos, p) triple and gives identical
//! numbers (used to cross-check the model against the rust-hdl simulation).
//!
//! # Error of one sample
//!
//! The angle is measured in fine LSB (2^-F quadrant). With q the sample's quadrant and
//! p the datapath's electrical angle (F + 2 bits), the error is
//! `e = wrap((p - q 2^F) mod 2^(F+2) - atan2(y', x') 2^F / (pi/2))`, wrapped into
//! [-2^(F+1), 2^(F+1)). Sums of e and e^2 are accumulated as integers in units of 2^-40
//! (LSB and LSB^2), so every figure is independent of the order of summation: the same
//! numbers for any thread count, for the weighted and the literal sweep.
use crate::blocks::cordic::model::{map, quadrant};
use crate::blocks::mask;
use crate::config::Derived;
use rayon::prelude::*;
use std::f64::consts::FRAC_PI_2;

/// Largest input width swept exhaustively.
pub const EXHAUSTIVE_MAX_WIDTH: u32 = 14;

/// Fixed-point scale of the accumulated sums (2^40).
const SUM_SCALE: f64 = (1u64 << 40) as f64;

/// Number of angle bins over one quadrant for the error-against-angle curve.
pub const ANGLE_BINS: usize = 900;

/// Which input pairs a sweep covers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SweepPlan {
    /// Input width A.
    pub width: u32,
    /// Stride between swept values along each mapped axis (1 = exhaustive).
    pub stride: u32,
}

impl SweepPlan {
    /// Exhaustive up to 14 bits; above that every 2^(A-14)-th value along each axis.
    pub fn for_width(width: u32) -> SweepPlan {
        SweepPlan {
            width,
            stride: 1 << width.saturating_sub(EXHAUSTIVE_MAX_WIDTH),
        }
    }

    /// Whether every input pair is covered.
    pub fn exhaustive(&self) -> bool {
        self.stride == 1
    }

    /// One sentence describing the input set.
    pub fn describe(&self) -> String {
        let a = self.width;
        let h = 1u64 << (a - 1);
        if self.exhaustive() {
            format!(
                "every input pair (sin, cos) of the {a}-bit signed input plane with sin^2 + cos^2 >= ({}/8)^2, i.e. magnitude at least 1/8 of full scale (exhaustive; swept as the mapped first-quadrant vectors weighted by the number of quadrants that map onto them)",
                h
            )
        } else {
            let k = self.stride;
            format!(
                "a dense sample of the {a}-bit input plane (not exhaustive): mapped first-quadrant vectors (x', y') with x' = {k} i and y' = {k} j + (i mod {k}), 0 <= x', y' <= {h}, magnitude at least {}/8 (1/8 of full scale), each weighted by the number of quadrants that map onto it; every residue of y' mod {k} occurs",
                h
            )
        }
    }
}

/// Order-independent accumulator of the error of many samples.
#[derive(Clone, Debug, PartialEq)]
pub struct ErrAcc {
    /// Samples counted (input pairs, with multiplicity).
    pub count: u64,
    /// Samples rejected by the magnitude monitor (not in the error figures).
    pub rejected: u64,
    /// Largest |e| in LSB (bits of the f64), and the mapped vector (x', y') where it occurs
    /// first in (x', y') order.
    max: Option<(u64, (u32, u32))>,
    /// Sum of e in units of 2^-40 LSB.
    sum: i128,
    /// Sum of e^2 in units of 2^-40 LSB^2.
    sum_sq: u128,
    /// Per-angle-bin (min e, max e) over one quadrant, when requested.
    bins: Option<Vec<(f64, f64)>>,
}

impl ErrAcc {
    /// Empty accumulator; `bins` keeps the error-against-angle envelope.
    pub fn new(bins: bool) -> ErrAcc {
        ErrAcc {
            count: 0,
            rejected: 0,
            max: None,
            sum: 0,
            sum_sq: 0,
            bins: bins.then(|| vec![(f64::INFINITY, f64::NEG_INFINITY); ANGLE_BINS]),
        }
    }

    #[inline]
    fn add(&mut self, e: f64, a0: f64, f: u32, mx: u32, my: u32, weight: u64) {
        self.count += weight;
        self.sum += (e * SUM_SCALE).round() as i128 * weight as i128;
        self.sum_sq += (e * e * SUM_SCALE).round() as u128 * weight as u128;
        let mag = e.abs().to_bits();
        let better = match self.max {
            None => true,
            Some((m, at)) => mag > m || (mag == m && (mx, my) < at),
        };
        if better {
            self.max = Some((mag, (mx, my)));
        }
        if let Some(b) = &mut self.bins {
            let k = ((a0 / (1u64 << f) as f64) * ANGLE_BINS as f64) as usize;
            let slot = &mut b[k.min(ANGLE_BINS - 1)];
            slot.0 = slot.0.min(e);
            slot.1 = slot.1.max(e);
        }
    }

    /// Adds one literal sample: input (sin, cos) and the datapath's electrical angle `p`
    /// (F + 2 bits, 2^-F quadrant); `mag_ok` false counts it as rejected.
    pub fn add_pair(&mut self, d: &Derived, sin: i32, cos: i32, p: u64, mag_ok: bool) {
        if !mag_ok {
            self.rejected += 1;
            return;
        }
        let f = d.fine_bits;
        let q = quadrant(sin, cos) as u64;
        let (mx, my) = map(sin, cos);
        let fine = p.wrapping_sub(q << f) & mask(f + 2);
        let a0 = exact_lsb(mx, my, f);
        self.add(wrap(fine as f64 - a0, f), a0, f, mx as u32, my as u32, 1);
    }

    /// Merges another accumulator (order-independent).
    pub fn merge(&mut self, o: &ErrAcc) {
        self.count += o.count;
        self.rejected += o.rejected;
        self.sum += o.sum;
        self.sum_sq += o.sum_sq;
        if let Some((m, at)) = o.max {
            let better = match self.max {
                None => true,
                Some((sm, sat)) => m > sm || (m == sm && at < sat),
            };
            if better {
                self.max = Some((m, at));
            }
        }
        if let (Some(a), Some(b)) = (&mut self.bins, &o.bins) {
            for (x, y) in a.iter_mut().zip(b) {
                x.0 = x.0.min(y.0);
                x.1 = x.1.max(y.1);
            }
        }
    }

    /// Largest |error| in LSB (0 without samples).
    pub fn max_lsb(&self) -> f64 {
        self.max.map(|(m, _)| f64::from_bits(m)).unwrap_or(0.0)
    }

    /// RMS error in LSB.
    pub fn rms_lsb(&self) -> f64 {
        if self.count == 0 {
            return 0.0;
        }
        (self.sum_sq as f64 / SUM_SCALE / self.count as f64).sqrt()
    }

    /// Mean (signed) error in LSB.
    pub fn mean_lsb(&self) -> f64 {
        if self.count == 0 {
            return 0.0;
        }
        self.sum as f64 / SUM_SCALE / self.count as f64
    }

    /// An input pair (sin, cos) where the largest error occurs (the first of its mapped
    /// vector's quadrants in the order 1, 2, 3, 4), for width `a`.
    pub fn worst_input(&self, a: u32) -> Option<(i64, i64)> {
        let (_, (mx, my)) = self.max?;
        let (mx, my) = (mx as i64, my as i64);
        let top = (1i64 << (a - 1)) - 1;
        Some(if mx <= top && my <= top {
            (my, mx)
        } else if mx <= top && my >= 1 {
            (mx, -my)
        } else if mx >= 1 && my >= 1 {
            (-my, -mx)
        } else {
            (-mx, my)
        })
    }

    /// Error envelope per angle bin: (bin centre in degrees of electrical angle within the
    /// quadrant, min e, max e) for bins that hold samples.
    pub fn envelope(&self) -> Vec<(f64, f64, f64)> {
        let Some(b) = &self.bins else {
            return Vec::new();
        };
        b.iter()
            .enumerate()
            .filter(|(_, (lo, hi))| lo <= hi)
            .map(|(k, &(lo, hi))| ((k as f64 + 0.5) * 90.0 / ANGLE_BINS as f64, lo, hi))
            .collect()
    }
}

/// Exact angle of the mapped first-quadrant vector in fine LSB (2^-F quadrant).
#[inline]
pub fn exact_lsb(mx: i64, my: i64, f: u32) -> f64 {
    (my as f64).atan2(mx as f64) * ((1u64 << f) as f64 / FRAC_PI_2)
}

/// Wraps an angle difference in LSB into [-2^(F+1), 2^(F+1)).
#[inline]
fn wrap(e: f64, f: u32) -> f64 {
    let half = (1u64 << (f + 1)) as f64;
    if e >= half {
        e - 2.0 * half
    } else if e < -half {
        e + 2.0 * half
    } else {
        e
    }
}

/// Lanes processed together by the inner loop (auto-vectorized).
const LANES: usize = 16;

/// The datapath of one design specialised for sweeping: the mapper's output (x', y') in,
/// the fine angle (F + 2 bits, quadrant 0) and the magnitude check out. Every word is held
/// in an i32 and sign-extended from its configured width after each operation, exactly as
/// the model (`cordic` + `combine`) masks its 64-bit words.
#[derive(Clone, Debug)]
pub struct Kernel {
    xy_shift: u32,
    z_shift: u32,
    guard: u32,
    table: Vec<i32>,
    z_round: i32,
    z_guard: u32,
    z_mask: u32,
    p_mask: u32,
    xy_mask: u32,
    min_magnitude: u64,
    f: u32,
}

impl Kernel {
    /// Kernel for a design.
    pub fn new(d: &Derived) -> Kernel {
        Kernel {
            xy_shift: 32 - d.xy_width,
            z_shift: 32 - d.z_width,
            guard: d.xy_guard,
            table: d.atan_table.iter().map(|&a| a as i32).collect(),
            z_round: 1 << (d.z_guard - 1),
            z_guard: d.z_guard,
            z_mask: mask(d.z_width) as u32,
            p_mask: mask(d.fine_bits + 2) as u32,
            xy_mask: mask(d.xy_width) as u32,
            min_magnitude: d.min_magnitude,
            f: d.fine_bits,
        }
    }

    /// Fine angle and magnitude check of LANES mapped vectors.
    #[inline(always)]
    fn chunk(&self, mx: &[i32; LANES], my: &[i32; LANES], out: &mut [(u32, bool); LANES]) {
        let (s, zs) = (self.xy_shift, self.z_shift);
        let sx = |v: i32| v.wrapping_shl(s).wrapping_shr(s);
        let sz = |v: i32| v.wrapping_shl(zs).wrapping_shr(zs);
        let mut x = [0i32; LANES];
        let mut y = [0i32; LANES];
        let mut z = [0i32; LANES];
        for l in 0..LANES {
            x[l] = sx(mx[l].wrapping_shl(self.guard));
            y[l] = sx(my[l].wrapping_shl(self.guard));
        }
        for (i, &a) in self.table.iter().enumerate() {
            let i = i as u32;
            for l in 0..LANES {
                let xs = x[l].wrapping_shr(i);
                let ys = y[l].wrapping_shr(i);
                // m = -1 when y < 0 (rotate up), 0 otherwise; (v ^ m) - m = m ? -v : v.
                let m = y[l] >> 31;
                x[l] = sx(x[l].wrapping_add((ys ^ m).wrapping_sub(m)));
                y[l] = sx(y[l].wrapping_sub((xs ^ m).wrapping_sub(m)));
                z[l] = sz(z[l].wrapping_add((a ^ m).wrapping_sub(m)));
            }
        }
        for l in 0..LANES {
            let zr = (z[l].wrapping_add(self.z_round) as u32) & self.z_mask;
            let fine = (zr >> self.z_guard) & self.p_mask;
            let mag = (x[l] as u32 & self.xy_mask) as u64;
            out[l] = (fine, mag >= self.min_magnitude);
        }
    }

    /// Fine angle (quadrant 0, F + 2 bits) and magnitude check for each mapped vector.
    pub fn run(&self, mx: &[i32], my: &[i32], out: &mut Vec<(u32, bool)>) {
        out.clear();
        let n = mx.len().min(my.len());
        let mut bx = [0i32; LANES];
        let mut by = [0i32; LANES];
        let mut bo = [(0u32, false); LANES];
        let mut k = 0;
        while k < n {
            let m = (n - k).min(LANES);
            bx[..m].copy_from_slice(&mx[k..k + m]);
            by[..m].copy_from_slice(&my[k..k + m]);
            for l in m..LANES {
                bx[l] = 0;
                by[l] = 0;
            }
            self.chunk(&bx, &by, &mut bo);
            out.extend_from_slice(&bo[..m]);
            k += m;
        }
    }

    /// Fine bits F.
    pub fn fine_bits(&self) -> u32 {
        self.f
    }
}

/// Number of quadrants whose mapped image holds (x', y'), with H = 2^(A-1):
/// Q1 [0,H-1]x[0,H-1], Q2 [0,H-1]x[1,H], Q3 [1,H]x[1,H], Q4 [1,H]x[0,H-1].
#[inline]
fn multiplicity(mx: u32, my: u32, h: u32) -> u64 {
    let xl = mx < h;
    let xh = mx >= 1;
    let yl = my < h;
    let yh = my >= 1;
    (xl && yl) as u64 + (xl && yh) as u64 + (xh && yh) as u64 + (xh && yl) as u64
}

/// Sweeps every design in `designs` (all with the same input width and fine bits) over the
/// plan's input set, in parallel over rows; `bins_for` selects the design (index) whose
/// error-against-angle envelope is kept; `tick` is called once per finished row.
pub fn sweep(
    designs: &[&Derived],
    plan: SweepPlan,
    bins_for: Option<usize>,
    tick: &(dyn Fn() + Sync),
) -> Vec<ErrAcc> {
    let Some(first) = designs.first() else {
        return Vec::new();
    };
    let f = first.fine_bits;
    let h = 1u32 << (plan.width - 1);
    let k = plan.stride;
    let r2 = {
        let r = (h / 8) as u64;
        r * r
    };
    let kernels: Vec<Kernel> = designs.iter().map(|d| Kernel::new(d)).collect();
    let rows: Vec<u32> = (0..=h / k).map(|i| i * k).collect();
    let empty = || -> Vec<ErrAcc> {
        (0..designs.len())
            .map(|i| ErrAcc::new(bins_for == Some(i)))
            .collect()
    };
    let merge_all = |mut a: Vec<ErrAcc>, b: Vec<ErrAcc>| {
        for (t, r) in a.iter_mut().zip(&b) {
            t.merge(r);
        }
        a
    };
    // Every merge is order-independent (integer sums, max with a fixed tie-break, min/max
    // envelopes), so the split among threads does not change any figure.
    rows.par_iter()
        .fold(
            || (empty(), Buffers::default()),
            |(mut accs, mut b), &mx| {
                b.xs.clear();
                b.ys.clear();
                b.exact.clear();
                let mut my = (mx / k) % k;
                while my <= h {
                    if (mx as u64 * mx as u64) + (my as u64 * my as u64) >= r2 {
                        b.xs.push(mx as i32);
                        b.ys.push(my as i32);
                        b.exact.push(exact_lsb(mx as i64, my as i64, f));
                    }
                    my += k;
                }
                for (kern, acc) in kernels.iter().zip(accs.iter_mut()) {
                    kern.run(&b.xs, &b.ys, &mut b.out);
                    for (j, &(fine, ok)) in b.out.iter().enumerate() {
                        let (x, y) = (b.xs[j] as u32, b.ys[j] as u32);
                        let w = multiplicity(x, y, h);
                        if !ok {
                            acc.rejected += w;
                            continue;
                        }
                        let a0 = b.exact[j];
                        acc.add(wrap(fine as f64 - a0, f), a0, f, x, y, w);
                    }
                }
                tick();
                (accs, b)
            },
        )
        .map(|(a, _)| a)
        .reduce(empty, merge_all)
}

/// Per-thread work buffers of [`sweep`].
#[derive(Default)]
struct Buffers {
    xs: Vec<i32>,
    ys: Vec<i32>,
    exact: Vec<f64>,
    out: Vec<(u32, bool)>,
}

/// Number of rows [`sweep`] processes (for progress bars).
pub fn rows(plan: SweepPlan) -> u64 {
    let h = 1u64 << (plan.width - 1);
    h / plan.stride as u64 + 1
}
