//! QEP decoder and QEP/CORDIC cross-check: rust-hdl == model cycle for cycle, rust-hdl ==
//! Icarus == Verilator, and behaviour against independent references (random walk in both
//! directions, glitches shorter / not shorter than the filter, index latch, double
//! transitions, counter wrap, cross-check tolerance across turn wraps).
use crate::common;
use sinedec::blocks::mask;
use sinedec::blocks::qep::hdl::{QepCrossCheck, QepDecoder};
use sinedec::blocks::qep::model::{CrossCheckIn, CrossCheckModel, QepIn, QepModel};
use sinedec::blocks::qep::{CrossCheckParams, QepParams};
use sinedec::cosim::stimulus::SplitMix64;
use sinedec::cosim::CosimBlock;
use sinedec::synth::{synthesize, Family, SynthStats};
use sinedec::verify::{block_traces, Simulators};

const RUST_ONLY: Simulators = Simulators {
    icarus: false,
    verilator: false,
};

/// Runs `uut` on `rows` in the chosen simulators; asserts rust-hdl == `model` row by row
/// and the Verilog simulators == rust-hdl; returns the rust-hdl trace.
fn check<B: CosimBlock>(
    uut: B,
    tag: &str,
    rows: &[Vec<u64>],
    model: &[Vec<u64>],
    sims: Simulators,
) -> Vec<Vec<u64>> {
    let dir = common::workdir(tag);
    let t = block_traces(uut, tag, "clk", rows, sims, &dir).expect("simulators ran");
    assert_eq!(t.rust_hdl.len(), model.len());
    for (k, (r, m)) in t.rust_hdl.iter().zip(model).enumerate() {
        assert_eq!(
            r, m,
            "{tag} row {k}: rust-hdl vs model (inputs {:?})",
            rows[k]
        );
    }
    if let Some(m) = t.mismatch() {
        panic!("{tag}: {m}");
    }
    t.rust_hdl
}

/// (A, B) of quadrant position `pos`: forward sequence 00 -> 10 -> 11 -> 01.
fn levels(pos: i64) -> (bool, bool) {
    match pos.rem_euclid(4) {
        0 => (false, false),
        1 => (true, false),
        2 => (true, true),
        _ => (false, true),
    }
}

/// A random walk with holds of at least `2F + 2` clocks; in some holds a glitch of
/// 1..F-1 clocks on A or B (after the new level has been stable F clocks). Returns the
/// inputs and the true position applied in each row.
fn walk(f: u32, n_moves: usize, glitch: bool, seed: u64) -> (Vec<QepIn>, Vec<i64>) {
    let mut r = SplitMix64(seed);
    let f = f as i64;
    let mut ins = vec![
        QepIn {
            rst: true,
            ..QepIn::default()
        };
        4
    ];
    let mut pos_at = vec![0i64; 4];
    let mut pos = 0i64;
    let mut dir = 1i64;
    for _ in 0..n_moves {
        let h = r.range(2 * f + 2, 2 * f + 25) as usize;
        let (a, b) = levels(pos);
        let mut seg = vec![
            QepIn {
                rst: false,
                a,
                b,
                z: false
            };
            h
        ];
        if glitch && f > 1 && r.unit() < 0.6 {
            let l = r.range(1, f - 1) as usize;
            let o = r.range(f, (h - l - 1) as i64) as usize;
            let on_a = r.next_u64() & 1 == 1;
            for s in &mut seg[o..o + l] {
                if on_a {
                    s.a = !s.a;
                } else {
                    s.b = !s.b;
                }
            }
        }
        for s in seg {
            ins.push(s);
            pos_at.push(pos);
        }
        if r.unit() < 0.1 {
            dir = -dir;
        }
        pos += if r.unit() < 0.85 { dir } else { -dir };
    }
    (ins, pos_at)
}

fn model_rows(p: &QepParams, ins: &[QepIn]) -> Vec<Vec<u64>> {
    let mut m = QepModel::new(p);
    ins.iter().map(|i| m.step(*i).row()).collect()
}

