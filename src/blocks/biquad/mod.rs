//! Time-multiplexed biquad IIR engine: ONE multiply-accumulate datapath, one
//! coefficient (+ control) ROM and one state RAM run every second-order section of every
//! branch within one sample period, sequenced by a program counter.
//!
//! For the capacitive chain one engine serves three branches: branch 0 = band-pass on the
//! ADC sample (S0 sections), branches 1 and 2 = low-pass on the I and Q demodulated products
//! (the same S1 sections each, own state). The engine is general: 1..=8 branches of 1..=16
//! sections each, every section with its own coefficients.
//!
//! # Arithmetic (direct form I)
//!
//! Each section computes, with `F = coef_frac`,
//!
//! ```text
//! y[n] = sat_S( floor(b0 x[n]/2^F) + floor(b1 x[n-1]/2^F) + floor(b2 x[n-2]/2^F)
//!             + floor(-a1 y[n-1]/2^F) + floor(-a2 y[n-2]/2^F) )
//! ```
//!
//! as five sequential MACs on the single multiplier (the ROM stores b0, b1, b2, -a1, -a2, so
//! every MAC is an add). Section k's output is section k+1's input.
//!
//! Why direct form I: (1) it has one summing node, so one saturation at the accumulator
//! output handles overflow; the accumulator is wide enough that no intermediate sum can
//! wrap (transposed forms have two state adders, each of which would need its own
//! saturation); (2) in a cascade the y history of section k IS the x history of section
//! k+1, so a branch of N sections keeps only N+1 node histories (2(N+1) state words),
//! not 4N; (3) the state holds filter signals, not internal DF-II nodes whose gain can be
//! large for narrow-band sections.
//!
//! # Bit growth (D = data_width, G = guard_frac, C = coef_width, F = coef_frac)
//!
//! * State format: S = D + G bits two's complement, LSB = 2^-G input LSB. An input sample
//!   enters as x * 2^G (exactly S bits). Every node (input, section outputs) is stored in
//!   this format, so the G guard bits reduce the recursion's rounding noise by 2^G.
//! * Coefficients: C-bit two's complement with F fractional bits (value = c / 2^F); for
//!   |a1| < 2 F <= C - 2. The negated a1, a2 must fit C bits too (validated).
//! * Product: S x C -> S + C bits, arithmetic right shift by F (floor, i.e. truncation
//!   toward minus infinity) inside the multiplier block -> S + C - F significant bits,
//!   returned sign-extended in a 32-bit word.
//! * Accumulator: each term |t| <= 2^(S-1) 2^(C-1) / 2^F = 2^(S+C-F-2), five terms sum to
//!   less than 2^(S+C-F+1), so A = S + C - F + 2 bits never wrap (validated A <= 32).
//! * Truncation happens once per product (5 floors per section: the section output is low
//!   by at most 5 LSB of the S format = 5 * 2^-G input LSB, before the feedback gain) and
//!   once at the branch output.
//! * Saturation: the A-bit sum is clamped to S bits ([-2^(S-1), 2^(S-1)-1]); a clamp of a
//!   section result that is used (next section's input, stored history, branch output)
//!   raises the sample's overflow flag. A full-scale step therefore saturates, never wraps.
//! * Output: the last section's S-bit result shifted right by G (floor) = D bits; it is
//!   always in range because the S-bit value was already saturated.
//!
//! Default widths of the tests: D = 16, G = 2, C = 18, F = 16 gives an 18 x 18 product
//! (one Cyclone III 18x18 embedded multiplier in Quartus) and A = 22; the precise variant
//! D = 16, G = 8, C = 25, F = 23 gives 24 x 25 (several embedded multipliers) and A = 28.
//! Yosys 0.23 `synth_intel -family cycloneive` has no DSP mapping and builds the product
//! from logic cells; measured (capacitive chain, 2 + 2 + 2 sections, state RAM in one
//! M9K): 18 x 18: 1342 LE of which 976 are the multiplier, 241 FF; 18 x 25: 1648 LE (1306
//! multiplier), 246 FF. With S > 18 Yosys maps the RAM to the M9K 36-bit mode with a port
//! resize warning that the project's synthesis gate rejects.
//!
//! Truncation bias: the five floors of a section average about -2.5 S-LSB per sample and
//! the low-pass recursion amplifies them by its DC gain 1/(1 + a1 + a2) (about 260 for the
//! 4 kHz / 400 kHz Butterworth), so with G = 2 the output of that low-pass sits up to
//! ~160 LSB low; G = 8 brings the error below 4 LSB (tests/capacitive/biquad.rs measures both).
//!
//! # Sketch
//!
//! ```text
//!  in_valid ─►┌────────┐ pc ┌──────────────┐ coef ┌──────┐ ┌──┐
//!  in_data[k]►│ latch  │───►│ program ROM  ├─reg─►│coef  ├►│op├──────┐
//!             │ in_lat │next│ (coef, ctrl) │ ctrl │ reg  │ │b │      ▼
//!             └───┬────┘    └──────┬───reg─┘      └──────┘ └──┘ ┌──────────┐ ┌────┐
//!                 │ << G           │ addr ^ parity             │ S x C    │ │prod│
//!                 ▼                ▼                 ┌──────┐┌──┐│ >> F     ├►│reg │
//!             ┌──────┐ x     ┌───────────┐  q        │ mux  ├┤op├►│ (ONE     │ └─┬──┘
//!             │ xcur ├──────►│ state RAM ├──────────►│x / q ││a │ │ $mul)    │   ▼
//!             └──▲───┘  wd   │ 2(N+1)    │           └──▲───┘└──┘ └──────────┘ ┌─────┐
//!                │     ┌────►│ words per │              │ xcur              │ acc │◄┐
//!                │     │     │ branch    │                                  │ A b │ │
//!                │     │     └───────────┘                                  └──┬──┴─┘
//!                │     └──────────────── sat_S(acc) ◄────────────────────────────┘
//!                └──────────────────────── sat_S(acc) ─► >> G ─► out_sh[b] ─► out_data[b]
//! ```
//!
//! # Sequencing
//!
//! A program counter `pc` runs 0..P-1 (P = [`BiquadParams::latency`] = 8 J + 2) after an
//! accepted `in_valid`; the ROM entry at `pc` holds the coefficient to load and the control
//! bits of everything that happens in that clock ([`BiquadParams::program`]). The ROM is
//! read one clock ahead (at the next pc) into a register, so the word of clock t comes from
//! a register in clock t. The multiplier has registered operands (`op`: the operand select
//! and the coefficient register, one clock) and a registered product, so each product
//! reaches the accumulator two clocks after its operands are selected. Section j (counted
//! over all branches in order) starts at c0 = 8 j:
//!
//! ```text
//! c0+0  xcur <= branch input << G (first section) or sat(acc); coef_reg <= b0
//! c0+1  RAM read h1[s];   coef_reg <= b1;  op <= xcur,   b0
//! c0+2  RAM read h2[s];   coef_reg <= b2;  op <= h1[s],  b1;  prod <= op
//! c0+3  RAM read h1[s+1]; coef_reg <= -a1; op <= h2[s],  b2;  prod <= op;  acc <= prod
//! c0+4  RAM read h2[s+1]; coef_reg <= -a2; op <= h1[s+1],-a1; prod <= op;  acc += prod
//! c0+5  RAM write node s <= xcur;          op <= h2[s+1],-a2; prod <= op;  acc += prod
//! c0+6                                                        prod <= op;  acc += prod
//! c0+7                                                                     acc += prod
//! c0+8  (= next section's c0) acc final; last section of a branch: RAM write node N <=
//!       sat(acc), out_sh[b] <= sat(acc) >> G
//! 8J+1  out_data <= out_sh, out_valid, overflow; parity toggles; busy falls
//! ```
//!
//! (`prod <= op` is the product of the operands registered in `op`.) Saturation: acc is in
//! the S-bit range exactly when its bits S-1..A-1 are all equal, a test without an adder.
//!
//! Node n's two history words sit at `base + 0/1`; the sample parity p selects which one is
//! h2 (`base ^ p`) and h1 (`(base + 1) ^ p`); the new value overwrites the h2 word, so each
//! node costs one write per sample (no h2 <= h1 copy).
//!
//! Timing: the edge that accepts `in_valid` latches the inputs; the next P = 8 J + 2 edges
//! run the program (`busy` high), the last one raises `out_valid`. Cycles per sample, the
//! minimum period of accepted strobes, is P + 1 = 8 J + 3, i.e. the sum over branches of
//! sections * (5 MACs + 3 pipeline clocks) plus 3 ([`BiquadParams::cycles_per_sample`]).
//! The capacitive chain with 2 band-pass and 2 + 2 low-pass sections needs 51 clocks:
//! 0.38 us at 133 MHz, 1.02 us at 50 MHz, inside the paper's 2.5 us sample period.
//!
//! # Ports of [`hdl::BiquadRtl`] (data words are `Bits<32>` with the value in the low bits)
//!
//! ```text
//! clk          in   system clock
//! rst          in   synchronous reset, active high: aborts a computation, clears out_data,
//!                   flags and then the whole state RAM (busy for W = state_words clocks
//!                   after rst falls)
//! in_valid     in   start strobe: accepted in a clock where busy is low; in_data latched
//! in_data_k    in   branch k input, D-bit two's complement
//! out_valid    out  one-clock strobe, P clocks after the edge that accepted in_valid
//! out_data_k   out  branch k output, D-bit two's complement (saturated); held until the
//!                   next out_valid (0 after reset)
//! overflow     out  one-clock flag with out_valid: some section of this sample saturated
//! busy         out  computing or clearing: an in_valid now is dropped
//! dropped      out  one-clock flag set by the edge that ignored an in_valid (busy)
//! ```
//!
//! Back-to-back samples: an `in_valid` while `busy` is not queued: it is dropped and
//! `dropped` pulses; the computation in progress is not disturbed. Seen from the outputs:
//! the row showing `out_valid` also shows `busy` low, and an `in_valid` in the next clock is
//! accepted, so strobes every P + 1 clocks are all accepted.
pub mod hdl;
pub mod model;
pub mod parts;

