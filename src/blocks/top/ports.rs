//! The port table of a board top: one list per top that declares the rust-hdl struct's
//! ports and is the source of the wrapper's port list, the pin lists the board section
//! needs, the VCD and params ports, and the co-simulation's rows (matched by name).
//!
//! ```text
//!  board_top! { TopRtl / SD_TOP_PORTS ... }      one line per port: name, direction,
//!        │                                      rtl type and width, pin group, idle level,
//!        │                                      comment
//!        ├──► struct TopRtl { pub clk: Signal<In, Clock>, ... }   (rust-hdl, field order)
//!        ├──► SD_TOP_PORTS: &[TopPort]     ──► wrapper ports, ties, pin lists, params
//!        └──► set_input / output by name   ──► CosimBlock rows, closed-loop records
//! ```
//!
//! A row of the co-simulation holds the inputs in the table's order (clock left out); a
//! row shorter than that leaves the missing inputs at their idle level.

/// Direction of a top's port.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dir {
    /// The system clock (an input the harness drives).
    Clock,
    /// An input.
    In,
    /// An output.
    Out,
}

/// Which board configuration gives a port of a top a pin (see `config::board_ports`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pin {
    /// Always a port with a pin.
    Always,
    /// A comparator input: a port with a pin only with `[qep] enabled`.
    Qep,
    /// The ADC's second data line: only for an ADC with two (`adc.frame.data_lines = 2`,
    /// presets `ads8354` and `ad7380`).
    AdcB,
    /// The pre-amplifier's lines: only with `[preamp]` (the LTC1407A-1 kit).
    Preamp,
    /// The SSI slave's line: only with `[ssi] enabled`.
    Ssi,
    /// The SPI slave's lines: only with `[spi] enabled`.
    Spi,
    /// A deselect line of the kit's other SPI devices: a port only when `[board.pins]` pins
    /// it.
    Deselect,
    /// A bus of `capacitive.dac_width` pins (LSB first), always a port.
    DacBus,
    /// The parallel bus: the wrapper forms its own `par_*` ports from it; no pin list.
    Parallel,
}

/// One port of a top's rust-hdl struct.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TopPort {
    /// The port's name: the struct field, the rtl port and (but for the parallel bus and
    /// the DAC buses, which the wrapper narrows) the wrapper's port.
    pub name: &'static str,
    /// Direction.
    pub dir: Dir,
    /// Width in the rtl, bits (32 for words).
    pub width: u32,
    /// When the port has a pin.
    pub pin: Pin,
    /// Level of an input when nothing drives it: the wrapper ties a left-out optional input
    /// to it, and a co-simulation row without the input applies it.
    pub idle: u64,
    /// One-line comment (struct field doc and wrapper port comment).
    pub comment: &'static str,
    /// The wire the wrapper connects the rtl port to: the port's name, or the wrapper's
    /// full-width wire for a port it narrows (`par_qc` -> `qc`).
    pub net: &'static str,
}

/// Number of ports of `table` in pin group `pin` (for [`pin_list`]).
pub const fn pin_count(table: &[TopPort], pin: Pin) -> usize {
    let mut n = 0;
    let mut i = 0;
    while i < table.len() {
        if table[i].pin as u8 == pin as u8 {
            n += 1;
        }
        i += 1;
    }
    n
}

/// Names of the `N` ports of `table` in pin group `pin`, in table order, at compile time
/// (`N` = [`pin_count`]; a name left empty means `N` was too large).
pub const fn pin_list<const N: usize>(table: &[TopPort], pin: Pin) -> [&'static str; N] {
    let mut out = [""; N];
    let mut i = 0;
    let mut k = 0;
    while i < table.len() && k < N {
        if table[i].pin as u8 == pin as u8 {
            out[k] = table[i].name;
            k += 1;
        }
        i += 1;
    }
    out
}

/// `pins!(TABLE, Group)`: the names of the table's ports in a pin group as a
/// `&'static [&'static str]` constant.
macro_rules! pins {
    ($table:expr, $pin:ident) => {
        &$crate::blocks::top::ports::pin_list::<
            {
                $crate::blocks::top::ports::pin_count($table, $crate::blocks::top::ports::Pin::$pin)
            },
        >($table, $crate::blocks::top::ports::Pin::$pin)
    };
}
pub(crate) use pins;

/// The co-simulation ports (everything but the clock) of direction `dir`, in table order.
pub fn cosim_ports(table: &[TopPort], dir: Dir) -> Vec<crate::cosim::Port> {
    table
        .iter()
        .filter(|p| p.dir == dir)
        .map(|p| crate::cosim::Port::new(p.name, p.width))
        .collect()
}

/// A port's value as the u64 of a co-simulation row, and back.
pub trait PortWord: Sized {
    /// The value's bits.
    fn to_word(&self) -> u64;
    /// The value of the low bits of `v`.
    fn from_word(v: u64) -> Self;
}

impl PortWord for bool {
    fn to_word(&self) -> u64 {
        *self as u64
    }
    fn from_word(v: u64) -> Self {
        v & 1 != 0
    }
}

