//! Rendered outputs: the pattern files every command makes, and writing a run's files
//! and report into a directory.

use crate::report::{PatternReport, Report, REPORT_FORMAT};
use sheetform_io::{Texture, UpAxis};
use sheetform_mesh::SheetMesh;
use sheetform_pattern::{
    dxf_bytes, pack_pieces, pattern_from_mesh, pdf_tiled, smallest_bounding_rotation, svg_bytes, DxfUnit, FoldStyle,
    MaterialAllowance, PageSize, PatternOptions, PatternTexture, PdfOptions, SheetOptions, TabOptions,
    DEFAULT_MAX_PAGES,
};
use std::path::Path;

use super::context::OutputSet;
use super::error::PipelineError;

/// Rendered output files: `(file name relative to the output directory, bytes)`.
pub type RenderedFiles = Vec<(String, Vec<u8>)>;

/// The report's `outputs`: the rendered files' names and `report.json`.
pub(crate) fn output_names(files: &[(String, Vec<u8>)]) -> Vec<String> {
    files
        .iter()
        .map(|f| f.0.clone())
        .chain(std::iter::once("report.json".to_string()))
        .collect()
}

/// How the printable pattern is written (every command that makes one).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PatternOutputOptions {
    /// Scale factor (1 = true size).
    pub scale: f64,
    /// Paper of the tiled PDF.
    pub page: PageSize,
    /// Unit of the DXF coordinates.
    pub dxf_unit: DxfUnit,
    /// Folds below this dihedral angle (degrees) are not drawn.
    pub min_fold_angle_degrees: f64,
    /// Matching IDs on both sides of every seam.
    pub seam_labels: bool,
    /// Glue tabs along seams (`None`: none).
    pub tabs: Option<TabOptions>,
    /// Pack the pieces onto sheets of this size (`None`: keep the layout).
    pub sheet: Option<SheetOptions>,
    /// Most pages the PDF may have (a pattern that needs more is refused).
    pub max_pdf_pages: usize,
    /// Seam allowance, notches, grain lines, kerf, bend allowance.
    pub allowance: MaterialAllowance,
    /// Folds under this angle (degrees) are drawn as bending guides, not folds (`None`:
    /// the command's choice: 10° for the smooth panels of `ffd` and `photo` and the
    /// smooth charts of `flatten`, 0 for nets and for `bend` and `slit`, whose rulings
    /// are the guides).
    pub smooth_bend_degrees: Option<f64>,
}

impl PatternOutputOptions {
    /// These options for pieces glued along their seams (a net, developed pieces, a whole
    /// object from a photograph): `tabs` when no tabs were asked for (nor none), nor a
    /// seam allowance or a sheet thickness, which take the tabs' place.
    pub fn glued_with(self, tabs: Option<TabOptions>) -> Self {
        let mut glued = self;
        if glued.tabs.is_none() && glued.allowance.seam_allowance_mm == 0.0 && glued.allowance.bend.is_none() {
            glued.tabs = tabs;
        }
        glued
    }

    /// The sheets the pieces are packed on: those asked for, except that a sheet the size
    /// of the PDF's paper (`--sheet a4` with the A4 page) is that paper's printable area
    /// (inside the PDF's margins and above its scale bar), so that every sheet prints on
    /// one page at true scale.
    pub fn packing_sheet(&self) -> Option<SheetOptions> {
        let sheet = self.sheet?;
        let (pw, ph) = self.page.millimetres();
        let same = |a: f64, b: f64| (a - b).abs() <= 0.5;
        let paper = (same(sheet.width_mm, pw) && same(sheet.height_mm, ph))
            || (same(sheet.width_mm, ph) && same(sheet.height_mm, pw));
        if !paper {
            return Some(sheet);
        }
        let (w, h) = PdfOptions {
            page: self.page,
            ..Default::default()
        }
        .printable_area();
        let landscape = sheet.width_mm > sheet.height_mm;
        Some(SheetOptions {
            width_mm: if landscape { h } else { w },
            height_mm: if landscape { w } else { h },
            ..sheet
        })
    }

