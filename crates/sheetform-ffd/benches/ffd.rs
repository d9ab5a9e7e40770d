//! Criterion benchmarks of developability restoration: both solvers (and the constrained
//! one along the deformation's path, and with steps along the normals) on the examples
//! at the paper's sizes, and a warm-started drag. The 100k-vertex duct
//! (`examples/ffd/duct-100k.json`) is not benchmarked here: 9–10 s a run with its normal
//! steps, 56 s with every parameter (docs/benchmarks-history.md gives its timed runs).
//!
//! `cargo bench -p sheetform-ffd --bench ffd`

use criterion::{criterion_group, criterion_main, Criterion};
use sheetform_ffd::{
    apply_edits, restore_constrained, run_design, DevelopabilityProblem, FfdScene, ModelSource, SolverMethod,
};
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
        // The springs alone, as in examples/ffd/skirt-springs.json (the default before
        // the bending term was on).
        let mut springs = constrained.clone();
        springs.solver.bending_weight = 0.0;
        // Restored along the deformation's path in adaptive sub-steps.
        let mut continuation = constrained.clone();
        continuation.solver.continuation = Some(Default::default());
        // One unknown per node, along the normal.
        let mut normal = constrained.clone();
        normal.solver.step_unknowns = sheetform_ffd::StepUnknowns::Normal;
        for (label, s) in [
            ("constrained", &constrained),
            ("paper", &paper),
            ("springs", &springs),
            ("continuation", &continuation),
            ("normal", &normal),
        ] {
            // Normal steps stall on the trousers' second deformation (nearly flat vertex
            // stars near the crotch; tests/ffd.rs): nothing to time.
            if name == "trousers" && label == "normal" {
                continue;
            }
            group.bench_function(format!("{name}/{label}"), |b| {
                b.iter(|| black_box(run_design(s, &mesh).expect("design")))
            });
        }
    }
    group.finish();
}

/// The editor's case: the skirt restored once, then one control point dragged 5 mm
/// (`examples/ffd/skirt-drag.json`, second deformation), restored from the restored
/// parameters (a warm start). Only the second restoration is timed.
fn warm_drag(c: &mut Criterion) {
    let scene = scene("skirt-drag");
    let ModelSource::Procedural(model) = &scene.model else {
        unreachable!("procedural example")
    };
    let mesh = model.build();
    let mut first = scene.clone();
    first.deformations.truncate(1);
    let design = run_design(&first, &mesh).expect("design");
    let step = &design.steps[0];
    let dragged = apply_edits(&step.volume, &scene.deformations[1].edits, "drag").expect("drag");
    let problem = DevelopabilityProblem::new(
        &dragged,
        &design.assembly,
        step.parameters.clone(),
        &scene.solver.problem_options(),
    );
    let options = scene.solver.constrained_options();
    let mut group = c.benchmark_group("ffd");
    group.sample_size(20);
    group.bench_function("skirt/warm drag", |b| {
        b.iter(|| black_box(restore_constrained(&problem, &options).expect("restored")))
    });
    group.finish();
}

criterion_group!(benches, restoration, warm_drag);
criterion_main!(benches);
