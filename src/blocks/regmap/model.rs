//! Bit-accurate model of the register map: the same registers as the RTL, updated once per
//! clock edge; `step` returns what the outputs show after the edge.
use super::hdl::MIRROR_WORD_BITS;
use super::{
    flag_bit, RegmapParams, ADDR_BITS, CODE_WORDS, FLAGS_MASK, HARM_WORDS, ID, POSITION_WORD,
    PRESET_WORD, STATUS_MASK, STATUS_WORD, THRESHOLD_WORDS, VERSION,
};
use crate::blocks::mask;

/// Inputs of one clock cycle: the AXI4-Lite master's signals and the decoder's values.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RegIn {
    /// Synchronous reset.
    pub rst: bool,
    /// Write address channel.
    pub awaddr: u64,
    /// See `awaddr`.
    pub awvalid: bool,
    /// Write data channel.
    pub wdata: u64,
    /// Byte strobes.
    pub wstrb: u64,
    /// See `wdata`.
    pub wvalid: bool,
    /// Write response channel: the master takes it.
    pub bready: bool,
    /// Read address channel.
    pub araddr: u64,
    /// See `araddr`.
    pub arvalid: bool,
    /// Read data channel: the master takes it.
    pub rready: bool,
    /// Live flags, FLAGS's bits (REFERENCED as the block gets it).
    pub flags: u64,
    /// A new CORDIC magnitude.
    pub amp_valid: bool,
    /// The CORDIC magnitude.
    pub amplitude: u64,
    /// The position every output takes: quadrant count, fine part, turn word (held).
    pub qc: u64,
    /// See `qc`.
    pub fine: u64,
    /// See `qc`.
    pub turns: u64,
    /// The velocity (held).
    pub velocity: u64,
    /// The last index: quadrant count and turn word (held).
    pub index_qc: u64,
    /// See `index_qc`.
    pub index_turns: u64,
    /// The last capture: quadrant count, fine part, turn word, velocity, age (held).
    pub cap_qc: u64,
    /// See `cap_qc`.
    pub cap_fine: u64,
    /// See `cap_qc`.
    pub cap_turns: u64,
    /// See `cap_qc`.
    pub cap_velocity: u64,
    /// See `cap_qc`.
    pub cap_age: u64,
    /// The correction's codes in use, as OFFSET_SIN, OFFSET_COS, GAIN_SIN, GAIN_COS and
    /// PHASE read.
    pub cor: [u64; 5],
    /// The BiSS control channel's byte port (with [`RegmapParams::biss_port`]): the byte
    /// address in the map (bank * 64 + the channel's address; 256 and above: no register).
    pub bus_addr: u64,
    /// One clock: write `bus_wdata` to the byte at `bus_addr`.
    pub bus_we: bool,
    /// The byte written.
    pub bus_wdata: u64,
    /// One clock: a read of the byte at `bus_addr` begins; at POSITION's byte 0 it
    /// latches the channel's own POSITION, TURNS and VELOCITY.
    pub bus_snap: bool,
    /// The learner (with [`RegmapParams::with_harmonics`]): one clock, it writes entry
    /// `h_tw_addr` = bank * P + i of its table with `h_tw_data` (E bits, 2^-8 LSB).
    pub h_tw: bool,
    /// See `h_tw`.
    pub h_tw_addr: u64,
    /// See `h_tw`.
    pub h_tw_data: u64,
    /// The learner's bank in use.
    pub h_bank: bool,
    /// The learner has a load pending.
    pub h_ld_busy: bool,
}

