//! A RAM with one write port and one read port that behaves as rust-hdl's `RAM` does (the
//! word at the address of the last read edge, read before that edge's write), built for
//! distributed (LUT) RAM: the read address is registered and the array read after it, and
//! every write is held a clock in a write stage, so the word the read sees is the one
//! before the write of its own edge:
//!
//! ```text
//!  read_address ──reg──► ra ──► mem[ra] ─────────────────────────────► read_data
//!  write_address, write_data, write_enable ──reg──► (wa, wd, we) ──► mem[wa] <= wd
//! ```
//!
//! After edge c the array holds every write presented before cycle c (one edge late), and
//! `ra` the address of cycle c: `read_data` = M_(c-1)[addr_c], the registered read of
//! rust-hdl's `RAM`, clock for clock. The array carries `(* ram_style = "distributed" *)`.
//! Written here because rust-hdl's `RAM` has no way to carry an attribute and reads the
//! array before its output register.
//!
//! Why: on the ECP5 of the timing rule (docs/timing.md) Yosys maps a block RAM to a DP16KD
//! without its output register, whose clock-to-out alone (5.61 ns at speed 6) nearly fills
//! the rule's 6.0 ns at 133.33 MHz; and a LUT RAM read at a computed address puts the
//! address logic, its fan-out to every LUT RAM cell and the read mux in one path (the
//! learner's state to its table: 83.8 MHz). Here the path starts at the address register.
//! Yosys honours the attribute on ECP5 (TRELLIS_DPR16X4, the address register kept before
//! the array) and xc3sa (RAM16X1D); its Cyclone IV E flow ignores it and maps an M9K, the
//! address register merged into the M9K's read port ([`PipedLutRam`] keeps its address
//! registers, and the M9K registers their value again: the same two clocks). No register
//! here has an initial value: one would keep Yosys from that merge (the array then becomes
//! flip-flops).
use rust_hdl::prelude::*;
use std::collections::BTreeMap;

/// One write port and one read port, as rust-hdl's `RAM` (see the module doc).
#[derive(LogicBlock, Default)]
pub struct LutRam<D: Synth, const N: usize> {
    /// The word read at the next `read_clock` edge.
    pub read_address: Signal<In, Bits<N>>,
    /// The read port's clock.
    pub read_clock: Signal<In, Clock>,
    /// The word at `read_address` at the last edge, before that edge's write.
    pub read_data: Signal<Out, D>,
    /// The word written at the next `write_clock` edge when `write_enable` is high.
    pub write_address: Signal<In, Bits<N>>,
    /// The write port's clock.
    pub write_clock: Signal<In, Clock>,
    /// The word written.
    pub write_data: Signal<In, D>,
    /// Write this clock.
    pub write_enable: Signal<In, bool>,
    /// The simulation's words (none known at power-up: they read as 0 here, `x` in
    /// Verilog).
    _sim: BTreeMap<Bits<N>, D>,
    /// The registered read address.
    _ra: Bits<N>,
    /// The write stage: the write presented a clock before, if any.
    _wr: Option<(Bits<N>, D)>,
    /// Each clock's edge acts once however often the simulator settles within it: armed
    /// while the clock is low (write clock, read clock).
    _warm: bool,
    _rarm: bool,
}

impl<D: Synth, const N: usize> Logic for LutRam<D, N> {
    fn update(&mut self) {
        if !self.write_clock.val().clk {
            self._warm = true;
        } else if self._warm {
            self._warm = false;
            if let Some((a, d)) = self._wr.take() {
                self._sim.insert(a, d);
            }
            if self.write_enable.val() {
                self._wr = Some((self.write_address.val(), self.write_data.val()));
            }
        }
        if !self.read_clock.val().clk {
            self._rarm = true;
        } else if self._rarm {
            self._rarm = false;
            self._ra = self.read_address.val();
        }
        self.read_data.next = *self._sim.get(&self._ra).unwrap_or(&D::default());
    }

    fn connect(&mut self) {
        self.read_data.connect();
    }

    fn hdl(&self) -> Verilog {
        Verilog::Custom(format!(
            "\
(* ram_style = \"distributed\" *) reg[{d}:0] mem[{a}:0];
reg[{n}:0] ra;
reg[{n}:0] wa;
reg[{d}:0] wd;
reg we;

always @(posedge read_clock) begin
   ra <= read_address;
end

always @(*) begin
   read_data = mem[ra];
end

always @(posedge write_clock) begin
   we <= write_enable;
   wa <= write_address;
   wd <= write_data;
   if (we) begin
      mem[wa] <= wd;
   end
end
",
            d = D::BITS - 1,
            n = N - 1,
            a = (1usize << N) - 1,
        ))
    }
}

