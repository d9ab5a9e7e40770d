use crate::{Fold, FoldStyle, Label, Pattern, PatternError, Vec2};
use pdf_writer::{Content, Name, Pdf, Rect, Ref, Str};
use rstar::primitives::{GeomWithData, Rectangle};
use rstar::{RTree, AABB};
use std::borrow::Cow;

/// Paper size.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
pub enum PageSize {
    /// ISO A4, 210 × 297 mm.
    #[default]
    A4,
    /// US Letter, 8.5 × 11 in.
    Letter,
}

impl PageSize {
    /// Width and height in millimetres (portrait).
    pub fn millimetres(self) -> (f64, f64) {
        match self {
            PageSize::A4 => (210.0, 297.0),
            PageSize::Letter => (215.9, 279.4),
        }
    }
}

/// Knobs of [`pdf_tiled`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PdfOptions {
    /// Paper.
    pub page: PageSize,
    /// Unprinted margin on every side (millimetres); printers cannot print to the edge.
    pub margin_mm: f64,
    /// How much neighbouring tiles overlap (millimetres), to glue or tape them together.
    pub overlap_mm: f64,
    /// Length of the scale bar (millimetres).
    pub scale_bar_mm: f64,
    /// Most pages to print: a pattern that needs more is refused (with the count and how
    /// to raise this), not printed on a ream of paper. Default [`DEFAULT_MAX_PAGES`].
    pub max_pages: usize,
    /// Draw the sheets' outlines (off when the sheets are the pages themselves).
    pub sheet_outlines: bool,
}

impl PdfOptions {
    /// Width and height (mm) of the printable area of a page: the paper less the margins
    /// and the 12 mm footer for the scale bar.
    pub fn printable_area(&self) -> (f64, f64) {
        let (pw, ph) = self.page.millimetres();
        (pw - 2.0 * self.margin_mm, ph - 2.0 * self.margin_mm - 12.0)
    }
}

/// Default page cap of [`PdfOptions`].
pub const DEFAULT_MAX_PAGES: usize = 100;

/// Most pages [`PdfOptions::max_pages`] may allow: each page holds its share of the
/// pattern's drawing, so the document's size grows with it (1e19 pages asked for
/// gigabytes and aborted).
pub const MAX_PAGES: usize = 10_000;

impl Default for PdfOptions {
    fn default() -> Self {
        Self {
            page: PageSize::A4,
            margin_mm: 12.0,
            overlap_mm: 10.0,
            scale_bar_mm: 50.0,
            max_pages: DEFAULT_MAX_PAGES,
            sheet_outlines: true,
        }
    }
}

/// A tiled PDF and its layout.
#[derive(Debug, Clone, PartialEq)]
pub struct TiledPdf {
    /// The PDF file.
    pub bytes: Vec<u8>,
    /// Tile rows (top to bottom) and columns (left to right) of the grid (of the largest
    /// sheet when the pattern is packed on sheets, each sheet tiled on its own).
    pub rows: usize,
    /// Tile columns.
    pub columns: usize,
    /// Pages printed: the tiles of the `rows × columns` grid that show part of the
    /// pattern (a tile with no line and no label on it is left out; every printed page
    /// names its place in the grid).
    pub page_count: usize,
}

/// Points per millimetre.
const PT: f64 = 72.0 / 25.4;

