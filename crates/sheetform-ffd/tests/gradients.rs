//! The problem's exact gradients against central differences.

use nalgebra::Vector3;
use sheetform_ffd::procedural_panels::ProceduralModel;
use sheetform_ffd::{apply_edits, embed_points, DevelopabilityProblem, FfdScene, PanelAssembly, ProblemOptions};

/// A deformed two-panel assembly in a rational, non-affine lattice.
fn deformed_problem_parts() -> (PanelAssembly, sheetform_ffd::NurbsVolume, Vec<Vector3<f64>>) {
    let mesh = ProceduralModel::TwoPanels { columns: 4, rows: 4 }.build();
    let assembly = PanelAssembly::from_mesh(&mesh).unwrap();
    let scene = FfdScene::from_json(
        r#"{"model": {"procedural": {"kind": "two_panels"}}, "lattice": {"counts": [4, 4, 4]},
            "deformations": [{"edits": [
               {"move": {"points": [[1, 2, 1], [2, 1, 2]], "by": [30, -20, 15]}},
               {"weight": {"points": [[2, 2, 2]], "value": 2.5}}]}]}"#,
    )
    .unwrap();
    let nodes = assembly.node_positions();
    let lattice = scene.lattice(&nodes).unwrap();
    let x = embed_points(&lattice, &nodes).unwrap();
    let volume = apply_edits(&lattice, &scene.deformations[0].edits, "edits").unwrap();
    (assembly, volume, x)
}

#[test]
fn spring_and_defect_gradients_match_finite_differences() {
    let (assembly, volume, x) = deformed_problem_parts();
    let problem = DevelopabilityProblem::new(&volume, &assembly, x, &ProblemOptions::default());
    assert!(problem.constraint_count() > 5 && problem.variables.len() > 10);
    // Evaluate away from the start so that spring residuals are not zero.
    let mut y = problem.gather(&problem.start);
    for (i, v) in y.iter_mut().enumerate() {
        *v += 0.01 * ((i as f64) * 0.77).sin();
    }
    let e = problem.evaluate(&y);
    let h = 1e-6;
    let mut row = Vec::new();
    let mut worst: f64 = 0.0;
    for c in (0..problem.constraint_count()).step_by(3) {
        problem.defect_gradient(&e, c, &mut row);
        for (v, d) in &row {
            for k in 0..3 {
                let (mut plus, mut minus) = (y.clone(), y.clone());
                plus[3 * *v as usize + k] += h;
                minus[3 * *v as usize + k] -= h;
                let fd = (problem.evaluate(&plus).defects[c] - problem.evaluate(&minus).defects[c]) / (2.0 * h);
                worst = worst.max((fd - d[k]).abs() / (1.0 + fd.abs()));
            }
        }
    }
    assert!(worst < 1e-6, "defect gradient error {worst}");
    let mut worst: f64 = 0.0;
    for s in (0..problem.springs.len()).step_by(5) {
        for (v, d) in problem.spring_gradient(&e, s) {
            if v == u32::MAX {
                continue;
            }
            for k in 0..3 {
                let (mut plus, mut minus) = (y.clone(), y.clone());
                plus[3 * v as usize + k] += h;
                minus[3 * v as usize + k] -= h;
                let fd = (problem.evaluate(&plus).spring_residuals[s] - problem.evaluate(&minus).spring_residuals[s])
                    / (2.0 * h);
                worst = worst.max((fd - d[k]).abs() / (1.0 + fd.abs()));
            }
        }
    }
    assert!(worst < 1e-6, "spring gradient error {worst}");
}
