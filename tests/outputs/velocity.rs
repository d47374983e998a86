//! Velocity block: rust-hdl == bit-accurate model cycle for cycle, and rust-hdl == Icarus ==
//! Verilator, for each method, on directed and random position streams: reversals, wraps
//! of the single-turn position (in_p is modulo 2^(F+2)), a long run in which the unwrapped
//! position overflows its Wp-bit register, resets while a result is pending, and gaps in
//! in_valid. At a constant integer speed every method must output exactly that speed
//! (2^frac_bits per position LSB per period), an expectation independent of the model.
//! Tracking settling and synthesis: `tests/outputs/velocity_synth.rs`.
use crate::common;
use sinedec::blocks::velocity::hdl::Velocity;
use sinedec::blocks::velocity::model::{VelIn, VelocityModel};
use sinedec::blocks::velocity::{Method, VelocityParams, VelocitySpec};
use sinedec::blocks::{mask, sext};
use sinedec::cosim::stimulus::SplitMix64;
use sinedec::verify::{block_traces, Simulators};

const RUST_ONLY: Simulators = Simulators {
    icarus: false,
    verilator: false,
};

const ALL_METHODS: [Method; 4] = [
    Method::DiffLpf,
    Method::Kalman,
    Method::Lsq,
    Method::Tracking,
];

/// The default configuration's velocity constants (F = 14, 7.5 kHz, the maximum speed of
/// the default decoder, every method's default parameters), time-scaled to a 960 kHz clock
/// so that an update period is D = 128 clocks instead of 17,777.
fn params(m: Method) -> VelocityParams {
    let mut s = VelocitySpec::defaults(960_000.0, 14, 4_997_175);
    s.method = m;
    VelocityParams::new(&s).expect("default-like parameters are valid")
}

/// Runs the block on `ins` in the chosen simulators; asserts rust-hdl == model row by row
/// and the Verilog simulators == rust-hdl; returns the model's (strobe, velocity) rows.
fn run(p: &VelocityParams, ins: &[VelIn], tag: &str, sims: Simulators) -> Vec<(bool, i64)> {
    let rows: Vec<Vec<u64>> = ins
        .iter()
        .map(|i| vec![i.rst as u64, i.p, i.valid as u64])
        .collect();
    let mut m = VelocityModel::new(p);
    let model: Vec<_> = ins.iter().map(|i| m.step(*i)).collect();
    let uut = Velocity::new(p).expect("block");
    let dir = common::workdir(tag);
    let t = block_traces(uut, tag, "clk", &rows, sims, &dir).expect("simulators ran");
    for (k, (r, o)) in t.rust_hdl.iter().zip(&model).enumerate() {
        assert_eq!(
            (r[0], r[1] == 1),
            (o.velocity, o.valid),
            "{tag} row {k}: rust-hdl vs model (velocity, strobe)"
        );
    }
    if let Some(msg) = t.mismatch() {
        panic!("{tag}: {msg}");
    }
    let w = p.spec.width;
    assert!(model.iter().all(|o| o.velocity & !mask(w) == 0));
    model
        .iter()
        .map(|o| (o.valid, sext(o.velocity, w)))
        .collect()
}

/// A position stream: `speed(clock)` in position LSB per clock, a sample on the clocks where
/// `valid(clock)` holds; in_p is the position modulo 2^(F+2) (it wraps every 2^16 LSB at
/// F = 14). Starts with 3 reset clocks and at position `start`.
fn stream(
    p: &VelocityParams,
    n: usize,
    start: f64,
    speed: impl Fn(usize) -> f64,
    mut valid: impl FnMut(usize) -> bool,
) -> Vec<VelIn> {
    let f2 = p.spec.fine_bits + 2;
    let mut x = start;
    let mut last = start.floor() as i64;
    let mut ins = vec![
        VelIn {
            rst: true,
            ..VelIn::default()
        };
        3
    ];
    for k in 0..n {
        x += speed(k);
        let v = valid(k);
        let pos = x.floor() as i64;
        if v {
            assert!(
                (pos - last).abs() < 1 << (f2 - 1),
                "stimulus: a step of 2 quadrants or more"
            );
            last = pos;
        }
        ins.push(VelIn {
            rst: false,
            valid: v,
            p: ((pos as u64) & mask(f2)) | (((k as u64) << 20) & 0xfff0_0000),
        });
    }
    ins
}

/// Directed: rest, a ramp up to 30,000 LSB per clock (0.92 quadrant per sample; 3.84 M LSB
/// per period, 77 % of the maximum), a hold long enough to overflow the Wp-bit position
/// register, an instant reversal, a hold backward, and a hold at an integer speed.
fn directed(p: &VelocityParams) -> Vec<VelIn> {
    let d = p.period_clocks as usize;
    let speed = move |k: usize| -> f64 {
        let u = k / d;
        match u {
            0..=3 => 0.0,
            4..=9 => 5000.0 * (u - 3) as f64,
            10..=49 => 30_000.0,
            50..=79 => -30_000.0,
            _ => -1234.0,
        }
    };
    stream(p, 100 * d, 12_345.6, speed, |_| true)
}

/// The strobed values, in update order.
fn strobes(out: &[(bool, i64)]) -> Vec<i64> {
    out.iter().filter(|o| o.0).map(|o| o.1).collect()
}

