//! SPI slave: an SPI master (modes 0 and 3, continuous time, line delay both ways) reads
//! the rust-hdl slave; every word carries the position latched at chip select and the
//! flags; glitches, early deselect and reset; the same stimulus in Icarus and Verilator.
use crate::common;
use sinedec::blocks::mask;
use sinedec::blocks::serial::data_word;
use sinedec::blocks::spi_slave::hdl::SpiSlave;
use sinedec::blocks::spi_slave::SpiSlaveParams;
use sinedec::cosim::step::{prepare, tick};
use sinedec::cosim::stimulus::SplitMix64;
use sinedec::cosim::CosimBlock;
use sinedec::sim::serial_line::LineTiming;
use sinedec::sim::spi_master::{SpiMaster, SpiTxn as Txn};

struct Run {
    rows: Vec<Vec<u64>>,
    out: Vec<Vec<u64>>,
    words: Vec<Vec<bool>>,
    timing: LineTiming,
}

#[derive(Clone, Copy, Default)]
struct Ctl {
    rst: bool,
    sck_flip: bool,
}

fn pos(k: usize) -> u64 {
    SplitMix64(k as u64 * 2 + 1).next_u64() & mask(32)
}
fn turns(k: usize) -> u64 {
    SplitMix64(k as u64 * 2 + 0x5555).next_u64() & mask(32)
}

fn run(
    p: &SpiSlaveParams,
    t: LineTiming,
    txns: &[Txn],
    errors: &[usize],
    warnings: &[usize],
    mut ctl: impl FnMut(usize) -> Ctl,
) -> Run {
    let mut m = SpiMaster::new(t, txns, 300.0);
    let cycles = ((m.end_ns() + 1000.0) / t.tclk_ns()) as usize;
    let mut uut = SpiSlave::new(p).expect("params");
    rust_hdl::prelude::Block::connect_all(&mut uut);
    prepare(&mut uut).expect("settles");
    let (mut rows, mut out) = (Vec::new(), Vec::new());
    for k in 0..cycles {
        let c = ctl(k);
        let (sck, cs_n) = m.lines_for_cycle(k);
        let row = vec![
            (k < 3 || c.rst) as u64,
            (sck ^ c.sck_flip) as u64,
            cs_n as u64,
            pos(k),
            turns(k),
            (k % 3 == 0) as u64,
            errors.contains(&k) as u64,
            warnings.contains(&k) as u64,
        ];
        uut.apply(&row);
        tick(&mut uut).expect("settles");
        let o = uut.sample();
        m.push_miso(o[0] != 0);
        out.push(o);
        rows.push(row);
    }
    let words = m.words();
    Run {
        rows,
        out,
        words,
        timing: t,
    }
}

impl Run {
    fn cs_row(&self, p: &SpiSlaveParams, from_ns: f64) -> usize {
        let need = if p.glitch_filter { 2 } else { 1 };
        let mut k = ((from_ns + self.timing.line_delay_ns) / self.timing.tclk_ns()) as usize;
        k = k.saturating_sub(3);
        while !(0..need).all(|i| self.rows[k + i][2] == 0) {
            k += 1;
        }
        k + p.latch_latency() as usize
    }
    /// The bits the slave must send for a word latched at row l (previous take at prev).
    fn expect(&self, p: &SpiSlaveParams, l: usize, prev: usize) -> Vec<bool> {
        let last_rst = (0..=l).rev().find(|&j| self.rows[j][0] != 0).unwrap_or(0);
        let from = prev.max(last_rst) + 1;
        let err = (from..=l).any(|j| self.rows[j][6] != 0);
        let warn = (from..=l).any(|j| self.rows[j][7] != 0);
        let v = (0..=l)
            .rev()
            .find(|&j| self.rows[j][5] != 0 && j > last_rst);
        let (w, err) = match v {
            Some(v) => (
                data_word(
                    self.rows[v][3],
                    self.rows[v][4],
                    p.position_bits,
                    p.multiturn_bits,
                    p.gray,
                ),
                err,
            ),
            None => (0, true),
        };
        let n = p.data_bits();
        let mut bits: Vec<bool> = (0..n).rev().map(|i| w >> i & 1 == 1).collect();
        bits.push(err);
        bits.push(warn);
        bits
    }
}

/// Checks transaction i (the first `check` bits, then zeros), returns its latch row.
fn check_txn(r: &Run, p: &SpiSlaveParams, pl_cs: f64, i: usize, prev: usize) -> usize {
    let l = r.cs_row(p, pl_cs);
    let want = r.expect(p, l, prev);
    let got = &r.words[i];
    for (b, g) in got.iter().enumerate() {
        let w = want.get(b).copied().unwrap_or(false);
        assert_eq!(*g, w, "transaction {i} bit {b}: got {got:?} want {want:?}");
    }
    l
}