impl RegIn {
    /// Stimulus row in [`crate::cosim::CosimBlock::input_ports`] order.
    pub fn row(&self) -> Vec<u64> {
        vec![
            self.rst as u64,
            self.awaddr & mask(ADDR_BITS),
            self.awvalid as u64,
            self.wdata & mask(32),
            self.wstrb & 0xf,
            self.wvalid as u64,
            self.bready as u64,
            self.araddr & mask(ADDR_BITS),
            self.arvalid as u64,
            self.rready as u64,
            self.flags & FLAGS_MASK as u64,
            self.amp_valid as u64,
            self.amplitude & mask(32),
            self.qc & mask(32),
            self.fine & mask(32),
            self.turns & mask(32),
            self.velocity,
            self.index_qc & mask(32),
            self.index_turns & mask(32),
            self.cap_qc & mask(32),
            self.cap_fine & mask(32),
            self.cap_turns & mask(32),
            self.cap_velocity,
            self.cap_age & mask(32),
            self.cor[0] & mask(32),
            self.cor[1] & mask(32),
            self.cor[2] & mask(32),
            self.cor[3] & mask(32),
            self.cor[4] & mask(32),
        ]
    }
    /// [`Self::row`] with the BiSS byte port's inputs after it (the port order of a map
    /// with [`RegmapParams::biss_port`]).
    pub fn row_with_bus(&self) -> Vec<u64> {
        let mut r = self.row();
        r.extend([
            self.bus_addr & mask(32),
            self.bus_we as u64,
            self.bus_wdata & 0xff,
            self.bus_snap as u64,
        ]);
        r
    }
    /// The stimulus row of the map `p`: [`Self::row`], the BiSS port's inputs with
    /// [`RegmapParams::biss_port`], the learner's with [`RegmapParams::with_harmonics`].
    pub fn row_for(&self, p: &RegmapParams) -> Vec<u64> {
        let mut r = if p.biss_port() {
            self.row_with_bus()
        } else {
            self.row()
        };
        if p.harmonics().is_some() {
            r.extend([
                self.h_tw as u64,
                self.h_tw_addr & mask(32),
                self.h_tw_data & mask(32),
                self.h_bank as u64,
                self.h_ld_busy as u64,
            ]);
        }
        r
    }
}

/// Outputs after one clock edge.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RegOut {
    /// The write address holder is empty.
    pub awready: bool,
    /// The write data holder is empty.
    pub wready: bool,
    /// A write response is pending (OKAY).
    pub bvalid: bool,
    /// No read address held and no read data pending.
    pub arready: bool,
    /// The read data.
    pub rdata: u64,
    /// Read data pending (OKAY).
    pub rvalid: bool,
    /// One clock: PRESET was written with bit 0 set.
    pub preset: bool,
    /// LOS_THRESHOLD, LOS_RELEASE, CLIP_THRESHOLD (to the monitor).
    pub thresholds: [u64; 3],
    /// One clock: bit w loads the correction's code w, with the bits and mask written.
    pub cor_ld: u64,
    /// See `cor_ld`.
    pub cor_bits: u64,
    /// See `cor_ld`.
    pub cor_msk: u64,
    /// The BiSS byte port's read data: the byte at the `bus_addr` of three clocks before
    /// (one clock later while an AXI read holds the shared read select).
    pub bus_rdata: u64,
    /// HARM_CONTROL.LEARN (to the learner's `update`).
    pub h_update: bool,
    /// One clock: load entry `h_ld_addr` with `h_ld_data` (E bits).
    pub h_ld: bool,
    /// See `h_ld`.
    pub h_ld_addr: u64,
    /// See `h_ld`.
    pub h_ld_data: u64,
}

impl RegOut {
    /// Trace row in output-port order (bresp and rresp are 0).
    pub fn row(&self) -> Vec<u64> {
        vec![
            self.awready as u64,
            self.wready as u64,
            0,
            self.bvalid as u64,
            self.arready as u64,
            self.rdata,
            0,
            self.rvalid as u64,
            self.preset as u64,
            self.thresholds[0],
            self.thresholds[1],
            self.thresholds[2],
            self.cor_ld,
            self.cor_bits,
            self.cor_msk,
        ]
    }
    /// [`Self::row`] with the BiSS byte port's output after it.
    pub fn row_with_bus(&self) -> Vec<u64> {
        let mut r = self.row();
        r.push(self.bus_rdata);
        r
    }
    /// The trace row of the map `p` (as [`RegIn::row_for`]).
    pub fn row_for(&self, p: &RegmapParams) -> Vec<u64> {
        let mut r = if p.biss_port() {
            self.row_with_bus()
        } else {
            self.row()
        };
        if p.harmonics().is_some() {
            r.extend([
                self.h_update as u64,
                self.h_ld as u64,
                self.h_ld_addr,
                self.h_ld_data,
            ]);
        }
        r
    }
}

