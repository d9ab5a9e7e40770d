//! The FFD pipeline reports its progress: stages in order, a fraction that never
//! decreases from 0 to 1, and one report per iteration of each restoration.

use sheetform::ffd::FfdScene;
use sheetform::pipeline::{run_ffd, FfdRunOptions, RunContext};
use std::cell::RefCell;

#[test]
fn ffd_run_reports_each_restoration_iteration_with_a_rising_fraction() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/ffd/trousers.json");
    let text = std::fs::read_to_string(&path).unwrap();
    let events: RefCell<Vec<(String, f64)>> = RefCell::new(Vec::new());
    let record = |stage: &str, fraction: f64| events.borrow_mut().push((stage.to_string(), fraction));
    let context = RunContext::new(path.parent().unwrap()).with_progress(&record);
    let run = run_ffd(
        &FfdScene::from_json(&text).unwrap(),
        &FfdRunOptions::default(),
        &context,
    )
    .unwrap();
    let events = events.into_inner();
    assert_eq!(events.first().unwrap(), &("reading scene".to_string(), 0.0));
    assert_eq!(events.last().unwrap(), &("done".to_string(), 1.0));
    assert!(events.windows(2).all(|w| w[0].1 <= w[1].1), "{events:?}");
    assert!(events.iter().all(|(_, f)| (0.0..=1.0).contains(f)));
    // Iteration 0 and every iteration of both deformations, then the export.
    for (k, step) in run.design.steps.iter().enumerate() {
        let prefix = format!("deformation {}/2: iteration ", k + 1);
        let reported = events.iter().filter(|(s, _)| s.starts_with(&prefix)).count();
        assert_eq!(reported, step.info.iterations + 1, "{prefix}");
    }
    let exporting = events.iter().position(|(s, _)| s == "exporting").unwrap();
    assert!(events[..exporting]
        .iter()
        .any(|(s, _)| s.starts_with("deformation 2/2")));
    // The last restoration converged: its share of the bar is full before the export.
    assert!(
        (events[exporting - 1].1 - 0.9).abs() < 1e-12,
        "{:?}",
        events[exporting - 1]
    );
}
