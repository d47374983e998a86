//! Filter designer (src/filter) against independently worked values: closed-form Butterworth
//! poles, textbook bilinear-transform formulas of a second-order section worked by hand, the
//! analytic Butterworth magnitude `1 / (1 + W^(2n))` through the pre-warped frequency map,
//! and hand-quantized coefficients for the error cases.

use proptest::prelude::*;
use sinedec::filter::{
    butterworth_poles, cascade_gain, design, design_with_probes, CoefFormat, FilterError,
    FilterKind, FilterSpec, IdealSection,
};
use std::f64::consts::{PI, SQRT_2};

const FS: f64 = 400_000.0;
/// 18-bit coefficients, 16 fractional bits (Q2.16): fits Cyclone III 18x18 multipliers.
const Q2_16: CoefFormat = CoefFormat {
    width: 18,
    frac: 16,
};

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

fn db(g: f64) -> f64 {
    20.0 * g.log10()
}

/// `20 log10` of the analog Butterworth magnitude at normalised frequency `w`:
/// `|H|^2 = 1 / (1 + w^(2n))`.
fn butter_db(w: f64, n: u32) -> f64 {
    -10.0 * (1.0 + w.abs().powi(2 * n as i32)).log10()
}

/// The digital frequency `f` seen by the analog prototype after pre-warping + bilinear:
/// `T(f) = tan(pi f / fs)` (the common factor `2 fs` cancels in every ratio below).
fn t(f: f64, fs: f64) -> f64 {
    (PI * f / fs).tan()
}

/// Expected gain (dB) of the digital Butterworth designed from `spec` at `f`:
/// LP `W = T/Tc`, HP `W = Tc/T`, BP `W = (T^2 - T1 T2) / (T (T2 - T1))` (the LP->BP map
/// `(s^2 + W0^2)/(s B)` on `s = j T`).
fn expected_db(spec: &FilterSpec, f: f64) -> f64 {
    let fs = spec.sample_rate_hz;
    let w = match spec.kind {
        FilterKind::Lowpass => t(f, fs) / t(spec.corner_hz.unwrap(), fs),
        FilterKind::Highpass => t(spec.corner_hz.unwrap(), fs) / t(f, fs),
        FilterKind::Bandpass => {
            let [f1, f2] = spec.band_hz.unwrap();
            let (t1, t2, tf) = (t(f1, fs), t(f2, fs), t(f, fs));
            (tf * tf - t1 * t2) / (tf * (t2 - t1))
        }
    };
    butter_db(w, spec.order)
}

/// Roots of `z^2 + a1 z + a2` computed here (not with the library): moduli.
fn root_moduli(a1: f64, a2: f64) -> [f64; 2] {
    let d = a1 * a1 - 4.0 * a2;
    if d < 0.0 {
        // complex pair: |z|^2 = product of the roots = a2
        [a2.sqrt(), a2.sqrt()]
    } else {
        let r = d.sqrt();
        [((-a1 + r) / 2.0).abs(), ((-a1 - r) / 2.0).abs()]
    }
}

#[test]
fn analog_poles_order_2_and_4() {
    // Order 2: angles pi(2k+1)/4 for k = 1, 2 -> 3pi/4, 5pi/4: -1/sqrt2 +- j/sqrt2
    // = -0.70710678 +- 0.70710678j.
    let p = butterworth_poles(2);
    let h = 1.0 / SQRT_2;
    assert_eq!(p.len(), 2);
    assert!(
        close(p[0].re, -h, 1e-15) && close(p[0].im, h, 1e-15),
        "{p:?}"
    );
    assert!(
        close(p[1].re, -h, 1e-15) && close(p[1].im, -h, 1e-15),
        "{p:?}"
    );
    // Order 4: angles pi(2k+3)/8 = 5pi/8, 7pi/8, 9pi/8, 11pi/8.
    // sin(pi/8) = sqrt(2 - sqrt2)/2 = 0.38268343, cos(pi/8) = sqrt(2 + sqrt2)/2 = 0.92387953.
    // cos(5pi/8) = -sin(pi/8), sin(5pi/8) = cos(pi/8); cos(7pi/8) = -cos(pi/8),
    // sin(7pi/8) = sin(pi/8); the other two are the conjugates.
    let s = (2.0 - SQRT_2).sqrt() / 2.0;
    let c = (2.0 + SQRT_2).sqrt() / 2.0;
    assert!(close(s, 0.382_683_432_365, 1e-12) && close(c, 0.923_879_532_511, 1e-12));
    let want = [(-s, c), (-c, s), (-c, -s), (-s, -c)];
    let p = butterworth_poles(4);
    assert_eq!(p.len(), 4);
    for (got, (re, im)) in p.iter().zip(want) {
        assert!(
            close(got.re, re, 1e-15) && close(got.im, im, 1e-15),
            "{got:?} vs {re} {im}"
        );
    }
    // Order 3: the middle pole is exactly -1.
    let p = butterworth_poles(3);
    assert_eq!((p[1].re, p[1].im), (-1.0, 0.0));
}

