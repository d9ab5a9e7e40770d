//! The overlay drawing users check a reconstruction with (the paper's Fig. 4–7): over the
//! photograph, the patches, the propagated rulings, the symmetric correspondences, the
//! symmetry annotation, the traced curves and the solved 3D curves projected back into
//! the image. SVG text in image pixels; the caller supplies the image reference (a path
//! or a data URI).

use crate::annotation::{model_to_image, PhotoAnnotation};
use crate::reconstruction::{place_point, PhotoReconstruction};
use crate::{CurveKind, CurvePoint};
use std::fmt::Write;

/// A patch's fill colour (distinct hues, golden-angle spacing).
fn patch_colour(k: usize) -> String {
    let hue = (k as f64 * 137.507_764) % 360.0;
    format!("hsl({hue:.0},70%,55%)")
}

/// The overlay as SVG text (layers `patches`, `rulings`, `symmetry`, `curves`,
/// `reprojected`, each an Inkscape layer).
pub fn overlay_svg(annotation: &PhotoAnnotation, reconstruction: &PhotoReconstruction, image_href: &str) -> String {
    let r = reconstruction;
    let (w, h) = (annotation.image.width, annotation.image.height);
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape" width="{w}" height="{h}" viewBox="0 0 {w} {h}">"#
    );
    let _ = writeln!(
        s,
        r#"<title>{}: reconstruction over the photograph</title>"#,
        escape(annotation.name.as_deref().unwrap_or("photo"))
    );
    let _ = writeln!(
        s,
        r#"<image x="0" y="0" width="{w}" height="{h}" preserveAspectRatio="none" xlink:href="{}" href="{}"/>"#,
        escape(image_href),
        escape(image_href)
    );
    let layer = |s: &mut String, name: &str| {
        let _ = writeln!(
            s,
            r#"<g id="{name}" inkscape:groupmode="layer" inkscape:label="{name}">"#
        );
    };
    let point = |p: nalgebra::Vector2<f64>| {
        let q = model_to_image(p);
        format!("{:.2},{:.2}", q[0], q[1])
    };
    layer(&mut s, "patches");
    let mut material = 0;
    for patch in &r.patches {
        let points: Vec<String> = patch.polygon.outer().iter().map(|&p| point(p)).collect();
        if patch.opening {
            let _ = writeln!(
                s,
                r##"<polygon points="{}" fill="none" stroke="#888" stroke-width="1" stroke-dasharray="4 3"/>"##,
                points.join(" ")
            );
        } else {
            let _ = writeln!(
                s,
                r#"<polygon points="{}" fill="{}" fill-opacity="0.3" stroke="none"/>"#,
                points.join(" "),
                patch_colour(material)
            );
            material += 1;
        }
    }
    s.push_str("</g>\n");
    layer(&mut s, "rulings");
    for strip in &r.strips {
        for i in 0..strip.rulings.len() {
            let [a, b] = strip.segment(i);
            let (a, b) = (model_to_image(a), model_to_image(b));
            let _ = writeln!(
                s,
                r##"<line class="ruling" x1="{:.2}" y1="{:.2}" x2="{:.2}" y2="{:.2}" stroke="#1a9641" stroke-width="1.2"/>"##,
                a[0], a[1], b[0], b[1]
            );
        }
    }
    s.push_str("</g>\n");
    layer(&mut s, "symmetry");
    // At most 60 pairs, evenly chosen: all of them hide the photo.
    let step = r.pairs.len().div_ceil(60).max(1);
    for pair in r.pairs.iter().step_by(step) {
        let (a, b) = (model_to_image(pair.image[0]), model_to_image(pair.image[1]));
        let _ = writeln!(
            s,
            r##"<line class="pair" x1="{:.2}" y1="{:.2}" x2="{:.2}" y2="{:.2}" stroke="#d01c8b" stroke-width="0.7" stroke-opacity="0.8"/>"##,
            a[0], a[1], b[0], b[1]
        );
    }
    for seg in &annotation.symmetry.frame {
        let _ = writeln!(
            s,
            r##"<line x1="{:.2}" y1="{:.2}" x2="{:.2}" y2="{:.2}" stroke="#00bcd4" stroke-width="2.5"/>"##,
            seg[0][0], seg[0][1], seg[1][0], seg[1][1]
        );
    }
    for p in &annotation.symmetry.points {
        let _ = writeln!(
            s,
            r##"<rect x="{:.2}" y="{:.2}" width="8" height="8" fill="#e41a1c"/>"##,
            p[0] - 4.0,
            p[1] - 4.0
        );
    }
    s.push_str("</g>\n");
    layer(&mut s, "curves");
    for curve in &r.network.curves {
        let colour = match curve.kind {
            CurveKind::Silhouette => "#ff7f00",
            CurveKind::Boundary => "#2b83ba",
        };
        let mut d = String::new();
        for (k, &seg) in curve.segments.iter().enumerate() {
            let b = r.network.control_points(seg as usize);
            if k == 0 {
                let _ = write!(d, "M{} ", point(b[0]));
            }
            let _ = write!(d, "C{} {} {} ", point(b[1]), point(b[2]), point(b[3]));
        }
        let _ = writeln!(
            s,
            r#"<path d="{}" fill="none" stroke="{colour}" stroke-width="2"><title>{}</title></path>"#,
            d.trim_end(),
            escape(&curve.name)
        );
    }
    s.push_str("</g>\n");
    layer(&mut s, "reprojected");
    for (seg, params) in r.samples.parameters.iter().enumerate() {
        let points: Vec<String> = params
            .iter()
            .map(|&t| {
                let p = place_point(&r.network, &r.points3d, CurvePoint { segment: seg as u32, t });
                point(r.plane.camera.project(p))
            })
            .collect();
        let _ = writeln!(
            s,
            r#"<polyline points="{}" fill="none" stroke="white" stroke-width="1" stroke-dasharray="3 2"/>"#,
            points.join(" ")
        );
    }
    s.push_str("</g>\n</svg>\n");
    s
}

use sheetform_geometry::xml_escaped as escape;

/// The overlay rendered to a PNG of the photo's size (resvg; the embedded photo must be
/// a data URI or the SVG renders without it).
///
/// # Errors
/// [`crate::PhotoError::Field`] on `overlay` when the SVG cannot be parsed or rendered
/// (a bug, not bad input).
pub fn overlay_png(svg: &str) -> Result<Vec<u8>, crate::PhotoError> {
    let failed = |m: String| crate::PhotoError::field("overlay", m);
    let tree = resvg::usvg::Tree::from_str(svg, &resvg::usvg::Options::default()).map_err(|e| failed(e.to_string()))?;
    let size = tree.size().to_int_size();
    let mut pixmap =
        resvg::tiny_skia::Pixmap::new(size.width(), size.height()).ok_or_else(|| failed("empty size".into()))?;
    resvg::render(&tree, resvg::tiny_skia::Transform::identity(), &mut pixmap.as_mut());
    pixmap.encode_png().map_err(|e| failed(e.to_string()))
}
