//! The scan-fitted chair (Tsuruta et al. §4.1, Eq. 6), end to end, from a point cloud this
//! example makes itself.
//!
//! ```text
//! cargo run --release -p sheetform --example scan_fitted_chair [-- OUTDIR]
//! ```
//!
//! 1. "The real chair": `examples/slit/chair.json`, solved; its whole symmetric sheet
//!    (legs and strips) is sampled at about one point per 4 mm² and every point is moved
//!    by up to 0.3 mm of deterministic noise, as a scanner would. Written to
//!    `OUTDIR/scan.ply` (ASCII PLY, millimetres).
//! 2. The designer's scene `OUTDIR/scene.json`: the same sheet and legs, but only a rough
//!    guess of the seat (a straight, level seat curve) plus `"scan": {"points":
//!    "scan.ply"}`. Anyone can re-run it: `sheetform slit OUTDIR/scene.json -o DIR`.
//! 3. The scene is run through the same pipeline as the `slit` command, with and without
//!    the scan term; the outputs of the fitted run (model, pattern, mould,
//!    `report.json` with its `scan_fit` section) are written to `OUTDIR`.
//!
//! Asserts: the fitted strips are closed (`E ≤ 1e-6`); they are at least three times
//! closer to the scan than the rough design on average and within 4 mm of it everywhere
//! (the distance is to the nearest *scanned point*, so it includes the sampling: a
//! ridge-line end on a strip's edge is about a spacing from the nearest sample even on a
//! perfect fit); and, since the real chair is known here, the fitted ridge-line ends are
//! within 0.5 mm of the real ones on average and 4 mm at most (the outermost strip, seen
//! from one side only, is the loosest).

use sheetform::pipeline::{run_slit, write_outputs, RunContext, SlitRunOptions};
use sheetform::slit::SlitScene;
use std::fmt::Write as _;
use std::path::PathBuf;

/// A deterministic value in [−1, 1] from an integer (an integer hash; no random crate
/// needed and the cloud is the same on every machine).
fn noise(seed: u64) -> f64 {
    let mut x = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15);
    x ^= x >> 31;
    x = x.wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x ^= x >> 29;
    (x >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

/// One scanned point per this many mm² of sheet (a 2 mm spacing).
const SAMPLE_AREA: f64 = 4.0;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "out/scan-fitted-chair".into()),
    );
    std::fs::create_dir_all(&out)?;
    let chair_text = include_str!("../../../examples/slit/chair.json");

    // 1. The "real" chair and its scan.
    let chair = SlitScene::from_json(chair_text)?;
    let real = run_slit(&chair, &SlitRunOptions::default(), &RunContext::new(&out))?;
    let mesh = &real.mesh;
    let mut points = Vec::new();
    for (t, tri) in mesh.triangles.iter().enumerate() {
        let [a, b, c] = tri.map(|i| mesh.positions[i as usize]);
        let area = 0.5 * (b - a).cross(&(c - a)).norm();
        let count = (area / SAMPLE_AREA).ceil() as usize;
        for k in 0..count {
            // Low-discrepancy barycentric samples (R2 sequence), folded into the triangle.
            let (mut u, mut v) = (
                (0.5 + 0.754_877_666 * k as f64) % 1.0,
                (0.5 + 0.569_840_291 * k as f64) % 1.0,
            );
            if u + v > 1.0 {
                (u, v) = (1.0 - u, 1.0 - v);
            }
            let p = a + (b - a) * u + (c - a) * v;
            let seed = (t as u64) << 20 | k as u64;
            let jitter = nalgebra::Vector3::new(noise(3 * seed), noise(3 * seed + 1), noise(3 * seed + 2)) * 0.3;
            points.push(p + jitter);
        }
    }
    let mut ply = format!(
        "ply\nformat ascii 1.0\ncomment sheetform scan_fitted_chair: samples of examples/slit/chair.json, mm\nelement vertex {}\nproperty double x\nproperty double y\nproperty double z\nend_header\n",
        points.len()
    );
    for p in &points {
        writeln!(ply, "{:.4} {:.4} {:.4}", p.x, p.y, p.z)?;
    }
    std::fs::write(out.join("scan.ply"), ply)?;

    // 2. The designer's scene: a rough, level seat and the scan.
    let mut scene: serde_json::Value = serde_json::from_str(chair_text)?;
    scene["name"] = "scan-fitted chair".into();
    scene["seat_curve"] = serde_json::json!({ "control_points": [[0, 330], [420, 330]] });
    scene["scan"] = serde_json::json!({ "points": "scan.ply" });
    scene["weights"] = serde_json::json!({ "scan": 1.0 });
    let fitted_text = serde_json::to_string_pretty(&scene)?;
    std::fs::write(out.join("scene.json"), &fitted_text)?;
    scene["weights"]["scan"] = 0.0.into();
    let unfitted_text = serde_json::to_string(&scene)?;

    // 3. The pipeline, with and without the scan term.
    let options = SlitRunOptions {
        input: Some(out.join("scene.json").display().to_string()),
        ..Default::default()
    };
    let context = RunContext::new(&out);
    let fitted = run_slit(&SlitScene::from_json(&fitted_text)?, &options, &context)?;
    let unfitted = run_slit(&SlitScene::from_json(&unfitted_text)?, &options, &context)?;
    write_outputs(&out, &fitted.files, &fitted.report)?;

    let fit = |run: &sheetform::pipeline::SlitRun| run.report.slit.as_ref().and_then(|s| s.scan_fit.clone());
    let (before, after) = (fit(&unfitted).expect("scan fit"), fit(&fitted).expect("scan fit"));
    let slit = fitted.report.slit.as_ref().expect("slit report");
    println!(
        "scan: {} points; fitted {} ridge-line end points",
        after.scanned_point_count, after.fitted_point_count
    );
    println!(
        "distance to the scan, mean / max: rough seat {:.2} / {:.2} mm, fitted {:.2} / {:.2} mm",
        before.distance_mean_mm, before.distance_max_mm, after.distance_mean_mm, after.distance_max_mm
    );
    println!(
        "E = {:.1e}, {} strips converged: {}; wrote {} files to {}",
        slit.normalised_error,
        slit.strips.len(),
        slit.converged,
        fitted.report.outputs.len(),
        out.display()
    );
    // The real chair is known here: how far is each fitted ridge-line end from the real
    // one (same strip, ridge and side)?
    let offsets: Vec<f64> = real
        .design
        .folded(&real.model)
        .iter()
        .zip(fitted.design.folded(&fitted.model))
        .flat_map(|(r, f)| {
            let left = r.left.iter().zip(&f.left).skip(1);
            let right = r.right.iter().zip(&f.right).skip(1);
            left.chain(right).map(|(p, q)| (p - q).norm()).collect::<Vec<_>>()
        })
        .collect();
    let offset_mean = offsets.iter().sum::<f64>() / offsets.len() as f64;
    let offset_max = offsets.iter().copied().fold(0.0, f64::max);
    println!("fitted vs the real chair's ridge-line ends: mean {offset_mean:.2} mm, max {offset_max:.2} mm");
    assert!(slit.converged && slit.normalised_error <= 1e-6, "the strips close");
    assert!(
        after.distance_mean_mm * 3.0 < before.distance_mean_mm,
        "fitting brings the strips to the scan: {before:?} -> {after:?}"
    );
    assert!(after.distance_max_mm < 4.0, "{after:?}");
    assert!(offset_mean < 0.5 && offset_max < 4.0, "{offset_mean} {offset_max}");
    Ok(())
}
