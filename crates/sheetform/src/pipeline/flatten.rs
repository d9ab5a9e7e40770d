//! `sheetform flatten`: any mesh laid out in the plane, cut into charts when needed.

use crate::report::{ChartMethod, Command, NetReport, Report, SegmentationReport, Status, Timings};
use sheetform_flatten::{
    arap, choose_layout, cut_into_charts_until, distortion, exact_unfold, lscm, open_user_seams, unfold_net,
    ArapOptions, Chart, ChartOptions, Distortion, Layout, NetOptions, UnfoldOptions,
};
use sheetform_io::{glb_bytes, obj_string, UpAxis};
use sheetform_mesh::{mesh_topology, LengthUnit, Piece, PieceKind, SheetMesh, TriangleMesh};
use sheetform_pattern::TabOptions;
use sheetform_pattern::{arrange_in_rows, point_bounds, rotated, smallest_bounding_rotation};

type Vec2 = nalgebra::Vector2<f64>;
use super::check::{mesh_name, weld_input};
use super::context::RunContext;
use super::error::{Outcome, PipelineError};
use super::outputs::{
    output_names, pattern_files, PatternOutputOptions, PAGE_PACKING_GAP_MM, SMOOTH_PANEL_BEND_DEGREES,
};
use super::sheet_report::{angle_defects, chart_report, DEFAULT_ANGLE_TOLERANCE};
use std::time::Instant;

/// With `--charts auto`, a net of more pieces than this is compared with smooth charts.
pub const AUTO_NET_HANDFUL: usize = 8;

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

/// How `flatten` lays the mesh out: whole, in smooth charts or as a net.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ChartMode {
    /// What a maker would expect ([`sheetform_flatten::choose_layout`]): a developable
    /// disk whole, a developable with cone points or several boundaries in charts opened
    /// along straight seams, a faceted model as a net, a finely meshed curved surface in
    /// charts within the distortion bound. A net of more than [`AUTO_NET_HANDFUL`]
    /// pieces gives way to smooth charts when they need fewer than half as many. A disk
    /// given `--method lscm` or `arap` stays whole.
    #[default]
    Auto,
    /// Always smooth charts (a disk is still cut along sharp creases and split where it
    /// would distort).
    Smooth,
    /// Always a net: the facets unfolded edge by edge, exact, folded along kept edges.
    Net,
    /// Never cut, apart from the user's seams (a mesh that is not a disk after them is
    /// refused).
    Never,
}

/// Knobs of `sheetform flatten`.
#[derive(Debug, Clone)]
pub struct FlattenOptions {
    /// Layout method (for a mesh flattened whole; charts use exact unfolding).
    pub method: FlattenMethod,
    /// Whole, charts or net.
    pub charts: ChartMode,
    /// How to cut into charts.
    pub chart_options: ChartOptions,
    /// How to unfold a net.
    pub net_options: NetOptions,
    /// Glue tabs of a net when `pattern.tabs` asks for none (`None`: a net without tabs).
    /// Default: tabs on one side of every seam, as the papercraft tools print them.
    pub net_tabs: Option<TabOptions>,
    /// How the pattern is written.
    pub pattern: PatternOutputOptions,
    /// Merge vertices closer than this (model units) first.
    pub weld: Option<f64>,
    /// Length unit of the file.
    pub unit: LengthUnit,
    /// Where the mesh came from (recorded in the report; its file stem names the pieces).
    pub input: Option<String>,
    /// The name the pieces are named after (default: the input's file stem, or `mesh`).
    pub name: Option<String>,
    /// The model's final height as printed (mm, along +y, the up axis of OBJ and glTF):
    /// the pattern is scaled to it (`pattern.scale` must then be 1), as Pepakura asks for
    /// a model's size.
    pub size_mm: Option<f64>,
}

/// The largest `size_mm` of [`FlattenOptions`] (mm: a 100 m model).
pub const MAX_MODEL_SIZE_MM: f64 = 1e5;

/// A pattern whose model is smaller than this as printed (mm, its largest extent) gets a
/// warning: too small to cut and fold (a file in metres read as millimetres).
pub const SMALLEST_SENSIBLE_MODEL_MM: f64 = 20.0;

