//! Prints LUT/FF/carry counts of `<name>_core` for N = 2, 5, 8, 11, 14 on both families,
//! and the xc3sa LUT/FF of both CORDIC architectures (the figures quoted in README.md).
//! `cargo run --release --example synth_table`.
use sinedec::config::{Loaded, DEFAULT_CONFIG};
use sinedec::emit::{core_name, core_verilog};
use sinedec::synth::{synthesize, Family};

fn main() -> anyhow::Result<()> {
    let thesis = [
        (2, 313, 8),
        (5, 4231, 11),
        (8, 8782, 14),
        (11, 13177, 17),
        (14, 17521, 20),
    ];
    println!("| N | latency (cycles) | xc3sa LUT4 | xc3sa FF | xc3sa MUXCY | cycloneive LE | cycloneive FF | thesis gates | thesis cycles |");
    println!("|---|---|---|---|---|---|---|---|---|");
    let dir = std::env::temp_dir().join("sinedec_synth_table");
    std::fs::create_dir_all(&dir)?;
    let mut arch_rows = Vec::new();
    for (n, gates, cycles) in thesis {
        let text = DEFAULT_CONFIG.replace("iterations = 14", &format!("iterations = {n}"));
        let l = Loaded::parse(&text, "default")?;
        let v = core_verilog(&l)?;
        let top = core_name(&l);
        let x = synthesize(&v, &top, Family::Xc3sa, &dir)?;
        let c = synthesize(&v, &top, Family::CycloneIve, &dir)?;
        println!(
            "| {n} | {} | {} | {} | {} | {} | {} | {gates} | {cycles} |",
            l.derived.latency_cycles, x.luts, x.ffs, x.carry, c.luts, c.ffs
        );
        let it = Loaded::parse(
            &text.replace(
                "architecture = \"unrolled\"",
                "architecture = \"iterative\"",
            ),
            "default",
        )?;
        let i = synthesize(&core_verilog(&it)?, &core_name(&it), Family::Xc3sa, &dir)?;
        arch_rows.push(format!(
            "| {n} | {} / {} | {} / {} | {:.3} | {} | {:.3} |",
            x.luts,
            x.ffs,
            i.luts,
            i.ffs,
            i.luts as f64 / x.luts as f64,
            it.derived.latency_cycles,
            it.derived.clock_hz / it.derived.cycles_per_sample as f64 / 1e6
        ));
    }
    println!();
    println!("| N | unrolled LUT4 / FF | iterative LUT4 / FF | iterative / unrolled LUT4 | iterative latency | iterative throughput (Msample/s) |");
    println!("|---|---|---|---|---|---|");
    for r in arch_rows {
        println!("{r}");
    }
    Ok(())
}