    /// Room to keep between pieces laid side by side (model units, `mm` millimetres per
    /// unit) for what grows outside them on the pattern: glue tabs, seam allowance, kerf.
    pub fn room_between_pieces(&self, mm: f64) -> f64 {
        let tabs = self.tabs.map_or(0.0, |t| 2.5 * t.width_mm);
        let allowance = 2.0 * (self.allowance.seam_allowance_mm + self.allowance.kerf_mm);
        (tabs + allowance) / (mm * self.scale)
    }
}

/// Folds under this angle (degrees) are the bends of smooth panels (`ffd`, `photo`, smooth
/// charts), drawn as guides.
pub const SMOOTH_PANEL_BEND_DEGREES: f64 = 10.0;

/// Gap between pieces packed onto the PDF's pages (mm).
pub(crate) const PAGE_PACKING_GAP_MM: f64 = 4.0;

/// Most pieces for which packing onto pages is tried (each try renders a PDF).
const MAX_PAGE_PACKED_PIECES: usize = 2_000;

/// Sheets made of whole page tiles to pack a pattern's pieces on for printing: one page,
/// and the smallest grids of `c × r` tiles (their overlaps included) that hold the largest
/// piece either way round, with a column or a row more.
fn page_sheets(pattern: &sheetform_pattern::Pattern, pdf: &PdfOptions) -> Vec<SheetOptions> {
    let (aw, ah) = pdf.printable_area();
    let o = pdf.overlap_mm;
    let (sx, sy) = (aw - o, ah - o);
    let gap = PAGE_PACKING_GAP_MM;
    // The widest and the tallest of the pieces, each turned to its smallest bounding
    // rectangle and laid landscape: every piece fits a sheet that holds both.
    let largest = pattern
        .pieces
        .iter()
        .map(|p| {
            let points: Vec<_> = p.cut.iter().flatten().copied().collect();
            let s = smallest_bounding_rotation(&points).1;
            nalgebra::Vector2::new(s.x.max(s.y), s.x.min(s.y))
        })
        .fold(nalgebra::Vector2::<f64>::zeros(), |m, s| m.sup(&s));
    let tiles = |length: f64, step: f64| ((length + 2.0 * gap - o).max(0.0) / step).ceil().max(1.0) as usize;
    let mut grids = vec![(1, 1)];
    for (w, h) in [(largest.x, largest.y), (largest.y, largest.x)] {
        // (The counts saturate for a huge piece, `--scale 1e300`: their product too.)
        let (c, r) = (tiles(w, sx), tiles(h, sy));
        let count = c.saturating_mul(r);
        if count > 1 && count <= 64 {
            grids.extend([(c, r), (c + 1, r), (c, r + 1)]);
        }
    }
    grids.sort_unstable();
    grids.dedup();
    grids
        .into_iter()
        .map(|(c, r)| SheetOptions {
            width_mm: c as f64 * sx + o,
            height_mm: r as f64 * sy + o,
            gap_mm: gap,
        })
        .collect()
}

impl Default for PatternOutputOptions {
    fn default() -> Self {
        Self {
            scale: 1.0,
            page: PageSize::A4,
            dxf_unit: DxfUnit::Mm,
            min_fold_angle_degrees: PatternOptions::default().min_fold_angle_degrees,
            seam_labels: true,
            tabs: None,
            sheet: None,
            max_pdf_pages: DEFAULT_MAX_PAGES,
            allowance: MaterialAllowance::default(),
            smooth_bend_degrees: None,
        }
    }
}

