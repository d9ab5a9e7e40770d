//! Issue 34: patterns a maker can glue as printed, checked on the written files by an
//! outside reader (`tools/pattern_audit.py`), never on the report's own counts; the
//! report's figures are then compared with what the files show.

use crate::common::{example_mesh, pattern_audit, report, sheetform, write_obj};
use serde_json::Value;
use sheetform::mesh::primitives;
use std::path::{Path, PathBuf};

fn count(v: &Value, key: &str) -> u64 {
    v[key].as_u64().unwrap_or_else(|| panic!("{key} missing in {v}"))
}

/// What every pattern with glue tabs must show in its files: one tab per glued edge pair
/// (none counted by the report as such), tabs no shallower than the stated minimum and
/// clear of every other cut line, the seam IDs the report says are printed on both copies
/// found next to both copies, no crossing cut lines, no label over a line or outside its
/// piece, pieces apart by the clearance, and a DXF layer for each kind of line.
pub(crate) fn assert_gluable(name: &str, out: &Path) -> (Value, Value) {
    let r = report(out);
    let a = pattern_audit(out);
    let p = &r["pattern"];
    let tabs = &p["tabs"];
    assert_eq!(count(&a, "pieces_unregistered"), 0, "{name}: {a}");
    assert_eq!(
        count(&a, "pairs_tab_both"),
        0,
        "{name}: a pair with a tab on both copies: {a}"
    );
    assert_eq!(
        count(&a, "glued_edge_pairs"),
        count(tabs, "glued_edge_pair_count"),
        "{name}: {a} {tabs}"
    );
    assert_eq!(
        count(&a, "pairs_tab_none"),
        count(tabs, "glued_edge_pairs_without_tab"),
        "{name}: the report's pairs without a tab are those in the file: {a} {tabs}"
    );
    let clearance = tabs["clearance_mm"].as_f64().unwrap();
    if count(&a, "pairs_tab_one") > 0 {
        let shallowest = a["tab_depth_min_mm"].as_f64().unwrap();
        assert!(
            shallowest >= tabs["depth_min_allowed_mm"].as_f64().unwrap() - 1e-3,
            "{name}: a sliver of a tab: {a} {tabs}"
        );
        assert!(
            (shallowest - tabs["depth_min_mm"].as_f64().unwrap()).abs() < 1e-3,
            "{name}: {a} {tabs}"
        );
    }
    assert_eq!(count(&a, "tabs_closer_than_clearance"), 0, "{name}: {a}");
    if let Some(gap) = a["tab_clearance_min_mm"].as_f64() {
        assert!(gap >= clearance - 1e-3, "{name}: {a}");
    }
    if let Some(gap) = a["piece_gap_min_mm"].as_f64() {
        assert!(gap >= clearance - 1e-3, "{name}: pieces closer than the clearance: {a}");
    }
    // Seam IDs: on both copies as often as the report says, never two different IDs on
    // one seam's copies, never one ID on more than one seam.
    assert_eq!(count(&a, "seams"), count(p, "seam_count"), "{name}: {a}");
    assert_eq!(
        count(&a, "seams_id_both"),
        count(p, "seam_count") - count(p, "seam_id_missing_count"),
        "{name}: {a} {p}"
    );
    assert_eq!(count(&a, "seams_id_mismatch"), 0, "{name}: {a}");
    assert_eq!(count(&a, "seam_ids_reused"), 0, "{name}: {a}");
    assert_eq!(count(&a, "zero_width_slits"), 0, "{name}: an edge cut for nothing: {a}");
    assert_eq!(count(&a, "cut_crossings"), 0, "{name}: {a}");
    assert_eq!(count(&a, "labels_over_lines"), 0, "{name}: {a}");
    assert_eq!(count(&a, "labels_outside"), 0, "{name}: {a}");
    assert_eq!(a["dxf"]["layers_apart"], true, "{name}: {}", a["dxf"]);
    (r, a)
}

fn flatten(mesh: &Path, out: &Path, extra: &[&str]) {
    let mut args = vec!["flatten", mesh.to_str().unwrap(), "-o", out.to_str().unwrap(), "-q"];
    args.extend_from_slice(extra);
    let o = sheetform(&args);
    assert!(o.status.success(), "{args:?}: {}", String::from_utf8_lossy(&o.stderr));
}