/// The printed edges of a pattern whose median edge is shorter than this (mm) are too
/// short to fold and glue: a warning.
pub const SHORTEST_SENSIBLE_EDGE_MM: f64 = 1.0;

impl Default for FlattenOptions {
    fn default() -> Self {
        Self {
            method: FlattenMethod::default(),
            charts: ChartMode::default(),
            chart_options: ChartOptions::default(),
            net_options: NetOptions::default(),
            net_tabs: Some(TabOptions::default()),
            pattern: PatternOutputOptions::default(),
            weld: None,
            unit: LengthUnit::default(),
            input: None,
            name: None,
            size_mm: None,
        }
    }
}

/// A finished flattening.
#[derive(Debug)]
pub struct FlattenRun {
    /// The mesh with its pattern.
    pub sheet: SheetMesh,
    /// The vertex of the input mesh that each vertex of `sheet` is a copy of: a vertex on
    /// a seam between charts has a copy in each; after welding, the first of the input
    /// vertices merged into it.
    pub source_vertices: Vec<u32>,
    /// Distortion and overlaps.
    pub distortion: Distortion,
    /// Rendered outputs.
    pub files: Vec<(String, Vec<u8>)>,
    /// The report.
    pub report: Report,
    /// How the run ended (the report's `status` says the same).
    pub outcome: Outcome,
}

