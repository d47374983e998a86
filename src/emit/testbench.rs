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

/// Conversions of the top testbench checked against the encoder after the warm-up (fewer,
/// but at least 20, when the run would last more than [`TOP_TB_MAX_CLOCKS`]).
pub const TOP_TB_SAMPLES: u64 = 100;

/// Samples the top testbench leaves unchecked after reset: the monitor's amplitude window
/// and the correction settle.
pub const TOP_TB_WARMUP: u64 = 16;

/// System clocks the checked samples of the top testbench fit in, so that Icarus finishes
/// the run in well under a minute (the run also lasts four BiSS-C frames with their
/// timeout; docs/verification.md gives the figures).
pub const TOP_TB_MAX_CLOCKS: u64 = 20_000;

/// Electrical periods of the encoder per conversion in the top testbench (before the
/// reversal; a quarter of the QEP-CORDIC's limit of one quadrant per sample is 1/16).
pub const TOP_TB_PERIODS_PER_SAMPLE: f64 = 1.0 / 50.0;

/// Signal amplitude of the top testbench at the ADC, fraction of full scale (the template's
/// `AMPLITUDE`).
pub const TOP_TB_AMPLITUDE: f64 = 0.75;

/// The bound on |decoded - true position| of the top testbench, in LSB of 2^-F quadrant:
/// four times the angle one ADC code spans at the test amplitude, plus the CORDIC's residual
/// angle 2^-N rad, plus 4 LSB for the rounding in the correction and the core.
pub fn top_tb_max_error_lsb(loaded: &Loaded) -> u64 {
    let d = &loaded.derived;
    let lsb_per_rad = (1u64 << d.fine_bits) as f64 / std::f64::consts::FRAC_PI_2;
    let amp_codes = TOP_TB_AMPLITUDE * (1u64 << (d.adc_width - 1)) as f64;
    let cordic = 2f64.powi(-(d.iterations as i32));
    ((4.0 / amp_codes + cordic) * lsb_per_rad + 4.0).ceil() as u64
}

