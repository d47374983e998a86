//! VCD of `<name>_top`'s pins, streamed to a writer cycle by cycle with the `vcd` crate, so
//! memory stays bounded however long the run (the rust-hdl VCD probe writes every half
//! cycle of every internal signal and is ten times slower; this writes the top's pins only).
//!
//! The variables are `<name>_top`'s ports with their names and widths as declared in the
//! emitted Verilog (see `crate::emit::top_ports`), not the rust-hdl `<name>_rtl`'s 32-bit
//! words: `par_position` = {qc, fine} on `out_position`'s width, `par_turns` on M bits,
//! `par_fine` on F bits, `exc_sin`/`exc_cos` on the DAC width.
use crate::cosim::Port;
use std::io::Write;
use vcd::{IdCode, TimescaleUnit, Value};

/// Where a top port's value comes from, per cycle.
#[derive(Clone, Copy, Debug)]
enum Source {
    /// The system clock (written as its two edges).
    Clock,
    /// An rtl input (index into the input row).
    Input(usize),
    /// An rtl output (index into the output row).
    Output(usize),
    /// {par_qc, par_fine}: indices of par_qc and par_fine in the output row.
    Position(usize, usize),
}

/// The vcd crate's writer fills this buffer; [`TopTrace`] drains it into the output every
/// 64 KiB, so memory stays bounded and write errors surface where they happen.
#[derive(Clone, Default)]
struct Chunk(std::rc::Rc<std::cell::RefCell<Vec<u8>>>);

