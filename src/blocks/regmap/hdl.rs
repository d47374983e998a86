//! rust-hdl description of the register map (protocol, registers and sketch in the module
//! docs of [`crate::blocks::regmap`]). [`RegisterModel`](super::model::RegisterModel) is its
//! cycle reference.
//!
//! Timing: the read address is held as a one-hot select (`ar_sel`), so the read data is
//! an AND-OR of the words from registers; the write acts from the holders, also registers; every AXI output is a
//! register or one gate of registers.
use super::{
    flag_bit, RegmapParams, ADDR_BITS, FLAGS_MASK, ID, POSITION_WORD, PRESET_WORD, STATUS_MASK,
    STATUS_WORD, VERSION,
};
use crate::blocks::{c32, mask};
use crate::cosim::Port;
use rust_hdl::prelude::*;

fn c64(v: u64) -> Constant<Bits<64>> {
    Constant::new(Bits::<64>::from(v))
}

/// The AXI4-Lite slave and its registers (ports in the module docs of `regmap`).
#[derive(LogicBlock)]
pub struct RegisterMap {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high: nothing held, no response pending, STATUS 0.
    pub rst: Signal<In, Bit>,
    /// Write address (byte address, [`ADDR_BITS`] bits used).
    pub s_axi_awaddr: Signal<In, Bits<32>>,
    /// Write address valid.
    pub s_axi_awvalid: Signal<In, Bit>,
    /// Write address ready: the address holder is empty.
    pub s_axi_awready: Signal<Out, Bit>,
    /// Write data.
    pub s_axi_wdata: Signal<In, Bits<32>>,
    /// Write byte strobes.
    pub s_axi_wstrb: Signal<In, Bits<32>>,
    /// Write data valid.
    pub s_axi_wvalid: Signal<In, Bit>,
    /// Write data ready: the data holder is empty.
    pub s_axi_wready: Signal<Out, Bit>,
    /// Write response: always OKAY (0).
    pub s_axi_bresp: Signal<Out, Bits<32>>,
    /// Write response valid.
    pub s_axi_bvalid: Signal<Out, Bit>,
    /// Write response ready.
    pub s_axi_bready: Signal<In, Bit>,
    /// Read address (byte address, [`ADDR_BITS`] bits used).
    pub s_axi_araddr: Signal<In, Bits<32>>,
    /// Read address valid.
    pub s_axi_arvalid: Signal<In, Bit>,
    /// Read address ready: no address held, no data pending.
    pub s_axi_arready: Signal<Out, Bit>,
    /// Read data.
    pub s_axi_rdata: Signal<Out, Bits<32>>,
    /// Read response: always OKAY (0).
    pub s_axi_rresp: Signal<Out, Bits<32>>,
    /// Read data valid.
    pub s_axi_rvalid: Signal<Out, Bit>,
    /// Read data ready.
    pub s_axi_rready: Signal<In, Bit>,
    /// Live flags: FLAGS's bits (`FLAGS`).
    pub flags: Signal<In, Bits<32>>,
    /// A new CORDIC magnitude.
    pub amp_valid: Signal<In, Bit>,
    /// The CORDIC magnitude.
    pub amplitude: Signal<In, Bits<32>>,
    /// The position every output takes: quadrant count (held).
    pub qc: Signal<In, Bits<32>>,
    /// Its fine part.
    pub fine: Signal<In, Bits<32>>,
    /// Its turn word (M bits).
    pub turns: Signal<In, Bits<32>>,
    /// The velocity (held; its width's low bits).
    pub velocity: Signal<In, Bits<64>>,
    /// The last index's quadrant count.
    pub index_qc: Signal<In, Bits<32>>,
    /// The last index's turn word.
    pub index_turns: Signal<In, Bits<32>>,
    /// The last capture's quadrant count.
    pub cap_qc: Signal<In, Bits<32>>,
    /// The last capture's fine part.
    pub cap_fine: Signal<In, Bits<32>>,
    /// The last capture's turn word.
    pub cap_turns: Signal<In, Bits<32>>,
    /// The last capture's velocity.
    pub cap_velocity: Signal<In, Bits<64>>,
    /// The last capture's age.
    pub cap_age: Signal<In, Bits<32>>,
    /// One clock: PRESET written with bit 0 set.
    pub preset: Signal<Out, Bit>,
    aw_full: DFF<Bit>,
    aw_addr: DFF<Bits<32>>,
    w_full: DFF<Bit>,
    w_data: DFF<Bits<32>>,
    w_strb: DFF<Bits<32>>,
    bvalid: DFF<Bit>,
    ar_full: DFF<Bit>,
    /// The held read address as a one-hot word select (bit k: word k, k < 16). Timing: the
    /// read data is an AND-OR of the words, no compare chain before `rdata`.
    ar_sel: DFF<Bits<32>>,
    rvalid: DFF<Bit>,
    rdata: DFF<Bits<32>>,
    /// Latched faults.
    status: DFF<Bits<32>>,
    amp: DFF<Bits<32>>,
    /// TURNS and VELOCITY, latched by a POSITION read.
    sh_turns: DFF<Bits<32>>,
    sh_vel: DFF<Bits<32>>,
    pre: DFF<Bit>,
    wword: Signal<Local, Bits<32>>,
    rmux: Signal<Local, Bits<32>>,
    bits: Signal<Local, Bits<32>>,
    smask: Signal<Local, Bits<32>>,
    clear: Signal<Local, Bits<32>>,
    live: Signal<Local, Bits<32>>,
    pos: Signal<Local, Bits<32>>,
    ipos: Signal<Local, Bits<32>>,
    cpos: Signal<Local, Bits<32>>,
    tur: Signal<Local, Bits<32>>,
    itur: Signal<Local, Bits<32>>,
    ctur: Signal<Local, Bits<32>>,
    vel: Signal<Local, Bits<32>>,
    cvel: Signal<Local, Bits<32>>,
    /// Mask of the byte address.
    amask: Constant<Bits<32>>,
    /// Mask of the one-hot select (the 16 words).
    selmask: Constant<Bits<32>>,
    two: Constant<Bits<32>>,
    /// Word indices of the registers with an action.
    w_status: Constant<Bits<32>>,
    w_preset: Constant<Bits<32>>,
    w_position: Constant<Bits<32>>,
    /// Word indices of the others, in address order.
    w_id: Constant<Bits<32>>,
    w_version: Constant<Bits<32>>,
    w_flags: Constant<Bits<32>>,
    w_amp: Constant<Bits<32>>,
    w_turns: Constant<Bits<32>>,
    w_vel: Constant<Bits<32>>,
    w_ipos: Constant<Bits<32>>,
    w_itur: Constant<Bits<32>>,
    w_cpos: Constant<Bits<32>>,
    w_ctur: Constant<Bits<32>>,
    w_cvel: Constant<Bits<32>>,
    w_cage: Constant<Bits<32>>,
    id: Constant<Bits<32>>,
    version: Constant<Bits<32>>,
    one: Constant<Bits<32>>,
    zero: Constant<Bits<32>>,
    /// The byte strobes' masks (byte 0 .. 3).
    b0: Constant<Bits<32>>,
    b1: Constant<Bits<32>>,
    b2: Constant<Bits<32>>,
    b3: Constant<Bits<32>>,
    s0: Constant<Bits<32>>,
    s1: Constant<Bits<32>>,
    s2: Constant<Bits<32>>,
    s3: Constant<Bits<32>>,
    /// The four byte strobes.
    strb4: Constant<Bits<32>>,
    /// STATUS's fault bits.
    fmask: Constant<Bits<32>>,
    /// FLAGS's bits.
    flmask: Constant<Bits<32>>,
    /// FLAGS.REFERENCED forced to 1 (no position reference), else 0.
    refd: Constant<Bits<32>>,
    /// F (shift of the quadrant count) and the fine part's mask.
    fshift: Constant<Bits<32>>,
    fmask_fine: Constant<Bits<32>>,
    /// Turn words: mask, sign bit, fill above it (0 when M = 0: the word reads 0).
    tmask: Constant<Bits<32>>,
    tsign: Constant<Bits<32>>,
    tfill: Constant<Bits<32>>,
    /// Velocity words: mask of the low min(W, 32) bits, sign bit and fill (W < 32).
    vmask: Constant<Bits<64>>,
    vsign: Constant<Bits<64>>,
    vfill: Constant<Bits<32>>,
}