#[test]
fn decoder_random_walk_with_short_glitches_counts_exactly() {
    for (f, c, seed) in [(4u32, 16u32, 1u64), (1, 12, 2), (9, 32, 3)] {
        let p = QepParams::new(f, c).unwrap();
        let (ins, pos) = walk(f, 400, true, seed);
        let rows: Vec<Vec<u64>> = ins.iter().map(|i| i.row()).collect();
        let out = check(
            QepDecoder::new(&p),
            &format!("qep_walk_f{f}"),
            &rows,
            &model_rows(&p, &ins),
            RUST_ONLY,
        );
        // Independent reference: the count is the true position F + 2 rows earlier;
        // glitches shorter than F never show, in any row.
        let lat = f as usize + 2;
        let (mut lo, mut hi) = (0i64, 0i64);
        for k in 4 + lat..ins.len() {
            let want = pos[k - lat] as u64 & mask(c);
            assert_eq!(out[k][0], want, "F={f}: count at row {k}");
            assert_eq!(out[k][4], 0, "F={f}: no illegal transition at row {k}");
            lo = lo.min(pos[k]);
            hi = hi.max(pos[k]);
        }
        assert!(lo < -3 && hi > 3, "the walk went both ways ({lo}..{hi})");
    }
}

#[test]
fn pulses_shorter_than_the_filter_are_ignored_longer_ones_counted() {
    let f = 5u32;
    let p = QepParams::new(f, 16).unwrap();
    for l in 1..=f + 2 {
        for on_a in [true, false] {
            // Rest at position 1 (A=1, B=0), pulse one channel for l clocks.
            let mut ins = vec![
                QepIn {
                    rst: true,
                    a: true,
                    ..QepIn::default()
                };
                4
            ];
            ins.extend(vec![
                QepIn {
                    a: true,
                    ..QepIn::default()
                };
                20
            ]);
            let s = ins.len();
            for _ in 0..l {
                ins.push(if on_a {
                    QepIn::default()
                } else {
                    QepIn {
                        a: true,
                        b: true,
                        ..QepIn::default()
                    }
                });
            }
            ins.extend(vec![
                QepIn {
                    a: true,
                    ..QepIn::default()
                };
                30
            ]);
            let rows: Vec<Vec<u64>> = ins.iter().map(|i| i.row()).collect();
            let out = check(
                QepDecoder::new(&p),
                "qep_pulse",
                &rows,
                &model_rows(&p, &ins),
                RUST_ONLY,
            );
            // Dropping A at position 1 goes back to 0 (-1); raising B goes on to 2 (+1).
            let delta: u64 = if on_a { mask(16) } else { 1 };
            let first = s + f as usize + 2;
            for (k, o) in out.iter().enumerate() {
                let moved = l >= f && k >= first && k < first + l as usize;
                let want = if moved { delta } else { 0 };
                assert_eq!(
                    o[0],
                    want,
                    "pulse of {l} clocks on {}: row {k}",
                    if on_a { "A" } else { "B" }
                );
            }
        }
    }
}

#[test]
fn index_latches_the_count_and_double_transitions_are_illegal() {
    let f = 3u32;
    let p = QepParams::new(f, 10).unwrap();
    let (mut ins, pos) = walk(f, 60, false, 9);
    // Z pulses of F clocks at chosen rows (in the middle of holds is not required).
    let zrows = [100usize, 400, 777];
    for &z in &zrows {
        for s in &mut ins[z..z + f as usize + 1] {
            s.z = true;
        }
    }
    // A double transition: at the end, from the final position toggle both A and B.
    let last = *ins.last().unwrap();
    let dbl = ins.len();
    ins.extend(vec![
        QepIn {
            a: !last.a,
            b: !last.b,
            ..last
        };
        20
    ]);
    let mut pos = pos;
    pos.extend(vec![*pos.last().unwrap(); 20]);
    let rows: Vec<Vec<u64>> = ins.iter().map(|i| i.row()).collect();
    let out = check(
        QepDecoder::new(&p),
        "qep_index",
        &rows,
        &model_rows(&p, &ins),
        RUST_ONLY,
    );
    let lat = f as usize + 2;
    let strobes: Vec<usize> = (0..out.len()).filter(|&k| out[k][2] == 1).collect();
    assert_eq!(strobes, zrows.iter().map(|z| z + lat).collect::<Vec<_>>());
    for (&z, &k) in zrows.iter().zip(&strobes) {
        assert_eq!(
            out[k][1],
            pos[z] as u64 & mask(10),
            "index count at Z row {z}"
        );
        assert_eq!(out[k][1], out[k][0]);
        assert_eq!(out[k][3], 1, "index_seen");
    }
    assert_eq!(
        out[zrows[0] + lat - 1][3],
        0,
        "index_seen before the first Z"
    );
    let ill: Vec<usize> = (0..out.len()).filter(|&k| out[k][4] == 1).collect();
    assert_eq!(
        ill,
        vec![dbl + lat],
        "one illegal pulse for the double transition"
    );
    assert_eq!(
        out[dbl + lat][0],
        pos[dbl - 1] as u64 & mask(10),
        "count unchanged"
    );
    assert_eq!(out.last().unwrap()[5], 1, "illegal_seen is sticky");
}