use crate::error::{Error, Result};

/// Most branches one engine runs.
pub const MAX_BRANCHES: usize = 8;
/// Most sections per branch.
pub const MAX_SECTIONS: usize = 16;
/// Clocks per section: 5 MACs + 3 pipeline clocks (RAM read, operand register, product
/// register).
pub const CYCLES_PER_SECTION: u32 = 8;
/// Busy clocks per sample beyond the sections: last result and output update.
pub const CYCLES_FIXED: u32 = 2;

/// Control bits of a program word (bits 0..=9 are the state RAM address).
pub mod ctrl {
    /// State RAM address field (before the parity XOR).
    pub const ADDR_MASK: u32 = 0x3ff;
    /// Write the RAM at the address.
    pub const WE: u32 = 1 << 10;
    /// RAM write data = sat(acc) (else xcur).
    pub const WSRC_ACC: u32 = 1 << 11;
    /// Load xcur.
    pub const LDX: u32 = 1 << 12;
    /// xcur <= next branch input << G (else sat(acc)).
    pub const XIN: u32 = 1 << 13;
    /// Multiplier operand = xcur (else RAM data).
    pub const OPX: u32 = 1 << 14;
    /// Accumulate the product register.
    pub const ACC: u32 = 1 << 15;
    /// First term: acc <= prod (else acc += prod).
    pub const FIRST: u32 = 1 << 16;
    /// Branch done: out_sh[branch] <= sat(acc) >> G.
    pub const PUSH: u32 = 1 << 17;
    /// Sample done: out_data <= out_sh, out_valid.
    pub const LAST: u32 = 1 << 18;
}

