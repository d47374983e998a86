//! The register map's learned harmonic table (HARM_CONTROL, HARM_INDEX, HARM_ENTRY; issue
//! 46): the map alone, its learner port driven by a stand-in written here from the
//! learner's interface (docs/registers.md, "The harmonic table"): it keeps two banks of P
//! entries, publishes each write (`tw`), writes both banks and flips its bank while it
//! learns, takes a load request when not busy (drops one while busy) and applies it to both
//! banks. HARM_ENTRY reads the stand-in's entry of the bank in use; a whole-word AXI write
//! and the BiSS byte 3 each give exactly one load with the index and the value; LEARN
//! drives `update`; LOAD_BUSY reads the stand-in's busy. rust-hdl == model, and rust-hdl ==
//! Icarus == Verilator == engine on the same clocks.
use super::regmap::{four_ways, params, values, Master, Op};
use sinedec::blocks::mask;
use sinedec::blocks::regmap::model::{RegIn, RegOut, RegisterModel};
use sinedec::blocks::regmap::{RegmapParams, REGISTERS};
use sinedec::cosim::stimulus::SplitMix64;
use std::collections::VecDeque;

const CONTROL: u64 = 0x5c;
const INDEX: u64 = 0x60;
const ENTRY: u64 = 0x64;

/// Clocks a load keeps the stand-in busy before it writes the two banks.
const BUSY: usize = 40;

/// The learner as its interface describes it (not the RTL): two banks of P entries of E
/// bits, zero after reset, and no write in the 2P + 2 clocks after it (the map clears its
/// mirror then; docs/registers.md); while `update` it writes an entry every third clock
/// (alternating the banks) and flips its bank every `window` clocks; a load request waits
/// [`BUSY`] clocks, then lands in bank 0 and bank 1 on two clocks (each write published),
/// a request while busy is dropped.
struct Learner {
    p: usize,
    e: u32,
    window: usize,
    table: [Vec<i64>; 2],
    bank: usize,
    rng: SplitMix64,
    /// A load taken: (entry, value, clock it lands in bank 0).
    pending: Option<(usize, i64, usize)>,
    dropped: usize,
    /// The map's outputs of the clock before (what the learner sees).
    seen: RegOut,
}

impl Learner {
    fn new(p: usize, e: u32, window: usize, seed: u64) -> Self {
        Self {
            p,
            e,
            window,
            table: [vec![0; p], vec![0; p]],
            bank: 0,
            rng: SplitMix64(seed),
            pending: None,
            dropped: 0,
            seen: RegOut::default(),
        }
    }

    fn busy(&self) -> bool {
        self.pending.is_some()
    }

    /// The learner's outputs in clock `k` (its state changes with them), on top of `base`.
    fn drive(&mut self, k: usize, base: RegIn) -> RegIn {
        let mut i = base;
        i.h_bank = self.bank == 1;
        i.h_ld_busy = self.busy();
        let mut write = None;
        if let Some((n, v, at)) = self.pending {
            if k == at || k == at + 1 {
                write = Some((k - at, n, v));
            }
            if k == at + 1 {
                self.pending = None;
            }
        } else if self.seen.h_update && k >= 2 * self.p + 4 {
            if k.is_multiple_of(3) {
                let half = 1i64 << (self.e - 1);
                let v = self.rng.range(-half, half);
                write = Some(((k / 3) % 2, (k / 6) % self.p, v));
            }
            if k.is_multiple_of(self.window) {
                self.bank ^= 1;
            }
        }
        if let Some((b, n, v)) = write {
            self.table[b][n] = v;
            i.h_tw = true;
            i.h_tw_addr = (b * self.p + n) as u64;
            i.h_tw_data = v as u64 & mask(self.e);
        }
        i
    }

    /// After the edge of clock `k`: the map's outputs; a load request is taken or dropped.
    fn observe(&mut self, k: usize, o: &RegOut) {
        if o.h_ld {
            if self.busy() {
                self.dropped += 1;
            } else {
                let v = sinedec::blocks::sext(o.h_ld_data, self.e);
                self.pending = Some((o.h_ld_addr as usize, v, k + 1 + BUSY));
            }
        }
        self.seen = *o;
    }
}