/// The pattern at true scale on as many pages as it needs; a pattern packed on sheets
/// sheet by sheet (a sheet within the printable area on one page, captioned with its
/// number), at most `options.max_pages` pages.
///
/// Each page prints the window of the pattern that falls in its printable area (the page
/// less `margin_mm`); neighbouring windows overlap by `overlap_mm`, marked with dashed
/// lines to align them. Windows with nothing of the pattern in them (no cut or fold line,
/// label or sheet outline crosses them) are not printed. Every page carries corner registration marks, its position
/// (`row r, column c of R × C`), and a scale bar of `scale_bar_mm` to check the printer
/// did not scale the page ("print at 100 %"). Cut lines red, fold lines grey dashed,
/// labels blue (Helvetica).
///
/// A page's content holds only the marks whose bounds meet its printable area (found in
/// an R-tree of the part's cut segments, folds, labels and texture clips), so the
/// document grows with the drawing, not with pages × drawing; it prints the same.
///
/// # Errors
/// Margins or overlap that leave no printable area; more pages than `options.max_pages`;
/// a texture that cannot be read or has more than [`MAX_TEXTURE_PIXELS`].
pub fn pdf_tiled(pattern: &Pattern, options: &PdfOptions) -> Result<TiledPdf, PatternError> {
    if !(1..=MAX_PAGES).contains(&options.max_pages) {
        return Err(PatternError::Option {
            option: "max_pages",
            message: format!("must be 1 to {MAX_PAGES}, got {}", options.max_pages),
        });
    }
    let (pw, ph) = options.page.millimetres();
    let (m, o) = (options.margin_mm, options.overlap_mm);
    let (aw, ah) = options.printable_area();
    if !(m >= 0.0 && o >= 0.0 && aw > o + 10.0 && ah > o + 10.0) {
        return Err(PatternError::Option {
            option: "margin_mm/overlap_mm",
            message: "leave no printable area on the page".into(),
        });
    }
    // Every sheet takes a tile at least: far too many sheets are refused before they are
    // sorted out.
    if pattern.sheets.len() > options.max_pages.saturating_mul(16) {
        return Err(too_many_pages(pattern.sheets.len(), options));
    }
    // A packed pattern is printed sheet by sheet (a sheet that fits the printable area on
    // one page), an unpacked one as a whole.
    let parts: Vec<Cow<Pattern>> = if pattern.sheets.is_empty() {
        vec![Cow::Borrowed(pattern)]
    } else {
        pattern.split_into_sheets(false).into_iter().map(Cow::Owned).collect()
    };
    let (sx, sy) = (aw - o, ah - o);
    let grids: Vec<(usize, usize, Vec2)> = parts
        .iter()
        .map(|part| {
            let (lo, hi) = part.bounds();
            let (lo, hi) = if lo.x.is_finite() {
                (lo, hi)
            } else {
                (Vec2::zeros(), Vec2::zeros())
            };
            let (w, h) = (hi.x - lo.x, hi.y - lo.y);
            // (Float to integer casts saturate: an absurd size gives a huge count, refused
            // below before anything is drawn.)
            // (Less a hair before rounding up: a sheet made of exactly r tiles is r tiles.)
            let columns = ((w - o).max(0.0) / sx - 1e-9).ceil().max(1.0) as usize;
            let rows = ((h - o).max(0.0) / sy - 1e-9).ceil().max(1.0) as usize;
            // Centre the part in its tiled area.
            let (tw, th) = (columns as f64 * sx + o, rows as f64 * sy + o);
            (rows, columns, Vec2::new(lo.x - 0.5 * (tw - w), hi.y + 0.5 * (th - h)))
        })
        .collect();
    let tiles = grids
        .iter()
        .fold(0usize, |n, &(r, c, _)| n.saturating_add(r.saturating_mul(c)));
    // Empty tiles are skipped, so the grid may hold more tiles than pages get printed;
    // a grid far beyond the cap is refused before any tile is looked at.
    if tiles > options.max_pages.saturating_mul(16) {
        return Err(too_many_pages(tiles, options));
    }
    let sheet_count = parts.len();
    let mut pdf = Pdf::new();
    let catalog = Ref::new(1);
    let tree = Ref::new(2);
    let font = Ref::new(3);
    let mut next = 4;
    let mut page_ids = Vec::new();
    pdf.type1_font(font).base_font(Name(b"Helvetica"));
    // The texture, once per document.
    let texture = match &pattern.texture {
        Some(t) => {
            let id = Ref::new(next);
            next += 1;
            embed_texture(&mut pdf, id, t)?;
            Some((id, t))
        }
        None => None,
    };
    for (k, (pattern, &(rows, columns, origin))) in parts.iter().zip(&grids).enumerate() {
        let index = PartIndex::new(pattern, texture.is_some());
        // Every label printed whole on one tile, never cut at a tile's edge: the first
        // tile whose window holds all of its text, or else the one whose window holds its
        // middle deepest (printed past the window's edge into the page's margin).
        let window = |r: usize, c: usize| {
            let (wx, wy) = (origin.x + c as f64 * sx, origin.y - r as f64 * sy);
            (Vec2::new(wx, wy - ah), Vec2::new(wx + aw, wy))
        };
        let label_tile: Vec<(usize, usize)> = index
            .labels
            .iter()
            .map(|label| {
                let (half_width, half_height) = label_half_extent(label);
                let (lo, hi) = (
                    label.position - Vec2::new(half_width, half_height),
                    label.position + Vec2::new(half_width, half_height),
                );
                let tiles = (0..rows).flat_map(|r| (0..columns).map(move |c| (r, c)));
                let whole = tiles.clone().find(|&(r, c)| {
                    let (a, b) = window(r, c);
                    lo.x >= a.x && lo.y >= a.y && hi.x <= b.x && hi.y <= b.y
                });
                whole.unwrap_or_else(|| {
                    let depth = |(r, c): (usize, usize)| {
                        let (a, b) = window(r, c);
                        let p = label.position;
                        (p.x - a.x).min(b.x - p.x).min(p.y - a.y).min(b.y - p.y)
                    };
                    tiles.max_by(|&x, &y| depth(x).total_cmp(&depth(y))).unwrap_or((0, 0))
                })
            })
            .collect();
        for r in 0..rows {
            for c in 0..columns {
                // Pattern window of this tile: x from wx, y down from wy.
                let (wx, wy) = (origin.x + c as f64 * sx, origin.y - r as f64 * sy);
                // (The last tile is printed when nothing was: a PDF has at least one page.)
                let last = k + 1 == sheet_count && r + 1 == rows && c + 1 == columns && page_ids.is_empty();
                if !last
                    && !index.window_shows(
                        pattern,
                        Vec2::new(wx, wy - ah),
                        Vec2::new(wx + aw, wy),
                        options.sheet_outlines,
                    )
                {
                    continue;
                }
                // What this page draws: the marks whose bounds meet its printable area (a
                // little more, for the width of the strokes), in drawing order.
                let pad = Vec2::repeat(STROKE_PAD_MM);
                let marks = index.marks_in(Vec2::new(wx, wy - ah) - pad, Vec2::new(wx + aw, wy) + pad);
                let (page_id, content_id) = (Ref::new(next), Ref::new(next + 1));
                next += 2;
                page_ids.push(page_id);
                let to_page = |p: Vec2| (((p.x - wx + m) * PT) as f32, ((p.y - (wy - ah) + m + 12.0) * PT) as f32);
                let mut content = Content::new();
                // Clip to the printable area.
                content.save_state();
                content.rect(
                    (m * PT) as f32,
                    ((m + 12.0) * PT) as f32,
                    (aw * PT) as f32,
                    (ah * PT) as f32,
                );
                content.clip_nonzero();
                content.end_path();
                // The texture under each piece, moved with it, clipped to its outline.
                if let Some((_, t)) = texture {
                    for piece in marks.iter().filter_map(|m| match m {
                        Mark::Texture(n) => Some(&pattern.pieces[*n as usize]),
                        _ => None,
                    }) {
                        content.save_state();
                        for cycle in &piece.cut {
                            trace_ring(&mut content, cycle, &to_page);
                        }
                        content.clip_even_odd();
                        content.end_path();
                        // The image's unit square → first layout → the piece's place → page.
                        let corner = |u: f64, v: f64| {
                            let q = piece.placement.apply(t.origin + Vec2::new(u * t.size.x, v * t.size.y));
                            to_page(q)
                        };
                        let (o, x, y) = (corner(0.0, 0.0), corner(1.0, 0.0), corner(0.0, 1.0));
                        content.transform([x.0 - o.0, x.1 - o.1, y.0 - o.0, y.1 - o.1, o.0, o.1]);
                        content.x_object(Name(b"Im1"));
                        content.restore_state();
                    }
                }
                content.set_line_width(0.4);
                content.set_stroke_rgb(0.85, 0.0, 0.0);
                let cuts: Vec<(u32, u32)> = marks
                    .iter()
                    .filter_map(|m| match *m {
                        Mark::Cut { ring, segment } => Some((ring, segment)),
                        _ => None,
                    })
                    .collect();
                for same_ring in cuts.chunk_by(|a, b| a.0 == b.0) {
                    let ring = index.rings[same_ring[0].0 as usize];
                    if same_ring.len() == ring.len() {
                        trace_ring(&mut content, ring, &to_page);
                    } else {
                        let segments: Vec<u32> = same_ring.iter().map(|c| c.1).collect();
                        trace_segments(&mut content, ring, &segments, &to_page);
                    }
                    content.stroke();
                }
                let folds: Vec<&Fold> = marks
                    .iter()
                    .filter_map(|m| match m {
                        Mark::Fold(n) => Some(index.folds[*n as usize]),
                        _ => None,
                    })
                    .collect();
                content.set_line_width(0.3);
                // Origami convention: mountain dash-dot red, valley dashed blue; guides
                // dotted grey, tab bases dotted teal (as in the SVG); stitch lines dashed
                // green, notches solid red (cuts), grain lines solid dark grey.
                for style in [
                    FoldStyle::Mountain,
                    FoldStyle::Valley,
                    FoldStyle::Guide,
                    FoldStyle::TabBase,
                    FoldStyle::Stitch,
                    FoldStyle::Notch,
                    FoldStyle::Grain,
                ] {
                    match style {
                        FoldStyle::Mountain => {
                            content.set_stroke_rgb(0.8, 0.2, 0.2);
                            content.set_dash_pattern([4.0, 1.5, 1.0, 1.5], 0.0);
                        }
                        FoldStyle::Valley => {
                            content.set_stroke_rgb(0.2, 0.35, 0.8);
                            content.set_dash_pattern([3.0, 2.0], 0.0);
                        }
                        FoldStyle::Guide => {
                            content.set_stroke_rgb(0.55, 0.55, 0.55);
                            content.set_dash_pattern([1.0, 2.0], 0.0);
                        }
                        FoldStyle::TabBase => {
                            content.set_stroke_rgb(0.06, 0.5, 0.5);
                            content.set_dash_pattern([1.5, 1.5], 0.0);
                        }
                        FoldStyle::Stitch => {
                            content.set_stroke_rgb(0.1, 0.55, 0.25);
                            content.set_dash_pattern([2.0, 1.5], 0.0);
                        }
                        FoldStyle::Notch => {
                            content.set_stroke_rgb(0.85, 0.0, 0.0);
                            content.set_dash_pattern([], 0.0);
                        }
                        FoldStyle::Grain => {
                            content.set_stroke_rgb(0.3, 0.3, 0.3);
                            content.set_dash_pattern([], 0.0);
                        }
                    }
                    for f in folds.iter().filter(|f| f.style == style) {
                        let ((x0, y0), (x1, y1)) = (to_page(f.a), to_page(f.b));
                        content.move_to(x0, y0);
                        content.line_to(x1, y1);
                        content.stroke();
                    }
                }
                content.set_dash_pattern([], 0.0);
                // Sheet outlines (packed patterns), thin black.
                content.set_stroke_rgb(0.0, 0.0, 0.0);
                content.set_line_width(0.2);
                for (corner, size) in pattern.sheets.iter().filter(|_| options.sheet_outlines) {
                    let (x0, y0) = to_page(*corner);
                    let (x1, y1) = to_page(corner + size);
                    content.rect(x0, y0, x1 - x0, y1 - y0);
                    content.stroke();
                }
                // Overlap guides where this tile meets its neighbours: long magenta dashes
                // and a line a third as thick as a fold's, unlike every fold, guide and
                // cut line (neither red dash-dot, blue dashed, teal or grey dotted).
                content.set_stroke_rgb(0.85, 0.25, 0.85);
                content.set_line_width(0.1);
                content.set_dash_pattern([8.0, 4.0], 0.0);
                let (left, bottom, right, top) = (m, m + 12.0, m + aw, m + 12.0 + ah);
                if c + 1 < columns {
                    line(&mut content, right - o, bottom, right - o, top);
                }
                if c > 0 {
                    line(&mut content, left + o, bottom, left + o, top);
                }
                if r + 1 < rows {
                    line(&mut content, left, bottom + o, right, bottom + o);
                }
                if r > 0 {
                    line(&mut content, left, top - o, right, top - o);
                }
                content.restore_state();
                // Labels after the clip: each whole, on its own tile.
                content.set_dash_pattern([], 0.0);
                content.set_fill_rgb(0.2, 0.3, 0.65);
                for label in marks.iter().filter_map(|m| match m {
                    Mark::Label(n) if label_tile[*n as usize] == (r, c) => Some(index.labels[*n as usize]),
                    _ => None,
                }) {
                    let (x, y) = to_page(label.position);
                    let size = (label.height_mm * PT * 1.4) as f32;
                    let width = ascii(&label.text).len() as f32 * size * 0.55;
                    let (s, c) = (label.angle_radians as f32).sin_cos();
                    content.begin_text();
                    content.set_font(Name(b"F1"), size);
                    // Centred on the anchor, turned with the label.
                    let (dx, dy) = (-0.5 * width, -0.35 * size);
                    content.set_text_matrix([c, s, -s, c, x + c * dx - s * dy, y + s * dx + c * dy]);
                    content.show(Str(ascii(&label.text).as_bytes()));
                    content.end_text();
                }
                // Registration marks at the printable area's corners.
                content.set_line_width(0.3);
                content.set_stroke_rgb(0.0, 0.0, 0.0);
                for (x, y) in [(left, bottom), (right, bottom), (left, top), (right, top)] {
                    line(&mut content, x - 4.0, y, x + 4.0, y);
                    line(&mut content, x, y - 4.0, x, y + 4.0);
                }
                // Scale bar with 10 mm ticks, and the tile's place.
                let (bx, by) = (m, m + 3.0);
                content.set_line_width(0.6);
                line(&mut content, bx, by, bx + options.scale_bar_mm, by);
                let ticks = (options.scale_bar_mm / 10.0).floor() as usize;
                for t in 0..=ticks {
                    let x = bx + 10.0 * t as f64;
                    line(&mut content, x, by, x, by + 2.0);
                }
                content.set_fill_rgb(0.0, 0.0, 0.0);
                let sheet = if sheet_count > 1 {
                    format!("sheet {} of {sheet_count}    ", k + 1)
                } else {
                    String::new()
                };
                let tile = if rows * columns > 1 {
                    format!(
                        "tile row {} column {} of {} x {}    overlap {:.0} mm",
                        r + 1,
                        c + 1,
                        rows,
                        columns,
                        o
                    )
                } else {
                    String::new()
                };
                let caption = format!(
                    "{:.0} mm: measure to check 100 % scale    {sheet}{tile}",
                    options.scale_bar_mm
                );
                content.begin_text();
                content.set_font(Name(b"F1"), 7.0);
                content.next_line(((bx + options.scale_bar_mm + 4.0) * PT) as f32, (by * PT) as f32);
                content.show(Str(caption.as_bytes()));
                content.end_text();
                pdf.stream(content_id, &content.finish());
                let mut page = pdf.page(page_id);
                page.media_box(Rect::new(0.0, 0.0, (pw * PT) as f32, (ph * PT) as f32));
                page.parent(tree);
                page.contents(content_id);
                let mut resources = page.resources();
                resources.fonts().pair(Name(b"F1"), font);
                if let Some((id, _)) = texture {
                    resources.x_objects().pair(Name(b"Im1"), id);
                }
                drop(resources);
                drop(page);
                if page_ids.len() > options.max_pages {
                    return Err(too_many_pages(page_ids.len(), options));
                }
            }
        }
    }
    pdf.pages(tree)
        .kids(page_ids.iter().copied())
        .count(page_ids.len() as i32);
    pdf.catalog(catalog).pages(tree);
    let page_count = page_ids.len();
    Ok(TiledPdf {
        bytes: pdf.finish(),
        rows: grids.iter().map(|g| g.0).max().unwrap_or(1),
        columns: grids.iter().map(|g| g.1).max().unwrap_or(1),
        page_count,
    })
}