/// Hand-worked second-order low-pass: H(s) = 1/(s^2 + sqrt2 s + 1) (normalised s) with
/// s = (1/K)(1 - z^-1)/(1 + z^-1), K = tan(pi fc / fs) (pre-warped corner).
/// Multiplying by K^2 (1 + z^-1)^2:
///   num = K^2 (1 + 2 z^-1 + z^-2)
///   den = (1 - z^-1)^2 + sqrt2 K (1 - z^-2) + K^2 (1 + z^-1)^2
///       = (1 + sqrt2 K + K^2) + (2K^2 - 2) z^-1 + (1 - sqrt2 K + K^2) z^-2.
/// With D = 1 + sqrt2 K + K^2: b0 = K^2/D, b1 = 2 b0, b2 = b0, a1 = 2(K^2 - 1)/D,
/// a2 = (1 - sqrt2 K + K^2)/D. DC gain = 4K^2/(D + 2K^2 - 2 + 1 - sqrt2 K + K^2) = 1.
/// fs = 400 kHz, fc = 4 kHz: K = tan(0.01 pi) = 0.0314262660, D = 1.0454310619,
/// b0 = 9.4469184e-4, a1 = -1.9111970674, a2 = 0.9149758348.
#[test]
fn lowpass_order2_matches_hand_formula() {
    let k = (PI * 4_000.0 / FS).tan();
    let d = 1.0 + SQRT_2 * k + k * k;
    let b0 = k * k / d;
    let want = IdealSection {
        b: [b0, 2.0 * b0, b0],
        a: [2.0 * (k * k - 1.0) / d, (1.0 - SQRT_2 * k + k * k) / d],
    };
    assert!(close(want.a[0], -1.911_197_067_4, 1e-9) && close(b0, 9.446_918_4e-4, 1e-10));
    let r = design(&FilterSpec::lowpass(2, 4_000.0, FS), Q2_16).expect("design");
    assert_eq!(r.ideal.len(), 1);
    let got = r.ideal[0];
    for i in 0..3 {
        assert!(
            close(got.b[i], want.b[i], 1e-12),
            "b{i}: {got:?} vs {want:?}"
        );
    }
    for i in 0..2 {
        assert!(
            close(got.a[i], want.a[i], 1e-12),
            "a{}: {got:?} vs {want:?}",
            i + 1
        );
    }
    // Quantized: round half away of x * 2^16, worked here: a1 = -1.91119707 * 65536
    // = -125252.2 -> -125252; a2 = 0.91497583 * 65536 = 59963.9 -> 59964;
    // b0 = 9.4469184e-4 * 65536 = 61.911 -> 62, b = [62, 124, 62].
    let q = r.sos.sections[0];
    assert_eq!(q.a, [-125_252, 59_964], "{q:?}");
    assert_eq!(q.b, [62, 124, 62], "{q:?}");
    // DC gain of the quantized section: (62*4) / (65536 - 125252 + 59964) = 248/248 = 1.
    assert!(close(r.response.dc_gain_quantized, 1.0, 1e-12));
    assert!(close(r.response.dc_gain_ideal, 1.0, 1e-12));
}

