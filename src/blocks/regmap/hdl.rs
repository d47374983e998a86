//! rust-hdl description of the register map (protocol, registers and sketch in the module
//! docs of [`crate::blocks::regmap`]). [`RegisterModel`](super::model::RegisterModel) is its
//! cycle reference.
//!
//! Timing: the read address is held as a one-hot select (`ar_sel`), so the read data is
//! an AND-OR of the words from registers; the write acts from the holders, also registers; every AXI output is a
//! register or one gate of registers.
use super::{
    flag_bit, RegmapParams, ADDR_BITS, CODE_WORDS, FLAGS_MASK, HARM_WORDS, ID, POSITION_WORD,
    PRESET_WORD, STATUS_MASK, STATUS_WORD, THRESHOLD_WORDS, VERSION,
};
use crate::blocks::harmonics::hdl_ram::RAM_ADDR_BITS;
use crate::blocks::lutram::PipedLutRam;
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
    /// LOS_THRESHOLD, LOS_RELEASE and CLIP_THRESHOLD: the monitor's run-time thresholds.
    pub los_threshold: Signal<Out, Bits<32>>,
    /// See `los_threshold`.
    pub los_release: Signal<Out, Bits<32>>,
    /// See `los_threshold`.
    pub clip_threshold: Signal<Out, Bits<32>>,
    /// The correction's codes in use (OFFSET_SIN, OFFSET_COS, GAIN_SIN, GAIN_COS, PHASE as
    /// they read).
    pub cor_off_s: Signal<In, Bits<32>>,
    /// See `cor_off_s`.
    pub cor_off_c: Signal<In, Bits<32>>,
    /// See `cor_off_s`.
    pub cor_gain_s: Signal<In, Bits<32>>,
    /// See `cor_off_s`.
    pub cor_gain_c: Signal<In, Bits<32>>,
    /// See `cor_off_s`.
    pub cor_phase: Signal<In, Bits<32>>,
    /// One clock: bit w loads the correction's code w (`CODE_WORDS` order), a clock after
    /// the write acted here.
    pub cor_ld: Signal<Out, Bits<8>>,
    /// The written bits, with `cor_ld`.
    pub cor_bits: Signal<Out, Bits<32>>,
    /// The bits written (byte strobes as a mask), with `cor_ld`.
    pub cor_msk: Signal<Out, Bits<32>>,
    /// The BiSS control channel's byte port (used with [`RegmapParams::biss_port`], else
    /// ignored and 0): the byte address in the map (bank * 64 + channel address). Plain
    /// ports, not `Vec`s: rust-hdl names a port of a `Vec` element of a `Vec` wrongly.
    pub bus_addr: Signal<In, Bits<32>>,
    /// One clock: write `bus_wdata` to the byte at `bus_addr`.
    pub bus_we: Signal<In, Bit>,
    /// The byte written.
    pub bus_wdata: Signal<In, Bits<8>>,
    /// One clock: a read begins; at POSITION's byte 0 it latches the channel's snapshot.
    pub bus_snap: Signal<In, Bit>,
    /// The byte at the address of three clocks before (one more while AXI holds the read select).
    pub bus_rdata: Signal<Out, Bits<8>>,
    /// The learned harmonic table's learner (used with [`RegmapParams::with_harmonics`],
    /// else ignored; plain ports as the `bus_*` ones): one clock, the learner writes entry
    /// `h_tw_addr` = bank * P + i of its table with `h_tw_data`.
    pub h_tw: Signal<In, Bit>,
    /// See `h_tw`.
    pub h_tw_addr: Signal<In, Bits<32>>,
    /// The entry written, 2^-8 LSB, E-bit two's complement in the low bits.
    pub h_tw_data: Signal<In, Bits<32>>,
    /// The learner's bank in use (HARM_ENTRY reads entry i of it).
    pub h_bank: Signal<In, Bit>,
    /// The learner has a load pending (HARM_CONTROL.LOAD_BUSY).
    pub h_ld_busy: Signal<In, Bit>,
    /// HARM_CONTROL.LEARN: 1, learning moves the entries (0 without a learned table).
    pub h_update: Signal<Out, Bit>,
    /// One clock, two clocks after the handshake of a HARM_ENTRY write of byte 3: load
    /// entry `h_ld_addr` of both banks with `h_ld_data`.
    pub h_ld: Signal<Out, Bit>,
    /// The entry i (HARM_INDEX at the write), with `h_ld`.
    pub h_ld_addr: Signal<Out, Bits<32>>,
    /// The value, the written word's low E bits, with `h_ld`.
    pub h_ld_data: Signal<Out, Bits<32>>,
    /// One element with the port, none without: the port's logic is built in its loops.
    bus: Vec<Constant<Bit>>,
    /// The learned table's logic: one element with [`RegmapParams::with_harmonics`], none
    /// without (so a map without it has none of it). The mirror of the learner's table,
    /// written by `h_tw`, read at {bank, HARM_INDEX's next value} (2P words used).
    h_ram: Vec<TableMirror>,
    /// HARM_CONTROL.LEARN (reset 1), HARM_INDEX, HARM_ENTRY's staged bytes.
    h_learn: Vec<DFF<Bit>>,
    h_index: Vec<DFF<Bits<32>>>,
    /// A HARM_ENTRY read has waited its clock (the mirror's read takes two).
    h_wait: Vec<DFF<Bit>>,
    h_stage: Vec<DFF<Bits<32>>>,
    /// The mirror's clear after reset: the address cleared next, and the clear running.
    /// (Yosys 0.23's `synth_intel` cannot give an M9K initial contents, so the RAM has
    /// none: the clear makes its words 0, as the learner's table is after reset.)
    h_clr: Vec<DFF<Bits<32>>>,
    h_clring: Vec<DFF<Bit>>,
    /// A load on its way to the learner (as `cq_*`: the path from the write registers to
    /// the learner's load request).
    h_ldq: Vec<DFF<Bit>>,
    h_lda: Vec<DFF<Bits<32>>>,
    h_ldd: Vec<DFF<Bits<32>>>,
    /// HARM_INDEX after this clock's write, the RAM's read address, the staged word with
    /// this clock's bytes, HARM_ENTRY (the RAM's word sign-extended) and HARM_CONTROL.
    h_inext: Vec<Signal<Local, Bits<32>>>,
    h_raddr: Vec<Signal<Local, Bits<32>>>,
    h_val: Vec<Signal<Local, Bits<32>>>,
    h_entry: Vec<Signal<Local, Bits<32>>>,
    h_ctl: Vec<Signal<Local, Bits<32>>>,
    /// Word indices of HARM_CONTROL, HARM_INDEX, HARM_ENTRY.
    h_wctl: Vec<Constant<Bits<32>>>,
    h_widx: Vec<Constant<Bits<32>>>,
    h_went: Vec<Constant<Bits<32>>>,
    /// P - 1 (an index's mask), P (bank 1's offset), 2P - 1 (a write address's mask).
    h_imask: Vec<Constant<Bits<32>>>,
    h_pone: Vec<Constant<Bits<32>>>,
    h_amask: Vec<Constant<Bits<32>>>,
    /// An entry's E bits, its sign bit and the fill above it.
    h_emask: Vec<Constant<Bits<32>>>,
    h_esign: Vec<Constant<Bits<32>>>,
    h_efill: Vec<Constant<Bits<32>>>,
    aw_full: DFF<Bit>,
    /// The held write address as a one-hot word select (as `ar_sel`). Timing: the write
    /// decode is an AND of registers, no compare after the AXI/BiSS choice.
    aw_sel: DFF<Bits<32>>,
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
    /// The BiSS byte port: the address as a one-hot word select and a byte lane, the read
    /// byte, the channel's POSITION / TURNS / VELOCITY snapshot, and a byte write waiting
    /// for a clock without an AXI write (unused without the port).
    bsel: DFF<Bits<32>>,
    blane: DFF<Bits<32>>,
    /// The selected word (loaded while AXI leaves the select free) and its lane; the byte
    /// is taken from it a clock later. Timing: the AND-OR ends in `b_word`, the lane select
    /// starts from registers.
    b_word: DFF<Bits<32>>,
    b_wlane: DFF<Bits<32>>,
    b_rdata: DFF<Bits<32>>,
    bpos: DFF<Bits<32>>,
    btur: DFF<Bits<32>>,
    bvel: DFF<Bits<32>>,
    bw_full: DFF<Bit>,
    bw_addr: DFF<Bits<32>>,
    /// The waiting byte write's word as a one-hot select.
    bw_sel: DFF<Bits<32>>,
    bw_data: DFF<Bits<8>>,
    /// The thresholds (RW; reset: the configured values).
    thr_los: DFF<Bits<32>>,
    thr_rel: DFF<Bits<32>>,
    thr_clip: DFF<Bits<32>>,
    /// The write of this clock (AXI's, else the BiSS byte's): word index, bits and the
    /// mask of the bytes written.
    wen: Signal<Local, Bit>,
    wbits: Signal<Local, Bits<32>>,
    wmsk: Signal<Local, Bits<32>>,
    /// The read select of this clock (AXI's while it holds an address, else the BiSS
    /// port's) and the words whose value depends on the port.
    rsel: Signal<Local, Bits<32>>,
    /// With the BiSS port: the read select a clock ahead, registered (the path from the
    /// select's mux through the read AND-OR to `rdata` and `b_word`): `rs_sel` is
    /// `ar_full ? ar_sel : bsel` of the clock it is in, `rs_axi` is `ar_full`.
    rs_sel: DFF<Bits<32>>,
    rs_axi: DFF<Bit>,
    /// An AXI read address is taken this clock.
    take: Signal<Local, Bit>,
    /// The held address is HARM_ENTRY's and has not waited: no response this clock (a
    /// `Vec` as the table's other logic, so that a map without one is unchanged).
    h_hold: Vec<Signal<Local, Bit>>,
    /// The one-hot word of `s_axi_araddr`, and of `bus_addr` (none from byte 256 up).
    asel_n: Signal<Local, Bits<32>>,
    bsel_n: Signal<Local, Bits<32>>,
    w5: Signal<Local, Bits<32>>,
    w6: Signal<Local, Bits<32>>,
    w7: Signal<Local, Bits<32>>,
    wsel: Signal<Local, Bits<32>>,
    /// The write of the clock before, registered (enable, one-hot word, bits, byte mask):
    /// it acts a clock after its handshake. Timing: the AXI/BiSS choice ends in these
    /// flip-flops, so each register's enable and data are one LUT of registers.
    wq_en: DFF<Bit>,
    wq_sel: DFF<Bits<32>>,
    wq_bits: DFF<Bits<32>>,
    wq_msk: DFF<Bits<32>>,
    /// A write to a correction code, registered on its way to the correction (the path from
    /// the write registers to the correction's code registers).
    cq_ld: DFF<Bits<8>>,
    cq_bits: DFF<Bits<32>>,
    cq_msk: DFF<Bits<32>>,
    /// Word index of OFFSET_SIN, the first code (their load bits are `wq_sel`'s from it).
    w_code0: Constant<Bits<32>>,
    /// The five codes' load bits.
    codes5: Constant<Bits<32>>,
    /// Word indices of the codes, for the read select.
    w_cbs: Constant<Bits<32>>,
    w_cbc: Constant<Bits<32>>,
    w_cgs: Constant<Bits<32>>,
    w_cgc: Constant<Bits<32>>,
    w_ck: Constant<Bits<32>>,
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
    /// Bytes 0..255 of the BiSS port's address (above: no register); a byte's mask.
    bhigh: Constant<Bits<32>>,
    bmask8: Constant<Bits<32>>,
    three: Constant<Bits<32>>,
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
    w_tlos: Constant<Bits<32>>,
    w_trel: Constant<Bits<32>>,
    w_tclip: Constant<Bits<32>>,
    /// The thresholds' reset values (the config's).
    t0_los: Constant<Bits<32>>,
    t0_rel: Constant<Bits<32>>,
    t0_clip: Constant<Bits<32>>,
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
        let (points, ew) = p.harmonics().unwrap_or((0, 0));
        let h = usize::from(p.harmonics().is_some());
        let hc = |v: u64| (0..h).map(|_| c32(v)).collect::<Vec<_>>();
        // The mirror starts as the learner's table does: zero (every word read, 2P, set,
        // so that no read is unknown in Verilog).
        let ram = TableMirror::default;
        Self {
            h_tw: Default::default(),
            h_tw_addr: Default::default(),
            h_tw_data: Default::default(),
            h_bank: Default::default(),
            h_ld_busy: Default::default(),
            h_update: Default::default(),
            h_ld: Default::default(),
            h_ld_addr: Default::default(),
            h_ld_data: Default::default(),
            h_ram: (0..h).map(|_| ram()).collect(),
            h_learn: (0..h).map(|_| DFF::default()).collect(),
            h_index: (0..h).map(|_| DFF::default()).collect(),
            h_wait: (0..h).map(|_| DFF::default()).collect(),
            h_stage: (0..h).map(|_| DFF::default()).collect(),
            h_ldq: (0..h).map(|_| DFF::default()).collect(),
            h_clr: (0..h).map(|_| DFF::default()).collect(),
            h_clring: (0..h).map(|_| DFF::default()).collect(),
            h_lda: (0..h).map(|_| DFF::default()).collect(),
            h_ldd: (0..h).map(|_| DFF::default()).collect(),
            h_inext: (0..h).map(|_| Default::default()).collect(),
            h_raddr: (0..h).map(|_| Default::default()).collect(),
            h_val: (0..h).map(|_| Default::default()).collect(),
            h_entry: (0..h).map(|_| Default::default()).collect(),
            h_ctl: (0..h).map(|_| Default::default()).collect(),
            h_wctl: hc(HARM_WORDS[0] as u64),
            h_widx: hc(HARM_WORDS[1] as u64),
            h_went: hc(HARM_WORDS[2] as u64),
            h_imask: hc(points.saturating_sub(1) as u64),
            h_pone: hc(points as u64),
            h_amask: hc((2 * points as u64).saturating_sub(1)),
            h_emask: hc(mask(ew)),
            h_esign: hc(if ew == 0 { 0 } else { 1u64 << (ew - 1) }),
            h_efill: hc(mask(32) & !mask(ew)),
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
            los_threshold: Default::default(),
            los_release: Default::default(),
            clip_threshold: Default::default(),
            thr_los: Default::default(),
            thr_rel: Default::default(),
            thr_clip: Default::default(),
            wmsk: Default::default(),
            bus_addr: Default::default(),
            bus_we: Default::default(),
            bus_wdata: Default::default(),
            bus_snap: Default::default(),
            bus_rdata: Default::default(),
            bus: (0..usize::from(p.biss_port()))
                .map(|_| Constant::new(true))
                .collect(),
            bsel: Default::default(),
            blane: Default::default(),
            b_word: Default::default(),
            b_wlane: Default::default(),
            b_rdata: Default::default(),
            bpos: Default::default(),
            btur: Default::default(),
            bvel: Default::default(),
            bw_full: Default::default(),
            bw_addr: Default::default(),
            bw_sel: Default::default(),
            bw_data: Default::default(),
            wen: Default::default(),
            wbits: Default::default(),
            rsel: Default::default(),
            rs_sel: Default::default(),
            rs_axi: Default::default(),
            take: Default::default(),
            h_hold: (0..h).map(|_| Default::default()).collect(),
            asel_n: Default::default(),
            bsel_n: Default::default(),
            w5: Default::default(),
            w6: Default::default(),
            w7: Default::default(),
            aw_full: Default::default(),
            aw_sel: Default::default(),
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
            wsel: Default::default(),
            wq_en: Default::default(),
            wq_sel: Default::default(),
            wq_bits: Default::default(),
            wq_msk: Default::default(),
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
            bhigh: c32(mask(32) & !mask(ADDR_BITS)),
            bmask8: c32(0xff),
            three: c32(3),
            selmask: c32(mask(p.words())),
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
            w_tlos: wc(THRESHOLD_WORDS[0]),
            w_trel: wc(THRESHOLD_WORDS[1]),
            w_tclip: wc(THRESHOLD_WORDS[2]),
            w_code0: wc(CODE_WORDS[0]),
            codes5: c32(0x1f),
            w_cbs: wc(CODE_WORDS[0]),
            w_cbc: wc(CODE_WORDS[1]),
            w_cgs: wc(CODE_WORDS[2]),
            w_cgc: wc(CODE_WORDS[3]),
            w_ck: wc(CODE_WORDS[4]),
            cor_off_s: Default::default(),
            cor_off_c: Default::default(),
            cor_gain_s: Default::default(),
            cor_gain_c: Default::default(),
            cor_phase: Default::default(),
            cor_ld: Default::default(),
            cor_bits: Default::default(),
            cor_msk: Default::default(),
            cq_ld: Default::default(),
            cq_bits: Default::default(),
            cq_msk: Default::default(),
            t0_los: c32(p.thresholds()[0] as u64),
            t0_rel: c32(p.thresholds()[1] as u64),
            t0_clip: c32(p.thresholds()[2] as u64),
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
            self, clk, aw_full, aw_sel, w_full, w_data, w_strb, bvalid, ar_full, ar_sel, rvalid,
            rdata, status, amp, sh_turns, sh_vel, pre, bsel, blane, b_word, b_wlane, b_rdata, bpos,
            btur, bvel, bw_full, bw_addr, bw_sel, bw_data, thr_los, thr_rel, thr_clip, wq_en,
            wq_sel, wq_bits, wq_msk, cq_ld, cq_bits, cq_msk, rs_sel, rs_axi
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
            self.aw_sel.d.next = (self.one.val()
                << ((self.s_axi_awaddr.val() & self.amask.val()) >> self.two.val()))
                & self.selmask.val();
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
        // The write of this clock: AXI's when both holders are full and no response is
        // pending, else a BiSS byte write waiting (taken the next clock AXI leaves free).
        self.wen.next = false;
        self.wsel.next = self.aw_sel.q.val();
        self.wbits.next = self.bits.val();
        self.wmsk.next = self.smask.val();
        if self.aw_full.q.val() & self.w_full.q.val() & !self.bvalid.q.val() {
            self.wen.next = true;
            self.aw_full.d.next = false;
            self.w_full.d.next = false;
            self.bvalid.d.next = true;
        } else if self.bw_full.q.val() {
            self.wen.next = true;
            self.wsel.next = self.bw_sel.q.val();
            self.wbits.next = bit_cast::<32, 8>(self.bw_data.q.val())
                << ((self.bw_addr.q.val() & self.three.val()) << self.three.val());
            self.wmsk.next = self.bmask8.val()
                << ((self.bw_addr.q.val() & self.three.val()) << self.three.val());
            self.bw_full.d.next = false;
        }
        for _i in 0..self.bus.len() {
            if self.bus_we.val() {
                self.bw_full.d.next = true;
                self.bw_addr.d.next = self.bus_addr.val();
                self.bw_sel.d.next = self.zero.val();
                if !(self.bus_addr.val() & self.bhigh.val()).any() {
                    self.bw_sel.d.next = (self.one.val()
                        << (self.bus_addr.val() >> self.two.val()))
                        & self.selmask.val();
                }
                self.bw_data.d.next = self.bus_wdata.val();
            }
        }
        self.wq_en.d.next = self.wen.val();
        self.wq_sel.d.next = self.wsel.val();
        self.wq_bits.d.next = self.wbits.val();
        self.wq_msk.d.next = self.wmsk.val();
        self.clear.next = self.zero.val();
        self.pre.d.next = false;
        self.cq_ld.d.next = bit_cast::<8, 32>(self.zero.val());
        self.cq_bits.d.next = self.zero.val();
        self.cq_msk.d.next = self.zero.val();
        if self.wq_en.q.val() {
            // The correction's codes live in the correction: a write goes there (its bits
            // and mask pass for every write; the load bits select a code).
            self.cq_ld.d.next =
                bit_cast::<8, 32>((self.wq_sel.q.val() >> self.w_code0.val()) & self.codes5.val());
            self.cq_bits.d.next = self.wq_bits.q.val();
            self.cq_msk.d.next = self.wq_msk.q.val();
            if (self.wq_sel.q.val() & (self.one.val() << self.w_status.val())).any() {
                self.clear.next = self.wq_bits.q.val();
            }
            if (self.wq_sel.q.val() & (self.one.val() << self.w_preset.val())).any() {
                self.pre.d.next = (self.wq_bits.q.val() & self.one.val()).any();
            }
            if (self.wq_sel.q.val() & (self.one.val() << self.w_tlos.val())).any() {
                self.thr_los.d.next =
                    (self.thr_los.q.val() & !self.wq_msk.q.val()) | self.wq_bits.q.val();
            }
            if (self.wq_sel.q.val() & (self.one.val() << self.w_trel.val())).any() {
                self.thr_rel.d.next =
                    (self.thr_rel.q.val() & !self.wq_msk.q.val()) | self.wq_bits.q.val();
            }
            if (self.wq_sel.q.val() & (self.one.val() << self.w_tclip.val())).any() {
                self.thr_clip.d.next =
                    (self.thr_clip.q.val() & !self.wq_msk.q.val()) | self.wq_bits.q.val();
            }
        }
        // The learned table's registers: LEARN, the index, HARM_ENTRY's bytes staged; a
        // write that takes byte 3 sends the whole staged word to the learner.
        for i in 0..self.h_ram.len() {
            self.h_learn[i].clock.next = self.clk.val();
            self.h_index[i].clock.next = self.clk.val();
            self.h_wait[i].clock.next = self.clk.val();
            self.h_stage[i].clock.next = self.clk.val();
            self.h_ldq[i].clock.next = self.clk.val();
            self.h_lda[i].clock.next = self.clk.val();
            self.h_ldd[i].clock.next = self.clk.val();
            self.h_clr[i].clock.next = self.clk.val();
            self.h_clring[i].clock.next = self.clk.val();
            // The clear: one word a clock from 0 to 2P - 1, pausing while the learner writes.
            self.h_clr[i].d.next = self.h_clr[i].q.val();
            self.h_clring[i].d.next = self.h_clring[i].q.val();
            if self.h_clring[i].q.val() & !self.h_tw.val() {
                self.h_clr[i].d.next = self.h_clr[i].q.val() + self.one.val();
                if self.h_clr[i].q.val() == self.h_amask[i].val() {
                    self.h_clring[i].d.next = false;
                }
            }
            self.h_learn[i].d.next = self.h_learn[i].q.val();
            self.h_stage[i].d.next = self.h_stage[i].q.val();
            self.h_ldq[i].d.next = false;
            self.h_lda[i].d.next = self.h_lda[i].q.val();
            self.h_ldd[i].d.next = self.h_ldd[i].q.val();
            self.h_inext[i].next = self.h_index[i].q.val();
            self.h_val[i].next =
                (self.h_stage[i].q.val() & !self.wq_msk.q.val()) | self.wq_bits.q.val();
            if self.wq_en.q.val() {
                if (self.wq_sel.q.val() & (self.one.val() << self.h_wctl[i].val())).any()
                    & (self.wq_msk.q.val() & self.one.val()).any()
                {
                    self.h_learn[i].d.next = (self.wq_bits.q.val() & self.one.val()).any();
                }
                if (self.wq_sel.q.val() & (self.one.val() << self.h_widx[i].val())).any() {
                    self.h_inext[i].next = ((self.h_index[i].q.val() & !self.wq_msk.q.val())
                        | self.wq_bits.q.val())
                        & self.h_imask[i].val();
                }
                if (self.wq_sel.q.val() & (self.one.val() << self.h_went[i].val())).any() {
                    self.h_stage[i].d.next = self.h_val[i].val();
                    if (self.wq_msk.q.val() & self.s3.val()).any() {
                        self.h_ldq[i].d.next = true;
                        self.h_lda[i].d.next = self.h_index[i].q.val();
                        self.h_ldd[i].d.next = self.h_val[i].val() & self.h_emask[i].val();
                    }
                }
            }
        }
        // Faults: set wins over a clear in the same clock.
        self.status.d.next = (self.status.q.val() & !self.clear.val() & self.fmask.val())
            | (self.flags.val() & self.fmask.val());
        if self.amp_valid.val() {
            self.amp.d.next = self.amplitude.val();
        }
        // Read: the address held a clock, then the data.
        self.take.next = self.s_axi_arvalid.val() & !self.ar_full.q.val() & !self.rvalid.q.val();
        self.asel_n.next = (self.one.val()
            << ((self.s_axi_araddr.val() & self.amask.val()) >> self.two.val()))
            & self.selmask.val();
        if self.take.val() {
            self.ar_full.d.next = true;
            self.ar_sel.d.next = self.asel_n.val();
        }
        if self.rvalid.q.val() & self.s_axi_rready.val() {
            self.rvalid.d.next = false;
        }
        // HARM_ENTRY answers a clock later than the other words: the mirror RAM's word is
        // two clocks behind its address, and the address follows HARM_INDEX's write.
        for i in 0..self.h_ram.len() {
            self.h_hold[i].next = self.ar_full.q.val()
                & (self.ar_sel.q.val() & (self.one.val() << self.h_went[i].val())).any()
                & !self.h_wait[i].q.val();
            self.h_wait[i].d.next = self.h_hold[i].val();
        }
        // The read select: AXI's held address, else (with the BiSS port) the port's, whose
        // POSITION, TURNS and VELOCITY are its own snapshot.
        self.rsel.next = self.ar_sel.q.val();
        self.w5.next = self.pos.val();
        self.w6.next = self.sh_turns.q.val();
        self.w7.next = self.sh_vel.q.val();
        self.bsel_n.next = self.zero.val();
        if !(self.bus_addr.val() & self.bhigh.val()).any() {
            self.bsel_n.next =
                (self.one.val() << (self.bus_addr.val() >> self.two.val())) & self.selmask.val();
        }
        for _i in 0..self.bus.len() {
            // Next clock's select: the address AXI takes now, else the port's.
            self.rs_axi.d.next = self.take.val();
            self.rs_sel.d.next = self.bsel_n.val();
            if self.take.val() {
                self.rs_sel.d.next = self.asel_n.val();
            }
            // A HARM_ENTRY read that waits keeps AXI's select a clock more.
            for i in 0..self.h_ram.len() {
                if self.h_hold[i].val() {
                    self.rs_axi.d.next = true;
                    self.rs_sel.d.next = self.ar_sel.q.val();
                }
            }
            self.rsel.next = self.rs_sel.q.val();
            if !self.rs_axi.q.val() {
                self.w5.next = self.bpos.q.val();
                self.w6.next = self.btur.q.val();
                self.w7.next = self.bvel.q.val();
            }
        }
        // The learned table's words: HARM_CONTROL, and HARM_ENTRY from the mirror RAM's
        // read registers (the entry at the RAM address of two clocks before).
        for i in 0..self.h_ram.len() {
            self.h_ctl[i].next = self.zero.val();
            if self.h_learn[i].q.val() {
                self.h_ctl[i].next = self.one.val();
            }
            if self.h_ld_busy.val() {
                self.h_ctl[i].next = self.h_ctl[i].val() | self.two.val();
            }
            self.h_entry[i].next = self.h_ram[i].rdata.val() & self.h_emask[i].val();
            if (self.h_ram[i].rdata.val() & self.h_esign[i].val()).any() {
                self.h_entry[i].next = self.h_entry[i].val() | self.h_efill[i].val();
            }
        }
        // The read data: an AND-OR of the words by the one-hot select.
        self.rmux.next = self.zero.val();
        if (self.rsel.val() & (self.one.val() << self.w_id.val())).any() {
            self.rmux.next = self.rmux.val() | self.id.val();
        }
        if (self.rsel.val() & (self.one.val() << self.w_version.val())).any() {
            self.rmux.next = self.rmux.val() | self.version.val();
        }
        if (self.rsel.val() & (self.one.val() << self.w_status.val())).any() {
            self.rmux.next = self.rmux.val() | self.status.q.val();
        }
        if (self.rsel.val() & (self.one.val() << self.w_flags.val())).any() {
            self.rmux.next = self.rmux.val() | self.live.val();
        }
        if (self.rsel.val() & (self.one.val() << self.w_amp.val())).any() {
            self.rmux.next = self.rmux.val() | self.amp.q.val();
        }
        if (self.rsel.val() & (self.one.val() << self.w_position.val())).any() {
            self.rmux.next = self.rmux.val() | self.w5.val();
        }
        if (self.rsel.val() & (self.one.val() << self.w_turns.val())).any() {
            self.rmux.next = self.rmux.val() | self.w6.val();
        }
        if (self.rsel.val() & (self.one.val() << self.w_vel.val())).any() {
            self.rmux.next = self.rmux.val() | self.w7.val();
        }
        if (self.rsel.val() & (self.one.val() << self.w_ipos.val())).any() {
            self.rmux.next = self.rmux.val() | self.ipos.val();
        }
        if (self.rsel.val() & (self.one.val() << self.w_itur.val())).any() {
            self.rmux.next = self.rmux.val() | self.itur.val();
        }
        if (self.rsel.val() & (self.one.val() << self.w_cpos.val())).any() {
            self.rmux.next = self.rmux.val() | self.cpos.val();
        }
        if (self.rsel.val() & (self.one.val() << self.w_ctur.val())).any() {
            self.rmux.next = self.rmux.val() | self.ctur.val();
        }
        if (self.rsel.val() & (self.one.val() << self.w_cvel.val())).any() {
            self.rmux.next = self.rmux.val() | self.cvel.val();
        }
        if (self.rsel.val() & (self.one.val() << self.w_cage.val())).any() {
            self.rmux.next = self.rmux.val() | self.cap_age.val();
        }
        if (self.rsel.val() & (self.one.val() << self.w_tlos.val())).any() {
            self.rmux.next = self.rmux.val() | self.thr_los.q.val();
        }
        if (self.rsel.val() & (self.one.val() << self.w_trel.val())).any() {
            self.rmux.next = self.rmux.val() | self.thr_rel.q.val();
        }
        if (self.rsel.val() & (self.one.val() << self.w_tclip.val())).any() {
            self.rmux.next = self.rmux.val() | self.thr_clip.q.val();
        }
        if (self.rsel.val() & (self.one.val() << self.w_cbs.val())).any() {
            self.rmux.next = self.rmux.val() | self.cor_off_s.val();
        }
        if (self.rsel.val() & (self.one.val() << self.w_cbc.val())).any() {
            self.rmux.next = self.rmux.val() | self.cor_off_c.val();
        }
        if (self.rsel.val() & (self.one.val() << self.w_cgs.val())).any() {
            self.rmux.next = self.rmux.val() | self.cor_gain_s.val();
        }
        if (self.rsel.val() & (self.one.val() << self.w_cgc.val())).any() {
            self.rmux.next = self.rmux.val() | self.cor_gain_c.val();
        }
        if (self.rsel.val() & (self.one.val() << self.w_ck.val())).any() {
            self.rmux.next = self.rmux.val() | self.cor_phase.val();
        }
        for i in 0..self.h_ram.len() {
            if (self.rsel.val() & (self.one.val() << self.h_wctl[i].val())).any() {
                self.rmux.next = self.rmux.val() | self.h_ctl[i].val();
            }
            if (self.rsel.val() & (self.one.val() << self.h_widx[i].val())).any() {
                self.rmux.next = self.rmux.val() | self.h_index[i].q.val();
            }
            if (self.rsel.val() & (self.one.val() << self.h_went[i].val())).any() {
                self.rmux.next = self.rmux.val() | self.h_entry[i].val();
            }
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
        // HARM_ENTRY's wait: the address stays held, no data yet.
        for i in 0..self.h_ram.len() {
            if self.h_hold[i].val() {
                self.rdata.d.next = self.rdata.q.val();
                self.ar_full.d.next = true;
                self.rvalid.d.next = false;
            }
        }
        // The BiSS byte port: the address registered as a word select and a lane (bytes
        // 256 and above select nothing), the byte read while AXI leaves the select free,
        // the snapshot when a read begins at POSITION's byte 0.
        self.bus_rdata.next = bit_cast::<8, 32>(self.zero.val());
        for _i in 0..self.bus.len() {
            self.bsel.d.next = self.bsel_n.val();
            self.blane.d.next = self.bus_addr.val() & self.three.val();
            if !self.ar_full.q.val() {
                self.b_word.d.next = self.rmux.val();
                self.b_wlane.d.next = self.blane.q.val();
            }
            self.b_rdata.d.next = (self.b_word.q.val()
                >> (self.b_wlane.q.val() << self.three.val()))
                & self.bmask8.val();
            if self.bus_snap.val()
                & (self.bsel.q.val() & (self.one.val() << self.w_position.val())).any()
                & (self.blane.q.val() == self.zero.val())
            {
                self.bpos.d.next = self.pos.val();
                self.btur.d.next = self.tur.val();
                self.bvel.d.next = self.vel.val();
            }
            self.bus_rdata.next = bit_cast::<8, 32>(self.b_rdata.q.val());
        }
        if self.rst.val() {
            self.aw_full.d.next = false;
            self.w_full.d.next = false;
            self.bvalid.d.next = false;
            self.ar_full.d.next = false;
            self.rvalid.d.next = false;
            self.aw_sel.d.next = 0.into();
            self.w_data.d.next = 0.into();
            self.w_strb.d.next = 0.into();
            self.ar_sel.d.next = 0.into();
            self.rdata.d.next = 0.into();
            self.status.d.next = 0.into();
            self.amp.d.next = 0.into();
            self.sh_turns.d.next = 0.into();
            self.sh_vel.d.next = 0.into();
            self.pre.d.next = false;
            self.bsel.d.next = 0.into();
            self.blane.d.next = 0.into();
            self.b_word.d.next = 0.into();
            self.b_wlane.d.next = 0.into();
            self.b_rdata.d.next = 0.into();
            self.bpos.d.next = 0.into();
            self.btur.d.next = 0.into();
            self.bvel.d.next = 0.into();
            self.bw_full.d.next = false;
            self.bw_addr.d.next = 0.into();
            self.bw_sel.d.next = 0.into();
            self.bw_data.d.next = 0.into();
            self.wq_en.d.next = false;
            self.cq_ld.d.next = 0.into();
            self.rs_sel.d.next = 0.into();
            self.rs_axi.d.next = false;
            self.cq_bits.d.next = 0.into();
            self.cq_msk.d.next = 0.into();
            self.thr_los.d.next = self.t0_los.val();
            self.thr_rel.d.next = self.t0_rel.val();
            self.thr_clip.d.next = self.t0_clip.val();
            for i in 0..self.h_ram.len() {
                self.h_learn[i].d.next = true;
                self.h_index[i].d.next = self.zero.val();
                self.h_wait[i].d.next = false;
                self.h_stage[i].d.next = self.zero.val();
                self.h_ldq[i].d.next = false;
                self.h_lda[i].d.next = self.zero.val();
                self.h_ldd[i].d.next = self.zero.val();
                self.h_inext[i].next = self.zero.val();
                self.h_clr[i].d.next = self.zero.val();
                self.h_clring[i].d.next = true;
            }
        }
        // The mirror RAM: written by the learner, read at {bank, index} with the index's
        // next value, so that its read register holds the entry of the index now in force.
        self.h_update.next = false;
        self.h_ld.next = false;
        self.h_ld_addr.next = self.zero.val();
        self.h_ld_data.next = self.zero.val();
        for i in 0..self.h_ram.len() {
            self.h_index[i].d.next = self.h_inext[i].val();
            self.h_raddr[i].next = self.h_inext[i].val();
            if self.h_bank.val() {
                self.h_raddr[i].next = self.h_inext[i].val() | self.h_pone[i].val();
            }
            self.h_ram[i].clk.next = self.clk.val();
            self.h_ram[i].raddr.next = self.h_raddr[i].val();
            self.h_ram[i].we.next = self.h_tw.val() | self.h_clring[i].q.val();
            self.h_ram[i].waddr.next = self.h_clr[i].q.val();
            self.h_ram[i].wdata.next = self.zero.val();
            if self.h_tw.val() {
                self.h_ram[i].waddr.next = self.h_tw_addr.val() & self.h_amask[i].val();
                self.h_ram[i].wdata.next = self.h_tw_data.val();
            }
            self.h_update.next = self.h_learn[i].q.val();
            self.h_ld.next = self.h_ldq[i].q.val();
            self.h_ld_addr.next = self.h_lda[i].q.val();
            self.h_ld_data.next = self.h_ldd[i].q.val();
        }
        self.los_threshold.next = self.thr_los.q.val();
        self.los_release.next = self.thr_rel.q.val();
        self.clip_threshold.next = self.thr_clip.q.val();
        self.s_axi_awready.next = !self.aw_full.q.val();
        self.s_axi_wready.next = !self.w_full.q.val();
        self.s_axi_bresp.next = self.zero.val();
        self.s_axi_bvalid.next = self.bvalid.q.val();
        self.s_axi_arready.next = !self.ar_full.q.val() & !self.rvalid.q.val();
        self.s_axi_rdata.next = self.rdata.q.val();
        self.s_axi_rresp.next = self.zero.val();
        self.s_axi_rvalid.next = self.rvalid.q.val();
        self.preset.next = self.pre.q.val();
        self.cor_ld.next = self.cq_ld.q.val();
        self.cor_bits.next = self.cq_bits.q.val();
        self.cor_msk.next = self.cq_msk.q.val();
    }
}