/// The registers (names as in the RTL).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Regs {
    aw_full: bool,
    aw_addr: u64,
    w_full: bool,
    w_data: u64,
    w_strb: u64,
    bvalid: bool,
    ar_full: bool,
    ar_addr: u64,
    rvalid: bool,
    rdata: u64,
    status: u64,
    amp: u64,
    sh_turns: u64,
    sh_vel: u64,
    preset: bool,
    /// The BiSS byte port: its address (registered), read data, own POSITION / TURNS /
    /// VELOCITY latched at a snapshot, and a byte write waiting for a clock without an
    /// AXI write.
    b_addr: u64,
    /// `b_addr` holds an address (the reset leaves the select empty).
    b_held: bool,
    b_word: u64,
    b_wlane: u64,
    b_rdata: u64,
    bpos: u64,
    btur: u64,
    bvel: u64,
    bw_full: bool,
    bw_addr: u64,
    bw_data: u64,
    /// LOS_THRESHOLD, LOS_RELEASE, CLIP_THRESHOLD.
    thr: [u64; 3],
    /// The write of the clock before (word, bits, byte mask): it acts now.
    wq: Option<(u64, u64, u64)>,
    /// A write on its way to the correction: load bits (a code's word only), bits, mask.
    cq: (u64, u64, u64),
    /// The learned table: HARM_CONTROL.LEARN, HARM_INDEX, HARM_ENTRY's staged bytes, a
    /// load on its way (request, entry, value) and the mirror RAM's read register.
    h_learn: bool,
    h_index: u64,
    /// A HARM_ENTRY read has waited its clock.
    h_wait: bool,
    h_stage: u64,
    h_ld: bool,
    h_lda: u64,
    h_ldd: u64,
    h_rd: u64,
    /// The word HARM_ENTRY reads: `h_rd` a clock later (the RAM's read takes two clocks).
    h_rq: u64,
    /// The mirror's clear after reset: the next address, running.
    h_clr: u64,
    h_clring: bool,
}

/// The register map, clock by clock.
#[derive(Clone, Debug)]
pub struct RegisterModel {
    p: RegmapParams,
    r: Regs,
    /// The mirror of the learner's table (2P words, both banks; not touched by reset).
    ram: Vec<u64>,
}

/// The byte strobes as a bit mask of the 32-bit word.
fn strobe_mask(strb: u64) -> u64 {
    (0..4)
        .filter(|b| strb >> b & 1 == 1)
        .fold(0, |m, b| m | 0xff << (8 * b))
}

impl RegisterModel {
    /// The block after power-up (every register 0).
    pub fn new(p: &RegmapParams) -> Self {
        let words = p.harmonics().map_or(0, |(points, _)| 2 * points as usize);
        Self {
            p: *p,
            r: Self::reset(p),
            ram: vec![0; words],
        }
    }

    /// The registers after a reset: 0, the thresholds the configured values.
    fn reset(p: &RegmapParams) -> Regs {
        Regs {
            thr: p.thresholds().map(u64::from),
            h_learn: p.harmonics().is_some(),
            h_clring: p.harmonics().is_some(),
            ..Regs::default()
        }
    }

    /// The live flags as FLAGS reads them.
    fn flags(&self, i: &RegIn) -> u64 {
        let mut f = i.flags & FLAGS_MASK as u64;
        if self.p.referenced_always() {
            f |= flag_bit("REFERENCED") as u64;
        }
        f
    }

    /// The value an AXI read of word `w` loads (before its side effects).
    fn word(&self, w: u64, i: &RegIn) -> u64 {
        self.word_from(w, i, false)
    }

