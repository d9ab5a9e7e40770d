//! Rendered outputs: the pattern files every command makes, and writing a run's files
//! and report into a directory.

use crate::report::{PatternReport, Report};
use sheetform_io::write_atomic;
use sheetform_mesh::SheetMesh;
use sheetform_pattern::{
    dxf_bytes, pattern_from_mesh, pdf_tiled, svg_bytes, DxfUnit, FoldStyle, PageSize, PatternOptions, PdfOptions,
    SheetOptions, TabOptions,
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
        }
    }
}

/// `pattern.svg`, `pattern.dxf` and `pattern.pdf` of a mesh (only the SVG for a
/// preview), all from one [`sheetform_pattern::Pattern`], and the report of it.
pub(crate) fn pattern_files(
    mesh: &SheetMesh,
    title: &str,
    options: &PatternOutputOptions,
    outputs: OutputSet,
) -> Result<(RenderedFiles, PatternReport), PipelineError> {
    let pattern = pattern_from_mesh(
        mesh,
        &PatternOptions {
            scale: options.scale,
            min_fold_angle_degrees: options.min_fold_angle_degrees,
            seam_labels: options.seam_labels,
            tabs: options.tabs,
            sheet: options.sheet,
            ..Default::default()
        },
    )?;
    let all = outputs == OutputSet::All;
    let pdf = if all {
        Some(pdf_tiled(
            &pattern,
            &PdfOptions {
                page: options.page,
                ..Default::default()
            },
        )?)
    } else {
        None
    };
    let (lo, hi) = pattern.bounds();
    let report = PatternReport {
        scale: options.scale,
        width_mm: hi.x - lo.x,
        height_mm: hi.y - lo.y,
        page: options.page,
        tile_rows: pdf.as_ref().map_or(0, |p| p.rows),
        tile_columns: pdf.as_ref().map_or(0, |p| p.columns),
        page_count: pdf.as_ref().map_or(0, |p| p.page_count),
        piece_count: pattern.pieces.len(),
        sheet_count: pattern.sheets.len(),
        seam_count: pattern.seam_count,
        mountain_fold_count: pattern.folds().filter(|f| f.style == FoldStyle::Mountain).count(),
        valley_fold_count: pattern.folds().filter(|f| f.style == FoldStyle::Valley).count(),
        tabs: options.tabs.map(|_| pattern.tabs),
        label_count: pattern.labels().count(),
        label_shrunk_count: pattern.labels_shrunk,
        label_dropped_count: pattern.labels_dropped,
    };
    let mut files = vec![(
        "pattern.svg".to_string(),
        svg_bytes(&pattern, &format!("{title}: flat pattern"), 10.0),
    )];
    if let Some(pdf) = pdf {
        files.push(("pattern.dxf".to_string(), dxf_bytes(&pattern, options.dxf_unit)?));
        files.push(("pattern.pdf".to_string(), pdf.bytes));
        // One cutter file per sheet when packed.
        if pattern.sheets.len() > 1 || options.sheet.is_some() {
            for sheet in 0..pattern.sheets.len() {
                let one = pattern.sheet_pattern(sheet);
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

/// Writes rendered files and the report into `dir` (created if missing), each file
/// atomically; subdirectories named in file names are created.
///
/// # Errors
/// The directory cannot be created, or a write fails.
pub fn write_outputs(dir: &Path, files: &[(String, Vec<u8>)], report: &Report) -> Result<(), PipelineError> {
    if dir.exists() && !dir.is_dir() {
        return Err(PipelineError::OutputDirectory {
            path: dir.display().to_string(),
            message: "exists and is not a directory".into(),
        });
    }
    std::fs::create_dir_all(dir).map_err(|e| PipelineError::OutputDirectory {
        path: dir.display().to_string(),
        message: e.to_string(),
    })?;
    for (name, bytes) in files {
        let path = dir.join(name);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent).map_err(|e| PipelineError::OutputDirectory {
                path: parent.display().to_string(),
                message: e.to_string(),
            })?;
        }
        write_atomic(&path, bytes)?;
    }
    let json = serde_json::to_vec_pretty(report).expect("report serialises");
    write_atomic(&dir.join("report.json"), &json)?;
    Ok(())
}