#[test]
fn params_are_validated() {
    assert!(SpiSlaveParams::new(19, 0, 50e6).is_ok());
    assert!(SpiSlaveParams::new(0, 0, 50e6).is_err());
    assert!(SpiSlaveParams::new(30, 3, 50e6)
        .unwrap_err()
        .to_string()
        .contains("exceeds"));
    assert!(SpiSlaveParams::new(19, 0, 1e3)
        .unwrap_err()
        .to_string()
        .contains("clock_hz"));
    let p = SpiSlaveParams::new(19, 0, 50e6).unwrap();
    assert_eq!(p.word_bits(), 21);
    // 4 clocks of response + 20 ns round trip: 100 ns half period.
    assert!((p.max_sck_hz(10.0) - 5e6).abs() < 1.0);
}

fn txns(clock: f64) -> Vec<Txn> {
    let mut v = Vec::new();
    let rates: &[f64] = if clock > 100e6 {
        &[100e3, 1e6, 4e6, 8e6]
    } else {
        &[100e3, 1e6, 2.5e6, 4.5e6]
    };
    for &hz in rates {
        for mode in [0, 3] {
            v.push(Txn {
                mode,
                sck_hz: hz,
                clocks: 0,
                gap_ns: 500.0,
            });
        }
    }
    v
}

/// Modes 0 and 3 at 100 kHz up to near the limit, 50 and 133.33 MHz, binary and Gray:
/// every word is the latched position with its flags, then zeros.
#[test]
fn words_in_mode_0_and_3() {
    for clock in [50e6, 133.33e6] {
        let mut a = SpiSlaveParams::new(13, 12, clock).unwrap();
        a.gray = true;
        let b = SpiSlaveParams::new(32, 0, clock).unwrap();
        for p in [a, b] {
            let t = LineTiming {
                clock_hz: clock,
                line_delay_ns: 10.0,
            };
            let mut tx = txns(clock);
            for x in tx.iter_mut() {
                x.clocks = p.word_bits() + 2;
            }
            let pl = SpiMaster::new(t, &tx, 300.0);
            let r = run(&p, t, &tx, &[20_000, 20_100], &[40_000], |_| Ctl::default());
            let mut prev = 0;
            for (i, tcs) in pl.txns().iter().map(|x| &x.t_cs_ns).enumerate() {
                prev = check_txn(&r, &p, *tcs, i, prev);
            }
            // MISO is driven exactly while selected, as the slave sees chip select (L rows
            // late), and is 0 whenever it is not driven.
            let lat = p.latch_latency() as usize;
            for k in 10..r.rows.len() {
                let sel = r.rows[k - lat][2] == 0;
                assert_eq!(r.out[k][1] == 1, sel, "miso_oe at row {k}");
                if !sel {
                    assert_eq!(r.out[k][0], 0, "miso at row {k}");
                }
            }
        }
    }
}

/// The supported line round trip (cable and transceivers, both ways) at each SCK rate, the
/// figure `check` prints (`sinedec::blocks::serial::max_round_trip_ns` with the SCK low time
/// as the window, docs/interfaces.md), with the `[board]` default pad budgets added to the
/// model's line: every word is read right at the limit in modes 0 and 3; one clock period
/// beyond it every bit after the first is read one SCK period late, a wrong word that SPI,
/// without a check sum, cannot flag (why the limit must be kept).
#[test]
fn supported_round_trip_at_each_sck_rate() {
    use sinedec::blocks::serial::{answer_window, max_round_trip_ns};
    let io = sinedec::board::IoTiming::DEFAULT;
    let pads = io.input_setup_ns + io.clock_to_out_ns;
    let clock = 50e6;
    let p = SpiSlaveParams::new(19, 0, clock).unwrap();
    let a = answer_window(clock, p.glitch_filter, &io);
    for hz in [1e6, 4e6] {
        let limit = max_round_trip_ns(0.5e9 / hz, &a);
        for (rt, right) in [(limit - 0.05, true), (limit + 1e9 / clock + 0.05, false)] {
            let t = LineTiming {
                clock_hz: clock,
                line_delay_ns: (rt + pads) / 2.0,
            };
            let tx: Vec<Txn> = [0, 3, 0, 3]
                .iter()
                .map(|&mode| Txn {
                    mode,
                    sck_hz: hz,
                    clocks: p.word_bits(),
                    gap_ns: 500.0 + rt,
                })
                .collect();
            let pl = SpiMaster::new(t, &tx, 300.0);
            let r = run(&p, t, &tx, &[], &[], |_| Ctl::default());
            let mut prev = 0;
            for (i, x) in pl.txns().iter().enumerate() {
                let l = r.cs_row(&p, x.t_cs_ns);
                let want = r.expect(&p, l, prev);
                prev = l;
                assert_eq!(
                    r.words[i] == want,
                    right,
                    "{hz} Hz, round trip {rt:.2} ns (limit {limit:.2}): word {i} {:?} vs {want:?}",
                    r.words[i]
                );
            }
        }
    }
}