/// Most pages the page-cap error counts: past it the count (of tiles, saturating) says
/// nothing more (`--scale 1e300` printed "18446744073709551615 or more").
const MOST_PAGES_COUNTED: usize = 1_000_000;

/// The error for a PDF over the page cap (`pages`: how many it would print at least).
fn too_many_pages(pages: usize, options: &PdfOptions) -> PatternError {
    let count = if pages > MOST_PAGES_COUNTED {
        "over a million".to_string()
    } else {
        format!("{pages} or more")
    };
    PatternError::Option {
        option: "max_pages",
        message: format!(
            "the PDF would print more than {} {:?} pages ({count}); shrink the pattern (--scale), pack it on sheets (--sheet), or raise the cap (--max-pages)",
            options.max_pages, options.page
        ),
    }
}

/// Most pixels of a texture printed on the PDF (100 megapixels, as for photos): its
/// samples go into the PDF as 3 bytes a pixel, uncompressed, 300 MB at most.
pub const MAX_TEXTURE_PIXELS: u64 = 100_000_000;

/// Writes the texture as an image XObject of 8-bit RGB samples (PNG or JPEG decoded;
/// uncompressed, which keeps the writer free of an encoder).
///
/// # Errors
/// An image that cannot be read, or of more than [`MAX_TEXTURE_PIXELS`] (its size is read
/// from its header before anything is decoded).
fn embed_texture(pdf: &mut Pdf, id: Ref, texture: &crate::PatternTexture) -> Result<(), PatternError> {
    use sheetform_geometry::short_number;
    let bad = |e: String| PatternError::Option {
        option: "texture",
        message: format!("cannot be printed on the PDF: {e}"),
    };
    let reader = || {
        image::ImageReader::new(std::io::Cursor::new(&texture.bytes))
            .with_guessed_format()
            .map_err(|e| bad(e.to_string()))
    };
    let (w, h) = reader()?.into_dimensions().map_err(|e| bad(e.to_string()))?;
    let pixels = u64::from(w) * u64::from(h);
    if pixels > MAX_TEXTURE_PIXELS {
        return Err(bad(format!(
            "the image is {w} × {h} pixels ({} megapixels), more than the {} megapixels a texture may have; use a smaller image",
            short_number(pixels as f64 / 1e6),
            short_number(MAX_TEXTURE_PIXELS as f64 / 1e6)
        )));
    }
    let mut reader = reader()?;
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(w);
    limits.max_image_height = Some(h);
    reader.limits(limits);
    let rgb = reader.decode().map_err(|e| bad(e.to_string()))?.to_rgb8();
    let (w, h) = rgb.dimensions();
    let mut xobject = pdf.image_xobject(id, rgb.as_raw());
    xobject.width(w as i32);
    xobject.height(h as i32);
    xobject.color_space().device_rgb();
    xobject.bits_per_component(8);
    Ok(())
}