/// High-pass: H(s) = s^2/(s^2 + sqrt2 s + 1) with the same substitution: numerator
/// (1 - z^-1)^2, same denominator, so b = [1, -2, 1]/D and a as for the low-pass.
/// Nyquist gain (z = -1): 4/D / ((D - 2K^2 + 2 + 1 - sqrt2 K + K^2)/D) = 4/4 = 1.
/// fs = 400 kHz, fc = 4 kHz: b0 = 1/D = 0.9565432256.
#[test]
fn highpass_order2_matches_hand_formula() {
    let k = (PI * 4_000.0 / FS).tan();
    let d = 1.0 + SQRT_2 * k + k * k;
    let want_b = [1.0 / d, -2.0 / d, 1.0 / d];
    let want_a = [2.0 * (k * k - 1.0) / d, (1.0 - SQRT_2 * k + k * k) / d];
    assert!(close(want_b[0], 0.956_543_225_6, 1e-9));
    let spec = FilterSpec::highpass(2, 4_000.0, FS);
    let r = design(&spec, Q2_16).expect("design");
    let got = r.ideal[0];
    for (i, (g, w)) in got.b.iter().zip(want_b).enumerate() {
        assert!(close(*g, w, 1e-12), "b{i}: {got:?}");
    }
    for (i, (g, w)) in got.a.iter().zip(want_a).enumerate() {
        assert!(close(*g, w, 1e-12), "a{}: {got:?}", i + 1);
    }
    // Exact DC null in both cascades; -3.0103 dB at the corner; 0 dB at Nyquist.
    assert_eq!(r.response.dc_gain_quantized, 0.0);
    assert!(r.response.dc_gain_ideal < 1e-12);
    assert!(close(
        db(cascade_gain(&r.ideal, 4_000.0, FS)),
        -10.0 * 2f64.log10(),
        1e-9
    ));
    assert!(close(r.response.centre_gain_ideal_db, 0.0, 1e-9));
    // Higher orders against the analytic magnitude (W = Tc/T).
    for n in 1..=6 {
        let spec = FilterSpec::highpass(n, 4_000.0, FS);
        let r = design(&spec, Q2_16).expect("design");
        assert_eq!(r.ideal.len(), n.div_ceil(2) as usize);
        for f in [
            500.0, 1_000.0, 2_000.0, 4_000.0, 8_000.0, 50_000.0, 199_000.0,
        ] {
            let g = db(cascade_gain(&r.ideal, f, FS));
            assert!(close(g, expected_db(&spec, f), 1e-8), "n {n} f {f}: {g}");
        }
    }
}

#[test]
fn lowpass_magnitude_matches_butterworth_formula() {
    for n in 1..=8 {
        let spec = FilterSpec::lowpass(n, 4_000.0, FS);
        let r = design(&spec, Q2_16).expect("design");
        assert_eq!(r.ideal.len(), n.div_ceil(2) as usize);
        for f in [0.0, 1_000.0, 3_000.0, 4_000.0, 5_000.0, 8_000.0, 40_000.0] {
            let g = db(cascade_gain(&r.ideal, f, FS));
            assert!(close(g, expected_db(&spec, f), 1e-7), "n {n} f {f}: {g}");
        }
        // -3.0103 dB = -10 log10(2) at the corner for every order.
        assert!(close(
            db(cascade_gain(&r.ideal, 4_000.0, FS)),
            -3.010_299_956_6,
            1e-9
        ));
        // Every section has unity gain at DC (the stated gain rule).
        for s in &r.ideal {
            assert!(close(
                (s.b[0] + s.b[1] + s.b[2]) / (1.0 + s.a[0] + s.a[1]),
                1.0,
                1e-12
            ));
        }
    }
}

