//! The SDC and XDC of a top without `[board]` (`<name>_top.sdc`, `<name>_top.xdc`,
//! `src/emit/constraints.rs`): run through `tclsh` with stub procs for the constraint
//! commands of Quartus/Synopsys SDC and Vivado XDC that check every option (a misspelt
//! option, a non-numeric delay, a port the top lacks or a command outside the XDC subset
//! fails) and record what is constrained. Every port of the top but `clk` has an input or
//! output delay (min and max) or, when it enters through a synchronizer, a false path;
//! the clock period is the configured one and the delays are those of the one derivation
//! `check` prints (`sinedec::board::IoTiming`, `sinedec::board::adc_data_arrival`,
//! `AdcParams::capture_distance_clocks`). Every port of the port table has a constraint
//! rule, so a port added to the table without one fails here.
//!
//! `tclsh` comes from the `tcl` package (`scripts/test.sh` installs it with apt-get); the
//! tests fail with that hint when it is missing.
use sinedec::config::{Loaded, DEFAULT_CONFIG};
use sinedec::emit::generate;
use std::collections::{BTreeMap, BTreeSet};
use std::process::Command;

const INSTALL: &str = "apt-get install -y tcl (scripts/test.sh does this)";

/// The stub commands. `::ports` maps each port of the top to `{in|out width}`, `::xdc` is
/// 1 for an XDC (then the file runs in an interpreter that has only `set`, `list`, `expr`
/// and the constraint commands, the Tcl subset Vivado reads in an XDC). Each constraint is
/// printed as one line: `clock NAME PERIOD PORT`, `input_delay PORT max|min VALUE`,
/// `output_delay PORT max|min VALUE`, `false_from PORT`, `false_to PORT`,
/// `max_delay PORT VALUE`, `multicycle setup|hold PORT N`.
const STUBS: &str = r#"
proc fail {msg} { puts stderr "FAIL: $msg"; exit 3 }
set ::clocks {}
set ::rec {}
proc number {cmd v} {
    if {![string is double -strict $v]} { fail "$cmd: `$v` is not a number" }
    return $v
}
# Splits argv by the option spec (option -> flag | value): {found positional}.
proc options {cmd argv spec} {
    set found {}
    set pos {}
    for {set i 0} {$i < [llength $argv]} {incr i} {
        set a [lindex $argv $i]
        if {[string index $a 0] eq "-" && ![string is double -strict $a]} {
            if {![dict exists $spec $a]} { fail "$cmd: unknown option $a" }
            if {[dict exists $found $a]} { fail "$cmd: $a given twice" }
            if {[dict get $spec $a] eq "flag"} {
                dict set found $a 1
            } else {
                incr i
                if {$i >= [llength $argv]} { fail "$cmd: $a needs a value" }
                dict set found $a [lindex $argv $i]
            }
        } else {
            lappend pos $a
        }
    }
    return [list $found $pos]
}
proc get_ports {args} {
    if {[llength $args] != 1} { fail "get_ports: one list of names, got `$args`" }
    set out {}
    foreach p [lindex $args 0] {
        set bus [string match {*\[\*\]} $p]
        if {$bus} { set p [string range $p 0 end-3] }
        if {![dict exists $::ports $p]} { fail "get_ports: `$p` is not a port of the top" }
        set w [lindex [dict get $::ports $p] 1]
        if {$bus != ($w > 1)} { fail "get_ports: `$p` is $w bits: name a bus as name\[*\]" }
        lappend out $p
    }
    if {![llength $out]} { fail "get_ports: no port" }
    return [list PORTS {*}$out]
}
proc get_clocks {args} {
    if {[llength $args] != 1} { fail "get_clocks: one name, got `$args`" }
    set c [lindex $args 0]
    if {[lsearch -exact $::clocks $c] < 0} { fail "get_clocks: no clock `$c`" }
    return [list CLOCK $c]
}
proc objects {cmd v kind} {
    if {[lindex $v 0] ne $kind} { fail "$cmd: `$v` is not a $kind object" }
    return [lrange $v 1 end]
}
proc ports_dir {cmd ps dir} {
    foreach p $ps {
        if {[lindex [dict get $::ports $p] 0] ne $dir} { fail "$cmd: `$p` is not an ${dir}put" }
    }
}
proc create_clock {args} {
    lassign [options create_clock $args {-name value -period value -waveform value -add flag}] o pos
    if {![dict exists $o -period]} { fail "create_clock: no -period" }
    if {![dict exists $o -name]} { fail "create_clock: no -name" }
    set t [number create_clock [dict get $o -period]]
    if {$t <= 0} { fail "create_clock: period $t" }
    if {[llength $pos] != 1} { fail "create_clock: one port list, got `$pos`" }
    set ps [objects create_clock [lindex $pos 0] PORTS]
    ports_dir create_clock $ps in
    lappend ::clocks [dict get $o -name]
    foreach p $ps { lappend ::rec "clock [dict get $o -name] $t $p" }
}
proc io_delay {cmd dir kind argv} {
    lassign [options $cmd $argv {-clock value -max flag -min flag -add_delay flag -clock_fall flag -rise flag -fall flag}] o pos
    if {![dict exists $o -clock]} { fail "$cmd: no -clock" }
    objects $cmd [dict get $o -clock] CLOCK
    if {[llength $pos] != 2} { fail "$cmd: a delay and a port list, got `$pos`" }
    set v [number $cmd [lindex $pos 0]]
    set ps [objects $cmd [lindex $pos 1] PORTS]
    ports_dir $cmd $ps $dir
    set which {}
    if {[dict exists $o -max]} { lappend which max }
    if {[dict exists $o -min]} { lappend which min }
    if {![llength $which]} { set which {max min} }
    foreach p $ps { foreach w $which { lappend ::rec "$kind $p $w $v" } }
}
proc set_input_delay {args} { io_delay set_input_delay in input_delay $args }
proc set_output_delay {args} { io_delay set_output_delay out output_delay $args }
proc path_ends {cmd o} {
    set out {}
    foreach {opt dir what} {-from in from -to out to} {
        if {[dict exists $o $opt]} {
            set v [dict get $o $opt]
            if {[lindex $v 0] eq "CLOCK"} { continue }
            set ps [objects $cmd $v PORTS]
            ports_dir $cmd $ps $dir
            foreach p $ps { lappend out [list $what $p] }
        }
    }
    return $out
}
proc set_false_path {args} {
    lassign [options set_false_path $args {-from value -to value -through value -setup flag -hold flag}] o pos
    if {[llength $pos]} { fail "set_false_path: unexpected `$pos`" }
    if {![dict exists $o -from] && ![dict exists $o -to]} { fail "set_false_path: no -from or -to" }
    foreach e [path_ends set_false_path $o] { lappend ::rec "false_[lindex $e 0] [lindex $e 1]" }
}
proc set_max_delay {args} {
    lassign [options set_max_delay $args {-from value -to value -through value -datapath_only flag}] o pos
    if {[llength $pos] != 1} { fail "set_max_delay: one delay, got `$pos`" }
    set v [number set_max_delay [lindex $pos 0]]
    foreach e [path_ends set_max_delay $o] { lappend ::rec "max_delay [lindex $e 1] $v" }
}
proc set_multicycle_path {args} {
    lassign [options set_multicycle_path $args {-setup flag -hold flag -start flag -end flag -from value -to value -through value}] o pos
    if {[llength $pos] != 1 || ![string is integer -strict [lindex $pos 0]]} {
        fail "set_multicycle_path: one integer multiplier, got `$pos`"
    }
    if {[dict exists $o -setup] == [dict exists $o -hold]} { fail "set_multicycle_path: -setup or -hold" }
    set w [expr {[dict exists $o -setup] ? "setup" : "hold"}]
    foreach e [path_ends set_multicycle_path $o] { lappend ::rec "multicycle $w [lindex $e 1] [lindex $pos 0]" }
}
proc set_clock_uncertainty {args} {
    lassign [options set_clock_uncertainty $args {-from value -to value -setup flag -hold flag}] o pos
    if {[llength $pos] < 1} { fail "set_clock_uncertainty: no value" }
    number set_clock_uncertainty [lindex $pos 0]
}
proc derive_clock_uncertainty {args} {
    if {$::xdc} { fail "derive_clock_uncertainty is not an XDC command" }
    if {[llength $args]} { fail "derive_clock_uncertainty: unexpected `$args`" }
}
proc derive_pll_clocks {args} { if {$::xdc} { fail "derive_pll_clocks is not an XDC command" } }