/// Corner cases and the three simulators: back-to-back words, early deselect, extra clocks,
/// SCK glitches of one sample, reset mid-word.
fn scenario(p: &SpiSlaveParams, tag: &str) {
    let t = LineTiming {
        clock_hz: p.clock_hz,
        line_delay_ns: 10.0,
    };
    let w = p.word_bits();
    let tx = vec![
        Txn {
            mode: 0,
            sck_hz: 1e6,
            clocks: w,
            gap_ns: 200.0,
        },
        Txn {
            mode: 0,
            sck_hz: 1e6,
            clocks: w + 3,
            gap_ns: 0.0,
        },
        Txn {
            mode: 3,
            sck_hz: 2e6,
            clocks: 5,
            gap_ns: 0.0,
        }, // deselected early
        Txn {
            mode: 3,
            sck_hz: 2e6,
            clocks: w,
            gap_ns: 0.0,
        },
        Txn {
            mode: 0,
            sck_hz: 3e6,
            clocks: w,
            gap_ns: 300.0,
        }, // glitches
        Txn {
            mode: 3,
            sck_hz: 3e6,
            clocks: w,
            gap_ns: 300.0,
        }, // reset mid-word
        Txn {
            mode: 3,
            sck_hz: 3e6,
            clocks: w,
            gap_ns: 300.0,
        },
        Txn {
            mode: 0,
            sck_hz: 100e3,
            clocks: w,
            gap_ns: 300.0,
        },
    ];
    let pl = SpiMaster::new(t, &tx, 300.0);
    let tc = t.tclk_ns();
    let row_of = |ns: f64| (ns / tc) as usize;
    // Glitches in word 4: at a third and at two thirds of a period after its 3rd and 8th clock.
    let per4 = 1e9 / 3e6;
    let g1 = row_of(pl.txns()[4].t_cs_ns + per4 * 3.33);
    let g2 = row_of(pl.txns()[4].t_cs_ns + per4 * 8.66);
    let g0 = row_of(pl.txns()[4].t_cs_ns - 150.0); // in idle, before chip select
    let rst_at = row_of(pl.txns()[5].t_cs_ns + per4 * 6.5);
    let r = run(p, t, &tx, &[3000, 9000], &[15_000], |k| Ctl {
        rst: (rst_at..rst_at + 2).contains(&k),
        sck_flip: k == g0 || k == g1 || k == g2,
    });
    let mut prev = 0;
    for (i, tcs) in pl.txns().iter().map(|x| &x.t_cs_ns).enumerate() {
        match i {
            5 => prev = r.cs_row(p, *tcs), // reset mid-word: anything goes after it
            4 if !p.glitch_filter => prev = r.cs_row(p, *tcs),
            _ => prev = check_txn(&r, p, *tcs, i, prev),
        }
    }
    common::replay_in_all_simulators(SpiSlave::new(p).unwrap(), "spi_slave", &r.rows, &r.out, tag);
}

#[test]
fn cosim_50mhz() {
    let p = SpiSlaveParams::new(19, 0, 50e6).unwrap();
    scenario(&p, "spi_50");
}

#[test]
fn cosim_133mhz_gray_multiturn() {
    let mut p = SpiSlaveParams::new(16, 12, 133.33e6).unwrap();
    p.gray = true;
    scenario(&p, "spi_133");
}

#[test]
fn cosim_50mhz_without_glitch_filter() {
    let mut p = SpiSlaveParams::new(24, 4, 50e6).unwrap();
    p.glitch_filter = false;
    scenario(&p, "spi_50_nofilter");
}

#[test]
fn synthesizes_for_both_families() {
    use sinedec::synth::{synthesize, Family};
    let p = SpiSlaveParams::new(19, 0, 50e6).unwrap();
    let mut uut = SpiSlave::new(&p).unwrap();
    rust_hdl::prelude::Block::connect_all(&mut uut);
    let v = sinedec::emit::verilog::export(&uut, "spi", "spi_slave").expect("export");
    let dir = common::workdir("spi_synth");
    let n = p.data_bits() as u64;
    // two syncs 8 with their registered edge pulses 4, hold N + 3, state 3, miso, oe,
    // armed, shift N, counter 7, flags 2.
    let want = 8 + 4 + n + 3 + 3 + 3 + n + 7 + 2;
    for fam in [Family::Xc3sa, Family::CycloneIve] {
        let s = synthesize(&v, "spi_slave", fam, &dir).expect("synthesis");
        eprintln!(
            "spi {}: {} LUT, {} FF (bound {want})",
            fam.name(),
            s.luts,
            s.ffs
        );
        assert!(s.ffs <= want && s.ffs + 8 >= want, "{} FF vs {want}", s.ffs);
    }
}
