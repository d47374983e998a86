//! The harmonic-correction block with its table in RAM (the learned table, issue 46):
//! rust-hdl == model cycle for cycle == Icarus == Verilator == engine under writes to both
//! banks and bank flips; its arithmetic against the static block's model
//! (`harmonics::model::correct`) on the same table; the write port's conversion from the
//! learner's q units against a rounding in f64.
use crate::common;
use sinedec::blocks::harmonics::hdl_ram::{HarmonicCorrectionRam, RAM_ADDR_BITS};
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

/// The Clear's writes of `p`'s table (z units, as q units 2^(T-Gz) times larger, which the
/// write port takes back exactly): bank 0's entries, then bank 1's, one per clock.
fn clear_writes(p: &HarmonicParams) -> Vec<(u64, u64)> {
    let pts = u64::from(p.points());
    (0..2 * pts)
        .map(|a| {
            let c = p.table[(a % pts) as usize] << (TABLE_FRAC - GZ);
            (a, c as u64 & mask(E))
        })
        .collect()
}

fn run_four_ways(n: usize, seed: u64, tag: &str) {
    let p = HarmonicParams::new(ZW, GZ, F, &random_table(n, 200.0, seed)).expect("params");
    let pts = n as u64;
    let lim = 1u64 << (F - 4 + TABLE_FRAC);
    let mut r = SplitMix64(seed);
    let clear = clear_writes(&p);
    let cycles = 4000 + clear.len();
    let mut bank = false;
    let ins: Vec<HarmonicRamIn> = (0..cycles)
        .map(|c| {
            // The Clear first (samples pass uncorrected); then flip the bank now and then
            // and write bursts of entries of either bank, among them the one being read.
            let clearing = c < clear.len();
            if c % 500 == 250 && !clearing {
                bank = !bank;
            }
            let z = match c % 7 {
                0 => (r.next_u64() % pts) << (ZW - p.points_log2),
                1 => mask(ZW) - (r.next_u64() & 3),
                _ => r.next_u64() & mask(ZW),
            };
            let (tw, tw_addr, tw_data) = if let Some(&(a, d)) = clear.get(c) {
                (true, a, d)
            } else if clearing {
                (false, 0, 0)
            } else {
                let a = if c % 5 == 0 {
                    (u64::from(bank) * pts) + (z >> (ZW - p.points_log2))
                } else {
                    r.next_u64() % (2 * pts)
                };
                (
                    c % 9 < 4,
                    a,
                    (r.next_u64() % (2 * lim + 1)).wrapping_sub(lim) & mask(E),
                )
            };
            HarmonicRamIn {
                core: HarmonicIn {
                    rst: c < 2 || (c > cycles / 2 && c < cycles / 2 + 3),
                    z,
                    x: r.next_u64() & mask(32),
                    v: r.next_u64() & 3 != 0,
                },
                bank,
                clearing,
                tw,
                tw_addr,
                tw_data,
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
    run_four_ways(128, 23, "harmonics_ram_128");
}

/// After the Clear has written a table into both banks, the block gives the static
/// block's corrected angle (`correct`) for that table, reading either bank; during the
/// Clear it gives the angle uncorrected (rounded to the z unit: the half is in y).
#[test]
fn after_the_clear_either_bank_gives_the_static_blocks_angle() {
    let p = HarmonicParams::new(ZW, GZ, F, &random_table(64, 300.0, 31)).expect("params");
    let zero = HarmonicParams::new(ZW, GZ, F, &[0.0; 64]).expect("zeros");
    let mut m = HarmonicRamModel::new(&p, E);
    let mut r = SplitMix64(31);
    let lat = sinedec::blocks::harmonics::HarmonicParams::LATENCY_RAM as usize;
    let clear = clear_writes(&p);
    let mut zs = Vec::new();
    let mut outs = Vec::new();
    for c in 0..clear.len() + 2000 {
        let z = r.next_u64() & mask(ZW);
        let (tw, tw_addr, tw_data) = clear.get(c).map_or((false, 0, 0), |&(a, d)| (true, a, d));
        let clearing = c < clear.len();
        outs.push(m.step(HarmonicRamIn {
            core: HarmonicIn {
                rst: false,
                z,
                x: 0,
                v: true,
            },
            bank: c % 3 == 0,
            clearing,
            tw,
            tw_addr,
            tw_data,
        }));
        zs.push((z, clearing));
    }
    for (k, &(z, clearing)) in zs.iter().enumerate().take(zs.len() - lat) {
        // The clock after the Clear still reads zeros.
        let zeros = clearing || (k > 0 && zs[k - 1].1);
        let want = correct(if zeros { &zero } else { &p }, z);
        assert_eq!(outs[k + lat - 1].z, want, "clock {k}, clearing {clearing}");
    }
    for i in 0..64 {
        let c = p.table[i] as u64 & mask(ZW);
        assert_eq!((m.entry(0, i), m.entry(1, i)), (Some(c), Some(c)));
    }
}

/// The block alone in Yosys with a 128-point table: no hard multiplier, at most one carry
/// chain on every register-to-register path of the xc3sa mapping, the RAMs in the columns
/// they are read in; the figures are printed.
#[test]
fn the_ram_block_synthesizes_with_one_carry_chain_per_path_and_no_multiplier() {
    let p = HarmonicParams::new(ZW, GZ, F, &random_table(128, 300.0, 41)).expect("params");
    let (x, c) =
        crate::correction_util::synth(HarmonicCorrectionRam::new(&p, E), "harmonics_ram_synth");
    let path = x.path.expect("a register-to-register path");
    eprintln!(
        "harmonics_ram_synth: xc3sa {} LUT, {} FF, {} MULT18X18, {} BRAM; cycloneive {} LE, {} FF, {} multipliers, {} BRAM; worst path {} -> {}: {} carry chains, {} LUT levels",
        x.luts, x.ffs, x.multipliers, x.brams, c.luts, c.ffs, c.multipliers, c.brams, path.from, path.to, path.carry_chains, path.lut_levels
    );
    assert_eq!(x.multipliers + c.multipliers, 0);
    assert!(path.carry_chains <= 1, "{path:?}");
    // The two RAMs (`PipedLutRam`, four 64-word arrays each) are LUT RAM on xc3sa, read in
    // ZW bits: 2 RAMs x 256 / 16 words per RAM16X1D x ZW = 22 columns = 704 cells (the
    // other RAM_WORD_BITS - ZW = 14 columns dropped). Cyclone ignores the attribute and
    // maps each array to an M9K (Yosys 0.23's `altsyncram`, counted in `brams`): 2 x 4 = 8
    // (the one-clock `LutRam` was one M9K per RAM).
    let lutram = x.cells.get("RAM16X1D").copied().unwrap_or(0);
    assert_eq!(x.brams, 0);
    assert_eq!(lutram, 2 * ((1 << RAM_ADDR_BITS) / 16) * u64::from(ZW));
    assert_eq!(c.brams, 2 * 4);
}
