//! Position reference block: rust-hdl == model cycle for cycle, rust-hdl == Icarus ==
//! Verilator == engine, and its behaviour against expectations written from the spec
//! (the Z tag of each sample, homing at the first qualified sample, the index latch, the
//! preset with its synchronizer, the offset's wrap into the turns).
use crate::common;
use sinedec::blocks::mask;
use sinedec::blocks::reference::hdl::PositionReference;
use sinedec::blocks::reference::model::{ReferenceIn, ReferenceModel, ReferenceOut};
use sinedec::blocks::reference::ReferenceParams;
use sinedec::cosim::stimulus::SplitMix64;
use sinedec::synth::{synthesize, Family};
use sinedec::verify::{block_traces, Simulators};

const RUST_ONLY: Simulators = Simulators {
    icarus: false,
    verilator: false,
};

/// Q = 8192 (PPR 2048), M = 12 turn bits, gate quadrant `gate`, index count (100, turn 3),
/// preset (5000, turn -1), L = 219 clocks from CONV to the core's sample, P = 102.
fn params(gate: u32) -> ReferenceParams {
    ReferenceParams::new(
        8192,
        12,
        gate,
        (100, 3),
        (5000, mask(12)),
        219,
        102,
        true,
        true,
    )
    .expect("params")
}

/// Runs the block on `ins` in the chosen simulators; asserts rust-hdl == model row by row
/// and the Verilog simulators == rust-hdl; returns the model's outputs.
fn run(p: &ReferenceParams, ins: &[ReferenceIn], tag: &str, sims: Simulators) -> Vec<ReferenceOut> {
    let rows: Vec<Vec<u64>> = ins.iter().map(|i| i.row()).collect();
    let mut m = ReferenceModel::new(p);
    let model: Vec<ReferenceOut> = ins.iter().map(|i| m.step(*i)).collect();
    let dir = common::workdir(tag);
    let t = block_traces(PositionReference::new(p), tag, "clk", &rows, sims, &dir)
        .expect("simulators ran");
    for (k, (r, m)) in t.rust_hdl.iter().zip(&model).enumerate() {
        assert_eq!(
            r,
            &m.row(),
            "{tag} row {k}: rust-hdl vs model (inputs {:?})",
            rows[k]
        );
    }
    if let Some(m) = t.mismatch() {
        panic!("{tag}: {m}");
    }
    model
}

/// A decoder's view of an encoder moving by `step(k)` quadrants per sample (as a fraction):
/// CONV pulses every P = 102 clocks, each sample leaves the core L = 219 clocks after its
/// CONV, Z is `z_at(angle in quadrants)` at each clock's CONV. Returns the inputs and the
/// true quadrant position (unwrapped, in quadrants) of each sample leaving at that clock.
fn stimulus(
    clocks: usize,
    start: f64,
    speed: f64,
    z_at: impl Fn(f64) -> bool,
    preset_at: Option<usize>,
) -> (Vec<ReferenceIn>, Vec<Option<f64>>) {
    let (p, l) = (102usize, 219usize);
    let q = 8192.0;
    let angle = |c: usize| start + speed * c as f64 / p as f64;
    let mut ins = vec![];
    let mut truth = vec![];
    for c in 0..clocks {
        let conv = c % p < 4 && c >= 4;
        let from = c.checked_sub(l).filter(|s| s % p == 0 && *s >= 4);
        let a = from.map(angle);
        let (valid, qc, turns) = match a {
            Some(a) => {
                let qf = a.floor();
                let t = (qf / q).floor();
                (true, (qf - t * q) as u64, (t as i64 as u64) & mask(12))
            }
            None => (false, 0, 0),
        };
        ins.push(ReferenceIn {
            rst: c < 2,
            conv,
            z: z_at(angle(c)),
            preset: preset_at.is_some_and(|s| c >= s && c < s + 5),
            valid,
            qc,
            fine: (a.unwrap_or(0.0).fract() * 16384.0) as u64,
            turns,
            ..Default::default()
        });
        truth.push(a);
    }
    (ins, truth)
}