#[test]
fn directed_stream_matches_the_model_and_the_speeds() {
    for m in ALL_METHODS {
        let p = params(m);
        let ins = directed(&p);
        let wp = p.pos_width;
        // The run moves 40 x 3.84 M LSB one way: more than the Wp-bit register holds.
        assert!(40.0 * 30_000.0 * 128.0 > (1u64 << wp) as f64, "Wp = {wp}");
        let tag = format!("vel_dir_{m}");
        let out = run(&p, &ins, &tag, RUST_ONLY);
        let ys = strobes(&out);
        assert!(ys.len() >= 95, "{tag}: {} updates", ys.len());
        let one = 1i64 << p.spec.frac_bits;
        // Values at integer speeds (LSB per clock x 128 clocks x 2^S), independent of the
        // model: at rest, at +30,000, at -30,000 and at -1,234 per clock, each 20 to 40
        // updates after the last speed change. lsq (a 4-point FIR) is exact by then; the
        // recursive methods are within a fraction of the jump that their decay leaves
        // (diff_lpf/kalman (1 - 0.43)^20 < 1e-4; tracking, whose 2 % time is 34 updates,
        // 5 % after 20).
        let frac = match m {
            Method::Lsq => 0.0,
            Method::DiffLpf | Method::Kalman => 1e-4,
            Method::Tracking => 5e-2,
        };
        let at = |u: usize| ys[u - 1];
        let check = |u: usize, v: i64, jump: i64, what: &str| {
            let want = v * 128 * one;
            let tol = (frac * (jump * 128 * one) as f64).ceil() as i64;
            assert!(
                (at(u) - want).abs() <= tol,
                "{tag}: {what}: update {u}: {} vs {want} (tolerance {tol})",
                at(u)
            );
        };
        check(3, 0, 0, "at rest");
        check(49, 30_000, 5000, "forward");
        check(79, -30_000, 60_000, "backward");
        check(99, -1234, 28_766, "slow");
    }
}

/// Random speeds (a random walk, reversals included), samples with random gaps, random
/// resets, and resets placed while a result is pending (a few clocks after a tick).
fn random(p: &VelocityParams, n: usize, seed: u64) -> Vec<VelIn> {
    let d = p.period_clocks as usize;
    let lat = p.latency() as usize;
    let mut r = SplitMix64(seed);
    let f2 = p.spec.fine_bits + 2;
    let mut x = 1e6 * r.unit();
    let mut v = 0.0f64;
    let mut last = x.floor() as i64;
    let mut ins = vec![
        VelIn {
            rst: true,
            ..VelIn::default()
        };
        2
    ];
    // Clocks since reset: the tick is at clock D - 1 of each period after it.
    let mut since = 0usize;
    for _ in 0..n {
        if r.unit() < 0.02 {
            v = r.range(-3000, 3000) as f64 + r.unit();
        }
        v = (v + r.range(-50, 50) as f64).clamp(-3000.0, 3000.0);
        x += v;
        let pos = x.floor() as i64;
        // Gaps of up to 8 clocks at up to 3,000 LSB per clock: steps below 2 quadrants.
        let valid = r.unit() < 0.6 || (pos - last).abs() > 20_000;
        // Within `lat` clocks after a tick (since = D - 1 mod D) a result is pending.
        let phase = since % d;
        let rst = r.unit() < 0.0005 || (since > 4 * d && phase < lat && r.unit() < 0.005);
        if valid {
            last = pos;
        }
        ins.push(VelIn {
            rst,
            valid,
            p: (pos as u64) & mask(f2),
        });
        since = if rst { 0 } else { since + 1 };
    }
    ins
}

#[test]
fn random_streams_with_gaps_and_resets_match_the_model() {
    for (i, m) in ALL_METHODS.into_iter().enumerate() {
        let p = params(m);
        let ins = random(&p, 12_000, 11 + i as u64);
        let resets = ins.iter().filter(|i| i.rst).count();
        assert!(resets > 5, "{resets} resets");
        let tag = format!("vel_rand_{m}");
        let out = run(&p, &ins, &tag, RUST_ONLY);
        assert!(strobes(&out).iter().filter(|&&y| y != 0).count() > 20);
    }
}

/// A reset one clock after a tick, before the result: no strobe for that update, and the
/// block starts again from scratch (first update after reset loads its history: 0).
#[test]
fn reset_while_a_result_is_pending_drops_it() {
    for m in ALL_METHODS {
        let p = params(m);
        let d = p.period_clocks as usize;
        let mut ins = stream(&p, 12 * d, 777.0, |_| 1000.0, |_| true);
        // Ticks at rows 3 + u D - 1; reset 2 clocks after the 6th.
        let rr = 3 + 6 * d + 1;
        ins[rr].rst = true;
        let tag = format!("vel_rst_{m}");
        let out = run(&p, &ins, &tag, RUST_ONLY);
        let lat = p.latency() as usize;
        assert!(!out[rr..rr + lat + 2].iter().any(|o| o.0), "{tag}: dropped");
        assert!(out[rr].1 == 0, "{tag}: output cleared");
        // After the reset the position counter restarts: the next strobe is the priming 0.
        let next = out[rr + 1..].iter().find(|o| o.0).expect("strobe");
        assert_eq!(next.1, 0, "{tag}: first update after reset");
    }
}

/// rust-hdl == model == Icarus == Verilator on one stream per method: the directed run
/// (cut short), then random speeds with gaps and resets.
#[test]
fn four_way_cosimulation() {
    for (i, m) in ALL_METHODS.into_iter().enumerate() {
        let p = params(m);
        let d = p.period_clocks as usize;
        let mut ins = directed(&p);
        ins.truncate(3 + 56 * d);
        ins.extend(random(&p, 4000, 101 + i as u64));
        let tag = format!("vel_cosim_{m}");
        let out = run(&p, &ins, &tag, Simulators::ALL);
        assert!(strobes(&out).len() > 60);
    }
}