/// `pattern.svg`, `pattern.dxf` and `pattern.pdf` of a mesh (only the SVG for a
/// preview), all from one [`sheetform_pattern::Pattern`], and the report of it; a
/// texture printed on the sheet is printed on the SVG and PDF pieces.
pub(crate) fn pattern_files(
    mesh: &SheetMesh,
    title: &str,
    options: &PatternOutputOptions,
    outputs: OutputSet,
    texture: Option<Texture<'_>>,
    up_axis: UpAxis,
    smooth_bend_degrees: f64,
) -> Result<(RenderedFiles, PatternReport), PipelineError> {
    // Every command's model goes through here before any file is rendered.
    mesh.validate().map_err(PipelineError::InvalidResult)?;
    let mut pattern = pattern_from_mesh(
        mesh,
        &PatternOptions {
            scale: options.scale,
            min_fold_angle_degrees: options.min_fold_angle_degrees,
            seam_labels: options.seam_labels,
            tabs: options.tabs,
            sheet: options.packing_sheet(),
            allowance: options.allowance,
            up_axis,
            smooth_bend_degrees: options.smooth_bend_degrees.unwrap_or(smooth_bend_degrees),
            ..Default::default()
        },
    )?;
    // A texture printed on the sheet is printed on the pattern too: the image spans the
    // flat pattern's bounding box, as in the GLB's texture coordinates.
    if let Some(t) = texture {
        let k = mesh.unit.millimetres() * options.scale;
        let (lo, hi) = mesh.flat_bounds();
        pattern.texture = Some(PatternTexture {
            bytes: t.bytes.to_vec(),
            mime_type: t.mime_type.to_string(),
            origin: lo * k,
            size: (hi - lo) * k,
        });
    }
    let all = outputs == OutputSet::All;
    let pdf = if all {
        let pdf_options = PdfOptions {
            page: options.page,
            max_pages: options.max_pdf_pages,
            ..Default::default()
        };
        let tiled = pdf_tiled(&pattern, &pdf_options);
        // Several pieces and no sheets asked for: the pieces are also packed onto sheets
        // of whole pages (turned to fit, a sheet of one page or of a few tiles for pieces
        // larger than a page); the PDF with the fewest pages is kept.
        let mut best = tiled.map(|t| (t, false));
        if pattern.sheets.is_empty() && !pattern.pieces.is_empty() && pattern.pieces.len() <= MAX_PAGE_PACKED_PIECES {
            for sheet in page_sheets(&pattern, &pdf_options) {
                let mut paged = pattern.clone();
                if pack_pieces(&mut paged, &sheet).is_err() {
                    continue;
                }
                let packed = pdf_tiled(
                    &paged,
                    &PdfOptions {
                        sheet_outlines: false,
                        ..pdf_options
                    },
                );
                if let Ok(p) = packed {
                    if best.as_ref().is_err() || best.as_ref().is_ok_and(|b| p.page_count < b.0.page_count) {
                        best = Ok((p, true));
                    }
                }
            }
        }
        Some(best?)
    } else {
        None
    };
    let (lo, hi) = pattern.bounds();
    let report = PatternReport {
        scale: options.scale,
        width_mm: hi.x - lo.x,
        height_mm: hi.y - lo.y,
        page: options.page,
        tile_rows: pdf.as_ref().map_or(0, |p| p.0.rows),
        tile_columns: pdf.as_ref().map_or(0, |p| p.0.columns),
        page_count: pdf.as_ref().map_or(0, |p| p.0.page_count),
        pieces_packed_on_pages: pdf.as_ref().is_some_and(|p| p.1),
        piece_count: pattern.pieces.len(),
        sheet_count: pattern.sheets.len(),
        seam_count: pattern.seam_count,
        seam_id_missing_count: pattern.seam_count - pattern.seams_labelled_on_both_sides(),
        mountain_fold_count: pattern.folds().filter(|f| f.style == FoldStyle::Mountain).count(),
        valley_fold_count: pattern.folds().filter(|f| f.style == FoldStyle::Valley).count(),
        tabs: options.tabs.map(|_| pattern.tabs),
        seam_allowance_mm: options.allowance.seam_allowance_mm,
        kerf_mm: options.allowance.kerf_mm,
        bend_allowance: options.allowance.bend.map(|bend| {
            let changes = &pattern.bend_flat_changes_mm;
            let (min, max) = changes.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &c| {
                (lo.min(c), hi.max(c))
            });
            crate::report::BendAllowanceReport {
                thickness_mm: bend.thickness_mm,
                inner_radius_mm: bend.inner_radius_mm,
                k_factor: bend.k_factor,
                material_side: bend.material_side,
                bend_count: changes.len(),
                corner_relief_count: pattern.corner_relief_count,
                flat_change_min_mm: if changes.is_empty() { 0.0 } else { min },
                flat_change_max_mm: if changes.is_empty() { 0.0 } else { max },
            }
        }),
        notch_count: pattern.folds().filter(|f| f.style == FoldStyle::Notch).count(),
        grain_line_count: pattern.folds().filter(|f| f.style == FoldStyle::Grain).count() / 5,
        label_count: pattern.labels().count(),
        label_shrunk_count: pattern.labels_shrunk,
        label_dropped_count: pattern.labels_dropped,
    };
    let mut files = vec![(
        "pattern.svg".to_string(),
        svg_bytes(&pattern, &format!("{title}: flat pattern"), 10.0),
    )];
    if let Some((pdf, _)) = pdf {
        files.push(("pattern.dxf".to_string(), dxf_bytes(&pattern, options.dxf_unit)?));
        files.push(("pattern.pdf".to_string(), pdf.bytes));
        // One cutter file per sheet when packed.
        if pattern.sheets.len() > 1 || options.sheet.is_some() {
            for (sheet, one) in pattern.sheet_patterns().into_iter().enumerate() {
                files.push((
                    format!("sheets/sheet-{:02}.svg", sheet + 1),
                    svg_bytes(&one, &format!("{title}: sheet {}", sheet + 1), 0.0),
                ));
                files.push((
                    format!("sheets/sheet-{:02}.dxf", sheet + 1),
                    dxf_bytes(&one, options.dxf_unit)?,
                ));
            }
        }
    }
    Ok((files, report))
}

