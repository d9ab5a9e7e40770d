//! Criterion benchmarks of developability restoration: both solvers on the examples at
//! the paper's sizes. The 100k-vertex duct (`examples/ffd/duct-100k.json`) is not
//! benchmarked yet: the constrained solver does not converge on it (see
//! docs/benchmarks.md).
//!
//! `cargo bench -p sheetform-ffd --bench ffd`

use criterion::{criterion_group, criterion_main, Criterion};
use sheetform_ffd::{run_design, FfdScene, ModelSource, SolverMethod};
use std::hint::black_box;

fn scene(name: &str) -> FfdScene {
    let path = format!("{}/../../examples/ffd/{name}.json", env!("CARGO_MANIFEST_DIR"));
    FfdScene::from_json(&std::fs::read_to_string(path).expect("example")).expect("scene")
}

fn restoration(c: &mut Criterion) {
    let names = ["two-panels", "duct", "skirt", "trousers"];
    let mut group = c.benchmark_group("ffd");
    group.sample_size(10);
    for name in names {
        let constrained = scene(name);
        let ModelSource::Procedural(model) = &constrained.model else {
            unreachable!("procedural examples")
        };
        let mesh = model.build();
        let mut paper = constrained.clone();
        paper.solver.method = SolverMethod::Paper;
        // The preview settings of examples/ffd/skirt-preview.json: the bending term in
        // the step metric, and the bound 1e-8 as tolerance.
        let mut preview = constrained.clone();
        preview.solver.bending_weight = 0.1;
        preview.solver.tolerance_rad = 1e-8;
        for (label, s) in [("constrained", &constrained), ("paper", &paper), ("preview", &preview)] {
            group.bench_function(format!("{name}/{label}"), |b| {
                b.iter(|| black_box(run_design(s, &mesh).expect("design")))
            });
        }
    }
    group.finish();
}

criterion_group!(benches, restoration);
criterion_main!(benches);