/// Room around a page's printable area in which marks are still drawn (mm): a line just
/// outside the area shows the edge of its stroke (and of a mitred corner) inside it.
const STROKE_PAD_MM: f64 = 2.0;

/// Something a page draws, in drawing order: the texture under each piece, the cut
/// lines, the folds and the labels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Mark {
    /// The texture clipped to piece `n`.
    Texture(u32),
    /// The segment from point `segment` of cut loop `ring` (numbered over
    /// [`Pattern::cut_loops`]) to the next point.
    Cut {
        /// The loop.
        ring: u32,
        /// The segment's first point.
        segment: u32,
    },
    /// Fold `n` of [`Pattern::folds`].
    Fold(u32),
    /// Label `n` of [`Pattern::labels`].
    Label(u32),
}

/// The marks of a part of the pattern (a sheet, or the whole) in an R-tree of their
/// bounds, so that each page looks only at what it shows: a page's content stream then
/// holds its share of the drawing, not all of it.
/// Half the width and height (mm) of the box a label's text takes on the page, turned
/// with it: the text as printed (Helvetica at 1.4 times the label's height, 0.55 of the
/// size a character).
fn label_half_extent(label: &Label) -> (f64, f64) {
    let size = 1.4 * label.height_mm;
    let (w, h) = (0.5 * 0.55 * size * ascii(&label.text).len() as f64, 0.5 * size);
    let (s, c) = label.angle_radians.sin_cos();
    (c.abs() * w + s.abs() * h, s.abs() * w + c.abs() * h)
}