/// Verilog text of `<name>_top_tb` (`rtl-templates/tb/top_tb.v.j2`) for the top wrapper
/// `top` (its ports are read from the text, [`crate::emit::flow::ports_of`]): the encoder,
/// the configured ADC as a timed model (the LTC6912-1 too with `[preamp]`), and a BiSS-C
/// master, checking `<name>_top` in real time. None for a capacitive top.
pub fn top_testbench(loaded: &Loaded, top: &str) -> Result<Option<String>> {
    use crate::blocks::top::hdl::SD_TOP_PORTS;
    let d = &loaded.derived;
    if d.capacitive.is_some() {
        return Ok(None);
    }
    let ports: Vec<(String, u32, bool)> = crate::emit::flow::ports_of(top)?
        .into_iter()
        .map(|p| (p.name, p.width, p.direction == "input"))
        .collect();
    let clk_ns = 1e9 / d.clock_hz;
    let io = &d.io_timing;
    let fs = d.sample_rate_hz;
    let ppr = loaded.config.encoder.ppr;
    let w_rad_s = std::f64::consts::TAU * TOP_TB_PERIODS_PER_SAMPLE * fs;
    let rpm = w_rad_s / (std::f64::consts::TAU * ppr as f64) * 60.0;
    // From the clock edge that raises CONV to the one that raises par_valid: the top's
    // CONV-to-position latency, counted from the first clock CONV is high, + 1 (`simulate`
    // matches its records the same way).
    let lat = crate::blocks::top::hdl::conv_to_position_cycles(d) as u64 + 1;
    let preamp_clocks = d
        .preamp
        .as_ref()
        .map_or(0, |p| 20 * p.half_period_clocks as u64);
    // The blocks leave reset TOP_RESET_RELEASE_CLOCKS after the wrapper's `rst` falls.
    let release = crate::blocks::top::hdl::TOP_RESET_RELEASE_CLOCKS as u64;
    let startup_ns =
        (10 + release + preamp_clocks + d.adc.startup_clocks() as u64 + lat) as f64 * clk_ns;
    let sample_ns = 1e9 / fs;
    let room = ((TOP_TB_MAX_CLOCKS as f64 * clk_ns - startup_ns) / sample_ns)
        .floor()
        .max(0.0) as u64;
    let checked = TOP_TB_SAMPLES
        .min(room.saturating_sub(TOP_TB_WARMUP))
        .max(20);
    // At least four BiSS-C frames (MA edges, their timeout and the gap) after the warm-up.
    let ma_half_ns = (8.0 * clk_ns).max(50.0);
    let frame_ns = (2 * d.biss.frame_rising_edges() + 6) as f64 * ma_half_ns
        + d.biss.timeout_clocks as f64 * clk_ns;
    let warm_ns = startup_ns + TOP_TB_WARMUP as f64 * sample_ns;
    let run_ns = (warm_ns + (checked + 2) as f64 * sample_ns).max(warm_ns + 4.2 * frame_ns);
    let t_rev_ns = startup_ns + (TOP_TB_WARMUP + checked / 2) as f64 * sample_ns;
    let t_rev_len_ns = (checked / 8) as f64 * sample_ns;
    let f = d.fine_bits;
    let q = (1u64 << f) as f64;
    let b = &d.biss;
    let frame = &d.adc.frame;
    let data_lines = if ports.iter().any(|p| p.0 == "adc_miso_b") {
        2
    } else {
        1
    };
    let port_list: Vec<minijinja::Value> = ports
        .iter()
        .filter(|(n, _, _)| n != "clk")
        .map(|(n, w, input)| {
            let idle = SD_TOP_PORTS
                .iter()
                .find(|t| t.name == n)
                .map_or(0, |t| t.idle);
            minijinja::context! {
                name => n,
                width => w,
                dir => if *input { "in" } else { "out" },
                idle => idle,
            }
        })
        .collect();
    let conns = ports
        .iter()
        .filter(|(n, _, _)| n != "clk")
        .map(|(n, _, _)| format!(".{n}({n})"))
        .collect::<Vec<_>>()
        .join(", ");
    let bit = |v: bool| if v { "1" } else { "0" };
    let (gain_a, gain_b) = d.preamp.as_ref().map_or((1, 1), |p| (p.gain_a, p.gain_b));
    let text = render(
        "tb/top_tb.v.j2",
        minijinja::context! {
            name => crate::emit::top_name(loaded),
            chip => d.adc.chip.to_string(),
            preamp => d.preamp.is_some(),
            gain_a => gain_a,
            gain_b => gain_b,
            gain_scale_a => format!("{:.1}", (gain_a as f64).abs()),
            gain_scale_b => format!("{:.1}", (gain_b as f64).abs()),
            ports => port_list,
            conns => conns,
            qep => ports.iter().any(|p| p.0 == "qep_a"),
            clk_ns => format!("{clk_ns:.4}"),
            pin_ns => format!("{:.3}", io.clock_to_out_ns + io.trace_ns),
            trace_ns => format!("{:.3}", io.trace_ns),
            setup_ns => format!("{:.3}", io.input_setup_ns),
            valid_ns => format!("{:.3}", d.adc.timing.data_valid_ns),
            ppr => ppr,
            rpm => format!("{rpm:.1}"),
            w_rad_ns => format!("{:.9e}", w_rad_s * 1e-9),
            t_rev_us => format!("{:.1}", t_rev_ns / 1e3),
            t_rev_ns => format!("{t_rev_ns:.1}"),
            t_rev_len_ns => format!("{t_rev_len_ns:.1}"),
            off_sin => d.correction.offset()[0],
            off_cos => d.correction.offset()[1],
            run_ns => format!("{run_ns:.1}"),
            ma_half_ns => format!("{ma_half_ns:.1}"),
            max_err => top_tb_max_error_lsb(loaded),
            min_checked => checked / 2,
            width => d.adc_width,
            f => f,
            pw => d.position_width,
            tw => d.turns_width,
            mt => d.multiturn_bits,
            lat => lat,
            warmup => TOP_TB_WARMUP,
            frame_sck => frame.frame_sck,
            channels => frame.channels,
            data_lines => data_lines,
            off0 => frame.offsets[0],
            off1 => frame.offsets[1],
            offset_binary => bit(frame.sign == crate::blocks::adc::SignFormat::OffsetBinary),
            cpol => bit(frame.cpol),
            cpha => bit(frame.cpha),
            conv_high => bit(frame.conv_active_high),
            // A chip select held over the frame (more than one clock active) frames it, as
            // `sim::spi_adc` reads the frame.
            cs_framing => bit(frame.conv_clocks > 1),
            pipeline => frame.pipeline,
            bn => b.data_bits(),
            bm => b.multiturn_bits,
            bv => b.velocity_bits,
            ba => b.ack_periods,
            gray => bit(b.gray),
            pbits => b.position_bits,
            drop => d.position_width - b.position_bits,
            timeout_clocks => b.timeout_clocks,
            lsb_per_rad => format!("{:.6}", q / std::f64::consts::FRAC_PI_2),
            turn_lsb => format!("{:.1}", d.quadrants_per_turn as f64 * q),
            range_lsb => format!("{:.1}", d.quadrants_per_turn as f64 * q * (1u64 << d.multiturn_bits) as f64),
            turned => format!("{:.1}", if d.preamp.is_some() { 2.0 * q } else { 0.0 }),
        },
    )?;
    Ok(Some(text))
}
