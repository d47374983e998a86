//! The hand-written wrappers around the rust-hdl modules: `<name>_core` with its exact port
//! widths, the sinewave and capacitive `<name>_top`, and the port list of the tops.
use super::{core_name, has_top, templates, top_name, verilog};
use crate::blocks::core::hdl::CoreRtl;
use crate::blocks::top::hdl::SD_TOP_PORTS;
use crate::blocks::top::ports::{Dir, Pin, TopPort};
use crate::config::Loaded;
use crate::error::{Error, Result};

/// The velocity estimator (`[velocity] enabled`) as the module `module`, exported from its
/// rust-hdl block, and the template values of its ports: `vel` (present), `vel_rtl` (the
/// module), `vm` (width - 1), `vmethod`, `vunit` (F + frac_bits) and `vrate` (updates per
/// second). Without it: None and `vel` false.
fn velocity_module(
    d: &crate::config::Derived,
    module: &str,
) -> Result<(Option<String>, minijinja::Value)> {
    let Some(p) = &d.velocity else {
        return Ok((None, velocity_ctx(d, module)));
    };
    let mut uut = crate::blocks::velocity::hdl::Velocity::new(p)?;
    rust_hdl::prelude::Block::connect_all(&mut uut);
    let body = verilog::export(&uut, "velocity", module)?;
    Ok((Some(body), velocity_ctx(d, module)))
}

/// The template values of the velocity ports (see [`velocity_module`]); `vel` false without
/// `[velocity] enabled`.
fn velocity_ctx(d: &crate::config::Derived, module: &str) -> minijinja::Value {
    let Some(p) = &d.velocity else {
        return minijinja::context! { vel => false };
    };
    minijinja::context! {
        vel => true,
        vel_rtl => module,
        vm => p.spec.width - 1,
        vmethod => p.spec.method.to_string(),
        vunit => p.spec.fine_bits + p.spec.frac_bits,
        vrate => format!("{:.1}", p.spec.clock_hz / p.period_clocks as f64),
    }
}

/// The wrapper that gives `<name>_core` its exact port widths
/// (`rtl-templates/core/core_wrapper.v.j2`).
fn core_wrapper(loaded: &Loaded, rtl: &str, vel: minijinja::Value) -> Result<String> {
    let d = &loaded.derived;
    let a = d.adc_width;
    let pad = |s: &str| {
        if a < 16 {
            format!("{{{}'d0, {s}}}", 16 - a)
        } else {
            s.to_string()
        }
    };
    let f = d.fine_bits;
    templates::render(
        "core/core_wrapper.v.j2",
        minijinja::context! {
            name => core_name(loaded),
            rtl => rtl,
            f => f,
            turns => turns_expr(d),
            n => d.iterations,
            ppr => loaded.config.encoder.ppr,
            lat => d.latency_cycles,
            thr => if d.cycles_per_sample == 1 {
                "one sample per clock".to_string()
            } else {
                format!(
                    "one sample per {} clocks (iterative CORDIC; hold samples off while in_ready is low)",
                    d.cycles_per_sample
                )
            },
            am => a - 1,
            pm => d.position_width - 1,
            tm => d.turns_width - 1,
            fm => f - 1,
            mt => d.multiturn_bits,
            qmax => d.quadrants_per_turn - 1,
            qb => d.quadrant_bits - 1,
            sin => pad("in_sin"),
            cos => pad("in_cos"),
            learn => d.harmonics.as_ref().is_some_and(|h| h.learn.is_some()),
            ..vel
        },
    )
}

/// Verilog of `<name>_core` (wrapper first, then the rust-hdl modules), without header.
pub fn core_verilog(loaded: &Loaded) -> Result<String> {
    let rtl_name = format!("{}_rtl", core_name(loaded));
    let mut uut = CoreRtl::new(&loaded.derived);
    rust_hdl::prelude::Block::connect_all(&mut uut);
    let body = verilog::export(&uut, "core", &rtl_name)?;
    let (vel, ctx) = velocity_module(&loaded.derived, &format!("{}_vel", core_name(loaded)))?;
    let wrapper = core_wrapper(loaded, &rtl_name, ctx)?;
    Ok(match vel {
        Some(v) => format!("{wrapper}\n{body}\n{v}"),
        None => format!("{wrapper}\n{body}"),
    })
}

