//! Development probe.
use sheetform_bend::*;
fn main() {
    let a: Vec<String> = std::env::args().collect();
    let scene = BendScene::from_json(&std::fs::read_to_string(&a[1]).unwrap()).unwrap();
    let model = BendModel::from_scene(&scene).unwrap();
    let g = region_geometry(&model, 0).unwrap();
    for j in [0usize, 1] {
        let (s, e) = (&g.samples[j], &g.extents[j]);
        println!("ruling {j} p {:?} r {:?} ext [{}, {}] touches {:?} ends {:?}", s.flat_point.as_slice(), s.flat_ruling.as_slice(), e.negative_end, e.positive_end, e.touches, e.ends);
    }
}