impl RegisterMap {
    /// The block for `p`.
    pub fn new(p: &RegmapParams) -> Self {
        let m = p.turns_bits();
        let (tmask, tsign) = if m == 0 {
            (0, 0)
        } else {
            (mask(m), 1u64 << (m - 1))
        };
        let w = p.velocity_width();
        let (vmask, vsign) = match w {
            0 => (0, 0),
            w if w >= 32 => (mask(32), 0),
            w => (mask(w), 1u64 << (w - 1)),
        };
        let wc = |k: u32| c32(k as u64);
        Self {
            clk: Default::default(),
            rst: Default::default(),
            s_axi_awaddr: Default::default(),
            s_axi_awvalid: Default::default(),
            s_axi_awready: Default::default(),
            s_axi_wdata: Default::default(),
            s_axi_wstrb: Default::default(),
            s_axi_wvalid: Default::default(),
            s_axi_wready: Default::default(),
            s_axi_bresp: Default::default(),
            s_axi_bvalid: Default::default(),
            s_axi_bready: Default::default(),
            s_axi_araddr: Default::default(),
            s_axi_arvalid: Default::default(),
            s_axi_arready: Default::default(),
            s_axi_rdata: Default::default(),
            s_axi_rresp: Default::default(),
            s_axi_rvalid: Default::default(),
            s_axi_rready: Default::default(),
            flags: Default::default(),
            amp_valid: Default::default(),
            amplitude: Default::default(),
            qc: Default::default(),
            fine: Default::default(),
            turns: Default::default(),
            velocity: Default::default(),
            index_qc: Default::default(),
            index_turns: Default::default(),
            cap_qc: Default::default(),
            cap_fine: Default::default(),
            cap_turns: Default::default(),
            cap_velocity: Default::default(),
            cap_age: Default::default(),
            preset: Default::default(),
            aw_full: Default::default(),
            aw_addr: Default::default(),
            w_full: Default::default(),
            w_data: Default::default(),
            w_strb: Default::default(),
            bvalid: Default::default(),
            ar_full: Default::default(),
            ar_sel: Default::default(),
            rvalid: Default::default(),
            rdata: Default::default(),
            status: Default::default(),
            amp: Default::default(),
            sh_turns: Default::default(),
            sh_vel: Default::default(),
            pre: Default::default(),
            wword: Default::default(),
            rmux: Default::default(),
            bits: Default::default(),
            smask: Default::default(),
            clear: Default::default(),
            live: Default::default(),
            pos: Default::default(),
            ipos: Default::default(),
            cpos: Default::default(),
            tur: Default::default(),
            itur: Default::default(),
            ctur: Default::default(),
            vel: Default::default(),
            cvel: Default::default(),
            amask: c32(mask(ADDR_BITS)),
            selmask: c32(0xffff),
            two: c32(2),
            w_status: wc(STATUS_WORD),
            w_preset: wc(PRESET_WORD),
            w_position: wc(POSITION_WORD),
            w_id: wc(0),
            w_version: wc(1),
            w_flags: wc(3),
            w_amp: wc(4),
            w_turns: wc(6),
            w_vel: wc(7),
            w_ipos: wc(8),
            w_itur: wc(9),
            w_cpos: wc(11),
            w_ctur: wc(12),
            w_cvel: wc(13),
            w_cage: wc(14),
            id: c32(ID as u64),
            version: c32(VERSION as u64),
            one: c32(1),
            zero: c32(0),
            b0: c32(1),
            b1: c32(2),
            b2: c32(4),
            b3: c32(8),
            s0: c32(0xff),
            s1: c32(0xff00),
            s2: c32(0xff_0000),
            s3: c32(0xff00_0000),
            strb4: c32(0xf),
            fmask: c32(STATUS_MASK as u64),
            flmask: c32(FLAGS_MASK as u64),
            refd: c32(if p.referenced_always() {
                flag_bit("REFERENCED") as u64
            } else {
                0
            }),
            fshift: c32(p.fine_bits() as u64),
            fmask_fine: c32(mask(p.fine_bits())),
            tmask: c32(tmask),
            tsign: c32(tsign),
            tfill: c32(mask(32) & !tmask),
            vmask: c64(vmask),
            vsign: c64(vsign),
            vfill: c32(mask(32) & !vmask),
        }
    }
}

