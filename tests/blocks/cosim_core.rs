//! The exported `<name>_core` in Icarus and Verilator == rust-hdl == model, bit for bit,
//! for every iteration count 1..=20 and the directed and random stimulus.
use crate::common;
use sinedec::cosim::stimulus;
use sinedec::verify::{core_traces, Simulators};

fn run(n: u32, f: u32, a: u32, ppr: u32, mt: u32, seed: u64) {
    let l = common::cfg_named(&format!("n{n}"), n, f, a, ppr, mt);
    let mut s = stimulus::directed(a);
    s.extend(stimulus::random(a, 1500, 0.25, seed));
    // Slow rotation over several turns both ways, to wrap the counters.
    let step = std::f64::consts::FRAC_PI_2 * 0.9;
    s.extend(stimulus::rotation(
        a,
        0.7,
        0.0,
        step,
        4 * ppr as usize * 2 + 40,
    ));
    s.extend(stimulus::rotation(
        a,
        0.7,
        0.0,
        -step,
        4 * ppr as usize * 3 + 40,
    ));
    let dir = common::workdir(&format!("cosim_core_n{n}_f{f}_a{a}"));
    let t = core_traces(&l, &s, Simulators::ALL, &dir).expect("all simulators ran");
    assert!(t.rust_hdl.iter().filter(|r| r[0] == 1).count() > 1000);
    if let Some(m) = t.mismatch(&l) {
        panic!("N={n} F={f} A={a}: {m}");
    }
}

#[test]
fn every_iteration_count_default_widths() {
    for n in 1..=20 {
        run(n, 14, 14, 3, 4, n as u64);
    }
}

#[test]
fn extreme_widths() {
    run(20, 16, 16, 5, 16, 100); // widest words
    run(1, 2, 10, 1, 0, 101); // narrowest, single-turn only
    run(11, 16, 10, 7, 3, 102); // most guard bits
}