/// The nets of the models: every glued pair with one tab (none on both copies),
/// every seam's ID on both copies, as the files show (the gift box had 4 of its 7 pairs
/// tabbed on both copies and 4 of its 5 IDs on one copy only).
#[test]
fn nets_carry_one_tab_per_glued_pair_and_both_ids() {
    let dir = tempfile::tempdir().unwrap();
    let tmp = dir.path();
    let cases: Vec<(&str, PathBuf, Vec<&str>)> = vec![
        ("gift-box", example_mesh("gift-box.obj"), vec![]),
        (
            "box",
            write_obj(tmp, "box", &primitives::cuboid([60.0, 40.0, 30.0])),
            vec![],
        ),
        (
            "icosphere",
            write_obj(tmp, "icosphere", &primitives::icosphere(50.0, 2)),
            vec![],
        ),
        (
            "cylinder",
            write_obj(tmp, "cylinder", &primitives::cylinder(30.0, 80.0, 32, true)),
            vec![],
        ),
        ("bunny", example_mesh("bunny-99.stl"), vec!["--units", "m"]),
    ];
    for (name, mesh, extra) in cases {
        let out = tmp.join(format!("{name}-out"));
        flatten(&mesh, &out, &extra);
        let (r, a) = assert_gluable(name, &out);
        assert_eq!(r["layout"], "net", "{name}");
        // These have room for every ID.
        assert_eq!(count(&r["pattern"], "seam_id_missing_count"), 0, "{name}: {a}");
        assert_eq!(count(&a, "seams_id_one_side"), 0, "{name}: {a}");
        assert!(count(&a, "pairs_tab_one") > 0, "{name}: {a}");
    }
}

/// Tabs alternating between the seams' sides, and a user's tab depth: still one per pair.
#[test]
fn alternating_and_deep_tabs_stay_one_per_pair() {
    let tmp = tempfile::tempdir().unwrap();
    let mesh = example_mesh("gift-box.obj");
    for (label, extra) in [
        ("alternate", vec!["--tabs", "alternate"]),
        ("deep", vec!["--tab-width", "12", "--tab-angle", "60"]),
    ] {
        let out = tmp.path().join(label);
        flatten(&mesh, &out, &extra);
        let (_, a) = assert_gluable(label, &out);
        assert_eq!(
            count(&a, "pairs_tab_one"),
            count(&a, "glued_edge_pairs"),
            "{label}: {a}"
        );
    }
}

/// `--sheet a4`: a net too large for a page (the icosphere's was one 290 × 281 mm star)
/// is cut into pieces that each fit the printable area of an A4 page with their tabs,
/// packed one sheet per page; still one tab per glued pair and both IDs, read from the
/// packed files (each piece found turned and moved on its sheet).
#[test]
fn a_net_is_cut_to_fit_the_sheet_and_printed_one_sheet_a_page() {
    let dir = tempfile::tempdir().unwrap();
    let tmp = dir.path();
    let cases: Vec<(&str, PathBuf, Vec<&str>)> = vec![
        (
            "icosphere",
            write_obj(tmp, "icosphere", &primitives::icosphere(50.0, 2)),
            vec!["--sheet", "a4"],
        ),
        (
            "bunny",
            example_mesh("bunny-99.stl"),
            vec!["--units", "m", "--sheet", "a4"],
        ),
    ];
    for (name, mesh, extra) in cases {
        let out = tmp.join(format!("{name}-a4"));
        flatten(&mesh, &out, &extra);
        let (r, a) = assert_gluable(name, &out);
        let p = &r["pattern"];
        assert_eq!(r["layout"], "net", "{name}");
        assert!(
            count(&a, "pairs_tab_none") * 50 <= count(&a, "glued_edge_pairs"),
            "{name}: {a}"
        );
        assert!(count(p, "sheet_count") >= 1, "{name}");
        assert_eq!(
            count(p, "page_count"),
            count(p, "sheet_count"),
            "{name}: one page a sheet"
        );
        // Every sheet's cut lines inside the printable area of A4 (186 × 261 mm).
        for sheet in 1..=count(p, "sheet_count") {
            let svg = std::fs::read_to_string(out.join(format!("sheets/sheet-{sheet:02}.svg"))).unwrap();
            let loops = crate::common::svg_cut_loops(&svg);
            let (lo, hi) = loops
                .iter()
                .flatten()
                .fold(([f64::MAX; 2], [f64::MIN; 2]), |(lo, hi), p| {
                    ([lo[0].min(p[0]), lo[1].min(p[1])], [hi[0].max(p[0]), hi[1].max(p[1])])
                });
            assert!(
                hi[0] - lo[0] <= 186.0 && hi[1] - lo[1] <= 261.0,
                "{name} sheet {sheet}: {lo:?} {hi:?}"
            );
        }
    }
}

