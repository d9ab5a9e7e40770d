//! Solves a slit scene, prints what the solver did per strip, and asserts that every
//! strip converged and, with the gap as a constraint (the default), closed (E ≤ 1e-6).
//!
//! `cargo run --release -p sheetform-slit --example solve_scene -- examples/slit/chair.json`

fn main() {
    let path = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "examples/slit/chair.json".into());
    let text = std::fs::read_to_string(&path).expect("scene file");
    let scene = sheetform_slit::SlitScene::from_json(&text).expect("valid scene");
    let dir = std::path::Path::new(&path)
        .parent()
        .map(|p| p.to_path_buf())
        .unwrap_or_default();
    let scan = scene
        .scan
        .as_ref()
        .map(|s| std::fs::read(dir.join(&s.points)).expect("scan file"));
    let model = sheetform_slit::SlitModel::from_scene(&scene, scan.as_deref()).expect("valid model");
    let started = std::time::Instant::now();
    let design = sheetform_slit::solve_design(&model);
    let ms = started.elapsed().as_secs_f64() * 1e3;
    for s in &design.strips {
        println!(
            "strip {} quads {} iterations {} F {:.6e} -> {:.6e} E {:.2e} converged {} {:.2} ms",
            s.strip,
            s.quads,
            s.iterations,
            s.initial_penalty,
            s.penalty.total,
            s.normalised_error,
            s.converged,
            s.time_ms
        );
    }
    println!(
        "E = {:.3e}, G = {:.3e}, whole design {ms:.2} ms",
        design.normalised_error, design.gap
    );
    if model.solver.gap == sheetform_slit::GapHandling::Exact {
        assert!(design.normalised_error <= 1e-6, "the strips close");
    }
    assert!(design.strips.iter().all(|s| s.converged), "every strip converged");
}
