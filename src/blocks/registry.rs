//! The block registry: one [`BlockDef`] per block, kept in the block's own folder
//! (`blocks/<key>/mod.rs`, `pub const BLOCK`), and one list of them, [`BLOCKS`].
//!
//! ```text
//!  blocks/abz/mod.rs: pub const BLOCK: BlockDef = BlockDef {
//!      key, label, section,        ──► report block table, check's lines,
//!      enabled, ports, describe,       <name>_top's ports (wrapper, params.json,
//!      build, timing_case }            board pins, SDC/XDC groups, error messages)
//!                │                     timing rule (tests/timing.rs), co-simulation pins
//!                ▼
//!  BLOCKS: &[&abz::BLOCK, ...]   (this file: one line per block)
//! ```
//!
//! A block's config section (its struct, defaults and checks) and its Params derivation
//! live in its folder too; the config's root struct and `Derived` hold one typed field per
//! optional block (serde and the rust-hdl top need the types), and the rust-hdl top
//! (`blocks/top/hdl.rs`) instantiates and wires it: `#[hdl_gen]` transpiles one `update`
//! function over concrete fields, so the wiring cannot be looked up from a list.
//!
//! Adding an optional block of the sinewave top therefore touches its folder, one line
//! here, one field in `config/schema/mod.rs` and in `blocks/params.rs` (`Derived`), the
//! field and wiring in `blocks/top/hdl.rs` and, for its output pins, the top's
//! `@optional_outputs` (rust-hdl struct fields).
use crate::blocks::top::ports::Dir;
use crate::config::{Config, Derived, Loaded};
use crate::error::Result;
use crate::report::blocks::BlockJob;

/// Builds the report's synthesis job of one block from the configuration.
pub type BlockCtor = fn(&Loaded) -> Result<BlockJob>;

/// One pinned port a block adds to `<name>_top` when it is enabled. The rust-hdl top has it
/// as an optional output `<name>_0` (a Vec of length 0 or 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BlockPort {
    /// The wrapper's port name (the rtl's is `<name>_0`).
    pub name: &'static str,
    /// Direction (one bit wide). An output is registered in the block; an input enters
    /// through the block's synchronizer (the SDC/XDC constrain them so).
    pub dir: Dir,
    /// One-line comment of the wrapper's port.
    pub comment: &'static str,
}

/// One block: everything the top, the wrappers, `check`, the report, the constraints, the
/// timing rule and the co-simulation read about it.
#[derive(Clone, Copy)]
pub struct BlockDef {
    /// Key: the config section (`[key]`) of an optional block, the report's row key and the
    /// module suffix `<name>_blk_<key>` (lower case, digits and `_`).
    pub key: &'static str,
    /// Row label in the report.
    pub label: &'static str,
    /// The setting that puts the block into the top, as messages quote it
    /// (`[abz] enabled = true`); "" for a block every sinewave top has.
    pub section: &'static str,
    /// Whether this configuration's sinewave top has the block (its optional ports).
    pub enabled: fn(&Config) -> bool,
    /// Pinned ports the block adds to `<name>_top`, in the wrapper's order.
    pub ports: &'static [BlockPort],
    /// Group of those ports in the SDC/XDC constraints (a comment line).
    pub io_group: &'static str,
    /// The block's lines of `check` (None: none, or printed elsewhere).
    pub describe: fn(&Derived) -> Option<String>,
    /// The report's synthesis job.
    pub build: BlockCtor,
    /// For the timing rule (`tests/timing.rs`): TOML appended to the default config that
    /// switches the block on (None: the block is in a held design already).
    pub timing_case: Option<&'static str>,
}

impl BlockDef {
    /// A block of the report table with nothing else registered (always in the top, or
    /// not a block of the sinewave top).
    pub const fn report_only(key: &'static str, label: &'static str, build: BlockCtor) -> Self {
        BlockDef {
            key,
            label,
            section: "",
            enabled: |_| true,
            ports: &[],
            io_group: "",
            describe: |_| None,
            build,
            timing_case: None,
        }
    }
}

/// Every block, in the report table's order (the whole top last).
pub const BLOCKS: &[&BlockDef] = &[
    &crate::blocks::adc::BLOCK,
    &crate::blocks::preamp::BLOCK,
    &crate::blocks::correction::BLOCK,
    &crate::blocks::monitor::BLOCK,
    &crate::blocks::harmonics::BLOCK,
    &crate::blocks::core::BLOCK,
    &crate::blocks::counter::BLOCK,
    &crate::blocks::qep::BLOCK,
    &crate::blocks::fallback::BLOCK,
    &crate::blocks::biss::BLOCK,
    &crate::blocks::ssi::BLOCK,
    &crate::blocks::spi_slave::BLOCK,
    &crate::blocks::parallel::BLOCK,
    &crate::blocks::abz::BLOCK,
    &crate::blocks::velocity::BLOCK,
    &crate::blocks::reference::BLOCK,
    &crate::blocks::absolute::BLOCK,
    &crate::blocks::capture::BLOCK,
    &crate::blocks::regmap::BLOCK,
    &crate::blocks::nco::BLOCK,
    &crate::blocks::biquad::BLOCK,
    &crate::blocks::capacitive::BLOCK,
    &crate::blocks::top::BLOCK,
];

/// The optional pinned ports of this configuration's sinewave top, in the wrapper's order.
pub fn enabled_ports(c: &Config) -> impl Iterator<Item = &'static BlockPort> + '_ {
    BLOCKS
        .iter()
        .filter(move |b| !b.ports.is_empty() && (b.enabled)(c))
        .flat_map(|b| b.ports.iter())
}

/// The block that owns an optional pinned port, whether enabled or not.
pub fn port_owner(port: &str) -> Option<&'static BlockDef> {
    BLOCKS
        .iter()
        .copied()
        .find(|b| b.ports.iter().any(|p| p.name == port))
}
