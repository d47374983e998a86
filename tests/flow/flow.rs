//! The tool-flow files `generate` writes next to the Verilog (`src/emit/flow.rs`):
//! - `<name>_sinedec.core`: FuseSoC runs its `sim` target with Icarus and passes, and fails
//!   (non-zero exit) when one expected vector of the testbench is flipped; its `sim_top`
//!   target runs the top's testbench in Icarus and passes; its `synth`
//!   target sets up an ISE project for the kit (Spartan3A and Spartan3AN, xc3s700an,
//!   fgg484, -4, the UCF) and a Quartus project for the capacitive board (the SDC, the QSF
//!   sourced), checked in the project scripts edalize writes (`--setup`: no vendor tool
//!   runs), and sinedec's own ISE script (`<name>_ise.tcl`) and Quartus QSF/QPF say what
//!   edalize's scripts say (part, files, top, revision);
//! - `<name>_inst.v`: its instance of `<name>_core` compiles with Icarus against the core;
//! - `<name>_params.json`: the ports equal the testbench's port list and the derived
//!   parameters the library's.
//!
//! FuseSoC comes from PyPI (`scripts/test.sh` installs it into the tools' venv); the test
//! fails with the install command when it is missing.
use crate::common;

use sinedec::config::{Loaded, DEFAULT_CONFIG};
use sinedec::emit::{core_input_ports, core_output_ports, generate};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The `fusesoc` executable of the tools' venv (`common::venv_tool`).
fn fusesoc() -> PathBuf {
    common::venv_tool("fusesoc", "fusesoc==2.4.7")
}

/// Writes the generated files of `text` into a fresh `dir` and returns the generation.
fn write(text: &str, dir: &Path) -> sinedec::emit::Generation {
    let l = Loaded::parse(text, "flow.toml").expect("config");
    let g = generate(&l, "test").expect("generate");
    let _ = std::fs::remove_dir_all(dir);
    std::fs::create_dir_all(dir).unwrap();
    for f in &g.files {
        std::fs::write(dir.join(&f.name), &f.text).unwrap();
    }
    g
}

/// Runs fusesoc in `dir`; (success, combined output).
fn run_fusesoc(dir: &Path, args: &[&str]) -> (bool, String) {
    let o = Command::new(fusesoc())
        .arg("--cores-root")
        .arg(".")
        .args(args)
        .current_dir(dir)
        .output()
        .expect("fusesoc runs");
    (
        o.status.success(),
        format!(
            "{}{}",
            String::from_utf8_lossy(&o.stdout),
            String::from_utf8_lossy(&o.stderr)
        ),
    )
}

fn kit_config() -> String {
    format!(
        "{DEFAULT_CONFIG}\n[board]\npreset = \"spartan3an-starter-kit\"\n[board.pins]\n\
         qep_a = \"H1\"\nqep_b = \"H2\"\nqep_z = \"H3\"\nbiss_ma = \"H4\"\nbiss_slo = \"H5\"\n"
    )
}

const VLNV: &str = concat!("sinedec:generated:sd:", env!("CARGO_PKG_VERSION"));

#[test]
fn fusesoc_sim_passes_and_fails_on_a_mismatch() {
    let dir = common::workdir("flow_fusesoc_sim");
    write(&kit_config(), &dir);
    let (ok, out) = run_fusesoc(&dir, &["run", "--target", "sim", "--tool", "icarus", VLNV]);
    assert!(ok && out.contains("PASS: "), "{out}");
    // One expected bit flipped: the testbench reports it and the run fails.
    let tb = dir.join("sd_core_tb.v");
    let text = std::fs::read_to_string(&tb).unwrap();
    let at = text.find("expected[100] = ").expect("vector 100");
    let bit = at + text[at..].find("'b").unwrap() + 2;
    let flipped = if &text[bit..bit + 1] == "0" { "1" } else { "0" };
    let text = format!("{}{flipped}{}", &text[..bit], &text[bit + 1..]);
    std::fs::write(&tb, text).unwrap();
    let _ = std::fs::remove_dir_all(dir.join("build"));
    let (ok, out) = run_fusesoc(&dir, &["run", "--target", "sim", "--tool", "icarus", VLNV]);
    assert!(!ok, "a mismatch must fail the run: {out}");
    assert!(out.contains("FAIL: 1 mismatching cycles"), "{out}");
    // The top's testbench: its target runs it in Icarus (the default tool) and it passes.
    let (ok, out) = run_fusesoc(&dir, &["run", "--target", "sim_top", VLNV]);
    assert!(
        ok && out.contains("PASS: ") && out.contains("BiSS-C frames"),
        "{out}"
    );
}

