//! The report's table: every column (key, title), the Markdown tables that show them, the
//! cell formatting, and the CSV files (main table and blocks).

use super::*;

/// Every column of the report table: (key used in CSV and JSON, title used in Markdown).
pub const COLUMNS: &[(&str, &str)] = &[
    ("n", "N"),
    ("latency_cycles", "latency (cycles)"),
    ("latency_ns", "latency (ns)"),
    ("throughput_msps", "throughput (Msample/s)"),
    ("xc3sa_lut", "xc3sa LUT4 (incl. INV)"),
    ("xc3sa_ff", "xc3sa FF"),
    ("xc3sa_carry", "xc3sa MUXCY"),
    ("xc3sa_mult", "xc3sa MULT18X18"),
    ("xc3sa_bram", "xc3sa RAMB16"),
    ("cycloneive_lut", "cycloneive LE"),
    ("cycloneive_ff", "cycloneive FF"),
    ("cycloneive_carry", "cycloneive carry"),
    ("cycloneive_mult", "cycloneive mult"),
    ("cycloneive_bram", "cycloneive M9K"),
    ("gates", "gates (2-input, MUX = 1)"),
    ("gates_mux", "of which MUX"),
    ("gates_not", "NOT"),
    ("gates_ff", "FF (generic)"),
    ("logic_depth", "gate depth (generic gates, not timing)"),
    (
        "ecp5_fmax_mhz",
        "ECP5-6 post-route Fmax, median of seeds 1-3 (MHz)",
    ),
    ("ecp5_seeds_mhz", "ECP5-6 Fmax at seeds 1 / 2 / 3 (MHz)"),
    ("ecp5_slack_ns", "ECP5-6 slack at the median (ns)"),
    ("ecp5_from_block", "ECP5 critical path from"),
    ("ecp5_to_block", "ECP5 critical path to"),
    ("xc3sa_lut_levels", "xc3sa LUT levels"),
    ("xc3sa_carry_bits", "xc3sa carry bits"),
    ("xc3sa_carry_chains", "xc3sa carry chains"),
    ("xc3sa_est_fmax_mhz", "xc3sa -4 est. Fmax (MHz)"),
    ("cycloneive_lut_levels", "cycloneive LUT levels"),
    ("cycloneive_carry_bits", "cycloneive carry bits"),
    ("cycloneive_est_fmax_mhz", "Cyclone III C8 est. Fmax (MHz)"),
    ("err_max_lsb", "max error (LSB)"),
    ("err_rms_lsb", "RMS error (LSB)"),
    ("err_mean_lsb", "mean error (LSB)"),
    ("err_max_el_deg", "max error (el. deg)"),
    ("err_rms_el_deg", "RMS error (el. deg)"),
    ("err_max_el_arcsec", "max error (el. arcsec)"),
    ("err_rms_el_arcsec", "RMS error (el. arcsec)"),
    ("err_max_mech_arcsec", "max error (mech. arcsec)"),
    ("err_rms_mech_arcsec", "RMS error (mech. arcsec)"),
    ("err_max_mech_deg", "max error (mech. deg)"),
    ("err_max_quadrant_pct", "max error (% of quadrant)"),
    ("enob", "ENOB (bits per period)"),
    ("bits_per_turn", "bits per turn from max error"),
    ("samples", "samples"),
    ("rejected", "rejected"),
    ("pred_residual_lsb", "residual bound (LSB)"),
    ("pred_bound_lsb", "residual bound + 1 (LSB)"),
    ("pred_quant_rms_lsb", "quantization RMS, ZipCPU (LSB)"),
    ("pred_rms_lsb", "predicted RMS (LSB)"),
    ("paper_gates", "paper: gates (Table 3-2)"),
    ("paper_cycles", "paper: cycles (Table 3-2)"),
    (
        "paper_max_mech_deg",
        "paper: max error (mech. deg, 2048 PPR, Table 2-2)",
    ),
    ("paper_max_quadrant_pct", "paper: max error (% of quadrant)"),
    ("paper_bits_per_turn", "paper: bits per turn"),
    ("unrolled_xc3sa_lut", "unrolled: xc3sa LUT4"),
    ("unrolled_xc3sa_ff", "unrolled: xc3sa FF"),
    ("unrolled_cycloneive_lut", "unrolled: cycloneive LE"),
    ("unrolled_cycloneive_ff", "unrolled: cycloneive FF"),
    ("unrolled_latency_cycles", "unrolled: latency (cycles)"),
    (
        "unrolled_throughput_msps",
        "unrolled: throughput (Msample/s)",
    ),
    ("unrolled_ecp5_fmax_mhz", "unrolled: ECP5-6 Fmax (MHz)"),
    (
        "unrolled_xc3sa_est_fmax_mhz",
        "unrolled: xc3sa -4 est. Fmax (MHz)",
    ),
    ("iterative_xc3sa_lut", "iterative: xc3sa LUT4"),
    ("iterative_xc3sa_ff", "iterative: xc3sa FF"),
    ("iterative_cycloneive_lut", "iterative: cycloneive LE"),
    ("iterative_cycloneive_ff", "iterative: cycloneive FF"),
    ("iterative_latency_cycles", "iterative: latency (cycles)"),
    (
        "iterative_throughput_msps",
        "iterative: throughput (Msample/s)",
    ),
    ("iterative_ecp5_fmax_mhz", "iterative: ECP5-6 Fmax (MHz)"),
    (
        "iterative_xc3sa_est_fmax_mhz",
        "iterative: xc3sa -4 est. Fmax (MHz)",
    ),
    ("arch_lut_ratio", "iterative / unrolled xc3sa LUT4"),
];