/// [`LutRam`] with its read split over two clocks for a RAM too large to read in one (256
/// words on the ECP5 of the timing rule: the address register's fan-out to every cell and a
/// 16-to-1 read multiplexer, 6.5 to 7 ns of routing):
///
/// ```text
///  read_address ─┬─reg──► ra_0 ─► mem_0[ra_0 low] ──reg──► q_0 ─┐
///                ├─reg──► ra_1 ─► mem_1[ra_1 low] ──reg──► q_1 ─┤
///                ├─reg──► ra_2 ─► mem_2[ra_2 low] ──reg──► q_2 ─┼─► q_(rb) ─► read_data
///                ├─reg──► ra_3 ─► mem_3[ra_3 low] ──reg──► q_3 ─┘
///                └─ ra_0's top two bits ──reg──► rb
///  write_address, write_data, write_enable ──reg──► (wa, wd, we) ──► mem_(wa top)[wa low] <= wd
/// ```
///
/// Four arrays of 2^(N-2) words, selected by the address's top two bits: the first clock reads
/// each array's word into its register (`q_k`, the cells and a 4-to-1 multiplexer), the
/// second selects one of them (a 4-to-1 multiplexer out of registers). `read_data` in clock
/// c + 1 is [`LutRam`]'s `read_data` of clock c: the word at the address presented two clocks
/// before, as the array held it before the write of the first of those clocks' edge. A
/// write presented in the clock before an address is therefore not seen by its read (the
/// write stage lands it one edge after the `q_k` registers have read). Yosys keeps each
/// `q_k` as the array's read register and honours `ram_style` on ECP5 and xc3sa (four
/// distributed RAMs); Cyclone IV E maps each array to an M9K.
#[derive(LogicBlock, Default)]
pub struct PipedLutRam<D: Synth, const N: usize> {
    /// The word read two `clock` edges later.
    pub read_address: Signal<In, Bits<N>>,
    /// The word at `read_address` two edges before, before the first edge's write.
    pub read_data: Signal<Out, D>,
    /// The word written at the next edge when `write_enable` is high.
    pub write_address: Signal<In, Bits<N>>,
    /// The word written.
    pub write_data: Signal<In, D>,
    /// Write this clock.
    pub write_enable: Signal<In, bool>,
    /// The read and write ports' clock.
    pub clock: Signal<In, Clock>,
    /// The simulation's words (none known at power-up: they read as 0 here, `x` in
    /// Verilog).
    _sim: BTreeMap<Bits<N>, D>,
    /// The registered read address.
    _ra: Bits<N>,
    /// The word read at `_ra` at the last edge (the selected `q_k`).
    _q: D,
    /// The write stage: the write presented a clock before, if any.
    _wr: Option<(Bits<N>, D)>,
    /// The clock's edge acts once however often the simulator settles within it: armed
    /// while the clock is low.
    _arm: bool,
    /// One array read into one register instead of four ([`PipedLutRam::one_array`]).
    _one: bool,
}

impl<D: Synth, const N: usize> PipedLutRam<D, N> {
    /// The same two-clock read from one array into one register, with no select after it:
    /// for a RAM of at most 128 words, whose read (eight cells and an 8-to-1 multiplexer)
    /// fits a clock on ECP5 once it ends at a register. Cyclone IV E maps it to one M9K per
    /// 36 bits of word, where the four arrays take four.
    pub fn one_array() -> Self {
        Self {
            _one: true,
            ..Default::default()
        }
    }
}

impl<D: Synth, const N: usize> Logic for PipedLutRam<D, N> {
    fn update(&mut self) {
        if !self.clock.val().clk {
            self._arm = true;
        } else if self._arm {
            self._arm = false;
            // The read registers take the array before this edge's write lands.
            self._q = *self._sim.get(&self._ra).unwrap_or(&D::default());
            if let Some((a, d)) = self._wr.take() {
                self._sim.insert(a, d);
            }
            if self.write_enable.val() {
                self._wr = Some((self.write_address.val(), self.write_data.val()));
            }
            self._ra = self.read_address.val();
        }
        self.read_data.next = self._q;
    }

    fn connect(&mut self) {
        self.read_data.connect();
    }

    fn hdl(&self) -> Verilog {
        // Four arrays, selected by the address's top two bits a clock after their read, or
        // one array and no select. Each array has its own read address register, and the RAM
        // its own write stage, each in a `keep` block: Yosys would merge identical registers
        // across arrays and RAMs that share an address or a write port, and the merged
        // register then drives every cell (the read and write paths' fan-out).
        let (arrays, top) = if self._one { (1, 0) } else { (4, 2) };
        let (d, n, lo) = (D::BITS - 1, N - 1, N - 1 - top);
        let a = (1usize << (N - top)) - 1;
        let mut v = String::new();
        for k in 0..arrays {
            v += &format!("(* ram_style = \"distributed\" *) reg[{d}:0] mem_{k}[{a}:0];\n");
            v += &format!("reg[{d}:0] q_{k};\nreg[{n}:0] ra_{k};\n");
        }
        if arrays > 1 {
            v += "reg[1:0] rb;\n";
        }
        v += &format!("reg[{n}:0] wa;\nreg[{d}:0] wd;\nreg we;\n\n");
        for k in 0..arrays {
            v += &format!(
                "(* keep *)\nalways @(posedge clock) begin\n   ra_{k} <= read_address;\nend\n\n"
            );
        }
        v += "(* keep *)\nalways @(posedge clock) begin\n   we <= write_enable;\n   wa <= write_address;\n   wd <= write_data;\nend\n\n";
        v += "always @(posedge clock) begin\n";
        if arrays > 1 {
            v += &format!("   rb <= ra_0[{n}:{}];\n", N - top);
        }
        for k in 0..arrays {
            v += &format!("   q_{k} <= mem_{k}[ra_{k}[{lo}:0]];\n");
        }
        v += "end\n\nalways @(*) begin\n";
        if arrays > 1 {
            v += "   case (rb)\n";
            for k in 0..arrays {
                v += &format!("      2'd{k}: read_data = q_{k};\n");
            }
            v += "   endcase\n";
        } else {
            v += "   read_data = q_0;\n";
        }
        v += "end\n\nalways @(posedge clock) begin\n";
        for k in 0..arrays {
            let sel = if arrays > 1 {
                format!(" && wa[{n}:{}] == 2'd{k}", N - top)
            } else {
                String::new()
            };
            v += &format!("   if (we{sel}) begin\n      mem_{k}[wa[{lo}:0]] <= wd;\n   end\n");
        }
        v += "end\n";
        Verilog::Custom(v)
    }
}
