//! `<name>_core`: the QEP-CORDIC decoder core, from ADC samples to position.
//!
//! ```text
//!           ┌────────┐   ┌─────────┐       ┌───────────┐   ┌──────────┐   ┌─────────┐
//! in_sin ──►│quadrant├──►│ stage 0 ├─ ... ►│ stage N-1 ├──►│ combiner ├──►│ counter ├─► out_*
//! in_cos ──►│ mapper │   └─────────┘       └───────────┘   └──────────┘   └─────────┘
//! in_valid─►└────────┘
//!   cycle:     1            2 .. N+1                          N+2            N+3 edge
//! ```
//!
//! Latency: a sample presented with `in_valid` in cycle k appears with `out_valid` in
//! cycle k + N + 2 (N + 2 register stages after the input: mapper, N stages, combiner,
//! counter, counting the edge that captures the input as the first). The thesis's design
//! needs N + 6. Throughput: one sample per clock; `in_valid` may have gaps of any length.
//!
//! Ports of the emitted Verilog `<name>_core` (widths from the config):
//!
//! | port | dir | width | meaning |
//! |---|---|---|---|
//! | `clk` | in | 1 | system clock |
//! | `rst` | in | 1 | synchronous reset, active high; drops samples in flight |
//! | `in_valid` | in | 1 | `in_sin`/`in_cos` hold a sample |
//! | `in_sin`, `in_cos` | in | A | signed ADC samples |
//! | `out_valid` | out | 1 | one-cycle strobe per decoded sample |
//! | `out_position` | out | Q+F | single-turn position, 2^-F quadrant units, 0..4PPR*2^F-1 |
//! | `out_turns` | out | max(M,1) | signed multi-turn count (0 when M = 0) |
//! | `out_fine` | out | F | fine part of `out_position` (angle within the quadrant) |
//! | `out_error` | out | 1 | sample rejected: magnitude below `monitor.min_amplitude` |
//! | `out_warning` | out | 1 | step of >= 1.75 quadrants: near the 2-quadrant ambiguity |
//!
//! The flags and the position hold their values between `out_valid` strobes. The rust-hdl
//! block [`hdl::CoreRtl`] carries the datapath in 32-bit words (see `crate::blocks`); the
//! emitted `<name>_core` is a thin wrapper that gives the ports their exact widths and
//! concatenates `out_position` from the quadrant count and the fine part.
pub mod hdl;
pub mod model;

/// The block's entry in the registry (`crate::blocks::registry`).
pub const BLOCK: crate::blocks::registry::BlockDef = crate::blocks::registry::BlockDef::report_only(
    "core",
    "core (mapper + CORDIC + combiner + counter)",
    crate::report::jobs::core_job,
);