/// Columns of the architecture table, in order.
pub(super) const ARCH_KEYS: &[&str] = &[
    "n",
    "unrolled_xc3sa_lut",
    "unrolled_xc3sa_ff",
    "unrolled_cycloneive_lut",
    "unrolled_cycloneive_ff",
    "unrolled_latency_cycles",
    "unrolled_throughput_msps",
    "unrolled_ecp5_fmax_mhz",
    "unrolled_xc3sa_est_fmax_mhz",
    "iterative_xc3sa_lut",
    "iterative_xc3sa_ff",
    "iterative_cycloneive_lut",
    "iterative_cycloneive_ff",
    "iterative_latency_cycles",
    "iterative_throughput_msps",
    "iterative_ecp5_fmax_mhz",
    "iterative_xc3sa_est_fmax_mhz",
    "arch_lut_ratio",
];

/// Markdown tables: (heading, column keys).
pub(super) const TABLES: &[(&str, &[&str])] = &[
    (
        "Timing and resources",
        &[
            "n",
            "latency_cycles",
            "latency_ns",
            "throughput_msps",
            "xc3sa_lut",
            "xc3sa_ff",
            "xc3sa_carry",
            "xc3sa_mult",
            "xc3sa_bram",
            "cycloneive_lut",
            "cycloneive_ff",
            "cycloneive_mult",
            "cycloneive_bram",
            "gates",
            "gates_mux",
            "gates_not",
            "gates_ff",
            "logic_depth",
        ],
    ),
    (
        "Timing: post-route ECP5 (measured), xc3sa and Cyclone III (estimated)",
        &[
            "n",
            "ecp5_fmax_mhz",
            "ecp5_seeds_mhz",
            "ecp5_slack_ns",
            "ecp5_from_block",
            "ecp5_to_block",
            "xc3sa_lut_levels",
            "xc3sa_carry_bits",
            "xc3sa_carry_chains",
            "xc3sa_est_fmax_mhz",
            "cycloneive_lut_levels",
            "cycloneive_carry_bits",
            "cycloneive_est_fmax_mhz",
        ],
    ),
    (
        "Accuracy (measured)",
        &[
            "n",
            "err_max_lsb",
            "err_rms_lsb",
            "err_mean_lsb",
            "err_max_el_deg",
            "err_rms_el_deg",
            "err_max_el_arcsec",
            "err_rms_el_arcsec",
            "err_max_mech_arcsec",
            "err_rms_mech_arcsec",
            "enob",
            "bits_per_turn",
            "rejected",
        ],
    ),
    (
        "Predicted and measured error",
        &[
            "n",
            "pred_residual_lsb",
            "pred_bound_lsb",
            "err_max_lsb",
            "pred_quant_rms_lsb",
            "pred_rms_lsb",
            "err_rms_lsb",
        ],
    ),
    ("Architectures (unrolled vs iterative)", ARCH_KEYS),
];

/// An Fmax cell (MHz, two decimals; empty when there is no register-to-register path).
pub fn fmax_cell(f: Option<f64>) -> String {
    f.map(|f| format!("{f:.2}")).unwrap_or_default()
}

/// The estimated Fmax of a Yosys mapping's worst path (empty without such a path).
pub fn est_cell(s: &SynthStats) -> String {
    s.path
        .as_ref()
        .map(|p| format!("{:.1}", p.fmax_mhz()))
        .unwrap_or_default()
}

