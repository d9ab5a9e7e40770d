use crate::Pattern;
use std::fmt::Write;

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The pattern as SVG at true size: the document is `W mm × H mm` and one user unit is
/// one millimetre, so it prints and laser-cuts at 1:1. Layers (Inkscape layer groups,
/// plain `<g id>` for other tools): `cut` (the loops, red hairline), `fold` (fold/score
/// guides, grey dashed), `labels`. The y axis is flipped so the pattern reads as seen
/// from the sheet's top side; `margin_mm` surrounds it.
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
    let _ = writeln!(s, "<desc>1 user unit = 1 mm. Layers: cut, fold, labels.</desc>");
    let _ = writeln!(
        s,
        r##"<g id="cut" inkscape:groupmode="layer" inkscape:label="cut" fill="none" stroke="#e00000" stroke-width="0.1">"##
    );
    for cycle in &pattern.cut {
        let mut d = String::new();
        for (i, p) in cycle.iter().enumerate() {
            let _ = write!(d, "{}{:.4},{:.4} ", if i == 0 { "M" } else { "L" }, px(p.x), py(p.y));
        }
        d.push('Z');
        let _ = writeln!(s, r#"<path d="{d}"/>"#);
    }
    let _ = writeln!(s, "</g>");
    let _ = writeln!(
        s,
        r##"<g id="fold" inkscape:groupmode="layer" inkscape:label="fold" fill="none" stroke="#9a9a9a" stroke-width="0.1" stroke-dasharray="1,1">"##
    );
    for [a, b] in &pattern.fold {
        let _ = writeln!(
            s,
            r#"<line x1="{:.4}" y1="{:.4}" x2="{:.4}" y2="{:.4}"/>"#,
            px(a.x),
            py(a.y),
            px(b.x),
            py(b.y)
        );
    }
    let _ = writeln!(s, "</g>");
    let _ = writeln!(
        s,
        r##"<g id="labels" inkscape:groupmode="layer" inkscape:label="labels" font-family="Helvetica, Arial, sans-serif" font-size="4" fill="#3050a0" text-anchor="middle">"##
    );
    for (p, text) in &pattern.labels {
        let _ = writeln!(
            s,
            r#"<text x="{:.4}" y="{:.4}">{}</text>"#,
            px(p.x),
            py(p.y),
            escape(text)
        );
    }
    let _ = writeln!(s, "</g>\n</svg>");
    s.into_bytes()
}
