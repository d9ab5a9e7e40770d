//! The pipelines every front end calls.

use crate::report::{
    AngleDefects, ChartReport, FfdReport, FfdStepReport, MouldReport, PatternReport, PhotoReport, RegionReport,
    RegressionEntry, Report, ScanFitReport, SegmentationReport, SlitReport, StripReport, SymmetrizationReport, Timings,
};
use base64::Engine as _;
use sheetform_bend::{bend, BendError, BendModel, BendScene, BentSheet};
use sheetform_ffd::{run_design_with_progress, FfdDesign, FfdError, FfdScene, ModelSource, SolverMethod};
use sheetform_flatten::Chart;
use sheetform_flatten::{
    arap, cut_into_charts, distortion, exact_unfold, lscm, ArapOptions, ChartOptions, ChartSet, Distortion,
    FlattenError, UnfoldOptions,
};
use sheetform_io::glb_bytes_projected;
use sheetform_io::{colour_ramp, glb_vertex_colours, ply_vertex_colours, read_mesh, MeshReadError};
use sheetform_io::{glb_bytes, obj_string, stl_bytes, write_atomic, IoError, Texture};
use sheetform_mesh::{
    developability_error, developability_summary, isometry_error, mesh_topology, vertex_developability, LengthUnit,
    MeshTopology, Piece, PieceKind, Ruling, SheetMesh, TriangleMesh, VertexDevelopability,
};
use sheetform_pattern::{
    arrange_in_rows, dxf_bytes, pattern_from_mesh, pdf_tiled, point_bounds, rotated, smallest_bounding_rotation,
    svg_bytes, DxfUnit, FoldStyle, PageSize, PatternError, PatternOptions, PdfOptions, SheetOptions, TabOptions,
};
use sheetform_photo::{
    annotation_from_svg, overlay_png, overlay_svg, reconstruct, svg_image_reference, AngleSummary, CurveNetwork,
    PatchSurface, PhotoAnnotation, PhotoError, PhotoReconstruction,
};
use sheetform_slit::{build_mould, slit_mesh, solve_design, SlitDesign, SlitError, SlitModel, SlitScene};
use std::path::Path;

type Vec2 = nalgebra::Vector2<f64>;
use std::time::Instant;
use thiserror::Error;