/// The paper's band-pass 15-25 kHz at 400 kHz. At the edges the LP->BP map gives
/// W = (T1^2 - T1 T2)/(T1 (T2 - T1)) = -1 and W = +1: exactly -10 log10 2 = -3.0103 dB.
/// At sqrt(15k * 25k) = 19364.9 Hz: T = tan(pi 19364.9/400000) = 0.15328,
/// T1 = tan(0.0375 pi) = 0.11836, T2 = tan(0.0625 pi) = 0.19891,
/// W = (T^2 - T1 T2)/(T (T2 - T1)) = -0.0040, so the gain is -10 log10(1 + W^(2n))
/// = -7.0e-5 dB for n = 1 and smaller for higher n: ~0 dB.
#[test]
fn paper_bandpass_edges_and_centre() {
    let centre = (15_000.0f64 * 25_000.0).sqrt();
    assert!(close(centre, 19_364.916_731, 1e-5));
    for n in 1..=4 {
        let spec = FilterSpec::bandpass(n, 15_000.0, 25_000.0, FS);
        let r = design_with_probes(&spec, Q2_16, &[40_000.0]).expect("design");
        assert_eq!(r.ideal.len(), n as usize, "bandpass: n sections of 2 poles");
        let edge1 = db(cascade_gain(&r.ideal, 15_000.0, FS));
        let edge2 = db(cascade_gain(&r.ideal, 25_000.0, FS));
        assert!(close(edge1, -3.010_299_956_6, 1e-9), "n {n}: {edge1}");
        assert!(close(edge2, -3.010_299_956_6, 1e-9), "n {n}: {edge2}");
        let mid = db(cascade_gain(&r.ideal, centre, FS));
        assert!(
            mid.abs() < 2e-3 && close(mid, expected_db(&spec, centre), 1e-9),
            "{mid}"
        );
        // Other frequencies against the analytic magnitude.
        for f in [1_000.0, 10_000.0, 17_000.0, 22_000.0, 40_000.0, 150_000.0] {
            let g = db(cascade_gain(&r.ideal, f, FS));
            assert!(close(g, expected_db(&spec, f), 1e-7), "n {n} f {f}: {g}");
        }
        // Probe reported as attenuation (positive) at 40 kHz, equal to the formula.
        let p = r.response.probes[0];
        assert!(close(p.ideal_atten_db, -expected_db(&spec, 40_000.0), 1e-7));
        // Every section: unity gain at the design centre, exact zeros at DC and Nyquist.
        let w0 = 2.0 * PI * r.response.centre_hz / FS;
        assert!((r.response.centre_hz - centre).abs() < 50.0);
        for s in &r.ideal {
            assert!(close(s.eval(w0).norm(), 1.0, 1e-12));
            assert_eq!((s.b[1], s.b[2]), (0.0, -s.b[0]));
        }
        for s in &r.sos.sections {
            assert_eq!((s.b[1], s.b[2]), (0, -s.b[0]), "{s:?}");
        }
        assert_eq!(r.response.dc_gain_quantized, 0.0);
        // With Q2.16 the poles (distance to the circle >= 0.03) move by ~1e-5: the
        // quantized response stays within 0.1 dB in the pass band.
        assert!(
            r.response.max_passband_dev_db < 0.1,
            "{}",
            r.response.to_markdown()
        );
    }
}

/// Quantized poles inside the unit circle, checked here on the integers and with roots
/// computed in this file.
#[test]
fn quantized_poles_inside_unit_circle() {
    let specs = [
        FilterSpec::bandpass(2, 15_000.0, 25_000.0, FS),
        FilterSpec::bandpass(3, 15_000.0, 25_000.0, FS),
        FilterSpec::lowpass(4, 4_000.0, FS),
        FilterSpec::lowpass(3, 2_000.0, FS),
        FilterSpec::highpass(4, 10_000.0, FS),
    ];
    for spec in &specs {
        let r = design(spec, Q2_16).expect("design");
        let one = 1i64 << 16;
        for (i, s) in r.sos.sections.iter().enumerate() {
            let (a1, a2) = (s.a[0], s.a[1]);
            assert!(
                a2.abs() < one && a1.abs() < one + a2,
                "{spec} section {i}: {s:?}"
            );
            let m = root_moduli(a1 as f64 / one as f64, a2 as f64 / one as f64);
            assert!(m[0] < 1.0 && m[1] < 1.0, "{spec} section {i}: {m:?}");
            assert!(close(s.pole_radius(Q2_16), m[0].max(m[1]), 1e-12));
        }
        assert!(r.response.max_pole_radius_quantized < 1.0);
        // The sections come sorted by increasing pole radius.
        let radii: Vec<f64> = r.ideal.iter().map(|s| s.pole_radius()).collect();
        assert!(radii.windows(2).all(|w| w[0] <= w[1]), "{radii:?}");
    }
}

