//! rust-hdl simulation of the core == the bit-accurate model, cycle for cycle.
use crate::common;
use common::cfg;
use sinedec::blocks::core::hdl::simulate_rtl;
use sinedec::blocks::core::model::{CoreIn, CoreModel};
use sinedec::config::Loaded;
use sinedec::cosim::stimulus;

fn check(l: &Loaded, stim: &[CoreIn]) {
    let d = &l.derived;
    let rtl = simulate_rtl(d, stim).expect("rust-hdl settles");
    let mut m = CoreModel::new(d);
    for (k, (i, r)) in stim.iter().zip(&rtl).enumerate() {
        let o = m.step(*i);
        assert_eq!(o, *r, "cycle {k}, input {i:?}, N={}", d.iterations);
    }
}

#[test]
fn default_config_directed_and_random() {
    let l = cfg(14, 14, 14, 2048, 12);
    let mut s = stimulus::directed(14);
    s.extend(stimulus::random(14, 3000, 0.2, 1));
    check(&l, &s);
}

#[test]
fn outputs_are_not_trivial() {
    let l = cfg(14, 14, 14, 2048, 12);
    let s = stimulus::rotation(14, 0.9, 0.1, 0.3, 200);
    let rtl = simulate_rtl(&l.derived, &s).expect("settles");
    let valid: Vec<_> = rtl.iter().filter(|o| o.valid).collect();
    assert_eq!(valid.len(), 200 - l.derived.latency_cycles as usize);
    let positions: std::collections::BTreeSet<u64> = valid.iter().map(|o| o.position).collect();
    assert!(positions.len() > 150, "{positions:?}");
    eprintln!("{:?}", &valid[..5]);
}