/// Congruent pieces with no printed name (issue 34): a torus of 32 × 12 quads cut to fit
/// A4 sheets has pieces too small to carry their name, some of them congruent, each
/// fitting the others' printed outlines. The audit finds every place each piece fits and
/// assigns them all together, one piece to an outline; placed one by one, the first took
/// a place only a later one fits, and a piece was not found. Every piece is found, and
/// the files pass as any packed pattern: one tab per glued pair, every seam's ID on both
/// copies.
#[test]
fn congruent_unnamed_pieces_are_each_found_on_their_own_outline() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = write_obj(dir.path(), "torus", &primitives::torus(60.0, 20.0, 32, 12));
    let out = dir.path().join("torus-a4");
    flatten(&mesh, &out, &["--sheet", "a4"]);
    let (r, a) = assert_gluable("torus", &out);
    let p = &r["pattern"];
    assert_eq!(count(&a, "pieces"), count(p, "piece_count"), "{a}");
    // The case: pieces printed without their name.
    let svg = std::fs::read_to_string(out.join("pattern.svg")).unwrap();
    let named = crate::common::svg_texts(&svg, "piece").len() as u64;
    assert!(named + 2 <= count(p, "piece_count"), "{named} names: {a}");
    assert_eq!(count(p, "seam_id_missing_count"), 0, "{a}");
    assert_eq!(count(&a, "seams_id_both"), count(&a, "seams"), "{a}");
    assert!(count(&a, "pairs_tab_none") * 50 <= count(&a, "glued_edge_pairs"), "{a}");
}

/// No edge cut for nothing (issue 34): a net that cuts the fans of saddle vertices (the
/// inner half of a torus) kept those cuts where the growth had in the end laid both faces
/// of the edge side by side, so 34 of this torus's seams (47 of a 32 × 32 one) were
/// slits of zero width, their two IDs printed next to each other and no tab on either.
/// Such edges are joined again, and pieces that meet across a saddle's cut are joined
/// where they fit.
#[test]
fn a_torus_cut_at_its_saddles_has_no_slit_of_zero_width() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = write_obj(dir.path(), "torus", &primitives::torus(60.0, 20.0, 24, 32));
    let out = dir.path().join("torus-a4");
    flatten(&mesh, &out, &["--sheet", "a4"]);
    let (r, a) = assert_gluable("torus", &out);
    assert_eq!(r["layout"], "net");
    assert!(count(&a, "pairs_tab_none") * 50 <= count(&a, "glued_edge_pairs"), "{a}");
    assert!(count(&a, "seams_id_both") * 20 >= count(&a, "seams") * 19, "{a}");
}