set f [open $::file]
set text [read $f]
close $f
set commands {get_ports get_clocks create_clock set_input_delay set_output_delay set_false_path
    set_max_delay set_multicycle_path set_clock_uncertainty derive_clock_uncertainty derive_pll_clocks}
interp create x
if {$::xdc} {
    foreach c [x eval {info commands}] {
        if {$c ni {set list expr}} { x hide $c }
    }
}
foreach c $commands { interp alias x $c {} $c }
if {[catch {x eval $text} err]} { fail "the file does not run: $err" }
foreach r $::rec { puts $r }
"#;

/// `tclsh`, or a panic with the install hint.
fn tclsh() -> &'static str {
    let ok = Command::new("tclsh")
        .stdin(std::process::Stdio::null())
        .arg("/dev/null")
        .output();
    assert!(
        ok.is_ok_and(|o| o.status.success()),
        "tclsh not found; install it: {INSTALL}"
    );
    "tclsh"
}

/// Runs `text` (an SDC, or an XDC with `xdc`) through the stubs for a top with `ports`
/// (name -> (input, width)): the recorded constraints, or the stubs' complaint.
fn run_stubs(
    text: &str,
    xdc: bool,
    ports: &BTreeMap<String, (bool, u32)>,
    tag: &str,
) -> Result<Vec<String>, String> {
    let dir = crate::common::workdir(&format!("io_constraints_{tag}"));
    let file = dir.join("constraints.tcl");
    std::fs::write(&file, text).unwrap();
    let dict: String = ports
        .iter()
        .map(|(n, (i, w))| format!("{n} {{{} {w}}} ", if *i { "in" } else { "out" }))
        .collect();
    let script = format!(
        "set ::ports {{{dict}}}\nset ::xdc {}\nset ::file {{{}}}\n{STUBS}",
        xdc as u8,
        file.display()
    );
    let stubs = dir.join("stubs.tcl");
    std::fs::write(&stubs, script).unwrap();
    let o = Command::new(tclsh())
        .arg(&stubs)
        .output()
        .expect("tclsh runs");
    let out = String::from_utf8_lossy(&o.stdout).into_owned();
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    if o.status.success() && err.is_empty() {
        Ok(out.lines().map(str::to_string).collect())
    } else {
        Err(format!("{err}{out}"))
    }
}

