//! Runs an FFD scene with a procedural model and prints each step's figures; asserts
//! that the default solver met its tolerance.
//!
//! `cargo run --release -p sheetform-ffd --example run_scene -- examples/ffd/duct.json [paper]`

use sheetform_ffd::{run_design, FfdScene, ModelSource, SolverMethod};

// The allocator of the `sheetform` binary, so that the figures are the CLI's: glibc
// returns large blocks to the system on free and each new one is faulted in again.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() {
    // `SHEETFORM_TRACE=1`: the solver's per-iteration traces on stderr.
    if std::env::var_os("SHEETFORM_TRACE").is_some() {
        tracing_subscriber::fmt()
            .with_max_level(tracing_subscriber::filter::LevelFilter::DEBUG)
            .with_writer(std::io::stderr)
            .without_time()
            .init();
    }
    let args: Vec<String> = std::env::args().collect();
    let path = args.get(1).map_or("examples/ffd/duct.json", String::as_str);
    let text = std::fs::read_to_string(path).expect("scene file");
    let mut scene = FfdScene::from_json(&text).expect("scene");
    if args.get(2).map(String::as_str) == Some("paper") {
        scene.solver.method = SolverMethod::Paper;
    }
    let ModelSource::Procedural(model) = &scene.model else {
        panic!("this example needs a procedural model");
    };
    let mesh = model.build();
    let design = run_design(&scene, &mesh).expect("design");
    println!(
        "{}: {} vertices, {} nodes, {} panels, embedding {:.2} ms ({})",
        scene.name,
        design.assembly.mesh.positions.len(),
        design.assembly.node_count,
        design.assembly.panels.len(),
        design.embedding_time_ms,
        if design.linear_embedding { "linear" } else { "Newton" }
    );
    for step in &design.steps {
        let i = &step.info;
        println!(
            "  {} [{}]: G {:.4e} -> {:.4e}, max defect {:.3e} -> {:.3e} rad, {} iterations ({} sub-steps), converged {}, {:.1} ms, {} variables, {} constraints, deviation {:.3e}, edge change max {:.3e} mean {:.3e}, fold angle {:.3} -> {:.3} rad (largest change {:.3})",
            step.name,
            i.solver,
            i.developability_g_before,
            i.developability_g_after,
            i.angle_defect_max_before_rad,
            i.angle_defect_max_after_rad,
            i.iterations,
            i.sub_steps,
            i.converged,
            i.time_ms,
            i.variable_node_count,
            i.constraint_count,
            step.deviation_max,
            step.edge_length_change_max_relative,
            step.edge_length_change_mean_relative,
            step.fold_angle_max_before,
            step.fold_angle_max_after,
            step.fold_angle_change_max
        );
        if scene.solver.method == SolverMethod::Constrained {
            assert!(i.angle_defect_max_after_rad <= 1e-8, "defect not restored");
        }
    }
}
