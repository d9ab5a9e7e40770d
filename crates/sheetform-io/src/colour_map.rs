use sheetform_mesh::TriangleMesh;
use std::fmt::Write;

/// A perceptually ordered blue → white → red ramp for `t ∈ [0, 1]` (values outside are
/// clamped; NaN is grey): blue where a measure is zero, red at the top of the scale, as
/// in Wang & Tang's developability detection map (Fig. 4).
pub fn colour_ramp(t: f64) -> [f32; 3] {
    if !t.is_finite() {
        return [0.5, 0.5, 0.5];
    }
    let t = t.clamp(0.0, 1.0) as f32;
    let blue = [0.17, 0.35, 0.78];
    let white = [0.97, 0.97, 0.95];
    let red = [0.80, 0.12, 0.12];
    let (a, b, u) = if t < 0.5 {
        (blue, white, t * 2.0)
    } else {
        (white, red, t * 2.0 - 1.0)
    };
    [
        a[0] + (b[0] - a[0]) * u,
        a[1] + (b[1] - a[1]) * u,
        a[2] + (b[2] - a[2]) * u,
    ]
}

/// ASCII PLY of a triangle mesh with a colour per vertex (`red green blue` as bytes) and
/// the measure itself as a float property `value` per vertex.
pub fn ply_vertex_colours(mesh: &TriangleMesh, colours: &[[f32; 3]], values: &[f64], value_name: &str) -> String {
    let mut s = String::with_capacity(mesh.positions.len() * 48 + mesh.triangles.len() * 16);
    let _ = writeln!(s, "ply\nformat ascii 1.0\ncomment sheetform colour map: {value_name}");
    let _ = writeln!(s, "element vertex {}", mesh.positions.len());
    let _ = writeln!(s, "property double x\nproperty double y\nproperty double z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nproperty double {value_name}");
    let _ = writeln!(
        s,
        "element face {}\nproperty list uchar int vertex_indices\nend_header",
        mesh.triangles.len()
    );
    for ((p, c), v) in mesh.positions.iter().zip(colours).zip(values) {
        let b = c.map(|x| (x.clamp(0.0, 1.0) * 255.0).round() as u8);
        let _ = writeln!(s, "{} {} {} {} {} {} {}", p.x, p.y, p.z, b[0], b[1], b[2], v);
    }
    for t in &mesh.triangles {
        let _ = writeln!(s, "3 {} {} {}", t[0], t[1], t[2]);
    }
    s
}
