//! `simulate`'s outputs tell the truth (issue 13, section E), at the library level: the CSV
//! columns are the docs/cli.md's on both paths, and the VCD streams `<name>_top`'s ports.
use crate::simulate_truth::{cap, default};
use sinedec::config::Loaded;
use sinedec::simulate::{run, run_capacitive, run_capacitive_traced, run_traced, SimOptions};
use std::cell::RefCell;
use std::io::Write;
use std::rc::Rc;

/// The docs/cli.md's `--csv` column table, in order.
fn readme_csv_columns() -> Vec<String> {
    let readme = include_str!("../../docs/cli.md");
    let start = readme
        .find("### `simulate --csv` columns")
        .expect("docs/cli.md documents the CSV columns");
    readme[start..]
        .lines()
        .skip_while(|l| !l.starts_with("| column"))
        .skip(2)
        .take_while(|l| l.starts_with('|'))
        .map(|l| l.split('`').nth(1).expect("`name` in the row").to_string())
        .collect()
}

/// Both paths write docs/cli.md's columns; warm-up rows are marked and are exactly the
/// rows left out of the statistics; error_lsb carries the summary's figures.
#[test]
fn csv_columns_are_documented_and_shared_by_both_paths() {
    let cols = readme_csv_columns();
    assert!(cols.len() >= 8, "{cols:?}");
    let l = default();
    let o = SimOptions {
        duration_s: 1e-4,
        ..Default::default()
    };
    let r = run(&l, &o, |_, _| {}).expect("runs");
    let csv = r.csv(&l, o.skip);
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    // The default config has no velocity estimator: docs/cli.md's columns marked "only with
    // `[velocity] enabled`" are absent (tests/system/velocity_top.rs checks them when enabled).
    let readme = include_str!("../../docs/cli.md");
    let always: Vec<&String> = cols
        .iter()
        .filter(|c| {
            let row = readme
                .lines()
                .find(|l| l.starts_with(&format!("| `{c}` |")))
                .unwrap();
            !row.contains("only with `[velocity] enabled`")
        })
        .collect();
    assert!(
        always.len() < cols.len(),
        "the velocity columns are documented"
    );
    assert_eq!(header, always);
    let w = header.iter().position(|c| *c == "warmup").unwrap();
    let e = header.iter().position(|c| *c == "error_lsb").unwrap();
    let rows: Vec<Vec<&str>> = csv
        .lines()
        .skip(1)
        .map(|x| x.split(',').collect())
        .collect();
    assert_eq!(rows.len(), r.result.records.len());
    assert_eq!(rows.iter().filter(|x| x[w] == "1").count(), o.skip);
    let stat: Vec<f64> = rows
        .iter()
        .filter(|x| x[w] == "0")
        .map(|x| x[e].parse().unwrap())
        .collect();
    assert_eq!(stat.len(), r.stats.samples);
    let max = stat.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(
        (max - r.stats.max_lsb).abs() < 2e-3,
        "{max} vs {:?}",
        r.stats
    );

    let c = cap();
    let o = SimOptions {
        duration_s: 4e-3,
        ..Default::default()
    };
    let (_, csv) = run_capacitive(&c, &o, |_, _| {}).expect("capacitive runs");
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    assert_eq!(header, always, "the capacitive CSV uses the same columns");
    let rows: Vec<Vec<&str>> = csv
        .lines()
        .skip(1)
        .map(|x| x.split(',').collect())
        .collect();
    assert!(rows.iter().any(|x| x[w] == "1") && rows.iter().any(|x| x[w] == "0"));
}

