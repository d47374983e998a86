// The semantics of Yosys's word-level cells on `u64` words: one source for the interpreter
// (src/engine/interp.rs) and the generated Rust (src/engine/codegen.rs pastes this file into
// every generated crate, so it must not use anything outside `core`).
//
// Every value is a `u64` holding a word of 1..=64 bits, the bits above the width zero.
// Operands are extended to the width the cell computes in (sign or zero, by the cell's
// `*_SIGNED` parameters, as in Yosys's simlib.v), the result is cut to `Y_WIDTH`. `x` results
// (division by zero, a shift of `$shiftx` past the word) are 0, like Verilator's
// `--x-assign 0`.

/// All ones in the low `w` bits (w in 0..=64).
#[inline(always)]
pub const fn mask(w: u32) -> u64 {
    if w >= 64 {
        u64::MAX
    } else {
        (1u64 << w) - 1
    }
}

/// `v` (a `w`-bit word) extended to 64 bits: sign-extended when `signed`, else as is.
#[inline(always)]
pub const fn ext(v: u64, w: u32, signed: bool) -> u64 {
    if signed && w > 0 && w < 64 && (v >> (w - 1)) & 1 == 1 {
        v | !mask(w)
    } else {
        v
    }
}

/// `$not`, `$neg`, `$pos`: `op` 0, 1, 2.
#[inline(always)]
pub const fn unary(op: u8, a: u64, aw: u32, asg: bool, yw: u32) -> u64 {
    let a = ext(a, aw, asg);
    let r = match op {
        0 => !a,
        1 => a.wrapping_neg(),
        _ => a,
    };
    r & mask(yw)
}

/// `$and $or $xor $xnor $add $sub $mul $div $mod`: `op` 0..=8. Signed when both operands
/// are (simlib.v's `A_SIGNED && B_SIGNED`).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub const fn arith(op: u8, a: u64, aw: u32, asg: bool, b: u64, bw: u32, bsg: bool, yw: u32) -> u64 {
    let s = asg && bsg;
    let a = ext(a, aw, s);
    let b = ext(b, bw, s);
    let r = match op {
        0 => a & b,
        1 => a | b,
        2 => a ^ b,
        3 => !(a ^ b),
        4 => a.wrapping_add(b),
        5 => a.wrapping_sub(b),
        6 => a.wrapping_mul(b),
        7 => {
            if b == 0 {
                0
            } else if s {
                (a as i64).wrapping_div(b as i64) as u64
            } else {
                a / b
            }
        }
        _ => {
            if b == 0 {
                0
            } else if s {
                (a as i64).wrapping_rem(b as i64) as u64
            } else {
                a % b
            }
        }
    };
    r & mask(yw)
}

/// `$eq $ne $lt $le $gt $ge`: `op` 0..=5; 1 or 0.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub const fn compare(op: u8, a: u64, aw: u32, asg: bool, b: u64, bw: u32, bsg: bool) -> u64 {
    let s = asg && bsg;
    let a = ext(a, aw, s);
    let b = ext(b, bw, s);
    let (lt, eq) = if s {
        ((a as i64) < (b as i64), a == b)
    } else {
        (a < b, a == b)
    };
    let r = match op {
        0 => eq,
        1 => !eq,
        2 => lt,
        3 => lt || eq,
        4 => !lt && !eq,
        _ => !lt,
    };
    r as u64
}

/// `$logic_not $logic_and $logic_or $reduce_and $reduce_or/$reduce_bool $reduce_xor
/// $reduce_xnor`: `op` 0..=6 (`b` unused by the unary ones); 1 or 0.
#[inline(always)]
pub const fn logic(op: u8, a: u64, aw: u32, b: u64) -> u64 {
    let r = match op {
        0 => a == 0,
        1 => a != 0 && b != 0,
        2 => a != 0 || b != 0,
        3 => a == mask(aw),
        4 => a != 0,
        5 => a.count_ones() & 1 == 1,
        _ => a.count_ones() & 1 == 0,
    };
    r as u64
}

/// `$shl/$sshl $shr $sshr $shift $shiftx`: `op` 0..=4, `a` shifted by `b`. `$shift` and
/// `$shiftx` shift right by a signed `b` when `bsg` (negative: left); `$shiftx` fills with
/// 0 for x.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub const fn shift(op: u8, a: u64, aw: u32, asg: bool, b: u64, bw: u32, bsg: bool, yw: u32) -> u64 {
    // The width the shift happens in: max(A, Y), as Verilog sizes `Y = A << B`.
    let w = if aw > yw { aw } else { yw };
    let r = match op {
        0 => {
            let a = ext(a, aw, asg) & mask(w);
            if b >= 64 {
                0
            } else {
                a << b
            }
        }
        1 => {
            let a = ext(a, aw, asg) & mask(w);
            if b >= 64 {
                0
            } else {
                a >> b
            }
        }
        2 => {
            let a = ext(a, aw, asg);
            if asg {
                ((a as i64) >> if b >= 63 { 63 } else { b }) as u64
            } else if b >= 64 {
                0
            } else {
                (a & mask(w)) >> b
            }
        }
        _ => {
            let a = if op == 3 {
                ext(a, aw, asg) & mask(w)
            } else {
                a
            };
            let sb = ext(b, bw, bsg) as i64;
            if bsg && sb < 0 {
                let l = sb.unsigned_abs();
                if l >= 64 {
                    0
                } else {
                    a << l
                }
            } else {
                let r = sb as u64;
                if r >= 64 {
                    0
                } else {
                    a >> r
                }
            }
        }
    };
    r & mask(yw)
}

/// `$pmux`: `a` unless a bit of `s` is set; then the word of `b` of the lowest set bit.
#[inline(always)]
pub fn pmux(a: u64, b: &[u64], s: u64) -> u64 {
    if s == 0 {
        a
    } else {
        b[s.trailing_zeros() as usize]
    }
}
