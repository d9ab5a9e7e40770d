use sheetform_mesh::{PieceKind, SheetMesh};
use std::fmt::Write;

/// Knobs of the SVG pattern.
#[derive(Debug, Clone, PartialEq)]
pub struct SvgOptions {
    /// Margin around the pattern, in millimetres.
    pub margin_mm: f64,
    /// At most this many rulings drawn per piece (evenly chosen); the rulings are guides,
    /// not cuts.
    pub max_rulings_per_piece: usize,
    /// Title written into the file.
    pub title: String,
}

impl Default for SvgOptions {
    fn default() -> Self {
        Self {
            margin_mm: 10.0,
            max_rulings_per_piece: 60,
            title: "sheetform pattern".into(),
        }
    }
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The flat pattern as SVG at true size: the document is `W mm × H mm` and one user unit
/// is one millimetre, so it prints and laser-cuts at 1:1.
///
/// Layers (Inkscape layer groups, also plain `<g id>` for other tools):
/// - `cut`: the outline and holes (the boundary loops of the flat mesh), red hairline;
/// - `rulings`: the rulings, light grey dashed (guides for bending, not cuts);
/// - `labels`: each piece's name at an interior point.
///
/// The y axis is flipped so the pattern reads as seen from the sheet's top side.
pub fn svg_pattern(mesh: &SheetMesh, options: &SvgOptions) -> String {
    let mm = mesh.unit.millimetres();
    let (lo, hi) = mesh.flat_bounds();
    let m = options.margin_mm;
    let (w, h) = ((hi.x - lo.x) * mm + 2.0 * m, (hi.y - lo.y) * mm + 2.0 * m);
    let px = |x: f64| (x - lo.x) * mm + m;
    let py = |y: f64| (hi.y - y) * mm + m;
    let mut s = String::new();
    let _ = writeln!(s, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape" width="{w:.4}mm" height="{h:.4}mm" viewBox="0 0 {w:.4} {h:.4}">"#
    );
    let _ = writeln!(s, "<title>{}</title>", escape(&options.title));
    let _ = writeln!(
        s,
        r#"<desc>1 user unit = 1 mm. Layers: cut (outline and holes), rulings (bending guides), labels.</desc>"#
    );
    let _ = writeln!(
        s,
        r##"<g id="cut" inkscape:groupmode="layer" inkscape:label="cut" fill="none" stroke="#e00000" stroke-width="0.1">"##
    );
    for cycle in mesh.boundary_loops() {
        let mut d = String::new();
        for (i, &v) in cycle.iter().enumerate() {
            let q = mesh.flat[v as usize];
            let _ = write!(d, "{}{:.4},{:.4} ", if i == 0 { "M" } else { "L" }, px(q.x), py(q.y));
        }
        d.push('Z');
        let _ = writeln!(s, r#"<path d="{d}"/>"#);
    }
    let _ = writeln!(s, "</g>");
    let _ = writeln!(
        s,
        r##"<g id="rulings" inkscape:groupmode="layer" inkscape:label="rulings" fill="none" stroke="#9a9a9a" stroke-width="0.1" stroke-dasharray="1,1">"##
    );
    for piece in 0..mesh.pieces.len() {
        let rulings: Vec<_> = mesh.rulings.iter().filter(|r| r.piece as usize == piece).collect();
        if rulings.is_empty() {
            continue;
        }
        let step = rulings.len().div_ceil(options.max_rulings_per_piece.max(1)).max(1);
        for (i, r) in rulings.iter().enumerate() {
            if i % step != 0 && i + 1 != rulings.len() {
                continue;
            }
            let a = mesh.flat[r.vertices[0] as usize];
            let b = mesh.flat[*r.vertices.last().expect("ruling has vertices") as usize];
            let _ = writeln!(
                s,
                r#"<line x1="{:.4}" y1="{:.4}" x2="{:.4}" y2="{:.4}"/>"#,
                px(a.x),
                py(a.y),
                px(b.x),
                py(b.y)
            );
        }
    }
    let _ = writeln!(s, "</g>");
    let _ = writeln!(
        s,
        r##"<g id="labels" inkscape:groupmode="layer" inkscape:label="labels" font-family="Helvetica, Arial, sans-serif" font-size="4" fill="#3050a0" text-anchor="middle">"##
    );
    for (p, piece) in mesh.pieces.iter().enumerate() {
        // Label at the centroid of the piece's largest triangle.
        let best = mesh
            .triangles
            .iter()
            .zip(&mesh.face_pieces)
            .filter(|(_, &fp)| fp as usize == p)
            .map(|(t, _)| {
                let [a, b, c] = t.map(|i| mesh.flat[i as usize]);
                (((b - a).x * (c - a).y - (b - a).y * (c - a).x).abs(), (a + b + c) / 3.0)
            })
            .max_by(|x, y| x.0.total_cmp(&y.0));
        if let Some((_, c)) = best {
            let kind = match piece.kind {
                PieceKind::Curved => "curved",
                PieceKind::Planar => "planar",
                PieceKind::Chart => "chart",
            };
            let _ = writeln!(
                s,
                r#"<text x="{:.4}" y="{:.4}">{} ({kind})</text>"#,
                px(c.x),
                py(c.y),
                escape(&piece.name)
            );
        }
    }
    let _ = writeln!(s, "</g>");
    let _ = writeln!(s, "</svg>");
    s
}
