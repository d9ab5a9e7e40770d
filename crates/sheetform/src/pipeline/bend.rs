//! `sheetform bend`: system A (Bo & Wang).

use crate::report::{Command, RegionReport, RegressionEntry, Report, Status, Timings};
use sheetform_bend::{bend, BendError, BendModel, BendScene, BentSheet};
use sheetform_io::{glb_bytes, obj_string, stl_bytes, Texture};
use sheetform_mesh::developability_error;

use super::context::RunContext;
use super::error::{Outcome, PipelineError};
use super::outputs::{output_names, pattern_files, PatternOutputOptions};
use super::sheet_report::sheet_mesh_report_and_defects;
use std::time::Instant;

/// Knobs of `sheetform bend`.
#[derive(Debug, Clone, Default)]
pub struct BendRunOptions {
    /// How the pattern is written.
    pub pattern: PatternOutputOptions,
    /// Write this many frames of the isometric deformation from flat to bent.
    pub animate_frames: usize,
    /// Input path, recorded in the report.
    pub input: Option<String>,
}

/// Most frames `--animate` may ask for: each is an OBJ of the whole sheet held in memory.
pub const MAX_ANIMATION_FRAMES: usize = 10_000;

/// Most vertices over all animation frames (frames × the sheet's vertices): about 200
/// bytes of OBJ each, so at most about 400 MB of frames held in memory and written.
pub const MAX_ANIMATION_VERTICES: usize = 2_000_000;

/// A finished bend run: the model, the bent sheet, the files to write and the report.
#[derive(Debug)]
pub struct BendRun {
    /// The validated model.
    pub model: BendModel,
    /// The bent sheet.
    pub sheet: BentSheet,
    /// Rendered outputs `(file name, bytes)`, not yet written.
    pub files: Vec<(String, Vec<u8>)>,
    /// The report (its `outputs` lists `files` and `report.json`).
    pub report: Report,
    /// The angle defect `2π − Σθ` at each vertex of `sheet.mesh` (radians; 0 on the
    /// boundary): the developability colour map of a live preview, zero to rounding on
    /// a sheet bent without stretching.
    pub angle_defects_rad: Vec<f64>,
    /// How the run ended (always [`Outcome::Ok`]: an inadmissible shape is the error
    /// [`PipelineError::Inadmissible`], with its report).
    pub outcome: Outcome,
}

/// Runs system A on a scene and renders its outputs in memory (the texture is read
/// through the context's assets).
///
/// # Errors
/// [`PipelineError::Bend`] for invalid scenes; [`PipelineError::Inadmissible`] for shapes
/// that cannot be made, carrying the report that says where; [`PipelineError::Asset`] and
/// [`PipelineError::Image`] for the texture (not a PNG or JPEG that decodes to its end); [`PipelineError::Option`] for too many
/// animation frames; [`PipelineError::Cancelled`].
pub fn run_bend(scene: &BendScene, options: &BendRunOptions, context: &RunContext) -> Result<BendRun, PipelineError> {
    run_bend_bent(scene, None, options, context)
}

/// A scene's model and its sheet as [`sheetform_bend::bend`] bent it.
#[derive(Debug, Clone)]
pub struct BentScene {
    /// The validated model of the scene.
    pub model: BendModel,
    /// The bent sheet.
    pub sheet: BentSheet,
}

