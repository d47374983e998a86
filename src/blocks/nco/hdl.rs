//! rust-hdl description of the NCO (see the module docs of `nco`).
use super::NcoParams;
use crate::blocks::{c32, mask};
use crate::cosim::Port;
use rust_hdl::prelude::*;

/// The first octant of the carrier: one address j (T-1 bits) reads two words at once,
/// `data_s = tab[j]` and `data_c = tab[2^T - 1 - j]` (the sin and cos of the angle of
/// index j), combinationally. With the octant fold in [`Nco`] this is the whole quarter
/// table in 2^(T-1) two-word entries: half the entries of two quarter-table ports.
///
/// Modelled on rust-hdl's `ROM` widget (a custom Verilog `always @(*) case` body, the
/// tables kept in `_`-prefixed fields that the derive skips), but the address width and the
/// contents come from the parameters at run time. Only the low T-1 address bits are used.
/// The read is combinational and its data passes through the fold and sign logic before
/// the output registers, so Yosys builds it from logic (LUTs). A synchronous-read table
/// would become a block RAM, which Yosys 0.23 maps on xc3sa only with port-resizing
/// warnings and fails to map on cycloneive (M9K `INIT` defparam error).
#[derive(LogicBlock)]
pub struct SineRom {
    /// Read address j (low T-1 bits).
    pub addr: Signal<In, Bits<16>>,
    /// tab[j]: the sin word of index j.
    pub data_s: Signal<Out, Bits<16>>,
    /// tab[2^T - 1 - j]: the cos word of index j.
    pub data_c: Signal<Out, Bits<16>>,
    _sin: Vec<u64>,
    _cos: Vec<u64>,
    _abits: u32,
}

impl SineRom {
    /// ROM of the first octant of the quarter table `table` (2^T entries, each < 2^16).
    pub fn new(table: &[u64]) -> Self {
        let n = table.len();
        let half = n / 2;
        Self {
            addr: Default::default(),
            data_s: Default::default(),
            data_c: Default::default(),
            _sin: table[..half].to_vec(),
            _cos: (0..half).map(|j| table[n - 1 - j]).collect(),
            _abits: half.trailing_zeros(),
        }
    }
    fn read(t: &[u64], abits: u32, addr: Bits<16>) -> Bits<16> {
        let a = (addr.to_u64() & mask(abits)) as usize;
        Bits::<16>::from(t.get(a).copied().unwrap_or(0) & 0xffff)
    }
}

impl Logic for SineRom {
    fn update(&mut self) {
        self.data_s.next = Self::read(&self._sin, self._abits, self.addr.val());
        self.data_c.next = Self::read(&self._cos, self._abits, self.addr.val());
    }
    fn connect(&mut self) {
        self.data_s.connect();
        self.data_c.connect();
    }
    fn hdl(&self) -> Verilog {
        let ab = self._abits;
        let arms = (0..self._sin.len())
            .map(|j| {
                format!(
                    "        {ab}'d{j}: begin data_s = 16'h{:04x}; data_c = 16'h{:04x}; end",
                    self._sin[j] & 0xffff,
                    self._cos.get(j).copied().unwrap_or(0) & 0xffff
                )
            })
            .collect::<Vec<_>>()
            .join("\n");
        Verilog::Custom(format!(
            "always @(*) begin\n    case (addr[{top}:0])\n{arms}\n        \
             default: begin data_s = 16'h0000; data_c = 16'h0000; end\n    endcase\nend",
            top = ab - 1
        ))
    }
}

/// Phase accumulator, quarter-wave table and sign logic: A sin / A cos once per tick.
#[derive(LogicBlock)]
pub struct Nco {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high.
    pub rst: Signal<In, Bit>,
    /// Advance strobe: one NCO update per clock with tick high.
    pub tick: Signal<In, Bit>,
    /// High for one clock, in the cycle after each tick (registered with the words).
    pub out_valid: Signal<Out, Bit>,
    /// A sin(phi), W-bit two's complement in the low bits.
    pub out_sin: Signal<Out, Bits<32>>,
    /// A cos(phi), W-bit two's complement in the low bits.
    pub out_cos: Signal<Out, Bits<32>>,
    /// P-bit phase word the outputs belong to.
    pub out_phase: Signal<Out, Bits<32>>,
    rom: SineRom,
    phase: DFF<Bits<32>>,
    o_valid: DFF<Bit>,
    o_sin: DFF<Bits<32>>,
    o_cos: DFF<Bits<32>>,
    o_phase: DFF<Bits<32>>,
    idx: Signal<Local, Bits<32>>,
    jdx: Signal<Local, Bits<32>>,
    oct: Signal<Local, Bit>,
    ta: Signal<Local, Bits<32>>,
    tb: Signal<Local, Bits<32>>,
    smag: Signal<Local, Bits<32>>,
    qhi_set: Signal<Local, Bit>,
    qlo_set: Signal<Local, Bit>,
    cmag: Signal<Local, Bits<32>>,
    /// Frequency word fw.
    fw: Constant<Bits<32>>,
    /// Mask of the P phase bits.
    pmask: Constant<Bits<32>>,
    /// P - T - 2: shift from the phase to the table index.
    ishift: Constant<Bits<32>>,
    /// Mask of the T index bits.
    tmask: Constant<Bits<32>>,
    /// Index bit T-1 (upper half of the quadrant).
    omsb: Constant<Bits<32>>,
    /// Mask of the T-1 octant index bits.
    hmask: Constant<Bits<32>>,
    /// Phase bit P-1 (quadrant MSB).
    qhi: Constant<Bits<32>>,
    /// Phase bit P-2 (quadrant LSB).
    qlo: Constant<Bits<32>>,
    /// Mask of the W output bits.
    wmask: Constant<Bits<32>>,
    /// One.
    one: Constant<Bits<32>>,
    /// Zero.
    zero: Constant<Bits<32>>,
}

