//! Benchmarks of system A (issue 2): a bent sheet with 100, 1 000 and 10 000 rulings
//! (sampling + boundary + mesh), and the sampling stage alone. Run with
//! `cargo bench -p sheetform --bench bend`; figures in docs/benchmarks.md.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use sheetform::bend::{bend, region_geometries, BendModel, BendScene};
use std::hint::black_box;

fn model(rulings: usize) -> BendModel {
    let text = include_str!("../../../examples/bent-rectangle.json");
    let mut scene = BendScene::from_json(text).expect("example parses");
    scene.tessellation.rulings = Some(rulings);
    BendModel::from_scene(&scene).expect("example is valid")
}

fn bench_bend(c: &mut Criterion) {
    let mut group = c.benchmark_group("bend");
    for n in [100usize, 1_000, 10_000] {
        let m = model(n);
        group.throughput(Throughput::Elements(n as u64));
        group.bench_with_input(BenchmarkId::new("sample+boundary+mesh", n), &m, |b, m| {
            b.iter(|| bend(black_box(m)).expect("admissible"))
        });
        group.bench_with_input(BenchmarkId::new("sample+boundary", n), &m, |b, m| {
            b.iter(|| region_geometries(black_box(m)).expect("admissible"))
        });
    }
    group.finish();
}

criterion_group!(benches, bench_bend);
criterion_main!(benches);