/// What a read answered, with the learner's state at its handshake.
struct Answer {
    data: u64,
    bank: usize,
    busy: bool,
    frozen: bool,
    table: [Vec<i64>; 2],
}

/// Runs `ops` one after the other (each once the one before has its response) on the model
/// with the learner, the decoder's values and `extra(k)` (the BiSS port's inputs) for the
/// clocks; returns the inputs, the outputs, the answers and the learner.
fn run(
    p: &RegmapParams,
    ops: &[Op],
    stall: f64,
    seed: u64,
    window: usize,
    min_clocks: usize,
    extra: impl Fn(usize, RegIn) -> RegIn,
) -> (Vec<RegIn>, Vec<RegOut>, Vec<Answer>, Learner) {
    let (points, e) = p.harmonics().expect("a learned table");
    let mut m = RegisterModel::new(p);
    let mut master = Master::new(seed, stall);
    let mut l = Learner::new(points as usize, e, window, seed + 1);
    let (mut ins, mut outs, mut answers) = (vec![], vec![], vec![]);
    let mut todo: VecDeque<Op> = ops.iter().copied().collect();
    let mut k = 0;
    loop {
        if k >= 2 && master.idle() {
            if let Some(op) = todo.pop_front() {
                master.push(op);
            }
        }
        if k >= 2 && master.idle() && todo.is_empty() && k >= min_clocks {
            break;
        }
        assert!(k < 200_000, "the slave stopped answering");
        let base = extra(k, values(0));
        let mut i = l.drive(k, base);
        if k < 2 {
            i.rst = true;
        } else {
            i = master.drive(i);
        }
        let o = m.step(i);
        let n = master.rs.len();
        master.observe(&i, &o, k);
        if master.rs.len() > n {
            answers.push(Answer {
                data: master.rs[n],
                bank: l.bank,
                busy: l.busy(),
                frozen: !l.seen.h_update,
                table: l.table.clone(),
            });
        }
        l.observe(k, &o);
        ins.push(i);
        outs.push(o);
        k += 1;
    }
    (ins, outs, answers, l)
}

/// F = 14's learned table: 64 entries of E = 20 bits.
fn harm_params() -> RegmapParams {
    params().with_harmonics(64, 20).expect("harmonics")
}

/// The runs of equal values of `v`, in order.
fn runs(v: impl Iterator<Item = bool>) -> Vec<bool> {
    let mut r: Vec<bool> = vec![];
    for x in v {
        if r.last() != Some(&x) {
            r.push(x);
        }
    }
    r
}