/// One program word: the coefficient to load into the coefficient register and the control
/// bits of that clock.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MicroOp {
    /// Coefficient (signed integer, C bits).
    pub coef: i64,
    /// Control word ([`ctrl`] bits and the RAM address).
    pub ctrl: u32,
}

/// Parameters of the biquad engine: widths and quantized coefficients.
#[derive(Clone, Debug, PartialEq)]
pub struct BiquadParams {
    /// Input/output width D in bits (two's complement), 2..=24; 16..=18 intended.
    pub data_width: u32,
    /// Coefficient width C in bits (two's complement), 2..=30.
    pub coef_width: u32,
    /// Fractional bits F of the coefficients (value = integer / 2^F), 1..C.
    pub coef_frac: u32,
    /// Extra fractional bits G kept in the state and accumulator, 0..=16.
    pub guard_frac: u32,
    /// Per branch, the sections in cascade order as quantized (b0, b1, b2, a1, a2) with
    /// y = (b0 x + b1 x1 + b2 x2 - a1 y1 - a2 y2) / 2^F.
    pub branches: Vec<Vec<[i64; 5]>>,
}

fn bad(key: impl Into<String>, message: String) -> Error {
    Error::ConfigValue {
        source_name: "biquad".into(),
        location: String::new(),
        key: key.into(),
        message,
    }
}