/// The block of an ECP5 cell (`short`: without the register name), or "" for none.
pub fn path_block(cell: &str, short: bool) -> String {
    if cell.is_empty() {
        return String::new();
    }
    let reg = nextpnr::register_name(cell);
    let b = block_of(&reg);
    if short {
        b
    } else {
        format!("{b} ({reg})")
    }
}

/// Columns holding text, not numbers (CSV/JSON keep them as strings).
pub const TEXT_COLUMNS: &[&str] = &["ecp5_seeds_mhz", "ecp5_from_block", "ecp5_to_block"];

/// Key of a Markdown column title (for tests and tools reading the Markdown).
pub fn column_key(title: &str) -> Option<&'static str> {
    COLUMNS.iter().find(|c| c.1 == title).map(|c| c.0)
}

/// A number with `digits` significant digits: fixed notation for 1e-3 <= |x| < 1e6,
/// exponent notation otherwise (both parse as f64).
pub fn sig(x: f64, digits: usize) -> String {
    if x == 0.0 || !x.is_finite() {
        return if x.is_finite() {
            "0".into()
        } else {
            String::new()
        };
    }
    let mag = x.abs().log10().floor() as i32;
    if (-3..6).contains(&mag) {
        let dec = (digits as i32 - 1 - mag).max(0) as usize;
        format!("{x:.dec$}")
    } else {
        format!("{:.*e}", digits.saturating_sub(1), x)
    }
}

