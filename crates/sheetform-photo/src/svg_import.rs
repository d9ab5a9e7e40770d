//! Annotations drawn in an SVG editor (Inkscape) over the photo, read into a
//! [`PhotoAnnotation`]: no special tool is needed to trace a photograph.
//!
//! **Convention** (documented for users in docs/guide/photo.md):
//!
//! - One `<image>` element holds the photograph (`href` or `xlink:href`: a path relative to
//!   the SVG file). Its placement (`x`, `y`, `width`, `height`, and the transforms of its
//!   groups) maps document coordinates to image pixels; without `width`/`height` it is
//!   drawn at its pixel size. Labelled `perspective` (focal length from the photo's EXIF)
//!   or `perspective 26mm` (35 mm equivalent), it is a perspective view.
//! - Layers (`<g inkscape:groupmode="layer">`, named by `inkscape:label`, or plain groups
//!   named by `id`), matched case-insensitively by prefix:
//!   - `silhouette…`: every path, line, polyline, polygon, circle or ellipse is a
//!     silhouette curve; `boundar…`: a boundary curve. The curve's name is its
//!     `inkscape:label` (or `id`); a label `name | mirror other` makes `name` and `other` a
//!     mirror pair, `name | self-symmetric` a self-symmetric curve. A path with several
//!     subpaths gives one curve per subpath (`name`, `name-2`, …); a closed subpath
//!     (`Z`, circles, ellipses, polygons) a closed curve. Lines become straight cubics,
//!     quadratic curves are raised to cubics, arcs are converted to cubics (svgtypes).
//!   - `symmetry…`: two shapes labelled `frame` (or one `frame` path with two subpaths):
//!     the two frame segments (first and last point of each); one labelled `pair` (or
//!     `pair flip` for the other depth reading): the two mirror points.
//!   - `marks…`: circles, ellipses or paths labelled `opening` or `occlusion` (their
//!     centre, or their first point), and one two-point path labelled `true-size LENGTH
//!     [UNIT]` (`mm` by default; `cm`, `m`, `in`).
//! - Everything else (the photo's layer, notes) is ignored.

use crate::annotation::{
    AnalysisSpec, CameraSpec, CurveKind, CurveSpec, ImagePoint, ImageSpec, PhotoAnnotation, Projection, SymmetrySpec,
    TrueSizeSpec,
};
use crate::PhotoError;
use sheetform_mesh::LengthUnit;
use svgtypes::{SimplePathSegment, SimplifyingPathParser};

/// Affine map `[a c e; b d f]` (SVG's matrix order).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Affine([f64; 6]);

impl Affine {
    const IDENTITY: Self = Self([1.0, 0.0, 0.0, 1.0, 0.0, 0.0]);

    fn then_local(self, local: Self) -> Self {
        // self ∘ local: apply `local` first (a child's transform inside its parent's).
        let [a, b, c, d, e, f] = self.0;
        let [a2, b2, c2, d2, e2, f2] = local.0;
        Self([
            a * a2 + c * b2,
            b * a2 + d * b2,
            a * c2 + c * d2,
            b * c2 + d * d2,
            a * e2 + c * f2 + e,
            b * e2 + d * f2 + f,
        ])
    }

    fn apply(self, p: [f64; 2]) -> [f64; 2] {
        let [a, b, c, d, e, f] = self.0;
        [a * p[0] + c * p[1] + e, b * p[0] + d * p[1] + f]
    }
}

fn transform_of(node: roxmltree::Node<'_, '_>) -> Result<Affine, PhotoError> {
    match node.attribute("transform") {
        None => Ok(Affine::IDENTITY),
        Some(text) => {
            let t: svgtypes::Transform = text
                .parse()
                .map_err(|e| PhotoError::field(element_name(node), format!("transform `{text}`: {e}")))?;
            Ok(Affine([t.a, t.b, t.c, t.d, t.e, t.f]))
        }
    }
}

/// The transform from an element's coordinates to the document's.
fn current_transform(node: roxmltree::Node<'_, '_>) -> Result<Affine, PhotoError> {
    let mut chain = Vec::new();
    let mut n = Some(node);
    while let Some(e) = n {
        if e.is_element() {
            chain.push(transform_of(e)?);
        }
        n = e.parent();
    }
    Ok(chain.into_iter().rev().fold(Affine::IDENTITY, Affine::then_local))
}