#[test]
fn the_entries_read_loaded_and_learn_switched_over_axi_four_ways() {
    let p = harm_params();
    let e = 20;
    let pad = |n: usize| (0..n).map(|_| Op::Read(0x00)).collect::<Vec<_>>();
    // Learning long enough to write every entry of both banks (one every third clock, from
    // clock 2P + 4).
    let mut ops = vec![Op::Read(CONTROL), Op::Read(ENTRY)];
    ops.extend(pad(200));
    // Frozen: each index written, read back, its entry read.
    ops.push(Op::Write(CONTROL, 0, 0b0001));
    for i in [0u64, 1, 17, 63, 64 + 5] {
        ops.extend([
            Op::Write(INDEX, i, 0b1111),
            Op::Read(INDEX),
            Op::Read(ENTRY),
        ]);
    }
    // Learning again long enough for a bank flip, then frozen and read.
    ops.push(Op::Write(CONTROL, 1, 0b0001));
    ops.extend(pad(60));
    ops.push(Op::Write(CONTROL, 0, 0b0001));
    ops.extend([
        Op::Read(ENTRY),
        Op::Write(INDEX, 40, 0b0001),
        Op::Read(ENTRY),
    ]);
    // A whole-word load at entry 9; LOAD_BUSY; a second write while busy (dropped by the
    // learner); the entry after the load has landed.
    ops.extend([
        Op::Write(INDEX, 9, 0b1111),
        Op::Write(ENTRY, -1234i64 as u64 & mask(32), 0b1111),
        Op::Read(CONTROL),
        Op::Write(ENTRY, 777, 0b1111),
    ]);
    ops.extend(pad(25));
    ops.extend([Op::Read(CONTROL), Op::Read(ENTRY)]);
    // Bytes 0..2 staged (no load), then byte 3 alone loads the staged word.
    ops.extend([
        Op::Write(ENTRY, 0x0003_5678, 0b0111),
        Op::Write(ENTRY, 0xff00_0000, 0b1000),
    ]);
    ops.extend(pad(25));
    ops.push(Op::Read(ENTRY));
    let (ins, outs, ans, l) = run(&p, &ops, 0.0, 21, 150, 0, |_, i| i);
    let sx = |v: i64| v as u64 & mask(32);
    // The reads of the map's table words, in order (the padding reads ID).
    let reads = ops.iter().filter_map(|o| match o {
        Op::Read(a) => Some(*a),
        Op::Write(..) => None,
    });
    let ans: Vec<&Answer> = ans
        .iter()
        .zip(reads)
        .filter(|(_, r)| *r != 0x00)
        .map(|(x, _)| x)
        .collect();
    assert_eq!(ans[0].data, 1, "HARM_CONTROL after reset: LEARN, not busy");
    let mut a = ans.iter().skip(2);
    for i in [0usize, 1, 17, 63, 5] {
        let idx = a.next().expect("index read");
        assert_eq!(idx.data, i as u64, "HARM_INDEX keeps the low p bits");
        let ent = a.next().expect("entry read");
        assert!(ent.frozen);
        assert_eq!(
            ent.data,
            sx(ent.table[ent.bank][i]),
            "entry {i}, bank {}",
            ent.bank
        );
        assert_ne!(ent.table[0][i], ent.table[1][i], "the banks differ at {i}");
    }
    let before = ans[3].bank;
    for i in [5usize, 40] {
        let ent = a.next().expect("entry read");
        assert!(ent.frozen);
        assert_eq!(
            ent.data,
            sx(ent.table[ent.bank][i]),
            "entry {i} after the flip"
        );
        assert_ne!(ent.bank, before, "learning flipped the bank");
    }
    let busy = a.next().expect("control read");
    assert!(busy.busy, "the learner is busy at the read");
    assert_eq!(busy.data, 0b10, "LOAD_BUSY, LEARN 0");
    let a: Vec<&&Answer> = a.collect();
    assert_eq!(a[0].data, 0, "not busy any more");
    assert_eq!(a[1].data, sx(-1234), "entry 9 after the load");
    assert_eq!(a[1].table[0][9], -1234);
    assert_eq!(a[1].table[1][9], -1234, "the load lands in both banks");
    assert_eq!(a[2].data, 0x35678, "the staged bytes with byte 3");
    // Exactly one load per write with byte 3, with the index and the low E bits.
    let loads: Vec<(u64, u64)> = outs
        .iter()
        .filter(|o| o.h_ld)
        .map(|o| (o.h_ld_addr, o.h_ld_data))
        .collect();
    assert_eq!(
        loads,
        vec![(9, -1234i64 as u64 & mask(e)), (9, 777), (9, 0x3_5678)]
    );
    assert_eq!(
        l.dropped, 1,
        "the write while busy was dropped by the learner"
    );
    // LEARN drives update: on after reset, off, on, off.
    assert_eq!(
        runs(outs.iter().skip(2).map(|o| o.h_update)),
        vec![true, false, true, false]
    );
    let rows: Vec<Vec<u64>> = ins.iter().map(|i| i.row_for(&p)).collect();
    let model: Vec<Vec<u64>> = outs.iter().map(|o| o.row_for(&p)).collect();
    four_ways(&p, "regmap_harmonics_axi", &rows, &model);
}

