//! Benchmarks of `develop` on a fine target (issue 36: 100k faces ≤ 30 s): an icosphere
//! of 81 920 faces remeshed to the working size (10 000 faces), and the whole develop of
//! it (remeshing, automatic seams, the developability solve, the unfolding, the preview
//! outputs). Run with `cargo bench -p sheetform --bench develop`. Figures in
//! docs/benchmarks-history.md.

use criterion::{criterion_group, criterion_main, Criterion};
use sheetform::mesh::{primitives, remesh_isotropic, RemeshOptions};
use sheetform::pipeline::{run_develop, DevelopRunOptions, OutputSet, RunContext};
use std::hint::black_box;

#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn bench_develop(c: &mut Criterion) {
    let sphere = primitives::icosphere(50.0, 6);
    let mut group = c.benchmark_group("develop");
    group.sample_size(10);
    group.bench_function("remesh 82k to 10k", |b| {
        b.iter(|| remesh_isotropic(black_box(&sphere), &[], &RemeshOptions::default()))
    });
    group.bench_function("develop 82k", |b| {
        b.iter(|| {
            let context = RunContext::new(".").with_outputs(OutputSet::Preview);
            run_develop(black_box(sphere.clone()), &DevelopRunOptions::default(), &context).expect("developed")
        })
    });
    group.finish();
}

criterion_group!(benches, bench_develop);
criterion_main!(benches);