const INKSCAPE: &str = "http://www.inkscape.org/namespaces/inkscape";
const XLINK: &str = "http://www.w3.org/1999/xlink";

fn label(node: roxmltree::Node<'_, '_>) -> Option<String> {
    node.attribute((INKSCAPE, "label"))
        .or_else(|| node.attribute("id"))
        .map(|s| s.trim().to_string())
}

fn element_name(node: roxmltree::Node<'_, '_>) -> String {
    match label(node) {
        Some(l) => format!("svg <{} {l}>", node.tag_name().name()),
        None => format!("svg <{}> at byte {}", node.tag_name().name(), node.range().start),
    }
}

fn number(node: roxmltree::Node<'_, '_>, name: &str, default: Option<f64>) -> Result<f64, PhotoError> {
    match node.attribute(name) {
        Some(text) => {
            let t = text.trim().trim_end_matches("px");
            t.parse::<f64>().ok().filter(|v| v.is_finite()).ok_or_else(|| {
                PhotoError::field(element_name(node), format!("attribute {name}=`{text}` is not a number"))
            })
        }
        None => default.ok_or_else(|| PhotoError::field(element_name(node), format!("missing attribute {name}"))),
    }
}

/// The photograph referenced by the SVG: its path (as written) — read its pixel size and
/// pass it to [`annotation_from_svg`].
///
/// # Errors
/// Not an SVG document, no `<image>`, more than one, or an embedded (`data:`) image.
pub fn svg_image_reference(text: &str) -> Result<String, PhotoError> {
    let doc = roxmltree::Document::parse(text).map_err(|e| PhotoError::field("svg", e.to_string()))?;
    let image = the_image(&doc)?;
    let href = image
        .attribute((XLINK, "href"))
        .or_else(|| image.attribute("href"))
        .ok_or_else(|| PhotoError::field("svg <image>", "no href"))?;
    if href.starts_with("data:") {
        return Err(PhotoError::field(
            "svg <image>",
            "the photo is embedded: link it instead (Inkscape: File > Import, \"Link\") so the annotation can name it",
        ));
    }
    Ok(href.strip_prefix("file://").unwrap_or(href).to_string())
}

/// The camera named by the photo's label (`inkscape:label`, or `id`): `perspective`
/// (focal length from the photo's EXIF) or `perspective 26mm` (35 mm equivalent);
/// anything else, the orthographic camera.
fn image_camera(image: roxmltree::Node) -> Result<CameraSpec, PhotoError> {
    let Some(name) = label(image) else {
        return Ok(CameraSpec::default());
    };
    let lower = name.to_lowercase();
    let mut words = lower.split_whitespace();
    if words.next() != Some("perspective") {
        return Ok(CameraSpec::default());
    }
    let focal_length_35mm = match words.next() {
        None => None,
        Some(word) => Some(
            word.trim_end_matches("mm")
                .parse::<f64>()
                .map_err(|_| PhotoError::field("svg <image>", "label it `perspective` or `perspective 26mm`"))?,
        ),
    };
    Ok(CameraSpec {
        projection: Projection::Perspective,
        focal_length_35mm,
        ..CameraSpec::default()
    })
}

fn the_image<'a, 'b>(doc: &'a roxmltree::Document<'b>) -> Result<roxmltree::Node<'a, 'b>, PhotoError> {
    let root = doc.root_element();
    if root.tag_name().name() != "svg" {
        return Err(PhotoError::field("svg", "the root element is not <svg>"));
    }
    let images: Vec<_> = root.descendants().filter(|n| n.has_tag_name("image")).collect();
    match images.len() {
        1 => Ok(images[0]),
        0 => Err(PhotoError::field(
            "svg",
            "no <image>: import the photo into the drawing",
        )),
        n => Err(PhotoError::field(
            "svg",
            format!("{n} <image> elements: keep only the photo"),
        )),
    }
}

/// A shape's subpaths as cubic control points (document coordinates) and whether each is
/// closed.
/// Subpaths as cubic control points and whether each is closed.
type Subpaths = Vec<(Vec<[f64; 2]>, bool)>;

