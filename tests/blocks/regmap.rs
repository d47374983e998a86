//! Register map: an AXI4-Lite master with back-pressure drives the slave through every
//! register; a protocol checker watches every clock (valid held until its handshake, the
//! data stable meanwhile, OKAY responses, one response per request, in order); the values
//! read are the ones the register table defines (written here from the table, not from the
//! model); STATUS is write-1-to-clear with a present fault setting again, PRESET pulses,
//! POSITION latches TURNS and VELOCITY. rust-hdl == model, and rust-hdl == Icarus ==
//! Verilator == engine on the same traffic.
use crate::common;
use sinedec::blocks::mask;
use sinedec::blocks::regmap::hdl::RegisterMap;
use sinedec::blocks::regmap::model::{RegIn, RegOut, RegisterModel};
use sinedec::blocks::regmap::{
    Access, RegmapParams, FLAGS_WIDTH, ID, REGISTERS, STATUS_MASK, VERSION,
};
use sinedec::cosim::stimulus::SplitMix64;
use sinedec::verify::{block_traces, Simulators};
use std::collections::VecDeque;

/// The monitor thresholds the map resets to (LOS_THRESHOLD, LOS_RELEASE, CLIP_THRESHOLD).
pub(crate) const THRESHOLDS: [u32; 3] = [1500, 1800, 70_000];

/// F = 14, M = 12, a 32-bit velocity, with a position reference, [`THRESHOLDS`].
pub(crate) fn params() -> RegmapParams {
    RegmapParams::new(27, 14, 12, 32, false)
        .expect("params")
        .with_thresholds(THRESHOLDS)
}

/// One AXI4-Lite request.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Op {
    /// Write (byte address, data, strobes).
    Write(u64, u64, u64),
    /// Read (byte address).
    Read(u64),
}

/// The master and the checker: issues the requests with random gaps and random
/// back-pressure on B and R, records each response, and checks the protocol.
pub(crate) struct Master {
    rng: SplitMix64,
    aw: VecDeque<(u64, u64)>,
    w: VecDeque<(u64, u64)>,
    ar: VecDeque<u64>,
    /// Requests started (for the order of responses).
    writes: usize,
    reads: usize,
    /// Responses: B count, R data in order.
    pub(crate) bs: usize,
    pub(crate) rs: Vec<u64>,
    /// The last clock's outputs (what the master sees before the next edge).
    seen: RegOut,
    /// The last clock's inputs, for the stability rules.
    last: RegIn,
    /// Probability of holding back a valid or a ready this clock.
    stall: f64,
}

impl Master {
    pub(crate) fn new(seed: u64, stall: f64) -> Self {
        Self {
            rng: SplitMix64(seed),
            aw: VecDeque::new(),
            w: VecDeque::new(),
            ar: VecDeque::new(),
            writes: 0,
            reads: 0,
            bs: 0,
            rs: vec![],
            seen: RegOut {
                awready: true,
                wready: true,
                arready: true,
                ..Default::default()
            },
            last: RegIn::default(),
            stall,
        }
    }

    pub(crate) fn push(&mut self, op: Op) {
        match op {
            Op::Write(a, d, s) => {
                self.aw.push_back((a, 0));
                self.w.push_back((d, s));
                self.writes += 1;
            }
            Op::Read(a) => {
                self.ar.push_back(a);
                self.reads += 1;
            }
        }
    }

    pub(crate) fn idle(&self) -> bool {
        self.aw.is_empty()
            && self.w.is_empty()
            && self.ar.is_empty()
            && self.bs == self.writes
            && self.rs.len() == self.reads
    }

    /// The master's signals for the next clock on top of the decoder's values in `base`.
    pub(crate) fn drive(&mut self, base: RegIn) -> RegIn {
        let mut i = base;
        // A valid stays up until its handshake (AXI): once raised it is not withdrawn.
        let go = |m: &mut Self, was: bool| was || m.rng.unit() >= m.stall;
        if let Some(&(a, _)) = self.aw.front() {
            i.awvalid = go(self, self.last.awvalid);
            i.awaddr = a;
        }
        if let Some(&(d, s)) = self.w.front() {
            i.wvalid = go(self, self.last.wvalid);
            i.wdata = d;
            i.wstrb = s;
        }
        if let Some(&a) = self.ar.front() {
            i.arvalid = go(self, self.last.arvalid);
            i.araddr = a;
        }
        i.bready = self.rng.unit() >= self.stall;
        i.rready = self.rng.unit() >= self.stall;
        i
    }