/// The wrapper's comment for its reset input, which it synchronizes before the rtl
/// (`rtl-templates/top/rst_sync.v.j2`): the blocks leave reset `release` clock edges after
/// it falls.
fn rst_comment(release: u32) -> String {
    format!(
        "reset, active high, asynchronous: asserts at once; the blocks leave reset {release} clock edges after it falls"
    )
}

/// The register map's AXI4-Lite ports of `<name>_top` (`[registers] enabled`), then its
/// live flags: name, width, input.
pub const REG_PORTS: [(&str, u32, bool); 18] = [
    ("s_axi_awaddr", 8, true),
    ("s_axi_awvalid", 1, true),
    ("s_axi_awready", 1, false),
    ("s_axi_wdata", 32, true),
    ("s_axi_wstrb", 4, true),
    ("s_axi_wvalid", 1, true),
    ("s_axi_wready", 1, false),
    ("s_axi_bresp", 2, false),
    ("s_axi_bvalid", 1, false),
    ("s_axi_bready", 1, true),
    ("s_axi_araddr", 8, true),
    ("s_axi_arvalid", 1, true),
    ("s_axi_arready", 1, false),
    ("s_axi_rdata", 32, false),
    ("s_axi_rresp", 2, false),
    ("s_axi_rvalid", 1, false),
    ("s_axi_rready", 1, true),
    ("flags", crate::blocks::regmap::FLAGS_WIDTH, false),
];

/// Verilog expression of the turn count from the 32-bit `turns` word (M bits, or 0).
fn turns_expr(d: &crate::config::Derived) -> String {
    if d.multiturn_bits == 0 {
        "1'b0".to_string()
    } else {
        format!("turns[{}:0]", d.multiturn_bits - 1)
    }
}

/// Ports of `<name>_top` in declaration order as (name, width): the sinewave top's pins
/// ([`crate::config::board_ports`] in the wrapper's order) or the capacitive top's, then the
/// parallel bus; empty when the configuration has no board top. The VCD of `simulate` uses
/// these names and widths.
pub fn top_ports(loaded: &Loaded) -> Vec<(String, u32)> {
    let d = &loaded.derived;
    let one = |p: &str| (p.to_string(), 1u32);
    let mut v: Vec<(String, u32)> = if let Some(k) = &d.capacitive {
        let w = k.config.dac_width;
        crate::blocks::captop::hdl::CAP_TOP_PORTS
            .iter()
            .filter(|p| p.pin != Pin::Parallel)
            .map(|p| match p.pin {
                Pin::DacBus => (p.name.to_string(), w),
                _ => one(p.name),
            })
            .collect()
    } else if has_top(loaded) {
        let used: Vec<&str> = crate::config::board_ports(&loaded.config)
            .iter()
            .map(|p| p.0)
            .collect();
        SD_TOP_PORTS
            .iter()
            .filter(|t| used.contains(&t.name))
            .map(|t| one(t.name))
            .collect()
    } else {
        return Vec::new();
    };
    v.extend([
        one("par_valid"),
        ("par_position".into(), d.position_width),
        ("par_turns".into(), d.turns_width),
        ("par_fine".into(), d.fine_bits),
        one("par_error"),
    ]);
    if d.capacitive.is_none() {
        v.extend(crate::blocks::registry::enabled_ports(&loaded.config).map(|p| one(p.name)));
    }
    if let (Some(_), false) = (&d.registers, d.capacitive.is_some()) {
        v.extend(REG_PORTS.iter().map(|&(n, w, _)| (n.to_string(), w)));
    }
    if let (Some(_), false) = (&d.capture, d.capacitive.is_some()) {
        v.extend([
            one("cap_valid"),
            ("cap_position".into(), d.position_width),
            ("cap_turns".into(), d.turns_width),
            ("cap_fine".into(), d.fine_bits),
            ("cap_age".into(), crate::blocks::capture::AGE_BITS),
        ]);
        if let Some(p) = &d.velocity {
            v.push(("cap_velocity".into(), p.spec.width));
        }
    }
    v.push(one("par_warning"));
    if let (Some(p), false) = (&d.velocity, d.capacitive.is_some()) {
        v.extend([
            ("par_velocity".into(), p.spec.width),
            one("par_velocity_valid"),
        ]);
    }
    v
}

