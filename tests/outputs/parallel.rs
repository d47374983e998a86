//! Parallel bus: the rust-hdl block against a reference written from the behaviour stated in
//! the module doc of src/blocks/parallel/mod.rs (registered words, one-cycle strobe, sticky
//! flags, hold, reset), and rust-hdl == Icarus == Verilator.
use crate::common;
use sinedec::blocks::mask;
use sinedec::blocks::parallel::hdl::ParallelBus;
use sinedec::blocks::parallel::ParallelParams;
use sinedec::cosim::stimulus::SplitMix64;
use sinedec::verify::{block_traces, Simulators};

/// Random rows: [rst, pos, turns, pos_valid, error, warning, hold], with bursts of hold and
/// of valid strobes, sparse flags and a few resets.
fn stimulus(n: usize, seed: u64) -> Vec<Vec<u64>> {
    let mut r = SplitMix64(seed);
    let mut hold = false;
    (0..n)
        .map(|k| {
            if r.next_u64().is_multiple_of(23) {
                hold = !hold;
            }
            vec![
                (k < 2 || r.next_u64().is_multiple_of(997)) as u64,
                r.next_u64() & mask(32),
                r.next_u64() & mask(32),
                (r.next_u64().is_multiple_of(3)) as u64,
                (r.next_u64().is_multiple_of(41)) as u64,
                (r.next_u64().is_multiple_of(53)) as u64,
                hold as u64,
            ]
        })
        .collect()
}

/// The expected outputs: [par_pos, par_turns, par_valid, par_error, par_warning] per row.
fn reference(p: &ParallelParams, rows: &[Vec<u64>]) -> Vec<Vec<u64>> {
    let mut o = vec![0u64; 5];
    let (mut eacc, mut wacc) = (false, false);
    rows.iter()
        .map(|r| {
            let (rst, valid, err, warn, hold) =
                (r[0] != 0, r[3] != 0, r[4] != 0, r[5] != 0, r[6] != 0);
            if rst {
                o = vec![0; 5];
                eacc = false;
                wacc = false;
            } else if valid && !hold {
                o = vec![
                    r[1] & mask(p.position_bits),
                    r[2] & mask(p.multiturn_bits),
                    1,
                    (err || eacc) as u64,
                    (warn || wacc) as u64,
                ];
                eacc = false;
                wacc = false;
            } else {
                o[2] = 0;
                eacc |= err;
                wacc |= warn;
            }
            o.clone()
        })
        .collect()
}

#[test]
fn params_are_validated() {
    assert!(ParallelParams::new(19, 12).is_ok());
    assert!(ParallelParams::new(32, 32).is_ok());
    assert!(ParallelParams::new(0, 0)
        .unwrap_err()
        .to_string()
        .contains("position_bits"));
    assert!(ParallelParams::new(33, 0).is_err());
    assert!(ParallelParams::new(19, 33)
        .unwrap_err()
        .to_string()
        .contains("multiturn_bits"));
}

#[test]
fn matches_reference_in_three_simulators() {
    for (st, mt, seed) in [(19, 0, 1), (13, 12, 2), (32, 32, 3)] {
        let p = ParallelParams::new(st, mt).unwrap();
        let rows = stimulus(6000, seed);
        let dir = common::workdir(&format!("parallel_{st}_{mt}"));
        let t = block_traces(
            ParallelBus::new(&p).unwrap(),
            "par_bus",
            "clk",
            &rows,
            Simulators::ALL,
            &dir,
        )
        .expect("simulators ran");
        if let Some(m) = t.mismatch() {
            panic!("{m}");
        }
        let want = reference(&p, &rows);
        for (k, (g, w)) in t.rust_hdl.iter().zip(&want).enumerate() {
            assert_eq!(g, w, "row {k}");
        }
        // The stimulus exercised what it should.
        assert!(want.iter().filter(|o| o[2] == 1).count() > 600);
        assert!(want.iter().filter(|o| o[3] == 1).count() > 50);
    }
}

#[test]
fn synthesizes_for_both_families() {
    use sinedec::synth::{synthesize, Family};
    let p = ParallelParams::new(19, 12).unwrap();
    let mut uut = ParallelBus::new(&p).unwrap();
    rust_hdl::prelude::Block::connect_all(&mut uut);
    let v = sinedec::emit::verilog::export(&uut, "par", "par_bus").expect("export");
    let dir = common::workdir("par_synth");
    let want = 19 + 12 + 5;
    for fam in [Family::Xc3sa, Family::CycloneIve] {
        let s = synthesize(&v, "par_bus", fam, &dir).expect("synthesis");
        eprintln!("parallel {}: {} LUT, {} FF", fam.name(), s.luts, s.ffs);
        assert_eq!(s.ffs, want, "flip-flops");
    }
}
