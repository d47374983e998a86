//! The generic block co-simulation on a single CORDIC stage, driven with raw words
//! (including values with bits above the datapath width set, which the stage must mask):
//! rust-hdl == Icarus == Verilator, and each output equals the stage's arithmetic.
use crate::common;
use sinedec::blocks::cordic::hdl::CordicStage;
use sinedec::blocks::{mask, sext};
use sinedec::cosim::stimulus::SplitMix64;
use sinedec::verify::{block_traces, Simulators};

#[test]
#[allow(clippy::needless_range_loop)] // rows[k] and rows[k + 1] are read together
fn one_stage_in_three_simulators() {
    let l = common::cfg(14, 14, 14, 2048, 12);
    let d = &l.derived;
    let i = 3u32;
    let w = d.xy_width;
    let mut r = SplitMix64(7);
    let rows: Vec<Vec<u64>> = (0..400)
        .map(|k| {
            let x = r.next_u64() & mask(w - 1); // x >= 0
            let y = r.next_u64() & mask(w);
            let z = r.next_u64() & mask(d.z_width);
            vec![
                (k % 97 == 0) as u64,
                x,
                y,
                z,
                r.next_u64() & 3,
                r.next_u64() & 1,
            ]
        })
        .collect();
    let dir = common::workdir("cosim_stage");
    let t = block_traces(
        CordicStage::new(d, i),
        "st3",
        "clk",
        &rows,
        Simulators::ALL,
        &dir,
    )
    .expect("simulators ran");
    if let Some(m) = t.mismatch() {
        panic!("{m}");
    }
    // Independent arithmetic check of the registered outputs (one cycle later).
    for k in 0..rows.len() - 1 {
        let (x, y, z) = (sext(rows[k][1], w), sext(rows[k][2], w), rows[k][3]);
        let a = d.atan_table[i as usize];
        let (ex, ey, ez) = if y < 0 {
            (x - (y >> i), y + (x >> i), z.wrapping_sub(a))
        } else {
            (x + (y >> i), y - (x >> i), z + a)
        };
        let o = &t.rust_hdl[k];
        assert_eq!(o[0], ex as u64 & mask(w), "x at {k}");
        assert_eq!(o[1], ey as u64 & mask(w), "y at {k}");
        assert_eq!(o[2], ez & mask(d.z_width), "z at {k}");
        assert_eq!(o[3], rows[k][4]);
        assert_eq!(o[4], rows[k][5] & (1 - rows[k][0]));
    }
}
