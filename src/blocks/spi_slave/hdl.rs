//! rust-hdl description of the SPI slave.
use crate::blocks::serial::hdl::{LineSync, PosWord};
use crate::blocks::spi_slave::SpiSlaveParams;
use crate::blocks::{c32, mask};
use rust_hdl::prelude::*;

fn c64(v: u64) -> Constant<Bits<64>> {
    Constant::new(Bits::<64>::from(v))
}

/// Where the SPI slave is in its word.
#[derive(Copy, Clone, PartialEq, Eq, Debug, LogicState)]
pub enum SpiState {
    /// Not selected.
    Off,
    /// Data bits on MISO.
    Data,
    /// Error flag on MISO.
    Err,
    /// Warning flag on MISO.
    Warn,
    /// Zeros after the word.
    Tail,
}

/// SPI slave (modes 0 and 3) that sends the position word.
#[derive(LogicBlock)]
pub struct SpiSlave {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high.
    pub rst: Signal<In, Bit>,
    /// SPI clock (asynchronous).
    pub sck: Signal<In, Bit>,
    /// Chip select, active low (asynchronous).
    pub cs_n: Signal<In, Bit>,
    /// Single-turn position (low `position_bits`).
    pub pos: Signal<In, Bits<32>>,
    /// Turn count (low `multiturn_bits`).
    pub turns: Signal<In, Bits<32>>,
    /// `pos` and `turns` are new.
    pub pos_valid: Signal<In, Bit>,
    /// Decoder error.
    pub error: Signal<In, Bit>,
    /// Decoder warning.
    pub warning: Signal<In, Bit>,
    /// Serial data out (registered; 0 while deselected).
    pub miso: Signal<Out, Bit>,
    /// MISO output enable (registered; high while selected).
    pub miso_oe: Signal<Out, Bit>,
    /// The velocity word sent after the data when `velocity_bits` > 0 (latched with the
    /// position), two's complement in the low `velocity_bits`; unused otherwise. A plain
    /// port, not a `Vec` like BiSS's: the top reaches it through its own `Vec` of slaves, and
    /// rust-hdl's Verilog resolves only one index per name.
    pub vel: Signal<In, Bits<64>>,
    /// The velocity shift register: its MSB enters `sh` at every data shift.
    vsh: Vec<DFF<Bits<64>>>,
    /// Mask of the velocity bits.
    vmask: Vec<Constant<Bits<64>>>,
    /// Bit `velocity_bits` - 1 of `vsh`.
    vmsb: Vec<Constant<Bits<64>>>,
    sck_sync: LineSync,
    cs_sync: LineSync,
    posw: PosWord,
    state: DFF<SpiState>,
    miso_reg: DFF<Bit>,
    oe_reg: DFF<Bit>,
    armed: DFF<Bit>,
    sh: DFF<Bits<32>>,
    cnt: DFF<Bits<32>>,
    errl: DFF<Bit>,
    warnl: DFF<Bit>,
    dbit: Signal<Local, Bit>,
    step: Signal<Local, Bit>,
    /// Mask of the N data bits.
    nmask: Constant<Bits<32>>,
    /// Bit N-1.
    msb: Constant<Bits<32>>,
    /// N.
    nbits: Constant<Bits<32>>,
    /// Mask of the bit counter.
    cmask: Constant<Bits<32>>,
    /// One.
    one: Constant<Bits<32>>,
}

impl SpiSlave {
    /// Slave for validated parameters.
    pub fn new(p: &SpiSlaveParams) -> crate::error::Result<Self> {
        p.validate()?;
        let n = p.data_bits();
        let v = p.velocity_bits;
        let nv = (v > 0) as usize;
        Ok(Self {
            vel: Default::default(),
            vsh: (0..nv).map(|_| Default::default()).collect(),
            vmask: (0..nv).map(|_| c64(mask(v))).collect(),
            vmsb: (0..nv).map(|_| c64(1 << (v.max(1) - 1))).collect(),
            clk: Default::default(),
            rst: Default::default(),
            sck: Default::default(),
            cs_n: Default::default(),
            pos: Default::default(),
            turns: Default::default(),
            pos_valid: Default::default(),
            error: Default::default(),
            warning: Default::default(),
            miso: Default::default(),
            miso_oe: Default::default(),
            sck_sync: LineSync::new(p.glitch_filter),
            cs_sync: LineSync::new(p.glitch_filter),
            posw: PosWord::new(p.position_bits, p.multiturn_bits, p.gray),
            state: Default::default(),
            miso_reg: Default::default(),
            oe_reg: Default::default(),
            armed: Default::default(),
            sh: Default::default(),
            cnt: Default::default(),
            errl: Default::default(),
            warnl: Default::default(),
            dbit: Default::default(),
            step: Default::default(),
            nmask: c32(mask(n)),
            msb: c32(1 << (n - 1)),
            nbits: c32((n + v) as u64),
            cmask: c32(mask(7)),
            one: c32(1),
        })
    }
}

