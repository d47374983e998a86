//! Speed of the bit-accurate model (what report sweeps run) and of the hand-stepped rust-hdl
//! simulation of the core. `cargo bench --bench core`.
use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use sinedec::blocks::core::hdl::simulate_rtl;
use sinedec::blocks::core::model::{sample, CoreModel};
use sinedec::config::Loaded;
use sinedec::cosim::stimulus;

fn bench(c: &mut Criterion) {
    let l = Loaded::default_config().expect("default config");
    let d = &l.derived;
    // Every input pair of one row of the 14-bit input plane: 16384 samples.
    let mut g = c.benchmark_group("model");
    g.throughput(Throughput::Elements(16384));
    g.bench_function("sample_n14_16k", |b| {
        b.iter(|| {
            let mut acc = 0u64;
            for s in -8192..8192 {
                acc = acc.wrapping_add(sample(d, black_box(s), 3000).p);
            }
            acc
        })
    });
    let stim = stimulus::random(14, 16384, 0.0, 3);
    g.throughput(Throughput::Elements(stim.len() as u64));
    g.bench_function("core_model_cycles", |b| {
        b.iter(|| {
            let mut m = CoreModel::new(d);
            stim.iter().map(|i| m.step(*i).position).sum::<u64>()
        })
    });
    g.finish();
    let mut g = c.benchmark_group("rust_hdl");
    let stim = stimulus::random(14, 2000, 0.0, 4);
    g.throughput(Throughput::Elements(stim.len() as u64));
    g.sample_size(10);
    g.bench_function("core_n14_cycles", |b| {
        b.iter(|| simulate_rtl(d, &stim).map(|o| o.len()).unwrap_or(0))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
