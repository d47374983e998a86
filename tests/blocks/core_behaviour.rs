//! Timing and tracking of the core in the rust-hdl simulation (equal to the Verilog by
//! tests/blocks/cosim_core.rs): latency, throughput, unwrapping over turns, zero input, resets.
use crate::common;
use sinedec::blocks::core::hdl::simulate_rtl;
use sinedec::blocks::core::model::{CoreIn, CoreModel, CoreOut};
use sinedec::cosim::stimulus::{self, idle, reset};
use std::f64::consts::FRAC_PI_2;

#[test]
fn latency_is_n_plus_2_and_throughput_one_per_clock() {
    for n in [1, 2, 5, 8, 11, 14, 20] {
        let l = common::cfg(n, 14, 14, 2048, 12);
        let mut s = vec![reset(), idle(), idle()];
        // One lone sample, a gap, then 50 back-to-back samples.
        s.extend(stimulus::rotation(14, 0.8, 0.3, 0.0, 1));
        s.extend((0..30).map(|_| idle()));
        s.extend(stimulus::rotation(14, 0.8, 0.3, 0.01, 50));
        s.extend((0..30).map(|_| idle()));
        let out = simulate_rtl(&l.derived, &s).expect("settles");
        let first_in = 3;
        let first_out = out.iter().position(|o| o.valid).expect("an output");
        let lat = first_out - first_in;
        assert_eq!(lat as u32, n + 2, "N={n}");
        assert!(lat as u32 <= n + 3);
        let burst_in = 3 + 1 + 30;
        let valid_rows: Vec<usize> = (0..out.len()).filter(|&k| out[k].valid).collect();
        assert_eq!(valid_rows.len(), 51, "every sample comes out once (N={n})");
        let expect: Vec<usize> = std::iter::once(first_in)
            .chain(burst_in..burst_in + 50)
            .map(|k| k + lat)
            .collect();
        assert_eq!(valid_rows, expect, "N={n}: one output per clock, in order");
    }
}

/// Unwrapped position in fine LSB: turns * 4PPR * 2^F + position.
fn unwrapped(o: &CoreOut, l: &sinedec::config::Loaded) -> i64 {
    let d = &l.derived;
    o.turns_signed(d) * (d.quadrants_per_turn as i64) * (1i64 << d.fine_bits) + o.position as i64
}

fn track(l: &sinedec::config::Loaded, step: f64, samples: usize, use_rtl: bool) {
    let d = &l.derived;
    let start = 0.2;
    let mut s = vec![reset()];
    s.extend(stimulus::rotation(d.adc_width, 0.75, start, step, samples));
    s.extend((0..d.latency_cycles + 1).map(|_| idle()));
    let out: Vec<CoreOut> = if use_rtl {
        simulate_rtl(d, &s).expect("settles")
    } else {
        let mut m = CoreModel::new(d);
        s.iter().map(|i| m.step(*i)).collect()
    };
    let v: Vec<&CoreOut> = out.iter().filter(|o| o.valid).collect();
    assert_eq!(v.len(), samples);
    let lsb_per_rad = (1u64 << d.fine_bits) as f64 / FRAC_PI_2;
    let tol = 3.0; // the CORDIC at N = 14 is within 2.3 LSB (tests/blocks/accuracy.rs)
    let mut prev = None;
    for (k, o) in v.iter().enumerate() {
        assert!(!o.error && !o.warning, "sample {k}: {o:?}");
        let u = unwrapped(o, l);
        // The true electrical angle, unwrapped, relative to the position the core started
        // from (its first sample sets turns = 0 at the first period's angle).
        let truth = (start + step * k as f64) * lsb_per_rad;
        assert!(
            (u as f64 - truth).abs() <= tol,
            "sample {k}: {u} vs {truth}"
        );
        if let Some(p) = prev {
            if step > 0.0 {
                assert!(u >= p, "monotonic up at {k}");
            } else {
                assert!(u <= p, "monotonic down at {k}");
            }
        }
        prev = Some(u);
    }
}

#[test]
fn tracks_several_turns_both_ways_rtl() {
    // PPR 3: 12 quadrants per turn; 0.4 quadrant per sample; 4 turns each way.
    let l = common::cfg(14, 14, 14, 3, 4);
    let step = 0.4 * FRAC_PI_2;
    track(&l, step, 12 * 4 * 10 / 4 + 5, true);
    track(&l, -step, 12 * 4 * 10 / 4 + 5, true);
}

