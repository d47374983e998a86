//! QEP-CORDIC fine interpolator: quadrant mapper and N unrolled vectoring stages
//! (thesis section 2.3.3).
//!
//! ```text
//!  in_sin ─┐   ┌────────────┐  x0,y0  ┌─────────┐ x1,y1,z1     ┌─────────┐ xN,yN,zN
//!  in_cos ─┼──►│ quadrant   ├────────►│ stage 0 ├────► ... ───►│ stage   ├─────────►
//!  in_valid┘   │ mapper  reg│ q0,v0   │ i=0  reg│ q,v          │ N-1  reg│ q,v
//!              └────────────┘         └─────────┘              └─────────┘
//! ```
//!
//! Quadrant mapping (thesis Table 2-3), x = cos, y = sin, q from the sign bits only:
//!
//! | q | signs (cos, sin) | mapped (x', y') | angle subtracted |
//! |---|---|---|---|
//! | 0 | (+, +) | ( x,  y) | 0 |
//! | 1 | (-, +) | ( y, -x) | pi/2 |
//! | 2 | (-, -) | (-x, -y) | pi |
//! | 3 | (+, -) | (-y,  x) | 3pi/2 |
//!
//! "+" means sign bit clear (>= 0). The mapped vector has x' >= 0, y' >= 0, so its angle is
//! in [0, pi/2]; q = {sign(sin), sign(sin) ^ sign(cos)}.
//!
//! Bit growth, A = ADC width, G = x/y guard bits, Gz = angle guard bits, F = fine bits:
//! * Mapping: -(-2^(A-1)) = 2^(A-1) needs A+1 bits signed; the mapped vector has
//!   |v| <= sqrt(2) 2^(A-1).
//! * Stages: x grows to K_N |v| < 1.6468 * 1.4143 * 2^(A-1) < 2^(A+1), y stays within
//!   +-x, so x/y need A+2 integer bits (with sign) plus G fraction bits: W = A + 2 + G.
//!   Each stage truncates x>>i and y>>i (arithmetic shift): < 1 unit of 2^-G each.
//! * Stage i: if y >= 0 then x += y>>i, y -= x>>i, z += atan(2^-i) else the opposite.
//!   In the unrolled stage x and y are one adder each with y's sign in the operand's
//!   inversion and carry-in; z + atan and z - atan are two adders side by side and y's sign
//!   selects after them, so the sign (about 3W loads) reaches z through one LUT, not a
//!   carry chain (docs/timing.md, "Design rules learned").
//!   z starts at 0; the angle table atan(2^-i) is pre-scaled by 1/(pi/2) and held in units
//!   of 2^-(F+Gz) quadrant, rounded to nearest (`crate::exact`).
//! * z reaches sum atan(2^-i) = 1.7433 rad = 1.11 quadrant and can dip to -0.11 quadrant
//!   near angle 0: z needs 2 integer bits with sign, ZW = F + Gz + 2.
//! * Residual after N stages: |angle - z| <= atan(2^-(N-1)), the CORDIC's own bound.
//!
//! Ports of [`hdl::QuadrantMapper`] and [`hdl::CordicStage`] are listed on the structs.
//!
//! Architectures (`cordic.architecture`): `"unrolled"` (default) instantiates the N stages
//! above, one sample per clock, latency N + 2; `"iterative"`
//! ([`iterative::IterativeCordic`]) reuses one digit-serial stage (4 bits per clock) with
//! one-hot shift taps and an angle ROM, one sample per S = N·ceil(W/4) clocks, latency
//! S + 2, with an `in_ready` handshake. Both have the same arithmetic, bit for bit (the
//! model of both is [`model::cordic`]).
pub mod hdl;
pub mod iterative;
pub mod model;
