//! `[velocity] enabled` in the emitted files: `<name>_core` as `sinedec generate` writes it
//! (the wrapper wiring the decoder's position strobe and low F+2 position bits into the
//! estimator) runs in Icarus and Verilator, and its `out_velocity` / `out_velocity_valid`
//! equal the bit-accurate chain CoreModel -> VelocityModel cycle for cycle, for every
//! method, through a rotation each way and a reset; `<name>_top` gets `par_velocity*`;
//! without `[velocity]` neither file has any velocity logic.
use sinedec::blocks::core::model::{CoreIn, CoreModel};
use sinedec::blocks::mask;
use sinedec::blocks::velocity::model::{VelIn, VelocityModel};
use sinedec::config::{Loaded, DEFAULT_CONFIG};
use sinedec::cosim::stimulus;
use sinedec::cosim::{
    cosim_engine_kind, first_mismatch, run_engine_expecting, run_icarus_expecting,
    run_verilator_expecting, CosimSpec, Port,
};
use sinedec::emit::{core_input_ports, core_name, core_output_ports, core_verilog};
use sinedec::verify::stimulus_rows;

fn config(method: &str) -> Loaded {
    // 1 MHz updates (133 clocks) keep the run short; the loop bandwidth and the cut-off
    // scaled with the rate (the defaults are for 7.5 kHz), every other key at its default.
    let text = format!(
        "{DEFAULT_CONFIG}\n[velocity]\nenabled = true\nmethod = \"{method}\"\nrate_hz = 1e6\n\
         bandwidth_hz = 20000.0\ncutoff_hz = 100000.0\n"
    );
    Loaded::parse(&text, "velocity_core.toml").expect("config")
}

/// Samples every 102 clocks (the ADC's frame): a rotation forward, a reset, a rotation
/// backward, then idle clocks until the last update is out.
fn stimulus(a: u32) -> Vec<CoreIn> {
    let mut s = vec![stimulus::reset(), stimulus::reset()];
    let spaced = |rows: Vec<CoreIn>, s: &mut Vec<CoreIn>| {
        for r in rows {
            s.push(r);
            s.extend((0..101).map(|_| stimulus::idle()));
        }
    };
    let step = std::f64::consts::FRAC_PI_2 * 0.3;
    spaced(stimulus::rotation(a, 0.7, 0.1, step, 150), &mut s);
    s.push(stimulus::reset());
    spaced(stimulus::rotation(a, 0.7, 0.4, -step * 0.7, 150), &mut s);
    s.extend((0..400).map(|_| stimulus::idle()));
    s
}

/// The expected trace: the core model's outputs, then the velocity model fed with them one
/// clock later (the wrapper registers nothing in between: the estimator samples the core's
/// registered outputs at the next edge).
fn expected(l: &Loaded, ins: &[CoreIn]) -> Vec<Vec<u64>> {
    let d = &l.derived;
    let p = d.velocity.as_ref().expect("enabled");
    let mut core = CoreModel::new(d);
    let mut vel = VelocityModel::new(p);
    let f2 = mask(d.fine_bits + 2);
    let mut prev = None;
    ins.iter()
        .map(|i| {
            let o = core.step(*i);
            let (valid, pos) = match prev {
                Some((v, p)) => (v, p),
                None => (false, 0),
            };
            let v = vel.step(VelIn {
                rst: i.rst,
                valid,
                p: pos & f2,
            });
            prev = Some((o.valid, o.position));
            let mut row = o.row();
            row.extend([v.velocity, v.valid as u64]);
            row
        })
        .collect()
}

#[test]
fn emitted_core_velocity_equals_the_models_in_icarus_and_verilator() {
    for method in ["tracking", "kalman", "lsq", "diff_lpf"] {
        let l = config(method);
        let d = &l.derived;
        let p = d.velocity.as_ref().expect("enabled");
        let verilog = core_verilog(&l).expect("core");
        let top = core_name(&l);
        let ins = core_input_ports(d);
        let mut outs = core_output_ports(d);
        outs.extend([
            Port::new("out_velocity", p.spec.width),
            Port::new("out_velocity_valid", 1),
        ]);
        let spec = CosimSpec {
            verilog: &verilog,
            top: &top,
            clock: "clk",
            inputs: &ins,
            outputs: &outs,
        };
        let stim = stimulus(d.adc_width);
        let rows = stimulus_rows(&l, &stim);
        let want = expected(&l, &stim);
        // The models did something worth comparing: updates with non-zero velocity both ways.
        let vcol = outs.len() - 2;
        let strobes: Vec<i64> = want
            .iter()
            .filter(|r| r[vcol + 1] == 1)
            .map(|r| {
                let w = p.spec.width;
                ((r[vcol] << (64 - w)) as i64) >> (64 - w)
            })
            .collect();
        assert!(strobes.len() > 100, "{method}: {} updates", strobes.len());
        assert!(
            strobes.iter().any(|&v| v > 0) && strobes.iter().any(|&v| v < 0),
            "{method}: velocity of both signs"
        );
        let dir =
            std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("vel_core_{method}"));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("dir");
        let icarus = run_icarus_expecting(&spec, &rows, &dir, &want).expect("icarus ran");
        let verilator = run_verilator_expecting(&spec, &rows, &dir, &want).expect("verilator ran");
        let kind = cosim_engine_kind().expect("engine choice");
        let engine = run_engine_expecting(&spec, &rows, kind, &want).expect("engine ran");
        for (name, t) in [
            ("icarus", &icarus),
            ("verilator", &verilator),
            ("engine", &engine),
        ] {
            if let Some(m) = first_mismatch("model", &want, name, t, &outs) {
                panic!("{method}: {m}");
            }
        }
    }
}

#[test]
fn the_ports_come_only_with_velocity_enabled() {
    let off = Loaded::parse(DEFAULT_CONFIG, "d.toml").expect("default");
    let g = sinedec::emit::generate(&off, "test").expect("generate");
    for f in &g.files {
        assert!(!f.text.contains("velocity"), "{} mentions velocity", f.name);
    }
    let on = config("tracking");
    let g = sinedec::emit::generate(&on, "test").expect("generate");
    let text = |n: &str| {
        g.files
            .iter()
            .find(|f| f.name == n)
            .unwrap_or_else(|| panic!("{n}"))
            .text
            .clone()
    };
    let core = text("sd_core.v");
    assert!(
        core.contains("output wire signed [31:0]  out_velocity,"),
        "core ports"
    );
    assert!(core.contains("module sd_core_vel"), "estimator module");
    let top = text("sd_top.v");
    assert!(
        top.contains("output wire signed [31:0]  par_velocity,"),
        "top ports"
    );
    assert!(top.contains("par_velocity_valid"), "top strobe");
    // The estimator is inside the rust-hdl top (its rtl's optional outputs).
    assert!(
        top.contains("module sd_top_rtl_vel_0") && !top.contains("module sd_top_vel"),
        "estimator module in the top's rtl"
    );
    assert!(
        top.contains(".par_velocity_0(velocity)"),
        "rtl output wired"
    );
    // The instantiation template and the parameter file list them too.
    assert!(text("sd_inst.v").contains(".out_velocity      (out_velocity)"));
    assert!(text("sd_params.json").contains("\"velocity\""));
}