struct PartIndex<'a> {
    rings: Vec<&'a [Vec2]>,
    folds: Vec<&'a Fold>,
    labels: Vec<&'a Label>,
    tree: RTree<GeomWithData<Rectangle<[f64; 2]>, Mark>>,
}

impl<'a> PartIndex<'a> {
    /// The marks of `pattern`, with the pieces' textures when `texture`.
    fn new(pattern: &'a Pattern, texture: bool) -> Self {
        let rings: Vec<&[Vec2]> = pattern.cut_loops().map(|l| l.as_slice()).collect();
        let folds: Vec<&Fold> = pattern.folds().collect();
        let labels: Vec<&Label> = pattern.labels().collect();
        let mut entries = Vec::new();
        // Marks with a coordinate that is not a number are nowhere on any page.
        let mut add = |lo: Vec2, hi: Vec2, mark: Mark| {
            if lo.iter().chain(hi.iter()).all(|x| x.is_finite()) {
                entries.push(GeomWithData::new(
                    Rectangle::from_corners([lo.x, lo.y], [hi.x, hi.y]),
                    mark,
                ));
            }
        };
        if texture {
            for (n, piece) in pattern.pieces.iter().enumerate() {
                let (lo, hi) = piece.bounds();
                add(lo, hi, Mark::Texture(n as u32));
            }
        }
        for (ring, points) in rings.iter().enumerate() {
            for (segment, &a) in points.iter().enumerate() {
                let b = points[(segment + 1) % points.len()];
                add(
                    a.inf(&b),
                    a.sup(&b),
                    Mark::Cut {
                        ring: ring as u32,
                        segment: segment as u32,
                    },
                );
            }
        }
        for (n, f) in folds.iter().enumerate() {
            add(f.a.inf(&f.b), f.a.sup(&f.b), Mark::Fold(n as u32));
        }
        for (n, label) in labels.iter().enumerate() {
            // Within a circle of (characters + 2) text heights of the anchor, turned any
            // way (no Helvetica glyph is wider than its height).
            let height = label.height_mm * 1.4;
            let reach = Vec2::repeat((ascii(&label.text).len() as f64 + 2.0) * height);
            add(label.position - reach, label.position + reach, Mark::Label(n as u32));
        }
        Self {
            rings,
            folds,
            labels,
            tree: RTree::bulk_load(entries),
        }
    }

