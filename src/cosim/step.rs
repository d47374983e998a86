//! Hand-stepping of rust-hdl designs: no simulation threads (about 10x faster than the
//! `Simulation` API, see docs/rust-hdl.md), identical results.
//!
//! One call to [`tick`] is one clock cycle with the semantics of the co-simulation harness:
//! the caller has set the inputs (`.next`) while the clock is low; the clock rises; the
//! design settles; the caller reads the outputs.
use rust_hdl::prelude::*;

/// Passes allowed for a design to settle after a clock change.
pub const MAX_PASSES: usize = 200;

/// A rust-hdl block with a single clock input.
pub trait Clocked: Block {
    /// Drives the clock input.
    fn set_clock(&mut self, high: bool);
}

/// Error: the design did not settle (combinational loop or too deep a hierarchy).
#[derive(Debug, thiserror::Error)]
#[error("rust-hdl simulation did not settle within {MAX_PASSES} passes")]
pub struct NoConvergence;

/// Connects the design for simulation; call once before the first [`tick`].
pub fn prepare<B: Clocked>(uut: &mut B) -> Result<(), NoConvergence> {
    uut.connect_all();
    uut.set_clock(false);
    if simulate(uut, MAX_PASSES) {
        Ok(())
    } else {
        Err(NoConvergence)
    }
}

/// One clock cycle: settle the inputs with the clock low, raise it, settle.
pub fn tick<B: Clocked>(uut: &mut B) -> Result<(), NoConvergence> {
    uut.set_clock(false);
    if !simulate(uut, MAX_PASSES) {
        return Err(NoConvergence);
    }
    uut.set_clock(true);
    if !simulate(uut, MAX_PASSES) {
        return Err(NoConvergence);
    }
    Ok(())
}