#[test]
fn homing_maps_the_reference_quadrant_to_the_index_count_both_ways() {
    // Z high in quadrant 4..8 (a whole period, as a real index may be); gate quadrant 2:
    // the reference quadrant is count 6 of the raw numbering, and reads 100 (turn 3).
    let p = params(2);
    let z = |a: f64| (4.0..8.0).contains(&a);
    for (start, speed, tag) in [
        (1.3, 0.3, "ref_fwd"),
        (11.2, -0.45, "ref_bwd"),
        (6.4, 0.1, "ref_in"),
    ] {
        let (ins, truth) = stimulus(6000, start, speed, z, None);
        let out = run(&p, &ins, tag, RUST_ONLY);
        let mut seen = false;
        for (k, o) in out.iter().enumerate() {
            // Output k is the sample that entered with row k (the edge after it).
            let (Some(a), true) = (truth[k], o.valid) else {
                continue;
            };
            if o.referenced {
                seen = true;
                // Reference quadrant (raw 6) -> 100 of turn 3: raw count c reads c + 94.
                let want = a.floor() + 94.0 + 3.0 * 8192.0;
                let got = o.qc as f64 + 8192.0 * sinedec::blocks::sext(o.turns, 12) as f64;
                assert_eq!(got, want, "{tag} clock {k}");
                assert!(!o.warning);
            } else {
                assert!(o.warning, "{tag}: warning until referenced");
            }
        }
        assert!(seen, "{tag}: homed");
        // Every index latch reads the index count.
        let idx: Vec<_> = out.iter().filter(|o| o.index_valid).collect();
        assert!(!idx.is_empty(), "{tag}: index latched");
        assert!(
            idx.iter().all(|o| o.index_qc == 100 && o.index_turns == 3),
            "{tag}"
        );
    }
}

#[test]
fn the_offset_wraps_into_the_turns_as_specified() {
    let p = params(0);
    // offset then apply is the identity on the target, and a step over the turn carries.
    for (t, b) in [
        ((100, 3), (8191, 0)),
        ((0, 0), (1, 0)),
        ((8191, 4095), (0, 7)),
    ] {
        let o = p.offset(t, b);
        assert_eq!(p.apply(b, o), t, "{t:?} from {b:?}");
    }
    let o = p.offset((8191, 0), (0, 0));
    assert_eq!(
        p.apply((1, 0), o),
        (0, 1),
        "one quadrant past the end of the turn"
    );
}

#[test]
fn a_preset_takes_the_next_sample_after_two_synchronizer_clocks() {
    let p = params(0);
    let (ins, truth) = stimulus(3000, 50.2, 0.2, |_| false, Some(1000));
    let out = run(&p, &ins, "ref_preset", RUST_ONLY);
    let first = out.iter().position(|o| o.referenced).expect("preset");
    // The sample taking the preset is the first valid from row 1002 on: the edge of row
    // 1000 takes the pin into the first synchronizer flop, 1001 into the second, and in row
    // 1002 the second is 1 and the edge register still 0.
    let taken = (1002..).find(|&c| ins[c].valid).expect("a sample");
    let (bq, bt) = (ins[taken].qc, ins[taken].turns);
    let o = p.offset((5000, mask(12)), (bq, bt));
    for k in first..out.len() {
        if out[k].valid {
            assert!(k > taken);
            assert_eq!(
                (out[k].qc, out[k].turns),
                p.apply((ins[k].qc, ins[k].turns), o)
            );
            assert!(truth[k].is_some());
        }
    }
}

#[test]
fn four_way_cosimulation() {
    for (gate, tag, seed) in [(0u32, "ref_cosim_a", 3u64), (3, "ref_cosim_b", 4)] {
        let p = params(gate);
        let mut r = SplitMix64(seed);
        let mut ins = vec![];
        let mut pos = 4.0;
        for k in 0..6000 {
            let valid = r.unit() < 0.1;
            if valid {
                pos += r.range(-40, 41) as f64 / 64.0;
            }
            let qf = pos.floor() as i64;
            ins.push(ReferenceIn {
                rst: k < 2 || r.unit() < 0.0005,
                conv: r.unit() < 0.05,
                z: (qf.rem_euclid(64)) < 6 || r.unit() < 0.01,
                preset: r.unit() < 0.002 || (k % 1500 > 1490),
                valid,
                qc: qf.rem_euclid(8192) as u64,
                fine: r.range(0, 16384) as u64,
                turns: (qf.div_euclid(8192) as u64) & mask(12),
                ..Default::default()
            });
        }
        let out = run(&p, &ins, tag, Simulators::ALL);
        assert!(out.iter().any(|o| o.index_valid));
        assert!(out.iter().any(|o| o.referenced));
    }
}

/// The target words of T = (tq, tt) as the absolute start gives them (Q = 8192, M = 12).
fn abs_target(tq: u64, tt: u64) -> [u64; 6] {
    [
        tq,
        tq.wrapping_sub(8192) & mask(14),
        tq + 8192,
        tt,
        tt.wrapping_sub(1) & mask(12),
        (tt + 1) & mask(12),
    ]
}

