//! Resynchronisation of the quadrant counter (used by the QEP fallback): the model, the
//! rust-hdl simulation, Icarus and Verilator agree on random loads; and a load moves the
//! count to the nearest value congruent with the sample's quadrant.
use crate::common;
use sinedec::blocks::core::hdl::{simulate_rtl, CoreRtl};
use sinedec::blocks::core::model::{CoreIn, CoreModel};
use sinedec::blocks::counter::model::Load;
use sinedec::blocks::mask;
use sinedec::cosim::stimulus::{self, SplitMix64};
use sinedec::verify::{block_traces, Simulators};

fn with_loads(l: &sinedec::config::Loaded, seed: u64) -> Vec<CoreIn> {
    let d = &l.derived;
    let mut r = SplitMix64(seed);
    let mut s = stimulus::random(d.adc_width, 1200, 0.2, seed);
    for i in s.iter_mut() {
        if r.unit() < 0.03 {
            i.load = Some(Load {
                qc: r.next_u64() % d.quadrants_per_turn,
                turns: r.next_u64() & mask(d.multiturn_bits),
            });
        }
    }
    s
}

#[test]
fn loads_agree_in_every_simulator() {
    let l = common::cfg(6, 12, 14, 5, 3);
    let d = &l.derived;
    let s = with_loads(&l, 9);
    assert!(s.iter().filter(|i| i.load.is_some()).count() > 20);
    let rtl = simulate_rtl(d, &s).expect("settles");
    let mut m = CoreModel::new(d);
    for (k, (i, o)) in s.iter().zip(&rtl).enumerate() {
        assert_eq!(m.step(*i), *o, "cycle {k}");
    }
    let am = mask(14);
    let rows: Vec<Vec<u64>> = s
        .iter()
        .map(|i| {
            let ld = i.load.unwrap_or_default();
            vec![
                i.rst as u64,
                i.valid as u64,
                i.sin as u64 & am,
                i.cos as u64 & am,
                i.load.is_some() as u64,
                ld.qc,
                ld.turns,
            ]
        })
        .collect();
    let dir = common::workdir("counter_load");
    let t = block_traces(
        CoreRtl::new(d),
        "core_load",
        "clk",
        &rows,
        Simulators::ALL,
        &dir,
    )
    .expect("simulators ran");
    if let Some(m) = t.mismatch() {
        panic!("{m}");
    }
}

#[test]
fn load_takes_the_nearest_congruent_count() {
    let l = common::cfg(14, 14, 14, 2048, 12);
    let d = &l.derived;
    let mut m = CoreModel::new(d);
    // Electrical angle 1.3 rad: quadrant 0, fine 0.83 quadrant.
    let sample = stimulus::rotation(14, 0.8, 1.3, 0.0, 1)[0];
    let mut s = vec![stimulus::reset(), sample];
    let mut ld = sample;
    ld.load = Some(Load { qc: 8191, turns: 7 }); // 8191 = 3 mod 4: nearest 0-congruent is +1
    s.push(ld);
    s.push(sample);
    s.extend((0..20).map(|_| stimulus::idle()));
    let outs: Vec<_> = s.iter().map(|i| m.step(*i)).filter(|o| o.valid).collect();
    assert_eq!(outs.len(), 3);
    let fine = outs[0].fine;
    assert_eq!(outs[0].position >> 14, 0);
    // The second sample entered the pipeline together with the load request; it is the
    // first accepted sample after the request reached the counter: wrapped to qc 0, turns 8.
    assert_eq!(outs[1].position, fine, "{:?}", outs[1]);
    assert_eq!(outs[1].turns, 8);
    assert_eq!(outs[2].position, fine);
    assert_eq!(outs[2].turns, 8);
}

/// Small and odd PPR (u of 0..2 bits, power of two or not), narrow turn counters, random
/// loads at every count: the rust-hdl core equals the model, so every wrap of u and of the
/// turns is exercised with and without a pending load.
#[test]
fn loads_and_wraps_agree_with_the_model_for_small_ppr() {
    for (k, (ppr, mt)) in [(1, 0), (1, 2), (2, 1), (3, 2), (4, 3), (6, 2), (8, 12)]
        .into_iter()
        .enumerate()
    {
        let l = common::cfg(1, 3 + k as u32 % 3, 10, ppr, mt);
        let d = &l.derived;
        let mut r = SplitMix64(50 + k as u64);
        let mut s = stimulus::random(d.adc_width, 3000, 0.2, 70 + k as u64);
        for i in s.iter_mut() {
            if r.unit() < 0.05 {
                i.load = Some(Load {
                    qc: r.next_u64() % d.quadrants_per_turn,
                    turns: r.next_u64() & mask(d.multiturn_bits),
                });
            }
        }
        let rtl = simulate_rtl(d, &s).expect("settles");
        let mut m = CoreModel::new(d);
        let mut loads = 0;
        for (c, (i, o)) in s.iter().zip(&rtl).enumerate() {
            loads += i.load.is_some() as usize;
            assert_eq!(m.step(*i), *o, "PPR {ppr}, M {mt}, cycle {c}");
        }
        assert!(loads > 100, "PPR {ppr}: {loads} loads");
    }
}