/// The template context of one wrapper port declaration: direction, range (8 columns;
/// `width` for a bus narrowed from the rtl's word), the name with its comma in 14 columns,
/// and the comment.
fn wrapper_port(t: &TopPort, width: Option<u32>) -> minijinja::Value {
    port_line(t.dir, width, t.name, t.comment)
}

/// One port line of a wrapper: direction, range, name and comment.
fn port_line(dir: Dir, width: Option<u32>, name: &str, comment: &str) -> minijinja::Value {
    let dir = if dir == Dir::Out { "output" } else { "input " };
    let range = match width {
        Some(w) => format!("[{}:0]  ", w - 1),
        None => " ".repeat(8),
    };
    minijinja::context! {
        dir => dir,
        range => range,
        name => format!("{:<14}", format!("{name},")),
        comment => comment,
    }
}

/// `items` separated by ", " and closed by `end`, on lines that start with `prefix` and
/// stay within 95 columns (an item longer than a line gets a line of its own).
fn wrap_list(items: &[impl AsRef<str>], prefix: &str, end: &str) -> String {
    let mut out = String::new();
    let mut line = String::from(prefix);
    for (i, item) in items.iter().enumerate() {
        let sep = if i + 1 < items.len() { "," } else { end };
        let word = format!(" {}{sep}", item.as_ref());
        if line.len() > prefix.len() && line.len() + word.len() > 95 {
            out.push_str(&line);
            out.push('\n');
            line = String::from(prefix);
        }
        line.push_str(&word);
    }
    out.push_str(&line);
    out
}