/// Bits of a mirror word: the entries' E <= 24 ([`super::RegmapParams::with_harmonics`]).
pub const MIRROR_WORD_BITS: usize = 24;

/// The mirror of the learner's table: a RAM of 2^[`RAM_ADDR_BITS`] words of
/// [`MIRROR_WORD_BITS`] bits, without initial contents, with 32-bit ports (two clocks of
/// read latency, [`PipedLutRam`]: `rdata` is the word at the `raddr` of two clocks before,
/// before the first clock's write; 256 words are too many to read in one clock of the
/// timing rule).
#[derive(LogicBlock, Default)]
pub struct TableMirror {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Read address (its low [`RAM_ADDR_BITS`] bits).
    pub raddr: Signal<In, Bits<32>>,
    /// The word at the read address of two clocks before, zero-extended.
    pub rdata: Signal<Out, Bits<32>>,
    /// Write `wdata` at `waddr` this clock.
    pub we: Signal<In, Bit>,
    /// Write address (its low [`RAM_ADDR_BITS`] bits).
    pub waddr: Signal<In, Bits<32>>,
    /// Write data (its low [`MIRROR_WORD_BITS`] bits).
    pub wdata: Signal<In, Bits<32>>,
    ram: PipedLutRam<Bits<MIRROR_WORD_BITS>, RAM_ADDR_BITS>,
}