impl<const N: usize> PortWord for rust_hdl::prelude::Bits<N> {
    fn to_word(&self) -> u64 {
        self.to_u64()
    }
    fn from_word(v: u64) -> Self {
        rust_hdl::prelude::Bits::<N>::from(v)
    }
}

/// Declares a top's rust-hdl struct with its ports from one table, the table itself
/// (`pub const TABLE: &[TopPort]`), a private `Parts` struct of the other fields with
/// `from_parts` (the ports start at their defaults), `set_input` / `output` by name, and
/// the top's `Clocked` and `CosimBlock` impls. Each port line:
/// `name: In|Out Type, Clock|In|Out, width, PinGroup, idle, "comment" [=> wrapper_net];`.
/// An optional `@optional_outputs { name: Type, width, "comment"; }` section declares outputs
/// that exist only in some configurations: `Vec<Signal<Out, Type>>` fields of length 0 or 1
/// (set in `Parts`), so a configuration without them exports no port and no logic for
/// them; element 0 is the rtl port `name_0`, the co-simulation port of the same name. An
/// `@optional_inputs { ... }` section before it declares inputs the same way (`Vec<Signal<In,
/// Type>>`); a co-simulation row holds them after the table's inputs.
macro_rules! board_top {
    (
        $(#[$meta:meta])*
        pub struct $name:ident / $table:ident / $parts:ident {
            ports {
                $( $port:ident : $io:ident $ty:ty, $dir:ident, $w:literal, $pin:ident,
                   $idle:literal, $doc:literal $(=> $net:ident)?; )*
            }
            $( @optional_inputs {
                $( $iport:ident : $ity:ty, $iw:literal, $idoc:literal; )*
            } )?
            $( @optional_outputs {
                $( $oport:ident : $oty:ty, $ow:literal, $odoc:literal; )*
            } )?
            $( $(#[$fmeta:meta])* $f:ident : $fty:ty, )*
        }
    ) => {
        $(#[$meta])*
        #[derive(LogicBlock)]
        pub struct $name {
            $( #[doc = $doc] pub $port: Signal<$io, $ty>, )*
            $( $( #[doc = $idoc] pub $iport: Vec<Signal<In, $ity>>, )* )?
            $( $( #[doc = $odoc] pub $oport: Vec<Signal<Out, $oty>>, )* )?
            $( $(#[$fmeta])* $f: $fty, )*
        }

        /// The fields of the top besides its ports, and the length (0 or 1) of its optional
        /// inputs and outputs.
        struct $parts {
            $( $( $iport: usize, )* )?
            $( $( $oport: usize, )* )?
            $( $(#[$fmeta])* $f: $fty, )*
        }

        #[doc = concat!("The ports of [`", stringify!($name), "`], in field order.")]
        pub const $table: &[$crate::blocks::top::ports::TopPort] = &[
            $( $crate::blocks::top::ports::TopPort {
                name: stringify!($port),
                dir: $crate::blocks::top::ports::Dir::$dir,
                width: $w,
                pin: $crate::blocks::top::ports::Pin::$pin,
                idle: $idle,
                comment: $doc,
                net: $crate::blocks::top::ports::board_top!(@net $port $(, $net)?),
            }, )*
        ];

        impl $name {
            /// The top from its other fields; every port starts at its default.
            fn from_parts(p: $parts) -> Self {
                Self {
                    $( $port: Default::default(), )*
                    $( $( $iport: (0..p.$iport).map(|_| Default::default()).collect(), )* )?
                    $( $( $oport: (0..p.$oport).map(|_| Default::default()).collect(), )* )?
                    $( $f: p.$f, )*
                }
            }

            /// The optional outputs present in this instance as co-simulation ports and
            /// their values: element `i` of the `Vec` field `name` is the rtl port
            /// `name_i` (rust-hdl names it `name$i`; the export turns `$` into `_`).
            fn optional_outputs(&self) -> Vec<($crate::cosim::Port, u64)> {
                #[allow(unused_mut)]
                let mut v = Vec::new();
                $( $( for (i, s) in self.$oport.iter().enumerate() {
                    v.push((
                        $crate::cosim::Port::new(&format!("{}_{i}", stringify!($oport)), $ow),
                        $crate::blocks::top::ports::PortWord::to_word(&s.val()),
                    ));
                } )* )?
                v
            }

            /// The optional inputs present in this instance as co-simulation ports and
            /// their present values (named like the optional outputs).
            fn optional_inputs(&self) -> Vec<($crate::cosim::Port, u64)> {
                #[allow(unused_mut)]
                let mut v = Vec::new();
                $( $( for (i, s) in self.$iport.iter().enumerate() {
                    v.push((
                        $crate::cosim::Port::new(&format!("{}_{i}", stringify!($iport)), $iw),
                        $crate::blocks::top::ports::PortWord::to_word(&s.val()),
                    ));
                } )* )?
                v
            }

            /// Drives the input `name` (its `.next`) with the low bits of `v`; false when
            /// the top has no input of that name.
            pub fn set_input(&mut self, name: &str, v: u64) -> bool {
                $( if name == stringify!($port) {
                    return $crate::blocks::top::ports::board_top!(@set $dir, self.$port, v);
                } )*
                $( $( for (i, s) in self.$iport.iter_mut().enumerate() {
                    if name == format!("{}_{i}", stringify!($iport)) {
                        s.next = $crate::blocks::top::ports::PortWord::from_word(v);
                        return true;
                    }
                } )* )?
                false
            }

            /// The value of the port `name` (input or output; not the clock).
            pub fn output(&self, name: &str) -> Option<u64> {
                $( if name == stringify!($port) {
                    return $crate::blocks::top::ports::board_top!(@get $dir, self.$port);
                } )*
                self.optional_outputs()
                    .into_iter()
                    .chain(self.optional_inputs())
                    .find(|(p, _)| p.name == name)
                    .map(|(_, v)| v)
            }

            /// The inputs' present values in co-simulation order (after a clock edge: the
            /// row that was applied before it).
            pub fn input_row(&self) -> Vec<u64> {
                $table
                    .iter()
                    .filter(|p| p.dir == $crate::blocks::top::ports::Dir::In)
                    .map(|p| self.output(p.name).unwrap_or(p.idle))
                    .chain(self.optional_inputs().into_iter().map(|(_, v)| v))
                    .collect()
            }
        }

        impl $crate::cosim::step::Clocked for $name {
            fn set_clock(&mut self, high: bool) {
                self.clk.next = Clock::from(high);
            }
        }

        impl $crate::cosim::CosimBlock for $name {
            fn input_ports(&self) -> Vec<$crate::cosim::Port> {
                let mut v = $crate::blocks::top::ports::cosim_ports(
                    $table,
                    $crate::blocks::top::ports::Dir::In,
                );
                v.extend(self.optional_inputs().into_iter().map(|(p, _)| p));
                v
            }
            fn output_ports(&self) -> Vec<$crate::cosim::Port> {
                let mut v = $crate::blocks::top::ports::cosim_ports(
                    $table,
                    $crate::blocks::top::ports::Dir::Out,
                );
                v.extend(self.optional_outputs().into_iter().map(|(p, _)| p));
                v
            }
            fn apply(&mut self, row: &[u64]) {
                let inputs = $table
                    .iter()
                    .filter(|p| p.dir == $crate::blocks::top::ports::Dir::In);
                let mut n = 0;
                for (i, p) in inputs.enumerate() {
                    self.set_input(p.name, row.get(i).copied().unwrap_or(p.idle));
                    n = i + 1;
                }
                for (k, (p, _)) in self.optional_inputs().into_iter().enumerate() {
                    self.set_input(&p.name, row.get(n + k).copied().unwrap_or(0));
                }
            }
            fn sample(&self) -> Vec<u64> {
                $table
                    .iter()
                    .filter(|p| p.dir == $crate::blocks::top::ports::Dir::Out)
                    .map(|p| self.output(p.name).unwrap_or(0))
                    .chain(self.optional_outputs().into_iter().map(|(_, v)| v))
                    .collect()
            }
        }
    };
    (@net $port:ident) => {
        stringify!($port)
    };
    (@net $port:ident, $net:ident) => {
        stringify!($net)
    };
    (@set In, $s:expr, $v:expr) => {{
        $s.next = $crate::blocks::top::ports::PortWord::from_word($v);
        true
    }};
    (@set $other:ident, $s:expr, $v:expr) => {
        false
    };
    (@get Clock, $s:expr) => {
        None
    };
    (@get $other:ident, $s:expr) => {
        Some($crate::blocks::top::ports::PortWord::to_word(&$s.val()))
    };
}
pub(crate) use board_top;

#[cfg(test)]
mod tests {
    use super::*;

    const T: &[TopPort] = &[
        TopPort {
            name: "a",
            dir: Dir::In,
            width: 1,
            pin: Pin::Always,
            idle: 0,
            comment: "",
            net: "",
        },
        TopPort {
            name: "b",
            dir: Dir::Out,
            width: 32,
            pin: Pin::Qep,
            idle: 0,
            comment: "",
            net: "",
        },
        TopPort {
            name: "c",
            dir: Dir::In,
            width: 1,
            pin: Pin::Always,
            idle: 1,
            comment: "",
            net: "",
        },
    ];

    #[test]
    fn pins_and_ports_follow_the_table() {
        assert_eq!(pin_list::<2>(T, Pin::Always), ["a", "c"]);
        assert_eq!(pin_count(T, Pin::Ssi), 0);
        let ins: Vec<String> = cosim_ports(T, Dir::In)
            .into_iter()
            .map(|p| p.name)
            .collect();
        assert_eq!(ins, ["a", "c"]);
        assert_eq!(cosim_ports(T, Dir::Out)[0].width, 32);
        const ALWAYS: &[&str] = pins!(T, Always);
        assert_eq!(ALWAYS, ["a", "c"]);
        assert_eq!(pin_count(T, Pin::Qep), 1);
    }
}