#[test]
fn tracks_with_non_power_of_two_ppr_and_turn_wrap_model() {
    // PPR 5, 2 multi-turn bits: turns wraps 1 -> -2 after 2 turns; check via the raw bits.
    let l = common::cfg(14, 14, 14, 5, 2);
    let d = &l.derived;
    let step = 0.9 * FRAC_PI_2;
    let mut s = vec![reset()];
    let samples = 20 * 6; // 0.9 quadrant per sample, 20 quadrants per turn: 5.4 turns
    s.extend(stimulus::rotation(14, 0.75, 0.2, step, samples));
    s.extend((0..20).map(|_| idle()));
    let mut m = CoreModel::new(d);
    let rtl = simulate_rtl(d, &s).expect("settles");
    let mut turns_seen = vec![];
    for (i, r) in s.iter().zip(&rtl) {
        let o = m.step(*i);
        assert_eq!(o, *r);
        if o.valid {
            assert!(o.position < 20 << 14);
            if turns_seen.last() != Some(&o.turns) {
                turns_seen.push(o.turns);
            }
        }
    }
    // 2-bit two's complement: 0, 1, -2 (2), -1 (3), 0, 1.
    assert_eq!(turns_seen, vec![0, 1, 2, 3, 0, 1]);
}

#[test]
fn zero_input_sets_error_and_holds_position() {
    let l = common::cfg(14, 14, 14, 2048, 12);
    let d = &l.derived;
    let mut s = vec![reset()];
    s.extend(stimulus::rotation(14, 0.8, 0.5, 0.0, 3));
    s.push(CoreIn {
        rst: false,
        valid: true,
        sin: 0,
        cos: 0,
        load: None,
    });
    // 5 % of full scale: below the 6.25 % threshold.
    s.extend(stimulus::rotation(14, 0.05, 1.5, 0.0, 2));
    s.extend(stimulus::rotation(14, 0.8, 0.6, 0.0, 1));
    s.extend((0..20).map(|_| idle()));
    let out = simulate_rtl(d, &s).expect("settles");
    let v: Vec<&CoreOut> = out.iter().filter(|o| o.valid).collect();
    assert_eq!(v.len(), 7);
    let good = v[2].position;
    for o in &v[3..6] {
        assert!(o.error, "{o:?}");
        assert_eq!(
            o.position, good,
            "position held while the signal is missing"
        );
    }
    assert!(!v[6].error);
    let expect = (0.6 / FRAC_PI_2 * 16384.0) as i64;
    assert!((v[6].position as i64 - expect).abs() <= 2, "{:?}", v[6]);
}

#[test]
fn reset_mid_stream_drops_samples_in_flight_and_restarts() {
    let l = common::cfg(14, 14, 14, 2048, 12);
    let d = &l.derived;
    let mut s = vec![reset()];
    s.extend(stimulus::rotation(14, 0.8, 0.3, 0.05, 20));
    s.push(reset());
    s.extend(stimulus::rotation(14, 0.8, 2.0, 0.0, 1));
    s.extend((0..20).map(|_| idle()));
    let out = simulate_rtl(d, &s).expect("settles");
    // Outputs for the first 20 samples stop at the reset; the 12 cycles after the reset
    // carry only the new sample.
    let after: Vec<&CoreOut> = out[22..].iter().filter(|o| o.valid).collect();
    assert_eq!(after.len(), 1);
    assert_eq!(after[0].turns, 0);
    let expect = (2.0 / FRAC_PI_2 * 16384.0) as i64;
    assert!((after[0].position as i64 - expect).abs() <= 3);
    assert!(
        !out[21].valid && out[21].position == 0,
        "reset clears the outputs"
    );
}

#[test]
fn two_quadrant_jumps_resolved_and_warned() {
    let l = common::cfg(14, 14, 14, 2048, 12);
    let d = &l.derived;
    // 1.6 quadrants per sample: beyond the thesis's 1-quadrant state machine, below our
    // warning threshold: counted exactly, no warning.
    let mut m = CoreModel::new(d);
    let mut s = vec![reset()];
    s.extend(stimulus::rotation(14, 0.8, 0.1, 1.6 * FRAC_PI_2, 40));
    s.extend((0..20).map(|_| idle()));
    let outs: Vec<CoreOut> = s.iter().map(|i| m.step(*i)).filter(|o| o.valid).collect();
    let l2 = &l;
    let u0 = unwrapped(&outs[0], l2);
    let last = unwrapped(&outs[39], l2);
    let expect = 39.0 * 1.6 * 16384.0;
    assert!(
        ((last - u0) as f64 - expect).abs() < 4.0,
        "{} vs {expect}",
        last - u0
    );
    assert!(outs.iter().all(|o| !o.warning));
    // 1.9 quadrants per sample: still unwrapped in the right direction, but flagged.
    let mut m = CoreModel::new(d);
    let mut s = vec![reset()];
    s.extend(stimulus::rotation(14, 0.8, 0.1, -1.9 * FRAC_PI_2, 10));
    s.extend((0..20).map(|_| idle()));
    let outs: Vec<CoreOut> = s.iter().map(|i| m.step(*i)).filter(|o| o.valid).collect();
    let moved = unwrapped(&outs[9], &l) - unwrapped(&outs[0], &l);
    assert!((moved as f64 + 9.0 * 1.9 * 16384.0).abs() < 4.0, "{moved}");
    assert!(outs[1..].iter().all(|o| o.warning));
}
