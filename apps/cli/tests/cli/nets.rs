//! `sheetform flatten` on the shapes a maker tries first, meshes written by a generator
//! (as trimesh makes them): nets of faceted models, one-piece patterns of tubes and cones,
//! honest exit codes.

use crate::common::{
    cut_intersections, ezdxf_cut, obj_isometry_error, read_obj, report, sheetform, svg_cut_loops,
    svg_labels_over_lines, validate_glb, write_obj,
};
use sheetform::mesh::primitives;
use std::path::Path;

fn flatten(mesh: &Path, out: &Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec!["flatten", mesh.to_str().unwrap(), "-o", out.to_str().unwrap(), "-q"];
    args.extend_from_slice(extra);
    sheetform(&args)
}

/// Faceted models become nets: exact (every OBJ `vt` edge equal to its 3D edge), in the
/// piece counts of the papercraft tools for a box (one cross), a cylinder and a cone with
/// their caps; on finely faceted curved shapes (icosphere, hemisphere, torus) pieces that
/// each fit an A4 page and leave room for a glue tab on one copy of every glued pair
/// (issue 34: a one-piece star's narrow slits had none), so more of them, and no more
/// than a tenth of the pairs without a tab (edges too short near a pole, corners too
/// tight); cut outlines (glue tabs included) that touch nowhere; DXF read by ezdxf
/// without repairs; a valid GLB.
#[test]
fn faceted_models_unfold_into_exact_nets_in_few_pieces() {
    let tmp = tempfile::tempdir().unwrap();
    let cases = [
        ("box", primitives::cuboid([40.0, 60.0, 80.0]), 1),
        ("icosphere", primitives::icosphere(50.0, 2), 24),
        ("cylinder", primitives::cylinder(30.0, 80.0, 32, true), 1),
        ("cone", primitives::cone(30.0, 80.0, 32, true), 1),
        ("hemisphere", primitives::hemisphere(50.0, 8, 32), 22),
        ("torus", primitives::torus(60.0, 20.0, 32, 16), 50),
    ];
    for (name, mesh, most) in cases {
        let path = write_obj(tmp.path(), name, &mesh);
        let out = tmp.path().join(name);
        let o = flatten(&path, &out, &[]);
        assert!(o.status.success(), "{name}: {}", String::from_utf8_lossy(&o.stderr));
        let r = report(&out);
        assert_eq!(r["layout"], "net", "{name}: {}", r["layout_reason"]);
        assert_eq!(r["status"], "ok", "{name}");
        let pieces = r["net"]["piece_count"].as_u64().unwrap() as usize;
        assert!(pieces >= 1 && pieces <= most, "{name}: {pieces} pieces");
        assert_eq!(r["pattern"]["piece_count"].as_u64().unwrap() as usize, pieces, "{name}");
        assert!(r["isometry_error_max_relative"].as_f64().unwrap() <= 1e-10, "{name}");
        assert!(obj_isometry_error(&read_obj(&out.join("model.obj"))) <= 1e-10, "{name}");
        // Glue tabs by default on a net, and outlines that cross nowhere.
        let tabs = &r["pattern"]["tabs"];
        assert!(tabs["placed"].as_u64().unwrap() > 0, "{name}");
        let (pairs, untabbed) = (
            tabs["glued_edge_pair_count"].as_u64().unwrap(),
            tabs["glued_edge_pairs_without_tab"].as_u64().unwrap(),
        );
        if matches!(name, "box" | "icosphere" | "cylinder" | "cone") {
            assert_eq!(untabbed, 0, "{name}: {tabs}");
        } else {
            assert!(untabbed * 10 <= pairs, "{name}: {tabs}");
        }
        let svg = std::fs::read_to_string(out.join("pattern.svg")).unwrap();
        let loops = svg_cut_loops(&svg);
        assert_eq!(loops.len(), pieces, "{name}");
        assert_eq!(cut_intersections(&loops), 0, "{name}");
        // Labels upright inside their pieces, over no line and no other label.
        assert_eq!(svg_labels_over_lines(&svg), 0, "{name}");
        assert!(r["pattern"]["label_count"].as_u64().unwrap() > 0, "{name}");
        let dxf = ezdxf_cut(&out.join("pattern.dxf"));
        assert_eq!(
            (dxf["errors"].as_u64(), dxf["fixes"].as_u64()),
            (Some(0), Some(0)),
            "{name}"
        );
        assert!(dxf["mountain"].as_u64().unwrap() > 0, "{name}");
        validate_glb(&[out.join("model.glb")]);
    }
    // A box: one cross of six rectangles, five folds, all mountains seen from outside,
    // turned to print on one A4 page (the layout as it lies needs two).
    let r = report(&tmp.path().join("box"));
    assert_eq!(r["pattern"]["page_count"], 1);
    assert_eq!(r["pattern"]["pieces_packed_on_pages"], true);
    let render = std::process::Command::new("pdftoppm")
        .args(["-r", "20", "-png"])
        .arg(tmp.path().join("box/pattern.pdf"))
        .arg(tmp.path().join("box/page"))
        .output()
        .expect("pdftoppm runs");
    assert!(render.status.success(), "{}", String::from_utf8_lossy(&render.stderr));
    assert!(tmp.path().join("box/page-1.png").exists());
    assert!(!tmp.path().join("box/page-2.png").exists());
    assert_eq!(r["net"]["fold_edge_count"], 5);
    assert_eq!(r["pattern"]["mountain_fold_count"], 5);
    assert_eq!(r["pattern"]["valley_fold_count"], 0);
    let area = 2.0 * (40.0 * 60.0 + 40.0 * 80.0 + 60.0 * 80.0);
    assert!((r["flat_area_mm2"].as_f64().unwrap() - area).abs() < 1e-9 * area);
}