impl Logic for RegisterMap {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clk, aw_full, aw_addr, w_full, w_data, w_strb, bvalid, ar_full, ar_sel, rvalid,
            rdata, status, amp, sh_turns, sh_vel, pre
        );
        // The words each register reads, from the live inputs.
        self.live.next = (self.flags.val() & self.flmask.val()) | self.refd.val();
        self.pos.next =
            (self.qc.val() << self.fshift.val()) | (self.fine.val() & self.fmask_fine.val());
        self.ipos.next = self.index_qc.val() << self.fshift.val();
        self.cpos.next = (self.cap_qc.val() << self.fshift.val())
            | (self.cap_fine.val() & self.fmask_fine.val());
        self.tur.next = self.turns.val() & self.tmask.val();
        if (self.turns.val() & self.tsign.val()).any() {
            self.tur.next = (self.turns.val() & self.tmask.val()) | self.tfill.val();
        }
        self.itur.next = self.index_turns.val() & self.tmask.val();
        if (self.index_turns.val() & self.tsign.val()).any() {
            self.itur.next = (self.index_turns.val() & self.tmask.val()) | self.tfill.val();
        }
        self.ctur.next = self.cap_turns.val() & self.tmask.val();
        if (self.cap_turns.val() & self.tsign.val()).any() {
            self.ctur.next = (self.cap_turns.val() & self.tmask.val()) | self.tfill.val();
        }
        self.vel.next = bit_cast::<32, 64>(self.velocity.val() & self.vmask.val());
        if (self.velocity.val() & self.vsign.val()).any() {
            self.vel.next =
                bit_cast::<32, 64>(self.velocity.val() & self.vmask.val()) | self.vfill.val();
        }
        self.cvel.next = bit_cast::<32, 64>(self.cap_velocity.val() & self.vmask.val());
        if (self.cap_velocity.val() & self.vsign.val()).any() {
            self.cvel.next =
                bit_cast::<32, 64>(self.cap_velocity.val() & self.vmask.val()) | self.vfill.val();
        }
        // Write: the holders, then the write when both are held and no response pending.
        if self.s_axi_awvalid.val() & !self.aw_full.q.val() {
            self.aw_full.d.next = true;
            self.aw_addr.d.next = self.s_axi_awaddr.val() & self.amask.val();
        }
        if self.s_axi_wvalid.val() & !self.w_full.q.val() {
            self.w_full.d.next = true;
            self.w_data.d.next = self.s_axi_wdata.val();
            self.w_strb.d.next = self.s_axi_wstrb.val() & self.strb4.val();
        }
        if self.bvalid.q.val() & self.s_axi_bready.val() {
            self.bvalid.d.next = false;
        }
        self.smask.next = self.zero.val();
        if (self.w_strb.q.val() & self.b0.val()).any() {
            self.smask.next = self.s0.val();
        }
        if (self.w_strb.q.val() & self.b1.val()).any() {
            self.smask.next = self.smask.val() | self.s1.val();
        }
        if (self.w_strb.q.val() & self.b2.val()).any() {
            self.smask.next = self.smask.val() | self.s2.val();
        }
        if (self.w_strb.q.val() & self.b3.val()).any() {
            self.smask.next = self.smask.val() | self.s3.val();
        }
        self.bits.next = self.w_data.q.val() & self.smask.val();
        self.wword.next = self.aw_addr.q.val() >> self.two.val();
        self.clear.next = self.zero.val();
        self.pre.d.next = false;
        if self.aw_full.q.val() & self.w_full.q.val() & !self.bvalid.q.val() {
            if self.wword.val() == self.w_status.val() {
                self.clear.next = self.bits.val();
            }
            if self.wword.val() == self.w_preset.val() {
                self.pre.d.next = (self.bits.val() & self.one.val()).any();
            }
            self.aw_full.d.next = false;
            self.w_full.d.next = false;
            self.bvalid.d.next = true;
        }
        // Faults: set wins over a clear in the same clock.
        self.status.d.next = (self.status.q.val() & !self.clear.val() & self.fmask.val())
            | (self.flags.val() & self.fmask.val());
        if self.amp_valid.val() {
            self.amp.d.next = self.amplitude.val();
        }
        // Read: the address held a clock, then the data.
        if self.s_axi_arvalid.val() & !self.ar_full.q.val() & !self.rvalid.q.val() {
            self.ar_full.d.next = true;
            self.ar_sel.d.next = (self.one.val()
                << ((self.s_axi_araddr.val() & self.amask.val()) >> self.two.val()))
                & self.selmask.val();
        }
        if self.rvalid.q.val() & self.s_axi_rready.val() {
            self.rvalid.d.next = false;
        }
        // The read data: an AND-OR of the words by the one-hot select.
        self.rmux.next = self.zero.val();
        if (self.ar_sel.q.val() & (self.one.val() << self.w_id.val())).any() {
            self.rmux.next = self.rmux.val() | self.id.val();
        }
        if (self.ar_sel.q.val() & (self.one.val() << self.w_version.val())).any() {
            self.rmux.next = self.rmux.val() | self.version.val();
        }
        if (self.ar_sel.q.val() & (self.one.val() << self.w_status.val())).any() {
            self.rmux.next = self.rmux.val() | self.status.q.val();
        }
        if (self.ar_sel.q.val() & (self.one.val() << self.w_flags.val())).any() {
            self.rmux.next = self.rmux.val() | self.live.val();
        }
        if (self.ar_sel.q.val() & (self.one.val() << self.w_amp.val())).any() {
            self.rmux.next = self.rmux.val() | self.amp.q.val();
        }
        if (self.ar_sel.q.val() & (self.one.val() << self.w_position.val())).any() {
            self.rmux.next = self.rmux.val() | self.pos.val();
        }
        if (self.ar_sel.q.val() & (self.one.val() << self.w_turns.val())).any() {
            self.rmux.next = self.rmux.val() | self.sh_turns.q.val();
        }
        if (self.ar_sel.q.val() & (self.one.val() << self.w_vel.val())).any() {
            self.rmux.next = self.rmux.val() | self.sh_vel.q.val();
        }
        if (self.ar_sel.q.val() & (self.one.val() << self.w_ipos.val())).any() {
            self.rmux.next = self.rmux.val() | self.ipos.val();
        }
        if (self.ar_sel.q.val() & (self.one.val() << self.w_itur.val())).any() {
            self.rmux.next = self.rmux.val() | self.itur.val();
        }
        if (self.ar_sel.q.val() & (self.one.val() << self.w_cpos.val())).any() {
            self.rmux.next = self.rmux.val() | self.cpos.val();
        }
        if (self.ar_sel.q.val() & (self.one.val() << self.w_ctur.val())).any() {
            self.rmux.next = self.rmux.val() | self.ctur.val();
        }
        if (self.ar_sel.q.val() & (self.one.val() << self.w_cvel.val())).any() {
            self.rmux.next = self.rmux.val() | self.cvel.val();
        }
        if (self.ar_sel.q.val() & (self.one.val() << self.w_cage.val())).any() {
            self.rmux.next = self.rmux.val() | self.cap_age.val();
        }
        if self.ar_full.q.val() {
            self.rdata.d.next = self.rmux.val();
            if (self.ar_sel.q.val() & (self.one.val() << self.w_position.val())).any() {
                self.sh_turns.d.next = self.tur.val();
                self.sh_vel.d.next = self.vel.val();
            }
            self.ar_full.d.next = false;
            self.rvalid.d.next = true;
        }
        if self.rst.val() {
            self.aw_full.d.next = false;
            self.w_full.d.next = false;
            self.bvalid.d.next = false;
            self.ar_full.d.next = false;
            self.rvalid.d.next = false;
            self.aw_addr.d.next = 0.into();
            self.w_data.d.next = 0.into();
            self.w_strb.d.next = 0.into();
            self.ar_sel.d.next = 0.into();
            self.rdata.d.next = 0.into();
            self.status.d.next = 0.into();
            self.amp.d.next = 0.into();
            self.sh_turns.d.next = 0.into();
            self.sh_vel.d.next = 0.into();
            self.pre.d.next = false;
        }
        self.s_axi_awready.next = !self.aw_full.q.val();
        self.s_axi_wready.next = !self.w_full.q.val();
        self.s_axi_bresp.next = self.zero.val();
        self.s_axi_bvalid.next = self.bvalid.q.val();
        self.s_axi_arready.next = !self.ar_full.q.val() & !self.rvalid.q.val();
        self.s_axi_rdata.next = self.rdata.q.val();
        self.s_axi_rresp.next = self.zero.val();
        self.s_axi_rvalid.next = self.rvalid.q.val();
        self.preset.next = self.pre.q.val();
    }
}