    /// The value word `w` reads on the AXI port, or on the BiSS byte port (`biss`: POSITION,
    /// TURNS and VELOCITY from the channel's own snapshot).
    fn word_from(&self, w: u64, i: &RegIn, biss: bool) -> u64 {
        let p = &self.p;
        let f = p.fine_bits();
        let pos = |qc: u64, fine: u64| ((qc << f) | (fine & mask(f))) & mask(32);
        let v = match w as u32 {
            0 => ID as u64,
            1 => VERSION as u64,
            2 => self.r.status,
            3 => self.flags(i),
            4 => self.r.amp,
            5 if biss => self.r.bpos,
            6 if biss => self.r.btur,
            7 if biss => self.r.bvel,
            5 => pos(i.qc, i.fine),
            6 => self.r.sh_turns,
            7 => self.r.sh_vel,
            8 => pos(i.index_qc, 0),
            9 => p.turns32(i.index_turns) as u64,
            11 => pos(i.cap_qc, i.cap_fine),
            12 => p.turns32(i.cap_turns) as u64,
            13 => p.velocity32(i.cap_velocity) as u64,
            14 => i.cap_age & mask(32),
            w if THRESHOLD_WORDS.contains(&w) => {
                let k = THRESHOLD_WORDS.iter().position(|&t| t == w).unwrap_or(0);
                self.r.thr[k]
            }
            w if CODE_WORDS.contains(&w) => {
                let k = CODE_WORDS.iter().position(|&t| t == w).unwrap_or(0);
                i.cor[k]
            }
            w if w == HARM_WORDS[0] && p.harmonics().is_some() => {
                self.r.h_learn as u64 | (i.h_ld_busy as u64) << 1
            }
            w if w == HARM_WORDS[1] && p.harmonics().is_some() => self.r.h_index,
            w if w == HARM_WORDS[2] => match p.harmonics() {
                Some((_, e)) => crate::blocks::sext(self.r.h_rq, e) as u64,
                None => 0,
            },
            _ => 0,
        };
        v & mask(32)
    }

    /// One clock edge with inputs `i`; returns the outputs after it.
    pub fn step(&mut self, i: RegIn) -> RegOut {
        let o = self.r;
        let mut n = o;
        if i.rst {
            let clear = self.r.h_clring.then_some(self.r.h_clr);
            self.r = Self::reset(&self.p);
            self.table_ram(&i, 0, clear);
            return self.out();
        }
        let word = |a: u64| (a & mask(ADDR_BITS)) >> 2;
        // Write: the holders, then the write when both are held and no response pending.
        if i.awvalid && !o.aw_full {
            n.aw_full = true;
            n.aw_addr = i.awaddr & mask(ADDR_BITS);
        }
        if i.wvalid && !o.w_full {
            n.w_full = true;
            n.w_data = i.wdata & mask(32);
            n.w_strb = i.wstrb & 0xf;
        }
        if o.bvalid && i.bready {
            n.bvalid = false;
        }
        let mut clear = 0;
        n.preset = false;
        // The write of this clock: AXI's, else a BiSS byte write waiting (as (word, bits)).
        let mut write = None;
        if o.aw_full && o.w_full && !o.bvalid {
            let m = strobe_mask(o.w_strb);
            write = Some((word(o.aw_addr), o.w_data & m, m));
            n.aw_full = false;
            n.w_full = false;
            n.bvalid = true;
        } else if o.bw_full {
            let lane = 8 * (o.bw_addr & 3);
            write = Some((o.bw_addr >> 2, (o.bw_data & 0xff) << lane, 0xff << lane));
            n.bw_full = false;
        }
        if self.p.biss_port() && i.bus_we {
            n.bw_full = true;
            n.bw_addr = i.bus_addr & mask(32);
            n.bw_data = i.bus_wdata & 0xff;
        }
        n.wq = write;
        n.h_ld = false;
        let mut inext = o.h_index;
        // Every write's bits and mask go on to the correction; the load bits select a code.
        n.cq = o.wq.map_or((0, 0, 0), |(_, bits, m)| (0, bits, m));
        if let Some((w, bits, m)) = o.wq {
            if let Some(k) = CODE_WORDS.iter().position(|&t| t as u64 == w) {
                n.cq.0 = 1 << k;
            }
            if let Some((points, e)) = self.p.harmonics() {
                match w {
                    w if w == HARM_WORDS[0] as u64 && m & 1 == 1 => n.h_learn = bits & 1 == 1,
                    w if w == HARM_WORDS[1] as u64 => {
                        inext = ((o.h_index & !m) | bits) & (points as u64 - 1);
                    }
                    w if w == HARM_WORDS[2] as u64 => {
                        // The bytes staged; byte 3 sends the whole word to the learner.
                        let v = (o.h_stage & !m) | bits;
                        n.h_stage = v;
                        if m >> 24 & 0xff != 0 {
                            (n.h_ld, n.h_lda, n.h_ldd) = (true, o.h_index, v & mask(e));
                        }
                    }
                    _ => {}
                }
            }
            match w {
                w if w == STATUS_WORD as u64 => clear = bits,
                w if w == PRESET_WORD as u64 => n.preset = bits & 1 == 1,
                w => {
                    if let Some(k) = THRESHOLD_WORDS.iter().position(|&t| t as u64 == w) {
                        n.thr[k] = (o.thr[k] & !m) | bits;
                    }
                }
            }
        }
        // Faults: set wins over a clear in the same clock.
        let fmask = STATUS_MASK as u64;
        n.status = (o.status & !clear & fmask) | (i.flags & fmask);
        if i.amp_valid {
            n.amp = i.amplitude & mask(32);
        }
        // Read: the address held a clock, then the data.
        if i.arvalid && !o.ar_full && !o.rvalid {
            n.ar_full = true;
            n.ar_addr = i.araddr & mask(ADDR_BITS);
        }
        if o.rvalid && i.rready {
            n.rvalid = false;
        }
        if self.p.biss_port() {
            // The BiSS byte port: the address registered, the byte read while AXI does not
            // hold the read select, the snapshot at POSITION's byte 0.
            n.b_addr = i.bus_addr & mask(32);
            n.b_held = true;
            n.b_rdata = o.b_word >> (8 * o.b_wlane) & 0xff;
            if !o.ar_full {
                let w = o.b_addr >> 2;
                let v = if w < super::REGISTERS.len() as u64 && o.b_held {
                    self.word_from(w, &i, true)
                } else {
                    0
                };
                n.b_word = v;
                n.b_wlane = o.b_addr & 3;
            }
            if i.bus_snap && o.b_held && o.b_addr == 4 * POSITION_WORD as u64 {
                n.bpos = self.word(POSITION_WORD as u64, &i);
                n.btur = self.p.turns32(i.turns) as u64;
                n.bvel = self.p.velocity32(i.velocity) as u64;
            }
        }
        // HARM_ENTRY answers a clock later (the mirror's read takes two clocks).
        let hold = o.ar_full
            && self.p.harmonics().is_some()
            && word(o.ar_addr) == HARM_WORDS[2] as u64
            && !o.h_wait;
        n.h_wait = hold;
        if o.ar_full && !hold {
            let w = word(o.ar_addr);
            n.rdata = self.word(w, &i);
            if w == POSITION_WORD as u64 {
                n.sh_turns = self.p.turns32(i.turns) as u64;
                n.sh_vel = self.p.velocity32(i.velocity) as u64;
            }
            n.ar_full = false;
            n.rvalid = true;
        }
        n.h_index = inext;
        if let Some((points, _)) = self.p.harmonics() {
            // The clear: one word a clock, pausing while the learner writes.
            if o.h_clring && !i.h_tw {
                n.h_clr = (o.h_clr + 1) & mask(32);
                n.h_clring = o.h_clr != 2 * points as u64 - 1;
            }
        }
        self.r = n;
        self.table_ram(&i, inext, o.h_clring.then_some(o.h_clr));
        self.out()
    }