impl Nco {
    /// NCO for validated parameters.
    pub fn new(p: &NcoParams) -> Self {
        let (pb, t) = (p.phase_bits(), p.table_bits());
        Self {
            clk: Default::default(),
            rst: Default::default(),
            tick: Default::default(),
            out_valid: Default::default(),
            out_sin: Default::default(),
            out_cos: Default::default(),
            out_phase: Default::default(),
            rom: SineRom::new(&p.table()),
            phase: Default::default(),
            o_valid: Default::default(),
            o_sin: Default::default(),
            o_cos: Default::default(),
            o_phase: Default::default(),
            idx: Default::default(),
            jdx: Default::default(),
            oct: Default::default(),
            ta: Default::default(),
            tb: Default::default(),
            smag: Default::default(),
            qhi_set: Default::default(),
            qlo_set: Default::default(),
            cmag: Default::default(),
            fw: c32(p.freq_word()),
            pmask: c32(mask(pb)),
            ishift: c32((pb - t - 2) as u64),
            tmask: c32(mask(t)),
            omsb: c32(1 << (t - 1)),
            hmask: c32(mask(t - 1)),
            qhi: c32(1 << (pb - 1)),
            qlo: c32(1 << (pb - 2)),
            wmask: c32(mask(p.width())),
            one: c32(1),
            zero: c32(0),
        }
    }
}

impl Logic for Nco {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clk, phase, o_valid, o_sin, o_cos, o_phase);
        // Table look-up of the current phase: ta = tab[i], tb = tab[~i] (combinational).
        // Octant fold: for i in the upper half of the quadrant read index j = ~i (T-1 bits)
        // and swap, since tab[i] = tab[2^T-1-j] and tab[~i] = tab[j].
        self.idx.next = (self.phase.q.val() >> self.ishift.val()) & self.tmask.val();
        self.oct.next = (self.idx.val() & self.omsb.val()) != self.zero.val();
        self.jdx.next = self.idx.val() & self.hmask.val();
        if self.oct.val() {
            self.jdx.next = (self.idx.val() ^ self.hmask.val()) & self.hmask.val();
        }
        self.rom.addr.next = bit_cast::<16, 32>(self.jdx.val());
        self.ta.next = bit_cast::<32, 16>(self.rom.data_s.val());
        self.tb.next = bit_cast::<32, 16>(self.rom.data_c.val());
        if self.oct.val() {
            self.ta.next = bit_cast::<32, 16>(self.rom.data_c.val());
            self.tb.next = bit_cast::<32, 16>(self.rom.data_s.val());
        }
        // Mirror (odd quadrant) and negate (sin: q = 2, 3; cos: q = 1, 2).
        self.qhi_set.next = (self.phase.q.val() & self.qhi.val()) != self.zero.val();
        self.qlo_set.next = (self.phase.q.val() & self.qlo.val()) != self.zero.val();
        self.smag.next = self.ta.val();
        self.cmag.next = self.tb.val();
        if self.qlo_set.val() {
            self.smag.next = self.tb.val();
            self.cmag.next = self.ta.val();
        }
        // On a tick the words of the current phase are registered and the phase advances.
        self.o_valid.d.next = self.tick.val();
        if self.tick.val() {
            self.phase.d.next = (self.phase.q.val() + self.fw.val()) & self.pmask.val();
            self.o_phase.d.next = self.phase.q.val();
            if self.qhi_set.val() {
                self.o_sin.d.next = ((!self.smag.val()) + self.one.val()) & self.wmask.val();
            } else {
                self.o_sin.d.next = self.smag.val();
            }
            if self.qhi_set.val() ^ self.qlo_set.val() {
                self.o_cos.d.next = ((!self.cmag.val()) + self.one.val()) & self.wmask.val();
            } else {
                self.o_cos.d.next = self.cmag.val();
            }
        }
        if self.rst.val() {
            self.phase.d.next = self.zero.val();
            self.o_valid.d.next = false;
            self.o_sin.d.next = self.zero.val();
            self.o_cos.d.next = self.zero.val();
            self.o_phase.d.next = self.zero.val();
        }
        self.out_valid.next = self.o_valid.q.val();
        self.out_sin.next = self.o_sin.q.val();
        self.out_cos.next = self.o_cos.q.val();
        self.out_phase.next = self.o_phase.q.val();
    }
}

impl crate::cosim::step::Clocked for Nco {
    fn set_clock(&mut self, high: bool) {
        self.clk.next = Clock::from(high);
    }
}

impl crate::cosim::CosimBlock for Nco {
    fn input_ports(&self) -> Vec<Port> {
        vec![Port::new("rst", 1), Port::new("tick", 1)]
    }
    fn output_ports(&self) -> Vec<Port> {
        vec![
            Port::new("out_valid", 1),
            Port::new("out_sin", 32),
            Port::new("out_cos", 32),
            Port::new("out_phase", 32),
        ]
    }
    fn apply(&mut self, r: &[u64]) {
        self.rst.next = r.first().copied().unwrap_or(0) != 0;
        self.tick.next = r.get(1).copied().unwrap_or(0) != 0;
    }
    fn sample(&self) -> Vec<u64> {
        vec![
            self.out_valid.val() as u64,
            self.out_sin.val().to_u64(),
            self.out_cos.val().to_u64(),
            self.out_phase.val().to_u64(),
        ]
    }
}