    /// After the edge: the handshakes of `i` (with the outputs seen before it), the new
    /// outputs `o`, and the protocol rules.
    pub(crate) fn observe(&mut self, i: &RegIn, o: &RegOut, clock: usize) {
        let s = self.seen;
        if i.awvalid && s.awready {
            self.aw.pop_front();
        }
        if i.wvalid && s.wready {
            self.w.pop_front();
        }
        if i.arvalid && s.arready {
            self.ar.pop_front();
        }
        if s.bvalid && i.bready {
            self.bs += 1;
            assert!(self.bs <= self.writes, "clock {clock}: a B with no write");
        }
        if s.rvalid && i.rready {
            self.rs.push(s.rdata);
            assert!(
                self.rs.len() <= self.reads,
                "clock {clock}: an R with no read"
            );
        }
        // A response stays valid, and its data stable, until its handshake.
        if s.bvalid && !i.bready {
            assert!(o.bvalid, "clock {clock}: bvalid dropped before bready");
        }
        if s.rvalid && !i.rready {
            assert!(
                o.rvalid && o.rdata == s.rdata,
                "clock {clock}: rvalid or rdata changed before rready"
            );
        }
        self.seen = *o;
        self.last = *i;
    }
}

/// Runs `ops` on the model over the decoder values `values(clock)` until every response is
/// in: all issued at once (`concurrent`: writes and reads then overlap), or each once the
/// one before has its response. Returns the inputs, the outputs and the read data in
/// order.
fn drive(
    p: &RegmapParams,
    ops: &[Op],
    stall: f64,
    seed: u64,
    concurrent: bool,
    values: impl Fn(usize) -> RegIn,
) -> (Vec<RegIn>, Vec<RegOut>, Vec<u64>) {
    let mut m = RegisterModel::new(p);
    let mut master = Master::new(seed, stall);
    let (mut ins, mut outs) = (vec![], vec![]);
    // Reset for two clocks.
    for k in 0..2 {
        let i = RegIn {
            rst: true,
            ..values(k)
        };
        let o = m.step(i);
        master.observe(&i, &o, k);
        ins.push(i);
        outs.push(o);
    }
    let mut todo: VecDeque<Op> = ops.iter().copied().collect();
    let mut k = 2;
    loop {
        if concurrent {
            while let Some(op) = todo.pop_front() {
                master.push(op);
            }
        } else if master.idle() {
            if let Some(op) = todo.pop_front() {
                master.push(op);
            }
        }
        if master.idle() && todo.is_empty() {
            break;
        }
        assert!(k < 100_000, "the slave stopped answering");
        let i = master.drive(values(k));
        let o = m.step(i);
        master.observe(&i, &o, k);
        ins.push(i);
        outs.push(o);
        k += 1;
    }
    (ins, outs, master.rs)
}

/// The decoder's values: position (qc 1234, fine 567, turns -3), velocity -1000, index
/// (qc 77, turns 5), capture (qc 8000, fine 16000, turns -1, velocity 2_000_000, age 250),
/// amplitude 9999, live flags `flags`.
pub(crate) fn values(flags: u64) -> RegIn {
    RegIn {
        flags,
        amplitude: 9999,
        qc: 1234,
        fine: 567,
        turns: (-3i64 as u64) & mask(12),
        velocity: (-1000i64 as u64) & mask(32),
        index_qc: 77,
        index_turns: 5,
        cap_qc: 8000,
        cap_fine: 16000,
        cap_turns: mask(12),
        cap_velocity: 2_000_000,
        cap_age: 250,
        cor: COR.map(u64::from),
        ..Default::default()
    }
}

/// The correction's codes the map reads: offsets -5 and 12, gains 0x4000 and 0x4100, k = -77.
const COR: [u32; 5] = [-5i32 as u32, 12, 0x4000, 0x4100, 77 | 1 << 16];

