//! The report's four SVG plots (area, timing and accuracy against N, both architectures).

use super::*;

impl Report {
    pub(super) fn plots(&self, loaded: &Loaded) -> Result<[String; 4]> {
        use plot::{chart, Series};
        let pts = |g: &dyn Fn(&Row) -> f64| -> Vec<(f64, f64)> {
            self.rows.iter().map(|r| (r.n as f64, g(r))).collect()
        };
        let line = |label: &str, points: Vec<(f64, f64)>| Series {
            label: label.to_string(),
            points,
            markers_only: false,
        };
        let mut errs = vec![
            line("measured max", pts(&|r| r.acc.max_lsb())),
            line("measured RMS", pts(&|r| r.acc.rms_lsb())),
            line(
                "residual bound + 1 LSB",
                pts(&|r| r.predicted.residual_lsb + 1.0),
            ),
            line("predicted RMS", pts(&|r| r.predicted.rms_lsb)),
        ];
        let full = (1u64 << loaded.derived.fine_bits) as f64;
        let paper: Vec<(f64, f64)> = self
            .rows
            .iter()
            .filter_map(|r| thesis_error(r.n).map(|e| (r.n as f64, e.0 * full)))
            .collect();
        if !paper.is_empty() {
            errs.push(Series {
                label: "paper: max error (Table 2-2, as LSB of this F)".into(),
                points: paper,
                markers_only: true,
            });
        }
        let err = chart(
            &format!("{}_core: angle error against N", loaded.config.name),
            "CORDIC iterations N",
            "error (LSB = 2^-F quadrant)",
            &errs,
            true,
            false,
            false,
        )?;
        let mut res = vec![
            line("xc3sa LUT4", pts(&|r| r.xc3sa.luts as f64)),
            line("xc3sa FF", pts(&|r| r.xc3sa.ffs as f64)),
            line("xc3sa MUXCY", pts(&|r| r.xc3sa.carry as f64)),
            line("cycloneive LE", pts(&|r| r.cyclone.luts as f64)),
            line("cycloneive FF", pts(&|r| r.cyclone.ffs as f64)),
            line("generic 2-input gates", pts(&|r| r.gates.gates as f64)),
        ];
        let paper: Vec<(f64, f64)> = self
            .rows
            .iter()
            .filter_map(|r| thesis_gates(r.n).map(|g| (r.n as f64, g.0 as f64)))
            .collect();
        if !paper.is_empty() {
            res.push(Series {
                label: "paper: gates (Table 3-2)".into(),
                points: paper,
                markers_only: true,
            });
        }
        let resources = chart(
            &format!("{}_core: resources against N", loaded.config.name),
            "CORDIC iterations N",
            "count",
            &res,
            false,
            false,
            false,
        )?;
        let bound = self
            .rows
            .iter()
            .find(|r| r.n == self.angle_n)
            .map(|r| r.predicted.residual_lsb)
            .unwrap_or_else(|| {
                (2.0 / std::f64::consts::PI)
                    * 2f64.powi(1 - self.angle_n as i32).atan()
                    * (1u64 << loaded.derived.fine_bits) as f64
            });
        let angle = chart(
            &format!(
                "{}_core: error against angle, N = {} (min/max per {} deg)",
                loaded.config.name,
                self.angle_n,
                90.0 / sweep::ANGLE_BINS as f64
            ),
            "electrical angle within the quadrant (deg)",
            "error (LSB)",
            &[
                line(
                    "max error",
                    self.envelope.iter().map(|e| (e.0, e.2)).collect(),
                ),
                line(
                    "min error",
                    self.envelope.iter().map(|e| (e.0, e.1)).collect(),
                ),
                line(
                    "+(residual bound + 1 LSB)",
                    vec![(0.0, bound + 1.0), (90.0, bound + 1.0)],
                ),
                line(
                    "-(residual bound + 1 LSB)",
                    vec![(0.0, -bound - 1.0), (90.0, -bound - 1.0)],
                ),
                line("+ residual bound", vec![(0.0, bound), (90.0, bound)]),
                line("- residual bound", vec![(0.0, -bound), (90.0, -bound)]),
            ],
            false,
            true,
            true,
        )?;
        let arch_pts = |arch: Architecture, g: &dyn Fn(&ArchFigures) -> f64| -> Vec<(f64, f64)> {
            self.rows
                .iter()
                .filter_map(|r| r.arch(arch).map(|a| (r.n as f64, g(&a))))
                .collect()
        };
        let area = chart(
            &format!(
                "{}_core: area against N, unrolled and iterative CORDIC",
                loaded.config.name
            ),
            "CORDIC iterations N",
            "count",
            &[
                line(
                    "unrolled: xc3sa LUT4",
                    arch_pts(Architecture::Unrolled, &|a| a.xc3sa.luts as f64),
                ),
                line(
                    "unrolled: cycloneive LE",
                    arch_pts(Architecture::Unrolled, &|a| a.cyclone.luts as f64),
                ),
                line(
                    "iterative: xc3sa LUT4",
                    arch_pts(Architecture::Iterative, &|a| a.xc3sa.luts as f64),
                ),
                line(
                    "iterative: cycloneive LE",
                    arch_pts(Architecture::Iterative, &|a| a.cyclone.luts as f64),
                ),
            ],
            false,
            false,
            false,
        )?;
        Ok([err, resources, angle, area])
    }
}
