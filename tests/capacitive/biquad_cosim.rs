//! Time-multiplexed biquad engine: the model against hand-computed impulse responses and a
//! floating-point reference; rust-hdl == clock-level model == Icarus == Verilator on an
//! impulse, a saturating full-scale step, random stimulus, back-to-back strobes and a reset
//! in the middle of a computation; exactly one `$mul` after Yosys coarse synthesis; the
//! Cyclone III figures.
//!
//! (Second half of the tests of `tests/capacitive/biquad.rs`; helpers in `tests/capacitive/biquad_util/`.)
use crate::biquad_util;
use crate::common;
use biquad_util::*;
use rust_hdl::prelude::Block;
use sinedec::blocks::biquad::hdl::BiquadRtl;
use sinedec::blocks::biquad::model::{BiquadIn, BiquadModel};
use sinedec::blocks::biquad::BiquadParams;
use sinedec::cosim::stimulus::SplitMix64;
use sinedec::synth::{parse_stat_json, synthesize, Family};

#[test]
fn cosim_random_stimulus_several_shapes() {
    let mut r = SplitMix64(2024);
    // (data, coef, frac, guard, sections per branch)
    let shapes: [(u32, u32, u32, u32, &[usize]); 4] = [
        (16, 18, 16, 2, &[2, 1, 1]),
        (16, 25, 23, 8, &[1, 2, 2]),
        (18, 18, 16, 0, &[3]),
        (17, 20, 17, 4, &[1, 1, 2, 1]),
    ];
    for (i, (d, c, f, g, secs)) in shapes.iter().enumerate() {
        let branches = secs
            .iter()
            .map(|&n| (0..n).map(|_| random_section(&mut r, *f)).collect())
            .collect();
        let p = BiquadParams::new(*d, *c, *f, *g, branches).expect("valid");
        let per = p.cycles_per_sample() as usize;
        let full = 1i64 << (d - 1);
        let mut ins = reset(&p);
        for _ in 0..60 {
            let data = (0..p.branch_count())
                .map(|_| r.range(-full, full - 1))
                .collect();
            ins.push(sample(data));
            // Random gaps: some shorter than the period (dropped), some longer.
            let gap = r.range(per as i64 / 2, per as i64 + 6) as usize;
            ins.extend(idle(gap));
        }
        ins.extend(idle(per + 2));
        let rows = cosim(&p, &ins, &format!("random{i}"));
        let k = p.branch_count();
        let dropped = rows.iter().filter(|r| r[k + 3] == 1).count();
        let accepted = outputs(&rows, &p).len();
        assert_eq!(dropped + accepted, 60, "shape {i}");
        assert!(dropped > 0 && accepted > 20, "shape {i}: {dropped} dropped");
    }
}

#[test]
fn cosim_back_to_back_strobes_are_dropped_while_busy() {
    let p = capacitive(16, 18, 16, 2, 1, 1);
    let per = p.cycles_per_sample() as usize;
    let mut ins = reset(&p);
    let start = ins.len();
    let n = 5 * per + 3;
    let mut rng = SplitMix64(5);
    for _ in 0..n {
        ins.push(sample(vec![
            rng.range(-30000, 30000),
            rng.range(-30000, 30000),
            rng.range(-30000, 30000),
        ]));
    }
    ins.extend(idle(per + 2));
    let rows = cosim(&p, &ins, "b2b");
    let k = p.branch_count();
    // in_valid every clock: exactly the strobes at start + j * per are accepted (busy is
    // low before those edges), every other one is flagged by the edge that ignores it.
    let accepted: Vec<usize> = (start..start + n)
        .filter(|&row| rows[row - 1][k + 2] == 0)
        .collect();
    let want: Vec<usize> = (0..n).step_by(per).map(|j| start + j).collect();
    assert_eq!(accepted, want);
    for (row, r) in rows.iter().enumerate().skip(start).take(n) {
        assert_eq!(
            r[k + 3] == 1,
            !want.contains(&row),
            "dropped flag at row {row}"
        );
    }
    // The outputs are those of the accepted samples only.
    let mut m = BiquadModel::new(&p);
    let outs = outputs(&rows, &p);
    assert_eq!(outs.len(), want.len());
    for (&row, (_, y, _)) in want.iter().zip(&outs) {
        assert_eq!(&m.step(&ins[row].data).0, y);
    }
}