/// The BiSS byte port (16 entries of 12 bits): HARM_INDEX's byte 0, HARM_ENTRY's bytes 0..2
/// staged with no load, byte 3 one load of the whole word; the entry's four bytes read back
/// after the load has landed; then four ways.
#[test]
fn biss_bytes_load_on_byte_3_and_read_the_entry_four_ways() {
    let p = params()
        .with_biss_port()
        .with_harmonics(16, 12)
        .expect("harmonics");
    // (byte address, byte written or None: a read), 8 clocks each.
    let mut plan: Vec<(u64, Option<u64>)> = vec![
        (CONTROL, Some(0x00)),
        (INDEX, Some(0x13)),
        (ENTRY, Some(0x21)),
        (ENTRY + 1, Some(0x0f)),
        (ENTRY + 2, Some(0x00)),
        (ENTRY + 3, Some(0x00)),
    ];
    let load_step = plan.len() - 1;
    // Wait for the load to land (BUSY clocks), reading HARM_CONTROL and HARM_INDEX.
    for _ in 0..6 {
        plan.push((CONTROL, None));
    }
    plan.push((INDEX, None));
    let read_from = plan.len();
    for lane in 0..4 {
        plan.push((ENTRY + lane, None));
    }
    let hold = 8;
    let at = |j: usize| 2 + hold * j;
    let total = at(plan.len());
    let extra = |k: usize, mut i: RegIn| {
        if k >= 2 {
            let j = ((k - 2) / hold).min(plan.len() - 1);
            let (a, w) = plan[j];
            i.bus_addr = a;
            if k == at(j) + 1 {
                i.bus_we = w.is_some();
                i.bus_wdata = w.unwrap_or(0);
            }
        }
        i
    };
    let (ins, outs, _, l) = run(&p, &[], 0.0, 31, 1000, total, extra);
    let loads: Vec<(usize, u64, u64)> = (0..outs.len())
        .filter(|&k| outs[k].h_ld)
        .map(|k| (k, outs[k].h_ld_addr, outs[k].h_ld_data))
        .collect();
    assert_eq!(loads.len(), 1, "one load: {loads:?}");
    assert!(loads[0].0 > at(load_step), "after byte 3's write");
    assert_eq!(
        (loads[0].1, loads[0].2),
        (3, 0xf21),
        "entry 19 mod 16, the low 12 bits"
    );
    assert_eq!(l.table[0][3], 0xf21 - 0x1000);
    assert_eq!(l.table[1][3], 0xf21 - 0x1000);
    let got = |j: usize| outs[at(j) + hold - 1].bus_rdata;
    assert_eq!(got(read_from - 1), 3, "HARM_INDEX byte 0");
    assert_eq!(got(read_from - 2), 0, "LEARN off, not busy");
    let want = (0xf21u32 as i32 - 0x1000) as u32;
    for lane in 0..4 {
        assert_eq!(
            got(read_from + lane),
            (want >> (8 * lane) & 0xff) as u64,
            "HARM_ENTRY byte {lane}"
        );
    }
    assert!(!outs[total - 1].h_update, "LEARN written 0 by byte 0");
    let rows: Vec<Vec<u64>> = ins.iter().map(|i| i.row_for(&p)).collect();
    let model: Vec<Vec<u64>> = outs.iter().map(|o| o.row_for(&p)).collect();
    four_ways(&p, "regmap_harmonics_biss", &rows, &model);
}

/// Random AXI traffic over every register while the learner learns, flips and loads:
/// rust-hdl == model == Icarus == Verilator == engine (128 entries of 22 bits).
#[test]
fn random_traffic_with_a_learning_table_four_ways() {
    let p = params().with_harmonics(128, 22).expect("harmonics");
    let mut r = SplitMix64(41);
    // The mirror's 512 words are cleared first (ID read meanwhile).
    let mut ops: Vec<Op> = (0..180).map(|_| Op::Read(0x00)).collect();
    ops.extend((0..400).map(|_| {
        let a = (r.range(0, REGISTERS.len() as i64) * 4) as u64;
        let a = if r.unit() < 0.5 {
            ENTRY - 8 + 4 * (a % 3)
        } else {
            a
        };
        if r.unit() < 0.5 {
            Op::Read(a)
        } else {
            Op::Write(a, r.range(0, 1 << 31) as u64, r.range(0, 16) as u64)
        }
    }));
    let (ins, outs, _, _) = run(&p, &ops, 0.3, 43, 97, 0, |_, i| i);
    assert!(outs.iter().filter(|o| o.h_ld).count() > 5, "loads happened");
    let rows: Vec<Vec<u64>> = ins.iter().map(|i| i.row_for(&p)).collect();
    let model: Vec<Vec<u64>> = outs.iter().map(|o| o.row_for(&p)).collect();
    four_ways(&p, "regmap_harmonics_random", &rows, &model);
}

