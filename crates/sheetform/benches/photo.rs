//! Benchmarks of system D (issue 18): the reconstruction alone (`reconstruct`: network,
//! rulings, symmetry, linear solve, refinement, meshing) and the whole pipeline
//! (`run_photo`: the image read, every patch unfolded, OBJ/GLB/STL, SVG/DXF/PDF pattern,
//! overlay, report) on the dense lamp (118 control points, 149 rulings; the issue's
//! "100 control points and ~150 rulings") and the hand-traced espresso cup. Run with
//! `cargo bench -p sheetform --bench photo`; figures in docs/benchmarks-history.md.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use sheetform::photo::{reconstruct, PhotoAnnotation};
use sheetform::pipeline::{run_photo, PhotoInput, PhotoRunOptions, RunContext};
use std::hint::black_box;
use std::path::PathBuf;

#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn bench_photo(c: &mut Criterion) {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/photo");
    let mut group = c.benchmark_group("photo");
    group.sample_size(20);
    for (label, file) in [
        ("lamp", root.join("bench/lamp.json")),
        ("cup", root.join("coffee-cup.json")),
    ] {
        let text = std::fs::read_to_string(&file).expect("example");
        let annotation = PhotoAnnotation::from_json(&text).expect("valid");
        group.bench_with_input(BenchmarkId::new("reconstruct", label), &annotation, |b, a| {
            b.iter(|| reconstruct(black_box(a)).expect("reconstructs"))
        });
        let options = PhotoRunOptions::default();
        let context = RunContext::new(file.parent().expect("a directory"));
        let input = PhotoInput::from_text(&text).expect("valid");
        group.bench_with_input(BenchmarkId::new("run_photo", label), &input, |b, i| {
            b.iter(|| run_photo(black_box(i), &options, &context).expect("runs"))
        });
    }
    group.finish();
}

criterion_group!(benches, bench_photo);
criterion_main!(benches);