impl Report {
    pub(super) fn cells(&self, loaded: &Loaded, r: &Row) -> Vec<(&'static str, String)> {
        let d = &r.derived;
        let f = d.fine_bits;
        let ppr = loaded.config.encoder.ppr as f64;
        let lsb_el_deg = 90.0 / (1u64 << f) as f64;
        let max = r.acc.max_lsb();
        let rms = r.acc.rms_lsb();
        let enob = (f + 2) as f64 - (rms * 12f64.sqrt()).log2();
        let bits_per_turn = ((4.0 * ppr) * (1u64 << f) as f64 / max).log2();
        let paper_g = thesis_gates(r.n);
        let paper_e = thesis_error(r.n);
        let int = |v: u64| v.to_string();
        let mut cells = vec![
            ("n", int(r.n as u64)),
            ("latency_cycles", int(d.latency_cycles as u64)),
            ("latency_ns", format!("{:.1}", d.latency_ns())),
            (
                "throughput_msps",
                format!(
                    "{:.3}",
                    d.clock_hz / d.cycles_per_sample.max(1) as f64 / 1e6
                ),
            ),
            ("xc3sa_lut", int(r.xc3sa.luts)),
            ("xc3sa_ff", int(r.xc3sa.ffs)),
            ("xc3sa_carry", int(r.xc3sa.carry)),
            ("xc3sa_mult", int(r.xc3sa.multipliers)),
            ("xc3sa_bram", int(r.xc3sa.brams)),
            ("cycloneive_lut", int(r.cyclone.luts)),
            ("cycloneive_ff", int(r.cyclone.ffs)),
            ("cycloneive_carry", int(r.cyclone.carry)),
            ("cycloneive_mult", int(r.cyclone.multipliers)),
            ("cycloneive_bram", int(r.cyclone.brams)),
            ("gates", int(r.gates.gates)),
            ("gates_mux", int(r.gates.muxes)),
            ("gates_not", int(r.gates.inverters)),
            ("gates_ff", int(r.gates.ffs)),
            ("logic_depth", int(r.gates.depth)),
            ("ecp5_fmax_mhz", fmax_cell(r.ecp5.fmax_mhz)),
            ("ecp5_seeds_mhz", nextpnr::seeds_text(&r.ecp5.seeds_mhz)),
            (
                "ecp5_slack_ns",
                r.ecp5
                    .slack_ns()
                    .map(|v| format!("{v:.2}"))
                    .unwrap_or_default(),
            ),
            ("ecp5_from_block", path_block(&r.ecp5.from_cell, true)),
            ("ecp5_to_block", path_block(&r.ecp5.to_cell, true)),
            (
                "xc3sa_lut_levels",
                r.xc3sa
                    .path
                    .as_ref()
                    .map(|p| int(p.lut_levels as u64))
                    .unwrap_or_default(),
            ),
            (
                "xc3sa_carry_bits",
                r.xc3sa
                    .path
                    .as_ref()
                    .map(|p| int(p.carry_bits as u64))
                    .unwrap_or_default(),
            ),
            (
                "xc3sa_carry_chains",
                r.xc3sa
                    .path
                    .as_ref()
                    .map(|p| int(p.carry_chains as u64))
                    .unwrap_or_default(),
            ),
            ("xc3sa_est_fmax_mhz", est_cell(&r.xc3sa)),
            (
                "cycloneive_lut_levels",
                r.cyclone
                    .path
                    .as_ref()
                    .map(|p| int(p.lut_levels as u64))
                    .unwrap_or_default(),
            ),
            (
                "cycloneive_carry_bits",
                r.cyclone
                    .path
                    .as_ref()
                    .map(|p| int(p.carry_bits as u64))
                    .unwrap_or_default(),
            ),
            ("cycloneive_est_fmax_mhz", est_cell(&r.cyclone)),
            ("err_max_lsb", format!("{max:.4}")),
            ("err_rms_lsb", format!("{rms:.4}")),
            ("err_mean_lsb", format!("{:.4}", r.acc.mean_lsb())),
            ("err_max_el_deg", sig(max * lsb_el_deg, 5)),
            ("err_rms_el_deg", sig(rms * lsb_el_deg, 5)),
            ("err_max_el_arcsec", sig(max * lsb_el_deg * 3600.0, 5)),
            ("err_rms_el_arcsec", sig(rms * lsb_el_deg * 3600.0, 5)),
            (
                "err_max_mech_arcsec",
                sig(max * lsb_el_deg * 3600.0 / ppr, 5),
            ),
            (
                "err_rms_mech_arcsec",
                sig(rms * lsb_el_deg * 3600.0 / ppr, 5),
            ),
            ("err_max_mech_deg", sig(max * lsb_el_deg / ppr, 5)),
            (
                "err_max_quadrant_pct",
                sig(max / (1u64 << f) as f64 * 100.0, 5),
            ),
            ("enob", format!("{enob:.2}")),
            ("bits_per_turn", format!("{bits_per_turn:.2}")),
            ("samples", int(r.acc.count)),
            ("rejected", int(r.acc.rejected)),
            (
                "pred_residual_lsb",
                format!("{:.4}", r.predicted.residual_lsb),
            ),
            (
                "pred_bound_lsb",
                format!("{:.4}", r.predicted.residual_lsb + 1.0),
            ),
            (
                "pred_quant_rms_lsb",
                format!("{:.4}", r.predicted.quant_rms_lsb),
            ),
            ("pred_rms_lsb", format!("{:.4}", r.predicted.rms_lsb)),
            ("paper_gates", paper_g.map(|g| int(g.0)).unwrap_or_default()),
            (
                "paper_cycles",
                paper_g.map(|g| int(g.1 as u64)).unwrap_or_default(),
            ),
            (
                "paper_max_mech_deg",
                paper_e.map(|e| sig(e.1, 5)).unwrap_or_default(),
            ),
            (
                "paper_max_quadrant_pct",
                paper_e.map(|e| sig(e.0 * 100.0, 5)).unwrap_or_default(),
            ),
            (
                "paper_bits_per_turn",
                paper_e.map(|e| int(e.2 as u64)).unwrap_or_default(),
            ),
        ];
        let un = r.arch(Architecture::Unrolled);
        let it = r.arch(Architecture::Iterative);
        for (name, a) in [("unrolled", &un), ("iterative", &it)] {
            let cell = |f: &dyn Fn(&ArchFigures) -> String| a.as_ref().map(f).unwrap_or_default();
            let figures: [(&str, String); 8] = [
                ("xc3sa_lut", cell(&|a| int(a.xc3sa.luts))),
                ("xc3sa_ff", cell(&|a| int(a.xc3sa.ffs))),
                ("cycloneive_lut", cell(&|a| int(a.cyclone.luts))),
                ("cycloneive_ff", cell(&|a| int(a.cyclone.ffs))),
                ("latency_cycles", cell(&|a| int(a.latency_cycles as u64))),
                (
                    "throughput_msps",
                    cell(&|a| {
                        format!(
                            "{:.3}",
                            d.clock_hz / a.cycles_per_sample.max(1) as f64 / 1e6
                        )
                    }),
                ),
                ("ecp5_fmax_mhz", cell(&|a| fmax_cell(a.ecp5.fmax_mhz))),
                ("xc3sa_est_fmax_mhz", cell(&|a| est_cell(&a.xc3sa))),
            ];
            for (k, v) in figures {
                let key = COLUMNS
                    .iter()
                    .find(|c| c.0.strip_prefix(name).and_then(|x| x.strip_prefix('_')) == Some(k))
                    .map(|c| c.0)
                    .unwrap_or("");
                cells.push((key, v));
            }
        }
        let ratio = match (&un, &it) {
            (Some(u), Some(i)) if u.xc3sa.luts > 0 => {
                format!("{:.3}", i.xc3sa.luts as f64 / u.xc3sa.luts as f64)
            }
            _ => String::new(),
        };
        cells.push(("arch_lut_ratio", ratio));
        cells
    }