/// [`run_bend`] of a scene already bent: `bent` is its model and sheet as
/// [`sheetform_bend::bend`] made them from `scene` (an edit's check,
/// [`super::BendEditResult::bent`]), exported without bending again; `None` bends it.
/// With `bent`, the bend's time was spent by whoever bent it: the report's
/// `timings.solve_ms` is then only the time from reading to exporting (near 0).
///
/// # Errors
/// As [`run_bend`].
pub fn run_bend_bent(
    scene: &BendScene,
    bent: Option<Box<BentScene>>,
    options: &BendRunOptions,
    context: &RunContext,
) -> Result<BendRun, PipelineError> {
    let start = Instant::now();
    if options.animate_frames > MAX_ANIMATION_FRAMES {
        return Err(PipelineError::Option {
            option: "animate",
            message: format!("at most {MAX_ANIMATION_FRAMES} frames (got {})", options.animate_frames),
        });
    }
    context.progress("reading scene", 0.0);
    let (model, sheet) = match bent {
        Some(bent) => {
            let BentScene { model, sheet } = *bent;
            (model, Some(sheet))
        }
        None => (BendModel::from_scene(scene)?, None),
    };
    // The texture is read and checked with the scene, before the solve: decoded to its
    // end when every output is made (a preview of the editor, rendered on every edit,
    // only recognises it).
    let texture_bytes = match &model.texture {
        Some(relative) => Some(context.assets.read(relative, "texture")?),
        None => None,
    };
    let texture = match &texture_bytes {
        Some(bytes) => {
            let problem = |problem| PipelineError::Image {
                field: "texture",
                path: model.texture.clone().unwrap_or_default(),
                what: "the texture",
                problem,
            };
            let texture = if context.renders_all() {
                Texture::decoded(bytes).map(|(texture, _)| texture)
            } else {
                Texture::from_bytes(bytes).ok_or(sheetform_io::ImageError::NotAnImage)
            };
            Some(texture.map_err(problem)?)
        }
        None => None,
    };
    let parsed = Instant::now();
    context.check_cancelled()?;
    context.progress("bending", 0.1);
    let sheet = match sheet {
        Some(sheet) => sheet,
        None => bend(&model).map_err(|error| {
            match inadmissible_report(&error, model.unit.millimetres(), options.input.clone()) {
                Some(report) => PipelineError::Inadmissible {
                    error,
                    report: Box::new(report),
                },
                None => PipelineError::Bend(error),
            }
        })?,
    };
    let solved = Instant::now();
    context.check_cancelled()?;
    context.progress("exporting", 0.5);
    let name = model.name.clone().unwrap_or_else(|| "sheet".into());
    let mut files: Vec<(String, Vec<u8>)> = Vec::new();
    if context.renders_all() {
        let mut obj = obj_string(&sheet.mesh, &name, scene.up_axis);
        if let Some(t) = texture {
            // The OBJ shows the texture too: a material whose map scales the 1:1 `vt`
            // onto the image, and the image beside it.
            let (mtl, image) = textured_material(&sheet.mesh, t);
            obj = format!("mtllib model.mtl\nusemtl sheet\n{obj}");
            files.push(("model.mtl".into(), mtl.into_bytes()));
            files.push(image);
        }
        files.push(("model.obj".into(), obj.into_bytes()));
    }
    files.push((
        "model.glb".into(),
        glb_bytes(&sheet.mesh, &name, texture, scene.up_axis),
    ));
    if context.renders_all() {
        files.push(("model.stl".into(), stl_bytes(&sheet.mesh)));
    }
    let (pattern, pattern_report) = pattern_files(
        &sheet.mesh,
        &name,
        &options.pattern,
        context.outputs,
        texture,
        scene.up_axis,
        0.0,
    )?;
    files.extend(pattern);
    let frames = if context.renders_all() {
        options.animate_frames
    } else {
        0
    };
    let vertices = sheet.mesh.positions.len();
    if frames.saturating_mul(vertices) > MAX_ANIMATION_VERTICES {
        return Err(PipelineError::Option {
            option: "animate",
            message: format!(
                "{frames} frames of {vertices} vertices are over the budget of {MAX_ANIMATION_VERTICES} vertices in all \
                 (at most {} frames of this sheet)",
                MAX_ANIMATION_VERTICES / vertices.max(1)
            ),
        });
    }
    for i in 0..frames {
        context.check_cancelled()?;
        let t = if frames == 1 {
            1.0
        } else {
            i as f64 / (frames - 1) as f64
        };
        let frame = sheet.frame(&model, t)?;
        files.push((
            format!("frames/frame-{i:04}.obj"),
            obj_string(&frame, &format!("{name} t={t:.4}"), scene.up_axis).into_bytes(),
        ));
        context.progress("animating", 0.5 + 0.5 * (i + 1) as f64 / frames as f64);
    }
    let exported = Instant::now();
    let (mut report, angle_defects_rad) = bend_report(&model, &sheet, options.input.clone(), &files);
    report.pattern = Some(pattern_report);
    report.timings = Timings::from_stages(start, parsed, solved, exported);
    context.progress("done", 1.0);
    Ok(BendRun {
        model,
        sheet,
        files,
        report,
        angle_defects_rad,
        outcome: Outcome::Ok,
    })
}

