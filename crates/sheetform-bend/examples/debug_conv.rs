//! Convergence probe (development aid).
use sheetform_bend::*;
use sheetform_geometry::*;
use sheetform_mesh::*;
fn main() {
    let helix = Helix::new(10.0, 3.0, 0.0, 2.0).unwrap();
    let length = 2.0 * (109.0f64).sqrt();
    for deg in [4.0, 2.0, 1.0, 0.5, 0.25] {
        let sheet = Polygon::new(vec![Vec2::new(0.0, -5.0), Vec2::new(length, -5.0), Vec2::new(length, 5.0), Vec2::new(0.0, 5.0)], vec![]).unwrap();
        let model = BendModel { name: None, unit: LengthUnit::Mm, sheet, regions: vec![CurvedRegion { name: "t".into(), curve: ControlCurve::new(CurveShape::Helix(helix)).unwrap(), flat_start: Vec2::zeros(), flat_direction: Vec2::x(), up: Vec3::z(), closed: false }], tessellation: TessellationOptions { max_fold_angle_degrees: deg, ..Default::default() } };
        let b = bend(&model).unwrap();
        let m = &b.mesh;
        let mut worst = (0.0, 0usize);
        for (t, &p) in m.triangles.iter().zip(&m.face_pieces) {
            if m.pieces[p as usize].kind != PieceKind::Curved { continue; }
            for &v in t { let q = m.positions[v as usize]; let e = ((q.x*q.x+q.y*q.y).sqrt() - 10.0).abs(); if e > worst.0 { worst = (e, v as usize); } }
        }
        let iso = isometry_error(m);
        println!("deg {deg} rulings {} err {:.3e} at flat {:?} dev {:.3e} iso {:.3e} edge {:?} len {:.3e}", b.regions[0].ruling_count, worst.0, m.flat[worst.1].as_slice(), b.regions[0].curve_deviation, iso.max_relative, iso.worst_edge, (m.flat[iso.worst_edge[0] as usize]-m.flat[iso.worst_edge[1] as usize]).norm());
    }
}
