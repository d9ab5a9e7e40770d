//! `sheetform`: the command-line front end. Thin: it parses arguments, calls the library
//! pipeline, shows progress and maps errors to exit codes.
//!
//! Exit codes: 0 success, 1 invalid input or I/O error, 2 usage error (from clap),
//! 3 shape not admissible (only `report.json` is written, saying where), 4 flattened
//! pattern overlaps itself (written, flagged in the report), 5 a photo reconstruction
//! out of its tolerances: a ruled patch not developable to the bound, or a curve whose
//! depth the drawing does not fix (written, flagged in the report and on stderr).

use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use sheetform::flatten::ChartOptions;
use sheetform::pattern::{DxfUnit, PageSize, SheetOptions, TabOptions, TabSides};
use sheetform::pipeline::{
    inadmissible_report, run_bend, run_check, run_ffd, run_flatten, run_photo, run_slit, write_outputs, BendRunOptions,
    ChartMode, CheckOptions, FfdRunOptions, FlattenMethod, FlattenOptions, PatternOutputOptions, PhotoRunOptions,
    PipelineError, SlitRunOptions,
};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

// The pipeline allocates and frees arrays of a few hundred KB per run; glibc's malloc
// returns them to the OS each time (page faults), mimalloc keeps them: ~1.5x faster
// bends (docs/benchmarks.md).
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

#[derive(Parser)]
#[command(
    name = "sheetform",
    version,
    about = "Design with developable surfaces: bend a virtual sheet, get the 3D model and the flat pattern to cut"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// No progress bar.
    #[arg(long, short, global = true)]
    quiet: bool,
}

