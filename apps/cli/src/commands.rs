//! One function per subcommand: parse the scene at the edge, call the library pipeline
//! with a context rooted at the scene's directory, write the outputs, print a summary and
//! return the exit code the library decided.

use crate::args::{BackSideArg, ChartArgs, Charts, Method, PatternArgs, SchemaFormat, SolverArg, Tabs, Unit};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use sheetform::bend::BendScene;
use sheetform::flatten::ChartOptions;
use sheetform::io::read_mesh;
use sheetform::pattern::{TabOptions, TabSides};
use sheetform::pipeline::{
    read_scene_file, run_bend, run_check, run_ffd, run_flatten, run_photo, run_slit, scene_directory, write_outputs,
    BendRunOptions, ChartMode, CheckOptions, FfdRunOptions, FlattenMethod, FlattenOptions, Outcome, PhotoInput,
    PhotoRunOptions, PipelineError, RunContext, SlitRunOptions,
};
use sheetform::slit::SlitScene;
use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

pub(crate) fn check_command(
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
        input: Some(mesh.display().to_string()),
        name: None,
    };
    let model = read_mesh(&mesh)?;
    let run = with_progress_bar(quiet, |progress| {
        run_check(
            model,
            &options,
            &run_context(scene_directory(&mesh)).with_progress(progress),
        )
    })?;
    write_set(&output, &run.files, &run.report)?;
    if !quiet {
        let r = &run.report;
        let d = r.angle_defects.as_ref().expect("check reports angle defects");
        say!(
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
    Ok(ExitCode::from(run.outcome.exit_code()))
}

/// The `flatten` arguments that become [`FlattenOptions`].
pub(crate) struct FlattenArgs {
    pub(crate) weld: Option<f64>,
    pub(crate) units: Unit,
    pub(crate) size: Option<f64>,
    pub(crate) method: Method,
    pub(crate) charts: ChartArgs,
    pub(crate) pattern: PatternArgs,
}

pub(crate) fn flatten_command(
    mesh: PathBuf,
    output: PathBuf,
    args: FlattenArgs,
    quiet: bool,
) -> Result<ExitCode, PipelineError> {
    let FlattenArgs {
        weld,
        units,
        size,
        method,
        charts,
        pattern,
    } = args;
    let method = match method {
        Method::Exact => FlattenMethod::Exact,
        Method::Lscm => FlattenMethod::Lscm,
        Method::Arap => FlattenMethod::Arap,
    };
    // `--tabs auto`: a net gets tabs on one side of every seam.
    let net_tabs = auto_tabs(&pattern);
    let options = FlattenOptions {
        weld,
        unit: units.into(),
        net_tabs,
        net_options: Default::default(),
        pattern: pattern.into(),
        method,
        charts: match charts.charts {
            Charts::Auto => ChartMode::Auto,
            Charts::Net => ChartMode::Net,
            Charts::Smooth => ChartMode::Smooth,
            Charts::Never => ChartMode::Never,
        },
        chart_options: ChartOptions {
            crease_angle_degrees: charts.crease_angle,
            max_edge_distortion: charts.max_distortion,
            ..Default::default()
        },
        input: Some(mesh.display().to_string()),
        name: None,
        size_mm: size,
    };
    let model = read_mesh(&mesh)?;
    let run = with_progress_bar(quiet, |progress| {
        run_flatten(
            model,
            &options,
            &run_context(scene_directory(&mesh)).with_progress(progress),
        )
    })?;
    write_set(&output, &run.files, &run.report)?;
    for warning in &run.report.warnings {
        say!("sheetform: warning: {}: {warning}", mesh.display());
    }
    let d = &run.distortion;
    if !d.is_overlap_free() {
        say!(
            "sheetform: {}: the pattern overlaps itself ({} flipped faces, {} boundary crossings); written to {}, but it cannot be cut from one sheet as it is",
            mesh.display(),
            d.flipped_faces.len(),
            d.boundary_crossings,
            output.display()
        );
    } else if run.outcome == Outcome::OutOfTolerance {
        say!(
            "sheetform: {}: the pattern stretches an edge by {:.1} % (bound {:.1} %); written to {}, but out of tolerance: cut it into charts (--charts smooth) or allow more (--max-distortion)",
            mesh.display(),
            100.0 * d.edge_length_max_relative,
            100.0 * options.chart_options.max_edge_distortion,
            output.display()
        );
    } else if !quiet {
        say!(
            "{}: flattened {} faces; edge-length error max {:.1e}, mean {:.1e}; area error max {:.1e}; wrote {}",
            mesh.display(),
            run.report.face_count,
            d.edge_length_max_relative,
            d.edge_length_mean_relative,
            d.area_max_relative,
            output.display()
        );
    }
    Ok(ExitCode::from(run.outcome.exit_code()))
}

/// The tabs `--tabs auto` gives a net's or `develop`'s pieces: one side of every seam,
/// the width and angle asked for.
fn auto_tabs(pattern: &PatternArgs) -> Option<TabOptions> {
    (pattern.tabs == Tabs::Auto).then_some(TabOptions {
        width_mm: pattern.tab_width,
        angle_degrees: pattern.tab_angle,
        sides: TabSides::One,
        ..Default::default()
    })
}

pub(crate) fn develop_command(
    mesh: PathBuf,
    output: PathBuf,
    units: Unit,
    size: Option<f64>,
    mut options: sheetform::pipeline::DevelopRunOptions,
    pattern: PatternArgs,
    quiet: bool,
) -> Result<ExitCode, PipelineError> {
    options.flatten.unit = units.into();
    options.flatten.size_mm = size;
    // `--tabs auto`: the pieces get tabs on one side of every seam, as a net does.
    options.flatten.net_tabs = auto_tabs(&pattern);
    options.flatten.pattern = pattern.into();
    options.flatten.input = Some(mesh.display().to_string());
    let model = read_mesh(&mesh)?;
    let developed = with_progress_bar(quiet, |progress| {
        sheetform::pipeline::run_develop(
            model,
            &options,
            &run_context(scene_directory(&mesh)).with_progress(progress),
        )
    })?;
    let run = &developed.run;
    write_set(&output, &run.files, &run.report)?;
    for warning in &run.report.warnings {
        say!("sheetform: warning: {}: {warning}", mesh.display());
    }
    let figures = run.report.develop.as_ref().expect("develop reports its figures");
    let too_far = figures.max_distance_mm.filter(|&bound| figures.hausdorff_mm > bound);
    if run.outcome == Outcome::OutOfTolerance && figures.pieces_fit_sheet == Some(false) {
        say!(
            "sheetform: {}: a piece of the {} still does not fit on the sheet after {} tries; the pattern is written to {} without the sheets, but out of tolerance: allow more pieces (--max-pieces) or a larger --sheet",
            mesh.display(),
            figures.piece_count,
            figures.attempt_count,
            output.display()
        );
    } else if let (Outcome::OutOfTolerance, Some(bound), true) = (
        run.outcome,
        too_far,
        figures.angle_defect_max_rad <= figures.angle_defect_tolerance_rad,
    ) {
        say!(
            "sheetform: {}: the closest result found, {} pieces, is {:.3} mm from the target (bound {:.3} mm) after {} tries; written to {}, but out of tolerance: allow more pieces (--max-pieces) or a larger distance",
            mesh.display(),
            figures.piece_count,
            figures.hausdorff_mm,
            bound,
            figures.attempt_count,
            output.display()
        );
    } else if run.outcome == Outcome::OutOfTolerance {
        say!(
            "sheetform: {}: a piece keeps an angle defect of {:.1e} rad (bound {:.1e}) after {} steps; written to {}, but out of tolerance: add seams where the shape is most curved, or allow more (--tolerance, --max-iterations)",
            mesh.display(),
            figures.angle_defect_max_rad,
            figures.angle_defect_tolerance_rad,
            figures.iterations,
            output.display()
        );
    } else if !quiet {
        say!(
            "{}: developed {} pieces; angle defect max {:.1e} -> {:.1e} rad in {} steps; Hausdorff distance to the target {:.3} mm ({:.2} % of its size), mean {:.3} mm; wrote {}",
            mesh.display(),
            figures.piece_count,
            figures.angle_defect_max_before_rad,
            figures.angle_defect_max_rad,
            figures.iterations,
            figures.hausdorff_mm,
            100.0 * figures.hausdorff_relative,
            figures.distance_mean_mm,
            output.display()
        );
    }
    Ok(ExitCode::from(run.outcome.exit_code()))
}

/// The progress bar on stderr when it is a terminal (none when `quiet` or not a terminal).
pub(crate) fn progress_bar(quiet: bool) -> Option<ProgressBar> {
    if quiet || !std::io::stderr().is_terminal() {
        return None;
    }
    Some(styled_progress_bar(ProgressDrawTarget::stderr()))
}

/// How often the spinner turns by itself.
const SPINNER_TICK: Duration = Duration::from_millis(100);

/// The commands' bar (stage, bar, percent) drawn to `target`, its spinner turning every
/// [`SPINNER_TICK`] on its own so that a long stage (an FFD restoration runs for minutes
/// between reports) does not look frozen.
fn styled_progress_bar(target: ProgressDrawTarget) -> ProgressBar {
    let bar = ProgressBar::with_draw_target(Some(1000), target);
    bar.set_style(
        ProgressStyle::with_template("{spinner} {msg:<16} [{bar:30}] {percent:>3}%")
            .expect("valid template")
            .progress_chars("=> "),
    );
    bar.enable_steady_tick(SPINNER_TICK);
    bar
}

/// Runs `job` with a progress callback that drives a bar on a terminal (nothing when
/// `quiet` or not a terminal), then clears the bar.
pub(crate) fn with_progress_bar<T>(quiet: bool, job: impl FnOnce(&dyn Fn(&str, f64)) -> T) -> T {
    let bar = progress_bar(quiet);
    let result = job(&|stage, fraction| {
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

/// Set by Ctrl-C (SIGINT): the run stops at its next stage and writes nothing, so the
/// previous output set stays as it was (exit code 130). A second Ctrl-C exits at once.
pub(crate) static CANCELLED: AtomicBool = AtomicBool::new(false);

/// Installs the Ctrl-C handler that sets [`CANCELLED`].
pub(crate) fn stop_cleanly_on_interrupt() {
    let _ = ctrlc::set_handler(|| {
        if CANCELLED.swap(true, Ordering::SeqCst) {
            std::process::exit(130);
        }
    });
}

/// The directory `--assets-within` allows scenes to read from (set once by `main`).
pub(crate) static ASSETS_WITHIN: std::sync::OnceLock<PathBuf> = std::sync::OnceLock::new();

/// The library's run context for a scene or mesh in `root`, cancelled by Ctrl-C; its
/// assets confined to `root`, or to `--assets-within` when given.
fn run_context(root: PathBuf) -> RunContext<'static> {
    let mut context = RunContext::new(root).with_cancel(&CANCELLED);
    if let Some(allowed) = ASSETS_WITHIN.get() {
        context.assets = context.assets.with_confinement(allowed);
    }
    context
}

/// Writes the output set, unless Ctrl-C came after the run's last stage.
fn write_set(
    output: &std::path::Path,
    files: &[(String, Vec<u8>)],
    report: &sheetform::report::Report,
) -> Result<(), PipelineError> {
    if CANCELLED.load(Ordering::SeqCst) {
        return Err(PipelineError::Cancelled);
    }
    write_outputs(output, files, report)
}

pub(crate) fn bend_command(
    scene: PathBuf,
    output: PathBuf,
    animate: usize,
    pattern: PatternArgs,
    quiet: bool,
) -> Result<ExitCode, PipelineError> {
    let parsed = BendScene::from_json(&read_scene_file(&scene)?)?;
    let options = BendRunOptions {
        pattern: pattern.into(),
        animate_frames: animate,
        input: Some(scene.display().to_string()),
    };
    let result = with_progress_bar(quiet, |progress| {
        run_bend(
            &parsed,
            &options,
            &run_context(scene_directory(&scene)).with_progress(progress),
        )
    });
    match result {
        Ok(run) => {
            write_set(&output, &run.files, &run.report)?;
            if !quiet {
                let r = &run.report;
                say!(
                    "bent `{}`: {} rulings, {} faces, isometry error {:.1e}, admissible; wrote {} files to {}",
                    scene.display(),
                    r.ruling_count.unwrap_or(0),
                    r.face_count,
                    r.isometry_error_max_relative.unwrap_or(f64::NAN),
                    r.outputs.len(),
                    output.display()
                );
            }
            Ok(ExitCode::from(run.outcome.exit_code()))
        }
        Err(e) => {
            // An inadmissible shape: only the report, which says where.
            if let Some(report) = e.report() {
                write_set(&output, &[], report)?;
                say!("sheetform: {}: {e}", scene.display());
                say!(
                    "sheetform: no mesh written; {} says where",
                    output.join("report.json").display()
                );
                return Ok(ExitCode::from(e.kind().exit_code()));
            }
            Err(e)
        }
    }
}

pub(crate) fn slit_command(
    scene: PathBuf,
    output: PathBuf,
    pattern: PatternArgs,
    quiet: bool,
) -> Result<ExitCode, PipelineError> {
    let parsed = SlitScene::from_json(&read_scene_file(&scene)?)?;
    let options = SlitRunOptions {
        pattern: pattern.into(),
        input: Some(scene.display().to_string()),
    };
    let run = with_progress_bar(quiet, |progress| {
        run_slit(
            &parsed,
            &options,
            &run_context(scene_directory(&scene)).with_progress(progress),
        )
    })?;
    write_set(&output, &run.files, &run.report)?;
    if !quiet {
        let slit = run.report.slit.as_ref().expect("slit report");
        say!(
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
    Ok(ExitCode::from(run.outcome.exit_code()))
}

pub(crate) fn photo_command(
    annotation: PathBuf,
    output: PathBuf,
    back_side: Option<BackSideArg>,
    pattern: PatternArgs,
    quiet: bool,
) -> Result<ExitCode, PipelineError> {
    let input = PhotoInput::from_text(&read_scene_file(&annotation)?)?;
    let options = PhotoRunOptions {
        whole_object_tabs: auto_tabs(&pattern),
        pattern: pattern.into(),
        input: Some(annotation.display().to_string()),
        back_side: back_side.map(Into::into),
    };
    let run = with_progress_bar(quiet, |progress| {
        run_photo(
            &input,
            &options,
            &run_context(scene_directory(&annotation)).with_progress(progress),
        )
    })?;
    write_set(&output, &run.files, &run.report)?;
    let photo = run.report.photo.as_ref().expect("photo report");
    for warning in &run.report.warnings {
        say!("sheetform: warning: {}: {warning}", annotation.display());
    }
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
        say!(
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
        say!(
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
    Ok(ExitCode::from(run.outcome.exit_code()))
}

pub(crate) fn ffd_command(
    scene: PathBuf,
    output: PathBuf,
    solver: Option<SolverArg>,
    pattern: PatternArgs,
    quiet: bool,
) -> Result<ExitCode, PipelineError> {
    use sheetform::ffd::SolverMethod;
    let parsed = sheetform::ffd::FfdScene::from_json(&read_scene_file(&scene)?)?;
    let options = FfdRunOptions {
        pattern: pattern.into(),
        input: Some(scene.display().to_string()),
        solver: solver.map(|s| match s {
            SolverArg::Constrained => SolverMethod::Constrained,
            SolverArg::Paper => SolverMethod::Paper,
            SolverArg::None => SolverMethod::None,
        }),
        warm_start: None,
    };
    let run = with_progress_bar(quiet, |progress| {
        run_ffd(
            &parsed,
            &options,
            &run_context(scene_directory(&scene)).with_progress(progress),
        )
    })?;
    write_set(&output, &run.files, &run.report)?;
    if !quiet {
        let ffd = run.report.ffd.as_ref().expect("ffd report");
        say!(
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
    Ok(ExitCode::from(run.outcome.exit_code()))
}

/// Prints the JSON Schema of a scene format.
pub(crate) fn schema_command(format: SchemaFormat) -> ExitCode {
    let schema = match format {
        SchemaFormat::Bend => sheetform::bend::BendScene::json_schema(),
        SchemaFormat::Slit => sheetform::slit::SlitScene::json_schema(),
        SchemaFormat::Ffd => sheetform::ffd::FfdScene::json_schema(),
        SchemaFormat::Photo => sheetform::photo::PhotoAnnotation::json_schema(),
        SchemaFormat::Report => sheetform::report::Report::json_schema(),
    };
    print_out(&serde_json::to_string_pretty(&schema).expect("schema serialises"))
}

/// Writes `text` and a line break to standard output; a stdout that cannot take it (a
/// closed pipe, a full disk) is an output error (exit 1) said on stderr, not a panic
/// (`println!` panicked with exit 101).
fn print_out(text: &str) -> ExitCode {
    use std::io::Write as _;
    let mut out = std::io::stdout().lock();
    match writeln!(out, "{text}").and_then(|()| out.flush()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            say!("sheetform: could not write to standard output: {e}");
            ExitCode::from(sheetform::pipeline::ErrorKind::Output.exit_code())
        }
    }
}

/// `sheetform serve`: binds the editor's server, prints its address, serves until Ctrl-C.
pub(crate) fn serve_command(
    host: Option<std::net::IpAddr>,
    port: u16,
    root: PathBuf,
    open: bool,
    quiet: bool,
) -> ExitCode {
    let mut options = sheetform_serve::ServeOptions {
        port,
        root,
        ..Default::default()
    };
    if let Some(host) = host {
        options.host = host;
    }
    let server = match sheetform_serve::Server::bind(&options).and_then(|s| Ok((s.local_address()?, s))) {
        Ok(bound) => bound,
        Err(e) => {
            say!("sheetform: {e}");
            return ExitCode::from(1);
        }
    };
    let (address, server) = server;
    let url = format!("http://{address}/");
    // The address goes to stdout even with -q: scripts and tests read it there.
    if print_out(&url) != ExitCode::SUCCESS {
        return ExitCode::from(sheetform::pipeline::ErrorKind::Output.exit_code());
    }
    if !quiet {
        say!(
            "sheetform editor at {url}, serving the scene files of {} (Ctrl-C stops it)",
            options.root.display()
        );
    }
    if !sheetform_serve::EDITOR_EMBEDDED {
        say!(
            "sheetform: warning: this binary was built without npm, so the editor's three.js is not embedded: {url} \
             says so, the API works; install Node.js and npm and build again for the editor"
        );
    }
    if open {
        let opener = if cfg!(target_os = "macos") { "open" } else { "xdg-open" };
        if let Err(e) = std::process::Command::new(opener).arg(&url).spawn() {
            say!("sheetform: could not start a browser ({opener}: {e}); open {url} yourself");
        }
    }
    match server.run(&CANCELLED) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            say!("sheetform: {e}");
            ExitCode::from(1)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::{Arc, Mutex};

    /// A terminal that keeps the lines drawn on it.
    #[derive(Debug, Clone, Default)]
    struct Screen(Arc<Mutex<Vec<String>>>);

    impl indicatif::TermLike for Screen {
        fn width(&self) -> u16 {
            80
        }
        fn move_cursor_up(&self, _: usize) -> std::io::Result<()> {
            Ok(())
        }
        fn move_cursor_down(&self, _: usize) -> std::io::Result<()> {
            Ok(())
        }
        fn move_cursor_right(&self, _: usize) -> std::io::Result<()> {
            Ok(())
        }
        fn move_cursor_left(&self, _: usize) -> std::io::Result<()> {
            Ok(())
        }
        fn write_line(&self, s: &str) -> std::io::Result<()> {
            self.write_str(s)
        }
        fn write_str(&self, s: &str) -> std::io::Result<()> {
            if !s.is_empty() {
                self.0.lock().unwrap().push(s.to_string());
            }
            Ok(())
        }
        fn clear_line(&self) -> std::io::Result<()> {
            Ok(())
        }
        fn flush(&self) -> std::io::Result<()> {
            Ok(())
        }
    }

    /// Issue 19: the bar was drawn only when a stage reported progress, so during a long
    /// stage it froze. Updated once, it keeps redrawing with a turning spinner with no
    /// further call. (No timing is asserted: the test waits, up to a generous limit, for
    /// the spinner to show several different frames.)
    #[test]
    fn the_spinner_turns_between_progress_reports() {
        let screen = Screen::default();
        let bar = styled_progress_bar(ProgressDrawTarget::term_like(Box::new(screen.clone())));
        bar.set_position(300);
        bar.set_message("restoring");
        let frames = || {
            let lines = screen.0.lock().unwrap();
            let mut spinners: Vec<char> = lines.iter().filter_map(|l| l.chars().next()).collect();
            spinners.sort_unstable();
            spinners.dedup();
            spinners.len()
        };
        let give_up = std::time::Instant::now() + Duration::from_secs(30);
        while frames() < 3 && std::time::Instant::now() < give_up {
            std::thread::sleep(Duration::from_millis(20));
        }
        bar.finish_and_clear();
        assert!(frames() >= 3, "the bar was not redrawn: {:?}", screen.0.lock().unwrap());
    }
}