/// The printable pattern of a mesh that already carries its flat layout (arrays handed
/// over by a binding, [`super::sheet_mesh_from_arrays`]): `pattern.svg`, and with every
/// output `pattern.dxf` and `pattern.pdf` (and one file per sheet when packed), rendered
/// as every command renders them, and the report (command `pattern`: the pattern's
/// figures, the isometry error of the layout against the 3D edges, whether pieces
/// overlap; status `overlapping` when they do, as for `flatten`). Folds under [`SMOOTH_PANEL_BEND_DEGREES`] are drawn as bending guides unless
/// `options.smooth_bend_degrees` says otherwise (as for the smooth charts of `flatten`).
///
/// # Errors
/// [`PipelineError::InvalidResult`] for a mesh that is not valid (a non-finite coordinate,
/// an index out of range), [`PipelineError::Pattern`] when a file cannot be made (a PDF
/// of more pages than allowed), [`PipelineError::Cancelled`].
pub fn run_pattern(
    mesh: &SheetMesh,
    title: &str,
    options: &PatternOutputOptions,
    context: &super::RunContext,
) -> Result<(RenderedFiles, Report, super::Outcome), PipelineError> {
    let start = std::time::Instant::now();
    context.check_cancelled()?;
    mesh.validate().map_err(PipelineError::InvalidResult)?;
    let d = sheetform_flatten::distortion(&mesh.to_triangle_mesh(), &mesh.flat);
    let measured = std::time::Instant::now();
    context.progress("rendering the pattern", 0.1);
    let (files, pattern) = pattern_files(
        mesh,
        title,
        options,
        context.outputs,
        None,
        UpAxis::Y,
        SMOOTH_PANEL_BEND_DEGREES,
    )?;
    let done = std::time::Instant::now();
    let mut report = Report::new(crate::report::Command::Pattern, None);
    report.model_unit = mesh.unit;
    report.vertex_count = mesh.positions.len();
    report.face_count = mesh.triangles.len();
    report.area_mm2 = mesh.area() * mesh.unit.millimetres().powi(2);
    report.flat_area_mm2 = Some(mesh.flat_area() * mesh.unit.millimetres().powi(2));
    report.isometry_error_max_relative = Some(d.edge_length_max_relative);
    report.isometry_error_mean_relative = Some(d.edge_length_mean_relative);
    let outcome = if d.is_overlap_free() {
        super::Outcome::Ok
    } else {
        super::Outcome::Overlapping
    };
    report.status = if d.is_overlap_free() {
        crate::report::Status::Ok
    } else {
        crate::report::Status::Overlapping
    };
    report.pattern = Some(pattern);
    report.outputs = output_names(&files);
    report.timings = crate::report::Timings::from_stages(start, start, measured, done);
    context.progress("done", 1.0);
    Ok((files, report, outcome))
}

