//! Annotations drawn in Inkscape (`examples/photo/coffee-cup.svg`, written from the JSON
//! annotation by `tools/annotation_to_svg.py`) read back to the same annotation, under
//! any placement of the drawing, and bad drawings named.

use sheetform_photo::{annotation_from_svg, reconstruct, svg_image_reference, PhotoAnnotation};

fn read(name: &str) -> String {
    std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/photo/").to_string() + name).unwrap()
}

fn assert_same(a: &PhotoAnnotation, b: &PhotoAnnotation, tolerance: f64) {
    assert_eq!(a.curves.len(), b.curves.len());
    for c in &a.curves {
        let d = b
            .curves
            .iter()
            .find(|d| d.name == c.name)
            .unwrap_or_else(|| panic!("curve {}", c.name));
        assert_eq!(c.kind, d.kind, "{}", c.name);
        assert_eq!(c.closed, d.closed, "{}", c.name);
        assert_eq!(c.control_points.len(), d.control_points.len(), "{}", c.name);
        for (p, q) in c.control_points.iter().zip(&d.control_points) {
            assert!(
                (p[0] - q[0]).abs() < tolerance && (p[1] - q[1]).abs() < tolerance,
                "{}: {p:?} {q:?}",
                c.name
            );
        }
    }
    let close = |p: [f64; 2], q: [f64; 2]| (p[0] - q[0]).abs() < tolerance && (p[1] - q[1]).abs() < tolerance;
    for k in 0..2 {
        assert!(close(a.symmetry.points[k], b.symmetry.points[k]));
        for e in 0..2 {
            assert!(close(a.symmetry.frame[k][e], b.symmetry.frame[k][e]));
        }
    }
    assert_eq!(a.symmetry.flip_depth, b.symmetry.flip_depth);
    assert_eq!(a.self_symmetric_curves, b.self_symmetric_curves);
    assert_eq!(a.symmetric_curves, b.symmetric_curves);
    assert_eq!(a.openings.len(), b.openings.len());
    for (p, q) in a.openings.iter().zip(&b.openings) {
        assert!(close(*p, *q));
    }
    assert!(close(a.true_size.from, b.true_size.from) && close(a.true_size.to, b.true_size.to));
    assert_eq!(a.true_size.length, b.true_size.length);
    assert_eq!(a.units, b.units);
    assert_eq!(a.image, b.image);
}

#[test]
fn the_traced_cup_reads_back_to_its_annotation() {
    let json = PhotoAnnotation::from_json(&read("coffee-cup.json")).unwrap();
    let svg = read("coffee-cup.svg");
    assert_eq!(svg_image_reference(&svg).unwrap(), "coffee.png");
    let from_svg = annotation_from_svg(&svg, (600, 400)).unwrap();
    // The SVG carries six decimals.
    assert_same(&json, &from_svg, 1e-6);
    let (a, b) = (reconstruct(&json).unwrap(), reconstruct(&from_svg).unwrap());
    assert_eq!(a.ruling_count(), b.ruling_count());
    assert_eq!(a.patches.len(), b.patches.len());
}

#[test]
fn the_drawing_may_be_placed_and_scaled_anywhere() {
    let svg = read("coffee-cup.svg");
    let reference = annotation_from_svg(&svg, (600, 400)).unwrap();
    // Everything moved and scaled by a group transform, the image drawn at half size in
    // its own coordinates and scaled back up by its own transform.
    let moved = svg
        .replace("<title>", "<g transform=\"translate(35,-12) scale(1.7)\"><title>")
        .replace("</svg>", "</g></svg>")
        .replace(
            "<image x=\"0\" y=\"0\" width=\"600\" height=\"400\"",
            "<image transform=\"scale(2)\" x=\"0\" y=\"0\" width=\"300\" height=\"200\"",
        );
    let read_back = annotation_from_svg(&moved, (600, 400)).unwrap();
    assert_same(&reference, &read_back, 1e-9);
}

#[test]
fn bad_drawings_are_named() {
    let svg = read("coffee-cup.svg");
    let error = |text: &str| annotation_from_svg(text, (600, 400)).unwrap_err().to_string();
    let no_frame = svg.replace("inkscape:label=\"frame\"", "inkscape:label=\"note\"");
    assert!(error(&no_frame).contains("frame"), "{}", error(&no_frame));
    let no_size = svg.replace("inkscape:label=\"true-size", "inkscape:label=\"size");
    assert!(error(&no_size).contains("true-size"));
    let embedded = svg.replace("xlink:href=\"coffee.png\"", "xlink:href=\"data:image/png;base64,AAAA\"");
    assert!(error(&embedded).contains("embedded"));
    let note = svg.replace("rim | self-symmetric", "rim | symmetric-ish");
    let e = error(&note);
    assert!(e.contains("symmetric-ish") && e.contains("rim"), "{e}");
    assert!(error("<svg xmlns=\"http://www.w3.org/2000/svg\"></svg>").contains("no <image>"));
    assert!(error("not xml").contains("svg"));
    let broken = svg.replace("M 172.630000,111.220000 C", "M 172.630000,111.220000 Q Q");
    assert!(error(&broken).contains("left-silhouette"));
}

/// Issue 37: the photo's label names its camera; unlabelled, the view is orthographic.
#[test]
fn the_photos_label_names_a_perspective_camera() {
    use sheetform_photo::Projection;
    let svg = read("coffee-cup.svg");
    let plain = annotation_from_svg(&svg, (600, 400)).unwrap();
    assert_eq!(plain.camera.projection, Projection::Orthographic);
    for (label, focal) in [("perspective 30mm", Some(30.0)), ("Perspective", None)] {
        let labelled = svg.replace("<image ", &format!("<image inkscape:label=\"{label}\" "));
        let a = annotation_from_svg(&labelled, (600, 400)).unwrap();
        assert_eq!(a.camera.projection, Projection::Perspective, "{label}");
        assert_eq!(a.camera.focal_length_35mm, focal, "{label}");
    }
    let bad = svg.replace("<image ", "<image inkscape:label=\"perspective wide\" ");
    let e = annotation_from_svg(&bad, (600, 400)).unwrap_err().to_string();
    assert!(e.contains("perspective 26mm"), "{e}");
}
