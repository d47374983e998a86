//! [`FitSolve`] in the co-simulation harness.
use super::*;

impl crate::cosim::step::Clocked for FitSolve {
    fn set_clock(&mut self, high: bool) {
        self.clk.next = Clock::from(high);
    }
}

/// The solver on its own in the co-simulation harness (`tests/blocks/correction_fit_solver.rs`
/// feeds it window sums at the limits of the module doc's bounds).
impl crate::cosim::CosimBlock for FitSolve {
    fn input_ports(&self) -> Vec<crate::cosim::Port> {
        use crate::cosim::Port;
        vec![
            Port::new("rst", 1),
            Port::new("start", 1),
            Port::new("n", 32),
            Port::new("s1_s", 64),
            Port::new("s1_c", 64),
            Port::new("s2_s", 64),
            Port::new("s2_c", 64),
            Port::new("ssc", 64),
            Port::new("bref_s", 32),
            Port::new("bref_c", 32),
        ]
    }
    fn output_ports(&self) -> Vec<crate::cosim::Port> {
        use crate::cosim::Port;
        vec![
            Port::new("busy", 1),
            Port::new("done", 1),
            Port::new("off_s", 32),
            Port::new("off_c", 32),
            Port::new("g_s", 16),
            Port::new("g_c", 16),
            Port::new("k_mag", 16),
            Port::new("k_neg", 1),
        ]
    }
    fn apply(&mut self, r: &[u64]) {
        self.rst.next = r[0] != 0;
        self.start.next = r[1] != 0;
        self.n.next = Bits::<32>::from(r[2] & mask(32));
        self.s1_s.next = Bits::<64>::from(r[3]);
        self.s1_c.next = Bits::<64>::from(r[4]);
        self.s2_s.next = Bits::<64>::from(r[5]);
        self.s2_c.next = Bits::<64>::from(r[6]);
        self.ssc.next = Bits::<64>::from(r[7]);
        self.bref_s.next = Bits::<32>::from(r[8] & mask(32));
        self.bref_c.next = Bits::<32>::from(r[9] & mask(32));
    }
    fn sample(&self) -> Vec<u64> {
        vec![
            self.busy.val() as u64,
            self.done.val() as u64,
            self.off_s.val().to_u64(),
            self.off_c.val().to_u64(),
            self.g_s.val().to_u64(),
            self.g_c.val().to_u64(),
            self.k_mag.val().to_u64(),
            self.k_neg.val() as u64,
        ]
    }
}
