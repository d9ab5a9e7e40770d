//! Reconstructs an annotation and prints what each stage made (no files written):
//! `cargo run --release -p sheetform-photo --example reconstruct -- ANNOTATION.json`.

use sheetform_photo::{reconstruct, AngleSummary, PhotoAnnotation};

fn main() {
    let path = std::env::args().nth(1).expect("usage: reconstruct ANNOTATION.json");
    let text = std::fs::read_to_string(&path).expect("readable annotation");
    let annotation = match PhotoAnnotation::from_json(&text) {
        Ok(a) => a,
        Err(e) => {
            eprintln!("{path}: {e}");
            std::process::exit(1);
        }
    };
    let start = std::time::Instant::now();
    let r = match reconstruct(&annotation) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("{path}: {e}");
            std::process::exit(1);
        }
    };
    let elapsed = start.elapsed().as_secs_f64() * 1e3;
    println!("{path}: {elapsed:.1} ms");
    println!(
        "  network: {} points, {} segments, {} junctions; patches {} ({} openings)",
        r.network.points.len(),
        r.network.segments.len(),
        r.network.junction_count,
        r.patches.len(),
        r.patches.iter().filter(|p| p.opening).count()
    );
    println!(
        "  rulings {} in {} strips (candidates {}, rejected {}); symmetric pairs {}",
        r.ruling_count(),
        r.strips.len(),
        r.propagation.candidate_count,
        r.propagation.rejected_count,
        r.pairs.len()
    );
    let (lin, refined) = (
        AngleSummary::of(&r.ruling_errors_linear),
        AngleSummary::of(&r.ruling_errors_refined),
    );
    println!(
        "  developability error: linear mean {:.3}° max {:.3}°; refined mean {:.2e}° max {:.2e}°",
        lin.mean_deg, lin.max_deg, refined.mean_deg, refined.max_deg
    );
    if let Some(info) = r.refinement {
        println!(
            "  refinement: {} iterations, {} constraints, violation {:.1e}, moved {:.2} px",
            info.iterations, info.constraint_count, info.constraint_violation, info.displacement_max
        );
    }
    println!(
        "  reprojection mean {:.3} px max {:.3} px; {:.4} units/px; mesh {} vertices {} triangles",
        r.reprojection_error_px.0,
        r.reprojection_error_px.1,
        r.unit_per_pixel,
        r.mesh.positions.len(),
        r.mesh.triangles.len()
    );
    println!(
        "  depth sensitivity max {:.3}; undetermined: {:?}",
        r.depth_sensitivity.iter().copied().fold(0.0, f64::max),
        r.depth_undetermined_curves()
    );
    println!("  times: {:?}", r.times);
}
