//! Self-checking Verilog testbench for `<name>_core`: stimulus and expected outputs come
//! from the bit-accurate Rust model (which the test suite proves equal to the RTL), so a user
//! can re-run the check in any Verilog simulator:
//!
//! ```text
//! iverilog -g2005 -o tb.vvp <name>_core.v <name>_core_tb.v && vvp -n tb.vvp
//! verilator --binary --timing --top-module <name>_core_tb <name>_core.v <name>_core_tb.v \
//!     && ./obj_dir/V<name>_core_tb
//! ```
//!
//! Both print PASS and exit 0, or print FAIL with the first mismatches and exit non-zero
//! (`$fatal`: vvp exits 1, the Verilator binary aborts), so a CI job can use the exit status.
//! `-g2012` works as well: no identifier is a SystemVerilog keyword (`tests/flow/testbench.rs`).
//!
//! Timing per cycle (the co-simulation harness's semantics): inputs change while `clk` is
//! low, `clk` rises, outputs are compared 1 ns after the edge.
use crate::blocks::core::model::{CoreIn, CoreModel};
use crate::blocks::mask;
use crate::blocks::velocity::model::{VelIn, VelocityModel};
use crate::config::Loaded;
use crate::cosim::stimulus;
use crate::cosim::Port;
use crate::emit::templates::render;
use crate::emit::{core_input_ports, core_name, core_output_ports};
use crate::error::Result;

/// Velocity update periods the rotation of a `[velocity] enabled` testbench lasts in each
/// direction (see [`testbench_stimulus`]).
pub const VELOCITY_TB_UPDATES: u64 = 4;

/// The stimulus the emitted testbench uses: directed cases, random samples with gaps and a
/// reset, and a rotation over a turn in each direction. With `[velocity] enabled`, then a
/// rotation at the ADC's sample spacing for [`VELOCITY_TB_UPDATES`] velocity update periods
/// in each direction (0.3 quadrant per sample forward, 0.21 backward), so that
/// `out_velocity` is checked over several updates, rising and falling (of both signs when the
/// estimator's loop is fast enough: `tests/flow/testbench.rs`).
pub fn testbench_stimulus(loaded: &Loaded) -> Vec<CoreIn> {
    let d = &loaded.derived;
    let a = d.adc_width;
    let mut s = stimulus::directed(a);
    s.extend(stimulus::random(a, 1000, 0.2, 0x5eed));
    let step = std::f64::consts::FRAC_PI_2 * 0.45;
    s.extend(stimulus::rotation(a, 0.7, 0.1, step, 200));
    s.extend(stimulus::rotation(a, 0.7, 0.1, -step, 200));
    if let Some(v) = &d.velocity {
        let spacing =
            ((d.clock_hz / d.sample_rate_hz).round() as u64).max(d.cycles_per_sample as u64);
        let n = (VELOCITY_TB_UPDATES * v.period_clocks).div_ceil(spacing) as usize;
        let step = std::f64::consts::FRAC_PI_2 * 0.3;
        for (dir, start) in [(1.0, 0.2), (-0.7, 0.4)] {
            for r in stimulus::rotation(a, 0.7, start, dir * step, n) {
                s.push(r);
                s.extend((1..spacing).map(|_| stimulus::idle()));
            }
        }
        // The last update's result is out within one period plus the estimator's latency.
        s.extend((0..v.period_clocks + v.latency()).map(|_| stimulus::idle()));
    }
    s.extend((0..d.latency_cycles + 2).map(|_| stimulus::idle()));
    s
}

/// The core's output ports the testbench checks: [`core_output_ports`], then
/// `out_velocity` and `out_velocity_valid` with `[velocity] enabled`.
pub fn testbench_output_ports(loaded: &Loaded) -> Vec<Port> {
    let d = &loaded.derived;
    let mut outs = core_output_ports(d);
    if let Some(v) = &d.velocity {
        outs.push(Port::new("out_velocity", v.spec.width));
        outs.push(Port::new("out_velocity_valid", 1));
    }
    outs
}

/// The expected outputs for `stim`, one row per cycle in [`testbench_output_ports`] order:
/// the core model's, then the velocity model's (`<name>_core` feeds the estimator the
/// core's registered strobe and low F + 2 position bits, so the model sees them one clock
/// later; the reset reaches both in the same clock).
pub fn testbench_expected(loaded: &Loaded, stim: &[CoreIn]) -> Vec<Vec<u64>> {
    let d = &loaded.derived;
    let mut core = CoreModel::new(d);
    let mut vel = d.velocity.as_ref().map(VelocityModel::new);
    let f2 = mask(d.fine_bits + 2);
    let mut prev = (false, 0);
    stim.iter()
        .map(|i| {
            let o = core.step(*i);
            let mut row = o.row();
            if let Some(m) = vel.as_mut() {
                let v = m.step(VelIn {
                    rst: i.rst,
                    valid: prev.0,
                    p: prev.1 & f2,
                });
                row.extend([v.velocity, v.valid as u64]);
            }
            prev = (o.valid, o.position);
            row
        })
        .collect()
}

/// Verilog text of `<name>_core_tb` (`rtl-templates/tb/core_tb.v.j2`). The stimulus and
/// the expected outputs are stored as change lists (the cycle at which a value starts and
/// the value, held until the next change), so a velocity run of many idle clocks stays
/// small; the outputs are still compared at every cycle.
pub fn core_testbench(loaded: &Loaded) -> Result<String> {
    let d = &loaded.derived;
    let stim = testbench_stimulus(loaded);
    let expected = testbench_expected(loaded, &stim);
    let ins = core_input_ports(d);
    let outs = testbench_output_ports(loaded);
    let am = mask(d.adc_width);
    let in_rows: Vec<Vec<u64>> = stim
        .iter()
        .map(|i| {
            vec![
                i.rst as u64,
                i.valid as u64,
                i.sin as u64 & am,
                i.cos as u64 & am,
            ]
        })
        .collect();
    // (cycle, bits) at every change, the first cycle always.
    let changes = |rows: &[Vec<u64>], ports: &[Port]| -> Vec<(usize, String)> {
        rows.iter()
            .enumerate()
            .filter(|(k, r)| *k == 0 || rows[k - 1] != **r)
            .map(|(k, r)| (k, bits(r, ports)))
            .collect()
    };
    let names = |ports: &[Port]| {
        ports
            .iter()
            .map(|p| p.name.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let list = |ports: &[Port]| -> Vec<minijinja::Value> {
        ports
            .iter()
            .map(|p| minijinja::context! { name => p.name.as_str(), width => p.width })
            .collect()
    };
    let conns = ins
        .iter()
        .chain(outs.iter())
        .map(|p| format!(".{0}({0})", p.name))
        .collect::<Vec<_>>()
        .join(", ");
    render(
        "tb/core_tb.v.j2",
        minijinja::context! {
            name => core_name(loaded),
            n => stim.len(),
            inputs => list(&ins),
            outputs => list(&outs),
            in_bits => ins.iter().map(|p| p.width).sum::<u32>(),
            out_bits => outs.iter().map(|p| p.width).sum::<u32>(),
            in_list => names(&ins),
            out_list => names(&outs),
            conns => conns,
            stim_changes => changes(&in_rows, &ins),
            out_changes => changes(&expected, &outs),
        },
    )
}

fn bits(values: &[u64], ports: &[Port]) -> String {
    values
        .iter()
        .zip(ports)
        .map(|(v, p)| format!("{:0w$b}", v & mask(p.width), w = p.width as usize))
        .collect::<Vec<_>>()
        .join("_")
}