/// A top without `[board]`: the core lists its SDC and XDC (fileset `top_constraints`,
/// FuseSoC file types SDC and xdc), and FuseSoC reads the core; a top with a board's
/// synthesis target lists its constraints there instead.
#[test]
fn fusesoc_core_lists_the_io_constraints_of_a_top_without_board() {
    let dir = common::workdir("flow_fusesoc_io");
    write(DEFAULT_CONFIG, &dir);
    let core = std::fs::read_to_string(dir.join("sd_sinedec.core")).expect("core");
    for line in [
        "  top_constraints:",
        "      - sd_top.sdc: {file_type: SDC}",
        "      - sd_top.xdc: {file_type: xdc}",
    ] {
        assert!(core.contains(line), "{line} missing:\n{core}");
    }
    assert!(dir.join("sd_top.sdc").is_file() && dir.join("sd_top.xdc").is_file());
    let (ok, out) = run_fusesoc(&dir, &["core-info", VLNV]);
    assert!(ok && out.contains("sim_top"), "{out}");
    let dir = common::workdir("flow_fusesoc_io_kit");
    write(&kit_config(), &dir);
    let core = std::fs::read_to_string(dir.join("sd_sinedec.core")).expect("core");
    assert!(!core.contains("top_constraints"), "{core}");
}

#[test]
fn fusesoc_synth_targets_set_up_the_vendor_projects() {
    // ISE for the kit: edalize's project script names the part and adds the sources.
    let dir = common::workdir("flow_fusesoc_ise");
    write(&kit_config(), &dir);
    let (ok, out) = run_fusesoc(&dir, &["run", "--setup", "--target", "synth", VLNV]);
    assert!(ok, "{out}");
    let build = dir.join("build/sinedec_generated_sd_0.1.0/synth-ise");
    let tcl = std::fs::read_dir(&build)
        .expect("ISE build directory")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "tcl"))
        .map(|p| std::fs::read_to_string(p).unwrap())
        .collect::<String>();
    for want in [
        "project set family \"Spartan3A and Spartan3AN\"",
        "project set device xc3s700an",
        "project set package fgg484",
        "project set speed -4",
        "sd_top.ucf",
        "sd_board.v",
        "sd_clock.v",
        "sd_top.v",
    ] {
        assert!(tcl.contains(want), "{want} not in the ISE script:\n{tcl}");
    }
    // sinedec's own ISE script (<name>_ise.tcl) says what edalize's says: the same part
    // lines, the same files, the same top.
    let ours = std::fs::read_to_string(dir.join("sd_ise.tcl")).expect("sd_ise.tcl");
    let src = "src/sinedec_generated_sd_0.1.0/";
    let mut files = 0;
    for line in ours.lines().filter(|l| !l.starts_with('#')) {
        if let Some(f) = line.strip_prefix("xfile add ") {
            files += 1;
            assert!(
                tcl.contains(&format!("xfile add {src}{f}"))
                    || tcl.contains(&format!("xfile_add_exist_ok {src}{f}")),
                "{f} is not in edalize's script:\n{tcl}"
            );
        } else if line.starts_with("project set ") {
            assert!(
                tcl.contains(line),
                "{line:?} is not in edalize's script:\n{tcl}"
            );
        }
    }
    assert_eq!(files, 4, "{ours}");
    assert!(ours.contains("project set top \"sd_board\""), "{ours}");
    // Quartus for the capacitive board: family, device, the SDC, the QSF sourced.
    let text = common::cap_board(Some("25e6"), "A1");
    let dir = common::workdir("flow_fusesoc_quartus");
    write(&text, &dir);
    let vlnv = VLNV.replace(":sd:", ":cap:");
    let (ok, out) = run_fusesoc(&dir, &["run", "--setup", "--target", "synth", &vlnv]);
    assert!(ok, "{out}");
    let build = dir.join("build/sinedec_generated_cap_0.1.0/synth-quartus");
    let tcl = std::fs::read_dir(&build)
        .expect("Quartus build directory")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "tcl"))
        .map(|p| std::fs::read_to_string(p).unwrap())
        .collect::<String>();
    for want in [
        "Cyclone III",
        "EP3C40F324C8",
        "cap_top.sdc",
        "cap_top.qsf",
        "cap_board.v",
        "cap_clock.v",
        "cap_top.v",
    ] {
        assert!(
            tcl.contains(want),
            "{want} not in the Quartus scripts:\n{tcl}"
        );
    }
    // The QSF names the same Verilog files as edalize's project script, and the QPF's
    // revision is the QSF.
    let qsf = std::fs::read_to_string(dir.join("cap_top.qsf")).unwrap();
    let ours: Vec<&str> = qsf
        .lines()
        .filter_map(|l| l.strip_prefix("set_global_assignment -name VERILOG_FILE "))
        .collect();
    assert_eq!(ours, ["cap_top.v", "cap_board.v", "cap_clock.v"], "{qsf}");
    for f in &ours {
        assert!(
            tcl.contains(&format!("VERILOG_FILE src/sinedec_generated_cap_0.1.0/{f}")),
            "{f} is not in edalize's script:\n{tcl}"
        );
    }
    let qpf = std::fs::read_to_string(dir.join("cap_top.qpf")).unwrap();
    assert!(qpf.contains("PROJECT_REVISION = \"cap_top\""), "{qpf}");
    assert!(qpf.contains("QUARTUS_VERSION = "), "{qpf}");
}