#[derive(Subcommand)]
enum Command {
    /// Bend a sheet with 3D control curves (Bo & Wang): writes model.obj (vt = flat
    /// pattern at 1:1), model.glb, model.stl, pattern.svg and report.json.
    Bend {
        /// Scene file (JSON; schema: `sheetform schema bend`).
        scene: PathBuf,
        /// Output directory (created if missing).
        #[arg(short, long)]
        output: PathBuf,
        /// Also write N frames of the isometric deformation from flat to bent
        /// (frames/frame-0000.obj …).
        #[arg(long, value_name = "N", default_value_t = 0)]
        animate: usize,
        #[command(flatten)]
        pattern: PatternArgs,
    },
    /// Design furniture from one sheet with parallel slits (Tsuruta et al.): solves every
    /// strip, writes the full symmetric model (model.obj with vt = flat sheet at 1:1,
    /// model.glb, model.stl), the cutting pattern (pattern.svg/.dxf/.pdf: outline and
    /// slits to cut, ridge lines to fold or score), mould.stl and report.json.
    Slit {
        /// Scene file (JSON; schema: `sheetform schema slit`).
        scene: PathBuf,
        /// Output directory (created if missing).
        #[arg(short, long)]
        output: PathBuf,
        #[command(flatten)]
        pattern: PatternArgs,
    },
    /// Reconstruct a piecewise-developable object from curves traced over one photograph
    /// (Fondevilla et al.): writes the model (model.obj with one group per patch and vt =
    /// each patch's flat pattern at 1:1, model.glb with the photo projected onto it,
    /// model.stl), the pattern (pattern.svg/.dxf/.pdf), overlay.svg (patches, rulings,
    /// symmetric pairs and the reprojected 3D curves over the photo) and report.json.
    Photo {
        /// Annotation file (JSON; schema: `sheetform schema photo`).
        annotation: PathBuf,
        /// Output directory (created if missing).
        #[arg(short, long)]
        output: PathBuf,
        #[command(flatten)]
        pattern: PatternArgs,
    },
    /// Deform developable panels with a NURBS lattice and restore their developability
    /// (Wang & Tang): writes the restored object (model.obj with one group per panel and
    /// vt = each panel's exact flat pattern at 1:1, model.glb, model.stl), the plain FFD
    /// (deformed.obj/.glb), developability colour maps before/after
    /// (developability-before/after.ply/.glb), the pattern (pattern.svg/.dxf/.pdf) and
    /// report.json.
    Ffd {
        /// Scene file (JSON; schema: `sheetform schema ffd`).
        scene: PathBuf,
        /// Output directory (created if missing).
        #[arg(short, long)]
        output: PathBuf,
        /// Restoration method (default: the scene's, which defaults to `constrained`).
        #[arg(long, value_enum)]
        solver: Option<SolverArg>,
        #[command(flatten)]
        pattern: PatternArgs,
    },
    /// Measure the developability of any triangle mesh (OBJ, PLY, STL, OFF): topology,
    /// angle defects, Gaussian curvature, `D[M]` and `G[X]`, the isometry error of the stored
    /// `vt` flattening. Writes report.json and a colour map (developability.ply/.glb).
    Check {
        /// Mesh file.
        mesh: PathBuf,
        /// Output directory (created if missing).
        #[arg(short, long)]
        output: PathBuf,
        /// Merge vertices closer than this distance (model units) before measuring.
        #[arg(long, value_name = "DISTANCE")]
        weld: Option<f64>,
        /// Angle defects up to this (radians) count as developable.
        #[arg(long, value_name = "RADIANS", default_value_t = sheetform::pipeline::DEFAULT_ANGLE_TOLERANCE)]
        tolerance: f64,
        /// Length unit of the mesh file.
        #[arg(long, value_enum, default_value_t = Unit::Mm)]
        units: Unit,
    },
    /// Flatten a developable (or nearly developable) mesh into its cutting pattern: a
    /// disk-like mesh whole (exact unfolding from its edge lengths, or LSCM / ARAP); a
    /// closed or high-genus mesh, or one with seams (OBJ `l` lines), cut into charts along
    /// sharp creases and split until each flattens without overlap within the distortion
    /// bound. Writes model.obj (vt = the pattern at 1:1), model.glb, pattern.svg/.dxf/.pdf
    /// and report.json (distortion per chart). Exit code 4 when the pattern overlaps
    /// itself (written, see the report).
    Flatten {
        /// Mesh file (OBJ, PLY, STL, OFF).
        mesh: PathBuf,
        /// Layout: `exact` unfolding from the edge lengths; for meshes that are only nearly
        /// developable `lscm` (least-squares conformal maps) or `arap` (as rigid as
        /// possible, started from LSCM).
        #[arg(long, value_enum, default_value_t = Method::Exact)]
        method: Method,
        /// Output directory (created if missing).
        #[arg(short, long)]
        output: PathBuf,
        /// Merge vertices closer than this distance (model units) first.
        #[arg(long, value_name = "DISTANCE")]
        weld: Option<f64>,
        /// Length unit of the mesh file.
        #[arg(long, value_enum, default_value_t = Unit::Mm)]
        units: Unit,
        #[command(flatten)]
        charts: ChartArgs,
        #[command(flatten)]
        pattern: PatternArgs,
    },
    /// Print the JSON Schema of a scene format.
    Schema {
        /// Which format.
        #[arg(value_enum)]
        format: SchemaFormat,
    },
}

/// How the printable pattern (pattern.svg, .dxf, .pdf) is written.
#[derive(clap::Args, Clone, Copy)]
struct PatternArgs {
    /// Scale factor for the pattern (1 = true size).
    #[arg(long, default_value_t = 1.0)]
    scale: f64,
    /// Paper for the tiled PDF.
    #[arg(long, value_enum, default_value_t = Page::A4)]
    page: Page,
    /// Unit of the DXF coordinates.
    #[arg(long, value_enum, default_value_t = PatternUnit::Mm)]
    pattern_units: PatternUnit,
    /// Folds with a smaller dihedral angle (degrees) are not drawn.
    #[arg(long, value_name = "DEGREES", default_value_t = 1.0)]
    min_fold_angle: f64,
    /// Leave out the seam IDs printed on both sides of every seam.
    #[arg(long)]
    no_seam_labels: bool,
    /// Glue tabs along seams: on one side of each seam, or alternating between seams.
    #[arg(long, value_enum, default_value_t = Tabs::None)]
    tabs: Tabs,
    /// Glue tab depth (mm).
    #[arg(long, value_name = "MM", default_value_t = 5.0)]
    tab_width: f64,
    /// Angle of the tabs' slanted sides (degrees; 90 = straight tabs).
    #[arg(long, value_name = "DEGREES", default_value_t = 45.0)]
    tab_angle: f64,
    /// Pack the pieces onto sheets of this size, `WIDTHxHEIGHT` in mm (e.g. 210x297,
    /// or a4 / letter); writes sheets/sheet-NN.svg and .dxf too.
    #[arg(long, value_name = "WxH", value_parser = parse_sheet)]
    sheet: Option<(f64, f64)>,
    /// Gap between packed pieces and from the sheet's edges (mm).
    #[arg(long, value_name = "MM", default_value_t = 5.0)]
    sheet_gap: f64,
}