impl Logic for SpiSlave {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clk, state, miso_reg, oe_reg, armed, sh, cnt, errl, warnl);
        self.sck_sync.clk.next = self.clk.val();
        self.sck_sync.rst.next = self.rst.val();
        self.sck_sync.pin.next = self.sck.val();
        self.cs_sync.clk.next = self.clk.val();
        self.cs_sync.rst.next = self.rst.val();
        self.cs_sync.pin.next = self.cs_n.val();
        self.posw.clk.next = self.clk.val();
        self.posw.rst.next = self.rst.val();
        self.posw.pos.next = self.pos.val();
        self.posw.turns.next = self.turns.val();
        self.posw.pos_valid.next = self.pos_valid.val();
        self.posw.error.next = self.error.val();
        self.posw.warning.next = self.warning.val();
        self.posw.take.next = false;
        self.dbit.next = (self.sh.q.val() & self.msb.val()).any();
        for i in 0..self.vsh.len() {
            self.vsh[i].clock.next = self.clk.val();
            self.vsh[i].d.next = self.vsh[i].q.val();
        }
        // A falling SCK edge after a rising one moves to the next bit.
        self.step.next = self.sck_sync.fall.val() & self.armed.q.val();
        if self.sck_sync.rise.val() {
            self.armed.d.next = true;
        }
        if self.step.val() {
            self.armed.d.next = false;
        }
        match self.state.q.val() {
            SpiState::Off => {}
            SpiState::Data => {
                if self.step.val() {
                    if self.cnt.q.val() == self.nbits.val() {
                        self.miso_reg.d.next = self.errl.q.val();
                        self.state.d.next = SpiState::Err;
                    } else {
                        self.miso_reg.d.next = self.dbit.val();
                        self.sh.d.next = (self.sh.q.val() << self.one.val()) & self.nmask.val();
                        for i in 0..self.vsh.len() {
                            self.vsh[i].d.next =
                                (self.vsh[i].q.val() << self.one.val()) & self.vmask[i].val();
                            if (self.vsh[i].q.val() & self.vmsb[i].val()).any() {
                                self.sh.d.next = ((self.sh.q.val() << self.one.val())
                                    & self.nmask.val())
                                    | self.one.val();
                            }
                        }
                        self.cnt.d.next = (self.cnt.q.val() + self.one.val()) & self.cmask.val();
                    }
                }
            }
            SpiState::Err => {
                if self.step.val() {
                    self.miso_reg.d.next = self.warnl.q.val();
                    self.state.d.next = SpiState::Warn;
                }
            }
            SpiState::Warn => {
                if self.step.val() {
                    self.miso_reg.d.next = false;
                    self.state.d.next = SpiState::Tail;
                }
            }
            SpiState::Tail => {}
        }
        // Chip select: falling edge latches the word and shows its MSB; rising edge ends it.
        if self.cs_sync.fall.val() {
            self.posw.take.next = true;
            self.miso_reg.d.next = (self.posw.word.val() & self.msb.val()).any();
            self.sh.d.next = (self.posw.word.val() << self.one.val()) & self.nmask.val();
            // The velocity word behind the data word: its MSB enters sh with this shift.
            for i in 0..self.vsh.len() {
                self.vsh[i].d.next = ((self.vel.val() & self.vmask[i].val()) << self.one.val())
                    & self.vmask[i].val();
                if (self.vel.val() & self.vmsb[i].val()).any() {
                    self.sh.d.next = ((self.posw.word.val() << self.one.val()) & self.nmask.val())
                        | self.one.val();
                }
            }
            self.errl.d.next = self.posw.err.val();
            self.warnl.d.next = self.posw.warn.val();
            self.cnt.d.next = self.one.val();
            self.armed.d.next = false;
            self.oe_reg.d.next = true;
            self.state.d.next = SpiState::Data;
        }
        if self.cs_sync.rise.val() | self.rst.val() {
            self.miso_reg.d.next = false;
            self.oe_reg.d.next = false;
            self.armed.d.next = false;
            self.state.d.next = SpiState::Off;
        }
        self.miso.next = self.miso_reg.q.val();
        self.miso_oe.next = self.oe_reg.q.val();
    }
}

crate::cosim::cosim_block!(SpiSlave {
    inputs: [rst: 1, sck: 1, cs_n: 1, pos: 32, turns: 32, pos_valid: 1, error: 1, warning: 1],
    outputs: [miso: 1, miso_oe: 1],
});
