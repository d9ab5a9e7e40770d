//! `sheetform photo`: system D (Fondevilla et al.).

use crate::report::{ChartMethod, Command, PhotoReport, Report, Status, Timings};
use base64::Engine as _;
use sheetform_flatten::Chart;
use sheetform_flatten::{distortion, exact_unfold, lscm, ChartSet, FlattenError, UnfoldOptions};
use sheetform_io::{glb_bytes_projected, UpAxis};
use sheetform_io::{obj_string, stl_bytes, Texture};
use sheetform_mesh::{Ruling, SheetMesh, TriangleMesh};
use sheetform_photo::{
    annotation_from_svg, overlay_png, overlay_svg, reconstruct, svg_image_reference, AngleSummary, BackSide,
    CurveNetwork, PatchSurface, PhotoAnnotation, PhotoError, PhotoReconstruction, Projection,
};

use super::context::RunContext;
use super::error::{Outcome, PipelineError};
use super::flatten::sheet_from_charts;
use super::outputs::{output_names, pattern_files, PatternOutputOptions, RenderedFiles, SMOOTH_PANEL_BEND_DEGREES};
use super::sheet_report::{chart_report, sheet_mesh_report};
use sheetform_pattern::TabOptions;
use std::time::Instant;

/// Knobs of `sheetform photo`.
#[derive(Debug, Clone)]
pub struct PhotoRunOptions {
    /// How the pattern is written.
    pub pattern: PatternOutputOptions,
    /// Input path, recorded in the report.
    pub input: Option<String>,
    /// What to make of the side the photo does not show, over the annotation's
    /// `back_side` (an SVG drawing has no mark for it).
    pub back_side: Option<BackSide>,
    /// Glue tabs of a whole object (`back_side: revolve`, whose pieces are glued along
    /// their seams) when `pattern.tabs` asks for none and there is no seam allowance or
    /// sheet thickness (`None`: no tabs). Default: one side of every seam, as a net's.
    pub whole_object_tabs: Option<TabOptions>,
}

impl Default for PhotoRunOptions {
    fn default() -> Self {
        Self {
            pattern: PatternOutputOptions::default(),
            input: None,
            back_side: None,
            whole_object_tabs: Some(TabOptions::default()),
        }
    }
}

/// What `sheetform photo` reads: an annotation, or a drawing made over the photo in an SVG
/// editor (read once the photo's size is known, [`sheetform_photo::annotation_from_svg`]).
#[derive(Debug, Clone)]
pub enum PhotoInput {
    /// A parsed annotation.
    Annotation(Box<PhotoAnnotation>),
    /// An SVG drawing's text.
    Drawing(String),
}

impl PhotoInput {
    /// A JSON annotation's or an SVG drawing's text (told apart by its first character).
    ///
    /// # Errors
    /// [`PipelineError::Photo`] for an invalid JSON annotation (naming the field).
    pub fn from_text(text: &str) -> Result<Self, PipelineError> {
        if text.trim_start().starts_with('<') {
            Ok(Self::Drawing(text.to_string()))
        } else {
            Ok(Self::Annotation(Box::new(PhotoAnnotation::from_json(text)?)))
        }
    }
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
    /// How the run ended (the report's `status` says the same).
    pub outcome: Outcome,
}

/// Why a patch of the reconstruction cannot be unfolded, in the terms of a drawing over a
/// photo: the flattening's own advice ("cut it into charts") is the `flatten` command's,
/// whose user gave the mesh; here the mesh comes from the curves, and the curves are what
/// to change.
fn patch_unfolding_failed(patch: &str, error: FlattenError) -> PipelineError {
    let message = match error {
        FlattenError::Cancelled => return PipelineError::Cancelled,
        FlattenError::NotADisk { boundary_loops, .. } => format!(
            "cannot be unfolded flat: it is not one disk-like piece ({boundary_loops} boundary loops, as a band \
             round a tube has two); trace a seam curve across it, from one of its boundary curves to another, so \
             that it opens into one piece"
        ),
        FlattenError::Topology { problem } => format!(
            "cannot be unfolded flat: the surface made from its curves is not clean ({problem}); look for curves \
             that cross or overlap around it, or a curve traced twice"
        ),
        FlattenError::Solver { message } => {
            tracing::debug!(patch, message, "photo: the least-squares flattening of a patch failed");
            "cannot be unfolded flat: its least-squares flattening has no solution (the surface made from its \
             curves has collapsed triangles); look for curves around it that nearly touch or double back"
                .to_string()
        }
        other => format!("cannot be unfolded flat: {other}"),
    };
    PhotoError::Patch {
        patch: patch.to_string(),
        message,
    }
    .into()
}