pub(crate) fn bend_report(
    model: &BendModel,
    sheet: &BentSheet,
    input: Option<String>,
    files: &[(String, Vec<u8>)],
) -> (Report, Vec<f64>) {
    let mm = model.unit.millimetres();
    let mesh = &sheet.mesh;
    let (mut report, angle_defects) = sheet_mesh_report_and_defects(Command::Bend, input, mesh);
    report.admissible = Some(true);
    report.ruling_count = Some(sheet.regions.iter().map(|r| r.ruling_count).sum());
    report.developability_error_max_rad = Some(developability_error(mesh).max_radians);
    report.regions = sheet
        .regions
        .iter()
        .map(|r| RegionReport {
            name: r.name.clone(),
            ruling_count: r.ruling_count,
            curve_length_mm: r.curve_length * mm,
            total_fold_rad: r.total_fold_radians,
            max_fold_rad: r.max_fold_radians,
            admissible: r.admissibility.admissible,
            regression_margin_mm: r.admissibility.regression_margin.map(|m| m * mm),
            curve_deviation_mm: r.curve_deviation * mm,
            closure_gap_mm: r.closure_gap.map(|g| g * mm),
        })
        .collect();
    report.outputs = output_names(files);
    (report, angle_defects)
}

/// The report of a shape refused as inadmissible (no mesh is made).
pub fn inadmissible_report(error: &BendError, unit_mm: f64, input: Option<String>) -> Option<Report> {
    let BendError::Inadmissible(detail) = error else {
        return None;
    };
    let mut report = Report::new(Command::Bend, input);
    report.status = Status::Inadmissible;
    report.admissible = Some(false);
    report.regression_entry = Some(RegressionEntry {
        message: detail.message.clone(),
        region: detail.region,
        arc_length_range_mm: detail.arc_length_range.map(|v| v * unit_mm),
        flat_point_mm: detail.flat_point.map(|v| v * unit_mm),
        point_mm: detail.point.map(|p| p.map(|v| v * unit_mm)),
    });
    report.outputs = vec!["report.json".into()];
    Some(report)
}

/// `model.mtl` for a textured sheet and the image file it names. The OBJ's `vt` is the
/// flat pattern at 1:1 (model units), so the map is scaled and offset onto it
/// (`map_Kd -s 1/W 1/H 1 -o −x0/W −y0/H 0`, W × H the pattern's bounding box from
/// (x0, y0)): the image spans the pattern's bounding box, as in the GLB and on the SVG
/// and PDF pattern.
fn textured_material(mesh: &sheetform_mesh::SheetMesh, texture: Texture<'_>) -> (String, (String, Vec<u8>)) {
    let (lo, hi) = mesh.flat_bounds();
    let size = (hi - lo).sup(&nalgebra::Vector2::repeat(f64::MIN_POSITIVE));
    let file = if texture.mime_type == "image/jpeg" {
        "texture.jpg"
    } else {
        "texture.png"
    };
    let mtl = format!(
        "# sheetform: the sheet's printed texture; vt is the flat pattern at 1:1\nnewmtl sheet\nKa 1 1 1\nKd 1 1 1\nKs 0 0 0\nillum 1\nmap_Kd -s {} {} 1 -o {} {} 0 {file}\n",
        1.0 / size.x,
        1.0 / size.y,
        -lo.x / size.x,
        -lo.y / size.y
    );
    (mtl, (file.to_string(), texture.bytes.to_vec()))
}