#[test]
fn cosim_reset_mid_computation_restarts_clean() {
    let p = capacitive(16, 18, 16, 2, 2, 2);
    let per = p.cycles_per_sample() as usize;
    let mut rng = SplitMix64(77);
    let mut rand_samples = |n: usize| -> Vec<Vec<i64>> {
        (0..n)
            .map(|_| (0..3).map(|_| rng.range(-20000, 20000)).collect())
            .collect()
    };
    let before = rand_samples(6);
    let after = rand_samples(8);
    let mut ins = reset(&p);
    ins.extend(strobes(&before, per));
    // One more sample, cut by a reset in the middle of its computation (and a strobe
    // during the clearing sweep, which is dropped).
    ins.push(sample(vec![30000, -30000, 30000]));
    ins.extend(idle(per / 2));
    ins.push(BiquadIn {
        rst: true,
        ..Default::default()
    });
    ins.push(sample(vec![1, 2, 3]));
    ins.extend(idle(p.state_words() as usize));
    let restart = ins.len();
    ins.extend(strobes(&after, per));
    ins.extend(idle(per + 2));
    let rows = cosim(&p, &ins, "reset");
    let k = p.branch_count();
    let outs = outputs(&rows, &p);
    assert_eq!(
        outs.len(),
        before.len() + after.len(),
        "the cut sample has no output"
    );
    // After the reset: out_data cleared, and the new samples' outputs are those of a
    // freshly reset filter (no state left from before).
    let rst_row = restart - p.state_words() as usize - 2;
    assert!(rows[rst_row][1..=k].iter().all(|&v| v == 0));
    assert_eq!(
        rows[rst_row + 1][k + 3],
        1,
        "strobe during clearing flagged"
    );
    let mut fresh = BiquadModel::new(&p);
    for (s, (_, y, _)) in after.iter().zip(&outs[before.len()..]) {
        assert_eq!(&fresh.step(s).0, y);
    }
}

// ---------------------------------------------------------------- synthesis

#[test]
fn yosys_coarse_has_exactly_one_multiplier() {
    use sinedec::cosim::require_tool;
    if let Err(e) = require_tool("yosys") {
        panic!("yosys is needed for this test: {e}");
    }
    for (tag, p) in [
        ("bqm18", capacitive(16, 18, 16, 2, 2, 2)),
        ("bqm25", capacitive(16, 25, 23, 8, 2, 2)),
    ] {
        let mut uut = BiquadRtl::new(&p);
        uut.connect_all();
        let v = sinedec::emit::verilog::export(&uut, tag, tag).expect("export");
        let dir = common::workdir(&format!("biquad_{tag}_coarse"));
        let vf = dir.join("bq.v");
        std::fs::write(&vf, &v).expect("write verilog");
        // Before alumacc (which rewrites a lone $mul into a one-product $macc in Yosys
        // 0.23): exactly one $mul; after the whole coarse script: one $mul or $macc.
        let run = |tail: &str, name: &str| {
            let stat = dir.join(name);
            let out = std::process::Command::new("yosys")
                .arg("-q")
                .arg("-p")
                .arg(format!(
                    "read_verilog {}; hierarchy -check -top {tag}; proc; flatten; {tail}; tee -q -o {} stat -json",
                    vf.display(),
                    stat.display()
                ))
                .output()
                .expect("yosys runs");
            assert!(
                out.status.success(),
                "yosys failed: {}",
                String::from_utf8_lossy(&out.stderr)
            );
            parse_stat_json(&std::fs::read_to_string(&stat).expect("stat written"), tag)
                .expect("stat -json has the module")
        };
        let n =
            |c: &std::collections::BTreeMap<String, u64>, k: &str| c.get(k).copied().unwrap_or(0);
        let early = run("opt; wreduce", "stat_early.json");
        eprintln!("{tag}: proc; opt; wreduce: {early:?}");
        assert_eq!(n(&early, "$mul"), 1, "{tag}: exactly one $mul ({early:?})");
        assert_eq!(n(&early, "$macc"), 0);
        let coarse = run(&format!("synth -run coarse -top {tag}"), "stat_coarse.json");
        eprintln!("{tag}: synth -run coarse: {coarse:?}");
        assert_eq!(
            n(&coarse, "$mul") + n(&coarse, "$macc"),
            1,
            "{tag}: one multiplier cell after coarse synthesis ({coarse:?})"
        );
    }
}