/// Runs system D on an annotation (or a drawing): read the photograph through the
/// context's assets, reconstruct (Fondevilla et al.), unfold every patch and write the
/// model (OBJ, GLB with the photo projected onto it, STL), the pattern, the overlay over
/// the photo and the report.
///
/// # Errors
/// [`PipelineError::Photo`] for invalid annotations (naming the field or curve),
/// [`PipelineError::Asset`] / [`PipelineError::Image`] for a missing, unreadable,
/// undecodable or mis-sized photo, [`PipelineError::Photo`] naming a patch that cannot be
/// unfolded,
/// [`PipelineError::Cancelled`].
pub fn run_photo(
    input: &PhotoInput,
    options: &PhotoRunOptions,
    context: &RunContext,
) -> Result<PhotoRun, PipelineError> {
    let start = Instant::now();
    context.progress("reading annotation", 0.0);
    let read_image = |relative: &str| -> Result<(String, Vec<u8>), PipelineError> {
        Ok((relative.to_string(), context.assets.read(relative, "image.path")?))
    };
    let from_svg = matches!(input, PhotoInput::Drawing(_));
    // The photo is decoded to its end here, before anything is made from it: a file that
    // only starts like a PNG, or was cut off, would go into the GLB and the overlay.
    let check_photo = |(path, bytes): &(String, Vec<u8>)| -> Result<(u32, u32), PipelineError> {
        Texture::decoded(bytes)
            .map(|(_, size)| size)
            .map_err(|problem| PipelineError::Image {
                field: "image.path",
                path: path.clone(),
                what: "the photo",
                problem,
            })
    };
    let (mut annotation, (image_path, image_bytes), size) = match input {
        PhotoInput::Drawing(text) => {
            // The drawing names the photo; its pixel size maps the drawing to the image.
            let image = read_image(&svg_image_reference(text)?)?;
            let size = check_photo(&image)?;
            (annotation_from_svg(text, size)?, image, size)
        }
        PhotoInput::Annotation(annotation) => {
            let image = read_image(&annotation.image.path)?;
            let size = check_photo(&image)?;
            (annotation.as_ref().clone(), image, size)
        }
    };
    let texture = Texture::from_bytes(&image_bytes).expect("decoded above");
    if size != (annotation.image.width, annotation.image.height) {
        return Err(PhotoError::field(
            "image",
            format!(
                "{} is {} × {} px, the annotation says {} × {}",
                image_path, size.0, size.1, annotation.image.width, annotation.image.height
            ),
        )
        .into());
    }
    if let Some(back_side) = options.back_side {
        annotation.back_side = back_side;
    }
    // A perspective camera without a focal length takes the photo's EXIF one.
    let camera = &mut annotation.camera;
    let focal_length_from_exif = camera.projection == Projection::Perspective
        && camera.focal_length_px.is_none()
        && camera.focal_length_35mm.is_none();
    if focal_length_from_exif {
        camera.focal_length_35mm = sheetform_io::focal_length_35mm_from_exif(&image_bytes);
        tracing::debug!(
            "photo: focal length from the EXIF of {image_path}: {:?} mm",
            camera.focal_length_35mm
        );
        annotation.validate()?;
    }
    // Without one there either, the reconstruction estimates it from the drawing.
    let focal_length_from_exif = focal_length_from_exif && annotation.camera.focal_length_35mm.is_some();
    let parsed = Instant::now();
    context.check_cancelled()?;
    context.progress("reconstructing", 0.1);
    let reconstruction = reconstruct(&annotation)?;
    context.check_cancelled()?;
    context.progress("unfolding", 0.5);
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
        // A band closed around its axis is cut open along its seam first.
        let seam: Vec<[u32; 2]> = reconstruction
            .revolution
            .iter()
            .flat_map(|r| r.seam_edges.iter())
            .filter_map(|&[a, b]| Some([*local.get(&a)?, *local.get(&b)?]))
            .collect();
        let (patch_mesh, vertices, triangles) = if seam.is_empty() {
            (patch_mesh, vertices, triangles)
        } else {
            let opened = sheetform_mesh::cut_along_edges(&patch_mesh, &seam);
            let vertices: Vec<u32> = opened.origin.iter().map(|&v| vertices[v as usize]).collect();
            let triangles = opened.mesh.triangles.clone();
            (opened.mesh, vertices, triangles)
        };
        // Ruled strips unfold exactly; a filled (minimal-surface) patch is only nearly
        // developable: least-squares conformal maps when the exact unfolding fails.
        let (flat, solver, method) = match exact_unfold(&patch_mesh, &UnfoldOptions::default()) {
            Ok(u) => (u.flat, u.solver, ChartMethod::Exact),
            Err(_) => {
                let u = lscm(&patch_mesh).map_err(|e| patch_unfolding_failed(&groups[g as usize], e))?;
                (u.flat, u.solver, ChartMethod::Lscm)
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
        opened_count: 0,
        merged_count: 0,
        straightened_count: 0,
    };
    // A whole object is glued along its seams: the tabs a net gets, unless the pattern
    // asks for others, none, a seam allowance or a sheet thickness.
    let pattern_options = if reconstruction.revolution.is_some() {
        options.pattern.glued_with(options.whole_object_tabs)
    } else {
        options.pattern
    };
    let tab_room = pattern_options.room_between_pieces(mm);
    let mut sheet = sheet_from_charts(&model, &chart_set.charts, &name, Some(&groups), unit, tab_room);
    // The strips' rulings are bending guides (the pattern draws rulings as guides, never
    // as mountain or valley folds), the zipper edges between them smooth edges (drawn as
    // neither): each in its chart's numbering of the sheet, through a face that has it
    // (a band cut open along its seam has two copies of the seam's vertices).
    let mut chart_offset = Vec::with_capacity(chart_set.charts.len());
    let mut offset = 0u32;
    for chart in &chart_set.charts {
        chart_offset.push(offset);
        offset += chart.vertices.len() as u32;
    }
    let mut face_corners = vec![[u32::MAX; 3]; mesh.triangles.len()];
    for (c, chart) in chart_set.charts.iter().enumerate() {
        for (&f, t) in chart.faces.iter().zip(&chart.triangles) {
            face_corners[f as usize] = t.map(|k| chart_offset[c] + k);
        }
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
        let corner = |v: u32| {
            let k = mesh.triangles[face].iter().position(|&w| w == v)?;
            let s = face_corners[face][k];
            (s != u32::MAX).then_some(s)
        };
        Some((chart, [corner(a)?, corner(b)?]))
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
    context.check_cancelled()?;
    context.progress("exporting", 0.7);
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
    let all = context.renders_all();
    let mut files: RenderedFiles = Vec::new();
    if all {
        files.push(("model.obj".into(), obj_string(&sheet, &name, UpAxis::Y).into_bytes()));
    }
    files.push((
        "model.glb".into(),
        glb_bytes_projected(&sheet, &name, texture, &texcoords, UpAxis::Y),
    ));
    if all {
        files.push(("model.stl".into(), stl_bytes(&sheet)));
    }
    let (pattern, pattern_report) = pattern_files(
        &sheet,
        &name,
        &pattern_options,
        context.outputs,
        None,
        UpAxis::Y,
        SMOOTH_PANEL_BEND_DEGREES,
    )?;
    files.extend(pattern);
    let data_uri = format!(
        "data:{};base64,{}",
        texture.mime_type,
        base64::engine::general_purpose::STANDARD.encode(&image_bytes)
    );
    let overlay = overlay_svg(&annotation, &reconstruction, &data_uri);
    if all {
        files.push(("overlay.png".into(), overlay_png(&overlay)?));
    }
    files.push(("overlay.svg".into(), overlay.into_bytes()));
    if from_svg {
        // What was read from the drawing, as an annotation file to edit or rerun.
        let mut json = serde_json::to_vec_pretty(&annotation).expect("annotation serialises");
        json.push(b'\n');
        files.push(("annotation.json".into(), json));
    }
    let exported = Instant::now();
    let mut report = sheet_mesh_report(Command::Photo, options.input.clone(), &sheet);
    report.pattern = Some(pattern_report);
    report.charts = chart_set
        .charts
        .iter()
        .zip(&groups)
        .zip(&methods)
        .map(|((c, n), &m)| chart_report(n, m, c.faces.len(), &c.distortion))
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
        camera_projection: if r.plane.camera.is_orthographic() {
            "orthographic"
        } else {
            "perspective"
        }
        .into(),
        camera_focal_length_px: r.plane.camera.focal_length_px,
        camera_focal_length_from_exif: focal_length_from_exif,
        camera_focal_length_estimated: r.focal_length_estimate.is_some(),
        symmetry_plane_normal: [r.plane.normal.x, r.plane.normal.y, r.plane.normal.z],
        developability_error_linear: linear,
        developability_error_refined: annotation.analysis.refine.then_some(refined),
        refinement_iterations: r.refinement.map(|i| i.iterations),
        refinement_converged: r.refinement.map(|i| i.converged),
        refinement_work_bound_reached: r.refinement.map(|i| i.work_bound_reached),
        refinement_displacement_max_px: r.refinement.map(|i| i.displacement_max),
        refinement_slide_max_px: r.refinement.map(|i| i.slide_max_px),
        refinement_bound: sheetform_photo::REFINEMENT_BOUND,
        developability_error_symmetrized: r.symmetrization.as_ref().map(|_| symmetrized),
        symmetrization: r.symmetrization.clone(),
        revolution: r.revolution.clone(),
        depth_sensitivity_max: r.depth_sensitivity.iter().copied().fold(0.0, f64::max),
        depth_sensitivity_bound: sheetform_photo::DEPTH_SENSITIVITY_BOUND,
        depth_undetermined_curves: r.depth_undetermined_curves(),
        reprojection_error_mean_px: r.reprojection_error_px.0,
        reprojection_error_max_px: r.reprojection_error_px.1,
        millimetres_per_pixel: r.unit_per_pixel * mm,
        stage_times: r.times,
    });
    if let Some(estimate) = &r.focal_length_estimate {
        let diagonal = f64::from(annotation.image.width).hypot(f64::from(annotation.image.height));
        report.warnings.push(format!(
            "the photo's focal length is given neither in the annotation nor in its EXIF: estimated from the \
             drawing as {:.0} px ({:.0} mm in 35 mm terms; within 0.2-16 % of the truth on the synthetic views){}; give \
             `camera.focal_length_35mm` (a phone's main camera: about 26 mm) for a closer model",
            estimate.focal_length_px,
            estimate.focal_length_px / diagonal * sheetform_photo::FILM_35MM_DIAGONAL_MM,
            if estimate.at_range_end {
                ", at the end of the range searched (the drawing hardly tells it)"
            } else {
                ""
            }
        ));
    }
    for band in r.revolution.iter().flat_map(|v| &v.bands) {
        if band.silhouette_angle_degrees > sheetform_photo::REVOLUTION_SILHOUETTE_WARNING_DEGREES {
            report.warnings.push(format!(
                "patch {}: at its silhouettes the cone round the fitted axis meets the camera's rays at {:.1}° \
                 instead of grazing them (exact drawings: under 1°): the symmetry frame or the mirror points are \
                 likely a few pixels off (a 3 px error makes 1.2-3.5° and shears the whole model); check them on \
                 the photo",
                band.patch, band.silhouette_angle_degrees
            ));
        }
        if band.fit_rms_relative > sheetform_photo::REVOLUTION_FIT_WARNING {
            report.warnings.push(format!(
                "patch {} is {:.1} % off a cone round the axis fitted to the bands: its closed band is a fit, not \
                 what the photo shows; check the traced curves (or draw it with `back_side: visible`)",
                band.patch,
                100.0 * band.fit_rms_relative
            ));
        }
    }
    report.ruling_count = Some(r.ruling_count());
    report.developability_error_max_rad = Some(r.ruling_errors_final.iter().copied().fold(0.0, f64::max));
    if !developable {
        report.status = Status::NotDevelopable;
    }
    if !r.depth_undetermined_curves().is_empty() {
        report.status = Status::DepthUndetermined;
    }
    report.timings = Timings::from_stages(start, parsed, solved, exported);
    report.outputs = output_names(&files);
    context.progress("done", 1.0);
    let outcome = if report.status == Status::Ok {
        Outcome::Ok
    } else {
        Outcome::OutOfTolerance
    };
    Ok(PhotoRun {
        annotation,
        reconstruction,
        sheet,
        files,
        report,
        outcome,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 35: a patch that cannot be unfolded was explained with the `flatten`
    /// command's advice ("cut it into charts first") and a solver's pivot: every failure
    /// of the flattening is told in the drawing's terms, naming the patch.
    #[test]
    fn a_patch_that_cannot_be_unfolded_is_explained_in_the_drawings_terms() {
        for error in [
            FlattenError::NotADisk {
                components: 1,
                boundary_loops: 2,
                euler: 0,
            },
            FlattenError::Topology {
                problem: "face 3 has zero area".into(),
            },
            FlattenError::Solver {
                message: "the linear system has no unique solution (pivot 96084 of 96100 is not positive)".into(),
            },
        ] {
            let text = patch_unfolding_failed("patch-03", error).to_string();
            assert!(text.starts_with("patch `patch-03`: cannot be unfolded flat"), "{text}");
            assert!(text.contains("curve"), "{text}");
            for flatten_words in ["charts", "--", "pivot", "mesh"] {
                assert!(!text.contains(flatten_words), "{text}");
            }
        }
        assert!(matches!(
            patch_unfolding_failed("patch-01", FlattenError::Cancelled),
            PipelineError::Cancelled
        ));
    }
}