impl Write for Chunk {
    fn write(&mut self, b: &[u8]) -> std::io::Result<usize> {
        self.0.borrow_mut().extend_from_slice(b);
        Ok(b.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// A VCD being written, one call per clock cycle.
pub struct TopTrace {
    w: vcd::Writer<Chunk>,
    chunk: Chunk,
    out: Box<dyn Write>,
    vars: Vec<(IdCode, u32, Source)>,
    last: Vec<Option<u64>>,
    clk: Option<IdCode>,
    fine_bits: u32,
    period_ps: u64,
    cycle: u64,
}

impl TopTrace {
    /// Writes the header: scope `module`, one wire per entry of `top_ports` (name, width),
    /// each mapped onto the rtl's ports of the same name (`par_position` onto `par_qc` and
    /// `par_fine`); a clock of `period_ps`. Errors name an unmapped port.
    pub fn new(
        out: Box<dyn Write>,
        module: &str,
        top_ports: &[(String, u32)],
        rtl_inputs: &[Port],
        rtl_outputs: &[Port],
        fine_bits: u32,
        period_ps: u64,
    ) -> std::io::Result<TopTrace> {
        let find = |ports: &[Port], n: &str| ports.iter().position(|p| p.name == n);
        let chunk = Chunk::default();
        let mut w = vcd::Writer::new(chunk.clone());
        w.timescale(1, TimescaleUnit::PS)?;
        w.add_module(module)?;
        let mut vars = Vec::new();
        let mut clk = None;
        for (name, width) in top_ports {
            let src = if name == "clk" {
                Source::Clock
            } else if let Some(i) = find(rtl_inputs, name) {
                Source::Input(i)
            } else if let Some(i) = find(rtl_outputs, name) {
                Source::Output(i)
            } else if let Some(i) = find(rtl_outputs, &format!("{name}_0")) {
                // An optional output of the rtl (`par_velocity` is the rtl's
                // `par_velocity_0`).
                Source::Output(i)
            } else if name == "par_position" {
                match (find(rtl_outputs, "par_qc"), find(rtl_outputs, "par_fine")) {
                    (Some(q), Some(f)) => Source::Position(q, f),
                    _ => return Err(unmapped(name)),
                }
            } else {
                return Err(unmapped(name));
            };
            let id = w.add_wire(*width, name)?;
            if let Source::Clock = src {
                clk = Some(id);
            }
            vars.push((id, *width, src));
        }
        w.upscope()?;
        w.enddefinitions()?;
        let n = vars.len();
        let mut t = TopTrace {
            w,
            chunk,
            out,
            vars,
            last: vec![None; n],
            clk,
            fine_bits,
            period_ps,
            cycle: 0,
        };
        t.drain(0)?;
        Ok(t)
    }

    /// Moves the buffered text to the output once it holds more than `above` bytes.
    fn drain(&mut self, above: usize) -> std::io::Result<()> {
        let mut b = self.chunk.0.borrow_mut();
        if b.len() > above {
            self.out.write_all(&b)?;
            b.clear();
        }
        Ok(())
    }

    /// One clock cycle: the rtl's input row (as applied before the edge) and output row
    /// (after it). Only changed values are written.
    pub fn cycle(&mut self, inputs: &[u64], outputs: &[u64]) -> std::io::Result<()> {
        let t = self.cycle * self.period_ps;
        self.w.timestamp(t)?;
        if let Some(c) = self.clk {
            self.w.change_scalar(c, Value::V1)?;
        }
        for (k, (id, width, src)) in self.vars.iter().enumerate() {
            let raw = match *src {
                Source::Clock => continue,
                Source::Input(i) => inputs.get(i).copied().unwrap_or(0),
                Source::Output(i) => outputs.get(i).copied().unwrap_or(0),
                Source::Position(q, f) => {
                    let fine = outputs.get(f).copied().unwrap_or(0) & mask(self.fine_bits);
                    (outputs.get(q).copied().unwrap_or(0) << self.fine_bits) | fine
                }
            };
            let v = raw & mask(*width);
            if self.last[k] == Some(v) {
                continue;
            }
            self.last[k] = Some(v);
            if *width == 1 {
                self.w.change_scalar(*id, v & 1 == 1)?;
            } else {
                let bits: Vec<Value> = (0..*width)
                    .rev()
                    .map(|b| Value::from((v >> b) & 1 == 1))
                    .collect();
                self.w.change_vector(*id, &bits)?;
            }
        }
        if let Some(c) = self.clk {
            self.w.timestamp(t + self.period_ps / 2)?;
            self.w.change_scalar(c, Value::V0)?;
        }
        self.cycle += 1;
        self.drain(1 << 16)
    }

    /// Writes the final timestamp and flushes the output (call at the end of the run).
    pub fn finish(mut self) -> std::io::Result<()> {
        self.w.timestamp(self.cycle * self.period_ps)?;
        self.drain(0)?;
        self.out.flush()
    }
}

fn mask(w: u32) -> u64 {
    if w >= 64 {
        u64::MAX
    } else {
        (1u64 << w) - 1
    }
}

fn unmapped(name: &str) -> std::io::Error {
    std::io::Error::other(format!(
        "VCD: the top's port `{name}` has no counterpart in the rtl"
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cell::RefCell;
    use std::rc::Rc;

    /// A writer into a shared buffer.
    #[derive(Clone, Default)]
    struct Shared(Rc<RefCell<Vec<u8>>>);
    impl Write for Shared {
        fn write(&mut self, b: &[u8]) -> std::io::Result<usize> {
            self.0.borrow_mut().extend_from_slice(b);
            Ok(b.len())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn writes_only_changes_with_the_top_names_and_widths() {
        let buf = Shared::default();
        let top = [
            ("clk".to_string(), 1),
            ("a".to_string(), 1),
            ("b".to_string(), 4),
            ("par_position".to_string(), 5),
        ];
        let ins = [Port::new("a", 1)];
        let outs = [
            Port::new("b", 32),
            Port::new("par_qc", 32),
            Port::new("par_fine", 32),
        ];
        let mut t =
            TopTrace::new(Box::new(buf.clone()), "m_top", &top, &ins, &outs, 3, 1000).unwrap();
        t.cycle(&[0], &[3, 1, 2]).unwrap();
        t.cycle(&[0], &[3, 1, 2]).unwrap();
        // b is masked to its 4 bits; the position is {qc, fine} = 2 << 3 | 1.
        t.cycle(&[1], &[0x15, 2, 1]).unwrap();
        t.finish().unwrap();
        let v = String::from_utf8(buf.0.borrow().clone()).unwrap();
        assert!(v.contains("$scope module m_top $end"), "{v}");
        assert!(v.contains("$var wire 4 # b $end"), "{v}");
        assert!(v.contains("$var wire 5 $ par_position $end"), "{v}");
        assert!(
            v.contains("#0\n1!\n0\"\nb0011 #\nb01010 $\n#500\n0!\n"),
            "{v}"
        );
        assert!(v.contains("#1000\n1!\n#1500\n0!\n"), "{v}");
        assert!(v.contains("#2000\n1!\n1\"\nb0101 #\nb10001 $\n"), "{v}");
    }
}
