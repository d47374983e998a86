//! The report's JSON document: every row's cells as numbers, the blocks and the method
//! notes.

use super::*;

impl Report {
    pub(super) fn json(&self, loaded: &Loaded, opts: &Options) -> Result<String> {
        use serde_json::{json, Map, Value};
        let d = &loaded.derived;
        let rows: Vec<Value> = self
            .table(loaded)
            .into_iter()
            .map(|row| {
                let mut m = Map::new();
                for ((key, _), cell) in COLUMNS.iter().zip(row) {
                    m.insert((*key).to_string(), cell_value(&cell, key));
                }
                Value::Object(m)
            })
            .collect();
        let blocks_json: Vec<Value> = self
            .blocks
            .iter()
            .map(|r| {
                let mut m = Map::new();
                m.insert("key".into(), Value::from(r.key.clone()));
                for ((key, _), cell) in blocks::BLOCK_COLUMNS.iter().zip(blocks::block_cells(r)) {
                    m.insert((*key).to_string(), cell_value(&cell, key));
                }
                Value::Object(m)
            })
            .collect();
        let methods: Map<String, Value> = self
            .methods(loaded)
            .into_iter()
            .map(|(k, v)| (k.to_string(), Value::from(v)))
            .collect();
        let worst: Vec<Value> = self
            .rows
            .iter()
            .map(|r| {
                let w = r.acc.worst_input(d.adc_width);
                json!({
                    "n": r.n,
                    "worst_input": w.map(|(s, c)| json!({"sin": s, "cos": c})),
                    "path_from": r.gates.path_from,
                    "path_to": r.gates.path_to,
                    "ecp5": r.ecp5,
                    "ecp5_from_register": r.ecp5.from_register(),
                    "ecp5_to_register": r.ecp5.to_register(),
                    "xc3sa_path": r.xc3sa.path,
                    "cycloneive_path": r.cyclone.path,
                })
            })
            .collect();
        let v = json!({
            "tool": format!("sinedec {} (commit {})", crate::emit::VERSION, crate::emit::commit()),
            "config": loaded.source_name,
            "config_hash": loaded.hash(),
            "command": opts.command,
            "yosys": self.yosys_version,
            "ecp5_flow": self.ecp5_version,
            "configuration": {
                "name": loaded.config.name,
                "adc_width": d.adc_width,
                "fine_bits": d.fine_bits,
                "ppr": loaded.config.encoder.ppr,
                "clock_hz": d.clock_hz,
                "sample_rate_hz": d.sample_rate_hz,
                "coarse_bits": (d.quadrants_per_turn as f64).log2(),
                "resolution_bits": d.resolution_bits,
                "max_speed_rpm_full_res": d.max_speed_rpm_full_res,
                "sweep_exhaustive": self.plan.exhaustive(),
                "sweep_stride": self.plan.stride,
            },
            "columns": COLUMNS.iter().map(|(k, t)| json!({"key": k, "title": t})).collect::<Vec<_>>(),
            "rows": rows,
            "details": worst,
            "error_vs_angle": {
                "n": self.angle_n,
                "bins": self.envelope.iter().map(|&(a, lo, hi)| json!([a, lo, hi])).collect::<Vec<_>>(),
            },
            "block_columns": blocks::BLOCK_COLUMNS.iter().map(|(k, t)| json!({"key": k, "title": t})).collect::<Vec<_>>(),
            "blocks": blocks_json,
            "methods": methods,
        });
        let mut s = serde_json::to_string_pretty(&v).map_err(|source| Error::Json {
            what: "report".into(),
            source,
        })?;
        s.push('\n');
        Ok(s)
    }
}

/// A table cell as JSON: null when empty, a number when it parses as one (text columns
/// stay strings).
pub(super) fn cell_value(cell: &str, key: &str) -> serde_json::Value {
    use serde_json::Value;
    if cell.is_empty() {
        Value::Null
    } else if matches!(key, "block" | "module" | "timing" | "ecp5_path")
        || TEXT_COLUMNS.contains(&key)
    {
        Value::from(cell)
    } else if let Ok(i) = cell.parse::<u64>() {
        Value::from(i)
    } else if let Ok(x) = cell.parse::<f64>() {
        Value::from(x)
    } else {
        Value::from(cell)
    }
}