/// Without a learned table the three words read 0, writes to them do nothing, and the
/// map's Verilog has none of the table's logic (no RAM, no harmonic register).
#[test]
fn without_a_learned_table_the_words_read_zero_and_the_logic_is_absent() {
    let p = params();
    assert!(p.harmonics().is_none());
    let mut m = RegisterModel::new(&p);
    let mut master = Master::new(5, 0.0);
    for op in [
        Op::Write(CONTROL, 1, 0xf),
        Op::Write(INDEX, 7, 0xf),
        Op::Write(ENTRY, 99, 0xf),
        Op::Read(CONTROL),
        Op::Read(INDEX),
        Op::Read(ENTRY),
    ] {
        master.push(op);
    }
    for _ in 0..2 {
        m.step(RegIn {
            rst: true,
            ..values(0)
        });
    }
    let mut k = 0;
    while !master.idle() {
        let i = master.drive(values(0));
        let o = m.step(i);
        assert!(!o.h_ld && !o.h_update);
        master.observe(&i, &o, k);
        k += 1;
        assert!(k < 1000);
    }
    assert_eq!(master.rs, vec![0, 0, 0]);
    let v = |p: &RegmapParams| {
        let mut uut = sinedec::blocks::regmap::hdl::RegisterMap::new(p);
        rust_hdl::prelude::Block::connect_all(&mut uut);
        sinedec::emit::verilog::export(&uut, "m", "m").expect("export")
    };
    let plain = v(&p);
    assert!(!plain.contains("mem_0[") && !plain.contains("h_learn"));
    let with = v(&harm_params());
    assert!(with.contains("mem_0[") && with.contains("h_learn"));
}

#[test]
fn bad_table_parameters_are_rejected() {
    for (n, e) in [(8, 20), (48, 20), (512, 20), (64, 1), (64, 25)] {
        let err = params().with_harmonics(n, e).unwrap_err().to_string();
        assert!(err.contains("16") && err.contains("128"), "{err}");
    }
}

/// The most eager master: it raises the HARM_ENTRY read in the very clock the HARM_INDEX
/// write's response first shows (with `bready`). The read still returns the new index's
/// entry, since the RAM is read at the index's next value (docs/registers.md); then four
/// ways.
#[test]
fn an_entry_read_in_the_clock_of_the_index_writes_response_is_not_stale() {
    let p = harm_params();
    let e = 20;
    let entry = |n: u64| (n as i64 * 4099 - 200_000) as u64 & mask(e);
    let mut m = RegisterModel::new(&p);
    let (mut ins, mut outs) = (vec![], vec![]);
    let mut step = |i: RegIn, ins: &mut Vec<RegIn>, outs: &mut Vec<RegOut>| {
        let o = m.step(i);
        ins.push(i);
        outs.push(o);
        o
    };
    // Reset, the mirror's clear (2P clocks), then the learner writes the 64 entries of
    // bank 0.
    for k in 0..200u64 {
        let mut i = values(0);
        i.rst = k < 2;
        if k >= 136 {
            (i.h_tw, i.h_tw_addr, i.h_tw_data) = (true, k - 136, entry(k - 136));
        }
        step(i, &mut ins, &mut outs);
    }
    let mut got = vec![];
    for target in [33u64, 34, 0, 63] {
        // The write: address and data in one clock (both holders empty).
        let mut i = values(0);
        (i.awvalid, i.awaddr, i.wvalid, i.wdata, i.wstrb) = (true, INDEX, true, target, 0xf);
        let mut o = step(i, &mut ins, &mut outs);
        while !o.bvalid {
            o = step(values(0), &mut ins, &mut outs);
        }
        // The clock the response first shows: take it and ask for the entry at once.
        let mut i = values(0);
        (i.bready, i.arvalid, i.araddr) = (true, true, ENTRY);
        assert!(o.arready);
        o = step(i, &mut ins, &mut outs);
        while !o.rvalid {
            o = step(values(0), &mut ins, &mut outs);
        }
        got.push(o.rdata);
        let mut i = values(0);
        i.rready = true;
        step(i, &mut ins, &mut outs);
    }
    let want: Vec<u64> = [33u64, 34, 0, 63]
        .iter()
        .map(|&n| sinedec::blocks::sext(entry(n), e) as u64 & mask(32))
        .collect();
    assert_eq!(got, want);
    let rows: Vec<Vec<u64>> = ins.iter().map(|i| i.row_for(&p)).collect();
    let model: Vec<Vec<u64>> = outs.iter().map(|o| o.row_for(&p)).collect();
    four_ways(&p, "regmap_harmonics_eager", &rows, &model);
}