/// Flattens a developable (or nearly developable) disk-like mesh by exact unfolding from
/// its edge lengths (see [`sheetform_flatten::exact_unfold`]) and renders the pattern.
///
/// # Errors
/// Meshes that cannot be unfolded (closed, non-manifold, …) with the reason; a bad weld
/// distance; [`PipelineError::Cancelled`].
pub fn run_flatten(
    mesh: TriangleMesh,
    options: &FlattenOptions,
    context: &RunContext,
) -> Result<FlattenRun, PipelineError> {
    let start = Instant::now();
    let charts = &options.chart_options;
    if !(charts.crease_angle_degrees.is_finite() && (0.0..=180.0).contains(&charts.crease_angle_degrees)) {
        return Err(PipelineError::Option {
            option: "--crease-angle",
            message: format!(
                "must be an angle from 0 to 180 degrees, got {}",
                sheetform_geometry::refused_number(charts.crease_angle_degrees, &[0.0, 180.0])
            ),
        });
    }
    if !(charts.max_edge_distortion.is_finite() && charts.max_edge_distortion > 0.0) {
        return Err(PipelineError::Option {
            option: "--max-distortion",
            message: format!(
                "must be a positive fraction (0.01 = 1 %), got {}",
                sheetform_geometry::short_number(charts.max_edge_distortion)
            ),
        });
    }
    let mut mesh = mesh;
    let (welded, welded_origins) = weld_input(&mut mesh, options.weld)?;
    let sized = sized_to_height(options, &mesh)?;
    let options = sized.as_ref().unwrap_or(options);
    let parsed = Instant::now();
    context.progress("flattening", 0.1);
    let topology = mesh_topology(&mesh);
    let disk = topology.component_count == 1 && topology.boundary_loop_count == 1 && topology.euler_characteristic == 1;
    let (layout, reason) = match options.charts {
        ChartMode::Auto if disk && options.method != FlattenMethod::Exact => (
            Layout::Whole,
            "a disk with a whole-mesh method (--method lscm or arap): flattened whole".to_string(),
        ),
        ChartMode::Auto => {
            let choice = choose_layout(&mesh, &topology, options.chart_options.crease_angle_degrees);
            (choice.layout, choice.reason)
        }
        ChartMode::Smooth => (Layout::Charts, "smooth charts asked for".into()),
        ChartMode::Net => (Layout::Net, "a net asked for".into()),
        ChartMode::Never => (Layout::Whole, "no charts asked for: flattened whole".into()),
    };
    // A net of many pieces is kept only when smooth charts (within the distortion bound)
    // would not need far fewer: a finely faceted model cut into a handful of charts is
    // easier to make than a net of a hundred scraps.
    let (mut layout, mut reason) = (layout, reason);
    let (mut net, mut chart_set) = (None, None);
    if layout == Layout::Net {
        context.progress("unfolding a net", 0.2);
        let net_options = net_limits(options);
        let unfolded = unfold_net(&mesh, &net_options)?;
        if options.charts == ChartMode::Auto && unfolded.pieces.len() > AUTO_NET_HANDFUL {
            context.check_cancelled()?;
            let set = cut_into_charts_until(&mesh, &options.chart_options, context.cancel).map_err(cancelled)?;
            // (Charts are not cut to fit a sheet or page: they are taken only when each
            // fits, as every piece of the net does.)
            let fit = |chart: &Chart| {
                net_options.sheet.is_none_or(|(w, h)| {
                    sheetform_geometry::hull_fits_rectangle(&sheetform_geometry::convex_hull(chart.flat.clone()), w, h)
                })
            };
            if 2 * set.charts.len() < unfolded.pieces.len() && set.charts.iter().all(fit) {
                reason = format!(
                    "{reason}; but the net needs {} pieces and smooth charts within the distortion bound {}: cut into charts",
                    unfolded.pieces.len(),
                    set.charts.len()
                );
                layout = Layout::Charts;
                chart_set = Some(set);
            }
        }
        if layout == Layout::Net {
            net = Some(unfolded);
        }
    }
    let mm = options.unit.millimetres();
    let name = mesh_name(options.name.as_deref(), options.input.as_deref());
    let mut report = Report::new(Command::Flatten, options.input.clone());
    report.layout = Some(layout);
    report.layout_reason = Some(reason);
    // A net gets glue tabs unless the pattern options say otherwise (or ask for a seam
    // allowance or a sheet thickness instead).
    let pattern_options = if layout == Layout::Net {
        options.pattern.glued_with(options.net_tabs)
    } else {
        options.pattern
    };
    // Room between charts for glue tabs (model units).
    let tab_room = pattern_options.room_between_pieces(mm);
    let (sheet, source_vertices, solved) = match layout {
        Layout::Charts => {
            let set = match chart_set.take() {
                Some(set) => set,
                None => cut_into_charts_until(&mesh, &options.chart_options, context.cancel).map_err(cancelled)?,
            };
            let solved = Instant::now();
            let sheet = sheet_from_charts(&mesh, &set.charts, &name, None, options.unit, tab_room);
            report.segmentation = Some(SegmentationReport {
                chart_count: set.charts.len(),
                initial_chart_count: set.initial_chart_count,
                split_count: set.split_count,
                opened_chart_count: set.opened_count,
                merged_chart_count: set.merged_count,
                straightened_border_count: set.straightened_count,
                seam_edge_count: set.seam_edge_count,
                user_seam_edge_count: mesh.seam_edges.len(),
                crease_angle_degrees: options.chart_options.crease_angle_degrees,
                max_edge_distortion_relative: options.chart_options.max_edge_distortion,
            });
            report.charts = charts_report(&sheet, &set.charts);
            report.solver = Some(sum_solvers(&set.charts));
            (sheet, chart_vertex_sources(&set.charts), solved)
        }
        Layout::Net => {
            let net = net.take().expect("a net layout was unfolded above");
            let solved = Instant::now();
            let sheet = sheet_from_charts(&mesh, &net.pieces, &name, None, options.unit, tab_room);
            report.net = Some(NetReport {
                piece_count: net.pieces.len(),
                fold_edge_count: net.fold_edge_count,
                cut_edge_count: net.cut_edge_count,
                cut_length_mm: net.cut_length * mm,
                user_seam_edge_count: mesh.seam_edges.len(),
                attempt_count: net.attempts,
                merged_piece_count: net.merged_piece_count,
                budget_cut_count: net.budget_cut_count,
            });
            report.charts = charts_report(&sheet, &net.pieces);
            (sheet, chart_vertex_sources(&net.pieces), solved)
        }
        Layout::Whole => {
            // The user's seams are opened first (the mesh then has to be a disk).
            let opened = open_user_seams(&mesh)?;
            let whole = opened.as_ref().map_or(&mesh, |cut| &cut.mesh);
            let sources = opened
                .as_ref()
                .map_or_else(|| (0..mesh.positions.len() as u32).collect(), |cut| cut.origin.clone());
            let unfolding = match options.method {
                FlattenMethod::Exact => exact_unfold(whole, &UnfoldOptions::default())?,
                FlattenMethod::Lscm => lscm(whole)?,
                FlattenMethod::Arap => arap(whole, &ArapOptions::default())?,
            };
            let solved = Instant::now();
            let sheet = SheetMesh {
                positions: whole.positions.clone(),
                flat: unfolding.flat.clone(),
                triangles: whole.triangles.clone(),
                face_pieces: vec![0; whole.triangles.len()],
                pieces: vec![Piece {
                    name: name.clone(),
                    kind: PieceKind::Chart,
                }],
                rulings: vec![],
                smooth_edges: vec![],
                unit: options.unit,
            };
            report.solver = Some(unfolding.solver);
            (sheet, sources, solved)
        }
    };
    let use_charts = layout != Layout::Whole;
    // Distortion and overlaps over the whole pattern (charts against each other too);
    // a mesh flattened whole is its own single chart.
    let d = distortion(&sheet.to_triangle_mesh(), &sheet.flat);
    if !use_charts {
        let method = match options.method {
            FlattenMethod::Exact => ChartMethod::Exact,
            FlattenMethod::Lscm => ChartMethod::Lscm,
            FlattenMethod::Arap => ChartMethod::Arap,
        };
        report.charts = vec![chart_report(&name, method, mesh.triangles.len(), &d)];
    }
    context.check_cancelled()?;
    context.progress("exporting", 0.8);
    let mut files = Vec::new();
    if context.renders_all() {
        files.push((
            "model.obj".to_string(),
            obj_string(&sheet, &name, UpAxis::Y).into_bytes(),
        ));
    }
    files.push(("model.glb".to_string(), glb_bytes(&sheet, &name, None, UpAxis::Y)));
    let (pattern, pattern_report) = pattern_files(
        &sheet,
        &name,
        &pattern_options,
        context.outputs,
        None,
        UpAxis::Y,
        if layout == Layout::Net {
            0.0
        } else {
            SMOOTH_PANEL_BEND_DEGREES
        },
    )?;
    files.extend(pattern);
    let exported = Instant::now();
    // The bound the report states: no overlap, and no edge stretched by more than the
    // distortion bound (whole meshes included: a hemisphere flattened whole is refused
    // as out of tolerance, not called ok).
    let within = d.edge_length_max_relative <= options.chart_options.max_edge_distortion;
    report.status = if !d.is_overlap_free() {
        Status::Overlapping
    } else if !within {
        Status::OutOfTolerance
    } else {
        Status::Ok
    };
    report.model_unit = options.unit;
    report.vertex_count = mesh.positions.len();
    report.face_count = mesh.triangles.len();
    report.isometry_error_max_relative = Some(d.edge_length_max_relative);
    report.isometry_error_mean_relative = Some(d.edge_length_mean_relative);
    report.angle_defects = Some(angle_defects(&mesh, &topology, DEFAULT_ANGLE_TOLERANCE, mm).0);
    report.flat_area_mm2 = Some(sheet.flat_area() * mm * mm);
    report.area_mm2 = sheet.area() * mm * mm;
    report.welded_vertex_count = welded;
    report.warnings = size_warnings(&mesh, options, layout == Layout::Net);
    report.pattern = Some(pattern_report);
    report.outputs = output_names(&files);
    report.timings = Timings::from_stages(start, parsed, solved, exported);
    let source_vertices = source_vertices
        .into_iter()
        .map(|v| welded_origins[v as usize])
        .collect();
    Ok(FlattenRun {
        sheet,
        source_vertices,
        outcome: if !d.is_overlap_free() {
            Outcome::Overlapping
        } else if !within {
            Outcome::OutOfTolerance
        } else {
            Outcome::Ok
        },
        distortion: d,
        files,
        report,
    })
}

