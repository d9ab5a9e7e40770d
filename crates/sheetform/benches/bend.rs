//! Benchmarks of system A (issue 2): a bent sheet with 100, 1 000 and 10 000 rulings
//! (sampling + boundary + mesh), and the sampling stage alone. Run with
//! `cargo bench -p sheetform --bench bend`; figures in docs/benchmarks-history.md.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use sheetform::bend::{bend, region_geometries, BendModel, BendScene};
use std::hint::black_box;

// Same allocator as the `sheetform` binary.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

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

fn bench_edits(c: &mut Criterion) {
    use sheetform::bend::{
        solve_end_normals, trim_to_length, BendEditor, CurveShape, EndHandleOptions, LengthPreservation,
    };
    use sheetform::geometry::Vec3;
    let m = model(1_000);
    let CurveShape::Bezier(curve) = m.regions[0].curve.shape().clone() else {
        panic!("example uses a Bézier")
    };
    let points = curve.control_points().to_vec();
    let rot = nalgebra::Rotation3::from_axis_angle(&Vec3::x_axis(), 0.1);
    let (n0, n1) = (rot * Vec3::new(0.0, 0.0, 1.0), rot * Vec3::new(-1.0, 0.0, 0.0));
    let options = EndHandleOptions::default();
    let mut group = c.benchmark_group("edit");
    group.bench_function("end-handle solve", |b| {
        b.iter(|| solve_end_normals(black_box(&points), Some(n0), Some(n1), &options))
    });
    let length = m.regions[0].curve.length();
    let dragged = curve.with_point(2, points[2] + Vec3::new(10.0, 0.0, 5.0));
    group.bench_function("length-preserving trim", |b| {
        b.iter(|| trim_to_length(black_box(&dragged), length))
    });
    group.bench_function("length-preserving drag + rebend (1000 rulings)", |b| {
        b.iter_batched(
            || BendEditor::new(m.clone()).expect("admissible"),
            |mut e| {
                e.drag_preserving_length(0, 2, points[2] + Vec3::new(10.0, 0.0, 5.0), LengthPreservation::Trim)
                    .expect("valid edit")
            },
            criterion::BatchSize::LargeInput,
        )
    });
    group.finish();
}

criterion_group!(edits, bench_edits);

/// The web editor's solve (issue 20): the whole pipeline with the preview outputs (GLB,
/// pattern SVG, report) next to the bend alone, at 1 000 rulings.
fn bench_preview(c: &mut Criterion) {
    use sheetform::pipeline::{run_bend, BendRunOptions, OutputSet, RunContext};
    let text = include_str!("../../../examples/bent-rectangle.json");
    let mut scene = BendScene::from_json(text).expect("example parses");
    scene.tessellation.rulings = Some(1000);
    let mut group = c.benchmark_group("editor");
    group.bench_function("run_bend preview (1000 rulings)", |b| {
        b.iter(|| {
            let context = RunContext::new(".").with_outputs(OutputSet::Preview);
            black_box(run_bend(&scene, &BendRunOptions::default(), &context).expect("bends"))
        })
    });
    let model = BendModel::from_scene(&scene).expect("example is valid");
    group.bench_function("bend alone (1000 rulings)", |b| {
        b.iter(|| black_box(bend(&model).expect("bends")))
    });
    group.finish();
}

criterion_group!(editor, bench_preview);
criterion_main!(benches, edits, editor);