impl Logic for TableMirror {
    #[hdl_gen]
    fn update(&mut self) {
        self.ram.clock.next = self.clk.val();
        self.ram.read_address.next = bit_cast::<RAM_ADDR_BITS, 32>(self.raddr.val());
        self.ram.write_enable.next = self.we.val();
        self.ram.write_address.next = bit_cast::<RAM_ADDR_BITS, 32>(self.waddr.val());
        self.ram.write_data.next = bit_cast::<MIRROR_WORD_BITS, 32>(self.wdata.val());
        self.rdata.next = bit_cast::<32, MIRROR_WORD_BITS>(self.ram.read_data.val());
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
            Port::new("cor_off_s", 32),
            Port::new("cor_off_c", 32),
            Port::new("cor_gain_s", 32),
            Port::new("cor_gain_c", 32),
            Port::new("cor_phase", 32),
        ]
        .into_iter()
        .chain(self.bus.iter().flat_map(|_| {
            [
                Port::new("bus_addr", 32),
                Port::new("bus_we", 1),
                Port::new("bus_wdata", 8),
                Port::new("bus_snap", 1),
            ]
        }))
        .chain(self.h_ram.iter().flat_map(|_| {
            [
                Port::new("h_tw", 1),
                Port::new("h_tw_addr", 32),
                Port::new("h_tw_data", 32),
                Port::new("h_bank", 1),
                Port::new("h_ld_busy", 1),
            ]
        }))
        .collect()
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
            Port::new("los_threshold", 32),
            Port::new("los_release", 32),
            Port::new("clip_threshold", 32),
            Port::new("cor_ld", 8),
            Port::new("cor_bits", 32),
            Port::new("cor_msk", 32),
        ]
        .into_iter()
        .chain(self.bus.iter().map(|_| Port::new("bus_rdata", 8)))
        .chain(self.h_ram.iter().flat_map(|_| {
            [
                Port::new("h_update", 1),
                Port::new("h_ld", 1),
                Port::new("h_ld_addr", 32),
                Port::new("h_ld_data", 32),
            ]
        }))
        .collect()
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
        self.cor_off_s.next = b32(r[24]);
        self.cor_off_c.next = b32(r[25]);
        self.cor_gain_s.next = b32(r[26]);
        self.cor_gain_c.next = b32(r[27]);
        self.cor_phase.next = b32(r[28]);
        let mut k = 29;
        if !self.bus.is_empty() {
            self.bus_addr.next = b32(r[k]);
            self.bus_we.next = r[k + 1] != 0;
            self.bus_wdata.next = Bits::<8>::from(r[k + 2] & 0xff);
            self.bus_snap.next = r[k + 3] != 0;
            k += 4;
        }
        if !self.h_ram.is_empty() {
            self.h_tw.next = r[k] != 0;
            self.h_tw_addr.next = b32(r[k + 1]);
            self.h_tw_data.next = b32(r[k + 2]);
            self.h_bank.next = r[k + 3] != 0;
            self.h_ld_busy.next = r[k + 4] != 0;
        }
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
            self.los_threshold.val().to_u64(),
            self.los_release.val().to_u64(),
            self.clip_threshold.val().to_u64(),
            self.cor_ld.val().to_u64(),
            self.cor_bits.val().to_u64(),
            self.cor_msk.val().to_u64(),
        ]
        .into_iter()
        .chain(self.bus.iter().map(|_| self.bus_rdata.val().to_u64()))
        .chain(self.h_ram.iter().flat_map(|_| {
            [
                self.h_update.val() as u64,
                self.h_ld.val() as u64,
                self.h_ld_addr.val().to_u64(),
                self.h_ld_data.val().to_u64(),
            ]
        }))
        .collect()
    }
}

impl crate::cosim::step::Clocked for RegisterMap {
    fn set_clock(&mut self, high: bool) {
        self.clk.next = Clock::from(high);
    }
}
