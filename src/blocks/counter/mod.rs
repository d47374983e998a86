//! Position combiner and state-machine quadrant counter (thesis section 3.2.2), with the
//! multi-turn counter.
//!
//! ```text
//!  zN ──►┌──────────┐ p (F+2 bits)  ┌─────────────────────────────┐
//!  qN ──►│ combiner ├──────────────►│ quadrant counter            ├─► qc  (0 .. 4PPR-1)
//!  xN ──►│ round,   │ mag_ok        │ delta = p - p_prev (F+2 b)  ├─► fine (F bits)
//!  vN ──►│ |v| test │ v             │ qc += carry, wrap at 4PPR   ├─► turns (M bits)
//!        └──────reg─┘               └──────────────────────reg────┘ ─► valid, error, warning
//! ```
//!
//! Combiner (one register stage):
//! * fine = round(z / 2^Gz) = (z + 2^(Gz-1)) >> Gz, taken modulo 2^(F+2): z has
//!   ZW = F + Gz + 2 bits, so the shifted value has exactly F+2 bits and no sign fill is
//!   needed. fine may be slightly negative (angle 0 approached from below by the CORDIC
//!   residual) or reach 2^F and beyond (the boundary case): both are absorbed below.
//! * p = (q * 2^F + fine) mod 2^(F+2): the electrical angle within one signal period in
//!   units of 2^-F quadrant. The quadrant q comes from the sign bits of the same sample
//!   that fed the CORDIC, delayed through the pipeline with it, so coarse and fine can
//!   never disagree; a fine value that rounds up to a full quadrant carries into q here.
//! * mag_ok = xN >= K_N * min_amplitude * 2^(A-1) * 2^G (unsigned W-bit compare): below
//!   it the sample has no usable angle (zero input included) and is rejected.
//!
//! Quadrant counter (one register stage, the state is (p_prev, qc, fine, turns)):
//! * The thesis's state machine takes the quadrant from sign(sin), sign(cos) and counts
//!   +-1 on adjacent transitions. Here the transition table is computed arithmetically:
//!   delta = (p - p_prev) mod 2^(F+2), read as signed (F+2)-bit, is the step in fine LSB.
//!   Adjacent-quadrant steps give delta within +-1 quadrant (the +-1 of the thesis); a
//!   two-quadrant jump, ambiguous for the sign-only state machine, is resolved by the fine
//!   angle: any step of |delta| < 2 quadrants is unwrapped exactly.
//! * |delta| >= 1.75 quadrants (7 * 2^(F-2) LSB) raises `warning`: the step is near the
//!   ambiguity at exactly 2 quadrants, where noise can flip its direction. The maximum speed
//!   at full resolution is therefore 1.75 quadrants per sample.
//! * total = fine + delta (signed, F+3 bits); carry = floor(total / 2^F) in -2..=2;
//!   fine' = total mod 2^F (= p mod 2^F); qc' = qc + carry wrapped into 0..4PPR-1 (PPR need
//!   not be a power of two: one compare against 4PPR, one add/subtract of 4PPR), and each
//!   wrap steps the M-bit two's-complement turn counter by +-1 (modulo 2^M).
//! * The first accepted sample after reset sets qc = p >> F, fine = p mod 2^F, turns = 0.
//! * A rejected sample (mag_ok = 0) holds the position and sets `error` for that sample.
//! * Hardware form, bit for bit the same: fine = p_prev mod 2^F and qc mod 4 = p_prev >> F
//!   at all times (both come from the same p, and carry = q - q_prev mod 4), so the counter
//!   keeps only p_prev (F+2 bits), u = qc >> 2 (quadrant_bits - 2 bits, 0..PPR-1) and turns
//!   (M bits), and outputs qc = 4u + (p_prev >> F). carry lies in 0..=2 when delta >= 0 and
//!   in -2..=0 when delta < 0, so qc + carry leaves the signal period (u +- 1) exactly when
//!   a forward step goes to a lower quadrant (3 -> 0) or a backward one to a higher
//!   (0 -> 3): two 2-bit compares replace total and carry. u + {+1, 0, -1} is one
//!   (quadrant_bits - 1)-bit adder whose top bit flags u = 0 down and (PPR a power of two)
//!   u = PPR-1 up; otherwise u = PPR-1 is a constant compare and the wrapped u a constant.
//!   Two forms, the same bit for bit (a constant `flat` chooses; docs/timing.md). The iterative architecture's: each wrap adds +1 or -1 to the
//!   turn count its step starts from (turns, or the latched count of a pending load), with
//!   the wrap from compares of u with PPR-1 and 0 and a load's step decoded in the clock:
//!   the fewest LUTs, which its area target needs. The unrolled architecture's, below,
//!   for timing.
//!   Each wrap adds +1 or -1 to the turns, chosen from registers: turns + 1 and turns - 1
//!   are M-bit adders into registers of their own at every clock (for a load, load_turns
//!   plus and minus one are taken when the load is latched), so the turn register's input is a
//!   selection with no carry chain. In the clock after the turns move those registers are
//!   stale, and the update that moved them leaves the one the next sample can use in a
//!   register of its own with a flag (no carry chain and no wrap logic in front of the
//!   adders' registers, one registered select behind them): a step
//!   over quadrant 3 -> 0 ends in quadrant 0 or 1 and steps are under 2 quadrants, so two
//!   consecutive samples never both wrap up (or both down); after a wrap up, turns - 1 is
//!   the count the wrap started from, after a wrap down turns + 1 is, and after a load's
//!   step without a wrap they are the latched + 1 and - 1. The turn register's selects
//!   come from registers too: the combiner registers acc = valid and mag_ok (from its
//!   compare's chain), and a load's wrap (its step crosses the turn
//!   from the latched period) is registered a clock ahead with the load's direction
//!   (below), so the selection is hold, latched count (+- 1) or turns (+- 1), with no
//!   decode of p in front of it. The warning compares
//!   delta >> (F-2) (4 bits) with 7 and 9 plus a zero test of the low F-2 bits; that test
//!   is an equality of the low F-2 bits of p and p_last ((p - p_last) mod 2^(F-2) is zero
//!   exactly when they agree), so it sits beside the delta subtractor, not after it.
//!   The step's addend {+1, 0, -1} comes from registers: the combiner registers up, down
//!   and step = up | down, and the addend is step in bit 0 and down in every bit above.
//!   The combiner's magnitude test for p_last's enable is one compare of x with the valid
//!   bit on top (bit 31) against 2^31 + threshold, so the carry chain's end drives the
//!   enable directly.
//!   u and turns are zero whenever the counter is uninitialised, so the first sample only
//!   sets p_prev and fine.
//! * Resynchronisation (`load`, from the QEP fallback): the count moves from the latched
//!   load_qc by -1..=+2 to the sample's quadrant, wrapping at 4PPR as above (up and down
//!   from the two 2-bit quadrants as four-input functions, with no subtractor or comparator
//!   in front of the u adder: up = b1 & !a1 & (b0 | !a0), down = !b1 & !b0 & a1 & a0 for
//!   the load's quadrant b and the sample's a; both are registered a clock ahead, from the
//!   count being latched and the combiner's quadrant before its p register, so a load's
//!   step reaches the turn and period registers from registers, not from p). The running count's step and a load's step
//!   have a u adder each, chosen by `pending` after the adders, and a load's wrap comes
//!   from two flags taken when the load is latched (its period is PPR-1, is 0), so no
//!   multiplexer sits in front of an adder; load_qc must lie
//!   in 0..4PPR-1 (the fallback's does; the capacitive top and `<name>_core` tie load off),
//!   load_turns is taken modulo 2^M.
//! * Widths: qc needs quadrant_bits = ceil(log2(4PPR)) bits (18 at PPR = 65535); out_position
//!   = qc * 2^F + fine needs that plus F bits (34 at most), assembled by the Verilog wrapper
//!   from qc and fine so no simulated word exceeds 32 bits. The widest adders are delta (F+2
//!   bits) and the combiner's rounding (ZW bits).
pub mod hdl;
pub mod model;

/// The block's entry in the registry (`crate::blocks::registry`): the counter synthesized
/// alone (it is part of the core's row too).
pub const BLOCK: crate::blocks::registry::BlockDef =
    crate::blocks::registry::BlockDef::report_only("counter", "quadrant counter alone", |l| {
        let t = crate::report::blocks::BlockTiming::latency(1, "one register stage");
        crate::report::blocks::job(l, "counter", hdl::QuadrantCounter::new(&l.derived), t)
    });