/// The default config with the tables `on` enabled (`enabled = false` turned on, or the
/// table appended).
fn config_with(on: &[&str]) -> String {
    let mut text = DEFAULT_CONFIG.to_string();
    for t in on {
        let head = format!("\n[{t}]\n");
        match text.find(&head) {
            Some(at) => {
                let rest = &text[at..];
                let e = rest.find("enabled = false").expect("enabled key");
                text = format!(
                    "{}enabled = true{}",
                    &text[..at + e],
                    &rest[e + "enabled = false".len()..]
                );
            }
            None => text.push_str(&format!("{head}enabled = true\n")),
        }
    }
    text
}

/// The configs without `[board]` that have a `<name>_top`: the default one, one with
/// every optional interface of the top, and a generic 16-bit SPI ADC.
fn configs() -> Vec<(&'static str, Loaded)> {
    let mut v: Vec<(&'static str, Loaded)> = vec![
        ("default", DEFAULT_CONFIG.to_string()),
        ("all", config_with(&["ssi", "spi", "velocity", "abz"])),
    ]
    .into_iter()
    .map(|(tag, t)| {
        assert!(!t.contains("\n[board]"), "{tag} has a [board]");
        (tag, Loaded::parse(&t, "io.toml").expect("config"))
    })
    .collect();
    v.push(("generic", crate::common::cfg(14, 14, 16, 2048, 12)));
    v
}

/// The files of `loaded` by name.
fn files(loaded: &Loaded) -> BTreeMap<String, String> {
    generate(loaded, "test")
        .expect("generate")
        .files
        .into_iter()
        .map(|f| (f.name, f.text))
        .collect()
}

