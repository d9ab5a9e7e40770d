//! Criterion benchmarks of the slit-sheet solver (issue 4): one strip of the chair with
//! M = 10, 20 and 40 quads, from the paper's initial state and from a nearly converged
//! state, and the whole 6-strip chair with 10 quads per strip.
//!
//! `cargo bench -p sheetform-slit --bench slit`
//!
//! "Nearly converged": the solved strip with every ridge angle moved by up to 0.5 mrad and
//! every ridge-line end by up to 0.1 mm (a small edit, as when the user drags an anchor).
//! Iteration counts and the reached `E` are printed once per case, before timing.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use sheetform_slit::strip_folding::StripState;
use sheetform_slit::strip_solver::solve_strip;
use sheetform_slit::{solve_design, SlitModel, SlitScene};
use std::hint::black_box;

fn chair(quads: usize) -> SlitModel {
    let path = format!("{}/../../examples/slit/chair.json", env!("CARGO_MANIFEST_DIR"));
    let mut scene = SlitScene::from_json(&std::fs::read_to_string(path).expect("example")).expect("scene");
    scene.sheet.quads_per_strip = quads;
    SlitModel::from_scene(&scene, None).expect("model")
}

fn nearly_converged(model: &SlitModel) -> StripState {
    let mut state = StripState::initial(model.layout.quads_per_strip, model.layout.strip_length);
    solve_strip(model.strip_terms(0, 0), 0, &mut state, &model.solve_options());
    for i in 1..state.quads() {
        let t = i as f64;
        state.angles[i] += 5e-4 * (1.7 * t).sin();
        state.left[i] += 0.1 * (0.9 * t).cos();
        state.right[i] -= 0.1 * (1.3 * t).sin();
    }
    state
}

fn strips(c: &mut Criterion) {
    let mut group = c.benchmark_group("slit_strip");
    group.sample_size(20);
    for quads in [10, 20, 40] {
        let model = chair(quads);
        let options = model.solve_options();
        let starts = [
            ("initial", StripState::initial(quads, model.layout.strip_length)),
            ("nearly_converged", nearly_converged(&model)),
        ];
        for (name, start) in starts {
            let mut once = start.clone();
            let info = solve_strip(model.strip_terms(0, 0), 0, &mut once, &options);
            eprintln!(
                "slit_strip/{name}/{quads}: {} iterations, E = {:.1e}, converged {}",
                info.iterations, info.normalised_error, info.converged
            );
            assert!(info.converged && info.normalised_error <= 1e-6, "{info:?}");
            group.bench_with_input(BenchmarkId::new(name, quads), &start, |b, start| {
                b.iter(|| {
                    let mut state = start.clone();
                    black_box(solve_strip(model.strip_terms(0, 0), 0, &mut state, &options))
                })
            });
        }
    }
    group.finish();
}

fn whole_chair(c: &mut Criterion) {
    let model = chair(10);
    let design = solve_design(&model);
    eprintln!(
        "slit_chair/6x10: iterations per strip {:?}, E = {:.1e}",
        design.strips.iter().map(|s| s.iterations).collect::<Vec<_>>(),
        design.normalised_error
    );
    assert!(design.normalised_error <= 1e-6);
    let mut group = c.benchmark_group("slit_chair");
    group.sample_size(20);
    group.bench_function("6x10", |b| b.iter(|| black_box(solve_design(&model))));
    group.finish();
}

criterion_group!(benches, strips, whole_chair);
criterion_main!(benches);