/// A flattening error, stopped runs as the pipeline's [`PipelineError::Cancelled`].
fn cancelled(e: sheetform_flatten::FlattenError) -> PipelineError {
    match e {
        sheetform_flatten::FlattenError::Cancelled => PipelineError::Cancelled,
        other => PipelineError::from(other),
    }
}

/// The options with the pattern scaled so that the model's height (its extent along +y)
/// prints as `size_mm` (`None` without a size).
///
/// # Errors
/// A size that is not a positive number up to [`MAX_MODEL_SIZE_MM`], a size given with a
/// scale other than 1, a model with no height.
fn sized_to_height(options: &FlattenOptions, mesh: &TriangleMesh) -> Result<Option<FlattenOptions>, PipelineError> {
    let Some(size) = options.size_mm else { return Ok(None) };
    if !(size.is_finite() && size > 0.0 && size <= MAX_MODEL_SIZE_MM) {
        return Err(PipelineError::Option {
            option: "--size",
            message: format!(
                "must be the model's height in millimetres, over 0 and at most {}, got {}",
                sheetform_geometry::short_number(MAX_MODEL_SIZE_MM),
                sheetform_geometry::refused_number(size, &[0.0, MAX_MODEL_SIZE_MM])
            ),
        });
    }
    if options.pattern.scale != 1.0 {
        return Err(PipelineError::Option {
            option: "--size",
            message: "sets the scale itself: give --size or --scale, not both".into(),
        });
    }
    let (lo, hi) = mesh
        .positions
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p.y), hi.max(p.y))
        });
    let height_mm = (hi - lo) * options.unit.millimetres();
    if !(height_mm.is_finite() && height_mm > 0.0) {
        return Err(PipelineError::Option {
            option: "--size",
            message: "the model has no height along y (the up axis of OBJ and glTF) to scale to: use --scale".into(),
        });
    }
    let mut sized = options.clone();
    sized.pattern.scale = size / height_mm;
    Ok(Some(sized))
}