#[test]
fn instantiation_template_compiles_against_the_core() {
    let dir = common::workdir("flow_inst");
    let g = write(DEFAULT_CONFIG, &dir);
    let inst = &g
        .files
        .iter()
        .find(|f| f.name == "sd_inst.v")
        .expect("sd_inst.v")
        .text;
    // The sd_core instance, inside a module that declares its signals from the JSON.
    let start = inst.find("sd_core u_sd_core (").expect("core instance");
    let end = start + inst[start..].find(");").unwrap() + 2;
    let json: serde_json::Value = serde_json::from_str(
        &g.files
            .iter()
            .find(|f| f.name == "sd_params.json")
            .unwrap()
            .text,
    )
    .unwrap();
    let mut decl = String::new();
    for p in json["modules"][0]["ports"].as_array().unwrap() {
        let w = p["width"].as_u64().unwrap();
        let range = if w > 1 {
            format!("[{}:0] ", w - 1)
        } else {
            String::new()
        };
        decl.push_str(&format!(
            "    wire {range}{};\n",
            p["name"].as_str().unwrap()
        ));
    }
    std::fs::write(
        dir.join("check.v"),
        format!(
            "module inst_check;\n{decl}    {}\nendmodule\n",
            &inst[start..end]
        ),
    )
    .unwrap();
    let o = Command::new("iverilog")
        .args(["-g2005", "-Wall", "-s", "inst_check", "-o", "check.vvp"])
        .args(["sd_core.v", "check.v"])
        .current_dir(&dir)
        .output()
        .expect("iverilog (apt-get install iverilog)");
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(!err.contains("port") && !err.contains("width"), "{err}");
}

#[test]
fn params_json_lists_the_ports_and_the_derived_parameters() {
    let l = Loaded::parse(DEFAULT_CONFIG, "flow.toml").unwrap();
    let g = generate(&l, "test").unwrap();
    let text = &g
        .files
        .iter()
        .find(|f| f.name == "sd_params.json")
        .expect("sd_params.json")
        .text;
    let json: serde_json::Value = serde_json::from_str(text).expect("valid JSON");
    let d = &l.derived;
    assert_eq!(json["derived"]["latency_cycles"], d.latency_cycles);
    assert_eq!(json["derived"]["iterations"], d.iterations);
    assert_eq!(json["derived"]["position_width"], d.position_width);
    assert_eq!(json["derived"]["adc"]["period_clocks"], d.adc.period_clocks);
    assert_eq!(
        json["derived"]["atan_table"].as_array().unwrap().len(),
        d.atan_table.len()
    );
    // The core's ports: the testbench's list (names, widths) plus clk and in_ready.
    let core = &json["modules"][0];
    assert_eq!(core["module"], "sd_core");
    let ports: Vec<(String, u64, String)> = core["ports"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            (
                p["name"].as_str().unwrap().to_string(),
                p["width"].as_u64().unwrap(),
                p["direction"].as_str().unwrap().to_string(),
            )
        })
        .collect();
    let mut want: Vec<(String, u64, String)> = core_input_ports(d)
        .iter()
        .map(|p| (p.name.clone(), p.width as u64, "input".to_string()))
        .chain(
            core_output_ports(d)
                .iter()
                .map(|p| (p.name.clone(), p.width as u64, "output".to_string())),
        )
        .collect();
    want.push(("in_ready".into(), 1, "output".into()));
    want.push(("clk".into(), 1, "input".into()));
    let mut got = ports.clone();
    got.sort();
    want.sort();
    assert_eq!(got, want);
    // The top's port names are the ones the top declares.
    let top = &json["modules"][1];
    assert_eq!(top["module"], "sd_top");
    let names: Vec<&str> = top["ports"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["name"].as_str().unwrap())
        .collect();
    for (p, _) in sinedec::emit::top_ports(&l) {
        assert!(names.contains(&p.as_str()), "{p} missing from {names:?}");
    }
}
