//! Evaluation order: the combinational cells sorted so that every cell comes after the
//! cells it reads (Kahn's algorithm; a loop is an error), and the two cones the engine
//! evaluates each cycle (what the registers and memory writes need before the edge, what the
//! outputs need after it).
use super::netlist::{Netlist, SigKind};
use crate::error::{Error, Result};

/// Sorts `nl.cells` topologically, renumbers the `Comb` signals and fills the cones.
pub fn levelize(nl: &mut Netlist) -> Result<()> {
    let n = nl.cells.len();
    // Which cell drives each signal (before sorting).
    let mut driver = vec![usize::MAX; nl.signals.len()];
    for (k, c) in nl.cells.iter().enumerate() {
        driver[c.out] = k;
    }
    let deps: Vec<Vec<usize>> = nl
        .cells
        .iter()
        .map(|c| {
            let mut d: Vec<usize> = c
                .operands()
                .flat_map(|o| o.sources())
                .filter_map(|s| (driver[s] != usize::MAX).then_some(driver[s]))
                .collect();
            d.sort_unstable();
            d.dedup();
            d
        })
        .collect();
    let mut users = vec![vec![]; n];
    let mut pending: Vec<usize> = deps.iter().map(|d| d.len()).collect();
    for (k, d) in deps.iter().enumerate() {
        for &j in d {
            users[j].push(k);
        }
    }
    let mut order = Vec::with_capacity(n);
    let mut ready: Vec<usize> = (0..n).filter(|&k| pending[k] == 0).collect();
    while let Some(k) = ready.pop() {
        order.push(k);
        for &u in &users[k] {
            pending[u] -= 1;
            if pending[u] == 0 {
                ready.push(u);
            }
        }
    }
    if order.len() != n {
        let stuck: Vec<&str> = (0..n)
            .filter(|&k| pending[k] > 0)
            .take(5)
            .map(|k| nl.cells[k].name.as_str())
            .collect();
        return Err(Error::ToolOutput {
            tool: "yosys (engine)".into(),
            message: format!("combinational loop through the cells {stuck:?}"),
        });
    }
    let mut old: Vec<Option<super::netlist::Cell>> = nl.cells.drain(..).map(Some).collect();
    for &k in &order {
        if let Some(c) = old[k].take() {
            nl.cells.push(c);
        }
    }
    for (i, c) in nl.cells.iter().enumerate() {
        nl.signals[c.out].kind = SigKind::Comb(i);
    }
    // Cones: walk back from the roots, then keep the marked cells in order.
    let cone = |nl: &Netlist, roots: Vec<usize>| -> Vec<usize> {
        let mut mark = vec![false; n];
        let mut stack = roots;
        while let Some(s) = stack.pop() {
            if let SigKind::Comb(i) = nl.signals[s].kind {
                if !mark[i] {
                    mark[i] = true;
                    stack.extend(nl.cells[i].operands().flat_map(|o| o.sources()));
                }
            }
        }
        (0..n).filter(|&i| mark[i]).collect()
    };
    let mut next_roots = vec![];
    for r in &nl.regs {
        next_roots.extend(r.d.sources());
        if let Some((o, _)) = &r.en {
            next_roots.extend(o.sources());
        }
        if let Some((o, _, _)) = &r.srst {
            next_roots.extend(o.sources());
        }
    }
    for w in &nl.writes {
        next_roots.extend(
            w.addr
                .sources()
                .chain(w.data.sources())
                .chain(w.en.sources()),
        );
    }
    let out_roots = nl.outputs.iter().flat_map(|(_, o)| o.sources()).collect();
    nl.next_cone = cone(nl, next_roots);
    nl.out_cone = cone(nl, out_roots);
    Ok(())
}