/// Why a pipeline stopped.
#[derive(Debug, Error)]
pub enum PipelineError {
    /// The input file could not be read.
    #[error("cannot read {path}: {source}")]
    Read {
        /// The file.
        path: String,
        /// The OS error.
        source: std::io::Error,
    },
    /// The bend model is invalid or cannot be built.
    #[error(transparent)]
    Bend(#[from] BendError),
    /// Writing the outputs failed.
    #[error(transparent)]
    Io(#[from] IoError),
    /// A mesh file cannot be read.
    #[error(transparent)]
    MeshRead(#[from] MeshReadError),
    /// A mesh cannot be flattened.
    #[error(transparent)]
    Flatten(#[from] FlattenError),
    /// A command-line option is out of range.
    #[error("option `{option}`: {message}")]
    Option {
        /// The option.
        option: &'static str,
        /// What is wrong.
        message: String,
    },
    /// The slit-sheet model is invalid or cannot be built.
    #[error(transparent)]
    Slit(#[from] SlitError),
    /// The FFD scene is invalid or the restoration failed.
    #[error(transparent)]
    Ffd(#[from] FfdError),
    /// The pattern files cannot be made.
    #[error(transparent)]
    Pattern(#[from] PatternError),
    /// The photo annotation is invalid or cannot be reconstructed.
    #[error(transparent)]
    Photo(#[from] PhotoError),
    /// The texture is not a PNG or JPEG image.
    #[error("texture {path}: not a PNG or JPEG image")]
    Texture {
        /// The file.
        path: String,
    },
    /// The output directory cannot be used.
    #[error("output directory {path}: {message}")]
    OutputDirectory {
        /// The directory.
        path: String,
        /// What is wrong.
        message: String,
    },
}

/// Rendered output files: `(file name relative to the output directory, bytes)`.
pub type RenderedFiles = Vec<(String, Vec<u8>)>;

/// The report's `outputs`: the rendered files' names and `report.json`.
fn output_names(files: &[(String, Vec<u8>)]) -> Vec<String> {
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

/// `pattern.svg`, `pattern.dxf` and `pattern.pdf` of a mesh, all from one
/// [`sheetform_pattern::Pattern`], and the report of it.
fn pattern_files(
    mesh: &SheetMesh,
    title: &str,
    options: &PatternOutputOptions,
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
    let pdf = pdf_tiled(
        &pattern,
        &PdfOptions {
            page: options.page,
            ..Default::default()
        },
    )?;
    let (lo, hi) = pattern.bounds();
    let report = PatternReport {
        scale: options.scale,
        width_mm: hi.x - lo.x,
        height_mm: hi.y - lo.y,
        page: format!("{:?}", options.page),
        tile_rows: pdf.rows,
        tile_columns: pdf.columns,
        piece_count: pattern.pieces.len(),
        sheet_count: pattern.sheets.len(),
        seam_count: pattern.seam_count,
        mountain_fold_count: pattern.folds().filter(|f| f.style == FoldStyle::Mountain).count(),
        valley_fold_count: pattern.folds().filter(|f| f.style == FoldStyle::Valley).count(),
        tabs: options.tabs.map(|_| pattern.tabs),
    };
    let mut files = vec![
        (
            "pattern.svg".to_string(),
            svg_bytes(&pattern, &format!("{title}: flat pattern"), 10.0),
        ),
        ("pattern.dxf".to_string(), dxf_bytes(&pattern, options.dxf_unit)?),
        ("pattern.pdf".to_string(), pdf.bytes),
    ];
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
    Ok((files, report))
}

/// Knobs of `sheetform bend`.
#[derive(Debug, Clone, Default)]
pub struct BendRunOptions {
    /// How the pattern is written.
    pub pattern: PatternOutputOptions,
    /// Write this many frames of the isometric deformation from flat to bent.
    pub animate_frames: usize,
    /// Input path, recorded in the report.
    pub input: Option<String>,
    /// Directory that relative paths in the scene (the texture) are relative to.
    pub base_dir: Option<std::path::PathBuf>,
}

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
}

/// Runs system A on a scene's JSON text and renders every output in memory.
///
/// `progress(stage, fraction)` is called as the run advances.
///
/// # Errors
/// [`PipelineError::Bend`] for invalid scenes and inadmissible shapes (the error carries
/// where), nothing else.
pub fn run_bend(
    scene_text: &str,
    options: &BendRunOptions,
    progress: &mut dyn FnMut(&str, f64),
) -> Result<BendRun, PipelineError> {
    let start = Instant::now();
    progress("reading scene", 0.0);
    let scene = BendScene::from_json(scene_text)?;
    let model = BendModel::from_scene(&scene)?;
    let parsed = Instant::now();
    progress("bending", 0.1);
    let sheet = bend(&model)?;
    let solved = Instant::now();
    progress("exporting", 0.5);
    let name = model.name.clone().unwrap_or_else(|| "sheet".into());
    let texture_bytes = match &model.texture {
        Some(relative) => {
            let path = options.base_dir.clone().unwrap_or_default().join(relative);
            Some(std::fs::read(&path).map_err(|source| PipelineError::Read {
                path: path.display().to_string(),
                source,
            })?)
        }
        None => None,
    };
    let texture = match &texture_bytes {
        Some(bytes) => Some(Texture::from_bytes(bytes).ok_or_else(|| PipelineError::Texture {
            path: model.texture.clone().unwrap_or_default(),
        })?),
        None => None,
    };
    let mut files: Vec<(String, Vec<u8>)> = vec![
        ("model.obj".into(), obj_string(&sheet.mesh, &name).into_bytes()),
        ("model.glb".into(), glb_bytes(&sheet.mesh, &name, texture)),
        ("model.stl".into(), stl_bytes(&sheet.mesh)),
    ];
    let (pattern, pattern_report) = pattern_files(&sheet.mesh, &name, &options.pattern)?;
    files.extend(pattern);
    let frames = options.animate_frames;
    for i in 0..frames {
        let t = if frames == 1 {
            1.0
        } else {
            i as f64 / (frames - 1) as f64
        };
        let frame = sheet.frame(&model, t)?;
        files.push((
            format!("frames/frame-{i:04}.obj"),
            obj_string(&frame, &format!("{name} t={t:.4}")).into_bytes(),
        ));
        progress("animating", 0.5 + 0.5 * (i + 1) as f64 / frames as f64);
    }
    let exported = Instant::now();
    let mut report = bend_report(&model, &sheet, options.input.clone(), &files);
    report.pattern = Some(pattern_report);
    report.timings = Timings::from_stages(start, parsed, solved, exported);
    progress("done", 1.0);
    Ok(BendRun {
        model,
        sheet,
        files,
        report,
    })
}

/// Knobs of `sheetform slit`.
#[derive(Debug, Clone, Default)]
pub struct SlitRunOptions {
    /// How the pattern is written.
    pub pattern: PatternOutputOptions,
    /// Input path, recorded in the report.
    pub input: Option<String>,
    /// Directory that relative paths in the scene (the scan) are relative to.
    pub base_dir: Option<std::path::PathBuf>,
}

/// A finished slit run.
#[derive(Debug)]
pub struct SlitRun {
    /// The validated model.
    pub model: SlitModel,
    /// The solved design.
    pub design: SlitDesign,
    /// The full symmetric sheet.
    pub mesh: SheetMesh,
    /// Rendered outputs `(file name, bytes)`, not yet written.
    pub files: RenderedFiles,
    /// The report.
    pub report: Report,
}

/// Runs system B on a scene's JSON text: solve the strips, build the full sheet and its
/// pattern, the mould, and the report.
///
/// # Errors
/// [`PipelineError::Slit`] for invalid scenes (naming the field) and impossible moulds.
pub fn run_slit(scene_text: &str, options: &SlitRunOptions) -> Result<SlitRun, PipelineError> {
    let start = Instant::now();
    let scene = SlitScene::from_json(scene_text)?;
    let model = SlitModel::from_scene(&scene, options.base_dir.as_deref())?;
    let parsed = Instant::now();
    let design = solve_design(&model);
    let mesh = slit_mesh(&model, &design);
    let mould = if model.mould.enabled {
        Some(build_mould(&model, &design)?)
    } else {
        None
    };
    let solved = Instant::now();
    let name = model.name.clone().unwrap_or_else(|| "slit sheet".into());
    let mut files: RenderedFiles = vec![
        ("model.obj".into(), obj_string(&mesh, &name).into_bytes()),
        ("model.glb".into(), glb_bytes(&mesh, &name, None)),
        ("model.stl".into(), stl_bytes(&mesh)),
    ];
    let (pattern, pattern_report) = pattern_files(&mesh, &name, &options.pattern)?;
    files.extend(pattern);
    let mm = model.unit.millimetres();
    let mould_report = mould.as_ref().map(|m| {
        let solid = SheetMesh {
            positions: m.positions.clone(),
            flat: vec![Vec2::zeros(); m.positions.len()],
            triangles: m.triangles.clone(),
            face_pieces: vec![0; m.triangles.len()],
            pieces: vec![Piece {
                name: "mould".into(),
                kind: PieceKind::Planar,
            }],
            rulings: vec![],
            smooth_edges: vec![],
            unit: model.unit,
        };
        files.push(("mould.stl".into(), stl_bytes(&solid)));
        MouldReport {
            face_count: m.triangles.len(),
            volume_mm3: m.volume() * mm * mm * mm,
            watertight: m.is_watertight(),
        }
    });
    let exported = Instant::now();
    let mut report = sheet_mesh_report("slit", options.input.clone(), &mesh);
    report.pattern = Some(pattern_report);
    report.slit = Some(SlitReport {
        solve_mode: format!("{:?}", model.solver.mode).to_lowercase(),
        gap_handling: format!("{:?}", model.solver.gap).to_lowercase(),
        subdivision_count: design.level,
        normalised_error: design.normalised_error,
        gap_max_mm: design.gap * mm,
        converged: design.strips.iter().all(|s| s.converged),
        strips: design
            .strips
            .iter()
            .map(|s| StripReport {
                strip: s.strip,
                quad_count: s.quads,
                iterations: s.iterations,
                initial_penalty: s.initial_penalty,
                penalty: s.penalty.total,
                penalty_terms: s.penalty,
                gap_mm: s.gap * mm,
                normalised_error: s.normalised_error,
                converged: s.converged,
                time_ms: s.time_ms,
            })
            .collect(),
        mould: mould_report,
        scan_fit: design.scan_fit(&model).map(|f| ScanFitReport {
            scanned_point_count: f.scanned_point_count,
            fitted_point_count: f.fitted_point_count,
            distance_mean_mm: f.distance_mean * mm,
            distance_rms_mm: f.distance_rms * mm,
            distance_max_mm: f.distance_max * mm,
        }),
    });
    report.timings = Timings::from_stages(start, parsed, solved, exported);
    report.outputs = output_names(&files);
    Ok(SlitRun {
        model,
        design,
        mesh,
        files,
        report,
    })
}

/// Developability colour map (the paper's Fig. 4): a logarithmic scale from `tolerance`
/// (blue: developable) to `top` (red; at least 10 × the tolerance), so that typical
/// defects show next to a few large ones (cone points).
fn defect_colours(defects: &[f64], tolerance: f64, top: f64) -> Vec<[f32; 3]> {
    let span = (top.max(10.0 * tolerance) / tolerance).ln();
    defects
        .iter()
        .map(|g| colour_ramp((g.abs().max(tolerance) / tolerance).ln() / span))
        .collect()
}

/// Angle-defect figures of a mesh, lengths converted to millimetres by `mm` per unit.
fn angle_defects(
    mesh: &TriangleMesh,
    topology: &MeshTopology,
    tolerance: f64,
    mm: f64,
) -> (AngleDefects, VertexDevelopability) {
    let vertices = vertex_developability(mesh, topology);
    let s = developability_summary(mesh, topology, &vertices, tolerance);
    (
        AngleDefects {
            interior_vertex_count: s.interior_vertex_count,
            angle_defect_max_rad: s.angle_defect_max_rad,
            angle_defect_mean_rad: s.angle_defect_mean_rad,
            angle_defect_rms_rad: s.angle_defect_rms_rad,
            vertices_over_tolerance: s.vertices_over_tolerance,
            tolerance_rad: s.tolerance_rad,
            gaussian_curvature_max_per_mm2: s.gaussian_curvature_max_per_length2 / (mm * mm),
            developability_d: s.developability_d,
            developability_g_rad2: s.developability_g,
        },
        vertices,
    )
}

/// The report fields every command that makes a [`SheetMesh`] shares: unit, counts, the
/// isometry error of its flat pattern, angle defects, areas (mm, mm²), pieces.
fn sheet_mesh_report(command: &str, input: Option<String>, mesh: &SheetMesh) -> Report {
    let mm = mesh.unit.millimetres();
    let iso = isometry_error(mesh);
    let triangle_mesh = mesh.to_triangle_mesh();
    let topology = mesh_topology(&triangle_mesh);
    let mut report = Report::new(command, input);
    report.model_unit = mesh.unit.symbol().into();
    report.vertex_count = mesh.vertex_count();
    report.face_count = mesh.triangles.len();
    report.isometry_error_max_relative = Some(iso.max_relative);
    report.isometry_error_mean_relative = Some(iso.mean_relative);
    report.angle_defects = Some(angle_defects(&triangle_mesh, &topology, DEFAULT_ANGLE_TOLERANCE, mm).0);
    report.flat_area_mm2 = Some(mesh.flat_area() * mm * mm);
    report.area_mm2 = mesh.area() * mm * mm;
    report.piece_count = Some(mesh.pieces.len());
    report
}

fn bend_report(model: &BendModel, sheet: &BentSheet, input: Option<String>, files: &[(String, Vec<u8>)]) -> Report {
    let mm = model.unit.millimetres();
    let mesh = &sheet.mesh;
    let mut report = sheet_mesh_report("bend", input, mesh);
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
    report
}

/// The report of a shape refused as inadmissible (no mesh is made).
pub fn inadmissible_report(error: &BendError, unit_mm: f64, input: Option<String>) -> Option<Report> {
    let BendError::Inadmissible(detail) = error else {
        return None;
    };
    let mut report = Report::new("bend", input);
    report.status = "inadmissible".into();
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

/// Default tolerance (radians) under which an angle defect counts as zero: 1e-4 rad
/// (0.006°) is far below anything a sheet material can show, and above the rounding of
/// mesh files written with 6–7 significant digits (whose exactly developable meshes show
/// defects of ~1e-5). `--tolerance` sets another.
pub const DEFAULT_ANGLE_TOLERANCE: f64 = 1e-4;

/// Knobs of `sheetform check`.
#[derive(Debug, Clone)]
pub struct CheckOptions {
    /// Merge vertices closer than this (model units); `None`: no welding.
    pub weld: Option<f64>,
    /// Angle defects up to this (radians) count as developable.
    pub tolerance: f64,
    /// Length unit of the file.
    pub unit: LengthUnit,
}

impl Default for CheckOptions {
    fn default() -> Self {
        Self {
            weld: None,
            tolerance: DEFAULT_ANGLE_TOLERANCE,
            unit: LengthUnit::Mm,
        }
    }
}

/// A finished check: the mesh, its per-vertex figures, the files and the report.
#[derive(Debug)]
pub struct CheckRun {
    /// The mesh as read (and welded).
    pub mesh: TriangleMesh,
    /// Its topology.
    pub topology: MeshTopology,
    /// Per-vertex angle defects and curvature.
    pub vertices: VertexDevelopability,
    /// Rendered outputs `(file name, bytes)`.
    pub files: Vec<(String, Vec<u8>)>,
    /// The report.
    pub report: Report,
}

/// Reads a mesh file and, if asked, welds vertices closer than `weld` (model units);
/// returns the mesh and the number of vertices merged.
fn read_input_mesh(path: &Path, weld: Option<f64>) -> Result<(TriangleMesh, Option<usize>), PipelineError> {
    if let Some(w) = weld {
        if !(w.is_finite() && w >= 0.0) {
            return Err(PipelineError::Option {
                option: "--weld",
                message: format!("must be a non-negative distance, got {w}"),
            });
        }
    }
    let mut mesh = read_mesh(path)?;
    let welded = weld.map(|tolerance| mesh.weld(tolerance));
    Ok((mesh, welded))
}

/// Measures the developability of any triangle mesh file (OBJ, PLY, STL, OFF): topology
/// (non-manifold edges and vertices, degenerate faces, orientability, boundary loops),
/// angle defects, Gaussian curvature, `D[M]` and `G[X]` (Wang & Tang 2004), and the
/// isometry error of the flattening stored in the file's `vt`; renders a colour map of
/// |angle defect| (PLY with vertex colours and GLB).
///
/// # Errors
/// The file cannot be read or is malformed (the message names the line).
pub fn run_check(path: &Path, options: &CheckOptions) -> Result<CheckRun, PipelineError> {
    let start = Instant::now();
    let (mesh, welded) = read_input_mesh(path, options.weld)?;
    let parsed = Instant::now();
    let mm = options.unit.millimetres();
    let topology = mesh_topology(&mesh);
    let (defects, vertices) = angle_defects(&mesh, &topology, options.tolerance, mm);
    let stored = mesh.corner_uvs.as_ref().map(|uv| stored_flattening_error(&mesh, uv));
    let solved = Instant::now();
    let colours = defect_colours(&vertices.angle_defect, options.tolerance, defects.angle_defect_max_rad);
    let name = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "mesh".into());
    let files = vec![
        (
            "developability.ply".to_string(),
            ply_vertex_colours(&mesh, &colours, &vertices.angle_defect, "angle_defect").into_bytes(),
        ),
        (
            "developability.glb".to_string(),
            glb_vertex_colours(&mesh, &colours, mm / 1000.0, &name),
        ),
    ];
    let exported = Instant::now();
    let mut report = Report::new("check", Some(path.display().to_string()));
    report.model_unit = options.unit.symbol().into();
    report.status = if topology.is_clean() && defects.vertices_over_tolerance == 0 {
        "developable"
    } else {
        "not developable"
    }
    .into();
    report.vertex_count = mesh.positions.len();
    report.face_count = mesh.triangles.len();
    report.isometry_error_max_relative = stored.map(|s| s.0);
    report.isometry_error_mean_relative = stored.map(|s| s.1);
    report.flat_area_mm2 = stored.map(|s| s.2 * mm * mm);
    report.area_mm2 = (0..mesh.triangles.len()).map(|f| mesh.face_area(f)).sum::<f64>() * mm * mm;
    report.angle_defects = Some(defects);
    report.topology = Some(topology.clone());
    report.welded_vertex_count = welded;
    report.outputs = output_names(&files);
    report.timings = Timings::from_stages(start, parsed, solved, exported);
    Ok(CheckRun {
        mesh,
        topology,
        vertices,
        files,
        report,
    })
}

/// How `flatten` lays a mesh out in the plane.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FlattenMethod {
    /// Exact unfolding from the edge lengths (developable meshes; least-squares layout of
    /// the edge lengths otherwise).
    #[default]
    Exact,
    /// Least-squares conformal maps (nearly developable meshes: keeps angles, spreads the
    /// area error).
    Lscm,
    /// As-rigid-as-possible (nearly developable meshes: balances length and angle error),
    /// started from LSCM.
    Arap,
}

/// When `flatten` cuts the mesh into charts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ChartMode {
    /// When the mesh is not a single disk (closed, several pieces, handles, holes) or
    /// has user seams.
    #[default]
    Auto,
    /// Always (a disk is still cut along sharp creases and split where it would distort).
    Always,
    /// Never (a mesh that is not a disk is refused).
    Never,
}

/// Knobs of `sheetform flatten`.
#[derive(Debug, Clone, Default)]
pub struct FlattenOptions {
    /// Layout method (for a mesh flattened whole; charts use exact unfolding).
    pub method: FlattenMethod,
    /// When to cut into charts.
    pub charts: ChartMode,
    /// How to cut into charts.
    pub chart_options: ChartOptions,
    /// How the pattern is written.
    pub pattern: PatternOutputOptions,
    /// Merge vertices closer than this (model units) first.
    pub weld: Option<f64>,
    /// Length unit of the file.
    pub unit: LengthUnit,
}

/// A finished flattening.
#[derive(Debug)]
pub struct FlattenRun {
    /// The mesh with its pattern.
    pub sheet: SheetMesh,
    /// Distortion and overlaps.
    pub distortion: Distortion,
    /// Rendered outputs.
    pub files: Vec<(String, Vec<u8>)>,
    /// The report.
    pub report: Report,
}

/// Flattens a developable (or nearly developable) disk-like mesh by exact unfolding from
/// its edge lengths (see [`sheetform_flatten::exact_unfold`]) and renders the pattern.
///
/// # Errors
/// Unreadable files; meshes that cannot be unfolded (closed, non-manifold, …) with the
/// reason.
pub fn run_flatten(path: &Path, options: &FlattenOptions) -> Result<FlattenRun, PipelineError> {
    let start = Instant::now();
    let (mesh, welded) = read_input_mesh(path, options.weld)?;
    let parsed = Instant::now();
    let topology = mesh_topology(&mesh);
    let disk = topology.component_count == 1 && topology.boundary_loop_count == 1 && topology.euler_characteristic == 1;
    let use_charts = match options.charts {
        ChartMode::Always => true,
        ChartMode::Never => false,
        ChartMode::Auto => !disk || !mesh.seam_edges.is_empty(),
    };
    let mm = options.unit.millimetres();
    let name = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "mesh".into());
    let mut report = Report::new("flatten", Some(path.display().to_string()));
    let (sheet, solved) = if use_charts {
        let set = cut_into_charts(&mesh, &options.chart_options)?;
        let solved = Instant::now();
        // Room between charts for glue tabs (model units).
        let tab_room = options
            .pattern
            .tabs
            .map_or(0.0, |t| 2.5 * t.width_mm / (mm * options.pattern.scale));
        let sheet = sheet_from_charts(&mesh, &set, &name, None, options.unit, tab_room);
        report.segmentation = Some(SegmentationReport {
            chart_count: set.charts.len(),
            initial_chart_count: set.initial_chart_count,
            split_count: set.split_count,
            seam_edge_count: set.seam_edge_count,
            user_seam_edge_count: mesh.seam_edges.len(),
            crease_angle_degrees: options.chart_options.crease_angle_degrees,
            max_edge_distortion_relative: options.chart_options.max_edge_distortion,
        });
        report.charts = set
            .charts
            .iter()
            .enumerate()
            .map(|(c, chart)| chart_report(&sheet.pieces[c].name, "exact", chart.faces.len(), &chart.distortion))
            .collect();
        let iterations = set.charts.iter().map(|c| c.solver.iterations).sum();
        report.solver = Some(sheetform_solve::SolverInfo {
            iterations,
            cost: set.charts.iter().map(|c| c.solver.cost).sum(),
            initial_cost: set.charts.iter().map(|c| c.solver.initial_cost).sum(),
            gradient_norm: set.charts.iter().map(|c| c.solver.gradient_norm).fold(0.0, f64::max),
            converged: set.charts.iter().all(|c| c.solver.converged),
        });
        (sheet, solved)
    } else {
        let unfolding = match options.method {
            FlattenMethod::Exact => exact_unfold(&mesh, &UnfoldOptions::default())?,
            FlattenMethod::Lscm => lscm(&mesh)?,
            FlattenMethod::Arap => arap(&mesh, &ArapOptions::default())?,
        };
        let solved = Instant::now();
        let sheet = SheetMesh {
            positions: mesh.positions.clone(),
            flat: unfolding.flat.clone(),
            triangles: mesh.triangles.clone(),
            face_pieces: vec![0; mesh.triangles.len()],
            pieces: vec![Piece {
                name: name.clone(),
                kind: PieceKind::Chart,
            }],
            rulings: vec![],
            smooth_edges: vec![],
            unit: options.unit,
        };
        report.solver = Some(unfolding.solver);
        (sheet, solved)
    };
    // Distortion and overlaps over the whole pattern (charts against each other too);
    // a mesh flattened whole is its own single chart.
    let d = distortion(&sheet.to_triangle_mesh(), &sheet.flat);
    if !use_charts {
        let method = format!("{:?}", options.method).to_lowercase();
        report.charts = vec![chart_report(&name, &method, mesh.triangles.len(), &d)];
    }
    let mut files = vec![
        ("model.obj".to_string(), obj_string(&sheet, &name).into_bytes()),
        ("model.glb".to_string(), glb_bytes(&sheet, &name, None)),
    ];
    let (pattern, pattern_report) = pattern_files(&sheet, &name, &options.pattern)?;
    files.extend(pattern);
    let exported = Instant::now();
    report.status = if d.is_overlap_free() { "ok" } else { "overlapping" }.into();
    report.model_unit = options.unit.symbol().into();
    report.vertex_count = mesh.positions.len();
    report.face_count = mesh.triangles.len();
    report.isometry_error_max_relative = Some(d.edge_length_max_relative);
    report.isometry_error_mean_relative = Some(d.edge_length_mean_relative);
    report.angle_defects = Some(angle_defects(&mesh, &topology, DEFAULT_ANGLE_TOLERANCE, mm).0);
    report.flat_area_mm2 = Some(sheet.flat_area() * mm * mm);
    report.area_mm2 = sheet.area() * mm * mm;
    report.welded_vertex_count = welded;
    report.pattern = Some(pattern_report);
    report.outputs = output_names(&files);
    report.timings = Timings::from_stages(start, parsed, solved, exported);
    Ok(FlattenRun {
        sheet,
        distortion: d,
        files,
        report,
    })
}

fn chart_report(name: &str, method: &str, face_count: usize, d: &Distortion) -> ChartReport {
    ChartReport {
        name: name.to_string(),
        method: method.to_string(),
        face_count,
        edge_length_max_relative: d.edge_length_max_relative,
        edge_length_mean_relative: d.edge_length_mean_relative,
        area_max_relative: d.area_max_relative,
        area_mean_relative: d.area_mean_relative,
        flipped_face_count: d.flipped_faces.len(),
        boundary_crossing_count: d.boundary_crossings,
    }
}

/// The charts as one [`SheetMesh`]: every chart keeps its own copy of its seam vertices
/// (same 3D position, own flat position), one piece per chart, the charts' flat layouts
/// set side by side in rows (`gap` apart plus `extra_gap`, model units) so that the
/// pattern (and the OBJ `vt`) has no chart over another.
fn sheet_from_charts(
    mesh: &TriangleMesh,
    set: &ChartSet,
    name: &str,
    piece_names: Option<&[String]>,
    unit: LengthUnit,
    extra_gap: f64,
) -> SheetMesh {
    // Each chart turned to its smallest bounding rectangle, landscape.
    let turned: Vec<Vec<Vec2>> = set
        .charts
        .iter()
        .map(|c| {
            let (angle, _) = smallest_bounding_rotation(&c.flat);
            c.flat.iter().map(|&p| rotated(p, angle)).collect()
        })
        .collect();
    let sizes: Vec<(Vec2, Vec2)> = turned
        .iter()
        .map(|flat| {
            let (lo, hi) = point_bounds(flat);
            (lo, hi - lo)
        })
        .collect();
    let area: f64 = sizes.iter().map(|(_, s)| s.x * s.y).sum();
    let gap = 0.02 * area.sqrt() + extra_gap;
    let corners = arrange_in_rows(&sizes.iter().map(|s| s.1).collect::<Vec<_>>(), 1.5 * area.sqrt(), gap);
    let digits = set.charts.len().to_string().len().max(2);
    let mut sheet = SheetMesh {
        positions: Vec::new(),
        flat: Vec::new(),
        triangles: Vec::new(),
        face_pieces: Vec::new(),
        pieces: Vec::new(),
        rulings: vec![],
        smooth_edges: vec![],
        unit,
    };
    for (c, chart) in set.charts.iter().enumerate() {
        let offset = sheet.positions.len() as u32;
        let shift = corners[c] - sizes[c].0;
        sheet
            .positions
            .extend(chart.vertices.iter().map(|&v| mesh.positions[v as usize]));
        sheet.flat.extend(turned[c].iter().map(|p| p + shift));
        sheet
            .triangles
            .extend(chart.triangles.iter().map(|t| t.map(|v| v + offset)));
        sheet
            .face_pieces
            .extend(std::iter::repeat_n(c as u32, chart.triangles.len()));
        sheet.pieces.push(Piece {
            name: piece_names.map_or_else(|| format!("{name}-{:0digits$}", c + 1), |names| names[c].clone()),
            kind: PieceKind::Chart,
        });
    }
    sheet
}

/// `(max, mean)` relative edge-length difference between the 3D faces and the stored
/// per-corner flattening, and the flattening's area.
fn stored_flattening_error(mesh: &TriangleMesh, uv: &[[nalgebra::Vector2<f64>; 3]]) -> (f64, f64, f64) {
    let (mut max, mut sum, mut n, mut area) = (0.0f64, 0.0, 0usize, 0.0);
    for (t, q) in mesh.triangles.iter().zip(uv) {
        let p = t.map(|i| mesh.positions[i as usize]);
        for k in 0..3 {
            let flat = (q[(k + 1) % 3] - q[k]).norm();
            if flat > 0.0 {
                let rel = ((p[(k + 1) % 3] - p[k]).norm() - flat).abs() / flat;
                max = max.max(rel);
                sum += rel;
                n += 1;
            }
        }
        let (a, b) = (q[1] - q[0], q[2] - q[0]);
        area += 0.5 * (a.x * b.y - a.y * b.x).abs();
    }
    (max, if n > 0 { sum / n as f64 } else { 0.0 }, area)
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

/// Knobs of `sheetform ffd`.
#[derive(Debug, Clone, Default)]
pub struct FfdRunOptions {
    /// How the pattern is written.
    pub pattern: PatternOutputOptions,
    /// Input path, recorded in the report.
    pub input: Option<String>,
    /// Directory that a mesh path in the scene is relative to.
    pub base_dir: Option<std::path::PathBuf>,
    /// Overrides the scene's solver (`--solver`).
    pub solver: Option<SolverMethod>,
}

/// A finished FFD run.
#[derive(Debug)]
pub struct FfdRun {
    /// The design: panels, lattice, every deformation step.
    pub design: FfdDesign,
    /// The restored object with each panel's exact flat pattern (pieces = panels).
    pub sheet: SheetMesh,
    /// Rendered outputs `(file name, bytes)`, not yet written.
    pub files: RenderedFiles,
    /// The report.
    pub report: Report,
}

/// Runs system C on a scene's JSON text: build (or read) the panels, embed them in the
/// lattice, apply each deformation and restore developability, then unfold every panel
/// exactly and write the plain and restored meshes, colour maps, the pattern and the
/// report.
///
/// `progress(stage, fraction)` is called as the run goes (fraction in `[0, 1]`, never
/// decreasing): after reading, after each iteration of each restoration (the stage
/// names the deformation, the iteration and the largest angle defect), before the
/// export, and at the end.
///
/// # Errors
/// [`PipelineError::Ffd`] for invalid scenes (naming the field), vertices outside the
/// lattice and solver failures; unreadable mesh files; panels that cannot be unfolded.
pub fn run_ffd(
    scene_text: &str,
    options: &FfdRunOptions,
    progress: &mut dyn FnMut(&str, f64),
) -> Result<FfdRun, PipelineError> {
    let start = Instant::now();
    progress("reading scene", 0.0);
    let mut scene = FfdScene::from_json(scene_text)?;
    if let Some(method) = options.solver {
        scene.solver.method = method;
    }
    let mesh = match &scene.model {
        ModelSource::Procedural(model) => model.build(),
        ModelSource::Mesh(path) => {
            let full = options
                .base_dir
                .as_deref()
                .map_or_else(|| Path::new(path).to_path_buf(), |d| d.join(path));
            read_mesh(&full)?
        }
    };
    let parsed = Instant::now();
    // Restorations take 5 % to 90 % of the bar, in equal shares per deformation.
    let mut shown = 0.05;
    progress("restoring", shown);
    let design = run_design_with_progress(&scene, &mesh, &mut |p| {
        let fraction = 0.05 + 0.85 * (p.deformation as f64 + p.fraction()) / p.deformation_count as f64;
        shown = fraction.max(shown);
        let stage = format!(
            "deformation {}/{}: iteration {}, max defect {:.1e} rad",
            p.deformation + 1,
            p.deformation_count,
            p.iteration,
            p.angle_defect_max_rad
        );
        progress(&stage, shown);
    })?;
    progress("exporting", 0.9);
    let solved = Instant::now();
    let unit = scene.units;
    let mm = unit.millimetres();
    let name = scene.name.clone();
    let assembly = &design.assembly;
    let last = design.steps.last().expect("validated: at least one deformation");
    let restored = assembly.mesh_at(&last.restored);
    let deformed = assembly.mesh_at(&last.deformed);
    // Each panel unfolded exactly (a panel is a disk: its seams are its boundary).
    let panel_names: Vec<String> = assembly.panels.iter().map(|p| p.name.clone()).collect();
    let charts = |positions: &[nalgebra::Vector3<f64>]| -> Result<ChartSet, PipelineError> {
        let mut charts = Vec::with_capacity(assembly.panels.len());
        for (k, panel) in assembly.panels.iter().enumerate() {
            let panel_mesh = assembly.panel_mesh(k, positions);
            let unfolding = exact_unfold(&panel_mesh, &UnfoldOptions::default()).map_err(|e| {
                PipelineError::Ffd(FfdError::Panel {
                    panel: panel.name.clone(),
                    message: format!("cannot be unfolded: {e}"),
                })
            })?;
            let d = distortion(&panel_mesh, &unfolding.flat);
            charts.push(Chart {
                faces: panel.faces.clone(),
                vertices: panel.vertices.clone(),
                triangles: panel_mesh.triangles.clone(),
                flat: unfolding.flat,
                distortion: d,
                solver: unfolding.solver,
            });
        }
        Ok(ChartSet {
            face_chart: assembly.mesh.face_groups.clone(),
            charts,
            seam_edge_count: 0,
            initial_chart_count: assembly.panels.len(),
            split_count: 0,
        })
    };
    let tab_room = options
        .pattern
        .tabs
        .map_or(0.0, |t| 2.5 * t.width_mm / (mm * options.pattern.scale));
    let restored_charts = charts(&last.restored)?;
    let sheet = sheet_from_charts(&restored, &restored_charts, &name, Some(&panel_names), unit, tab_room);
    let deformed_charts = charts(&last.deformed)?;
    let deformed_sheet = sheet_from_charts(&deformed, &deformed_charts, &name, Some(&panel_names), unit, tab_room);
    // Colour maps on one logarithmic scale, from 1e-8 rad (blue) to the largest defect
    // before restoration (red), so the two maps compare directly (the paper's Fig. 4).
    let topology = mesh_topology(&deformed);
    let (before, before_vertices) = angle_defects(&deformed, &topology, FFD_DEFECT_TOLERANCE, mm);
    let (after, after_vertices) = angle_defects(&restored, &topology, FFD_DEFECT_TOLERANCE, mm);
    let top = before.angle_defect_max_rad;
    let colours_before = defect_colours(&before_vertices.angle_defect, FFD_DEFECT_TOLERANCE, top);
    let colours_after = defect_colours(&after_vertices.angle_defect, FFD_DEFECT_TOLERANCE, top);
    let mut files: RenderedFiles = vec![
        ("model.obj".into(), obj_string(&sheet, &name).into_bytes()),
        ("model.glb".into(), glb_bytes(&sheet, &name, None)),
        ("model.stl".into(), stl_bytes(&sheet)),
        (
            "deformed.obj".into(),
            obj_string(&deformed_sheet, &format!("{name} (plain FFD)")).into_bytes(),
        ),
        (
            "deformed.glb".into(),
            glb_bytes(&deformed_sheet, &format!("{name} (plain FFD)"), None),
        ),
        (
            "developability-before.ply".into(),
            ply_vertex_colours(
                &deformed,
                &colours_before,
                &before_vertices.angle_defect,
                "angle_defect",
            )
            .into_bytes(),
        ),
        (
            "developability-before.glb".into(),
            glb_vertex_colours(&deformed, &colours_before, mm / 1000.0, &name),
        ),
        (
            "developability-after.ply".into(),
            ply_vertex_colours(&restored, &colours_after, &after_vertices.angle_defect, "angle_defect").into_bytes(),
        ),
        (
            "developability-after.glb".into(),
            glb_vertex_colours(&restored, &colours_after, mm / 1000.0, &name),
        ),
    ];
    let (pattern, pattern_report) = pattern_files(&sheet, &name, &options.pattern)?;
    files.extend(pattern);
    let exported = Instant::now();
    let mut report = sheet_mesh_report("ffd", options.input.clone(), &sheet);
    report.pattern = Some(pattern_report);
    report.charts = restored_charts
        .charts
        .iter()
        .zip(&panel_names)
        .map(|(c, n)| chart_report(n, "exact", c.faces.len(), &c.distortion))
        .collect();
    // Linked copies must coincide: the largest distance between vertices of one node.
    let node_positions = assembly.node_positions_of(&restored.positions);
    let linked_gap = restored
        .positions
        .iter()
        .zip(&assembly.vertex_node)
        .map(|(p, &n)| (p - node_positions[n as usize]).norm())
        .fold(0.0, f64::max);
    let deformed_distortion = deformed_charts
        .charts
        .iter()
        .map(|c| c.distortion.edge_length_max_relative)
        .fold(0.0, f64::max);
    report.ffd = Some(FfdReport {
        solver: format!("{:?}", scene.solver.method).to_lowercase(),
        bending_weight: scene.solver.bending_weight,
        line_search_memory: scene.solver.line_search_memory,
        panel_count: assembly.panels.len(),
        node_count: assembly.node_count,
        linked_node_count: assembly.linked_node_count(),
        linked_vertex_gap_max_mm: linked_gap * mm,
        linear_embedding: design.linear_embedding,
        embedding_time_ms: design.embedding_time_ms,
        lattice_counts: design.lattice.counts(),
        lattice_degrees: design.lattice.degrees(),
        angle_defects_before: before,
        angle_defects_after: after,
        deformed_pattern_edge_length_max_relative: deformed_distortion,
        steps: design
            .steps
            .iter()
            .map(|s| FfdStepReport {
                name: s.name.clone(),
                solver: s.info.solver.clone(),
                iterations: s.info.iterations,
                converged: s.info.converged,
                bending_weight: s.info.bending_weight,
                bending_fallback_iteration: s.info.bending_fallback_iteration,
                variable_node_count: s.info.variable_node_count,
                constraint_count: s.info.constraint_count,
                developability_g_before_rad2: s.info.developability_g_before,
                developability_g_after_rad2: s.info.developability_g_after,
                angle_defect_max_before_rad: s.info.angle_defect_max_before_rad,
                angle_defect_max_after_rad: s.info.angle_defect_max_after_rad,
                spring_energy_mm2: s.info.spring_energy_after * mm * mm,
                deviation_max_mm: s.deviation_max * mm,
                edge_length_change_max_relative: s.edge_length_change_max_relative,
                edge_length_change_mean_relative: s.edge_length_change_mean_relative,
                fold_angle_max_before_rad: s.fold_angle_max_before,
                fold_angle_max_after_rad: s.fold_angle_max_after,
                time_ms: s.info.time_ms,
            })
            .collect(),
    });
    report.status = if design.steps.iter().all(|s| s.info.converged) {
        "ok"
    } else {
        "not converged"
    }
    .into();
    report.timings = Timings::from_stages(start, parsed, solved, exported);
    report.outputs = output_names(&files);
    progress("done", 1.0);
    Ok(FfdRun {
        design,
        sheet,
        files,
        report,
    })
}

/// Angle defects below this count as developable in the FFD colour maps and `D[M]`
/// (radians; the paper's `λ`).
pub const FFD_DEFECT_TOLERANCE: f64 = 1e-8;

/// Knobs of `sheetform photo`.
#[derive(Debug, Clone, Default)]
pub struct PhotoRunOptions {
    /// How the pattern is written.
    pub pattern: PatternOutputOptions,
    /// Input path, recorded in the report.
    pub input: Option<String>,
    /// Directory that the annotation's image path is relative to.
    pub base_dir: Option<std::path::PathBuf>,
}

/// A finished photo run.
#[derive(Debug)]
pub struct PhotoRun {
    /// The validated annotation.
    pub annotation: PhotoAnnotation,
    /// Everything the method made (network, rulings, pairs, 3D curves, mesh).
    pub reconstruction: PhotoReconstruction,
    /// The model with each patch's flat pattern (pieces = patches).
    pub sheet: SheetMesh,
    /// Rendered outputs `(file name, bytes)`, not yet written.
    pub files: RenderedFiles,
    /// The report.
    pub report: Report,
}

/// Status of a photo reconstruction whose refinement did not reach its bound.
pub const PHOTO_NOT_DEVELOPABLE_STATUS: &str = "not developable";

/// Status of a photo reconstruction in which some curve's depth is not fixed by the
/// drawing (no mirror pair reaches it): the model is written, the shape is a guess.
pub const PHOTO_DEPTH_UNDETERMINED_STATUS: &str = "depth undetermined";

/// Runs system D on an annotation's JSON text: read the photograph, reconstruct
/// (Fondevilla et al.), unfold every patch and write the model (OBJ, GLB with the photo
/// projected onto it, STL), the pattern, the overlay over the photo and the report.
///
/// `progress(stage, fraction)` is called as the run goes.
///
/// # Errors
/// [`PipelineError::Photo`] for invalid annotations (naming the field or curve),
/// [`PipelineError::Read`] / [`PipelineError::Texture`] for a missing, unreadable or
/// mis-sized image, [`PipelineError::Flatten`] if a patch cannot be unfolded.
pub fn run_photo(
    annotation_text: &str,
    options: &PhotoRunOptions,
    progress: &mut dyn FnMut(&str, f64),
) -> Result<PhotoRun, PipelineError> {
    let start = Instant::now();
    progress("reading annotation", 0.0);
    let base_dir = options.base_dir.clone().unwrap_or_default();
    // An SVG drawn over the photo (Inkscape) or the JSON annotation.
    let from_svg = annotation_text.trim_start().starts_with('<');
    let read_image = |relative: &str| -> Result<(std::path::PathBuf, Vec<u8>), PipelineError> {
        let path = base_dir.join(relative);
        let bytes = std::fs::read(&path).map_err(|source| PipelineError::Read {
            path: path.display().to_string(),
            source,
        })?;
        Ok((path, bytes))
    };
    let (annotation, (image_path, image_bytes)) = if from_svg {
        // The drawing names the photo; its pixel size maps the drawing to the image.
        let image = read_image(&svg_image_reference(annotation_text)?)?;
        let size = Texture::from_bytes(&image.1)
            .and_then(|t| t.size())
            .ok_or_else(|| PipelineError::Texture {
                path: image.0.display().to_string(),
            })?;
        (annotation_from_svg(annotation_text, size)?, image)
    } else {
        let annotation = PhotoAnnotation::from_json(annotation_text)?;
        let image = read_image(&annotation.image.path)?;
        (annotation, image)
    };
    let texture = Texture::from_bytes(&image_bytes).ok_or_else(|| PipelineError::Texture {
        path: image_path.display().to_string(),
    })?;
    let size = texture.size().ok_or_else(|| PipelineError::Texture {
        path: image_path.display().to_string(),
    })?;
    if size != (annotation.image.width, annotation.image.height) {
        return Err(PhotoError::field(
            "image",
            format!(
                "{} is {} × {} px, the annotation says {} × {}",
                image_path.display(),
                size.0,
                size.1,
                annotation.image.width,
                annotation.image.height
            ),
        )
        .into());
    }
    let parsed = Instant::now();
    progress("reconstructing", 0.1);
    let reconstruction = reconstruct(&annotation)?;
    progress("unfolding", 0.5);
    let unit = annotation.units;
    let mm = unit.millimetres();
    let name = annotation.name.clone().unwrap_or_else(|| "photo".into());
    let mesh = &reconstruction.mesh;
    // One group per material patch.
    let mut group_of_patch = vec![u32::MAX; reconstruction.patches.len()];
    let mut groups = Vec::new();
    for (p, kind) in mesh.patch_kind.iter().enumerate() {
        if *kind != PatchSurface::Opening && mesh.face_patch.iter().any(|&f| f as usize == p) {
            group_of_patch[p] = groups.len() as u32;
            groups.push(format!("patch-{:02}", groups.len() + 1));
        }
    }
    let model = TriangleMesh {
        positions: mesh.positions.clone(),
        triangles: mesh.triangles.clone(),
        face_groups: mesh.face_patch.iter().map(|&p| group_of_patch[p as usize]).collect(),
        groups: groups.clone(),
        corner_uvs: None,
        seam_edges: vec![],
    };
    let mut charts = Vec::with_capacity(groups.len());
    let mut methods = Vec::with_capacity(groups.len());
    for g in 0..groups.len() as u32 {
        let faces: Vec<u32> = (0..model.triangles.len() as u32)
            .filter(|&f| model.face_groups[f as usize] == g)
            .collect();
        let mut local = std::collections::HashMap::new();
        let mut vertices = Vec::new();
        let triangles: Vec<[u32; 3]> = faces
            .iter()
            .map(|&f| {
                model.triangles[f as usize].map(|v| {
                    *local.entry(v).or_insert_with(|| {
                        vertices.push(v);
                        (vertices.len() - 1) as u32
                    })
                })
            })
            .collect();
        let patch_mesh = TriangleMesh {
            positions: vertices.iter().map(|&v| model.positions[v as usize]).collect(),
            triangles: triangles.clone(),
            face_groups: vec![0; triangles.len()],
            groups: vec![groups[g as usize].clone()],
            corner_uvs: None,
            seam_edges: vec![],
        };
        // Ruled strips unfold exactly; a filled (minimal-surface) patch is only nearly
        // developable: least-squares conformal maps when the exact unfolding fails.
        let (flat, solver, method) = match exact_unfold(&patch_mesh, &UnfoldOptions::default()) {
            Ok(u) => (u.flat, u.solver, "exact"),
            Err(_) => {
                let u = lscm(&patch_mesh)?;
                (u.flat, u.solver, "lscm")
            }
        };
        methods.push(method);
        let d = distortion(&patch_mesh, &flat);
        charts.push(Chart {
            faces,
            vertices,
            triangles,
            flat,
            distortion: d,
            solver,
        });
    }
    let chart_set = ChartSet {
        face_chart: model.face_groups.clone(),
        charts,
        seam_edge_count: 0,
        initial_chart_count: groups.len(),
        split_count: 0,
    };
    let tab_room = options
        .pattern
        .tabs
        .map_or(0.0, |t| 2.5 * t.width_mm / (mm * options.pattern.scale));
    let mut sheet = sheet_from_charts(&model, &chart_set, &name, Some(&groups), unit, tab_room);
    // The strips' rulings are bending guides (the pattern draws rulings as guides, never
    // as mountain or valley folds), the zipper edges between them smooth edges (drawn as
    // neither): each in its chart's numbering of the sheet.
    let mut sheet_vertex = std::collections::HashMap::new();
    let mut offset = 0u32;
    for (c, chart) in chart_set.charts.iter().enumerate() {
        for (k, &v) in chart.vertices.iter().enumerate() {
            sheet_vertex.insert((c as u32, v), offset + k as u32);
        }
        offset += chart.vertices.len() as u32;
    }
    let mut edge_face = std::collections::HashMap::new();
    for (f, t) in mesh.triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            edge_face.insert((a.min(b), a.max(b)), f);
        }
    }
    let sheet_edge = |[a, b]: [u32; 2]| -> Option<(u32, [u32; 2])> {
        let &face = edge_face.get(&(a.min(b), a.max(b)))?;
        let chart = model.face_groups[face];
        Some((
            chart,
            [*sheet_vertex.get(&(chart, a))?, *sheet_vertex.get(&(chart, b))?],
        ))
    };
    for &edge in &mesh.ruling_edges {
        if let Some((chart, [sa, sb])) = sheet_edge(edge) {
            sheet.rulings.push(Ruling {
                vertices: vec![sa, sb],
                piece: chart,
                arc_length: 0.0,
            });
        }
    }
    sheet.smooth_edges = mesh
        .bending_edges
        .iter()
        .filter_map(|&e| sheet_edge(e))
        .map(|(_, e)| e)
        .collect();
    let solved = Instant::now();
    progress("exporting", 0.7);
    // The photo projected onto the model: each vertex's image position.
    let (w, h) = (f64::from(annotation.image.width), f64::from(annotation.image.height));
    let texcoords: Vec<[f32; 2]> = chart_set
        .charts
        .iter()
        .flat_map(|c| c.vertices.iter())
        .map(|&v| {
            let p = mesh.image[v as usize];
            [(p.x / w) as f32, (-p.y / h) as f32]
        })
        .collect();
    let mut files: RenderedFiles = vec![
        ("model.obj".into(), obj_string(&sheet, &name).into_bytes()),
        (
            "model.glb".into(),
            glb_bytes_projected(&sheet, &name, texture, &texcoords),
        ),
        ("model.stl".into(), stl_bytes(&sheet)),
    ];
    let (pattern, pattern_report) = pattern_files(&sheet, &name, &options.pattern)?;
    files.extend(pattern);
    let data_uri = format!(
        "data:{};base64,{}",
        texture.mime_type,
        base64::engine::general_purpose::STANDARD.encode(&image_bytes)
    );
    let overlay = overlay_svg(&annotation, &reconstruction, &data_uri);
    files.push(("overlay.png".into(), overlay_png(&overlay)?));
    files.push(("overlay.svg".into(), overlay.into_bytes()));
    if from_svg {
        // What was read from the drawing, as an annotation file to edit or rerun.
        let mut json = serde_json::to_vec_pretty(&annotation).expect("annotation serialises");
        json.push(b'\n');
        files.push(("annotation.json".into(), json));
    }
    let exported = Instant::now();
    let mut report = sheet_mesh_report("photo", options.input.clone(), &sheet);
    report.pattern = Some(pattern_report);
    report.charts = chart_set
        .charts
        .iter()
        .zip(&groups)
        .zip(&methods)
        .map(|((c, n), m)| chart_report(n, m, c.faces.len(), &c.distortion))
        .collect();
    let r = &reconstruction;
    let linear = AngleSummary::of(&r.ruling_errors_linear);
    let refined = AngleSummary::of(&r.ruling_errors_refined);
    let symmetrized = AngleSummary::of(&r.ruling_errors_final);
    // The bound the report states, checked on the final rulings (after their ends
    // became curve samples, and after the symmetrisation).
    let developable = r.refinement.is_none()
        || r.ruling_errors_final
            .iter()
            .all(|&e| e.sin() <= sheetform_photo::REFINEMENT_BOUND);
    report.photo = Some(PhotoReport {
        control_point_count: r.network.points.len(),
        annotated_control_point_count: CurveNetwork::annotated_control_point_count(&annotation),
        curve_count: r.network.curves.len(),
        segment_count: r.network.segments.len(),
        junction_count: r.network.junction_count,
        occluded_crossing_count: r.network.occluded_crossing_count,
        patch_count: r.patches.iter().filter(|p| !p.opening).count(),
        opening_count: r.patches.iter().filter(|p| p.opening).count(),
        ruled_patch_count: mesh.patch_kind.iter().filter(|k| **k == PatchSurface::Ruled).count(),
        filled_patch_count: mesh.patch_kind.iter().filter(|k| **k == PatchSurface::Filled).count(),
        ruling_count: r.ruling_count(),
        ruling_candidate_count: r.propagation.candidate_count,
        ruling_rejected_count: r.propagation.rejected_count,
        ruling_aligned_count: r.aligned_ruling_count,
        symmetric_pair_count: r.pairs.len(),
        symmetry_plane_normal: [r.plane.normal.x, r.plane.normal.y, r.plane.normal.z],
        developability_error_linear: linear,
        developability_error_refined: annotation.analysis.refine.then_some(refined),
        refinement_iterations: r.refinement.map(|i| i.iterations),
        refinement_converged: r.refinement.map(|i| i.converged),
        refinement_displacement_max_px: r.refinement.map(|i| i.displacement_max),
        refinement_slide_max_px: r.refinement.map(|i| i.slide_max_px),
        refinement_bound: sheetform_photo::REFINEMENT_BOUND,
        developability_error_symmetrized: r.symmetrization.as_ref().map(|_| symmetrized),
        symmetrization: r.symmetrization.as_ref().map(|i| SymmetrizationReport {
            split_segment_count: i.split_segment_count,
            mirrored_segment_count: i.mirrored_segment_count,
            mirrored_strip_count: i.mirrored_strip_count,
            crossing_ruling_count: i.crossing_ruling_count,
            unmatched_curves: i.unmatched_curves.clone(),
            partly_mirrored_curves: i.partly_mirrored_curves.clone(),
            displacement_max_px: i.displacement_max_px,
            abandoned: i.abandoned,
        }),
        depth_sensitivity_max: r.depth_sensitivity.iter().copied().fold(0.0, f64::max),
        depth_sensitivity_bound: sheetform_photo::DEPTH_SENSITIVITY_BOUND,
        depth_undetermined_curves: r.depth_undetermined_curves(),
        reprojection_error_mean_px: r.reprojection_error_px.0,
        reprojection_error_max_px: r.reprojection_error_px.1,
        millimetres_per_pixel: r.unit_per_pixel * mm,
        stage_times: r.times,
    });
    report.ruling_count = Some(r.ruling_count());
    report.developability_error_max_rad = Some(r.ruling_errors_final.iter().copied().fold(0.0, f64::max));
    if !developable {
        report.status = PHOTO_NOT_DEVELOPABLE_STATUS.into();
    }
    if !r.depth_undetermined_curves().is_empty() {
        report.status = PHOTO_DEPTH_UNDETERMINED_STATUS.into();
    }
    report.timings = Timings::from_stages(start, parsed, solved, exported);
    report.outputs = output_names(&files);
    progress("done", 1.0);
    Ok(PhotoRun {
        annotation,
        reconstruction,
        sheet,
        files,
        report,
    })
}
