//! The ellipse fit's serial solver (`blocks::correction::fit_solve::FitSolve`) on its own,
//! against the integer specification `blocks::correction::fit::solve`, on window sums at the
//! limits of the bounds its module doc derives its register widths from (A = 16, N up to
//! 2^24, |d| up to 2^16 - 1): the largest variance, the largest mean of either sign, the
//! largest correlation (the clamp of S), a constant track (refused), one sample, and random
//! windows of a few weighted points drawn towards those limits. Every accepted solve loads
//! the specification's offsets, gains and cross code exactly `SOLVE_CYCLES` clocks after
//! its start and raises `done` for that clock only; a refused one loads nothing. rust-hdl,
//! Icarus and Verilator agree on every output at every clock.
//!
//! The windows the calibration loop produces (`tests/blocks/correction_fit_rtl.rs`) stay far
//! inside these bounds; this test is what holds each narrowed register (m: 24 bits, Amp:
//! 25, V: 49, C: 50, Amp_s Cc: 40, ...) to its bound.
use crate::common;
use sinedec::blocks::correction::fit::{self, FitParams, Sums};
use sinedec::blocks::correction::fit_solve::{FitSolve, SolveConsts, SOLVE_CYCLES};
use sinedec::blocks::correction::CorrectionParams;
use sinedec::cosim::stimulus::SplitMix64;
use sinedec::verify::Simulators;

const A: u32 = 16;
const GF: u32 = 15;
/// The largest |d| = |x - b_ref| of A-bit samples and offsets.
const M: i128 = (1 << A) - 1;
const H: i128 = 1 << (A - 1);
const N_MAX: i128 = 1 << 24;

fn params() -> FitParams {
    let full = (1u32 << (A - 1)) - 1;
    FitParams {
        adc_width: A,
        gain_frac_bits: GF,
        target_amplitude: full * 3 / 4,
        periods: 1,
        min_samples: 1,
        min_amplitude: full / 10,
    }
}

/// One window: weighted points (d_s, d_c, count) and the window's b_ref.
struct Case {
    name: String,
    points: Vec<(i128, i128, i128)>,
    b_ref: [i64; 2],
}

impl Case {
    fn sums(&self) -> Sums {
        let mut s = Sums::default();
        for &(ds, dc, w) in &self.points {
            assert!(ds.abs() <= M && dc.abs() <= M && w > 0, "{}", self.name);
            s.n += w;
            s.s1[0] += w * ds;
            s.s1[1] += w * dc;
            s.s2[0] += w * ds * ds;
            s.s2[1] += w * dc * dc;
            s.sc += w * ds * dc;
        }
        assert!(s.n <= N_MAX, "{}", self.name);
        s
    }
}

fn case(name: &str, points: &[(i128, i128, i128)], b_ref: [i64; 2]) -> Case {
    Case {
        name: name.to_string(),
        points: points.to_vec(),
        b_ref,
    }
}

fn cases() -> Vec<Case> {
    let w = N_MAX / 4;
    let mut v = vec![
        // Full-scale square waves in quadrature: the largest V (2^46) at N = 2^24, C = 0.
        case(
            "max_variance",
            &[(H, H, w), (-H, H, w), (H, -H, w), (-H, -H, w)],
            [0, 0],
        ),
        // Sine between 0 and 2^16 - 1 around b_ref = -2^15: mean and variance both large.
        case(
            "max_mean_and_variance",
            &[(0, H, w), (M, -H, w), (0, -H, w), (M, H, w)],
            [-(H as i64), 0],
        ),
        case(
            "min_mean_and_variance",
            &[(H, 0, w), (-H, -M, w), (-H, 0, w), (H, -M, w)],
            [0, H as i64 - 1],
        ),
        // A constant track at |d| = 2^16 - 1: the largest |m| (2^24 - 256), V = 0: refused.
        case(
            "max_mean_constant",
            &[(M, M, N_MAX - 1), (M, -M, 1)],
            [-(H as i64), 0],
        ),
        case("min_mean_constant", &[(-M, M, N_MAX)], [H as i64 - 1, 0]),
        // Fully correlated and anti-correlated tracks: S at its clamp, Cc at its least.
        case("correlated", &[(H, H, w), (-H, -H, w)], [0, 0]),
        case("anti_correlated", &[(H, -H, w), (-H, H, w)], [0, 0]),
        // Σd_s d_c = -2^28 (N = 2^12): its low 28 bits are zero, so |Σd_s d_c| takes the
        // carry from the low half of its negation into the high half; a slight
        // anti-correlation, so S is not at its clamp and the carry changes k.
        case(
            "carry_into_the_high_half_of_sc",
            &[
                (H, -8, 1 << 10),
                (-H, 8, 1 << 10),
                (4, H, 1 << 10),
                (-4, -H, 1 << 10),
            ],
            [0, 0],
        ),
        case("one_sample", &[(M, -M, 1)], [0, 0]),
        // A small variance around a large mean: refused at the amplitude check.
        case("small", &[(3276, 3276, w), (-3276, -3276, 3)], [5, -5]),
    ];
    let mut r = SplitMix64(0x5017e5);
    let pick = |r: &mut SplitMix64| -> i128 {
        match r.range(0, 6) {
            0 => M,
            1 => -M,
            2 => H,
            3 => -H,
            4 => 0,
            _ => r.range(-(M as i64), M as i64) as i128,
        }
    };
    for i in 0..32 {
        let k = r.range(2, 6) as usize;
        let mut points = Vec::new();
        let mut left = if i % 2 == 0 {
            N_MAX
        } else {
            1 << r.range(4, 24)
        };
        for j in 0..k {
            let cnt = if j + 1 == k {
                left
            } else {
                r.range(1, left as i64 / 2 + 1) as i128
            };
            left -= cnt;
            if cnt > 0 {
                points.push((pick(&mut r), pick(&mut r), cnt));
            }
            if left <= 1 {
                break;
            }
        }
        let b = |r: &mut SplitMix64| r.range(-(H as i64), H as i64 - 1);
        let b_ref = [b(&mut r), b(&mut r)];
        v.push(Case {
            name: format!("random_{i}"),
            points,
            b_ref,
        });
    }
    v
}