#[test]
fn an_absolute_request_makes_its_sample_read_the_target() {
    // Away from the index; at row 1500 (no sample there) the absolute start asks for
    // T = (5000, turn 7) for the count B of the sample that left at row 1000.
    let p = params(0).with_absolute(true);
    let (mut ins, _) = stimulus(3000, 50.2, 0.2, |_| false, None);
    let b_row = (1000..).find(|&c| ins[c].valid).expect("a sample");
    let b = (ins[b_row].qc, ins[b_row].turns);
    assert!(!ins[1500].valid);
    ins[1500].abs_req = true;
    for i in ins.iter_mut().skip(1500) {
        i.abs_t = abs_target(5000, 7);
        i.abs_b = b;
    }
    let out = run(&p, &ins, "ref_abs", RUST_ONLY);
    let o = p.offset((5000, 7), b);
    // The offset is taken in the clock after the request; every later sample reads in + T - B.
    let mut seen = 0;
    for k in 1502..out.len() {
        if ins[k].valid {
            seen += 1;
            assert_eq!(
                (out[k].qc, out[k].turns),
                p.apply((ins[k].qc, ins[k].turns), o)
            );
            assert!(out[k].referenced && !out[k].warning);
        }
    }
    assert!(seen > 10);
    assert!(out[..1501].iter().all(|o| !o.referenced));
    // B itself would read T.
    assert_eq!(p.apply(b, o), (5000, 7));
}

#[test]
fn four_way_cosimulation_with_the_absolute_start() {
    let p = params(1).with_absolute(true);
    let mut r = SplitMix64(9);
    let mut ins = vec![];
    let mut pos = 40.0;
    for k in 0..5000 {
        let valid = r.unit() < 0.1;
        if valid {
            pos += r.range(-40, 41) as f64 / 64.0;
        }
        let qf = pos.floor() as i64;
        ins.push(ReferenceIn {
            rst: k < 2 || r.unit() < 0.0005,
            conv: r.unit() < 0.05,
            z: qf.rem_euclid(64) < 6,
            preset: r.unit() < 0.001,
            valid,
            qc: qf.rem_euclid(8192) as u64,
            fine: r.range(0, 16384) as u64,
            turns: (qf.div_euclid(8192) as u64) & mask(12),
            // Requests in any row (with samples too), random words in every port.
            abs_req: r.unit() < 0.003,
            abs_t: [0; 6].map(|_| r.next_u64() & mask(16)),
            abs_b: (r.range(0, 8191) as u64, r.range(0, 4095) as u64),
        });
    }
    let out = run(&p, &ins, "ref_cosim_abs", Simulators::ALL);
    assert!(out.iter().any(|o| o.referenced));
}

#[test]
fn bad_parameters_are_rejected_with_a_message() {
    let msg = |r: sinedec::error::Result<ReferenceParams>| r.expect_err("rejected").to_string();
    assert!(msg(ReferenceParams::new(
        6,
        0,
        0,
        (0, 0),
        (0, 0),
        10,
        5,
        true,
        true
    ))
    .contains("4 * PPR"));
    assert!(msg(ReferenceParams::new(
        8,
        0,
        4,
        (0, 0),
        (0, 0),
        10,
        5,
        true,
        true
    ))
    .contains("gate"));
    assert!(msg(ReferenceParams::new(
        8,
        2,
        0,
        (8, 0),
        (0, 0),
        10,
        5,
        true,
        true
    ))
    .contains("below 8"));
}

#[test]
fn synthesizes_for_both_families() {
    let p = params(0);
    let mut uut = PositionReference::new(&p);
    rust_hdl::prelude::Block::connect_all(&mut uut);
    let name = "reference_synth";
    let v = sinedec::emit::verilog::export(&uut, name, name).expect("export");
    let dir = common::workdir(name);
    let x = synthesize(&v, name, Family::Xc3sa, &dir).expect("xc3sa synthesis");
    let c = synthesize(&v, name, Family::CycloneIve, &dir).expect("cycloneive synthesis");
    eprintln!(
        "{name}: xc3sa {} LUT, {} FF; cycloneive {} LE, {} FF",
        x.luts, x.ffs, c.luts, c.ffs
    );
    // Registers: the offset (13 + 14 + 12 + 12), the output (14 + 14 + 12 + flags), the
    // index latch (13 + 12), the tag and the synchronizers: about 150.
    assert!(x.ffs > 100 && x.ffs < 220, "{} FF", x.ffs);
}