    /// The marks whose bounds meet `[lo, hi]`, in drawing order.
    fn marks_in(&self, lo: Vec2, hi: Vec2) -> Vec<Mark> {
        let mut marks: Vec<Mark> = self
            .tree
            .locate_in_envelope_intersecting(&AABB::from_corners([lo.x, lo.y], [hi.x, hi.y]))
            .map(|e| e.data)
            .collect();
        marks.sort_unstable();
        marks
    }

    /// Whether any line, label or (when drawn) sheet outline of `pattern` (the part
    /// indexed) falls in the window `[lo, hi]` (pattern millimetres).
    fn window_shows(&self, pattern: &Pattern, lo: Vec2, hi: Vec2, sheet_outlines: bool) -> bool {
        let inside = |p: Vec2| p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y;
        let corners = [lo, Vec2::new(hi.x, lo.y), hi, Vec2::new(lo.x, hi.y)];
        let crosses = |a: Vec2, b: Vec2| {
            inside(a)
                || inside(b)
                || (0..4).any(|k| sheetform_geometry::segments_meet(a, b, corners[k], corners[(k + 1) % 4]))
        };
        self.tree
            .locate_in_envelope_intersecting(&AABB::from_corners([lo.x, lo.y], [hi.x, hi.y]))
            .any(|e| match e.data {
                Mark::Texture(_) => false,
                Mark::Cut { ring, segment } => {
                    let l = self.rings[ring as usize];
                    let i = segment as usize;
                    crosses(l[i], l[(i + 1) % l.len()])
                }
                Mark::Fold(n) => crosses(self.folds[n as usize].a, self.folds[n as usize].b),
                Mark::Label(n) => inside(self.labels[n as usize].position),
            })
            || pattern.sheets.iter().filter(|_| sheet_outlines).any(|(corner, size)| {
                let q = [
                    *corner,
                    corner + Vec2::new(size.x, 0.0),
                    corner + size,
                    corner + Vec2::new(0.0, size.y),
                ];
                (0..4).any(|k| crosses(q[k], q[(k + 1) % 4]))
            })
    }
}

/// Some segments of a closed ring (`segments`: first points, increasing) as open paths,
/// each run of consecutive segments one path (a run through the ring's last point goes
/// on into its first), to stroke.
fn trace_segments(content: &mut Content, ring: &[Vec2], segments: &[u32], to_page: &impl Fn(Vec2) -> (f32, f32)) {
    let n = ring.len();
    // Runs as (first segment, count).
    let mut runs: Vec<(usize, usize)> = Vec::new();
    for &s in segments {
        let s = s as usize;
        match runs.last_mut() {
            Some((first, count)) if *first + *count == s => *count += 1,
            _ => runs.push((s, 1)),
        }
    }
    if runs.len() > 1 {
        let (first, count) = runs[runs.len() - 1];
        if first + count == n && runs[0].0 == 0 {
            runs[0] = (first, count + runs[0].1);
            runs.pop();
        }
    }
    for (first, count) in runs {
        for k in 0..=count {
            let (x, y) = to_page(ring[(first + k) % n]);
            if k == 0 {
                content.move_to(x, y);
            } else {
                content.line_to(x, y);
            }
        }
    }
}

/// A closed ring as a path (page points from `to_page`), to stroke or clip.
fn trace_ring(content: &mut Content, ring: &[Vec2], to_page: &impl Fn(Vec2) -> (f32, f32)) {
    for (i, p) in ring.iter().enumerate() {
        let (x, y) = to_page(*p);
        if i == 0 {
            content.move_to(x, y);
        } else {
            content.line_to(x, y);
        }
    }
    content.close_path();
}

/// A straight stroke between two page points given in millimetres.
fn line(content: &mut Content, x0: f64, y0: f64, x1: f64, y1: f64) {
    content.move_to((x0 * PT) as f32, (y0 * PT) as f32);
    content.line_to((x1 * PT) as f32, (y1 * PT) as f32);
    content.stroke();
}

