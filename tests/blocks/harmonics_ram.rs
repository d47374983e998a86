//! The harmonic-correction block with its table in RAM (the learned table, issue 46):
//! rust-hdl == model cycle for cycle == Icarus == Verilator == engine under writes to both
//! banks and bank flips; its arithmetic against the static block's model
//! (`harmonics::model::correct`) on the same table; the write port's conversion from the
//! learner's q units against a rounding in f64.
use crate::common;
use sinedec::blocks::harmonics::hdl_ram::HarmonicCorrectionRam;
use sinedec::blocks::harmonics::model::{
    correct, correct_ab, q_to_z, HarmonicIn, HarmonicRamIn, HarmonicRamModel,
};
use sinedec::blocks::harmonics::sequencer::TABLE_FRAC;
use sinedec::blocks::harmonics::HarmonicParams;
use sinedec::blocks::mask;
use sinedec::cosim::stimulus::SplitMix64;
use sinedec::verify::Simulators;

/// The default config's angle word: F = 14, Gz = 6, ZW = 22; the learner's entries,
/// within +-2^(F-4+T), are F - 4 + T + 2 = 20 bits.
const F: u32 = 14;
const GZ: u32 = 6;
const ZW: u32 = F + GZ + 2;
const E: u32 = F - 4 + TABLE_FRAC + 2;

/// A table of `n` entries drawn within +-`amp` LSB.
fn random_table(n: usize, amp: f64, seed: u64) -> Vec<f64> {
    let mut r = SplitMix64(seed);
    (0..n).map(|_| (r.unit() * 2.0 - 1.0) * amp).collect()
}

#[test]
fn the_ram_arithmetic_equals_the_static_blocks_on_the_same_table() {
    for (n, amp, seed) in [(16, 1024.0, 11), (64, 300.0, 12), (256, 1000.0, 13)] {
        let p = HarmonicParams::new(ZW, GZ, F, &random_table(n, amp, seed)).expect("params");
        let t: Vec<u64> = p.table.iter().map(|&c| c as u64 & mask(ZW)).collect();
        let mut r = SplitMix64(seed);
        for k in 0..100_000u64 {
            let z = if k < 1000 {
                ((k % n as u64) << (ZW - p.points_log2))
                    | ((k / n as u64) % 2 * mask(ZW - p.points_log2))
            } else {
                r.next_u64() & mask(ZW)
            };
            let i = (z >> (ZW - p.points_log2)) as usize;
            assert_eq!(
                correct_ab(ZW, p.points_log2, z, t[i], t[(i + 1) % n]),
                correct(&p, z),
                "{n} points, z = {z:#x}"
            );
        }
    }
}

#[test]
fn the_write_port_rounds_q_units_to_z_units() {
    let p = HarmonicParams::new(ZW, GZ, F, &[0.0; 16]).expect("params");
    let lim = 1i64 << (F - 4 + TABLE_FRAC);
    let s = f64::from(1u32 << (TABLE_FRAC - GZ));
    for q in (-lim..=lim).step_by(7).chain([-lim, -1, 0, 1, 2, 3, lim]) {
        let want = (q as f64 / s + 0.5).floor() as i64;
        assert_eq!(
            q_to_z(&p, E, q as u64 & mask(E)),
            want as u64 & mask(ZW),
            "q = {q}"
        );
    }
}

fn run_four_ways(n: usize, seed: u64, tag: &str) {
    let p = HarmonicParams::new(ZW, GZ, F, &random_table(n, 200.0, seed)).expect("params");
    let pts = n as u64;
    let lim = 1u64 << (F - 4 + TABLE_FRAC);
    let mut r = SplitMix64(seed);
    let cycles = 4000;
    let mut bank = false;
    let ins: Vec<HarmonicRamIn> = (0..cycles)
        .map(|c| {
            // Flip the bank now and then; write bursts of entries of either bank, among
            // them the one being read.
            if c % 500 == 250 {
                bank = !bank;
            }
            let tw = c % 9 < 4;
            let z = match c % 7 {
                0 => (r.next_u64() % pts) << (ZW - p.points_log2),
                1 => mask(ZW) - (r.next_u64() & 3),
                _ => r.next_u64() & mask(ZW),
            };
            HarmonicRamIn {
                core: HarmonicIn {
                    rst: c < 2 || (c > cycles / 2 && c < cycles / 2 + 3),
                    z,
                    x: r.next_u64() & mask(32),
                    v: r.next_u64() & 3 != 0,
                },
                bank,
                tw,
                tw_addr: if c % 5 == 0 {
                    (u64::from(bank) * pts) + (z >> (ZW - p.points_log2))
                } else {
                    r.next_u64() % (2 * pts)
                },
                tw_data: (r.next_u64() % (2 * lim + 1)).wrapping_sub(lim) & mask(E),
            }
        })
        .collect();
    let rows: Vec<Vec<u64>> = ins.iter().map(|i| i.row()).collect();
    let mut m = HarmonicRamModel::new(&p, E);
    let model: Vec<Vec<u64>> = ins.iter().map(|i| m.step(*i).row()).collect();
    common::check_against_model(
        HarmonicCorrectionRam::new(&p, E),
        tag,
        &rows,
        &model,
        Simulators::ALL,
    );
}

#[test]
fn rtl_equals_the_model_four_ways_under_writes_and_bank_flips() {
    run_four_ways(16, 21, "harmonics_ram_16");
    run_four_ways(64, 22, "harmonics_ram_64");
    run_four_ways(256, 23, "harmonics_ram_256");
}

/// The start table sits in both banks at power-up: the first samples of either bank read
/// it as the static block does.
#[test]
fn the_start_table_is_in_both_banks() {
    let p = HarmonicParams::new(ZW, GZ, F, &random_table(64, 300.0, 31)).expect("params");
    let m = HarmonicRamModel::new(&p, E);
    for i in 0..64 {
        let c = p.table[i] as u64 & mask(ZW);
        assert_eq!((m.entry(0, i), m.entry(1, i)), (c, c));
    }
}