impl crate::cosim::CosimBlock for RegisterMap {
    fn input_ports(&self) -> Vec<Port> {
        vec![
            Port::new("rst", 1),
            Port::new("s_axi_awaddr", 32),
            Port::new("s_axi_awvalid", 1),
            Port::new("s_axi_wdata", 32),
            Port::new("s_axi_wstrb", 32),
            Port::new("s_axi_wvalid", 1),
            Port::new("s_axi_bready", 1),
            Port::new("s_axi_araddr", 32),
            Port::new("s_axi_arvalid", 1),
            Port::new("s_axi_rready", 1),
            Port::new("flags", 32),
            Port::new("amp_valid", 1),
            Port::new("amplitude", 32),
            Port::new("qc", 32),
            Port::new("fine", 32),
            Port::new("turns", 32),
            Port::new("velocity", 64),
            Port::new("index_qc", 32),
            Port::new("index_turns", 32),
            Port::new("cap_qc", 32),
            Port::new("cap_fine", 32),
            Port::new("cap_turns", 32),
            Port::new("cap_velocity", 64),
            Port::new("cap_age", 32),
        ]
    }
    fn output_ports(&self) -> Vec<Port> {
        vec![
            Port::new("s_axi_awready", 1),
            Port::new("s_axi_wready", 1),
            Port::new("s_axi_bresp", 32),
            Port::new("s_axi_bvalid", 1),
            Port::new("s_axi_arready", 1),
            Port::new("s_axi_rdata", 32),
            Port::new("s_axi_rresp", 32),
            Port::new("s_axi_rvalid", 1),
            Port::new("preset", 1),
        ]
    }
    fn apply(&mut self, r: &[u64]) {
        let b32 = |v: u64| Bits::<32>::from(v & mask(32));
        self.rst.next = r[0] != 0;
        self.s_axi_awaddr.next = b32(r[1]);
        self.s_axi_awvalid.next = r[2] != 0;
        self.s_axi_wdata.next = b32(r[3]);
        self.s_axi_wstrb.next = b32(r[4]);
        self.s_axi_wvalid.next = r[5] != 0;
        self.s_axi_bready.next = r[6] != 0;
        self.s_axi_araddr.next = b32(r[7]);
        self.s_axi_arvalid.next = r[8] != 0;
        self.s_axi_rready.next = r[9] != 0;
        self.flags.next = b32(r[10]);
        self.amp_valid.next = r[11] != 0;
        self.amplitude.next = b32(r[12]);
        self.qc.next = b32(r[13]);
        self.fine.next = b32(r[14]);
        self.turns.next = b32(r[15]);
        self.velocity.next = Bits::<64>::from(r[16]);
        self.index_qc.next = b32(r[17]);
        self.index_turns.next = b32(r[18]);
        self.cap_qc.next = b32(r[19]);
        self.cap_fine.next = b32(r[20]);
        self.cap_turns.next = b32(r[21]);
        self.cap_velocity.next = Bits::<64>::from(r[22]);
        self.cap_age.next = b32(r[23]);
    }
    fn sample(&self) -> Vec<u64> {
        vec![
            self.s_axi_awready.val() as u64,
            self.s_axi_wready.val() as u64,
            self.s_axi_bresp.val().to_u64(),
            self.s_axi_bvalid.val() as u64,
            self.s_axi_arready.val() as u64,
            self.s_axi_rdata.val().to_u64(),
            self.s_axi_rresp.val().to_u64(),
            self.s_axi_rvalid.val() as u64,
            self.preset.val() as u64,
        ]
    }
}

impl crate::cosim::step::Clocked for RegisterMap {
    fn set_clock(&mut self, high: bool) {
        self.clk.next = Clock::from(high);
    }
}