/// Verilog of `<name>_top` (sinewave path, every ADC preset), without header; None for the
/// capacitive path (see [`cap_top_verilog`]).
///
/// The wrapper declares only the ports the configuration uses (see
/// [`crate::config::board_ports`]): `qep_a/b/z` with `[qep] enabled`, `ssi_*` and `enc_*`
/// with the SSI / SPI slave, and each deselect line (`dac_cs`, `dac_clr`, `spi_ss_b`,
/// `sf_ce0`) only when `[board.pins]` pins it. The rtl's inputs of the ports left out are
/// tied to their idle level (`qep_*` 0, `ssi_clk` 1, `enc_cs_n` 1, `enc_sck` 0) and its
/// outputs left unconnected, so no output without a LOC reaches a package pin.
pub fn top_verilog(loaded: &Loaded) -> Result<Option<String>> {
    let d = &loaded.derived;
    if !has_top(loaded) {
        return Ok(None);
    }
    let name = top_name(loaded);
    let rtl_name = format!("{name}_rtl");
    let mut uut = crate::blocks::top::hdl::TopRtl::new(d)?;
    rust_hdl::prelude::Block::connect_all(&mut uut);
    let body = verilog::export(&uut, "top", &rtl_name)?;
    let f = d.fine_bits;
    let turns = turns_expr(d);
    let used: Vec<&str> = crate::config::board_ports(&loaded.config)
        .iter()
        .map(|p| p.0)
        .collect();
    if let Some(p) = used.iter().find(|p| {
        !SD_TOP_PORTS.iter().any(|t| t.name == **p)
            && crate::blocks::registry::port_owner(p).is_none()
    }) {
        return Err(Error::Export(format!(
            "{name}: the pinned port {p} has no place in the wrapper"
        )));
    }
    // The wrapper's ports and the rtl's connections, from the top's port table: a port the
    // configuration uses is a wrapper port; a left-out input is tied to its idle level, a
    // left-out output left open; the parallel bus goes to the wrapper's wires.
    let mut decl = Vec::new();
    let mut conns: Vec<String> = vec![];
    let mut left_out: Vec<&str> = vec![];
    for t in SD_TOP_PORTS {
        let p = t.name;
        let input = t.dir != Dir::Out;
        if t.pin == Pin::Parallel {
            conns.push(format!(".{p}({})", t.net));
        } else if p == "rst" {
            // The rtl's reset is the synchronizer's output (the wrapper's `rst` is
            // asynchronous).
            decl.push(port_line(
                t.dir,
                None,
                p,
                &rst_comment(crate::blocks::top::hdl::TOP_RESET_RELEASE_CLOCKS),
            ));
            conns.push(".rst(rst_sync[1])".into());
        } else if used.contains(&p) {
            decl.push(wrapper_port(t, None));
            conns.push(format!(".{p}({})", t.net));
        } else if input {
            if t.pin == Pin::Always {
                return Err(Error::Export(format!(
                    "{name}: the required input {p} is not a port of the wrapper"
                )));
            }
            conns.push(format!(".{p}(1'b{})", t.idle));
            left_out.push(p);
        } else {
            conns.push(format!(".{p}()"));
            left_out.push(p);
        }
    }
    // The rtl's optional velocity outputs (its estimator, `[velocity] enabled`).
    if d.velocity.is_some() {
        conns.push(".par_velocity_0(velocity)".into());
        conns.push(".par_velocity_valid_0(par_velocity_valid)".into());
    }
    // The register map's AXI4-Lite ports (`[registers] enabled`): the rtl's words to the
    // wrapper's narrower ports.
    if d.registers.is_some() {
        conns.extend(
            [
                ".s_axi_awaddr_0({24'd0, s_axi_awaddr})",
                ".s_axi_awvalid_0(s_axi_awvalid)",
                ".s_axi_wdata_0(s_axi_wdata)",
                ".s_axi_wstrb_0({28'd0, s_axi_wstrb})",
                ".s_axi_wvalid_0(s_axi_wvalid)",
                ".s_axi_bready_0(s_axi_bready)",
                ".s_axi_araddr_0({24'd0, s_axi_araddr})",
                ".s_axi_arvalid_0(s_axi_arvalid)",
                ".s_axi_rready_0(s_axi_rready)",
                ".s_axi_awready_0(s_axi_awready)",
                ".s_axi_wready_0(s_axi_wready)",
                ".s_axi_bresp_0(axi_bresp_w)",
                ".s_axi_bvalid_0(s_axi_bvalid)",
                ".s_axi_arready_0(s_axi_arready)",
                ".s_axi_rdata_0(s_axi_rdata)",
                ".s_axi_rresp_0(axi_rresp_w)",
                ".s_axi_rvalid_0(s_axi_rvalid)",
                ".flags_0(flags_w)",
            ]
            .map(String::from),
        );
    }
    // The capture's outputs (`[capture] enabled`) to the wrapper's full-width wires.
    if d.capture.is_some() {
        conns.extend(
            [
                ".cap_valid_0(cap_valid)",
                ".cap_qc_0(cap_qc_w)",
                ".cap_fine_0(cap_fine_w)",
                ".cap_turns_0(cap_turns_w)",
                ".cap_age_0(cap_age_w)",
            ]
            .map(String::from),
        );
        if d.velocity.is_some() {
            conns.push(".cap_velocity_0(cap_vel_w)".into());
        }
    }
    // The rtl's optional outputs of the enabled blocks (`abz_a_0` ... with `[abz] enabled`).
    let block_ports: Vec<_> = crate::blocks::registry::enabled_ports(&loaded.config).collect();
    conns.extend(block_ports.iter().map(|p| format!(".{0}_0({0})", p.name)));
    let inst = wrap_list(&conns, "       ", "");
    let vel_ctx = velocity_ctx(d, &format!("{name}_vel"));
    // The ports left out, as comment lines of at most 95 characters (empty: none).
    let left_out_lines = if left_out.is_empty() {
        String::new()
    } else {
        wrap_list(&left_out, "//", ".")
    };
    let wrapper = templates::render(
        "top/sinewave_top.v.j2",
        minijinja::context! {
            name => name,
            left_out => left_out_lines,
            ports => decl,
            rtl_name => rtl_name,
            inst => inst,
            turns => turns,
            f => f,
            rate => format!("{:.0}", d.sample_rate_hz),
            chip => d.adc.chip.to_string(),
            preamp => d.preamp.is_some(),
            block_ports => block_ports
                .iter()
                .map(|p| port_line(p.dir, None, p.name, p.comment))
                .collect::<Vec<_>>(),
            pm => d.position_width - 1,
            tm => d.turns_width - 1,
            fm => f - 1,
            qb => d.quadrant_bits - 1,
            cap => d.capture.is_some(),
            regs => d.registers.is_some(),
            flm => crate::blocks::regmap::FLAGS_WIDTH - 1,
            cap_extra => if d.capture.is_some_and(|c| c.extrapolation().is_some()) {
                " (extrapolated to the capture)"
            } else {
                ""
            },
            cap_turns => turns_expr(d).replace("turns", "cap_turns_w"),
            cap_am => crate::blocks::capture::AGE_BITS - 1,
            ..vel_ctx
        },
    )?;
    Ok(Some(format!("{wrapper}\n{body}")))
}

