//! Bit-accurate model of the register map: the same registers as the RTL, updated once per
//! clock edge; `step` returns what the outputs show after the edge.
use super::{
    flag_bit, RegmapParams, ADDR_BITS, FLAGS_MASK, ID, POSITION_WORD, PRESET_WORD, STATUS_MASK,
    STATUS_WORD, VERSION,
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
        ]
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
        ]
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
}

/// The register map, clock by clock.
#[derive(Clone, Debug)]
pub struct RegisterModel {
    p: RegmapParams,
    r: Regs,
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
        Self {
            p: *p,
            r: Regs::default(),
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

    /// The value a read of word `w` loads (before its side effects).
    fn word(&self, w: u64, i: &RegIn) -> u64 {
        let p = &self.p;
        let f = p.fine_bits();
        let pos = |qc: u64, fine: u64| ((qc << f) | (fine & mask(f))) & mask(32);
        let v = match w as u32 {
            0 => ID as u64,
            1 => VERSION as u64,
            2 => self.r.status,
            3 => self.flags(i),
            4 => self.r.amp,
            5 => pos(i.qc, i.fine),
            6 => self.r.sh_turns,
            7 => self.r.sh_vel,
            8 => pos(i.index_qc, 0),
            9 => p.turns32(i.index_turns) as u64,
            11 => pos(i.cap_qc, i.cap_fine),
            12 => p.turns32(i.cap_turns) as u64,
            13 => p.velocity32(i.cap_velocity) as u64,
            14 => i.cap_age & mask(32),
            _ => 0,
        };
        v & mask(32)
    }

    /// One clock edge with inputs `i`; returns the outputs after it.
    pub fn step(&mut self, i: RegIn) -> RegOut {
        let o = self.r;
        let mut n = o;
        if i.rst {
            self.r = Regs::default();
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
        if o.aw_full && o.w_full && !o.bvalid {
            let bits = o.w_data & strobe_mask(o.w_strb);
            match word(o.aw_addr) as u32 {
                STATUS_WORD => clear = bits,
                PRESET_WORD => n.preset = bits & 1 == 1,
                _ => {}
            }
            n.aw_full = false;
            n.w_full = false;
            n.bvalid = true;
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
        if o.ar_full {
            let w = word(o.ar_addr);
            n.rdata = self.word(w, &i);
            if w == POSITION_WORD as u64 {
                n.sh_turns = self.p.turns32(i.turns) as u64;
                n.sh_vel = self.p.velocity32(i.velocity) as u64;
            }
            n.ar_full = false;
            n.rvalid = true;
        }
        self.r = n;
        self.out()
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
        }
    }
}