const COEF_NAMES: [&str; 5] = ["b0", "b1", "b2", "a1", "a2"];

impl BiquadParams {
    /// Validated parameters (see [`BiquadParams::validate`]).
    pub fn new(
        data_width: u32,
        coef_width: u32,
        coef_frac: u32,
        guard_frac: u32,
        branches: Vec<Vec<[i64; 5]>>,
    ) -> Result<Self> {
        let p = BiquadParams {
            data_width,
            coef_width,
            coef_frac,
            guard_frac,
            branches,
        };
        p.validate()?;
        Ok(p)
    }

    /// Checks widths (every word fits 32 bits), counts and that every coefficient (and the
    /// negated a1, a2 the ROM stores) fits `coef_width` bits; errors name the offender.
    pub fn validate(&self) -> Result<()> {
        if !(2..=24).contains(&self.data_width) {
            return Err(bad(
                "data_width",
                format!("{} bits: 2..=24 are supported", self.data_width),
            ));
        }
        if !(2..=30).contains(&self.coef_width) {
            return Err(bad(
                "coef_width",
                format!("{} bits: 2..=30 are supported", self.coef_width),
            ));
        }
        if self.coef_frac == 0 || self.coef_frac >= self.coef_width {
            return Err(bad(
                "coef_frac",
                format!(
                    "{} fractional bits: 1..={} for coef_width {}",
                    self.coef_frac,
                    self.coef_width - 1,
                    self.coef_width
                ),
            ));
        }
        if self.guard_frac > 16 {
            return Err(bad(
                "guard_frac",
                format!("{} guard bits: 0..=16 are supported", self.guard_frac),
            ));
        }
        let a = self.acc_width();
        if a > 32 {
            return Err(bad(
                "coef_width",
                format!(
                    "accumulator width data_width + guard_frac + coef_width - coef_frac + 2 \
                     = {} + {} + {} - {} + 2 = {a} bits exceeds the 32-bit word",
                    self.data_width, self.guard_frac, self.coef_width, self.coef_frac
                ),
            ));
        }
        if self.branches.is_empty() || self.branches.len() > MAX_BRANCHES {
            return Err(bad(
                "branches",
                format!(
                    "{} branches: 1..={MAX_BRANCHES} are supported",
                    self.branches.len()
                ),
            ));
        }
        let hi = (1i64 << (self.coef_width - 1)) - 1;
        let lo = -(1i64 << (self.coef_width - 1));
        for (b, secs) in self.branches.iter().enumerate() {
            if secs.is_empty() || secs.len() > MAX_SECTIONS {
                return Err(bad(
                    format!("branches[{b}]"),
                    format!("{} sections: 1..={MAX_SECTIONS} are supported", secs.len()),
                ));
            }
            for (s, c) in secs.iter().enumerate() {
                for (k, &v) in c.iter().enumerate() {
                    // a1, a2 are stored negated: -v must fit as well.
                    let ok = if k < 3 {
                        (lo..=hi).contains(&v)
                    } else {
                        (lo..=hi).contains(&v) && (lo..=hi).contains(&-v)
                    };
                    if !ok {
                        let range = if k < 3 {
                            format!("{lo}..={hi}")
                        } else {
                            format!("{}..={hi} (stored negated)", lo + 1)
                        };
                        return Err(bad(
                            format!("branches[{b}][{s}].{}", COEF_NAMES[k]),
                            format!(
                                "coefficient {v} does not fit {} bits: {range}",
                                self.coef_width
                            ),
                        ));
                    }
                }
            }
        }
        Ok(())
    }

