//! Yosys's combinational cell types and the operation of src/engine/ops.rs each maps to
//! (the `op` numbers are those of ops.rs's functions). Sequential cells (`$dff`, `$dffe`,
//! `$sdff`, `$sdffe`, `$sdffce`) and memory cells are read in src/engine/netlist/build.rs; any
//! other type is reported as unsupported.
use super::netlist::Op;

/// The operation of a combinational cell type, None for other types.
pub fn comb_op(ty: &str) -> Option<Op> {
    Some(match ty {
        "$not" => Op::Unary(0),
        "$neg" => Op::Unary(1),
        "$pos" => Op::Unary(2),
        "$and" => Op::Arith(0),
        "$or" => Op::Arith(1),
        "$xor" => Op::Arith(2),
        "$xnor" => Op::Arith(3),
        "$add" => Op::Arith(4),
        "$sub" => Op::Arith(5),
        "$mul" => Op::Arith(6),
        "$div" => Op::Arith(7),
        "$mod" => Op::Arith(8),
        "$eq" | "$eqx" => Op::Compare(0),
        "$ne" | "$nex" => Op::Compare(1),
        "$lt" => Op::Compare(2),
        "$le" => Op::Compare(3),
        "$gt" => Op::Compare(4),
        "$ge" => Op::Compare(5),
        "$logic_not" => Op::Logic(0),
        "$logic_and" => Op::Logic(1),
        "$logic_or" => Op::Logic(2),
        "$reduce_and" => Op::Logic(3),
        "$reduce_or" | "$reduce_bool" => Op::Logic(4),
        "$reduce_xor" => Op::Logic(5),
        "$reduce_xnor" => Op::Logic(6),
        "$shl" | "$sshl" => Op::Shift(0),
        "$shr" => Op::Shift(1),
        "$sshr" => Op::Shift(2),
        "$shift" => Op::Shift(3),
        "$shiftx" => Op::Shift(4),
        "$mux" => Op::Mux,
        "$pmux" => Op::Pmux,
        _ => return None,
    })
}