fn shape_subpaths(node: roxmltree::Node<'_, '_>) -> Result<Subpaths, PhotoError> {
    let k = 0.552_284_749_830_793_4;
    let ellipse = |cx: f64, cy: f64, rx: f64, ry: f64| -> Vec<[f64; 2]> {
        let mut pts = Vec::with_capacity(13);
        // Start at angle 0, counter-clockwise in the document's own frame.
        let dirs = [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0), (1.0, 0.0)];
        for q in 0..4 {
            let (c0, s0) = dirs[q];
            let (c1, s1) = dirs[q + 1];
            let p0 = [cx + rx * c0, cy + ry * s0];
            let p1 = [cx + rx * c1, cy + ry * s1];
            if q == 0 {
                pts.push(p0);
            }
            pts.push([p0[0] - k * rx * s0, p0[1] + k * ry * c0]);
            pts.push([p1[0] + k * rx * s1, p1[1] - k * ry * c1]);
            pts.push(p1);
        }
        pts
    };
    let line_to = |pts: &mut Vec<[f64; 2]>, p: [f64; 2]| {
        let p0 = *pts.last().expect("a subpath starts with a point");
        let d = [p[0] - p0[0], p[1] - p0[1]];
        pts.push([p0[0] + d[0] / 3.0, p0[1] + d[1] / 3.0]);
        pts.push([p0[0] + 2.0 * d[0] / 3.0, p0[1] + 2.0 * d[1] / 3.0]);
        pts.push(p);
    };
    let poly = |text: &str, closed: bool| -> Result<Subpaths, PhotoError> {
        let values: Vec<f64> = text
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|s| !s.is_empty())
            .map(|s| s.parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|_| PhotoError::field(element_name(node), "points are not numbers"))?;
        if values.len() < 4 || values.len() % 2 != 0 {
            return Err(PhotoError::field(element_name(node), "needs at least two points"));
        }
        let mut pts = vec![[values[0], values[1]]];
        for c in values[2..].chunks(2) {
            line_to(&mut pts, [c[0], c[1]]);
        }
        if closed {
            line_to(&mut pts, [values[0], values[1]]);
        }
        Ok(vec![(pts, closed)])
    };
    match node.tag_name().name() {
        "circle" => {
            let r = number(node, "r", None)?;
            Ok(vec![(
                ellipse(number(node, "cx", Some(0.0))?, number(node, "cy", Some(0.0))?, r, r),
                true,
            )])
        }
        "ellipse" => Ok(vec![(
            ellipse(
                number(node, "cx", Some(0.0))?,
                number(node, "cy", Some(0.0))?,
                number(node, "rx", None)?,
                number(node, "ry", None)?,
            ),
            true,
        )]),
        "line" => {
            let mut pts = vec![[number(node, "x1", Some(0.0))?, number(node, "y1", Some(0.0))?]];
            line_to(
                &mut pts,
                [number(node, "x2", Some(0.0))?, number(node, "y2", Some(0.0))?],
            );
            Ok(vec![(pts, false)])
        }
        "polyline" => poly(node.attribute("points").unwrap_or(""), false),
        "polygon" => poly(node.attribute("points").unwrap_or(""), true),
        "path" => {
            let d = node.attribute("d").unwrap_or("");
            let mut out: Vec<(Vec<[f64; 2]>, bool)> = Vec::new();
            let mut current: Vec<[f64; 2]> = Vec::new();
            for segment in SimplifyingPathParser::from(d) {
                let segment = segment.map_err(|e| PhotoError::field(element_name(node), format!("path data: {e}")))?;
                match segment {
                    SimplePathSegment::MoveTo { x, y } => {
                        if current.len() >= 4 {
                            out.push((std::mem::take(&mut current), false));
                        }
                        current = vec![[x, y]];
                    }
                    SimplePathSegment::LineTo { x, y } => {
                        if !current.is_empty() {
                            line_to(&mut current, [x, y]);
                        }
                    }
                    SimplePathSegment::CurveTo { x1, y1, x2, y2, x, y } => {
                        current.extend([[x1, y1], [x2, y2], [x, y]]);
                    }
                    SimplePathSegment::Quadratic { x1, y1, x, y } => {
                        let p0 = *current.last().unwrap_or(&[x, y]);
                        current.push([p0[0] + 2.0 / 3.0 * (x1 - p0[0]), p0[1] + 2.0 / 3.0 * (y1 - p0[1])]);
                        current.push([x + 2.0 / 3.0 * (x1 - x), y + 2.0 / 3.0 * (y1 - y)]);
                        current.push([x, y]);
                    }
                    SimplePathSegment::ClosePath => {
                        if let (Some(&first), Some(&last)) = (current.first(), current.last()) {
                            if first != last {
                                line_to(&mut current, first);
                            }
                            if current.len() >= 4 {
                                out.push((std::mem::take(&mut current), true));
                            }
                        }
                    }
                }
            }
            if current.len() >= 4 {
                out.push((current, false));
            }
            Ok(out)
        }
        _ => Ok(vec![]),
    }
}