/// The classic developables with a boundary come out in one exact piece, cut along one
/// straight seam; a user's seam is honoured even without charts.
#[test]
fn an_open_tube_and_an_open_cone_come_out_in_one_exact_piece() {
    let tmp = tempfile::tempdir().unwrap();
    for (name, mesh) in [
        ("tube", primitives::cylinder(30.0, 80.0, 48, false)),
        ("cone", primitives::cone(30.0, 80.0, 48, false)),
    ] {
        let path = write_obj(tmp.path(), name, &mesh);
        let out = tmp.path().join(name);
        let o = flatten(&path, &out, &[]);
        assert!(o.status.success(), "{name}: {}", String::from_utf8_lossy(&o.stderr));
        let r = report(&out);
        assert_eq!(r["layout"], "charts", "{name}");
        assert_eq!(r["segmentation"]["chart_count"], 1, "{name}");
        assert_eq!(r["segmentation"]["opened_chart_count"], 1, "{name}");
        assert_eq!(r["pattern"]["piece_count"], 1, "{name}");
        assert!(r["isometry_error_max_relative"].as_f64().unwrap() <= 1e-10, "{name}");
    }
    // The tube with a user seam along one ruling (vertex 0 at the bottom, 48 above it),
    // flattened whole: the seam opens it into the rectangle.
    let mut tube = primitives::cylinder(30.0, 80.0, 48, false);
    tube.seam_edges = vec![[0, 48]];
    let path = write_obj(tmp.path(), "seamed", &tube);
    let out = tmp.path().join("seamed");
    let o = flatten(&path, &out, &["--charts", "never"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r = report(&out);
    assert_eq!(r["layout"], "whole");
    assert_eq!(r["pattern"]["piece_count"], 1);
    assert!(r["isometry_error_max_relative"].as_f64().unwrap() <= 1e-10);
}

/// What cannot be flattened within the bound is never called ok: a finely meshed dome
/// flattened whole overlaps itself (exact unfolding, exit 4) or stretches (LSCM, exit 5);
/// by default it is cut into charts that meet the bound.
#[test]
fn a_dome_flattened_whole_is_out_of_tolerance_and_in_charts_within_it() {
    let tmp = tempfile::tempdir().unwrap();
    let dome = primitives::hemisphere(50.0, 24, 96);
    let path = write_obj(tmp.path(), "dome", &dome);
    let out = tmp.path().join("whole");
    let o = flatten(&path, &out, &["--charts", "never"]);
    assert_eq!(o.status.code(), Some(4), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(report(&out)["status"], "overlapping");
    let o = flatten(&path, &out, &["--charts", "never", "--method", "lscm"]);
    assert_eq!(o.status.code(), Some(5), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(report(&out)["status"], "out of tolerance");
    let out = tmp.path().join("auto");
    let o = flatten(&path, &out, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r = report(&out);
    assert_eq!(r["layout"], "charts", "{}", r["layout_reason"]);
    assert!(r["isometry_error_max_relative"].as_f64().unwrap() <= 0.01);
    // As a net it is exact.
    let out = tmp.path().join("net");
    let o = flatten(&path, &out, &["--charts", "net"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(report(&out)["isometry_error_max_relative"].as_f64().unwrap() <= 1e-10);
}

/// The label check reads what a viewer draws and can fail: a label across a fold, one
/// outside the piece, and one on another are found; a free one is not.
#[test]
fn the_label_check_finds_labels_over_lines_outside_or_on_each_other() {
    let svg = |texts: &str| {
        format!(
            r#"<svg><g id="cut"><path d="M0,0 L40,0 L40,40 L0,40 Z"/></g><g id="fold"><line x1="20" y1="0" x2="20" y2="40"/></g><g id="labels">{texts}</g></svg>"#
        )
    };
    let text = |x: f64, y: f64, angle: f64, t: &str| {
        format!(r#"<text class="seam" x="{x}" y="{y}" font-size="3" transform="rotate({angle} {x} {y})">{t}</text>"#)
    };
    assert_eq!(svg_labels_over_lines(&svg(&text(10.0, 10.0, 0.0, "12"))), 0);
    assert_eq!(svg_labels_over_lines(&svg(&text(20.0, 10.0, 0.0, "12"))), 1);
    assert_eq!(svg_labels_over_lines(&svg(&text(16.0, 10.0, 90.0, "123456"))), 0);
    assert_eq!(svg_labels_over_lines(&svg(&text(16.0, 10.0, 0.0, "123456"))), 1);
    assert_eq!(svg_labels_over_lines(&svg(&text(50.0, 10.0, 0.0, "1"))), 1);
    let two = text(10.0, 10.0, 0.0, "12") + &text(10.5, 10.5, 0.0, "34");
    assert_eq!(svg_labels_over_lines(&svg(&two)), 1);
}

/// A pattern that needs more pages than the cap is refused before anything is written,
/// the message saying how to go on.
#[test]
fn a_pdf_over_the_page_cap_is_refused_with_the_way_out() {
    let tmp = tempfile::tempdir().unwrap();
    let path = write_obj(tmp.path(), "box", &primitives::cuboid([400.0, 600.0, 800.0]));
    let out = tmp.path().join("out");
    let o = flatten(&path, &out, &["--max-pages", "3"]);
    assert_eq!(o.status.code(), Some(1));
    let message = String::from_utf8_lossy(&o.stderr);
    assert!(
        message.contains("max_pages") && message.contains("--max-pages"),
        "{message}"
    );
    assert!(!out.exists());
    let o = flatten(&path, &out, &["--max-pages", "500"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(report(&out)["pattern"]["page_count"].as_u64().unwrap() > 3);
}

/// A finely faceted model whose net would come in a hundred scraps is cut into a handful
/// of smooth charts instead, and the report says why.
#[test]
fn the_wingnut_is_cut_into_charts_rather_than_a_net_of_scraps() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let o = flatten(&crate::common::example_mesh("wingnut.obj"), &out, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r = report(&out);
    assert_eq!(r["layout"], "charts");
    let reason = r["layout_reason"].as_str().unwrap();
    assert!(reason.contains("the net needs"), "{reason}");
    let charts = r["segmentation"]["chart_count"].as_u64().unwrap();
    assert!(charts <= 25, "{charts}");
    assert_eq!(r["status"], "ok");
}

/// A box of 1 mm sheet metal (`--thickness`): each of the net's five 90° folds becomes a
/// bend zone of `π/2·(R + K·T)` with the flanges set back `(R + T)·tan 45°` from the
/// outer mold line (FreeCAD SheetMetal's rule), so the cross shrinks by the bend
/// deduction once per fold across it; one outline, crossing nowhere; the bend line of
/// each zone a mountain fold, its two tangent lines guides; ezdxf reads it cleanly. Glue
/// tabs are refused with a thickness, as are K-factors outside [0, 1].
#[test]
fn a_sheet_metal_box_unfolds_with_its_bend_deductions() {
    let tmp = tempfile::tempdir().unwrap();
    let path = write_obj(tmp.path(), "box", &primitives::cuboid([40.0, 60.0, 80.0]));
    let bounds = |out: &Path| {
        let loops = svg_cut_loops(&std::fs::read_to_string(out.join("pattern.svg")).unwrap());
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in loops.iter().flatten() {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        (loops, [hi[0] - lo[0], hi[1] - lo[1]])
    };
    let paper = tmp.path().join("paper");
    let o = flatten(&path, &paper, &["--tabs", "none"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let metal = tmp.path().join("metal");
    let args = ["--thickness", "1", "--bend-radius", "1.5", "--k-factor", "0.4"];
    let o = flatten(&path, &metal, &args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r = report(&metal);
    let bend = &r["pattern"]["bend_allowance"];
    let allowance = std::f64::consts::FRAC_PI_2 * (1.5 + 0.4 * 1.0);
    let deduction = 2.0 * (1.5 + 1.0) - allowance;
    assert_eq!(bend["bend_count"], 5);
    for key in ["flat_change_min_mm", "flat_change_max_mm"] {
        assert!((bend[key].as_f64().unwrap() + deduction).abs() < 1e-9, "{key}: {bend}");
    }
    // No glue tabs on metal by default, five mountain bend lines at 90°.
    assert!(r["pattern"].get("tabs").is_none());
    assert_eq!(r["pattern"]["mountain_fold_count"], 5);
    let (paper_loops, paper_size) = bounds(&paper);
    let (loops, size) = bounds(&metal);
    assert_eq!((paper_loops.len(), loops.len()), (1, 1));
    assert_eq!(cut_intersections(&loops), 0);
    // Across the cross: two folds one way and three the other (the SVG holds 0.1 µm).
    let mut folds_across: Vec<f64> = (0..2).map(|k| (paper_size[k] - size[k]) / deduction).collect();
    folds_across.sort_by(f64::total_cmp);
    assert!(
        (folds_across[0] - 2.0).abs() < 1e-4 && (folds_across[1] - 3.0).abs() < 1e-4,
        "{folds_across:?}"
    );
    let svg = std::fs::read_to_string(metal.join("pattern.svg")).unwrap();
    assert_eq!(svg.matches(r#"data-fold-angle-degrees="90.0""#).count(), 5);
    let guides = &svg[svg.find(r#"id="fold-guide""#).unwrap()..];
    let guides = &guides[..guides.find("</g>").unwrap()];
    assert_eq!(guides.matches("<line").count(), 10);
    let dxf = ezdxf_cut(&metal.join("pattern.dxf"));
    assert_eq!((dxf["errors"].as_u64(), dxf["fixes"].as_u64()), (Some(0), Some(0)));
    assert_eq!(dxf["mountain"], 5);
    // Corner reliefs (issue 34): where two bend lines meet at the base's four corners, the
    // square where both zones would bend is cut out: the bend lines' crossing lies off
    // the outline's material, every bend line's middle on it.
    assert_eq!(bend["corner_relief_count"], 4, "{bend}");
    let mountains: Vec<([f64; 2], [f64; 2])> = {
        let group = &svg[svg.find(r#"id="fold-mountain""#).unwrap()..];
        let group = &group[..group.find("</g>").unwrap()];
        let attr = |tag: &str, name: &str| -> f64 {
            let key = format!(r#" {name}=""#);
            let start = tag.find(&key).unwrap() + key.len();
            tag[start..start + tag[start..].find('"').unwrap()].parse().unwrap()
        };
        group
            .split("<line")
            .skip(1)
            .map(|tag| ([attr(tag, "x1"), attr(tag, "y1")], [attr(tag, "x2"), attr(tag, "y2")]))
            .collect()
    };
    let inside = |p: [f64; 2]| {
        let l = &loops[0];
        let mut crossings = 0;
        for i in 0..l.len() {
            let (a, b) = (l[i], l[(i + 1) % l.len()]);
            if (a[1] > p[1]) != (b[1] > p[1]) && p[0] < a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]) {
                crossings += 1;
            }
        }
        crossings % 2 == 1
    };
    let mut corners = 0;
    for (i, &(a, b)) in mountains.iter().enumerate() {
        assert!(
            inside([(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0]),
            "bend line {i} on the material"
        );
        for &(c, d) in &mountains[i + 1..] {
            // Perpendicular bend lines of the base (axis-aligned here) that end near one
            // another: their crossing is cut out.
            let (u, v) = ([b[0] - a[0], b[1] - a[1]], [d[0] - c[0], d[1] - c[1]]);
            if (u[0] * v[0] + u[1] * v[1]).abs() > 1e-9 {
                continue;
            }
            let crossing = if u[0].abs() < 1e-9 { [a[0], c[1]] } else { [c[0], a[1]] };
            let near_end = |p: [f64; 2], q: [f64; 2]| (p[0] - q[0]).hypot(p[1] - q[1]) < 6.0;
            if (near_end(crossing, a) || near_end(crossing, b)) && (near_end(crossing, c) || near_end(crossing, d)) {
                corners += 1;
                assert!(!inside(crossing), "a corner relief at {crossing:?}");
            }
        }
    }
    assert_eq!(corners, 4);

    // Nets whose folds meet at every vertex in every direction still come out as one
    // outline each, the flanges trimmed and joined by their zones without hairline gaps.
    for (name, mesh) in [
        ("icosphere", primitives::icosphere(50.0, 2)),
        ("hemisphere", primitives::hemisphere(50.0, 8, 32)),
    ] {
        let path = write_obj(tmp.path(), name, &mesh);
        let out = tmp.path().join(format!("{name}-metal"));
        let o = flatten(&path, &out, &["--thickness", "0.5"]);
        assert!(o.status.success(), "{name}: {}", String::from_utf8_lossy(&o.stderr));
        let r = report(&out);
        let (loops, _) = bounds(&out);
        // Zero-width slits of the net (cut edges whose two sides lie on each other) stay
        // cut lines of their own; every other loop outlines a piece or a hole in one (a
        // strip of faces closing around a pole): one outer outline per piece.
        let area = |l: &Vec<[f64; 2]>| {
            (0..l.len())
                .map(|i| {
                    let (p, q) = (l[i], l[(i + 1) % l.len()]);
                    p[0] * q[1] - q[0] * p[1]
                })
                .sum::<f64>()
                / 2.0
        };
        let outlines: Vec<Vec<[f64; 2]>> = loops.into_iter().filter(|l| area(l).abs() > 1e-6).collect();
        let inside = |p: [f64; 2], l: &Vec<[f64; 2]>| {
            let mut crossings = 0;
            for i in 0..l.len() {
                let (a, b) = (l[i], l[(i + 1) % l.len()]);
                if (a[1] > p[1]) != (b[1] > p[1]) && p[0] < a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]) {
                    crossings += 1;
                }
            }
            crossings % 2 == 1
        };
        let outer = outlines
            .iter()
            .enumerate()
            .filter(|(i, l)| !outlines.iter().enumerate().any(|(j, m)| j != *i && inside(l[0], m)))
            .count();
        assert_eq!(outer, r["net"]["piece_count"].as_u64().unwrap() as usize, "{name}");
        assert_eq!(cut_intersections(&outlines), 0, "{name}");
        assert_eq!(
            r["pattern"]["bend_allowance"]["bend_count"], r["net"]["fold_edge_count"],
            "{name}"
        );
    }

    let refused = flatten(&path, &tmp.path().join("tabs"), &["--thickness", "1", "--tabs", "one"]);
    assert_eq!(
        refused.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&refused.stderr)
    );
    assert!(String::from_utf8_lossy(&refused.stderr).contains("tabs"));
    let refused = flatten(&path, &tmp.path().join("k"), &["--thickness", "1", "--k-factor", "1.5"]);
    assert_eq!(refused.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&refused.stderr).contains("k_factor"));
}
