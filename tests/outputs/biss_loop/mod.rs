//! The BiSS-C closed loop the BiSS tests share (`tests/outputs/biss.rs`, `tests/outputs/biss_corners.rs`):
//! the master model reads the slave (its Verilog on the compiled engine) cycle by cycle, and what every good frame must
//! carry is worked out from the stimulus rows.
#![allow(dead_code)]
use sinedec::blocks::biss::hdl::BissSlave;
use sinedec::blocks::biss::BissParams;
use sinedec::blocks::mask;
use sinedec::cosim::stimulus::SplitMix64;
use sinedec::cosim::BlockEngine;
use sinedec::engine::Kind;
use sinedec::sim::biss_master::{BissFrame, BissMaster, BissMasterConfig};
use sinedec::sim::serial_line::{FrameRequest, LineMaster, LineTiming};

/// Position stream: random 32-bit words every cycle (bits above the configured widths must
/// be ignored), valid every `every` cycles, error / warning in the listed cycles.
#[derive(Clone, Debug, Default)]
pub struct Stream {
    pub every: usize,
    pub errors: Vec<usize>,
    pub warnings: Vec<usize>,
}

impl Stream {
    pub fn pos(&self, k: usize) -> u64 {
        SplitMix64(k as u64 * 2 + 1).next_u64() & mask(32)
    }
    pub fn turns(&self, k: usize) -> u64 {
        SplitMix64(k as u64 * 2 + 0x5555).next_u64() & mask(32)
    }
    pub fn valid(&self, k: usize) -> bool {
        k.is_multiple_of(self.every.max(1))
    }
}

/// Per-cycle test controls.
#[derive(Clone, Copy, Debug, Default)]
pub struct Ctl {
    /// Reset this cycle.
    pub rst: bool,
    /// Invert MA at the slave's pin this cycle (a one-sample glitch).
    pub ma_flip: bool,
    /// Invert SLO on the wire to the master this cycle.
    pub slo_flip: bool,
}

/// One closed-loop run: the stimulus rows (slave port order), the slave's SLO per cycle and
/// the master's frames.
pub struct Run {
    pub rows: Vec<Vec<u64>>,
    pub slo: Vec<u64>,
    pub frames: Vec<BissFrame>,
    pub timing: LineTiming,
}

pub fn closed_loop(
    p: &BissParams,
    master: &mut BissMaster,
    stream: &Stream,
    cycles: usize,
    mut ctl: impl FnMut(usize, &BissMaster) -> Ctl,
    timing: LineTiming,
) -> Run {
    // The slave's exported Verilog on the compiled engine: these loops test the protocol,
    // not rust-hdl's simulation (the replays in rust-hdl, Icarus, Verilator and the engine
    // check that they agree, on these very rows).
    // Built once per parameter set and process, then restarted at power-up for each run
    // (the glitch and rate sweeps run hundreds of short loops on one design).
    thread_local! {
        static BUILT: std::cell::RefCell<std::collections::HashMap<String, BlockEngine>> =
            Default::default();
    }
    let key = format!("{p:?}");
    let mut uut = BUILT
        .with(|b| b.borrow_mut().remove(&key))
        .map(|mut e| {
            e.restart();
            e
        })
        .unwrap_or_else(|| {
            let uut = BissSlave::new(p).expect("params");
            // Named as the replays name it: the same Verilog, so one cached library serves
            // both.
            BlockEngine::new(uut, "biss_slave", Kind::Compiled).expect("engine builds")
        });
    let mut rows = Vec::with_capacity(cycles);
    let mut slo = Vec::with_capacity(cycles);
    for k in 0..cycles {
        let c = ctl(k, master);
        let ma = master.ma_for_cycle(k) ^ c.ma_flip;
        let row = vec![
            (k < 3 || c.rst) as u64,
            ma as u64,
            stream.pos(k),
            stream.turns(k),
            stream.valid(k) as u64,
            stream.errors.contains(&k) as u64,
            stream.warnings.contains(&k) as u64,
        ];
        uut.apply(&row);
        uut.tick();
        let s = uut.output(0);
        slo.push(s);
        rows.push(row);
        master.push_slo((s != 0) ^ c.slo_flip);
    }
    BUILT.with(|b| b.borrow_mut().insert(key, uut));
    Run {
        rows,
        slo,
        frames: master.frames().to_vec(),
        timing,
    }
}