/// fs = 400 kHz, fc = 10 Hz, order 2, 12-bit Q3.8: K = tan(pi 10/400000) = 7.854e-5,
/// a1 = 2(K^2 - 1)/D = -1.999778 -> *256 = -511.943 -> -512 (= -2.0),
/// a2 = (1 - sqrt2 K + K^2)/D = 0.999778 -> *256 = 255.943 -> 256 (= 1.0):
/// z^2 - 2z + 1 = (z - 1)^2, a double pole ON the circle (radius 1): must be rejected.
#[test]
fn narrow_lowpass_quantized_unstable_is_rejected() {
    let spec = FilterSpec::lowpass(2, 10.0, FS);
    let fmt = CoefFormat { width: 12, frac: 8 };
    let e = design(&spec, fmt).expect_err("must be rejected");
    match &e {
        FilterError::UnstableSection {
            stage,
            section,
            radius,
            a1,
            a2,
            ..
        } => {
            assert_eq!((*stage, *section), ("quantized", 0));
            assert_eq!((*a1, *a2), (-2.0, 1.0));
            assert!(close(*radius, 1.0, 1e-12), "{radius}");
        }
        other => panic!("wrong error {other:?}"),
    }
    let msg = e.to_string();
    assert!(
        msg.contains("section 0") && msg.contains("lowpass order 2"),
        "{msg}"
    );
    assert!(msg.contains("pole radius 1"), "{msg}");
}

/// Order 4, fc = 1 kHz, 14-bit Q3.10 (frac 10): K = tan(pi/400) = 0.0078541431.
/// Sections H = 1/(s^2 + 2 sigma s + 1), sigma = cos(pi/8) = 0.92388 (low Q, smaller pole
/// radius, so section 0) and sigma = sin(pi/8) = 0.38268 (section 1); D = 1 + 2 sigma K + K^2,
/// a1 = 2(K^2 - 1)/D, a2 = (1 - 2 sigma K + K^2)/D:
///   section 0: a1 = -1.9711486 -> *1024 = -2018.456 -> -2018, a2 = 0.9713918 -> 994.705
///     -> 995; |a1| = 2018 < 1024 + 995 = 2019: stable;
///   section 1: a1 = -1.9878047 -> -2035.512 -> -2036, a2 = 0.9880500 -> 1011.763 -> 1012;
///     |a1| = 2036 = 1024 + 1012: NOT strictly less: z^2 + a1 z + a2 has the root z = 1
///     (1024 - 2036 + 1012 = 0), radius exactly 1. The error must name section 1.
#[test]
fn unstable_second_section_is_named() {
    let spec = FilterSpec::lowpass(4, 1_000.0, FS);
    let e = design(
        &spec,
        CoefFormat {
            width: 14,
            frac: 10,
        },
    )
    .expect_err("must be rejected");
    match &e {
        FilterError::UnstableSection {
            section, radius, ..
        } => {
            assert_eq!(*section, 1, "{e}");
            assert_eq!(*radius, 1.0, "{e}");
        }
        other => panic!("wrong error {other:?}"),
    }
    assert!(e.to_string().contains("section 1"), "{e}");
    // frac 12: section 0 a = (-8074, 3979): 8074 < 4096 + 3979 = 8075, section 1
    // a = (-8142, 4047): 8142 < 8143, both stable; but the gains g = (1 + a1 + a2)/4 =
    // 6.080e-5 and 6.131e-5 give g * 4096 = 0.249 and 0.251 -> 0: gain underflow, section 0.
    let e = design(
        &spec,
        CoefFormat {
            width: 16,
            frac: 12,
        },
    )
    .expect_err("zero gain");
    assert!(
        matches!(e, FilterError::GainUnderflow { section: 0, .. }),
        "{e:?}"
    );
    // frac 14: a = (-32295, 15915) and (-32568, 16188), g * 16384 = 0.996 and 1.005 -> 1.
    let r = design(
        &spec,
        CoefFormat {
            width: 18,
            frac: 14,
        },
    )
    .expect("stable at frac 14");
    let a: Vec<[i64; 2]> = r.sos.sections.iter().map(|s| s.a).collect();
    assert_eq!(a, vec![[-32_295, 15_915], [-32_568, 16_188]]);
    for s in &r.sos.sections {
        assert_eq!(s.b, [1, 2, 1]);
    }
}