/// The ports of the emitted top, from its Verilog (`sinedec::emit::flow::ports_of`, the
/// parser of the instantiation template): name -> (input, width).
fn top_ports(files: &BTreeMap<String, String>) -> BTreeMap<String, (bool, u32)> {
    sinedec::emit::flow::ports_of(&files["sd_top.v"])
        .expect("ports")
        .into_iter()
        .map(|p| (p.name, (p.direction == "input", p.width)))
        .collect()
}

/// Inputs of the top that are asynchronous to `clk` and enter through a synchronizer
/// (docs/interfaces.md): a false path, no delay.
const SYNCHRONIZED: &[&str] = &[
    "biss_ma", "ssi_clk", "enc_sck", "enc_cs_n", "qep_a", "qep_b", "qep_z",
];

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 6e-4
}

#[test]
fn every_port_is_constrained_with_the_budget_check_prints() {
    for (tag, l) in configs() {
        let f = files(&l);
        let ports = top_ports(&f);
        let io = &l.derived.io_timing;
        let adc = &l.derived.adc;
        let t = 1e9 / l.config.clock.frequency_hz;
        let (adc_min, adc_max) = sinedec::board::adc_data_arrival(io, adc.timing.data_valid_ns);
        let c = adc.capture_distance_clocks();
        // The reset is false-pathed only when its comment says it is asynchronous.
        let top = &f["sd_top.v"];
        let rst_async = top
            .lines()
            .any(|x| x.contains(" rst,") && x.to_lowercase().contains("asynchronous"));
        for (ext, xdc) in [("sdc", false), ("xdc", true)] {
            let name = format!("sd_top.{ext}");
            let text = f.get(&name).unwrap_or_else(|| panic!("{tag}: no {name}"));
            assert!(
                text.starts_with("# Generated by sinedec") && text.contains("# Command: test"),
                "{tag} {name}: header\n{text}"
            );
            let rec = run_stubs(text, xdc, &ports, &format!("{tag}_{ext}"))
                .unwrap_or_else(|e| panic!("{tag} {name}: {e}\n{text}"));
            let mut seen: BTreeMap<&str, BTreeSet<String>> = BTreeMap::new();
            let mut clocks = 0;
            for r in &rec {
                let w: Vec<&str> = r.split(' ').collect();
                let v = |i: usize| w[i].parse::<f64>().unwrap();
                let what = format!("{tag} {name}: `{r}`");
                match w[0] {
                    "clock" => {
                        clocks += 1;
                        assert_eq!((w[1], w[3]), ("clk", "clk"), "{what}");
                        assert!(close(v(2), t), "{what}: period {t}");
                    }
                    "input_delay" if w[1].starts_with("adc_") => {
                        let want = if w[2] == "max" { adc_max } else { adc_min };
                        assert!(close(v(3), want), "{what}: want {want}");
                    }
                    "input_delay" => {
                        let want = if w[2] == "max" {
                            t - io.input_setup_ns
                        } else {
                            0.0
                        };
                        assert!(close(v(3), want), "{what}: want {want}");
                    }
                    "output_delay" => {
                        let want = if w[2] == "max" {
                            t - io.clock_to_out_ns
                        } else {
                            0.0
                        };
                        assert!(close(v(3), want), "{what}: want {want}");
                    }
                    "multicycle" => {
                        assert!(w[2].starts_with("adc_"), "{what}");
                        let want = if w[1] == "setup" { c } else { c - 1 };
                        assert_eq!(w[3], want.to_string(), "{what}");
                    }
                    "false_from" => {
                        let ok = SYNCHRONIZED.contains(&w[1]) || (w[1] == "rst" && rst_async);
                        assert!(ok, "{what}: a synchronous port is false-pathed");
                    }
                    _ => panic!("{what}: unexpected constraint"),
                }
                let port = if w[0] == "multicycle" { w[2] } else { w[1] };
                let kind = match w[0] {
                    "input_delay" | "output_delay" => format!("delay {}", w[2]),
                    k => k.to_string(),
                };
                seen.entry(ports.get_key_value(port).unwrap().0.as_str())
                    .or_default()
                    .insert(kind);
            }
            assert_eq!(clocks, 1, "{tag} {name}: one clock");
            for (p, (input, _)) in &ports {
                let got = seen.get(p.as_str()).cloned().unwrap_or_default();
                let want: BTreeSet<String> = if p == "clk" {
                    ["clock".to_string()].into()
                } else if SYNCHRONIZED.contains(&p.as_str()) || (p == "rst" && rst_async) {
                    ["false_from".to_string()].into()
                } else if *input && p.starts_with("adc_") && c > 1 {
                    ["delay max", "delay min", "multicycle"]
                        .map(String::from)
                        .into()
                } else {
                    ["delay max", "delay min"].map(String::from).into()
                };
                assert_eq!(got, want, "{tag} {name}: constraints of `{p}`\n{text}");
            }
        }
    }
}