/// The map with a 64-entry table of 20-bit entries synthesizes on both families, its mirror
/// in distributed RAM (M9Ks on Cyclone); the figures against the map without it (docs/registers.md).
#[test]
fn synthesizes_for_both_families_with_the_mirror_in_ram() {
    use sinedec::synth::{synthesize, Family};
    let mut figures = vec![];
    for (p, name) in [
        (params(), "regmap_plain_synth"),
        (harm_params(), "regmap_harm_synth"),
    ] {
        let mut uut = sinedec::blocks::regmap::hdl::RegisterMap::new(&p);
        rust_hdl::prelude::Block::connect_all(&mut uut);
        let v = sinedec::emit::verilog::export(&uut, name, name).expect("export");
        let dir = crate::common::workdir(name);
        let x = synthesize(&v, name, Family::Xc3sa, &dir).expect("xc3sa synthesis");
        let c = synthesize(&v, name, Family::CycloneIve, &dir).expect("cycloneive synthesis");
        eprintln!(
            "{name}: xc3sa {} LUT, {} FF, {} BRAM; cycloneive {} LE, {} FF, {} BRAM",
            x.luts, x.ffs, x.brams, c.luts, c.ffs, c.brams
        );
        figures.push((x, c));
    }
    let (x0, c0) = &figures[0];
    let (x1, c1) = &figures[1];
    assert_eq!(
        (x0.brams, c0.brams),
        (0, 0),
        "no RAM without a learned table"
    );
    // The mirror is LUT RAM on xc3sa (`PipedLutRam`) and M9Ks on Cyclone (one per array).
    let lutram = x1.cells.get("RAM16X1D").copied().unwrap_or(0);
    assert!(
        x1.brams == 0 && lutram > 0 && c1.brams >= 1,
        "the mirror's RAM"
    );
    // LEARN, the index (6), the staged word (the 20 bits a load takes), the load on its
    // way (1 + 6 + 20), the clear's counter (32) and flag, three more bits in each one-hot
    // select: about 100 flip-flops more; the LUT RAM's read address, one per array (4 x
    // 8), and write stage (1 + 8 + the 20 entry bits): about 160; its four arrays' read
    // registers (4 x 20), the array select (2) and HARM_ENTRY's wait (1): about 245.
    let more = x1.ffs as i64 - x0.ffs as i64;
    assert!((160..=260).contains(&more), "{more} FF more");
}

/// The map with a learned table as the top builds it (a `Vec` element of `<name>_top`, its
/// RAM a `Vec` element inside it): the top's Verilog names the mirror's instance and
/// compiles in Icarus. (The learner is not in the top yet: the map's inputs from it are
/// tied to 0.)
#[test]
fn the_top_with_a_learned_table_map_exports_valid_verilog() {
    use sinedec::config::{Loaded, DEFAULT_CONFIG};
    let text = format!("{DEFAULT_CONFIG}\n[registers]\nenabled = true\n");
    let mut l = Loaded::parse(&text, "r.toml").expect("config");
    let p = l.derived.registers.expect("registers");
    l.derived.registers = Some(p.with_harmonics(64, 20).expect("harmonics"));
    let g = sinedec::emit::generate(&l, "test").expect("generate");
    let dir = crate::common::workdir("regmap_harmonics_top");
    let mut files = vec![];
    for f in &g.files {
        if f.name.ends_with(".v") && !f.name.ends_with("_tb.v") && !f.name.ends_with("_inst.v") {
            std::fs::write(dir.join(&f.name), &f.text).expect("write");
            files.push(f.name.clone());
        }
    }
    let top = g
        .files
        .iter()
        .find(|f| f.name == "sd_top.v")
        .expect("sd_top.v");
    assert!(top.text.contains("h_ram_0"), "the mirror's instance");
    assert!(top
        .text
        .contains("(* ram_style = \"distributed\" *) reg[23:0] mem_0[63:0];"));
    let o = std::process::Command::new("iverilog")
        .args(["-g2012", "-o", "top.vvp", "-s", "sd_top"])
        .args(&files)
        .current_dir(&dir)
        .output()
        .expect("iverilog runs (apt-get install iverilog)");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}
