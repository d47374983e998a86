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
//!
//! The solver's program, `fit_solve::TABLE`, is also run on its own by a small interpreter
//! with exact integers (each operation, source and destination as `fit_solve.rs` documents
//! it, every stored value held to its register's width), which must equal `fit::solve` on
//! these windows and on random ones.
use crate::common;
use proptest::prelude::*;
use sinedec::blocks::correction::fit::{self, Coefs, FitParams, Sums};
use sinedec::blocks::correction::fit_solve::{
    Dst, FitSolve, Op, Row, Sign, SolveConsts, Src, SOLVE_CYCLES, TABLE,
};
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

/// A row's result as the next row may load it directly.
#[derive(Clone, Copy, Debug)]
enum Last {
    None,
    Quot { mag: i128, neg: bool },
    Prod(i128),
    Root(i128),
}

/// `v`, asserted to fit an unsigned register of `bits` bits.
fn unsigned(v: i128, bits: u32, what: &str) -> i128 {
    assert!(
        (0..1i128 << bits).contains(&v),
        "{what} = {v} overflows {bits} bits"
    );
    v
}

/// `v`, asserted to fit a two's complement register of `bits` bits.
fn signed(v: i128, bits: u32, what: &str) -> i128 {
    let h = 1i128 << (bits - 1);
    assert!((-h..h).contains(&v), "{what} = {v} overflows {bits} bits");
    v
}

/// The solve's named values an operand may be.
struct Named {
    m: [i128; 2],
    v: [i128; 2],
    amp: [i128; 2],
    cc: i128,
    sn: i128,
    cs: i128,
    q2: i128,
}

/// Row `i`'s u_x and u_d, after a row whose result was `last`.
fn operands(i: usize, r: &Row, last: Last, s: &Sums, n: &Named, p: &FitParams) -> (i128, i128) {
    let smax = (32768.0 * 15f64.to_radians().sin()).round() as i128;
    let (t, gf) = (p.target_amplitude as i128, p.gain_frac_bits);
    let (m, v, amp, cc) = (n.m, n.v, n.amp, n.cc);
    let a1 = [0, 1].map(|c| unsigned(s.s1[c].abs(), 40, "|sum d|"));
    let prod = || match last {
        Last::Prod(p) => p,
        l => panic!("row {i} loads a product after {l:?}"),
    };
    let clamped = || match last {
        Last::Quot { mag, .. } => mag.min(smax),
        l => panic!("row {i} loads a quotient after {l:?}"),
    };
    let x = match r.x {
        Src::A1s8 => a1[0] << 8,
        Src::A1c8 => a1[1] << 8,
        Src::A2s => s.s2[0],
        Src::A2c => s.s2[1],
        Src::Asc => s.sc.abs(),
        Src::Ms32 => m[0].abs() << 32,
        Src::Mc32 => m[1].abs() << 32,
        Src::Vs2 => 2 * v[0].max(0),
        Src::Vc2 => 2 * v[1].max(0),
        Src::AmpS32 => amp[0] << 32,
        Src::AmpC32 => amp[1] << 32,
        Src::Cmag16 => unsigned(cc.abs(), 48, "|C|") << 16,
        Src::Tgs => t << (gf + 8),
        Src::Tgc => t << (gf + 23),
        Src::T32 => t << 32,
        Src::ProdK => prod() << (gf + 8),
        Src::T30 => unsigned((1 << 30) - prod(), 31, "2^30 - S^2"),
        Src::Scl32 => clamped() << 32,
        other => panic!("row {i}: {other:?} is not a u_x source"),
    };
    let d = match r.d {
        Src::N => s.n,
        Src::Ms => m[0].abs(),
        Src::Mc => m[1].abs(),
        Src::AmpS => amp[0],
        Src::Cs => n.cs,
        Src::Smag => n.sn.abs(),
        Src::Q2 => n.q2,
        Src::One => 1,
        Src::Prod => prod(),
        Src::Scl => clamped(),
        Src::Root => match last {
            Last::Root(q) => q,
            l => panic!("row {i} loads a root after {l:?}"),
        },
        other => panic!("row {i}: {other:?} is not a u_d source"),
    };
    (x, d)
}