#[test]
fn the_tcl_check_fails_on_a_broken_file() {
    let (_, l) = configs().remove(0);
    let f = files(&l);
    let ports = top_ports(&f);
    let sdc = &f["sd_top.sdc"];
    let xdc = &f["sd_top.xdc"];
    assert!(run_stubs(sdc, false, &ports, "broken_ok").is_ok());
    for (what, from, to, in_xdc) in [
        (
            "misspelt option",
            "-clock [get_clocks",
            "-clk [get_clocks",
            false,
        ),
        ("misspelt -max", "-max", "-mx", false),
        ("no number", "-min 0.000", "-min 0.0x0", false),
        (
            "unknown port",
            "[get_ports biss_ma]",
            "[get_ports biss_mx]",
            false,
        ),
        ("bus without [*]", "par_fine[*]", "par_fine", false),
        (
            "unbraced bus",
            "{par_valid par_position[*]",
            "par_valid {par_position[*]",
            false,
        ),
        (
            "unknown clock",
            "[get_clocks clk]",
            "[get_clocks sys]",
            false,
        ),
        (
            "output delay on an input",
            "-min 0.000 [get_ports biss_slo]",
            "-min 0.000 [get_ports biss_ma]",
            false,
        ),
        (
            "Tcl outside the XDC subset",
            "create_clock",
            "if {1} {}\ncreate_clock",
            true,
        ),
    ] {
        let text = if in_xdc { xdc } else { sdc };
        assert!(text.contains(from), "{what}: `{from}` not in the file");
        let broken = text.replacen(from, to, 1);
        let r = run_stubs(&broken, in_xdc, &ports, "broken");
        assert!(r.is_err(), "{what}: the broken file passes: {r:?}");
    }
    // A constraint left out (the BiSS MA false path) is caught by the coverage check.
    let broken = sdc.replace("set_false_path -from [get_ports biss_ma]\n", "");
    let rec = run_stubs(&broken, false, &ports, "broken_missing").expect("still valid Tcl");
    assert!(!rec.iter().any(|r| r.contains("biss_ma")));
}

#[test]
fn every_port_of_the_table_has_a_constraint_rule() {
    use sinedec::blocks::top::hdl::SD_TOP_PORTS;
    use sinedec::blocks::top::ports::Dir;
    for p in SD_TOP_PORTS {
        let t = sinedec::emit::port_timing(p.name, p.dir != Dir::Out, p.comment);
        assert!(
            t.is_some(),
            "port `{}` of SD_TOP_PORTS has no constraint rule",
            p.name
        );
    }
    // An unknown port is refused by name rather than left out.
    let top = "module t (\n    input  wire clk, // c\n    input  wire odd_in // o\n);\n";
    let e = sinedec::emit::constrained_ports(top)
        .unwrap_err()
        .to_string();
    assert!(e.contains("odd_in"), "{e}");
}

#[test]
fn only_a_top_without_board_gets_them() {
    let (_, l) = configs().remove(0);
    let f = files(&l);
    assert!(f.contains_key("sd_top.sdc") && f.contains_key("sd_top.xdc"));
    let kit = format!(
        "{DEFAULT_CONFIG}\n[board]\npreset = \"spartan3an-starter-kit\"\n[board.pins]\n\
         qep_a = \"H1\"\nqep_b = \"H2\"\nqep_z = \"H3\"\nbiss_ma = \"H4\"\nbiss_slo = \"H5\"\n"
    );
    let k = Loaded::parse(&kit, "kit.toml").expect("kit");
    let f = files(&k);
    assert!(f.contains_key("sd_top.ucf"));
    assert!(!f.contains_key("sd_top.sdc") && !f.contains_key("sd_top.xdc"));
    // Same config, same bytes.
    assert_eq!(files(&l), files(&l));
}
