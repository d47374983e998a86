//! Cell and routing delay models of the families [`super::analyze`] times, and the arcs of
//! their cells (sources and calibration in `docs/timing.md`).
use crate::synth::Family;

/// Cell and routing delays of one family and speed grade, in picoseconds (sources and
/// calibration in `docs/timing.md`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DelayModel {
    /// Family, speed grade and data sheet.
    pub name: &'static str,
    /// Flip-flop clock to output.
    pub tcko_ps: u64,
    /// Flip-flop setup (data input, LUT already counted).
    pub tsu_ps: u64,
    /// One LUT.
    pub lut_ps: u64,
    /// Entering a carry chain (MUXCY select/data to out; Cyclone: the LUT's carry out).
    pub carry_entry_ps: u64,
    /// One carry bit along the chain.
    pub carry_bit_ps: u64,
    /// Carry to sum output (XORCY, lcell `cin -> combout`).
    pub carry_sum_ps: u64,
    /// One wide-function multiplexer (MUXF5..8).
    pub mux_ps: u64,
    /// A combinational hard multiplier, input to output.
    pub mult_ps: u64,
    /// Block RAM clock to output.
    pub ram_tco_ps: u64,
    /// Routing per net (calibrated against nextpnr-ecp5, `docs/timing.md`).
    pub route_ps: u64,
}

/// Spartan-3A/3AN, speed grade -4 (DS529 / DS557 switching characteristics).
pub const XC3SA_4: DelayModel = DelayModel {
    name: "Spartan-3A/3AN -4",
    tcko_ps: 630,
    tsu_ps: 400,
    lut_ps: 710,
    carry_entry_ps: 430,
    carry_bit_ps: 80,
    carry_sum_ps: 560,
    mux_ps: 450,
    mult_ps: 4880,
    ram_tco_ps: 2400,
    route_ps: 810,
};

/// Cyclone III (the EP3C40F324C8 of the capacitive preset). The Cyclone III handbook's data
/// sheet publishes no LE-level delays; these are the Quartus II 11.1 (Chip Planner) figures
/// of FloPoCo's Cyclone III target (`src/Targets/CycloneIII.hpp`), which states no speed
/// grade: LUT 0.436 ns, carry 0.058 ns per bit, carry-in to sum 0.455 ns, clock to Q
/// 0.352 ns (marked TODO there), 18x18 multiplier 2.860 ns with its 0.265 ns output
/// register (2.595 ns combinational), M9K 2.792 ns. Setup is not in that source: 0.20 ns is
/// an estimate. MUXF cells do not occur in the cycloneive mapping. See `docs/timing.md`.
pub const CYCLONE3_C8: DelayModel = DelayModel {
    name: "Cyclone III (Quartus II 11.1 figures)",
    tcko_ps: 352,
    tsu_ps: 200,
    lut_ps: 436,
    carry_entry_ps: 0,
    carry_bit_ps: 58,
    carry_sum_ps: 455,
    mux_ps: 450,
    mult_ps: 2595,
    ram_tco_ps: 2792,
    route_ps: 497,
};

/// The delay model of a family.
pub fn model(family: Family) -> &'static DelayModel {
    match family {
        Family::Xc3sa => &XC3SA_4,
        Family::CycloneIve => &CYCLONE3_C8,
    }
}

/// Kind of a cell arc.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Arc {
    /// Through a LUT.
    Lut,
    /// Into a carry chain (Cyclone: through the LUT into the chain).
    CarryEntry {
        /// The arc passes the LE's LUT too (Cyclone).
        through_lut: bool,
    },
    /// Along the carry chain.
    CarryBit,
    /// Carry to sum.
    CarrySum,
    /// Wide-function multiplexer.
    Mux,
    /// Combinational multiplier.
    Mult,
    /// No delay, no level (an inverter Yosys left for the LUT to absorb).
    Wire,
}

/// What a cell is for the analysis.
pub(super) enum Role {
    /// Flip-flop or synchronous RAM: outputs start paths, these inputs end them.
    Seq {
        tco_ps: u64,
        ends: &'static [&'static str],
    },
    /// Combinational cell.
    Comb,
    /// Not timed (I/O buffers, clock buffers, constants).
    None,
}

