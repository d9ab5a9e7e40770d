use crate::{FoldStyle, LabelKind, Pattern, PatternTexture, Vec2};
use base64::Engine as _;
use std::fmt::Write;

use sheetform_geometry::xml_escaped as escape;

/// The pattern as SVG at true size: the document is `W mm × H mm` and one user unit is
/// one millimetre, so it prints and laser-cuts at 1:1. Layers (Inkscape layer groups,
/// plain `<g id>` for other tools), side by side and each of one kind of line in a colour
/// of its own (cutter software that sorts by colour, such as LightBurn or Silhouette
/// Studio, gets the same layers): `cut` (the loops, glue tabs included, red hairline),
/// `fold-mountain` (red dash-dot) and `fold-valley` (blue dashed), both with their fold
/// angle as `data-fold-angle-degrees`, `fold-tab` (the bases of the glue tabs, to score:
/// teal dotted), `fold-guide` (bending guides, never to score: rulings, grey dotted),
/// `stitch` (the design outline inside a seam allowance, green dashed), `notch` (cuts
/// into the allowance, red), `grain` (grain lines, dark grey), `labels` (piece names and
/// seam IDs), and `sheets` (sheet outlines, when packed). The y axis is flipped so the
/// pattern reads as seen from the sheet's printed side; `margin_mm` surrounds it.
pub fn svg_bytes(pattern: &Pattern, title: &str, margin_mm: f64) -> Vec<u8> {
    let (lo, hi) = pattern.bounds();
    let (lo, hi) = if lo.x.is_finite() {
        (lo, hi)
    } else {
        (crate::Vec2::zeros(), crate::Vec2::zeros())
    };
    let (w, h) = (hi.x - lo.x + 2.0 * margin_mm, hi.y - lo.y + 2.0 * margin_mm);
    let px = |x: f64| x - lo.x + margin_mm;
    let py = |y: f64| hi.y - y + margin_mm;
    let mut s = String::new();
    let _ = writeln!(s, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape" width="{w:.4}mm" height="{h:.4}mm" viewBox="0 0 {w:.4} {h:.4}">"#
    );
    let _ = writeln!(s, "<title>{}</title>", escape(title));
    let _ = writeln!(
        s,
        "<desc>1 user unit = 1 mm. Layers: cut, fold-mountain, fold-valley (score), fold-tab (score), fold-guide (draw only), stitch, notch, grain, labels, sheets.</desc>"
    );
    if let Some(texture) = &pattern.texture {
        write_texture(&mut s, pattern, texture, &px, &py);
    }
    let _ = writeln!(
        s,
        r##"<g id="cut" inkscape:groupmode="layer" inkscape:label="cut" fill="none" stroke="#e00000" stroke-width="0.1">"##
    );
    // Each cut loop names its piece (`data-piece`, the piece's number) and the mesh
    // pieces it holds (`data-mesh-pieces`): the editor lights them up in 3D. Its
    // `data-flat-transform` is the SVG matrix from the pattern's first layout (the mesh's
    // flat coordinates in mm) to this drawing: where an editor draws its handles.
    for (k, piece) in pattern.pieces.iter().enumerate() {
        let held: Vec<String> = piece.mesh_pieces.iter().map(u32::to_string).collect();
        let [a, b, c, d, e, f] = first_layout_to_drawing(piece, &px, &py);
        let transform = format!("matrix({a:.6} {b:.6} {c:.6} {d:.6} {e:.4} {f:.4})");
        for cycle in &piece.cut {
            let _ = writeln!(
                s,
                r#"<path data-piece="{k}" data-mesh-pieces="{}" data-flat-transform="{transform}" d="{}"/>"#,
                held.join(" "),
                path_data([cycle], &px, &py)
            );
        }
    }
    let _ = writeln!(s, "</g>");
    for (style, id, colour, dash) in [
        (FoldStyle::Mountain, "fold-mountain", "#c03030", "3,1,0.6,1"),
        (FoldStyle::Valley, "fold-valley", "#3050c0", "2,1.2"),
        (FoldStyle::TabBase, "fold-tab", "#108080", "0.6,0.6"),
        (FoldStyle::Guide, "fold-guide", "#9a9a9a", "1,1"),
        (FoldStyle::Stitch, "stitch", "#20a040", "2,1.5"),
        (FoldStyle::Notch, "notch", "#e00000", "none"),
        (FoldStyle::Grain, "grain", "#505050", "none"),
    ] {
        let _ = writeln!(
            s,
            r#"<g id="{id}" inkscape:groupmode="layer" inkscape:label="{id}" fill="none" stroke-width="0.1" stroke="{colour}" stroke-dasharray="{dash}">"#
        );
        for f in pattern.folds().filter(|f| f.style == style) {
            // Folds carry their dihedral angle (how far to fold), for cutters and readers.
            let angle = if matches!(style, FoldStyle::Mountain | FoldStyle::Valley) {
                format!(r#" data-fold-angle-degrees="{:.1}""#, f.angle_degrees)
            } else {
                String::new()
            };
            let _ = writeln!(
                s,
                r#"<line x1="{:.4}" y1="{:.4}" x2="{:.4}" y2="{:.4}"{angle}/>"#,
                px(f.a.x),
                py(f.a.y),
                px(f.b.x),
                py(f.b.y)
            );
        }
        let _ = writeln!(s, "</g>");
    }
    let _ = writeln!(
        s,
        r##"<g id="labels" inkscape:groupmode="layer" inkscape:label="labels" font-family="Helvetica, Arial, sans-serif" fill="#3050a0" text-anchor="middle" dominant-baseline="middle">"##
    );
    for (k, label) in pattern
        .pieces
        .iter()
        .enumerate()
        .flat_map(|(k, p)| p.labels.iter().map(move |l| (k, l)))
    {
        let (x, y) = (px(label.position.x), py(label.position.y));
        // A seam ID says which seam (`data-seam`): the editor lights up both its copies.
        let (class, seam) = match label.kind {
            LabelKind::Piece => ("piece", String::new()),
            LabelKind::Seam => ("seam", format!(r#" data-seam="{}""#, escape(&label.text))),
        };
        // SVG's y axis points down, so the angle changes sign.
        let _ = writeln!(
            s,
            r#"<text class="{class}" data-piece="{k}"{seam} x="{x:.4}" y="{y:.4}" font-size="{:.3}" transform="rotate({:.3} {x:.4} {y:.4})">{}</text>"#,
            label.height_mm,
            -label.angle_radians.to_degrees(),
            escape(&label.text)
        );
    }
    let _ = writeln!(s, "</g>");
    let _ = writeln!(
        s,
        r##"<g id="sheets" inkscape:groupmode="layer" inkscape:label="sheets" fill="none" stroke="#000000" stroke-width="0.2">"##
    );
    for (corner, size) in &pattern.sheets {
        let _ = writeln!(
            s,
            r#"<rect x="{:.4}" y="{:.4}" width="{:.4}" height="{:.4}"/>"#,
            px(corner.x),
            py(corner.y + size.y),
            size.x,
            size.y
        );
    }
    let _ = writeln!(s, "</g>\n</svg>");
    s.into_bytes()
}

/// The `texture` layer: the image once in `<defs>`, and per piece a `<use>` of it moved
/// with the piece (its [`crate::Placement`]) and clipped to the piece's cut loops.
fn write_texture(
    s: &mut String,
    pattern: &Pattern,
    texture: &PatternTexture,
    px: &impl Fn(f64) -> f64,
    py: &impl Fn(f64) -> f64,
) {
    let data = base64::engine::general_purpose::STANDARD.encode(&texture.bytes);
    let _ = writeln!(s, "<defs>");
    // The image in its own frame: 1 unit = 1 mm, y down from its top-left corner.
    let _ = writeln!(
        s,
        r#"<image id="texture-image" width="{:.4}" height="{:.4}" preserveAspectRatio="none" href="data:{};base64,{data}"/>"#,
        texture.size.x,
        texture.size.y,
        escape(&texture.mime_type)
    );
    for (k, piece) in pattern.pieces.iter().enumerate() {
        let _ = writeln!(
            s,
            r#"<clipPath id="piece-{k}"><path d="{}" clip-rule="evenodd"/></clipPath>"#,
            path_data(&piece.cut, px, py)
        );
    }
    let _ = writeln!(s, "</defs>");
    let _ = writeln!(
        s,
        r#"<g id="texture" inkscape:groupmode="layer" inkscape:label="texture">"#
    );
    for (k, piece) in pattern.pieces.iter().enumerate() {
        // Image frame (u right, v down) → first layout (mm, y up) → the piece's place →
        // the SVG's user space.
        let [a, b, c, d, e, f] = first_layout_to_drawing(piece, px, py);
        let to_svg = |u: f64, v: f64| {
            let (x, y) = (texture.origin.x + u, texture.origin.y + texture.size.y - v);
            Vec2::new(a * x + c * y + e, b * x + d * y + f)
        };
        let (o, x, y) = (to_svg(0.0, 0.0), to_svg(1.0, 0.0), to_svg(0.0, 1.0));
        let (x, y) = (x - o, y - o);
        let _ = writeln!(
            s,
            r##"<g clip-path="url(#piece-{k})"><use href="#texture-image" transform="matrix({:.6} {:.6} {:.6} {:.6} {:.4} {:.4})"/></g>"##,
            x.x, x.y, y.x, y.y, o.x, o.y
        );
    }
    let _ = writeln!(s, "</g>");
}

/// The SVG matrix `[a, b, c, d, e, f]` (`x' = a x + c y + e`, `y' = b x + d y + f`) from
/// `piece`'s first layout (mm, y up) to the drawing's user space: its placement, then
/// `px`/`py`.
fn first_layout_to_drawing(
    piece: &crate::PatternPiece,
    px: &impl Fn(f64) -> f64,
    py: &impl Fn(f64) -> f64,
) -> [f64; 6] {
    let to_svg = |p: Vec2| {
        let q = piece.placement.apply(p);
        Vec2::new(px(q.x), py(q.y))
    };
    let (o, x, y) = (
        to_svg(Vec2::zeros()),
        to_svg(Vec2::new(1.0, 0.0)),
        to_svg(Vec2::new(0.0, 1.0)),
    );
    [x.x - o.x, x.y - o.y, y.x - o.x, y.y - o.y, o.x, o.y]
}

/// SVG path data of closed rings (`M … L … Z` each), in the SVG's user space.
fn path_data<'a>(
    rings: impl IntoIterator<Item = &'a Vec<Vec2>>,
    px: &impl Fn(f64) -> f64,
    py: &impl Fn(f64) -> f64,
) -> String {
    let mut d = String::new();
    for ring in rings {
        for (i, p) in ring.iter().enumerate() {
            let _ = write!(d, "{}{:.4},{:.4} ", if i == 0 { "M" } else { "L" }, px(p.x), py(p.y));
        }
        d.push_str("Z ");
    }
    d.truncate(d.trim_end().len());
    d
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{PatternPiece, Placement};

    /// Each cut loop's `data-flat-transform` takes the piece's first layout onto the
    /// drawing: a square turned a quarter and moved (as packing moves it) is drawn where
    /// the matrix puts its first-layout corners.
    #[test]
    fn the_flat_transform_maps_the_first_layout_onto_the_drawing() {
        let first = [
            Vec2::new(0.0, 0.0),
            Vec2::new(20.0, 0.0),
            Vec2::new(20.0, 10.0),
            Vec2::new(0.0, 10.0),
        ];
        let placement = Placement([0.0, 1.0, -1.0, 0.0, 50.0, 7.0]);
        let pattern = Pattern {
            pieces: vec![PatternPiece {
                cut: vec![first.iter().map(|p| placement.apply(*p)).collect()],
                placement,
                ..Default::default()
            }],
            ..Default::default()
        };
        let svg = String::from_utf8(svg_bytes(&pattern, "t", 10.0)).unwrap();
        let path = svg.lines().find(|l| l.contains("data-flat-transform")).unwrap();
        let field = |name: &str| {
            let start = path.find(&format!("{name}=\"")).unwrap() + name.len() + 2;
            path[start..start + path[start..].find('"').unwrap()].to_string()
        };
        let m: Vec<f64> = field("data-flat-transform")
            .trim_start_matches("matrix(")
            .trim_end_matches(')')
            .split(' ')
            .map(|v| v.parse().unwrap())
            .collect();
        let drawn: Vec<Vec2> = field("d")
            .split(' ')
            .filter(|t| *t != "Z")
            .map(|t| {
                let (x, y) = t.trim_start_matches(['M', 'L']).split_once(',').unwrap();
                Vec2::new(x.parse().unwrap(), y.parse().unwrap())
            })
            .collect();
        assert_eq!(drawn.len(), 4);
        for (p, q) in first.iter().zip(&drawn) {
            let mapped = Vec2::new(m[0] * p.x + m[2] * p.y + m[4], m[1] * p.x + m[3] * p.y + m[5]);
            assert!((mapped - q).norm() < 1e-4, "{mapped:?} vs {q:?}");
        }
    }
}