fn parse_sheet(text: &str) -> Result<(f64, f64), String> {
    match text.to_ascii_lowercase().as_str() {
        "a4" => return Ok((210.0, 297.0)),
        "a3" => return Ok((297.0, 420.0)),
        "letter" => return Ok((215.9, 279.4)),
        _ => {}
    }
    let (w, h) = text
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("`{text}`: expected WIDTHxHEIGHT in mm, e.g. 600x400"))?;
    let number = |s: &str| {
        s.trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite() && *v > 0.0)
            .ok_or_else(|| format!("`{s}` in `{text}` is not a positive number of millimetres"))
    };
    Ok((number(w)?, number(h)?))
}

#[derive(Clone, Copy, PartialEq, clap::ValueEnum)]
enum Tabs {
    None,
    One,
    Alternate,
}

/// How `flatten` cuts a mesh into charts.
#[derive(clap::Args, Clone, Copy)]
struct ChartArgs {
    /// When to cut into charts: `auto` when the mesh is not a disk or has seams.
    #[arg(long, value_enum, default_value_t = Charts::Auto)]
    charts: Charts,
    /// Edges folded by more than this (degrees) become seams between charts.
    #[arg(long, value_name = "DEGREES", default_value_t = 30.0)]
    crease_angle: f64,
    /// Charts that stretch an edge by more than this (relative) are split further.
    #[arg(long, value_name = "RELATIVE", default_value_t = 0.01)]
    max_distortion: f64,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum Charts {
    Auto,
    Always,
    Never,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum Method {
    Exact,
    Lscm,
    Arap,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum Page {
    A4,
    Letter,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum PatternUnit {
    Mm,
    Cm,
    In,
}

impl From<PatternArgs> for PatternOutputOptions {
    fn from(a: PatternArgs) -> Self {
        PatternOutputOptions {
            scale: a.scale,
            page: match a.page {
                Page::A4 => PageSize::A4,
                Page::Letter => PageSize::Letter,
            },
            dxf_unit: match a.pattern_units {
                PatternUnit::Mm => DxfUnit::Mm,
                PatternUnit::Cm => DxfUnit::Cm,
                PatternUnit::In => DxfUnit::In,
            },
            min_fold_angle_degrees: a.min_fold_angle,
            seam_labels: !a.no_seam_labels,
            tabs: (a.tabs != Tabs::None).then_some(TabOptions {
                width_mm: a.tab_width,
                angle_degrees: a.tab_angle,
                sides: if a.tabs == Tabs::Alternate {
                    TabSides::Alternate
                } else {
                    TabSides::One
                },
            }),
            sheet: a.sheet.map(|(w, h)| SheetOptions {
                width_mm: w,
                height_mm: h,
                gap_mm: a.sheet_gap,
            }),
        }
    }
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum Unit {
    Mm,
    Cm,
    M,
    In,
}

impl From<Unit> for sheetform::mesh::LengthUnit {
    fn from(u: Unit) -> Self {
        match u {
            Unit::Mm => Self::Mm,
            Unit::Cm => Self::Cm,
            Unit::M => Self::M,
            Unit::In => Self::In,
        }
    }
}

fn check_command(
    mesh: PathBuf,
    output: PathBuf,
    weld: Option<f64>,
    tolerance: f64,
    units: Unit,
    quiet: bool,
) -> Result<ExitCode, PipelineError> {
    let options = CheckOptions {
        weld,
        tolerance,
        unit: units.into(),
    };
    let run = run_check(&mesh, &options)?;
    write_outputs(&output, &run.files, &run.report)?;
    if !quiet {
        let r = &run.report;
        let d = r.angle_defects.as_ref().expect("check reports angle defects");
        eprintln!(
            "{}: {}; {} vertices, {} faces, max angle defect {:.2e} rad, D[M] = {:.4}{}; wrote {}",
            mesh.display(),
            r.status,
            r.vertex_count,
            r.face_count,
            d.angle_defect_max_rad,
            d.developability_d,
            r.isometry_error_max_relative
                .map(|e| format!(", stored flattening isometry error {e:.1e}"))
                .unwrap_or_default(),
            output.display()
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// The `flatten` arguments that become [`FlattenOptions`].
struct FlattenArgs {
    weld: Option<f64>,
    units: Unit,
    method: Method,
    charts: ChartArgs,
    pattern: PatternArgs,
}

fn flatten_command(mesh: PathBuf, output: PathBuf, args: FlattenArgs, quiet: bool) -> Result<ExitCode, PipelineError> {
    let FlattenArgs {
        weld,
        units,
        method,
        charts,
        pattern,
    } = args;
    let method = match method {
        Method::Exact => FlattenMethod::Exact,
        Method::Lscm => FlattenMethod::Lscm,
        Method::Arap => FlattenMethod::Arap,
    };
    let options = FlattenOptions {
        weld,
        unit: units.into(),
        pattern: pattern.into(),
        method,
        charts: match charts.charts {
            Charts::Auto => ChartMode::Auto,
            Charts::Always => ChartMode::Always,
            Charts::Never => ChartMode::Never,
        },
        chart_options: ChartOptions {
            crease_angle_degrees: charts.crease_angle,
            max_edge_distortion: charts.max_distortion,
            ..Default::default()
        },
    };
    let run = run_flatten(&mesh, &options)?;
    write_outputs(&output, &run.files, &run.report)?;
    let d = &run.distortion;
    if !d.is_overlap_free() {
        eprintln!(
            "sheetform: {}: the pattern overlaps itself ({} flipped faces, {} boundary crossings); written to {}, but it cannot be cut from one sheet as it is",
            mesh.display(),
            d.flipped_faces.len(),
            d.boundary_crossings,
            output.display()
        );
        return Ok(ExitCode::from(4));
    }
    if !quiet {
        eprintln!(
            "{}: flattened {} faces; edge-length error max {:.1e}, mean {:.1e}; area error max {:.1e}; wrote {}",
            mesh.display(),
            run.report.face_count,
            d.edge_length_max_relative,
            d.edge_length_mean_relative,
            d.area_max_relative,
            output.display()
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// `--solver` of `ffd`.
#[derive(Clone, Copy, clap::ValueEnum)]
enum SolverArg {
    /// Constrained Gauss–Newton with exact gradients (defects to 1e-10 rad).
    Constrained,
    /// The paper's penalty method with conjugate gradients.
    Paper,
    /// No restoration (plain FFD).
    None,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum SchemaFormat {
    /// The bend scene.
    Bend,
    /// The slit scene.
    Slit,
    /// The FFD scene.
    Ffd,
    /// The photo annotation.
    Photo,
}

fn progress_bar(quiet: bool) -> Option<ProgressBar> {
    if quiet || !std::io::stderr().is_terminal() {
        return None;
    }
    let bar = ProgressBar::new(1000);
    bar.set_style(
        ProgressStyle::with_template("{spinner} {msg:<16} [{bar:30}] {percent:>3}%")
            .expect("valid template")
            .progress_chars("=> "),
    );
    Some(bar)
}

/// Runs `job` with a progress callback that drives a bar on a terminal (nothing when
/// `quiet` or not a terminal), then clears the bar.
fn with_progress_bar<T>(quiet: bool, job: impl FnOnce(&mut dyn FnMut(&str, f64)) -> T) -> T {
    let bar = progress_bar(quiet);
    let result = job(&mut |stage, fraction| {
        if let Some(b) = &bar {
            // Position first: setting the message may redraw the bar.
            b.set_position((fraction * 1000.0) as u64);
            b.set_message(stage.to_string());
        }
    });
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    result
}

/// The scene file's text, or an error naming it.
fn read_scene(scene: &Path) -> Result<String, PipelineError> {
    std::fs::read_to_string(scene).map_err(|source| PipelineError::Read {
        path: scene.display().to_string(),
        source,
    })
}

fn bend_command(
    scene: PathBuf,
    output: PathBuf,
    animate: usize,
    pattern: PatternArgs,
    quiet: bool,
) -> Result<ExitCode, PipelineError> {
    let text = read_scene(&scene)?;
    let options = BendRunOptions {
        pattern: pattern.into(),
        animate_frames: animate,
        input: Some(scene.display().to_string()),
        base_dir: scene.parent().map(|p| p.to_path_buf()),
    };
    let result = with_progress_bar(quiet, |progress| run_bend(&text, &options, progress));
    match result {
        Ok(run) => {
            write_outputs(&output, &run.files, &run.report)?;
            if !quiet {
                let r = &run.report;
                eprintln!(
                    "bent `{}`: {} rulings, {} faces, isometry error {:.1e}, admissible; wrote {} files to {}",
                    scene.display(),
                    r.ruling_count.unwrap_or(0),
                    r.face_count,
                    r.isometry_error_max_relative.unwrap_or(f64::NAN),
                    r.outputs.len(),
                    output.display()
                );
            }
            Ok(ExitCode::SUCCESS)
        }
        Err(PipelineError::Bend(e)) => {
            let unit = serde_json::from_str::<serde_json::Value>(&text)
                .ok()
                .and_then(|v| v.get("units").and_then(|u| u.as_str()).map(str::to_owned))
                .map(|u| match u.as_str() {
                    "cm" => 10.0,
                    "m" => 1000.0,
                    "in" => 25.4,
                    _ => 1.0,
                })
                .unwrap_or(1.0);
            if let Some(report) = inadmissible_report(&e, unit, Some(scene.display().to_string())) {
                write_outputs(&output, &[], &report)?;
                eprintln!("sheetform: {}: {e}", scene.display());
                eprintln!(
                    "sheetform: no mesh written; {} says where",
                    output.join("report.json").display()
                );
                return Ok(ExitCode::from(3));
            }
            Err(PipelineError::Bend(e))
        }
        Err(e) => Err(e),
    }
}

fn slit_command(scene: PathBuf, output: PathBuf, pattern: PatternArgs, quiet: bool) -> Result<ExitCode, PipelineError> {
    let text = read_scene(&scene)?;
    let options = SlitRunOptions {
        pattern: pattern.into(),
        input: Some(scene.display().to_string()),
        base_dir: scene.parent().map(|p| p.to_path_buf()),
    };
    let run = run_slit(&text, &options)?;
    write_outputs(&output, &run.files, &run.report)?;
    if !quiet {
        let slit = run.report.slit.as_ref().expect("slit report");
        eprintln!(
            "slit `{}`: {} strips, E = {:.1e} (gap {:.2e} mm), {}; wrote {} files to {}",
            scene.display(),
            slit.strips.len(),
            slit.normalised_error,
            slit.gap_max_mm,
            if slit.converged {
                "converged"
            } else {
                "NOT all strips converged"
            },
            run.report.outputs.len(),
            output.display()
        );
    }
    Ok(ExitCode::SUCCESS)
}

fn photo_command(
    annotation: PathBuf,
    output: PathBuf,
    pattern: PatternArgs,
    quiet: bool,
) -> Result<ExitCode, PipelineError> {
    let text = read_scene(&annotation)?;
    let options = PhotoRunOptions {
        pattern: pattern.into(),
        input: Some(annotation.display().to_string()),
        base_dir: annotation.parent().map(|p| p.to_path_buf()),
    };
    let run = with_progress_bar(quiet, |progress| run_photo(&text, &options, progress))?;
    write_outputs(&output, &run.files, &run.report)?;
    let photo = run.report.photo.as_ref().expect("photo report");
    if !quiet {
        let mut refined = photo.developability_error_refined.map_or_else(
            || "not refined".to_string(),
            |a| format!("refined mean {:.2e}° max {:.2e}°", a.mean_deg, a.max_deg),
        );
        if let (Some(s), Some(a)) = (&photo.symmetrization, photo.developability_error_symmetrized) {
            if s.mirrored_segment_count > 0 && !s.abandoned {
                refined += &format!(
                    ", symmetrised ({} segments mirrored) mean {:.2e}° max {:.2e}°",
                    s.mirrored_segment_count, a.mean_deg, a.max_deg
                );
            }
        }
        eprintln!(
            "photo `{}`: {} patches, {} rulings, {} symmetric pairs; developability error mean {:.2}° (linear), {}; {}; wrote {} files to {}",
            annotation.display(),
            photo.patch_count,
            photo.ruling_count,
            photo.symmetric_pair_count,
            photo.developability_error_linear.mean_deg,
            refined,
            run.report.status,
            run.report.outputs.len(),
            output.display()
        );
    }
    if !photo.depth_undetermined_curves.is_empty() {
        eprintln!(
            "sheetform: the depth of {} is not fixed by the drawing (no mirror pair reaches it): mark their mirror \
             relations (`symmetric_curves`, `self_symmetric_curves`)",
            photo
                .depth_undetermined_curves
                .iter()
                .map(|c| format!("`{c}`"))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    Ok(if run.report.status == "ok" {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(5)
    })
}

fn ffd_command(
    scene: PathBuf,
    output: PathBuf,
    solver: Option<SolverArg>,
    pattern: PatternArgs,
    quiet: bool,
) -> Result<ExitCode, PipelineError> {
    use sheetform::ffd::SolverMethod;
    let text = read_scene(&scene)?;
    let options = FfdRunOptions {
        pattern: pattern.into(),
        input: Some(scene.display().to_string()),
        base_dir: scene.parent().map(|p| p.to_path_buf()),
        solver: solver.map(|s| match s {
            SolverArg::Constrained => SolverMethod::Constrained,
            SolverArg::Paper => SolverMethod::Paper,
            SolverArg::None => SolverMethod::None,
        }),
    };
    let run = with_progress_bar(quiet, |progress| run_ffd(&text, &options, progress))?;
    write_outputs(&output, &run.files, &run.report)?;
    if !quiet {
        let ffd = run.report.ffd.as_ref().expect("ffd report");
        eprintln!(
            "ffd `{}` ({}): {} panels, max angle defect {:.2e} -> {:.2e} rad, D[M] {:.3} -> {:.3}, {}; wrote {} files to {}",
            scene.display(),
            ffd.solver,
            ffd.panel_count,
            ffd.angle_defects_before.angle_defect_max_rad,
            ffd.angle_defects_after.angle_defect_max_rad,
            ffd.angle_defects_before.developability_d,
            ffd.angle_defects_after.developability_d,
            run.report.status,
            run.report.outputs.len(),
            output.display()
        );
    }
    Ok(ExitCode::SUCCESS)
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Bend {
            scene,
            output,
            animate,
            pattern,
        } => bend_command(scene, output, animate, pattern, cli.quiet),
        Command::Slit { scene, output, pattern } => slit_command(scene, output, pattern, cli.quiet),
        Command::Ffd {
            scene,
            output,
            solver,
            pattern,
        } => ffd_command(scene, output, solver, pattern, cli.quiet),
        Command::Photo {
            annotation,
            output,
            pattern,
        } => photo_command(annotation, output, pattern, cli.quiet),
        Command::Check {
            mesh,
            output,
            weld,
            tolerance,
            units,
        } => check_command(mesh, output, weld, tolerance, units, cli.quiet),
        Command::Flatten {
            mesh,
            output,
            weld,
            units,
            method,
            charts,
            pattern,
        } => flatten_command(
            mesh,
            output,
            FlattenArgs {
                weld,
                units,
                method,
                charts,
                pattern,
            },
            cli.quiet,
        ),
        Command::Schema {
            format: SchemaFormat::Slit,
        } => {
            println!(
                "{}",
                serde_json::to_string_pretty(&sheetform::slit::SlitScene::json_schema()).expect("schema serialises")
            );
            Ok(ExitCode::SUCCESS)
        }
        Command::Schema {
            format: SchemaFormat::Ffd,
        } => {
            println!(
                "{}",
                serde_json::to_string_pretty(&sheetform::ffd::FfdScene::json_schema()).expect("schema serialises")
            );
            Ok(ExitCode::SUCCESS)
        }
        Command::Schema {
            format: SchemaFormat::Photo,
        } => {
            println!(
                "{}",
                serde_json::to_string_pretty(&sheetform::photo::PhotoAnnotation::json_schema())
                    .expect("schema serialises")
            );
            Ok(ExitCode::SUCCESS)
        }
        Command::Schema {
            format: SchemaFormat::Bend,
        } => {
            println!(
                "{}",
                serde_json::to_string_pretty(&sheetform::bend::BendScene::json_schema()).expect("schema serialises")
            );
            Ok(ExitCode::SUCCESS)
        }
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("sheetform: {e}");
            ExitCode::FAILURE
        }
    }
}