/// Random raw inputs every clock (including resets), for cosim and model coverage.
fn raw_qep(n: usize, seed: u64) -> Vec<QepIn> {
    let mut r = SplitMix64(seed);
    let (mut a, mut b, mut z) = (false, false, false);
    (0..n)
        .map(|k| {
            // Mostly slow changes (held a few clocks), sometimes fast toggles.
            let rate = if (k / 500) % 2 == 0 { 0.15 } else { 0.6 };
            if r.unit() < rate {
                a = !a;
            }
            if r.unit() < rate {
                b = !b;
            }
            if r.unit() < rate / 4.0 {
                z = !z;
            }
            QepIn {
                rst: k < 2 || r.unit() < 0.002,
                a,
                b,
                z,
            }
        })
        .collect()
}

#[test]
fn decoder_in_three_simulators() {
    for (f, c, tag) in [(3u32, 8u32, "qep_cosim_a"), (1, 32, "qep_cosim_b")] {
        let p = QepParams::new(f, c).unwrap();
        let mut ins = raw_qep(3000, 17 + f as u64);
        let (w, _) = walk(f, 120, true, 5);
        ins.extend(w);
        let rows: Vec<Vec<u64>> = ins.iter().map(|i| i.row()).collect();
        let out = check(
            QepDecoder::new(&p),
            tag,
            &rows,
            &model_rows(&p, &ins),
            Simulators::ALL,
        );
        // The 8-bit counter must have wrapped in the fast part (coverage check).
        assert!(
            out.iter().any(|o| o[4] == 1),
            "{tag}: illegal transitions were exercised"
        );
    }
}

/// Cross-check stimulus: a position walk with steps up to `max_step` quadrants per sample,
/// the QEP count off by `noise` (reported per row), aligns and resets.
fn cross_stimulus(
    p: &CrossCheckParams,
    n: usize,
    max_step: i64,
    seed: u64,
) -> (Vec<CrossCheckIn>, Vec<i64>) {
    let mut r = SplitMix64(seed);
    let q = p.quadrants_per_turn() as i64;
    let c = p.count_width();
    let (qep0, qc0) = (r.range(0, 1 << 20), r.range(0, q - 1));
    let mut pos = 0i64;
    let mut ins = vec![
        CrossCheckIn {
            rst: true,
            ..CrossCheckIn::default()
        };
        2
    ];
    let mut noise_at = vec![0; 2];
    for _ in 0..n {
        let valid = r.unit() < 0.7;
        if valid {
            pos += r.range(-max_step, max_step);
        }
        let noise = if r.unit() < 0.8 { 0 } else { r.range(-3, 3) };
        ins.push(CrossCheckIn {
            rst: false,
            valid,
            align: false,
            qep_count: (pos + qep0 + noise) as u64 & mask(c),
            cordic_qc: (pos + qc0).rem_euclid(q) as u64,
        });
        noise_at.push(noise);
    }
    (ins, noise_at)
}

#[test]
fn cross_check_flags_disagreements_beyond_one_quadrant() {
    // Q = 4 * 5 (not a power of two), 8-bit QEP count (wraps), steps up to 9 quadrants.
    let p = CrossCheckParams::new(8, 20, 1).unwrap();
    let (ins, noise) = cross_stimulus(&p, 3000, 9, 4);
    let rows: Vec<Vec<u64>> = ins.iter().map(|i| i.row()).collect();
    let mut m = CrossCheckModel::new(&p);
    let model: Vec<Vec<u64>> = ins.iter().map(|i| m.step(*i).row()).collect();
    let out = check(QepCrossCheck::new(&p), "xchk", &rows, &model, RUST_ONLY);
    // The first valid sample aligns on noise n0; afterwards diff = noise - n0.
    let first = (0..ins.len())
        .find(|&k| ins[k].valid && !ins[k].rst)
        .unwrap();
    let n0 = noise[first];
    let mut last = (0i64, false);
    let mut flagged = 0;
    for k in first + 1..ins.len() {
        if ins[k].valid {
            let d = noise[k] - n0;
            last = (d, d.abs() > 1);
        }
        assert_eq!(out[k][1], last.0 as u64 & mask(8), "diff at row {k}");
        assert_eq!(out[k][0] == 1, last.1, "mismatch at row {k}");
        flagged += last.1 as usize;
    }
    assert!(flagged > 50, "mismatches were exercised");
}