#[test]
fn cyclone_iii_synthesis_figures() {
    // Yosys 0.23 `synth_intel -family cycloneive` has no DSP mapping: it builds the product
    // from logic cells (Quartus would use embedded 18x18 multipliers: one for 18 x 18, more
    // for 18 x 25). The multiplier alone is synthesized too so
    // its share of the logic is visible.
    use sinedec::blocks::biquad::hdl::BiquadMul;
    for (tag, p) in [
        ("bqc18", capacitive(16, 18, 16, 2, 2, 2)),
        // S = 18 here: with S > 18 (e.g. G = 8) Yosys 0.23 maps the state RAM to the M9K
        // 36-bit mode and warns "Resizing cell port ... from 32 bits to 36 bits", which
        // the project's synthesis gate rejects.
        ("bqc25", capacitive(16, 25, 23, 2, 2, 2)),
    ] {
        let mut uut = BiquadRtl::new(&p);
        uut.connect_all();
        let v = sinedec::emit::verilog::export(&uut, tag, tag).expect("export");
        let dir = common::workdir(&format!("biquad_{tag}_synth"));
        let s = synthesize(&v, tag, Family::CycloneIve, &dir).expect("cycloneive synthesis");
        let ram = s.cells.get("altsyncram").copied().unwrap_or(0);
        let mut mul = BiquadMul::new(p.state_width(), p.coef_width, p.coef_frac);
        mul.connect_all();
        let mtag = format!("{tag}_mul");
        let vm = sinedec::emit::verilog::export(&mul, &mtag, &mtag).expect("export");
        let sm = synthesize(&vm, &mtag, Family::CycloneIve, &dir).expect("multiplier synthesis");
        eprintln!(
            "{tag}: {}x{} product, {} sections, {} clocks/sample: cycloneive {} LE ({} in the multiplier), {} FF, {} DSP multiplier cells, {} altsyncram (state RAM); cells {:?}",
            p.state_width(),
            p.coef_width,
            p.total_sections(),
            p.cycles_per_sample(),
            s.luts,
            sm.luts,
            s.ffs,
            s.multipliers,
            ram,
            s.cells
        );
        assert!(s.luts > sm.luts && sm.luts > 0);
        assert_eq!(ram, 1, "{tag}: the state memory is one RAM block");
        // Registers: pc, parity, clear counter, xcur, coef, prod, acc, 3 x (input latch,
        // output stage, output) and flags: well below the RAM's bits; plus the multiplier's
        // operand registers (S + C) and the program word register (C + 19 control bits).
        let k = p.branch_count() as u64;
        let (d, sw, c, a) = (
            p.data_width as u64,
            p.state_width() as u64,
            p.coef_width as u64,
            p.acc_width() as u64,
        );
        let bound = 3 * k * d + k + sw + c + 2 * a + 2 * 10 + 16 + (sw + c) + (c + 19);
        assert!(s.ffs <= bound, "{tag}: {} FF > {bound}", s.ffs);
    }
}