/// Scale on import: a mesh in metres read as millimetres prints a fraction of a
/// millimetre: written (exit 0) with a warning in the report and on stderr that names
/// --units and --size. `--size 150` scales the pattern so the model stands 150 mm high
/// (its extent along y in the OBJ's 3D positions times the report's scale, and the files
/// read back at that scale); `--size` with `--scale`, or not a height, is refused naming it.
#[test]
fn a_model_in_metres_is_warned_about_and_sized_by_its_height() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = example_mesh("bunny-99.stl");
    let tiny = dir.path().join("tiny");
    let o = sheetform(&["flatten", mesh.to_str().unwrap(), "-o", tiny.to_str().unwrap(), "-q"]);
    assert!(o.status.success());
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.contains("warning") && stderr.contains("--units") && stderr.contains("--size"),
        "{stderr}"
    );
    let warnings = report(&tiny)["warnings"].clone();
    assert_eq!(warnings.as_array().map(Vec::len), Some(1), "{warnings}");
    assert!(
        warnings[0].as_str().unwrap().contains("0.155383 mm across"),
        "{warnings}"
    );

    let sized = dir.path().join("sized");
    flatten(&mesh, &sized, &["--size", "150"]);
    let r = report(&sized);
    assert!(r.get("warnings").is_none(), "{r}");
    let obj = crate::common::read_obj(&sized.join("model.obj"));
    let (lo, hi) = obj
        .v
        .iter()
        .fold((f64::MAX, f64::MIN), |(lo, hi), p| (lo.min(p[1]), hi.max(p[1])));
    let scale = r["pattern"]["scale"].as_f64().unwrap();
    assert!(((hi - lo) * scale - 150.0).abs() < 1e-9, "{} mm", (hi - lo) * scale);
    assert_gluable("bunny at 150 mm", &sized);

    for (extra, says) in [
        (vec!["--size", "150", "--scale", "2"], "not both"),
        (vec!["--size", "0"], "height"),
        (vec!["--size", "1e9"], "at most"),
        (vec!["--size", "nan"], "height"),
    ] {
        let mut args = vec!["flatten", mesh.to_str().unwrap(), "-o", "unused", "-q"];
        args.extend_from_slice(&extra);
        let o = sheetform(&args);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{extra:?}: {stderr}");
        assert!(
            stderr.contains("--size") && stderr.contains(says),
            "{extra:?}: {stderr}"
        );
    }
}

/// Every system's pattern goes through the same tabs and IDs: a bent tube with
/// `--tabs one` (its seam's tab once stood refused: its corner met the short edges of the
/// outline running on beside it), and the wing nut's smooth charts with alternating tabs
/// packed on 600 × 400 mm sheets (the guide's example, docs/guide/flatten.md), read back from the files.
#[test]
fn a_bent_tube_and_packed_charts_carry_one_tab_per_glued_pair() {
    let dir = tempfile::tempdir().unwrap();
    let tube = dir.path().join("tube");
    let scene = crate::common::repo().join("examples/tube.json");
    let o = sheetform(&[
        "bend",
        scene.to_str().unwrap(),
        "-o",
        tube.to_str().unwrap(),
        "-q",
        "--tabs",
        "one",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (_, a) = assert_gluable("tube", &tube);
    assert_eq!((count(&a, "pairs_tab_one"), count(&a, "pairs_tab_none")), (2, 0), "{a}");
    assert_eq!(count(&a, "seams_id_both"), 1, "{a}");

    let wingnut = dir.path().join("wingnut");
    flatten(
        &example_mesh("wingnut.obj"),
        &wingnut,
        &[
            "--scale",
            "40",
            "--tabs",
            "alternate",
            "--sheet",
            "600x400",
            "--min-fold-angle",
            "10",
        ],
    );
    let (r, a) = assert_gluable("wing nut", &wingnut);
    assert_eq!(r["layout"], "charts");
    assert!(count(&r["pattern"], "sheet_count") >= 2);
    // Nearly every pair tabbed, every seam's ID but a tight corner's on both copies.
    assert!(count(&a, "pairs_tab_none") * 20 <= count(&a, "glued_edge_pairs"), "{a}");
    assert!(count(&r["pattern"], "seam_id_missing_count") <= 2, "{r}");
}

/// `develop`'s pieces are glued along their seams: with `--tabs auto` they get a tab on
/// one side of every glued edge pair, as a net does, and pass every check of a gluable
/// pattern (the box's slit at a corner too).
#[test]
fn develop_pieces_get_glue_tabs_on_every_seam() {
    let dir = tempfile::tempdir().unwrap();
    for (name, units) in [("gift-box.obj", "mm"), ("bunny-99.stl", "m")] {
        let out = dir.path().join(name);
        let o = sheetform(&[
            "develop",
            example_mesh(name).to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "-q",
            "--units",
            units,
        ]);
        assert!(o.status.success(), "{name}: {}", String::from_utf8_lossy(&o.stderr));
        let (_, a) = assert_gluable(name, &out);
        assert!(count(&a, "glued_edge_pairs") > 0, "{name}: {a}");
        assert_eq!(count(&a, "pairs_tab_one"), count(&a, "glued_edge_pairs"), "{name}: {a}");
    }
}