    /// The table: one row per N, each cell as shown (empty = not applicable), in
    /// [`COLUMNS`] order.
    pub fn table(&self, loaded: &Loaded) -> Vec<Vec<String>> {
        self.rows
            .iter()
            .map(|r| {
                let cells = self.cells(loaded, r);
                debug_assert!(cells.iter().map(|c| c.0).eq(COLUMNS.iter().map(|c| c.0)));
                cells.into_iter().map(|c| c.1).collect()
            })
            .collect()
    }

    /// CSV: a header of column keys, then one line per N (no cell holds a comma or a quote,
    /// so none is quoted).
    pub fn csv(&self, loaded: &Loaded) -> String {
        let mut t = CsvText::new(COLUMNS.iter().map(|c| c.0));
        for row in self.table(loaded) {
            t.record(row);
        }
        t.finish()
    }

    pub(super) fn markdown_table(
        &self,
        table: &[Vec<String>],
        keys: &[&str],
        only: Option<&[u32]>,
    ) -> String {
        let idx: Vec<usize> = keys
            .iter()
            .filter_map(|k| COLUMNS.iter().position(|c| c.0 == *k))
            .collect();
        let mut s = String::new();
        let _ = writeln!(
            s,
            "| {} |",
            idx.iter()
                .map(|&i| COLUMNS[i].1)
                .collect::<Vec<_>>()
                .join(" | ")
        );
        let _ = writeln!(s, "|{}", "---|".repeat(idx.len()));
        for (r, row) in self.rows.iter().zip(table) {
            if only.is_some_and(|o| !o.contains(&r.n)) {
                continue;
            }
            let cells: Vec<&str> = idx
                .iter()
                .map(|&i| {
                    if row[i].is_empty() {
                        "-"
                    } else {
                        row[i].as_str()
                    }
                })
                .collect();
            let _ = writeln!(s, "| {} |", cells.join(" | "));
        }
        s
    }
}

impl Report {
    /// Names of the files for `formats`.
    ///
    /// Order: Markdown, CSV (per N), JSON, the four SVG plots (error against N, resources
    /// against N, error against angle, area against N for both architectures), and the
    /// blocks CSV (written with `csv`).
    pub fn file_names(name: &str) -> [String; 8] {
        [
            format!("{name}_report.md"),
            format!("{name}_report.csv"),
            format!("{name}_report.json"),
            format!("{name}_report_error_vs_n.svg"),
            format!("{name}_report_resources_vs_n.svg"),
            format!("{name}_report_error_vs_angle.svg"),
            format!("{name}_report_area_vs_n_arch.svg"),
            format!("{name}_report_blocks.csv"),
        ]
    }

    /// The blocks CSV: a header of [`blocks::BLOCK_COLUMNS`] keys, then one line per block
    /// (no cell holds a comma or a quote, so none is quoted).
    pub fn blocks_csv(&self) -> String {
        let mut t = CsvText::new(blocks::BLOCK_COLUMNS.iter().map(|c| c.0));
        for r in &self.blocks {
            t.record(blocks::block_cells(r));
        }
        t.finish()
    }

    pub(super) fn blocks_markdown(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "| {} |",
            blocks::BLOCK_COLUMNS
                .iter()
                .map(|c| c.1)
                .collect::<Vec<_>>()
                .join(" | ")
        );
        let _ = writeln!(s, "|{}", "---|".repeat(blocks::BLOCK_COLUMNS.len()));
        for r in &self.blocks {
            let cells: Vec<String> = blocks::block_cells(r)
                .into_iter()
                .enumerate()
                .map(|(i, c)| {
                    if c.is_empty() {
                        "-".to_string()
                    } else if i == 1 {
                        format!("`{c}`")
                    } else {
                        c
                    }
                })
                .collect();
            let _ = writeln!(s, "| {} |", cells.join(" | "));
        }
        s
    }
}