/// What register `name` reads with the decoder's [`values`] and live flags `live`, written
/// from the table (TURNS and VELOCITY as latched by a POSITION read of those values).
fn want(name: &str, live: u64) -> u32 {
    let f = 14;
    match name {
        "ID" => ID,
        "VERSION" => VERSION,
        "STATUS" => 0,
        "FLAGS" => live as u32,
        "AMPLITUDE" => 9999,
        "POSITION" => (1234 << f) | 567,
        "TURNS" => -3i32 as u32,
        "VELOCITY" => -1000i32 as u32,
        "INDEX_POSITION" => 77 << f,
        "INDEX_TURNS" => 5,
        "PRESET" => 0,
        "CAPTURE_POSITION" => (8000 << f) | 16000,
        "CAPTURE_TURNS" => -1i32 as u32,
        "CAPTURE_VELOCITY" => 2_000_000,
        "CAPTURE_AGE" => 250,
        "LOS_THRESHOLD" => THRESHOLDS[0],
        "LOS_RELEASE" => THRESHOLDS[1],
        "CLIP_THRESHOLD" => THRESHOLDS[2],
        "OFFSET_SIN" => -5i32 as u32,
        "OFFSET_COS" => 12,
        "GAIN_SIN" => 0x4000,
        "GAIN_COS" => 0x4100,
        "PHASE" => 77 | 1 << 16,
        // No learned table in this map: its words read 0.
        "HARM_CONTROL" | "HARM_INDEX" | "HARM_ENTRY" => 0,
        other => panic!("no expectation for {other}"),
    }
}

#[test]
fn every_register_reads_what_the_table_defines() {
    let p = params();
    // Read every register (and one address with none) with heavy back-pressure.
    let mut ops: Vec<Op> = REGISTERS
        .iter()
        .map(|r| Op::Read(r.address as u64))
        .collect();
    ops.push(Op::Read(0xfc));
    let live = 0b1_0100_0000; // WARNING, REFERENCED
    let (_, _, rs) = drive(&p, &ops, 0.5, 1, true, |k| RegIn {
        amp_valid: k == 2,
        ..values(live)
    });
    let want = |name: &str| want(name, live);
    for (r, got) in REGISTERS.iter().zip(&rs) {
        assert_eq!(
            *got as u32,
            want(r.name),
            "{} at 0x{:02x}",
            r.name,
            r.address
        );
    }
    assert_eq!(rs.last(), Some(&0), "an address with no register reads 0");
    assert_eq!(VERSION, 0x000100, "0.1.0");
}

#[test]
fn status_is_write_one_to_clear_and_a_present_fault_sets_again() {
    let p = params();
    let status = REGISTERS
        .iter()
        .find(|r| r.name == "STATUS")
        .expect("STATUS");
    assert_eq!(status.access, Access::W1c);
    let a = status.address as u64;
    // LOS (bit 0), OVERSPEED (bit 3) and ADC_FRAME (bit 9) pulse in clocks 0..4 (the
    // first two in reset); QEP_MISMATCH (bit 4) and NOT_REFERENCED (bit 10) stay.
    let flags = |k: usize| {
        let pulse = if k < 4 { 0b10_0000_1001 } else { 0 };
        pulse | 0b100_0001_0000
    };
    let ops = [
        Op::Read(a),
        // Clear LOS only (byte 0, bit 0), then ADC_FRAME (byte 1, bit 9), then everything:
        // QEP_MISMATCH and NOT_REFERENCED set again.
        Op::Write(a, 0b0001, 0b0001),
        Op::Read(a),
        Op::Write(a, 1 << 9, 0b0010),
        Op::Read(a),
        Op::Write(a, 0xffff_ffff, 0b1111),
        Op::Read(a),
        // A strobe that leaves byte 0 out clears nothing there.
        Op::Write(a, 0xffff_ffff, 0b1110),
        Op::Read(a),
    ];
    let (_, _, rs) = drive(&p, &ops, 0.0, 2, false, |k| values(flags(k)));
    // Each request after the one before: every read sees QEP_MISMATCH and NOT_REFERENCED;
    // LOS, OVERSPEED and ADC_FRAME stay latched until cleared.
    let m = STATUS_MASK as u64;
    assert_eq!(m, 0b110_0001_1111, "STATUS's bits");
    assert_eq!(rs[0] & m, 0b110_0001_1001, "latched: {:#b}", rs[0]);
    assert_eq!(rs[1] & m, 0b110_0001_1000, "LOS cleared: {:#b}", rs[1]);
    assert_eq!(
        rs[2] & m,
        0b100_0001_1000,
        "ADC_FRAME cleared: {:#b}",
        rs[2]
    );
    assert_eq!(
        rs[3] & m,
        0b100_0001_0000,
        "all cleared, QEP_MISMATCH and NOT_REFERENCED set again"
    );
    assert_eq!(rs[4] & m, 0b100_0001_0000);
}