/// Q0.15 (16 bits, 15 fractional): range [-1, 1 - 2^-15]; the 4 kHz low-pass has
/// a1 = -1.9112 (see the hand-worked section), which cannot fit: overflow naming a1.
#[test]
fn coefficient_overflow_names_the_coefficient() {
    let spec = FilterSpec::lowpass(2, 4_000.0, FS);
    let e = design(
        &spec,
        CoefFormat {
            width: 16,
            frac: 15,
        },
    )
    .expect_err("overflow");
    match &e {
        FilterError::CoefficientOverflow {
            section,
            coef,
            min,
            max,
            ..
        } => {
            assert_eq!((*section, *coef), (0, "a1"));
            assert_eq!((*min, *max), (-1.0, 1.0 - 2f64.powi(-15)));
        }
        other => panic!("wrong error {other:?}"),
    }
    assert!(e.to_string().contains("a1"), "{e}");
}

/// First-order low-pass, fc = 37.3 Hz, frac 10: K = tan(pi 37.3/400000) = 2.9295e-4;
/// a1 = -(1 - K)/(1 + K) -> *1024 = -1024 + 2K/(1+K)*1024 = -1023.40 -> -1023 (stable);
/// b0 = K/(1 + K) -> *1024 = 0.29990 -> 0: the section would output nothing.
#[test]
fn gain_rounding_to_zero_is_rejected() {
    let spec = FilterSpec::lowpass(1, 37.3, FS);
    let e = design(
        &spec,
        CoefFormat {
            width: 12,
            frac: 10,
        },
    )
    .expect_err("zero gain");
    assert!(
        matches!(e, FilterError::GainUnderflow { section: 0, .. }),
        "{e:?}"
    );
}

#[test]
fn invalid_specs_and_formats_are_rejected() {
    let bad = [
        (FilterSpec::lowpass(0, 4_000.0, FS), "order"),
        (FilterSpec::lowpass(17, 4_000.0, FS), "order"),
        (FilterSpec::lowpass(2, 200_000.0, FS), "corner_hz"),
        (FilterSpec::highpass(2, -1.0, FS), "corner_hz"),
        (FilterSpec::bandpass(2, 25_000.0, 15_000.0, FS), "band_hz"),
        (
            FilterSpec::bandpass(2, 15_000.0, 25_000.0, f64::NAN),
            "sample_rate_hz",
        ),
        (
            FilterSpec {
                corner_hz: None,
                ..FilterSpec::lowpass(2, 1.0, FS)
            },
            "corner_hz",
        ),
        (
            FilterSpec {
                corner_hz: Some(1.0),
                ..FilterSpec::bandpass(2, 15_000.0, 25_000.0, FS)
            },
            "corner_hz",
        ),
    ];
    for (spec, field) in bad {
        match design(&spec, Q2_16) {
            Err(FilterError::InvalidSpec { field: f, .. }) => assert_eq!(f, field, "{spec:?}"),
            other => panic!("{spec:?}: {other:?}"),
        }
    }
    for (width, frac) in [(1, 0), (65, 10), (16, 16)] {
        let r = design(
            &FilterSpec::lowpass(2, 4_000.0, FS),
            CoefFormat { width, frac },
        );
        assert!(matches!(r, Err(FilterError::InvalidFormat { .. })), "{r:?}");
    }
    let r = design_with_probes(&FilterSpec::lowpass(2, 4_000.0, FS), Q2_16, &[300_000.0]);
    assert!(matches!(r, Err(FilterError::InvalidSpec { .. })), "{r:?}");
}

