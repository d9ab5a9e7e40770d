//! Where the time of one bend goes, stage by stage, on `examples/bent-rectangle.json`
//! with N rulings (the figures of the stage split in docs/benchmarks-history.md):
//!
//! ```sh
//! cargo run --release -p sheetform-bend --example stage_timings -- 1000
//! ```
//!
//! Each stage is repeated enough times to take about half a second and its mean time is
//! printed. The stages are those of [`sheetform_bend::bend`]; the example checks that the
//! bend it times is admissible and exactly isometric.

#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

use sheetform_bend::{
    bend, flat_layout, place, region_geometries, ruling_extent, sample_rulings, BendModel, BendScene, FoldedStrip,
};
use std::hint::black_box;

fn main() {
    let rulings: usize = std::env::args()
        .nth(1)
        .map_or(1000, |a| a.parse().expect("N is a number"));
    let mut scene =
        BendScene::from_json(include_str!("../../../examples/bent-rectangle.json")).expect("example parses");
    scene.tessellation.rulings = Some(rulings);
    let model = BendModel::from_scene(&scene).expect("example is valid");
    let bent = bend(&model).expect("the example is admissible");
    let error = sheetform_mesh::isometry_error(&bent.mesh).max_relative;
    assert!(error < 1e-9, "the bend is an exact isometry ({error})");

    let repetitions = (400_000 / rulings).max(4);
    let time = |label: &str, f: &mut dyn FnMut()| {
        for _ in 0..repetitions / 4 {
            f();
        }
        let start = std::time::Instant::now();
        for _ in 0..repetitions {
            f();
        }
        println!("N = {rulings}: {label:<28} {:?}", start.elapsed() / repetitions as u32);
    };
    let region = &model.regions[0];
    let tessellation = &model.tessellation;
    time("sample rulings", &mut || {
        black_box(sample_rulings(0, "r", &region.curve, &region.flat, region.up, tessellation).expect("samples"));
    });
    let samples = sample_rulings(0, "r", &region.curve, &region.flat, region.up, tessellation).expect("samples");
    let scale = model.sheet.scale();
    time("ruling extents", &mut || {
        for s in &samples {
            black_box(ruling_extent(&model.sheet, s.flat_point, s.flat_ruling, scale));
        }
    });
    time("geometries (the two + Eq. 6)", &mut || {
        black_box(region_geometries(&model).expect("admissible"));
    });
    let geometries = region_geometries(&model).expect("admissible");
    time("flat layout (cut the sheet)", &mut || {
        black_box(flat_layout(&model, &geometries).expect("layout"));
    });
    time("strip motions", &mut || {
        black_box(
            geometries
                .iter()
                .map(|g| FoldedStrip::new(&g.samples))
                .collect::<Vec<_>>(),
        );
    });
    let strips: Vec<FoldedStrip> = geometries.iter().map(|g| FoldedStrip::new(&g.samples)).collect();
    let layout = flat_layout(&model, &geometries).expect("layout");
    time("place pieces", &mut || {
        black_box(place(&model, &layout, &strips).expect("placed"));
    });
    time("whole bend", &mut || {
        black_box(bend(&model).expect("admissible"));
    });
}