fn to_u64(v: i128) -> u64 {
    v as i64 as u64
}

#[test]
fn solver_rtl_equals_the_specification_at_the_bounds_of_its_widths() {
    let p = params();
    let cp = CorrectionParams::identity(A, GF).expect("params");
    let k = SolveConsts {
        adc_width: A,
        gain_frac_bits: GF,
        target_amplitude: p.target_amplitude,
        min_amplitude: p.min_amplitude,
    };
    let cases = cases();
    let gap = SOLVE_CYCLES as usize + 6;
    let mut rows: Vec<Vec<u64>> = vec![vec![1, 0, 0, 0, 0, 0, 0, 0, 0, 0]; 2];
    let mut starts = Vec::new();
    for c in &cases {
        let s = c.sums();
        starts.push(rows.len());
        rows.push(vec![
            0,
            1,
            s.n as u64,
            to_u64(s.s1[0]),
            to_u64(s.s1[1]),
            to_u64(s.s2[0]),
            to_u64(s.s2[1]),
            to_u64(s.sc),
            c.b_ref[0] as u64,
            c.b_ref[1] as u64,
        ]);
        rows.extend(vec![vec![0u64; 10]; gap]);
    }
    let out = &common::simulators_agree(
        FitSolve::new(&cp, k),
        "fit_solver",
        "fit_solver",
        &rows,
        Simulators::ALL,
    );
    let word = |v: u64| v as u32 as i32 as i64;
    // Coefficients in use: the configured ones (identity) until the first accepted solve.
    let mut cur = (0i64, 0i64, 1u64 << GF, 1u64 << GF, 0i64);
    let (mut accepted, mut refused) = (0, 0);
    for (c, &j) in cases.iter().zip(&starts) {
        let want = fit::solve(&p, c.b_ref, &c.sums());
        let due = j + SOLVE_CYCLES as usize;
        let before = cur;
        if let Some(co) = want {
            cur = (co.offset[0], co.offset[1], co.gain[0], co.gain[1], co.cross);
            accepted += 1;
        } else {
            refused += 1;
        }
        for (i, o) in out.iter().enumerate().take(j + gap + 1).skip(j) {
            let done = o[1] == 1;
            assert_eq!(
                done,
                want.is_some() && i == due,
                "{}: done at clock {} (start {j}, accepted: {})",
                c.name,
                i - j,
                want.is_some()
            );
            let k = if o[7] == 1 {
                -(o[6] as i64)
            } else {
                o[6] as i64
            };
            let got = (word(o[2]), word(o[3]), o[4], o[5], k);
            let exp = if i >= due { cur } else { before };
            assert_eq!(got, exp, "{}: coefficients at clock {}", c.name, i - j);
        }
    }
    // Both outcomes occur, so neither branch above is vacuous.
    assert!(
        accepted >= 10 && refused >= 3,
        "{accepted} accepted, {refused} refused"
    );
}

/// The solver's remainder zero test (`xr` in `fit_solve.rs`): u_r + u_d = 0 (mod 2^w)
/// exactly when (u_r ^ u_d) == (u_r | u_d) << 1 (mod 2^w), with no carry chain. Checked for
/// every pair of 9-bit words. The case it decides (a truncating division of a negative
/// quotient with a zero remainder, Cq of an exact window) moves Cq by one, which an
/// accepted window's coefficients almost never show (S moves by 2^16 / (Amp_s Amp_c) per
/// unit of C, under 2^-23 above this test's minimum amplitude), so the windows above do not
/// catch a wrong test (with `&` for `|` they pass); this does.
#[test]
fn the_carry_free_zero_test_is_a_plus_b_equals_zero() {
    let w = 9;
    let m = (1u32 << w) - 1;
    for a in 0..=m {
        for b in 0..=m {
            let zero = (a + b) & m == 0;
            let test = (a ^ b) & m == ((a | b) << 1) & m;
            assert_eq!(zero, test, "a = {a}, b = {b}");
        }
    }
}