/// Writes rendered files and the report into `dir` (created if missing) as one set.
///
/// The set replaces the previous run's as a unit ([`sheetform_io::replace_file_set`]):
/// the previous run's files are those its `report.json` lists in `outputs`; those this
/// run does not write again go (stale `frames/` and `sheets/`, the last good model
/// beside an inadmissible report), nothing else in `dir` is touched, and a failed or
/// killed write leaves the previous set as it was. A directory with a report holds
/// exactly the files it lists.
///
/// # Errors
/// `dir` is not a directory, or a write fails.
pub fn write_outputs(dir: &Path, files: &[(String, Vec<u8>)], report: &Report) -> Result<(), PipelineError> {
    if dir.exists() && !dir.is_dir() {
        return Err(PipelineError::OutputDirectory {
            path: dir.display().to_string(),
            message: "exists and is not a directory".into(),
        });
    }
    let json = serde_json::to_vec_pretty(report).expect("report serialises");
    let set: Vec<(&str, &[u8])> = files
        .iter()
        .map(|(name, bytes)| (name.as_str(), bytes.as_slice()))
        .chain(std::iter::once(("report.json", json.as_slice())))
        .collect();
    sheetform_io::replace_file_set(dir, &set, &previous_outputs(dir))?;
    Ok(())
}

/// The files the previous run wrote into `dir`: its `report.json`'s `outputs`, trusted
/// only when the report is sheetform's (`format` is [`REPORT_FORMAT`]: another tool's
/// `report.json` with an `outputs` list names that tool's files, which are kept) and
/// kept only when they are plain relative paths inside `dir` (a report edited by hand
/// cannot make a run delete anything outside).
fn previous_outputs(dir: &Path) -> Vec<String> {
    let Ok(bytes) = sheetform_io::read_bounded(&dir.join("report.json"), sheetform_io::MAX_SCENE_FILE_BYTES) else {
        return Vec::new();
    };
    let Ok(value) = serde_json::from_slice::<serde_json::Value>(&bytes) else {
        return Vec::new();
    };
    if value.get("format").and_then(|f| f.as_str()) != Some(REPORT_FORMAT) {
        return Vec::new();
    }
    let Some(list) = value.get("outputs").and_then(|o| o.as_array()) else {
        return Vec::new();
    };
    list.iter()
        .filter_map(|n| n.as_str())
        .filter(|n| sheetform_io::is_plain_relative(n))
        .map(str::to_string)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use sheetform_geometry::{Vec2, Vec3};
    use sheetform_mesh::{Piece, PieceKind};

    /// Issue 35: only sheetform's own report names a previous set. Another tool's
    /// `report.json` with an `outputs` list (or one without a format) deletes nothing.
    #[test]
    fn only_sheetforms_report_names_files_to_remove() {
        let root = tempfile::tempdir().unwrap();
        std::fs::write(root.path().join("theirs.csv"), "1,2").unwrap();
        for report in [
            r#"{"outputs": ["theirs.csv"]}"#,
            r#"{"format": "other-tool/2", "outputs": ["theirs.csv"]}"#,
        ] {
            std::fs::write(root.path().join("report.json"), report).unwrap();
            assert!(previous_outputs(root.path()).is_empty(), "{report}");
        }
        let ours = format!(r#"{{"format": "{REPORT_FORMAT}", "outputs": ["theirs.csv", "../x"]}}"#);
        std::fs::write(root.path().join("report.json"), ours).unwrap();
        assert_eq!(previous_outputs(root.path()), vec!["theirs.csv".to_string()]);
    }

    /// Issue 19: no NaN reaches a file. A model with a non-finite coordinate stops
    /// before anything is rendered, naming the vertex.
    #[test]
    fn a_model_with_a_non_finite_coordinate_is_not_rendered() {
        let mut mesh = SheetMesh {
            positions: vec![Vec3::zeros(), Vec3::x(), Vec3::y()],
            flat: vec![Vec2::zeros(), Vec2::x(), Vec2::y()],
            triangles: vec![[0, 1, 2]],
            face_pieces: vec![0],
            pieces: vec![Piece {
                name: "p".into(),
                kind: PieceKind::Planar,
            }],
            ..Default::default()
        };
        let render = |mesh: &SheetMesh| {
            pattern_files(
                mesh,
                "t",
                &PatternOutputOptions::default(),
                OutputSet::All,
                None,
                UpAxis::Z,
                0.0,
            )
        };
        assert!(render(&mesh).is_ok());
        mesh.positions[2].z = f64::NAN;
        let error = render(&mesh).unwrap_err();
        assert_eq!(error.kind(), super::super::ErrorKind::Failed);
        assert!(
            error.to_string().contains("vertex 2 has a non-finite 3D coordinate"),
            "{error}"
        );
    }
}