#[test]
fn preset_pulses_once_per_write_and_position_latches_turns_and_velocity() {
    let p = params();
    let ops = [
        Op::Write(0x28, 1, 0b1111),
        Op::Write(0x28, 0, 0b1111),
        Op::Write(0x28, 1, 0b1111),
    ];
    let (_, outs, _) = drive(&p, &ops, 0.3, 3, false, |_| values(0));
    assert_eq!(outs.iter().filter(|o| o.preset).count(), 2);
    // POSITION read at turns -3 (its data loads in clock 3); the turns change to 9 from
    // clock 4 on, before TURNS is read: it still reads -3.
    let ops = [
        Op::Read(0x14),
        Op::Read(0x18),
        Op::Read(0x14),
        Op::Read(0x18),
    ];
    let (ins, _, rs) = drive(&p, &ops, 0.0, 4, false, |k| RegIn {
        turns: if k < 4 { (-3i64 as u64) & mask(12) } else { 9 },
        ..values(0)
    });
    let first_turns_read = ins
        .iter()
        .position(|i| i.arvalid && i.araddr == 0x18)
        .expect("TURNS read");
    assert!(first_turns_read >= 4, "TURNS is read after the change");
    assert_eq!(rs[1] as u32, -3i32 as u32, "TURNS as of the POSITION read");
    assert_eq!(rs[3], 9, "TURNS as of the second POSITION read");
}

/// A write to a correction code leaves on the load port once, two clocks after its
/// handshake: the code's bit, the bits under the strobes and the strobes as a mask; other
/// writes load no code.
#[test]
fn code_writes_go_to_the_correction_load_port() {
    let p = params();
    let ops = [
        Op::Write(0x48, 0xdead_beef, 0b1111),
        Op::Write(0x54, 0x1234_5678, 0b0010),
        Op::Write(0x58, 0x0001_0042, 0b0101),
        Op::Write(0x3c, 77, 0b1111),
    ];
    let (_, outs, _) = drive(&p, &ops, 0.3, 12, false, |_| values(0));
    let loads: Vec<(u64, u64, u64)> = outs
        .iter()
        .filter(|o| o.cor_ld != 0)
        .map(|o| (o.cor_ld, o.cor_bits, o.cor_msk))
        .collect();
    assert_eq!(
        loads,
        vec![
            (0b00001, 0xdead_beef, 0xffff_ffff),
            (0b01000, 0x0000_5600, 0x0000_ff00),
            (0b10000, 0x0001_0042, 0x00ff_00ff),
        ]
    );
}

#[test]
fn a_write_and_a_read_in_the_same_clock_both_proceed() {
    let p = params();
    let ops = [Op::Write(0x08, 0x1f, 0xf), Op::Read(0x00)];
    let (ins, _, rs) = drive(&p, &ops, 0.0, 5, true, |_| values(0));
    let both = ins.iter().any(|i| i.awvalid && i.wvalid && i.arvalid);
    assert!(both, "write address, data and read address in one clock");
    assert_eq!(rs, vec![ID as u64]);
    // Two writes back to back: the second's address may come while the first's B waits.
    let ops = [Op::Write(0x28, 1, 1), Op::Write(0x28, 1, 1), Op::Read(0x04)];
    let (_, outs, rs) = drive(&p, &ops, 0.6, 6, true, |_| values(0));
    assert_eq!(outs.iter().filter(|o| o.preset).count(), 2);
    assert_eq!(rs, vec![VERSION as u64]);
}

#[test]
fn four_way_cosimulation() {
    let p = params();
    let mut r = SplitMix64(9);
    let mut ops = vec![];
    for _ in 0..300 {
        let a = (r.range(0, REGISTERS.len() as i64) * 4) as u64;
        if r.unit() < 0.5 {
            ops.push(Op::Read(a));
        } else {
            ops.push(Op::Write(
                a,
                r.range(0, 1 << 31) as u64,
                r.range(0, 16) as u64,
            ));
        }
    }
    let vals: Vec<RegIn> = (0..20_000)
        .map(|k| {
            let mut x = SplitMix64(k as u64 * 7 + 1);
            RegIn {
                rst: false,
                flags: if x.unit() < 0.02 {
                    x.range(0, 1 << FLAGS_WIDTH) as u64
                } else {
                    0
                },
                amp_valid: x.unit() < 0.1,
                amplitude: x.range(0, 1 << 30) as u64,
                qc: (k as u64 / 37) & mask(13),
                fine: (k as u64 * 13) & mask(14),
                turns: (k as u64 / 500) & mask(12),
                velocity: (x.range(-100_000, 100_000) as u64) & mask(32),
                index_qc: (k as u64 / 300) & mask(13),
                index_turns: 4095,
                cap_qc: 5,
                cap_fine: 6,
                cap_turns: 4090,
                cap_velocity: (-77i64 as u64) & mask(32),
                cap_age: 300,
                ..Default::default()
            }
        })
        .collect();
    let (ins, model, _) = drive(&p, &ops, 0.4, 10, true, |k| vals[k % vals.len()]);
    let rows: Vec<Vec<u64>> = ins.iter().map(|i| i.row()).collect();
    let model: Vec<Vec<u64>> = model.iter().map(|o| o.row()).collect();
    four_ways(&p, "regmap_cosim", &rows, &model);
}

