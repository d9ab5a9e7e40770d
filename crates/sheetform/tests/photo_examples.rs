//! Every photo example through the library pipeline (what the CLI, the web editor and
//! the Python binding call): status ok, every patch unfolded exactly, the pattern at the
//! model's area, no NaN anywhere.

use sheetform::pipeline::{run_photo, PhotoRunOptions};
use std::path::PathBuf;

#[test]
fn every_photo_example_runs_to_an_exact_pattern() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/photo");
    let mut files = vec![root.join("coffee-cup.json")];
    for entry in std::fs::read_dir(root.join("synthetic")).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        if name.ends_with(".json") && !name.ends_with(".truth.json") {
            files.push(path);
        }
    }
    files.sort();
    assert_eq!(files.len(), 10);
    for file in files {
        let text = std::fs::read_to_string(&file).unwrap();
        let options = PhotoRunOptions {
            base_dir: file.parent().map(|p| p.to_path_buf()),
            ..Default::default()
        };
        let run = run_photo(&text, &options, &mut |_, _| {}).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        let name = file.display();
        // The perspective composite misses the refinement's bound and says so (exit 5).
        // The noisy composite's neck arc is only partly pinned by its mirror pairs (12 %
        // of a prior shift leaks through): its depth is reported undetermined.
        let expected = if name.to_string().contains("composite-perspective") {
            "not developable"
        } else if name.to_string().contains("composite-noisy") {
            "depth undetermined"
        } else {
            "ok"
        };
        assert_eq!(run.report.status, expected, "{name}");
        // Ruled strips have no interior vertex: their patterns are exact isometries.
        let iso = run.report.isometry_error_max_relative.unwrap();
        assert!(iso < 1e-9, "{name}: isometry error {iso}");
        let photo = run.report.photo.as_ref().unwrap();
        assert_eq!(photo.filled_patch_count, 0, "{name}: every patch is ruled");
        if expected == "ok" {
            assert!(photo.developability_error_refined.unwrap().max_deg < 1e-5, "{name}");
            assert!(photo.depth_undetermined_curves.is_empty(), "{name}");
        }
        assert!(run.sheet.positions.iter().all(|p| p.iter().all(|v| v.is_finite())));
        assert!(run.sheet.flat.iter().all(|p| p.iter().all(|v| v.is_finite())));
        let pattern = run.report.pattern.as_ref().unwrap();
        assert_eq!(
            pattern.mountain_fold_count + pattern.valley_fold_count,
            0,
            "{name}: bends are guides"
        );
        assert_eq!(pattern.piece_count, photo.patch_count, "{name}");
        // Every kept ruling is a bending guide; the triangulation between them is smooth.
        assert_eq!(run.sheet.rulings.len(), photo.ruling_count, "{name}");
        assert!(!run.sheet.smooth_edges.is_empty(), "{name}");
    }
}