/// Warnings of a pattern printed too small to cut and fold: the model smaller than
/// [`SMALLEST_SENSIBLE_MODEL_MM`] across, or (a net, folded at every edge) its median
/// edge shorter than [`SHORTEST_SENSIBLE_EDGE_MM`], with what to do (the file's unit, or
/// a size).
fn size_warnings(mesh: &TriangleMesh, options: &FlattenOptions, net: bool) -> Vec<String> {
    let k = options.unit.millimetres() * options.pattern.scale;
    let (lo, hi) = mesh.positions.iter().fold(
        (
            nalgebra::Vector3::repeat(f64::INFINITY),
            nalgebra::Vector3::repeat(f64::NEG_INFINITY),
        ),
        |(lo, hi), p| (lo.inf(p), hi.sup(p)),
    );
    let across = (hi - lo).max() * k;
    let mut lengths: Vec<f64> = mesh
        .triangles
        .iter()
        .flat_map(|t| (0..3).map(move |i| (t[i], t[(i + 1) % 3])))
        .map(|(a, b)| (mesh.positions[a as usize] - mesh.positions[b as usize]).norm() * k)
        .collect();
    let median = if lengths.is_empty() {
        0.0
    } else {
        let middle = lengths.len() / 2;
        *lengths.select_nth_unstable_by(middle, f64::total_cmp).1
    };
    let advice = "if the file is in metres, centimetres or inches give --units m, cm or in; or set the model's height as printed with --size HEIGHT (mm)";
    let mut warnings = Vec::new();
    if across.is_finite() && across < SMALLEST_SENSIBLE_MODEL_MM {
        warnings.push(format!(
            "the model prints {} mm across, too small to cut and fold: {advice}",
            sheetform_geometry::short_number(across)
        ));
    } else if net && median.is_finite() && median < SHORTEST_SENSIBLE_EDGE_MM {
        warnings.push(format!(
            "half the model's edges print shorter than {} mm (median {} mm), too short to fold and glue: {advice}",
            SHORTEST_SENSIBLE_EDGE_MM,
            sheetform_geometry::short_number(median)
        ));
    }
    warnings
}