#[test]
fn spec_deserializes_from_toml() {
    let spec: FilterSpec = toml::from_str(
        "kind = \"bandpass\"\norder = 2\nband_hz = [15000.0, 25000.0]\nsample_rate_hz = 400000.0\n",
    )
    .expect("parse");
    assert_eq!(spec, FilterSpec::bandpass(2, 15_000.0, 25_000.0, FS));
    let fmt: CoefFormat = toml::from_str("width = 18\nfrac = 16\n").expect("parse");
    assert_eq!(fmt, Q2_16);
    assert!(toml::from_str::<FilterSpec>(
        "kind = \"lowpass\"\norder = 2\ncorner_hz = 1.0\nsample_rate_hz = 8.0\nfoo = 1\n"
    )
    .is_err());
}

#[test]
fn markdown_report_has_the_figures() {
    let r = design_with_probes(&FilterSpec::lowpass(2, 2_000.0, FS), Q2_16, &[40_000.0])
        .expect("design");
    let md = r.to_markdown();
    assert!(md.contains("attenuation at 40000.0 Hz"), "{md}");
    assert!(md.contains("max pass-band deviation"), "{md}");
    // 2nd-order LP at 2 kHz, 40 kHz: W = tan(0.1 pi)/tan(0.005 pi) = 20.7, gain
    // -10 log10(1 + W^4) = -52.6 dB.
    let want = 10.0 * (1.0 + (t(40_000.0, FS) / t(2_000.0, FS)).powi(4)).log10();
    assert!(close(want, 52.6, 0.1), "{want}");
    assert!(close(r.response.probes[0].ideal_atten_db, want, 1e-7));
}

fn any_spec() -> impl Strategy<Value = FilterSpec> {
    (
        0u8..3,
        1u32..=12,
        1e3f64..1e7,
        0.002f64..0.45,
        1.05f64..20.0,
    )
        .prop_map(|(k, order, fs, x, ratio)| match k {
            0 => FilterSpec::lowpass(order, x * fs, fs),
            1 => FilterSpec::highpass(order, x * fs, fs),
            _ => {
                let f1 = x * fs / 2.0;
                let f2 = (f1 * ratio).min(0.48 * fs);
                FilterSpec::bandpass(order, f1, f2, fs)
            }
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]
    /// Any valid spec designs sections whose ideal poles are strictly inside the unit circle
    /// (roots computed in this file), with unity gain at the centre and -3.01 dB at the
    /// corner(s), as the analytic Butterworth magnitude requires.
    #[test]
    fn valid_specs_design_stable_sections(spec in any_spec()) {
        let ideal = sinedec::filter::design_ideal(&spec).expect("valid spec");
        let want_sections = match spec.kind {
            FilterKind::Bandpass => spec.order,
            _ => spec.order.div_ceil(2),
        };
        prop_assert_eq!(ideal.len(), want_sections as usize);
        for s in &ideal {
            let m = root_moduli(s.a[0], s.a[1]);
            prop_assert!(m[0] < 1.0 && m[1] < 1.0, "{} {:?} {:?}", spec, s, m);
        }
        let fs = spec.sample_rate_hz;
        let c = db(cascade_gain(&ideal, spec.centre_hz(), fs));
        prop_assert!(c.abs() < 1e-8, "{} centre {}", spec, c);
        let edges: Vec<f64> = match spec.kind {
            FilterKind::Bandpass => spec.band_hz.unwrap().to_vec(),
            _ => vec![spec.corner_hz.unwrap()],
        };
        for f in edges {
            let g = db(cascade_gain(&ideal, f, fs));
            prop_assert!(close(g, -3.010_299_956_6, 1e-6), "{} at {} Hz: {}", spec, f, g);
        }
    }
}
