//! The fallback: the levelized netlist interpreted cell by cell, with the same cell
//! semantics (src/engine/ops.rs) and the same cycle as the generated code.
use super::netlist::{Cell, Netlist, Op, Operand};
use super::ops;
use super::Sim;

/// The interpreter's state: one word per signal, the memories.
pub struct Interp {
    nl: Netlist,
    vals: Vec<u64>,
    mems: Vec<Vec<u64>>,
    outs: Vec<u64>,
    next: Vec<u64>,
}

impl Interp {
    /// Registers and memories at their initial values, inputs 0, outputs evaluated.
    pub fn new(nl: Netlist) -> Interp {
        let mut vals = vec![0; nl.signals.len()];
        for r in &nl.regs {
            vals[r.q] = r.init;
        }
        let mems = nl.mems.iter().map(|m| m.init.clone()).collect();
        let mut s = Interp {
            outs: vec![0; nl.outputs.len()],
            next: vec![0; nl.regs.len()],
            nl,
            vals,
            mems,
        };
        s.eval();
        s
    }

    fn operand(&self, o: &Operand) -> u64 {
        o.chunks.iter().fold(o.konst, |acc, c| {
            acc | (((self.vals[c.sig] >> c.lo) & ops::mask(c.width)) << c.at)
        })
    }

    fn cell(&self, c: &Cell) -> u64 {
        let a = self.operand(&c.a);
        let (aw, asg, bw, bsg, yw) = (c.a.width, c.a_signed, c.b.width, c.b_signed, c.y_width);
        match c.op {
            Op::Unary(op) => ops::unary(op, a, aw, asg, yw),
            Op::Arith(op) => ops::arith(op, a, aw, asg, self.operand(&c.b), bw, bsg, yw),
            Op::Compare(op) => {
                ops::compare(op, a, aw, asg, self.operand(&c.b), bw, bsg) & ops::mask(yw)
            }
            Op::Logic(op) => ops::logic(op, a, aw, self.operand(&c.b)),
            Op::Shift(op) => ops::shift(op, a, aw, asg, self.operand(&c.b), bw, bsg, yw),
            Op::Mux => {
                if self.operand(&c.s) != 0 {
                    self.operand(&c.b)
                } else {
                    a
                }
            }
            Op::Pmux => {
                let s = self.operand(&c.s);
                if s == 0 {
                    a
                } else {
                    c.words
                        .get(s.trailing_zeros() as usize)
                        .map_or(0, |w| self.operand(w))
                }
            }
            Op::MemRead(k) => {
                let idx = a as i64 - self.nl.mems[k].offset;
                usize::try_from(idx)
                    .ok()
                    .and_then(|i| self.mems[k].get(i).copied())
                    .unwrap_or(0)
            }
        }
    }

    fn run_cone(&mut self, next: bool) {
        let cone = if next {
            std::mem::take(&mut self.nl.next_cone)
        } else {
            std::mem::take(&mut self.nl.out_cone)
        };
        for &i in &cone {
            let v = self.cell(&self.nl.cells[i]);
            let out = self.nl.cells[i].out;
            self.vals[out] = v;
        }
        if next {
            self.nl.next_cone = cone;
        } else {
            self.nl.out_cone = cone;
        }
    }
}

impl Sim for Interp {
    fn restart(&mut self) {
        *self = Interp::new(self.nl.clone());
    }

    fn set(&mut self, input: usize, v: u64) {
        if let Some(&(_, sig)) = self.nl.inputs.get(input) {
            self.vals[sig] = v & ops::mask(self.nl.signals[sig].width);
        }
    }

    fn get(&self, output: usize) -> u64 {
        self.outs.get(output).copied().unwrap_or(0)
    }

    fn eval(&mut self) {
        self.run_cone(false);
        for (k, (_, o)) in self.nl.outputs.iter().enumerate() {
            self.outs[k] = self.operand(o);
        }
    }

    fn tick(&mut self) {
        self.run_cone(true);
        for (k, r) in self.nl.regs.iter().enumerate() {
            let q = self.vals[r.q];
            let en =
                r.en.as_ref()
                    .is_none_or(|(o, pol)| (self.operand(o) != 0) == *pol);
            let rst = r.srst.as_ref().and_then(|(o, pol, v)| {
                ((self.operand(o) != 0) == *pol && (en || !r.ce_over_srst)).then_some(*v)
            });
            self.next[k] = match rst {
                Some(v) => v,
                None if en => self.operand(&r.d),
                None => q,
            };
        }
        for w in &self.nl.writes {
            let m = &self.nl.mems[w.mem];
            let idx = self.operand(&w.addr) as i64 - m.offset;
            let (data, en) = (self.operand(&w.data), self.operand(&w.en));
            if let Some(slot) = usize::try_from(idx)
                .ok()
                .and_then(|i| self.mems[w.mem].get_mut(i))
            {
                *slot = (*slot & !en) | (data & en);
            }
        }
        for (k, r) in self.nl.regs.iter().enumerate() {
            self.vals[r.q] = self.next[k];
        }
        self.eval();
    }

    fn run(&mut self, rows: &[u64], outs: &mut Vec<u64>) {
        let ni = self.nl.inputs.len().max(1);
        outs.clear();
        for row in rows.chunks(ni) {
            for (k, v) in row.iter().enumerate() {
                self.set(k, *v);
            }
            self.tick();
            outs.extend_from_slice(&self.outs);
        }
    }
}