impl Run {
    /// Row at which the slave latched the frame that the master started at `t0`: its first
    /// MA-low row (with the glitch filter: the first of two consecutive low rows, so that a
    /// one-row glitch next to the start counts as the slave sees it) plus the latency.
    pub fn latch_row(&self, t0: f64, p: &BissParams) -> usize {
        let need = if p.glitch_filter { 2 } else { 1 };
        let k0 = ((t0 + self.timing.line_delay_ns) / self.timing.tclk_ns()).floor() as usize;
        let mut k = k0.saturating_sub(3);
        while !(0..need).all(|i| self.rows[k + i][1] == 0) {
            k += 1;
        }
        k + p.latch_latency() as usize
    }
    /// Last valid row at or before `k`.
    pub fn last_valid(&self, k: usize) -> Option<usize> {
        (0..=k)
            .rev()
            .find(|&j| self.rows[j][4] != 0 && self.rows[j][0] == 0)
    }
    /// What the slave must send for a frame latched at row `l`, the previous take (or
    /// reset) at row `prev`: (position, turns, nE, nW).
    pub fn expect(&self, p: &BissParams, l: usize, prev: usize) -> (u64, u64, bool, bool) {
        let last_rst = (0..=l).rev().find(|&j| self.rows[j][0] != 0).unwrap_or(0);
        let from = prev.max(last_rst) + 1;
        let err = (from..=l).any(|j| self.rows[j][5] != 0);
        let warn = (from..=l).any(|j| self.rows[j][6] != 0);
        match self.last_valid(l).filter(|&v| v > last_rst) {
            Some(v) => {
                let pos = self.rows[v][2] & mask(p.position_bits);
                let turns = self.rows[v][3] & mask(p.multiturn_bits);
                (pos, turns, !err, !warn)
            }
            None => (0, 0, false, !warn),
        }
    }
}

pub fn timing(clock_hz: f64, d: f64) -> LineTiming {
    LineTiming {
        clock_hz,
        line_delay_ns: d,
    }
}

pub fn master_for(p: &BissParams, t: LineTiming, reqs: Vec<FrameRequest>) -> BissMaster {
    let mut c = BissMasterConfig::new(t, p.data_bits(), p.multiturn_bits);
    c.word.gray = p.gray;
    BissMaster::new(c, reqs, 500.0)
}

/// Cycles for a list of requests: frame time + timeout + margin, each.
pub fn cycles_for(p: &BissParams, reqs: &[FrameRequest], extra_ns: f64) -> usize {
    let ns: f64 = reqs
        .iter()
        .map(|r| {
            (p.frame_rising_edges() + 1) as f64 * 1e9 / r.ma_hz
                + r.gap_ns
                + p.timeout_us() * 1e3
                + 1000.0
        })
        .sum::<f64>()
        + extra_ns
        + 2000.0;
    (ns * p.clock_hz / 1e9) as usize + p.timeout_clocks as usize + 100
}

/// Every frame of a run is good and carries what the slave latched at its first MA edge.
pub fn check_frames(run: &Run, p: &BissParams, expect_frames: usize) {
    assert_eq!(run.frames.len(), expect_frames, "frames: {:#?}", run.frames);
    let mut prev = 0;
    for (i, f) in run.frames.iter().enumerate() {
        let d = f
            .good()
            .unwrap_or_else(|| panic!("frame {i} at {} MHz not good: {f:#?}", f.ma_hz / 1e6));
        let l = run.latch_row(f.t_start_ns, p);
        let (pos, turns, n_e, n_w) = run.expect(p, l, prev);
        prev = l;
        assert_eq!(d.position, pos, "frame {i} position (latched at row {l})");
        assert_eq!(d.turns, turns, "frame {i} turns");
        assert_eq!((d.n_e, d.n_w), (n_e, n_w), "frame {i} flags");
        assert_eq!(d.ack_bits, p.ack_periods, "frame {i} ack length");
        assert!(!d.cds && d.stop_low, "frame {i}: CDS 0 and the timeout low");
        let to = f.timeout_ns.expect("timeout measured");
        // Round trip, 3-4 clocks of synchronizer, up to 2 more when a glitch moves the edge.
        let nominal = p.timeout_us() * 1e3;
        assert!(
            to >= nominal
                && to <= nominal + 2.0 * run.timing.line_delay_ns + 7.0 * 1e9 / p.clock_hz,
            "frame {i}: timeout {to} ns, nominal {nominal} ns"
        );
    }
}