    /// The mirror RAM's clock edge: its second read register takes the first's word, the
    /// first the word at {bank, `index`} (before this clock's write), then the learner's
    /// write lands, else the clear's at `clear`.
    fn table_ram(&mut self, i: &RegIn, index: u64, clear: Option<u64>) {
        let Some((points, _)) = self.p.harmonics() else {
            return;
        };
        let p = points as u64;
        self.r.h_rq = self.r.h_rd;
        self.r.h_rd = self.ram[(i.h_bank as u64 * p + index) as usize];
        if i.h_tw {
            self.ram[(i.h_tw_addr & (2 * p - 1)) as usize] =
                i.h_tw_data & mask(MIRROR_WORD_BITS as u32);
        } else if let Some(a) = clear {
            // Words beyond 2P are not read: the RTL's clear stops at 2P - 1.
            if let Some(w) = self.ram.get_mut(a as usize) {
                *w = 0;
            }
        }
    }

    fn out(&self) -> RegOut {
        let r = &self.r;
        RegOut {
            awready: !r.aw_full,
            wready: !r.w_full,
            bvalid: r.bvalid,
            arready: !r.ar_full && !r.rvalid,
            rdata: r.rdata,
            rvalid: r.rvalid,
            preset: r.preset,
            thresholds: r.thr,
            cor_ld: r.cq.0,
            cor_bits: r.cq.1,
            cor_msk: r.cq.2,
            bus_rdata: r.b_rdata,
            h_update: r.h_learn,
            h_ld: r.h_ld,
            h_ld_addr: r.h_lda,
            h_ld_data: r.h_ldd,
        }
    }
}