    /// State width S = data_width + guard_frac.
    pub fn state_width(&self) -> u32 {
        self.data_width + self.guard_frac
    }

    /// Accumulator width A = S + C - F + 2 (five terms, never wraps).
    pub fn acc_width(&self) -> u32 {
        self.state_width() + self.coef_width + 2 - self.coef_frac
    }

    /// Number of branches.
    pub fn branch_count(&self) -> usize {
        self.branches.len()
    }

    /// Total number of sections J over all branches.
    pub fn total_sections(&self) -> u32 {
        self.branches.iter().map(|b| b.len() as u32).sum()
    }

    /// Latency P = 8 J + 2: clocks from the edge that accepts `in_valid` to the edge that
    /// raises `out_valid`; `busy` is high for these P clocks; the program has P words.
    pub fn latency(&self) -> u32 {
        CYCLES_PER_SECTION * self.total_sections() + CYCLES_FIXED
    }

    /// Clocks per sample = P + 1 = 8 J + 3 (sum over branches of sections times 5 MACs plus
    /// 3, plus 3): the minimum period of accepted `in_valid` strobes (the accepting clock
    /// and the P busy clocks).
    pub fn cycles_per_sample(&self) -> u32 {
        self.latency() + 1
    }

    /// State RAM words W = sum over branches of 2 (sections + 1); also the clocks of the
    /// clearing sweep after reset.
    pub fn state_words(&self) -> u32 {
        self.branches.iter().map(|b| 2 * (b.len() as u32 + 1)).sum()
    }

    /// Bits of the state RAM address.
    pub fn addr_width(&self) -> u32 {
        bits_for(self.state_words())
    }

    /// Bits of the program counter.
    pub fn pc_width(&self) -> u32 {
        bits_for(self.latency())
    }

    /// The program: one word per busy clock (see the module docs' schedule).
    pub fn program(&self) -> Vec<MicroOp> {
        let p = self.latency() as usize;
        let mut prog = vec![MicroOp::default(); p];
        let mut j = 0usize;
        let mut base = 0u32;
        for secs in &self.branches {
            let n = secs.len();
            for (s, c) in secs.iter().enumerate() {
                let c0 = CYCLES_PER_SECTION as usize * j;
                let node = |k: usize| base + 2 * k as u32;
                let x_src = if s == 0 { ctrl::XIN } else { 0 };
                let e = &mut prog[c0];
                e.ctrl |= ctrl::LDX | x_src;
                e.coef = c[0];
                prog[c0 + 1] = MicroOp {
                    coef: c[1],
                    ctrl: (node(s) + 1) | ctrl::OPX,
                };
                prog[c0 + 2] = MicroOp {
                    coef: c[2],
                    ctrl: node(s),
                };
                prog[c0 + 3] = MicroOp {
                    coef: -c[3],
                    ctrl: (node(s + 1) + 1) | ctrl::ACC | ctrl::FIRST,
                };
                prog[c0 + 4] = MicroOp {
                    coef: -c[4],
                    ctrl: node(s + 1) | ctrl::ACC,
                };
                prog[c0 + 5].ctrl = node(s) | ctrl::WE | ctrl::ACC;
                prog[c0 + 6].ctrl = ctrl::ACC;
                prog[c0 + 7].ctrl = ctrl::ACC;
                if s + 1 == n {
                    // Branch result: one clock after the last accumulate (shared with the
                    // next section's first clock, which does not use the RAM port).
                    prog[c0 + 8].ctrl |= node(n) | ctrl::WE | ctrl::WSRC_ACC | ctrl::PUSH;
                }
                j += 1;
            }
            base += 2 * (n as u32 + 1);
        }
        prog[p - 1].ctrl |= ctrl::LAST;
        prog
    }
}

/// Bits to count 0..n-1 (at least 1).
fn bits_for(n: u32) -> u32 {
    (32 - n.saturating_sub(1).leading_zeros()).max(1)
}

/// The block's entry in the registry (`crate::blocks::registry`).
pub const BLOCK: crate::blocks::registry::BlockDef = crate::blocks::registry::BlockDef::report_only(
    "biquad",
    "biquad engine (band-pass + low-pass)",
    crate::report::jobs::biquad_job,
);