/// Labels in the built-in Helvetica: keep printable ASCII.
fn ascii(text: &str) -> String {
    text.chars()
        .map(|c| if c.is_ascii_graphic() || c == ' ' { c } else { '?' })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rectangle(w: f64, h: f64) -> Pattern {
        Pattern {
            pieces: vec![crate::PatternPiece {
                name: "rectangle".into(),
                mesh_pieces: vec![],
                cut: vec![vec![
                    Vec2::new(0.0, 0.0),
                    Vec2::new(w, 0.0),
                    Vec2::new(w, h),
                    Vec2::new(0.0, h),
                ]],
                folds: vec![],
                labels: vec![],
                sheet: 0,
                placement: Default::default(),
            }],
            ..Default::default()
        }
    }

    /// The first cut path's points (in points) from the uncompressed content stream.
    fn cut_points(pdf: &[u8]) -> Vec<(f64, f64)> {
        let text = String::from_utf8_lossy(pdf);
        let start = text.find("0.85 0 0 RG").expect("cut colour set");
        let mut out = Vec::new();
        for line in text[start..].lines().skip(1) {
            let p: Vec<&str> = line.split_whitespace().collect();
            match p.as_slice() {
                [x, y, "m"] | [x, y, "l"] => out.push((x.parse().unwrap(), y.parse().unwrap())),
                ["h"] => break,
                _ => {}
            }
        }
        out
    }

    #[test]
    fn prints_at_true_size() {
        let pdf = pdf_tiled(&rectangle(100.0, 50.0), &PdfOptions::default()).unwrap();
        assert_eq!((pdf.rows, pdf.columns), (1, 1));
        let p = cut_points(&pdf.bytes);
        let mm = |a: (f64, f64), b: (f64, f64)| ((a.0 - b.0).hypot(a.1 - b.1)) / PT;
        assert!((mm(p[0], p[1]) - 100.0).abs() < 0.1, "{}", mm(p[0], p[1]));
        assert!((mm(p[1], p[2]) - 50.0).abs() < 0.1, "{}", mm(p[1], p[2]));
    }

    #[test]
    fn large_patterns_are_tiled_with_overlap() {
        let o = PdfOptions::default();
        let pdf = pdf_tiled(&rectangle(500.0, 300.0), &o).unwrap();
        let (pw, ph) = o.page.millimetres();
        let (aw, ah) = (pw - 2.0 * o.margin_mm, ph - 2.0 * o.margin_mm - 12.0);
        // Enough tiles to cover the pattern with the overlap, and no more.
        assert!(pdf.columns as f64 * (aw - o.overlap_mm) + o.overlap_mm >= 500.0);
        assert!((pdf.columns - 1) as f64 * (aw - o.overlap_mm) + o.overlap_mm < 500.0);
        assert!(pdf.rows as f64 * (ah - o.overlap_mm) + o.overlap_mm >= 300.0);
        assert!(pdf_tiled(&rectangle(10.0, 10.0), &PdfOptions { margin_mm: 150.0, ..o }).is_err());
    }

    /// The pages' content streams (text between `stream` and `endstream`).
    fn page_streams(pdf: &[u8]) -> Vec<String> {
        let text = String::from_utf8_lossy(pdf);
        text.split("\nstream\n")
            .skip(1)
            .map(|s| s.split("\nendstream").next().unwrap_or_default().to_string())
            .collect()
    }

    /// Operators `op` in a content stream.
    fn count(stream: &str, op: &str) -> usize {
        stream
            .lines()
            .filter(|l| l.split_whitespace().last() == Some(op))
            .count()
    }

    /// Issue 19: every page streamed the whole drawing (desk.json at `--scale 8`: 319
    /// pages of 12 KB each, 3.8 MB). A strip of 3 m with 600 fold guides and 30 labels
    /// across 17 pages: each page holds the folds and labels near it; every one is on
    /// some page.
    #[test]
    fn each_page_streams_only_the_marks_it_shows() {
        let mut pattern = rectangle(3000.0, 100.0);
        let piece = &mut pattern.pieces[0];
        for i in 0..600 {
            let x = 2.5 + 5.0 * i as f64;
            piece.folds.push(Fold {
                a: Vec2::new(x, 0.0),
                b: Vec2::new(x, 100.0),
                style: FoldStyle::Guide,
                angle_degrees: 0.0,
            });
        }
        for i in 0..30 {
            piece.labels.push(Label {
                position: Vec2::new(50.0 + 100.0 * i as f64, 50.0),
                text: format!("L{i}"),
                height_mm: 4.0,
                angle_radians: 0.0,
                kind: crate::LabelKind::Seam,
            });
        }
        let pdf = pdf_tiled(&pattern, &PdfOptions::default()).unwrap();
        assert_eq!(pdf.page_count, 17);
        let streams = page_streams(&pdf.bytes);
        assert_eq!(streams.len(), 17);
        // A page shows 186 mm (+ 2 mm each side): 38 guides, 2 or 3 labels, and the
        // strokes of its frame.
        for s in &streams {
            assert!(count(s, "m") < 70, "{} moves", count(s, "m"));
            assert!(count(s, "Tj") <= 4 + 1, "{} texts", count(s, "Tj"));
        }
        // Every guide on some page, every label on exactly one (issue 34: a label near a
        // tile's edge was cut there, part on each page).
        let folds: usize = streams.iter().map(|s| count(s, "m")).sum();
        assert!(folds > 600 + 17 * 8, "{folds}");
        let labels: usize = streams.iter().map(|s| count(s, "Tj") - 1).sum();
        assert_eq!(labels, 30);
        for i in 0..30 {
            let shown = format!("(L{i}) Tj");
            assert_eq!(streams.iter().filter(|s| s.contains(&shown)).count(), 1, "L{i}");
        }
    }

    /// Issue 34: a label across the edge between two tiles is printed whole on one of
    /// them, not clipped at the printable area; one entirely inside a tile stays there.
    #[test]
    fn a_label_across_a_tile_edge_is_printed_whole_on_one_tile() {
        let o = PdfOptions::default();
        let (aw, _) = o.printable_area();
        let mut pattern = rectangle(500.0, 100.0);
        // The pattern's tiles start at its left edge less half the spare width: a label
        // across the first tile's right edge.
        let pdf = pdf_tiled(&pattern, &o).unwrap();
        let spare = pdf.columns as f64 * (aw - o.overlap_mm) + o.overlap_mm - 500.0;
        let edge = aw - 0.5 * spare;
        pattern.pieces[0].labels.push(Label {
            position: Vec2::new(edge, 50.0),
            text: "ACROSS-THE-EDGE".into(),
            height_mm: 4.0,
            angle_radians: 0.0,
            kind: crate::LabelKind::Piece,
        });
        let pdf = pdf_tiled(&pattern, &o).unwrap();
        let streams = page_streams(&pdf.bytes);
        let pages: Vec<&String> = streams.iter().filter(|s| s.contains("(ACROSS-THE-EDGE) Tj")).collect();
        assert_eq!(pages.len(), 1);
        // Drawn after the clip is restored: after the page's last `Q`.
        let page = pages[0];
        assert!(
            page.rfind("(ACROSS-THE-EDGE) Tj") > page.rfind("\nQ\n").or(page.rfind(" Q")),
            "{page}"
        );
    }

    /// A cut line across pages is drawn on each page as the runs of its segments that
    /// meet the page (a ring of 4 000 points over 4 × 3 pages): no page draws all of it,
    /// every segment is drawn.
    #[test]
    fn a_cut_line_across_pages_is_drawn_in_runs_where_it_shows() {
        let mut pattern = rectangle(1.0, 1.0);
        pattern.pieces[0].cut = vec![(0..4000)
            .map(|i| {
                let a = std::f64::consts::TAU * i as f64 / 4000.0;
                Vec2::new(300.0 * a.cos(), 300.0 * a.sin())
            })
            .collect()];
        let pdf = pdf_tiled(&pattern, &PdfOptions::default()).unwrap();
        assert!(pdf.page_count >= 9, "{}", pdf.page_count);
        let streams = page_streams(&pdf.bytes);
        let mut drawn = 0;
        for s in &streams {
            let lines = count(s, "l");
            assert!(lines < 2000, "{lines}");
            drawn += lines;
        }
        assert!(drawn >= 4000, "{drawn}");
    }

    /// A PNG of `width × height` pixels: its header (and an empty image).
    fn png_header(width: u32, height: u32) -> Vec<u8> {
        fn crc(bytes: &[u8]) -> u32 {
            let mut c = 0xffff_ffffu32;
            for &b in bytes {
                c ^= u32::from(b);
                for _ in 0..8 {
                    c = if c & 1 == 1 { 0xedb8_8320 ^ (c >> 1) } else { c >> 1 };
                }
            }
            !c
        }
        let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
        let mut chunk = |kind: &[u8], data: &[u8]| {
            png.extend((data.len() as u32).to_be_bytes());
            let body = [kind, data].concat();
            png.extend(&body);
            png.extend(crc(&body).to_be_bytes());
        };
        let mut header = width.to_be_bytes().to_vec();
        header.extend(height.to_be_bytes());
        header.extend([8, 0, 0, 0, 0]);
        chunk(b"IHDR", &header);
        chunk(b"IDAT", &[]);
        chunk(b"IEND", &[]);
        png
    }

    /// Issue 19: a pattern scaled by 1e300 needs a saturated 2^64 − 1 tiles, and the
    /// error said "(18446744073709551615 or more)" pages; past a million it says so.
    #[test]
    fn the_page_cap_error_counts_in_words_people_read() {
        let e = pdf_tiled(&rectangle(1e300, 1e300), &PdfOptions::default())
            .unwrap_err()
            .to_string();
        assert!(e.contains("more than 100 A4 pages (over a million)"), "{e}");
        assert!(!e.contains("18446744073709551615"), "{e}");
        // A count within reach is stated.
        let e = pdf_tiled(&rectangle(20_000.0, 20_000.0), &PdfOptions::default())
            .unwrap_err()
            .to_string();
        assert!(e.contains(" or more)"), "{e}");
    }

    /// Issue 19: the texture was decoded with no limit on its size (and turned into 3
    /// bytes a pixel). Its size is read from the header first: over 100 megapixels it is
    /// refused, before any pixel is decoded.
    #[test]
    fn a_texture_over_the_pixel_cap_is_refused_before_it_is_decoded() {
        let mut pattern = rectangle(100.0, 50.0);
        pattern.texture = Some(crate::PatternTexture {
            bytes: png_header(20_000, 10_000),
            mime_type: "image/png".into(),
            origin: Vec2::zeros(),
            size: Vec2::new(100.0, 50.0),
        });
        let e = pdf_tiled(&pattern, &PdfOptions::default()).unwrap_err().to_string();
        assert!(
            e.contains("20000 × 10000 pixels (200 megapixels)") && e.contains("100 megapixels"),
            "{e}"
        );
        // A small texture is printed.
        let mut image = Vec::new();
        image::DynamicImage::new_rgb8(4, 3)
            .write_to(&mut std::io::Cursor::new(&mut image), image::ImageFormat::Png)
            .unwrap();
        pattern.texture.as_mut().unwrap().bytes = image;
        let pdf = pdf_tiled(&pattern, &PdfOptions::default()).unwrap();
        assert!(String::from_utf8_lossy(&pdf.bytes).contains("/Im1"));
    }
}
