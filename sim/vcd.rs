//! A minimal VCD writer for per-cycle traces (the rust-hdl VCD probe writes every half
//! cycle of every signal and is ten times slower; this one writes the top's pins only).
use crate::sim::cosim::Port;
use std::fmt::Write as _;

/// VCD text of `rows` (one per clock cycle, values in `ports` order) with a clock of
/// `period_ps`; identifiers are `"`, `#`, ... with `clk` first, then the ports in order.
pub fn write_vcd(module: &str, ports: &[Port], rows: &[Vec<u64>], period_ps: u64) -> String {
    let id = |i: usize| -> String {
        let mut n = i + 1;
        let mut s = String::new();
        while n > 0 {
            s.push((b'!' + (n % 94) as u8) as char);
            n /= 94;
        }
        s
    };
    let mut o = String::new();
    let _ = writeln!(o, "$timescale 1ps $end\n$scope module {module} $end");
    let _ = writeln!(o, "$var wire 1 {} clk $end", id(0));
    for (i, p) in ports.iter().enumerate() {
        let _ = writeln!(o, "$var wire {} {} {} $end", p.width, id(i + 1), p.name);
    }
    let _ = writeln!(o, "$upscope $end\n$enddefinitions $end");
    let value = |p: &Port, v: u64, i: usize| {
        if p.width == 1 {
            format!("{}{}\n", v & 1, id(i + 1))
        } else {
            format!("b{:b} {}\n", v, id(i + 1))
        }
    };
    let mut last: Option<&Vec<u64>> = None;
    for (k, r) in rows.iter().enumerate() {
        let t = k as u64 * period_ps;
        let _ = write!(o, "#{t}\n1{}\n", id(0));
        for (i, p) in ports.iter().enumerate() {
            let v = r.get(i).copied().unwrap_or(0);
            if last.map(|l| l.get(i).copied() != Some(v)).unwrap_or(true) {
                o.push_str(&value(p, v, i));
            }
        }
        let _ = write!(o, "#{}\n0{}\n", t + period_ps / 2, id(0));
        last = Some(r);
    }
    o
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_only_changes() {
        let ports = [Port::new("a", 1), Port::new("b", 4)];
        let rows = vec![vec![0, 3], vec![0, 3], vec![1, 5]];
        let v = write_vcd("t", &ports, &rows, 1000);
        // Identifiers: clk `"`, a `#`, b `$`.
        assert!(v.contains("$var wire 4 $ b $end"), "{v}");
        assert!(v.contains("#0\n1\"\n0#\nb11 $\n"), "{v}");
        assert!(v.contains("#1000\n1\"\n#1500"), "{v}");
        assert!(v.contains("#2000\n1\"\n1#\nb101 $\n"), "{v}");
    }
}