#[test]
fn cross_check_in_three_simulators() {
    let p = CrossCheckParams::new(16, 4 * 2048, 1).unwrap();
    let (mut ins, _) = cross_stimulus(&p, 2500, 4000, 8);
    // Aligns and resets mid-stream.
    for k in (100..ins.len()).step_by(317) {
        ins[k].align = true;
    }
    for k in (50..ins.len()).step_by(911) {
        ins[k].rst = true;
    }
    // Junk above the 13 bits of a count 0..8191 must be ignored.
    for k in (7..ins.len()).step_by(13) {
        ins[k].cordic_qc |= (k as u64 * 0x9e37) << 13;
    }
    let rows: Vec<Vec<u64>> = ins.iter().map(|i| i.row()).collect();
    let mut m = CrossCheckModel::new(&p);
    let model: Vec<Vec<u64>> = ins.iter().map(|i| m.step(*i).row()).collect();
    let out = check(
        QepCrossCheck::new(&p),
        "xchk_cosim",
        &rows,
        &model,
        Simulators::ALL,
    );
    assert!(out.iter().any(|o| o[0] == 1) && out.iter().any(|o| o[0] == 0));
}

#[test]
fn bad_parameters_are_rejected_with_a_message() {
    assert!(QepParams::new(0, 16)
        .unwrap_err()
        .to_string()
        .contains("filter"));
    assert!(QepParams::new(65536, 16).is_err());
    assert!(QepParams::new(3, 33)
        .unwrap_err()
        .to_string()
        .contains("width"));
    assert!(QepParams::new(3, 1).is_err());
    assert!(CrossCheckParams::new(16, 6, 1)
        .unwrap_err()
        .to_string()
        .contains("4 * PPR"));
    assert!(CrossCheckParams::new(2, 8, 1)
        .unwrap_err()
        .to_string()
        .contains("tolerance"));
    assert!(CrossCheckParams::new(16, 8, 1).is_ok());
}

/// Exports `uut` and synthesizes it with Yosys for xc3sa and cycloneive under the project's
/// rules (no latch, no undriven net, no unexpected warning); returns both statistics.
fn synth<B: rust_hdl::prelude::Block>(mut uut: B, name: &str) -> (SynthStats, SynthStats) {
    uut.connect_all();
    let v = sinedec::emit::verilog::export(&uut, name, name).expect("export");
    let dir = common::workdir(name);
    let x = synthesize(&v, name, Family::Xc3sa, &dir).expect("xc3sa synthesis");
    let c = synthesize(&v, name, Family::CycloneIve, &dir).expect("cycloneive synthesis");
    eprintln!(
        "{name}: xc3sa {} LUT, {} FF, {} MULT18X18; cycloneive {} LE, {} FF",
        x.luts, x.ffs, x.multipliers, c.luts, c.ffs
    );
    (x, c)
}

#[test]
fn synthesizes_for_both_families() {
    let (x, c) = synth(
        QepDecoder::new(&QepParams::new(4, 16).unwrap()),
        "qep_synth",
    );
    // 6 sync, 3 filtered, 3 x 2-bit counters, 3 previous, 16 + 16 count/index, 4 flags.
    assert!(x.ffs >= 40 && x.ffs <= 56, "{} FF", x.ffs);
    assert_eq!(c.ffs, x.ffs);
    let p = CrossCheckParams::new(16, 4 * 2048, 1).unwrap();
    let (x, _) = synth(QepCrossCheck::new(&p), "xchk_synth");
    // init, qc_prev (13 bits), cc, off, diff (16 each), mismatch.
    assert!(x.ffs >= 50 && x.ffs <= 70, "{} FF", x.ffs);
}
