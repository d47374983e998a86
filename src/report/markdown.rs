//! The Markdown report: the method notes under each table and the whole document.

use super::*;

impl Report {
    pub(super) fn methods(&self, loaded: &Loaded) -> Vec<(&'static str, String)> {
        let d = &loaded.derived;
        vec![
            (
                "sweep",
                format!(
                    "Accuracy: the bit-accurate model of the datapath (quadrant mapping, N CORDIC stages, rounding to F bits; `blocks::core::model::sample`, proven equal to the RTL by the co-simulation tests and cross-checked against the rust-hdl simulation by tests/report/report.rs) over {}. The error of a sample is its electrical angle minus atan2(sin, cos) of the same integer inputs in f64, in fine LSB (2^-F quadrant), wrapped into +-2 quadrants; max is the largest |error|, RMS the root of the mean square, mean the signed mean. Samples the magnitude monitor rejects are counted under `rejected` and left out. Sums are exact fixed-point integers (2^-40 LSB), so the figures do not depend on thread count.",
                    self.plan.describe()
                ),
            ),
            (
                "units",
                format!(
                    "1 LSB = 2^-F quadrant = 90/2^F electrical degrees; mechanical = electrical / PPR ({} PPR). ENOB (bits per electrical period) = F + 2 - log2(RMS x sqrt(12)): the bits of an ideal quantizer of one period with the same RMS error. Bits per turn from max error = log2(4 PPR 2^F / max LSB) = log2(360 deg / max mechanical error), the thesis's Table 2-2 way of turning a max error into a resolution (the thesis rounds it down).",
                    loaded.config.encoder.ppr
                ),
            ),
            (
                "predicted",
                "Residual bound: (2/pi) atan(2^-(N-1)) 2^F LSB, the angle N stages cannot resolve; the design's guarantee (README, tests/blocks/accuracy.rs) is max <= bound + 1 LSB for inputs of at least 1/8 full scale. Quantization RMS as ZipCPU's cordic generator estimates the phase variance (sw/cordiclib.cpp, phase_variance): 1/12 LSB^2 for the output quantization plus the squared rounding error of each angle-table entry (its table truncates; ours rounds, and our table errors are used). Predicted RMS adds the CORDIC residual as uniform within +-bound (bound^2/3). Neither estimate models the truncation of the x/y shifts (kept small by the guard bits).".into(),
            ),
            (
                "fpga",
                "FPGA resources: Yosys `synth_xilinx -family xc3sa -flatten` and `synth_intel -family cycloneive` through `sinedec::synth` (the project's design rules: no latch, `check -assert`, no unexpected warning). xc3sa LUT4 counts LUT1..LUT4 and INV; MUXCY are carry cells; cycloneive LE counts cycloneive_lcell_comb (its carry chain is inside the LE, so the carry column is 0). Multipliers: MULT18X18*, cycloneive_mac_mult*; block RAM: RAMB16*, cycloneive_ram_block* and altsyncram (M9K).".into(),
            ),
            (
                "gates",
                format!(
                    "Generic gate count: Yosys `synth -flatten -top T; abc -g {}; opt_clean; stat`. `gates` counts the two-input gates of that set, a 2:1 MUX counted as ONE gate (the MUX count is listed, so 3 per MUX can be computed: gates + 2 x MUX); inverters (NOT) and flip-flops are listed apart and not included. The thesis does not state how it counted its gates (most likely the ISE map report's equivalent gate count, which weighs LUTs and flip-flops differently): compare trends, not absolute values.",
                    yosys::GATE_SET
                ),
            ),
            (
                "depth",
                "Gate depth (not a timing figure): Yosys `ltp -noff` on the same generic netlist: the number of gates (MUX and NOT included, one level each) on the longest combinational path between flip-flops or ports. Generic gates are not FPGA cells (a carry chain of 20 bits is 40 or more gates here but one fast chain on the FPGA), so the depth says nothing about Fmax; see place_and_route and delay_model for timing. The path's start and end are listed per N.".into(),
            ),
            (
                "place_and_route",
                {
                    let per_net: Vec<f64> = self
                        .rows
                        .iter()
                        .map(|r| &r.ecp5)
                        .chain(self.blocks.iter().filter_map(|b| b.ecp5.as_ref()))
                        .filter_map(|t| t.routing_per_net_ns())
                        .collect();
                    let mean = per_net.iter().sum::<f64>() / per_net.len().max(1) as f64;
                    format!(
                        "Post-route timing ({}): every design of this report (each N, both architectures, every block, the whole top) is synthesized with `synth_ecp5 -top T -json T.json` and placed and routed with nextpnr-ecp5 `{} --out-of-context --timing-allow-fail --seed S --freq {:.3}` (the configured clock) at seeds S = {}. ECP5 speed 6 is a LUT4 + carry-chain family faster than Spartan-3A -4 and Cyclone III C8, so these figures flatter the target FPGAs. A seed's Fmax is the last `Max frequency` of its log (after routing), for register-to-register paths; one seed moves about +-6 % on the same netlist, so the figure is the median of the seeds, and the critical path is that of the median seed. The timing rule (docs/timing.md): median >= {} x the clock and every seed >= {} x. Slack = clock period - 1/median (negative: the configured clock fails). The critical path's start and end are named by block: nextpnr's cell names keep the RTL register names (`rtl.counter.usum_TRELLIS_FF_Q_3` is register `usum` of block `counter`); `(top level)` is a register named after a port of the top. The full register names are in the list below and in the JSON's `details`. Out of context, ports are not timed, so paths from and to the pins are not included. Results are cached by design hash. Mean routing delay per routed net on this report's critical paths: {:.3} ns over {} paths (the calibration of delay_model, docs/timing.md).",
                        self.ecp5_version,
                        nextpnr::DEVICE_ARGS.join(" "),
                        d.clock_hz / 1e6,
                        nextpnr::SEEDS
                            .iter()
                            .map(|s| s.to_string())
                            .collect::<Vec<_>>()
                            .join(", "),
                        nextpnr::MEDIAN_MARGIN,
                        nextpnr::SEED_MARGIN,
                        mean,
                        per_net.len(),
                    )
                },
            ),
            (
                "delay_model",
                {
                    let m = |x: &levels::DelayModel| {
                        format!(
                            "{}: clock-to-out {} ps, setup {} ps, LUT {} ps, carry entry {} ps, carry per bit {} ps, carry to sum {} ps, MUXF {} ps, multiplier {} ps, block RAM clock-to-out {} ps, routing {} ps per net",
                            x.name, x.tcko_ps, x.tsu_ps, x.lut_ps, x.carry_entry_ps, x.carry_bit_ps, x.carry_sum_ps, x.mux_ps, x.mult_ps, x.ram_tco_ps, x.route_ps
                        )
                    };
                    format!(
                        "xc3sa and cycloneive timing is estimated, not measured: the worst register-to-register path of the mapped netlist of the same Yosys run as the resource counts (`write_json`, `sinedec::report::levels`), as LUT levels (LUT1..4, INV; a Cyclone LE's LUT), carry bits (every MUXCY or LE carry step on the path, the entry included) and carry chains entered, with an estimated Fmax = 1 / (clock-to-out + cells + routing + setup). Routing through dedicated slice/LE connections (LUT to carry, along the carry, LUT or XORCY into the flip-flop beside it) is free; every other net costs the routing figure, calibrated against the nextpnr-ecp5 critical paths (docs/timing.md). Cell delays from the data sheets (docs/timing.md cites them): {}; {}. Yosys 0.23's cycloneive mapping builds adders from LUTs (no carry chain), so its carry columns are 0 and its LUT levels are high: Quartus would use the LE carry chain, so the Cyclone III estimate is pessimistic for arithmetic paths.",
                        m(&levels::XC3SA_4),
                        m(&levels::CYCLONE3_C8)
                    )
                },
            ),
            (
                "timing",
                format!(
                    "Latency: cycles from the in_valid cycle to the out_valid cycle of `<name>_core` (unrolled: N + 2, one stage per iteration, the combiner and the counter; iterative: S + 2 with S = N·ceil(W/4) digit clocks), in ns at the configured clock of {:.3} MHz. Throughput: samples per second the core accepts: the clock for the unrolled CORDIC (one sample per clock), the clock / S for the iterative one (cordic.architecture = {}).",
                    d.clock_hz / 1e6,
                    d.architecture
                ),
            ),
            (
                "architectures",
                {
                    let own = d.architecture;
                    let other = other_architecture(own);
                    let failed: Vec<String> = self
                        .rows
                        .iter()
                        .filter_map(|r| r.other.rejected().map(|e| format!("N = {}: {e}", r.n)))
                        .collect();
                    format!(
                        "For every N the core is synthesized a second time with cordic.architecture = \"{}\" (the configured one is \"{}\": its columns repeat the main table's), for xc3sa and cycloneive with the same scripts and cache. Latency is N + 2 cycles unrolled and S + 2 iterative (S = N·ceil(W/4): the iterative core is digit-serial, 4 bits per clock); throughput is the configured clock ({:.3} MHz) divided by the clocks per accepted sample (1 unrolled, S iterative). The ratio is iterative / unrolled xc3sa LUT4. The accuracy is identical for both architectures (their outputs are bit-identical for every input, proven by tests/blocks/iterative.rs), so the accuracy sweep is not repeated: the accuracy columns hold for both. {}",
                        arch_name(other),
                        arch_name(own),
                        d.clock_hz / 1e6,
                        if failed.is_empty() {
                            "Both architectures derived for every N.".to_string()
                        } else {
                            format!(
                                "Cells left empty where the other architecture could not be derived for this configuration: {}.",
                                failed.join("; ")
                            )
                        }
                    )
                },
            ),
            (
                "blocks",
                format!(
                    "Blocks of {}: each block of the sinewave top with the configured parameters, exported alone by `emit::verilog::export` as `<name>_blk_<key>` and synthesized like the core (all its ports are module ports, so logic the top ties off or shares is counted here: the rows do not add up to the top's). The core row is `CoreRtl` (mapper, CORDIC, combiner and quadrant counter; the configured N = {} and architecture) with the ports the top uses (the counter's resynchronisation inputs from the QEP fallback, the CORDIC magnitude to the monitor); the per-N tables measure `<name>_core` as `sinedec generate` writes it, which ties those inputs off and leaves the magnitude open, so its figures are smaller. The counter row is the quadrant counter alone. Blocks disabled in the config (SSI, SPI slave, QEP fallback) are built with the parameters they would get and marked so. The last row is `{}` as `sinedec generate` writes it. Timing: latency and clocks per sample where the block has them (the ADC's frame and sample rate, the core's N + 2 and throughput, the top's CONV-to-par_valid latency); serial slaves run on the master's clock. The blocks are also in `{}` and in the JSON's `blocks` array.",
                    crate::emit::top_name(loaded),
                    d.iterations,
                    crate::emit::top_name(loaded),
                    Report::file_names(&loaded.config.name)[7],
                ),
            ),
            (
                "thesis",
                format!(
                    "Rows marked `paper:` are the thesis's own figures for its own design (XC3S700AN, 14-bit ADC, {THESIS_PPR} PPR), not measured here. Table 3-2: gates and cycles of its unrolled QEP-CORDIC (6 + N cycles). Table 2-2: max error in MECHANICAL degrees for {THESIS_PPR} PPR; the text derives them from the max error as a fraction of a quadrant (+-0.24853 %, +-0.01552 %, +-3.8674e-5 at N = 8, 12, 14) times 360/2048/4. Method difference: the thesis simulated a floating-point CORDIC over one period at 2000 angles (0.18 deg apart), without input or output quantization, and its figures equal (2/pi) atan(2^-N) of a quadrant, the residual after N + 1 micro-rotations (i = 0..N); our N counts stages i = 0..N-1 (residual (2/pi) atan(2^-(N-1))), our figure is exhaustive over quantized {}-bit inputs and includes the rounding to F = {} bits, and our mechanical figures use the configured {} PPR. Compare the paper's N with our N + 1, and the % of a quadrant when the PPR differs.",
                    d.adc_width,
                    d.fine_bits,
                    loaded.config.encoder.ppr
                ),
            ),
        ]
    }