/// `table` executed with exact integers: a division of `steps` bits is u_x 2^(steps - 64) /
/// u_d (the quotient below 2^64, as u_x holds it), rounded half away from zero or floored,
/// then signed; a product takes u_x's top 32 bits times u_d; a root is isqrt(u_x). Sources
/// and destinations mean what `fit_solve::Src` and `fit_solve::Dst` say; a value loaded
/// from the row before must be that row's kind of result.
fn interpret(p: &FitParams, b_ref: [i64; 2], s: &Sums, table: &[Row]) -> Option<Coefs> {
    let smax = (32768.0 * 15f64.to_radians().sin()).round() as i128;
    let neg1 = [s.s1[0] < 0, s.s1[1] < 0];
    let (mut m, mut v, mut amp, mut g) = ([0i128; 2], [0i128; 2], [0i128; 2], [0i128; 2]);
    let (mut cc, mut sn, mut sneg, mut cs, mut q2, mut k) = (0i128, 0i128, false, 0, 0, None);
    let offsets = |m: [i128; 2]| {
        [0, 1].map(|c| {
            let r = (m[c].abs() + 128) >> 8;
            b_ref[c] + if neg1[c] { -r } else { r } as i64
        })
    };
    let mut last = Last::None;
    for (i, r) in table.iter().enumerate() {
        if r.check {
            let min = (p.min_amplitude as i128) << 8;
            let lim = 1i64 << (p.adc_width - 1);
            let out = offsets(m).iter().any(|&b| b < -lim || b >= lim);
            if amp[0] < min || amp[1] < min || out {
                return None;
            }
        }
        let (x, d) = operands(
            i,
            r,
            last,
            s,
            &Named {
                m,
                v,
                amp,
                cc,
                sn,
                cs,
                q2,
            },
            p,
        );
        unsigned(x, 64, "u_x");
        unsigned(d, 50, "u_d");
        last = match r.op {
            Op::Div { steps, round, neg } => {
                let neg = match neg {
                    Sign::Pos => false,
                    Sign::SumS => neg1[0],
                    Sign::SumC => neg1[1],
                    Sign::SumSc => s.sc < 0,
                    Sign::CPos => cc >= 0,
                    Sign::SNeg => sneg,
                };
                let num = x << (steps - 64);
                let (q, rem) = (unsigned(num / d, 64, "quotient"), num % d);
                let adj = if round { 2 * rem >= d } else { neg && rem != 0 };
                Last::Quot {
                    mag: q + adj as i128,
                    neg,
                }
            }
            Op::Mul => Last::Prod((x >> 32) * d),
            Op::Sqrt => {
                assert_eq!(d, 1, "row {i}: a root starts from the trial 1");
                Last::Root(fit::isqrt(x))
            }
        };
        let (mag, neg) = match last {
            Last::Quot { mag, neg } => (mag, neg),
            Last::Prod(v) | Last::Root(v) => (v, false),
            Last::None => unreachable!(),
        };
        let q = if neg { -mag } else { mag };
        match r.dst {
            Dst::Next => {}
            Dst::Ms => m[0] = signed(q, 25, "m_s"),
            Dst::Mc => m[1] = signed(q, 25, "m_c"),
            Dst::Vs => v[0] = unsigned(q, 48, "floor(s2_s 2^16 / N)"),
            Dst::Vc => v[1] = unsigned(q, 48, "floor(s2_c 2^16 / N)"),
            Dst::Cq => cc = signed(q, 49, "Cq"),
            Dst::VsLessProd => v[0] = signed(v[0] - q, 49, "V_s"),
            Dst::VcLessProd => v[1] = signed(v[1] - q, 49, "V_c"),
            Dst::C => {
                let p = if neg1[0] ^ neg1[1] { -q } else { q };
                cc = signed(cc - p, 50, "C");
            }
            Dst::AmpS => amp[0] = unsigned(q, 25, "Amp_s"),
            Dst::AmpC => amp[1] = unsigned(q, 25, "Amp_c"),
            Dst::S => (sn, sneg) = (if neg { -mag.min(smax) } else { mag.min(smax) }, neg),
            Dst::Cs => cs = unsigned(q, 16, "Cc"),
            Dst::Gs => g[0] = unsigned(q, 64, "g_s").min(0xffff),
            Dst::Gc => g[1] = unsigned(q, 64, "g_c").min(0xffff),
            Dst::Q2 => q2 = unsigned(q, 40, "Amp_s Cc"),
            Dst::K => k = Some(q.clamp(-0xffff, 0xffff)),
        }
    }
    Some(Coefs {
        offset: offsets(m),
        gain: [g[0] as u64, g[1] as u64],
        cross: k? as i64,
    })
}

#[test]
fn the_table_computes_the_specification_at_the_bounds_of_its_widths() {
    let p = params();
    let mut accepted = 0;
    for c in cases() {
        let (s, b) = (c.sums(), c.b_ref);
        let want = fit::solve(&p, b, &s);
        assert_eq!(interpret(&p, b, &s, &TABLE), want, "{}", c.name);
        accepted += want.is_some() as usize;
    }
    assert!(accepted >= 10, "{accepted} accepted");
}

/// A window of 1 to 5 weighted points of A-bit differences (N <= 2^24), its b_ref and the
/// fit's settings.
fn window() -> impl Strategy<Value = (FitParams, [i64; 2], Sums)> {
    (10u32..=16, 8u32..=15).prop_flat_map(|(a, gf)| {
        let m = (1i64 << a) - 1;
        let h = 1i64 << (a - 1);
        let pt = (-m..=m, -m..=m, 1i64..=1 << 22);
        (
            prop::collection::vec(pt, 1..=5),
            [-h..h, -h..h],
            1u32..h as u32,
            1u32..=(h as u32) / 4,
        )
            .prop_map(move |(pts, b_ref, t, min)| {
                let p = FitParams {
                    adc_width: a,
                    gain_frac_bits: gf,
                    target_amplitude: t,
                    periods: 1,
                    min_samples: 1,
                    min_amplitude: min,
                };
                let mut s = Sums::default();
                for (ds, dc, w) in pts {
                    let (ds, dc, w) = (ds as i128, dc as i128, w as i128);
                    s.n += w;
                    s.s1[0] += w * ds;
                    s.s1[1] += w * dc;
                    s.s2[0] += w * ds * ds;
                    s.s2[1] += w * dc * dc;
                    s.sc += w * ds * dc;
                }
                (p, b_ref, s)
            })
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]
    #[test]
    fn the_table_computes_the_specification_on_random_windows((p, b, s) in window()) {
        prop_assert_eq!(interpret(&p, b, &s, &TABLE), fit::solve(&p, b, &s));
    }
}