/// Verilog of the capacitive `<name>_top` (with `[capacitive]`), without header.
pub fn cap_top_verilog(loaded: &Loaded) -> Result<Option<String>> {
    let d = &loaded.derived;
    let Some(k) = &d.capacitive else {
        return Ok(None);
    };
    let name = top_name(loaded);
    let rtl_name = format!("{name}_rtl");
    let mut uut = crate::blocks::captop::hdl::CapTopRtl::new(d)?;
    rust_hdl::prelude::Block::connect_all(&mut uut);
    let body = verilog::export(&uut, "top", &rtl_name)?;
    let f = d.fine_bits;
    let turns = turns_expr(d);
    let w = k.config.dac_width;
    let table = crate::blocks::captop::hdl::CAP_TOP_PORTS;
    let decl: Vec<minijinja::Value> = table
        .iter()
        .filter(|t| t.pin != Pin::Parallel)
        .map(|t| match t.name {
            // The rtl's reset is the synchronizer's output; its blocks take it directly.
            "rst" => port_line(
                t.dir,
                None,
                t.name,
                &rst_comment(crate::blocks::top::hdl::RESET_SYNC_CLOCKS),
            ),
            _ => wrapper_port(t, (t.pin == Pin::DacBus).then_some(w)),
        })
        .collect();
    let conns: Vec<String> = table
        .iter()
        .map(|t| match t.name {
            "rst" => ".rst(rst_sync[1])".to_string(),
            _ => format!(".{}({})", t.name, t.net),
        })
        .collect();
    let wrapper = templates::render(
        "top/capacitive_top.v.j2",
        minijinja::context! {
            name => name,
            ports => decl,
            inst => wrap_list(&conns, "       ", ""),
            rtl_name => rtl_name,
            turns => turns,
            f => f,
            carrier => format!("{:.0}", k.config.carrier_hz),
            rate => format!("{:.0}", k.sample_rate_hz),
            wm => k.config.dac_width - 1,
            pm => d.position_width - 1,
            tm => d.turns_width - 1,
            fm => f - 1,
            qb => d.quadrant_bits - 1,
        },
    )?;
    Ok(Some(format!("{wrapper}\n{body}")))
}