    pub(super) fn markdown(&self, loaded: &Loaded, opts: &Options, timestamp: &str) -> String {
        let d = &loaded.derived;
        let name = &loaded.config.name;
        let table = self.table(loaded);
        let mut s = crate::emit::header(
            loaded,
            &opts.command,
            "Report: timing (post-route ECP5, estimated xc3sa/Cyclone III), resources, gates and accuracy per CORDIC iteration count.",
            "<!--",
        )
        .lines()
        .map(|l| format!("{l} -->\n"))
        .collect::<String>();
        let ns: Vec<String> = self.rows.iter().map(|r| r.n.to_string()).collect();
        let _ = writeln!(
            s,
            "\n# {name}_core: QEP-CORDIC report for N = {}\n",
            ns.join(", ")
        );
        let _ = writeln!(s, "Generated: {timestamp}\n");
        let f = d.fine_bits;
        let ppr = loaded.config.encoder.ppr;
        let lsb_el = 90.0 * 3600.0 / (1u64 << f) as f64;
        let coarse = (d.quadrants_per_turn as f64).log2();
        let _ = writeln!(s, "## Configuration\n");
        let _ = writeln!(
            s,
            "- ADC input width A = {} bits; fine bits F = {f}: 1 LSB = 2^-{f} quadrant = {} electrical arc-seconds = {} mechanical arc-seconds at {ppr} PPR.",
            d.adc_width,
            sig(lsb_el, 5),
            sig(lsb_el / ppr as f64, 5),
        );
        let _ = writeln!(
            s,
            "- Resolution for {ppr} PPR: {} coarse bits (4 x {ppr} = {} quadrants per turn) + {f} fine bits = {} bits per turn.",
            sig(coarse, 4),
            d.quadrants_per_turn,
            sig(d.resolution_bits, 4)
        );
        let _ = writeln!(
            s,
            "- Clock {:.3} MHz; CORDIC architecture {}: the core takes one sample per {} (throughput column). The ADC delivers {:.0} samples/s per channel.",
            d.clock_hz / 1e6,
            d.architecture,
            if d.cycles_per_sample > 1 { "N clocks" } else { "clock" },
            d.sample_rate_hz
        );
        let _ = writeln!(
            s,
            "- Maximum speed at full resolution: {:.0} rpm (steps below {:.2} quadrants per sample at {:.0} samples/s; independent of N).",
            d.max_speed_rpm_full_res,
            d.warn_step as f64 / (1u64 << f) as f64,
            d.sample_rate_hz
        );
        let _ = writeln!(
            s,
            "- Input set of the accuracy sweep: {}.",
            self.plan.describe()
        );
        let _ = writeln!(s, "- {}.", self.yosys_version);
        let _ = writeln!(s, "- Place and route: {}.\n", self.ecp5_version);
        for (heading, keys) in TABLES {
            let _ = writeln!(s, "## {heading}\n");
            s.push_str(&self.markdown_table(&table, keys, None));
            s.push('\n');
        }
        let paper_ns: Vec<u32> = self
            .rows
            .iter()
            .map(|r| r.n)
            .filter(|&n| thesis_gates(n).is_some() || thesis_error(n).is_some())
            .collect();
        if !paper_ns.is_empty() {
            let _ = writeln!(
                s,
                "## The thesis's figures (paper) next to this design's\n\nColumns marked `paper:` are quoted from the thesis, not measured (see Methods for what differs).\n"
            );
            s.push_str(&self.markdown_table(
                &table,
                &[
                    "n",
                    "gates",
                    "paper_gates",
                    "latency_cycles",
                    "paper_cycles",
                    "err_max_mech_deg",
                    "paper_max_mech_deg",
                    "err_max_quadrant_pct",
                    "paper_max_quadrant_pct",
                    "bits_per_turn",
                    "paper_bits_per_turn",
                ],
                Some(&paper_ns),
            ));
            s.push('\n');
        }
        let _ = writeln!(
            s,
            "## Blocks of {}\n\nEach block synthesized alone with the configured parameters (N = {}, {} CORDIC); see Methods.\n",
            crate::emit::top_name(loaded),
            d.iterations,
            arch_name(d.architecture)
        );
        s.push_str(&self.blocks_markdown());
        s.push('\n');
        let _ = writeln!(s, "## Critical paths per N\n");
        for r in &self.rows {
            let x = |p: &Option<levels::PathLevels>| {
                p.as_ref()
                    .map(|p| {
                        format!(
                            "{} LUT levels + {} carry bits ({} chains, {} MUXF, {} multipliers, {} routed nets), `{}` -> `{}`, est. {:.1} MHz",
                            p.lut_levels, p.carry_bits, p.carry_chains, p.muxes, p.multipliers, p.routed_nets, p.from, p.to, p.fmax_mhz()
                        )
                    })
                    .unwrap_or_else(|| "no register-to-register path".into())
            };
            let _ = writeln!(
                s,
                "- N = {}: ECP5 {} MHz, {} -> {} ({:.2} ns logic, {:.2} ns routing over {} nets); xc3sa: {}; cycloneive: {}",
                r.n,
                fmax_cell(r.ecp5.fmax_mhz),
                path_block(&r.ecp5.from_cell, false),
                path_block(&r.ecp5.to_cell, false),
                r.ecp5.logic_ns,
                r.ecp5.routing_ns,
                r.ecp5.routed_nets,
                x(&r.xc3sa.path),
                x(&r.cyclone.path)
            );
        }
        let _ = writeln!(
            s,
            "\n## Longest generic gate path (gate depth, not timing) per N\n"
        );
        for r in &self.rows {
            let _ = writeln!(
                s,
                "- N = {}: {} gates, from `{}` to `{}`",
                r.n, r.gates.depth, r.gates.path_from, r.gates.path_to
            );
        }
        let _ = writeln!(s, "\n## Worst-case inputs per N\n");
        for r in &self.rows {
            match r.acc.worst_input(d.adc_width) {
                Some((sin, cos)) => {
                    let _ = writeln!(
                        s,
                        "- N = {}: {} LSB at (sin, cos) = ({sin}, {cos})",
                        r.n,
                        format_args!("{:.4}", r.acc.max_lsb())
                    );
                }
                None => {
                    let _ = writeln!(s, "- N = {}: no sample", r.n);
                }
            }
        }
        let _ = writeln!(s, "\n## Methods\n");
        for (k, m) in self.methods(loaded) {
            let _ = writeln!(s, "- **{k}**: {m}");
        }
        if opts.formats.svg {
            let [_, _, _, e, r, a, ar, _] = Report::file_names(name);
            let _ = writeln!(
                s,
                "\n## Plots\n\n![error against N]({e})\n\n![resources against N]({r})\n\n![error against angle, N = {}]({a})\n\n![area against N, unrolled and iterative]({ar})",
                self.angle_n
            );
        }
        s
    }
}