/// A writer into a shared buffer that also counts what arrived.
#[derive(Clone, Default)]
struct Shared(Rc<RefCell<Vec<u8>>>);
impl Write for Shared {
    fn write(&mut self, b: &[u8]) -> std::io::Result<usize> {
        self.0.borrow_mut().extend_from_slice(b);
        Ok(b.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// (name, width) of every port of the emitted `<name>_top` module (the wrapper's
/// declarations, `input`/`output wire [H:0] name,`).
fn emitted_top_ports(l: &Loaded) -> Vec<(String, u32)> {
    let g = sinedec::emit::generate(l, "test").expect("generate");
    let top = format!("{}_top", l.config.name);
    let v = &g
        .files
        .iter()
        .find(|f| f.name == format!("{top}.v"))
        .expect("top file")
        .text;
    let start = v.find(&format!("module {top} (")).expect("module");
    let body = &v[start..v[start..].find(");").unwrap() + start];
    body.lines()
        .filter_map(|line| {
            let t = line.trim_start();
            let rest = t
                .strip_prefix("input")
                .or_else(|| t.strip_prefix("output"))?;
            let rest = rest.trim_start().strip_prefix("wire")?.trim_start();
            let (width, rest) = if let Some(r) = rest.strip_prefix('[') {
                let (hi, r) = r.split_once(":0]").unwrap();
                (hi.trim().parse::<u32>().unwrap() + 1, r)
            } else {
                (1, rest)
            };
            let name = rest.trim_start().split([',', ' ']).next()?.to_string();
            Some((name, width))
        })
        .collect()
}

/// (name, width) of the VCD's variables, read with the vcd crate's parser.
fn vcd_vars(text: &[u8]) -> (String, Vec<(String, u32)>) {
    let mut p = vcd::Parser::new(text);
    let h = p.parse_header().expect("VCD header parses");
    let scope = h
        .items
        .iter()
        .find_map(|i| match i {
            vcd::ScopeItem::Scope(s) => Some(s.clone()),
            _ => None,
        })
        .expect("a scope");
    let vars = scope
        .children
        .iter()
        .filter_map(|i| match i {
            vcd::ScopeItem::Var(v) => Some((v.reference.clone(), v.size)),
            _ => None,
        })
        .collect();
    (scope.identifier, vars)
}

/// The VCD streams while the simulation runs (bytes arrive before the end), and holds
/// `<name>_top`'s ports with their emitted names and widths, on both paths.
#[test]
fn vcd_streams_the_top_ports_on_both_paths() {
    for (l, duration) in [(default(), 2.5e-4), (cap(), 3.2e-3)] {
        let buf = Shared::default();
        let seen = Rc::new(RefCell::new(Vec::new()));
        let (b2, s2) = (buf.clone(), seen.clone());
        let progress = move |done: u64, _| s2.borrow_mut().push((done, b2.0.borrow().len()));
        let o = SimOptions {
            duration_s: duration,
            ..Default::default()
        };
        let records = if l.derived.capacitive.is_some() {
            run_capacitive_traced(&l, &o, progress, Some(Box::new(buf.clone()))).expect("runs");
            None
        } else {
            Some(
                run_traced(&l, &o, progress, Some(Box::new(buf.clone())))
                    .expect("runs")
                    .result
                    .records,
            )
        };
        let seen = seen.borrow();
        let total = buf.0.borrow().len();
        assert!(seen.len() >= 2);
        assert!(
            seen[0].1 > 0 && seen[0].1 < total,
            "nothing streamed before the end: {seen:?}"
        );
        let text = buf.0.borrow().clone();
        let (scope, vars) = vcd_vars(&text);
        assert_eq!(scope, format!("{}_top", l.config.name));
        assert_eq!(vars, emitted_top_ports(&l));
        assert!(vars
            .iter()
            .all(|(n, _)| !n.ends_with("_rtl") && n != "par_qc"));
        // The positions in the VCD are the decoded ones.
        if let Some(recs) = records {
            let s = String::from_utf8(text).unwrap();
            let want = format!(
                "b{:0w$b} ",
                recs[20].position,
                w = l.derived.position_width as usize
            );
            assert!(
                s.contains(&want),
                "position {} not in the VCD",
                recs[20].position
            );
        }
    }
}