const SHAPES: [&str; 6] = ["path", "line", "polyline", "polygon", "circle", "ellipse"];

/// Reads an annotation drawn in an SVG editor (see the module documentation);
/// `image_size` is the photo's size in pixels (read by the caller from the file
/// [`svg_image_reference`] names).
///
/// # Errors
/// [`PhotoError::Field`] naming the SVG element (`svg <path rim>`) or the missing part
/// (no silhouette/boundary layer, no frame, no pair, no true size); the annotation's own
/// validation.
pub fn annotation_from_svg(text: &str, image_size: (u32, u32)) -> Result<PhotoAnnotation, PhotoError> {
    let doc = roxmltree::Document::parse(text).map_err(|e| PhotoError::field("svg", e.to_string()))?;
    let image = the_image(&doc)?;
    let image_path = svg_image_reference(text)?;
    let (w, h) = (f64::from(image_size.0), f64::from(image_size.1));
    let image_ctm = current_transform(image)?;
    let (x0, y0) = (number(image, "x", Some(0.0))?, number(image, "y", Some(0.0))?);
    let (iw, ih) = (number(image, "width", Some(w))?, number(image, "height", Some(h))?);
    let (c0, c1) = (image_ctm.apply([x0, y0]), image_ctm.apply([x0 + iw, y0 + ih]));
    if !((c1[0] - c0[0]).abs() > 0.0 && (c1[1] - c0[1]).abs() > 0.0) {
        return Err(PhotoError::field("svg <image>", "has zero width or height"));
    }
    // Document → image pixels (the image must not be rotated).
    let to_pixels = |p: [f64; 2]| -> ImagePoint {
        [
            (p[0] - c0[0]) * w / (c1[0] - c0[0]),
            (p[1] - c0[1]) * h / (c1[1] - c0[1]),
        ]
    };
    let camera = image_camera(image)?;
    let mut curves: Vec<CurveSpec> = Vec::new();
    let mut mirror: Vec<[String; 2]> = Vec::new();
    let mut self_symmetric: Vec<String> = Vec::new();
    let mut frames: Vec<[ImagePoint; 2]> = Vec::new();
    let mut pair: Option<([ImagePoint; 2], bool)> = None;
    let mut openings = Vec::new();
    let mut occlusions = Vec::new();
    let mut true_size: Option<TrueSizeSpec> = None;
    let mut units = LengthUnit::Mm;
    let mut layers_seen = 0;
    for layer in doc.root_element().descendants().filter(|n| n.has_tag_name("g")) {
        let Some(name) = label(layer) else { continue };
        let name = name.to_lowercase();
        let kind = if name.starts_with("silhouette") {
            Some(Some(CurveKind::Silhouette))
        } else if name.starts_with("boundar") {
            Some(Some(CurveKind::Boundary))
        } else if name.starts_with("symmetry") || name.starts_with("marks") {
            Some(None)
        } else {
            None
        };
        let Some(kind) = kind else { continue };
        layers_seen += 1;
        for shape in layer.descendants().filter(|n| SHAPES.contains(&n.tag_name().name())) {
            let ctm = current_transform(shape)?;
            let subpaths: Vec<(Vec<ImagePoint>, bool)> = shape_subpaths(shape)?
                .into_iter()
                .map(|(pts, closed)| (pts.into_iter().map(|p| to_pixels(ctm.apply(p))).collect(), closed))
                .collect();
            let full = label(shape).unwrap_or_else(|| format!("curve-{}", curves.len() + 1));
            match kind {
                Some(kind) => {
                    let mut parts = full.split('|');
                    let base = parts.next().unwrap_or("").trim().to_string();
                    for (i, (points, closed)) in subpaths.into_iter().enumerate() {
                        let name = if i == 0 {
                            base.clone()
                        } else {
                            format!("{base}-{}", i + 1)
                        };
                        curves.push(CurveSpec {
                            name,
                            kind,
                            control_points: points,
                            closed,
                        });
                    }
                    for note in parts {
                        let note = note.trim();
                        if note.eq_ignore_ascii_case("self-symmetric") {
                            self_symmetric.push(base.clone());
                        } else if let Some(other) = note.strip_prefix("mirror") {
                            let other = other.trim().to_string();
                            if !mirror
                                .iter()
                                .any(|[a, b]| (a == &other && b == &base) || (a == &base && b == &other))
                            {
                                mirror.push([base.clone(), other]);
                            }
                        } else {
                            return Err(PhotoError::field(
                                element_name(shape),
                                format!("unknown note `{note}` (use `| mirror OTHER` or `| self-symmetric`)"),
                            ));
                        }
                    }
                }
                None => {
                    let lower = full.to_lowercase();
                    let ends = |pts: &Vec<ImagePoint>| -> [ImagePoint; 2] { [pts[0], *pts.last().expect("points")] };
                    let centre = |pts: &Vec<ImagePoint>, closed: bool| -> ImagePoint {
                        if closed {
                            let n = (pts.len() - 1) as f64;
                            let s = pts[..pts.len() - 1]
                                .iter()
                                .fold([0.0, 0.0], |a, p| [a[0] + p[0], a[1] + p[1]]);
                            [s[0] / n, s[1] / n]
                        } else {
                            pts[0]
                        }
                    };
                    if lower.starts_with("frame") {
                        frames.extend(subpaths.iter().map(|(p, _)| ends(p)));
                    } else if lower.starts_with("pair") {
                        let (p, _) = subpaths
                            .first()
                            .ok_or_else(|| PhotoError::field(element_name(shape), "empty"))?;
                        pair = Some((ends(p), lower.contains("flip")));
                    } else if lower.starts_with("opening") {
                        openings.extend(subpaths.iter().map(|(p, c)| centre(p, *c)));
                    } else if lower.starts_with("occlusion") {
                        occlusions.extend(subpaths.iter().map(|(p, c)| centre(p, *c)));
                    } else if lower.starts_with("true-size") || lower.starts_with("true size") {
                        let words: Vec<&str> = lower[9..].split_whitespace().collect();
                        let length = words.first().and_then(|w| w.parse::<f64>().ok()).ok_or_else(|| {
                            PhotoError::field(element_name(shape), "label it `true-size LENGTH [mm|cm|m|in]`")
                        })?;
                        if let Some(unit) = words.get(1) {
                            units = match *unit {
                                "mm" => LengthUnit::Mm,
                                "cm" => LengthUnit::Cm,
                                "m" => LengthUnit::M,
                                "in" => LengthUnit::In,
                                other => {
                                    return Err(PhotoError::field(
                                        element_name(shape),
                                        format!("unknown unit `{other}` (mm, cm, m, in)"),
                                    ))
                                }
                            };
                        }
                        let (p, _) = subpaths
                            .first()
                            .ok_or_else(|| PhotoError::field(element_name(shape), "empty"))?;
                        let [from, to] = ends(p);
                        true_size = Some(TrueSizeSpec { from, to, length });
                    }
                }
            }
        }
    }
    if layers_seen == 0 || curves.is_empty() {
        return Err(PhotoError::field(
            "svg",
            "no curves: draw them in layers named `silhouettes` and `boundaries`",
        ));
    }
    if frames.len() != 2 {
        return Err(PhotoError::field(
            "svg symmetry layer",
            format!("needs two segments labelled `frame` (found {})", frames.len()),
        ));
    }
    let (points, flip_depth) =
        pair.ok_or_else(|| PhotoError::field("svg symmetry layer", "needs a segment labelled `pair`"))?;
    let true_size =
        true_size.ok_or_else(|| PhotoError::field("svg marks layer", "needs a segment labelled `true-size LENGTH`"))?;
    let title = doc
        .root_element()
        .children()
        .find(|n| n.has_tag_name("title"))
        .and_then(|n| n.text())
        .map(|t| t.trim().to_string());
    let annotation = PhotoAnnotation {
        name: title,
        image: ImageSpec {
            path: image_path,
            width: image_size.0,
            height: image_size.1,
        },
        camera,
        units,
        curves,
        symmetry: SymmetrySpec {
            frame: [frames[0], frames[1]],
            points,
            flip_depth,
        },
        symmetric_curves: mirror,
        self_symmetric_curves: self_symmetric,
        occlusions,
        openings,
        // An SVG drawing has no mark for it: `sheetform photo --back-side revolve`.
        back_side: crate::BackSide::default(),
        true_size,
        analysis: AnalysisSpec::default(),
    };
    annotation.validate()?;
    Ok(annotation)
}
