//! Seams of a flat pattern: stretches of the cut outline that are glued to another
//! stretch, found from the 3D positions of the boundary vertices.

use rustc_hash::FxHashMap as HashMap;
use sheetform_mesh::SheetMesh;

/// A stretch of consecutive boundary edges on one cut loop that is glued to a stretch of
/// the same length elsewhere (on another piece or on the same one).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SeamRun {
    /// Index of the loop in [`SheetMesh::boundary_loops`] order.
    pub loop_index: usize,
    /// First edge of the run (edge `i` runs from loop vertex `i` to `i + 1`).
    pub start: usize,
    /// Number of edges.
    pub edges: usize,
    /// Seam ID (0-based), shared with the partner run.
    pub seam: usize,
    /// 0 for the run met first, 1 for its partner.
    pub side: u8,
}

/// The seams of `mesh`: boundary edges whose two end vertices coincide in 3D (within
/// `tolerance`) with the ends of another boundary edge are glued to it; maximal stretches
/// of glued edges whose partners are consecutive too form runs, and the two runs of one
/// seam share an ID. IDs number the seams in loop order.
pub fn match_seams(mesh: &SheetMesh, loops: &[Vec<u32>], tolerance: f64) -> Vec<SeamRun> {
    // 3D point ids for boundary vertices (grid hash, neighbouring cells searched).
    let cell = |p: &nalgebra::Vector3<f64>| [0, 1, 2].map(|k| (p[k] / tolerance).floor() as i64);
    let mut grid: HashMap<[i64; 3], Vec<(u32, usize)>> = HashMap::default();
    let mut point_of: HashMap<u32, usize> = HashMap::default();
    let mut points = 0usize;
    for &v in loops.iter().flatten() {
        if point_of.contains_key(&v) {
            continue;
        }
        let p = mesh.positions[v as usize];
        let c = cell(&p);
        let mut found = None;
        'search: for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    if let Some(list) = grid.get(&[c[0] + dx, c[1] + dy, c[2] + dz]) {
                        if let Some(&(_, id)) = list
                            .iter()
                            .find(|(w, _)| (mesh.positions[*w as usize] - p).norm() <= tolerance)
                        {
                            found = Some(id);
                            break 'search;
                        }
                    }
                }
            }
        }
        let id = found.unwrap_or_else(|| {
            points += 1;
            points - 1
        });
        grid.entry(c).or_default().push((v, id));
        point_of.insert(v, id);
    }
    // Boundary edges by their unordered 3D end points.
    let mut by_ends: HashMap<[usize; 2], Vec<(usize, usize)>> = HashMap::default();
    for (li, l) in loops.iter().enumerate() {
        for i in 0..l.len() {
            let (a, b) = (point_of[&l[i]], point_of[&l[(i + 1) % l.len()]]);
            if a != b {
                by_ends
                    .entry(if a < b { [a, b] } else { [b, a] })
                    .or_default()
                    .push((li, i));
            }
        }
    }
    let mut partner: HashMap<(usize, usize), (usize, usize)> = HashMap::default();
    for list in by_ends.values() {
        if let [x, y] = list[..] {
            partner.insert(x, y);
            partner.insert(y, x);
        }
    }
    // `e` continues the run of the edge before it when both are glued and their partners
    // are consecutive (in reverse) on one loop, unless the two are each other's partners:
    // at the apex of a slit (a seam folding back on itself around one vertex, as at the
    // leaves of a net's cut tree) one run ends and its partner begins. Without that
    // break, a run and its partner would be one run glued to itself: one ID for both
    // copies, tabs on both.
    let continues = |li: usize, i: usize| {
        let n = loops[li].len();
        let prev = (li, (i + n - 1) % n);
        match (partner.get(&(li, i)), partner.get(&prev)) {
            (Some(&p), Some(&(ql, qi))) => p != prev && p.0 == ql && (p.1 + 1) % loops[p.0].len() == qi,
            _ => false,
        }
    };
    let mut runs: Vec<SeamRun> = Vec::new();
    let mut run_of_edge: HashMap<(usize, usize), usize> = HashMap::default();
    for (li, l) in loops.iter().enumerate() {
        let n = l.len();
        // Start where a run begins (or at 0 when the whole loop is one run).
        let first = (0..n).find(|&i| !continues(li, i)).unwrap_or(0);
        let mut i = 0;
        while i < n {
            let e = (first + i) % n;
            if !partner.contains_key(&(li, e)) {
                i += 1;
                continue;
            }
            let mut len = 1;
            while i + len < n && continues(li, (first + i + len) % n) {
                len += 1;
            }
            for j in 0..len {
                run_of_edge.insert((li, (e + j) % n), runs.len());
            }
            runs.push(SeamRun {
                loop_index: li,
                start: e,
                edges: len,
                seam: usize::MAX,
                side: 0,
            });
            i += len;
        }
    }
    let mut next_id = 0;
    for r in 0..runs.len() {
        if runs[r].seam != usize::MAX {
            continue;
        }
        runs[r].seam = next_id;
        runs[r].side = 0;
        let key = (runs[r].loop_index, runs[r].start);
        if let Some(&q) = partner.get(&key).and_then(|p| run_of_edge.get(p)) {
            if q != r && runs[q].seam == usize::MAX {
                runs[q].seam = next_id;
                runs[q].side = 1;
            }
        }
        next_id += 1;
    }
    runs
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Vector2, Vector3};
    use sheetform_mesh::{LengthUnit, Piece, PieceKind};

    /// A cone opened along one ruling: a fan of `n` faces around the apex, laid flat with
    /// the gap of its angle defect between the first and the last ruling. The cut ruling's
    /// two copies meet at the apex, one after the other on the outline.
    fn opened_cone(n: usize) -> SheetMesh {
        let (radius, height) = (30.0, 40.0);
        let slant = f64::hypot(radius, height);
        let mut positions = vec![Vector3::new(0.0, 0.0, height)];
        let mut flat = vec![Vector2::zeros()];
        // The flat sector's angle: the circumference over the slant height.
        let sector = std::f64::consts::TAU * radius / slant;
        for i in 0..=n {
            let t = i as f64 / n as f64;
            let a = std::f64::consts::TAU * t;
            positions.push(Vector3::new(radius * a.cos(), radius * a.sin(), 0.0));
            flat.push(Vector2::new((sector * t).cos(), (sector * t).sin()) * slant);
        }
        // The last rim point is the first one in 3D.
        positions[n + 1] = positions[1];
        SheetMesh {
            positions,
            flat,
            triangles: (0..n as u32).map(|i| [0, i + 1, i + 2]).collect(),
            face_pieces: vec![0; n],
            pieces: vec![Piece {
                name: "cone".into(),
                kind: PieceKind::Chart,
            }],
            rulings: vec![],
            smooth_edges: vec![],
            unit: LengthUnit::Mm,
        }
    }

    /// Issue 34: the two copies of a cut ruling meet at the apex, consecutive on the
    /// outline. They are two runs of one seam (sides 0 and 1), not one run glued to
    /// itself (which printed the ID on one copy and a tab on both).
    #[test]
    fn a_seam_folding_back_at_an_apex_is_two_runs() {
        let mesh = opened_cone(12);
        let loops = mesh.boundary_loops();
        assert_eq!(loops.len(), 1);
        let runs = match_seams(&mesh, &loops, 1e-9);
        assert_eq!(runs.len(), 2, "{runs:?}");
        assert_eq!((runs[0].seam, runs[1].seam), (0, 0));
        assert_eq!((runs[0].edges, runs[1].edges), (1, 1));
        let mut sides = [runs[0].side, runs[1].side];
        sides.sort_unstable();
        assert_eq!(sides, [0, 1]);
        assert_ne!(runs[0].start, runs[1].start);
    }
}