/// The BiSS control channel's byte port ([`RegmapParams::with_biss_port`]), driven clock by
/// clock while an AXI master reads at random: each byte of every register reads what the
/// table defines, low byte first; POSITION, TURNS and VELOCITY come from the snapshot the
/// read start at POSITION's byte 0 took (the position moves after it); bytes of banks 1..3
/// with no register and of bank 4 read 0; a byte write to STATUS clears the bits of its
/// lane, one to PRESET's byte 0 pulses `preset` and one to its byte 1 does not. Then
/// rust-hdl == Icarus == Verilator == engine on the same clocks.
#[test]
fn biss_byte_port_reads_and_writes_the_map_four_ways() {
    let p = params().with_biss_port();
    let live = 0b1_0100_0000;
    // The schedule: (byte address, hold clocks, snapshot pulse, byte write).
    let mut plan: Vec<(u64, usize, bool, Option<u64>)> = vec![(0x14, 8, true, None)];
    for r in REGISTERS {
        for lane in 0..4 {
            plan.push((r.address as u64 + lane, 8, false, None));
        }
    }
    for a in [0x68u64, 0x7c, 0xfc, 0x100, 0x103] {
        plan.push((a, 8, false, None));
    }
    // STATUS has LOS and OVERSPEED from the faults of clocks 2..6: clear LOS by byte 0.
    plan.push((0x08, 8, false, Some(0x01)));
    plan.push((0x08, 8, false, None));
    plan.push((0x28, 8, false, Some(0x01)));
    plan.push((0x29, 8, false, Some(0x01)));
    // LOS_THRESHOLD's byte 1 written alone, then read back.
    plan.push((0x3d, 8, false, Some(0x12)));
    plan.push((0x3d, 8, false, None));
    // GAIN_SIN's byte 1: a load of the correction's code.
    plan.push((0x51, 8, false, Some(0x7f)));
    let mut at = vec![];
    let mut k = 2;
    for &(a, hold, _, _) in &plan {
        at.push(k);
        k += hold;
        let _ = a;
    }
    let total = k;
    let schedule = |k: usize| -> (u64, bool, Option<u64>) {
        let j = at.iter().rposition(|&s| s <= k).unwrap_or(0);
        let (a, _, snap, w) = plan[j];
        // The snapshot pulse and the write strobe one clock after the address is set.
        let first = k == at[j] + 1;
        (a, snap && first, if first { w } else { None })
    };
    let values_at = |k: usize| {
        let (bus_addr, bus_snap, w) = schedule(k.min(total - 1));
        RegIn {
            bus_addr,
            bus_snap,
            bus_we: w.is_some(),
            bus_wdata: w.unwrap_or(0),
            // The position moves once the snapshot is taken.
            qc: if k > at[0] + 3 { 999 } else { 1234 },
            flags: live | if (2..6).contains(&k) { 0b1001 } else { 0 },
            amp_valid: k == 2,
            ..values(live)
        }
    };
    let ops: Vec<Op> = (0..300).map(|j| Op::Read((j % 16) * 4)).collect();
    let (ins, outs, _) = drive(&p, &ops, 0.3, 11, false, values_at);
    assert!(
        ins.len() >= total,
        "the AXI traffic lasts {} clocks",
        ins.len()
    );
    // The byte of the address of step j, seen at its last clock.
    let got = |j: usize| outs[at[j] + plan[j].1 - 1].bus_rdata;
    for (n, r) in REGISTERS.iter().enumerate() {
        let v = match r.name {
            // After a clear by byte 0: OVERSPEED remains (read further down).
            "STATUS" => 0b1001,
            "FLAGS" => live as u32,
            name => want(name, live),
        };
        for lane in 0..4 {
            let j = 1 + 4 * n + lane;
            assert_eq!(
                got(j),
                (v >> (8 * lane) & 0xff) as u64,
                "{} byte {lane} over the BiSS port",
                r.name
            );
        }
    }
    let base = 1 + 4 * REGISTERS.len();
    for (j, step) in plan.iter().enumerate().skip(base).take(5) {
        assert_eq!(got(j), 0, "0x{:x} has no register", step.0);
    }
    assert_eq!(got(base + 6), 0b1000, "STATUS after clearing LOS by byte 0");
    let pulses: Vec<usize> = (0..outs.len()).filter(|&k| outs[k].preset).collect();
    assert_eq!(pulses.len(), 1, "PRESET: byte 0 pulses, byte 1 does not");
    assert!(pulses[0] > at[base + 7] && pulses[0] < at[base + 8]);
    assert_eq!(got(base + 10), 0x12, "LOS_THRESHOLD byte 1 after its write");
    let t = (THRESHOLDS[0] & !0xff00) | 0x1200;
    assert_eq!(
        outs[at[base + 10]].thresholds[0],
        t as u64,
        "the other bytes kept"
    );
    let loads: Vec<(u64, u64, u64)> = outs
        .iter()
        .filter(|o| o.cor_ld != 0)
        .map(|o| (o.cor_ld, o.cor_bits, o.cor_msk))
        .collect();
    assert_eq!(
        loads,
        vec![(0b100, 0x7f00, 0xff00)],
        "GAIN_SIN byte 1 loads"
    );
    let rows: Vec<Vec<u64>> = ins.iter().map(|i| i.row_with_bus()).collect();
    let model: Vec<Vec<u64>> = outs.iter().map(|o| o.row_with_bus()).collect();
    four_ways(&p, "regmap_biss_port", &rows, &model);
}