pub(super) fn role(t: &str, m: &DelayModel) -> Role {
    match t {
        _ if t.starts_with("FD") => Role::Seq {
            tco_ps: m.tcko_ps,
            ends: &["D", "CE", "R", "S"],
        },
        "dffeas" => Role::Seq {
            tco_ps: m.tcko_ps,
            ends: &["d", "ena", "sclr", "sload", "asdata"],
        },
        _ if t.starts_with("RAMB16") => Role::Seq {
            tco_ps: m.ram_tco_ps,
            ends: &[
                "ADDR", "DI", "DIP", "EN", "SSR", "WE", "ADDRA", "ADDRB", "DIA", "DIB", "DIPA",
                "DIPB", "ENA", "ENB", "SSRA", "SSRB", "WEA", "WEB",
            ],
        },
        _ if t.starts_with("cycloneive_ram_block") || t == "altsyncram" => Role::Seq {
            tco_ps: m.ram_tco_ps,
            ends: &[
                "portadatain",
                "portaaddr",
                "portawe",
                "portbdatain",
                "portbaddr",
                "portbwe",
                "portare",
                "portbre",
                "data_a",
                "address_a",
                "wren_a",
                "data_b",
                "address_b",
                "wren_b",
                "rden_a",
                "rden_b",
            ],
        },
        _ if t.starts_with("LUT")
            || t == "INV"
            || t == "MUXCY"
            || t == "XORCY"
            || t.starts_with("MUXF")
            || t == "MULT18X18"
            || t == "cycloneive_lcell_comb"
            || t == "$not"
            || t == "$_NOT_" =>
        {
            Role::Comb
        }
        _ => Role::None,
    }
}

/// The arc of a combinational cell from input `i` to output `o` (None: no arc).
pub fn arc(t: &str, i: &str, o: &str) -> Option<Arc> {
    match t {
        _ if t.starts_with("LUT") || t == "INV" => Some(Arc::Lut),
        "MUXCY" => Some(if i == "CI" {
            Arc::CarryBit
        } else {
            Arc::CarryEntry { through_lut: false }
        }),
        "XORCY" => Some(Arc::CarrySum),
        _ if t.starts_with("MUXF") => Some(Arc::Mux),
        "MULT18X18" => Some(Arc::Mult),
        "$not" | "$_NOT_" => Some(Arc::Wire),
        "cycloneive_lcell_comb" => match (i, o) {
            ("cin", "cout") => Some(Arc::CarryBit),
            ("cin", "combout") => Some(Arc::CarrySum),
            (_, "cout") => Some(Arc::CarryEntry { through_lut: true }),
            (_, "combout") => Some(Arc::Lut),
            _ => None,
        },
        _ => None,
    }
}

pub(super) fn arc_ps(a: Arc, m: &DelayModel) -> u64 {
    match a {
        Arc::Lut => m.lut_ps,
        Arc::CarryEntry { through_lut } => {
            m.carry_entry_ps + if through_lut { m.lut_ps } else { 0 }
        }
        Arc::CarryBit => m.carry_bit_ps,
        Arc::CarrySum => m.carry_sum_ps,
        Arc::Mux => m.mux_ps,
        Arc::Mult => m.mult_ps,
        Arc::Wire => 0,
    }
}

/// Whether the connection from a cell of type `driver` into input `pin` of a `sink` cell
/// uses general routing (false: a dedicated connection inside the slice or LE).
pub fn routed(driver: &str, sink: &str, pin: &str) -> bool {
    let lutlike = |t: &str| {
        t.starts_with("LUT")
            || t == "INV"
            || t == "XORCY"
            || t.starts_with("MUXF")
            || t == "cycloneive_lcell_comb"
    };
    match (sink, pin) {
        ("MUXCY", "CI") | ("XORCY", "CI") | ("MUXCY", "S") | ("XORCY", "LI") => false,
        (s, "I0") | (s, "I1") if s.starts_with("MUXF") => false,
        ("cycloneive_lcell_comb", "cin") => false,
        ("$not", _) | ("$_NOT_", _) => false,
        (s, "D") if s.starts_with("FD") => !lutlike(driver),
        ("dffeas", "d") => !lutlike(driver),
        _ => true,
    }
}
