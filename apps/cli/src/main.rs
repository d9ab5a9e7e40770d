//! `sheetform`: the command-line front end. Thin: it parses arguments and scenes
//! (`args`), calls the library pipeline with a context rooted at the scene's directory,
//! shows progress, writes the outputs (`commands`) and exits with the code the library
//! decided (`Outcome::exit_code`, `ErrorKind::exit_code`).
//!
//! Exit codes: 0 success, 1 invalid input or I/O error, 2 usage error (from clap),
//! 3 shape not admissible (only `report.json` is written, saying where), 4 flattened
//! pattern overlaps itself (written, flagged in the report), 5 a result outside a stated
//! tolerance (written, flagged: an FFD restoration or slit strip not converged, a photo
//! patch not developable to the bound or a curve whose depth the drawing does not fix),
//! 130 cancelled.

/// A message on standard error; a stderr that cannot be written (closed, a full disk) is
/// ignored: there is nowhere else to say it, and `eprintln!` would panic (exit 101).
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stderr(), $($arg)*);
    }};
}

mod args;
mod commands;

use args::{Cli, Command};
use clap::Parser;
use commands::{
    bend_command, check_command, develop_command, ffd_command, flatten_command, photo_command, schema_command,
    serve_command, slit_command, FlattenArgs,
};
use std::process::ExitCode;

// The pipeline allocates and frees arrays of a few hundred KB per run; glibc's malloc
// returns them to the OS each time (page faults), mimalloc keeps them: ~1.5x faster
// bends (docs/benchmarks-history.md).
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() -> ExitCode {
    let cli = Cli::parse();
    commands::stop_cleanly_on_interrupt();
    if let Some(allowed) = cli.assets_within.clone() {
        let _ = commands::ASSETS_WITHIN.set(allowed);
    }
    // `SHEETFORM_TRACE=1`: the solvers' per-iteration traces on stderr.
    if std::env::var_os("SHEETFORM_TRACE").is_some() {
        tracing_subscriber::fmt()
            .with_max_level(tracing::Level::DEBUG)
            .with_writer(std::io::stderr)
            .without_time()
            .init();
    }
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
            back_side,
            pattern,
        } => photo_command(annotation, output, back_side, pattern, cli.quiet),
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
            size,
            method,
            charts,
            pattern,
        } => flatten_command(
            mesh,
            output,
            FlattenArgs {
                weld,
                units,
                size,
                method,
                charts,
                pattern,
            },
            cli.quiet,
        ),
        Command::Develop {
            mesh,
            output,
            units,
            size,
            seams,
            max_pieces,
            normal_tolerance,
            cone_angle,
            fixed,
            max_distance,
            work_faces,
            mirror,
            seam_smoothing,
            smoothness,
            tolerance,
            max_iterations,
            pattern,
        } => develop_command(
            mesh,
            output,
            units,
            size,
            sheetform::pipeline::DevelopRunOptions {
                seams: seams.into(),
                max_distance,
                segmentation: sheetform::pipeline::SegmentationOptions {
                    max_pieces,
                    normal_tolerance_degrees: normal_tolerance,
                    cone_point_radians: cone_angle.to_radians(),
                    ..Default::default()
                },
                fixed_groups: fixed,
                work_faces: Some(work_faces),
                mirror,
                seam_smoothing: sheetform::pipeline::SeamSmoothingOptions {
                    iterations: seam_smoothing,
                    ..Default::default()
                },
                develop: sheetform::pipeline::DevelopOptions {
                    smoothness,
                    defect_tolerance: tolerance,
                    max_iterations,
                    ..Default::default()
                },
                ..Default::default()
            },
            pattern,
            cli.quiet,
        ),
        Command::Schema { format } => Ok(schema_command(format)),
        Command::Serve { host, port, root, open } => return serve_command(host, port, root, open, cli.quiet),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            say!("sheetform: {e}");
            ExitCode::from(e.kind().exit_code())
        }
    }
}