/// The net options with the limits the pattern sets, in model units: the cutting
/// clearance between cut lines; between the sides of a slit (a seam facing its own other
/// copy), room for the smallest glue tab and its clearance when tabs are on; and pieces
/// that fit a sheet's printable area (inside the gap at its edges), or without sheets a
/// page of the PDF (so that each prints whole), with room for the tabs and allowances
/// around them.
fn net_limits(options: &FlattenOptions) -> NetOptions {
    let pattern = &options.pattern;
    let model_mm = options.unit.millimetres() * pattern.scale;
    // The tabs the net will be drawn with.
    let tabs = pattern.glued_with(options.net_tabs).tabs;
    let clearance_mm = tabs.map_or(sheetform_pattern::DEFAULT_CUT_CLEARANCE_MM, |t| t.clearance_mm);
    let slit_mm = tabs.map_or(clearance_mm, |t| t.width_mm * t.min_width_fraction + t.clearance_mm);
    let around_mm =
        2.0 * (tabs.map_or(0.0, |t| t.width_mm) + pattern.allowance.seam_allowance_mm + pattern.allowance.kerf_mm);
    let (width_mm, height_mm) = match pattern.packing_sheet() {
        Some(s) => (s.width_mm - 2.0 * s.gap_mm, s.height_mm - 2.0 * s.gap_mm),
        None => {
            let (w, h) = sheetform_pattern::PdfOptions {
                page: pattern.page,
                ..Default::default()
            }
            .printable_area();
            (w - 2.0 * PAGE_PACKING_GAP_MM, h - 2.0 * PAGE_PACKING_GAP_MM)
        }
    };
    let sheet = (
        ((width_mm - around_mm) / model_mm).max(0.0),
        ((height_mm - around_mm) / model_mm).max(0.0),
    );
    NetOptions {
        clearance: options.net_options.clearance.max(clearance_mm / model_mm),
        slit_clearance: options.net_options.slit_clearance.max(slit_mm / model_mm),
        sheet: options.net_options.sheet.or(Some(sheet)),
        ..options.net_options
    }
}

/// The mesh vertex each vertex of [`sheet_from_charts`]'s sheet is a copy of.
fn chart_vertex_sources(charts: &[Chart]) -> Vec<u32> {
    charts.iter().flat_map(|c| c.vertices.iter().copied()).collect()
}

/// One report entry per chart (exact unfolding), named as the sheet's pieces.
fn charts_report(sheet: &SheetMesh, charts: &[Chart]) -> Vec<crate::report::ChartReport> {
    charts
        .iter()
        .enumerate()
        .map(|(c, chart)| {
            chart_report(
                &sheet.pieces[c].name,
                ChartMethod::Exact,
                chart.faces.len(),
                &chart.distortion,
            )
        })
        .collect()
}

/// The charts' solver reports summed (iterations, costs) or combined (worst gradient,
/// all converged).
fn sum_solvers(charts: &[Chart]) -> sheetform_solve::SolverInfo {
    sheetform_solve::SolverInfo {
        iterations: charts.iter().map(|c| c.solver.iterations).sum(),
        cost: charts.iter().map(|c| c.solver.cost).sum(),
        initial_cost: charts.iter().map(|c| c.solver.initial_cost).sum(),
        gradient_norm: charts.iter().map(|c| c.solver.gradient_norm).fold(0.0, f64::max),
        converged: charts.iter().all(|c| c.solver.converged),
    }
}

/// The charts as one [`SheetMesh`]: every chart keeps its own copy of its seam vertices
/// (same 3D position, own flat position), one piece per chart, the charts' flat layouts
/// set side by side in rows (`gap` apart plus `extra_gap`, model units) so that the
/// pattern (and the OBJ `vt`) has no chart over another.
pub(crate) fn sheet_from_charts(
    mesh: &TriangleMesh,
    charts: &[Chart],
    name: &str,
    piece_names: Option<&[String]>,
    unit: LengthUnit,
    extra_gap: f64,
) -> SheetMesh {
    // Each chart turned to its smallest bounding rectangle, landscape.
    let turned: Vec<Vec<Vec2>> = charts
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
    let digits = charts.len().to_string().len().max(2);
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
    for (c, chart) in charts.iter().enumerate() {
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
pub(crate) fn stored_flattening_error(mesh: &TriangleMesh, uv: &[[nalgebra::Vector2<f64>; 3]]) -> (f64, f64, f64) {
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
