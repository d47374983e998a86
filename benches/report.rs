//! Speed of the report's exhaustive accuracy sweep of the default configuration (14-bit
//! input: every input pair of at least 1/8 full scale, 263 million pairs), single N and all
//! N = 2..=20 in one pass. `cargo bench --bench report`.
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use sinedec::config::Loaded;
use sinedec::report::sweep::{sweep, SweepPlan};
use sinedec::report::with_iterations;

fn bench(c: &mut Criterion) {
    let l = Loaded::default_config().expect("default config");
    let plan = SweepPlan::for_width(l.derived.adc_width);
    assert!(plan.exhaustive());
    let n14 = with_iterations(&l, 14).expect("N = 14");
    let pairs = sweep(&[&n14.derived], plan, None, &|| {})[0].count;
    eprintln!(
        "exhaustive sweep: {pairs} input pairs, {} threads",
        rayon::current_num_threads()
    );
    let mut g = c.benchmark_group("report_sweep");
    g.sample_size(10);
    g.throughput(Throughput::Elements(pairs));
    g.bench_function("exhaustive_a14_n14", |b| {
        b.iter(|| sweep(&[&n14.derived], plan, Some(0), &|| {}))
    });
    let all: Vec<Loaded> = (2..=20)
        .map(|n| with_iterations(&l, n).expect("N"))
        .collect();
    let ds: Vec<_> = all.iter().map(|l| &l.derived).collect();
    g.throughput(Throughput::Elements(pairs * ds.len() as u64));
    g.bench_function("exhaustive_a14_n2_to_20", |b| {
        b.iter(|| sweep(&ds, plan, Some(12), &|| {}))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