/// The map on `rows` in rust-hdl (equal to the `model` rows), Icarus, Verilator and the
/// engine (equal to rust-hdl), work directory `tag`.
pub(crate) fn four_ways(p: &RegmapParams, tag: &str, rows: &[Vec<u64>], model: &[Vec<u64>]) {
    let dir = common::workdir(tag);
    let t = block_traces(RegisterMap::new(p), tag, "clk", rows, Simulators::ALL, &dir)
        .expect("simulators ran");
    for (k, (r, m)) in t.rust_hdl.iter().zip(model).enumerate() {
        assert_eq!(r, m, "row {k}: rust-hdl vs model");
    }
    assert_eq!(t.rust_hdl.len(), model.len());
    if let Some(m) = t.mismatch() {
        panic!("{m}");
    }
}

#[test]
fn the_table_is_in_address_order_without_gaps_in_the_words() {
    for (k, r) in REGISTERS.iter().enumerate() {
        assert_eq!(r.address, 4 * k as u32, "{}", r.name);
        assert_eq!(r.width, 32);
        let bits: u32 = r.fields.iter().map(|f| f.width).sum();
        assert!(bits <= 32 && r.fields.iter().all(|f| f.lsb + f.width <= 32));
    }
}

#[test]
fn synthesizes_for_both_families() {
    use sinedec::synth::{synthesize, Family};
    let p = params();
    let mut uut = RegisterMap::new(&p);
    rust_hdl::prelude::Block::connect_all(&mut uut);
    let name = "regmap_synth";
    let v = sinedec::emit::verilog::export(&uut, name, name).expect("export");
    let dir = common::workdir(name);
    let x = synthesize(&v, name, Family::Xc3sa, &dir).expect("xc3sa synthesis");
    let c = synthesize(&v, name, Family::CycloneIve, &dir).expect("cycloneive synthesis");
    eprintln!(
        "{name}: xc3sa {} LUT, {} FF; cycloneive {} LE, {} FF",
        x.luts, x.ffs, c.luts, c.ffs
    );
    // Registers Yosys keeps: the write holders (6 address bits, the 32 data bits the
    // thresholds take, 4 strobes), the channel flags, the one-hot read select (18; 23 with
    // the codes), the
    // read data (32), STATUS (7), the amplitude (32), the TURNS shadow (12: its sign extension
    // is one flip-flop), the VELOCITY shadow (32), the preset pulse and the three
    // thresholds (96): about 275; with the correction codes' write on its way (5 load bits,
    // 32 data and 32 mask bits) and 5 more select bits: about 355.
    assert!(x.ffs > 320 && x.ffs < 400, "{} FF", x.ffs);
}
