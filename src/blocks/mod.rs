//! Hardware blocks. Each block has `hdl.rs` (the rust-hdl description that is simulated and
//! exported), `model.rs` (a plain-Rust bit-accurate model of the same datapath) and a module
//! doc comment with its bit-growth maths, an ASCII sketch and its ports.
//!
//! Configurable widths: rust-hdl widths are const generics, and stable Rust cannot compute
//! `Bits<{W+1}>`. Every datapath word is therefore a `Bits<32>` that holds a W-bit
//! two's-complement value in its low W bits (upper bits always zero); W comes from the
//! config and reaches the hardware as per-instance `Constant` masks. After every add the
//! result is ANDed with the mask, so Yosys sees constant-zero upper bits and removes them:
//! the synthesized width is W, not 32. Right shifts are arithmetic by OR-ing a constant
//! fill mask when the sign bit (a constant-mask test, never a literal index) is set.
//! No unsized literal takes part in any expression: rust-hdl writes a Rust integer literal
//! as a 32-bit Verilog literal, which widens the expression around it; every constant is a
//! sized `Constant`.
pub mod absolute;
pub mod abz;
pub mod adc;
pub mod biquad;
pub mod biss;
pub mod capacitive;
pub mod captop;
pub mod capture;
pub mod cordic;
pub mod core;
pub mod correction;
pub mod counter;
pub mod fallback;
pub mod fsmreg;
pub mod harmonics;
pub mod init_bit;
pub mod lutram;
pub mod monitor;
pub mod nco;
pub mod parallel;
pub mod params;
pub mod preamp;
pub mod qep;
pub mod reference;
pub mod registry;
pub mod regmap;
pub mod serial;
pub mod spi_slave;
pub mod splitadd;
pub mod ssi;
pub mod top;
pub mod velocity;

use rust_hdl::prelude::*;

/// A block's logic in named stages, run in the order given: each stage is a trait of its
/// own whose `update` is a `#[hdl_gen]` function (which also writes the trait's `connect`
/// and `hdl`), and the block's [`Logic`] runs them in order and concatenates their
/// combinational statements, so simulation, drivers and the exported Verilog are the same
/// as from one `update` holding every stage's statements in sequence
/// (`docs/rust-hdl.md`). Written by hand: rust-hdl's `#[hdl_gen]` takes one function.
///
/// ```text
///   logic_stages!(Block: Capture, Track, Reset);
///   impl stages::Capture for Block { #[hdl_gen] fn update(&mut self) { dff_setup!(..); .. } }
///   impl stages::Track for Block { #[hdl_gen] fn update(&mut self) { .. } }
/// ```
macro_rules! logic_stages {
    ($block:ty: $($stage:ident),*) => {
        /// The stages of the block's logic (`logic_stages!`): traits in a module of their
        /// own, so that their `update` and `connect` do not shadow the block's.
        pub(crate) mod stages {
            #[allow(unused_imports)]
            use super::*;
            $(
                /// One stage of the block's logic.
                pub(crate) trait $stage {
                    /// The stage's statements.
                    fn update(&mut self);
                    /// The drivers its statements write.
                    fn connect(&mut self);
                    /// Its statements as Verilog.
                    fn hdl(&self) -> Verilog;
                }
            )*
            impl Logic for $block {
                fn update(&mut self) {
                    $(<Self as $stage>::update(self);)*
                }
                fn connect(&mut self) {
                    $(<Self as $stage>::connect(self);)*
                }
                fn hdl(&self) -> Verilog {
                    let mut body = Vec::new();
                    $(
                        if let Verilog::Combinatorial(b) = <Self as $stage>::hdl(self) {
                            body.extend(b);
                        }
                    )*
                    Verilog::Combinatorial(body)
                }
            }
        }
    };
}
pub(crate) use logic_stages;

/// A 32-bit constant word.
pub fn c32(v: u64) -> Constant<Bits<32>> {
    Constant::new(Bits::<32>::from(v & 0xffff_ffff))
}

/// Mask of the low `w` bits.
pub fn mask(w: u32) -> u64 {
    if w >= 64 {
        u64::MAX
    } else {
        (1u64 << w) - 1
    }
}

/// Sign-extends the low `w` bits of `v`.
#[inline]
pub fn sext(v: u64, w: u32) -> i64 {
    let s = 64 - w;
    ((v << s) as i64) >> s
}

/// Bits `k..w` set: the fill OR-ed after a logical right shift by k of a negative w-bit word.
pub fn fill(w: u32, k: u32) -> u64 {
    mask(w) & !(mask(w) >> k.min(w))
}
