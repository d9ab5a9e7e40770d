//! Edge unfolding of a faceted mesh into a net: pieces that are exact copies of the faces,
//! joined along the edges that are folded, with no piece overlapping itself.

use crate::{distortion, Chart, FlattenError, Vec2};
use rustc_hash::FxHashMap;
use sheetform_geometry::triangles_overlap;
use sheetform_mesh::{cut_along_edges, mesh_topology_with_edges, EdgeTable, TriangleMesh};
use sheetform_solve::SolverInfo;
use std::cmp::Reverse;
use std::collections::BinaryHeap;

type Vec3 = nalgebra::Vector3<f64>;

/// Knobs of [`unfold_net`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NetOptions {
    /// Starting faces tried; the net with the fewest pieces (then the shortest cut) is
    /// kept. Capped so that attempts × faces stays within [`MAX_NET_WORK`], and no
    /// further attempt starts once [`MAX_NET_OVERLAP_TESTS`] are spent. Default 12.
    pub attempts: usize,
    /// Join small pieces to a neighbour along one of their cut edges wherever they fit
    /// without overlap. Default true.
    pub merge_pieces: bool,
    /// Overlap tests the growth may make over all attempts, and again the merging:
    /// [`MAX_NET_OVERLAP_TESTS`] (the default) at most, larger values count as that.
    pub overlap_tests: usize,
}

impl Default for NetOptions {
    fn default() -> Self {
        Self {
            attempts: 12,
            merge_pieces: true,
            overlap_tests: MAX_NET_OVERLAP_TESTS,
        }
    }
}

/// Work budget of [`unfold_net`], in faces placed over all attempts (about a second).
pub const MAX_NET_WORK: usize = 4_000_000;

/// Work budget of [`unfold_net`] in overlap tests (a face of the piece examined against a
/// face being placed): over all attempts of the growth, and again for the merging of
/// pieces (about a second each; a torus of 160 000 faces takes 61 million in its 12
/// attempts). Faces that share one spot of the flat piece,
/// such as the thin triangles of a fan around one vertex, cannot be told apart by a
/// spatial index, and every placement is tested against all of them; a mesh that needs
/// more tests than this gets fewer attempts, its last growth joins a face only when
/// [`NET_TESTS_PER_FACE_WHEN_SPENT`] tests settle it (otherwise the edge is cut, counted
/// in [`Net::budget_cut_count`]), and the merging stops.
pub const MAX_NET_OVERLAP_TESTS: usize = 100_000_000;

/// Overlap tests a face may take to be joined to its piece once [`MAX_NET_OVERLAP_TESTS`]
/// is spent: a placement that needs more is refused and the edge cut (never an overlap).
pub const NET_TESTS_PER_FACE_WHEN_SPENT: usize = 64;

/// A net: the pieces (charts whose flattening is an exact copy of every face) and how
/// the mesh was cut.
#[derive(Debug, Clone, PartialEq)]
pub struct Net {
    /// The pieces, largest first.
    pub pieces: Vec<Chart>,
    /// Piece of every mesh face.
    pub face_piece: Vec<u32>,
    /// Edges kept whole across which the surface bends (the folds to make).
    pub fold_edge_count: usize,
    /// Edges with two faces that were cut (where pieces are glued back together).
    pub cut_edge_count: usize,
    /// Total length of the cut edges (model units; every cut edge counted once).
    pub cut_length: f64,
    /// Starting faces tried.
    pub attempts: usize,
    /// Pieces joined to a neighbour after the growth.
    pub merged_piece_count: usize,
    /// Edges cut only because [`MAX_NET_OVERLAP_TESTS`] was spent (the face would have
    /// needed more than [`NET_TESTS_PER_FACE_WHEN_SPENT`] tests to be joined); 0 unless
    /// the budget ran out.
    pub budget_cut_count: usize,
}

/// Unfolds `mesh` into a net: a forest of faces joined across edges, each tree laid flat
/// by hinging every face about its parent edge, with no two faces of one piece overlapping.
///
/// 1. **Growth** (greedy, Prim-like): a piece starts from a seed face laid flat; the
///    edges of its border wait in a priority queue, coplanar neighbours first (so flat
///    polygons of a faceted model stay whole, their diagonals never drawn), then by the
///    distance of the neighbour's flat centroid from the seed's (the piece grows as a
///    compact disk, which is what keeps nets of convex and nearly convex shapes in few
///    pieces). A popped neighbour not yet placed is laid flat across the edge — an exact
///    copy: the third corner from the law of cosines, `x = (w·e)/|e|`, `h = |e×w|/|e|`,
///    on the left of the edge as the face runs it — and kept when it overlaps no face of
///    the piece ([`triangles_overlap`] against the faces in the same cells of a uniform
///    grid, tolerance `1e-9 ×` the median edge length); otherwise the edge is cut and the
///    face waits for another edge or a later piece. A new piece starts from a face that
///    was refused (so pieces follow one another across the surface), else from any face
///    left. User seams (`mesh.seam_edges`) are always cut.
/// 2. **Attempts**: the growth is run from `options.attempts` seeds spread over the mesh
///    and the net with the fewest pieces, then the shortest total cut, is kept.
///    The work is bounded: attempts × faces by [`MAX_NET_WORK`], overlap tests by
///    [`MAX_NET_OVERLAP_TESTS`] (fewer attempts, then cuts counted in
///    [`Net::budget_cut_count`], when they run out).
/// 3. **Merging**: a piece, smallest first, is hinged onto a neighbouring piece across
///    one of the edges cut between them when it fits there without overlap (this gathers
///    the single faces and slivers a greedy growth leaves behind).
/// 4. **No zero-width slits**: a cut edge whose two faces lie in one piece with the edge
///    on the same place of both (around a flat interior vertex, where a tree of faces
///    has to leave one edge cut) is joined again.
///
/// The result has zero distortion by construction: every flat face is congruent to its 3D
/// face up to rounding. Published tools choose the spanning tree the same way in spirit
/// (Blender's Export Paper Model grows islands by edge priority, Pepakura and
/// rodrigorc/papercraft split overlapping islands); steepest-edge unfolding (Schlickrieder
/// 1997) is an alternative for convex polyhedra that this method does not need.
///
/// # Errors
/// Non-manifold, degenerate or non-orientable meshes (named); user seams that are not mesh
/// edges; an empty mesh.
pub fn unfold_net(mesh: &TriangleMesh, options: &NetOptions) -> Result<Net, FlattenError> {
    let (topology, table) = mesh_topology_with_edges(mesh);
    let problems = crate::exact_unfolding::topology_problems(&topology);
    if !problems.is_empty() {
        return Err(FlattenError::Topology {
            problem: problems.join("; "),
        });
    }
    let nf = mesh.triangles.len();
    if nf == 0 {
        return Err(FlattenError::Topology {
            problem: "the mesh has no faces".into(),
        });
    }
    let mut forced_cut = vec![false; table.len()];
    for e in crate::user_seam_edges(mesh, &table)? {
        forced_cut[e] = true;
    }
    // Every growth is tried as it is and with the fans of saddle vertices cut in two
    // (which pays on surfaces of negative curvature, where a growth closing around a
    // saddle leaves a face out).
    let mut saddle_cut = forced_cut.clone();
    for e in saddle_cuts(mesh, &table, &topology) {
        saddle_cut[e] = true;
    }
    let variants: Vec<&[bool]> = if saddle_cut == forced_cut {
        vec![&forced_cut]
    } else {
        vec![&forced_cut, &saddle_cut]
    };
    let faces = FaceGeometry::new(mesh, &table);
    let attempts = options.attempts.clamp(1, (MAX_NET_WORK / (nf * variants.len())).max(1));
    let mut best: Option<(Growth, usize)> = None;
    let overlap_tests = options.overlap_tests.min(MAX_NET_OVERLAP_TESTS);
    let mut tests_left = overlap_tests;
    // Seeds tried (fewer than `attempts` when the overlap tests ran out).
    let mut tried = 0;
    for (i, variant) in (0..attempts).flat_map(|i| (0..variants.len()).map(move |v| (i, v))) {
        if best.is_some() && tests_left == 0 {
            tracing::warn!(
                attempts = tried,
                "net: the budget of overlap tests is spent, no further attempt"
            );
            break;
        }
        tried = i + 1;
        let seed = if i == 0 {
            faces.central
        } else {
            (i * nf / attempts) as u32
        };
        let growth = grow(&faces, &table, variants[variant], seed, &mut tests_left);
        let better = best.as_ref().is_none_or(|(b, _)| {
            (growth.piece_count, growth.cut_length(&faces, &table)) < (b.piece_count, b.cut_length(&faces, &table))
        });
        tracing::debug!(seed, variant, pieces = growth.piece_count, "net attempt");
        if better {
            best = Some((growth, variant));
        }
    }
    let (mut growth, variant) = best.expect("at least one attempt");
    let attempts = tried;
    let forced_cut = variants[variant].to_vec();
    let before_merge = growth.piece_count;
    if options.merge_pieces {
        merge_pieces(&faces, &table, &forced_cut, overlap_tests, &mut growth);
    }
    let merged_piece_count = before_merge - growth.piece_count;
    close_zero_width_slits(&faces, &table, &forced_cut, &mut growth);

    // The pieces as charts: cut the mesh along every edge not kept.
    let cut: Vec<[u32; 2]> = (0..table.len())
        .filter(|&e| !growth.kept[e])
        .map(|e| table.edges[e])
        .collect();
    let opened = cut_along_edges(mesh, &cut);
    let mut flat = vec![Vec2::zeros(); opened.mesh.positions.len()];
    for (f, t) in opened.mesh.triangles.iter().enumerate() {
        for k in 0..3 {
            flat[t[k] as usize] = growth.flat[f][k];
        }
    }
    let mut members: Vec<Vec<u32>> = vec![Vec::new(); growth.piece_count];
    for f in 0..nf {
        members[growth.piece[f] as usize].push(f as u32);
    }
    members.sort_by(|a, b| b.len().cmp(&a.len()).then(a[0].cmp(&b[0])));
    let mut face_piece = vec![0u32; nf];
    let mut pieces = Vec::with_capacity(members.len());
    let mut local = vec![u32::MAX; opened.mesh.positions.len()];
    for (p, piece_faces) in members.into_iter().enumerate() {
        let mut vertices = Vec::new();
        let mut piece_flat = Vec::new();
        let mut positions = Vec::new();
        let triangles: Vec<[u32; 3]> = piece_faces
            .iter()
            .map(|&f| {
                face_piece[f as usize] = p as u32;
                opened.mesh.triangles[f as usize].map(|v| {
                    if local[v as usize] == u32::MAX {
                        local[v as usize] = vertices.len() as u32;
                        vertices.push(opened.origin[v as usize]);
                        piece_flat.push(flat[v as usize]);
                        positions.push(opened.mesh.positions[v as usize]);
                    }
                    local[v as usize]
                })
            })
            .collect();
        let sub = TriangleMesh {
            positions,
            face_groups: vec![0; triangles.len()],
            triangles: triangles.clone(),
            groups: vec!["piece".into()],
            corner_uvs: None,
            seam_edges: Vec::new(),
        };
        let d = distortion(&sub, &piece_flat);
        pieces.push(Chart {
            faces: piece_faces,
            vertices,
            triangles,
            flat: piece_flat,
            distortion: d,
            solver: SolverInfo {
                converged: true,
                ..Default::default()
            },
        });
    }
    let two_sided = |e: usize| table.sides(e).len() == 2;
    let fold_edge_count = (0..table.len())
        .filter(|&e| growth.kept[e] && two_sided(e) && faces.dihedral[e] > FLAT_DIHEDRAL)
        .count();
    let cut_edge_count = (0..table.len()).filter(|&e| !growth.kept[e] && two_sided(e)).count();
    Ok(Net {
        cut_length: growth.cut_length(&faces, &table),
        pieces,
        face_piece,
        fold_edge_count,
        cut_edge_count,
        attempts,
        merged_piece_count,
        budget_cut_count: growth.budget_cuts,
    })
}

/// Normals closer than this (radians) count as coplanar: such edges are kept first and
/// are no folds.
const FLAT_DIHEDRAL: f64 = 1e-6;

/// What the growth needs of every face and edge, computed once.
struct FaceGeometry<'a> {
    mesh: &'a TriangleMesh,
    /// Unsigned angle between the normals of the two faces on each edge (0 on the boundary).
    dihedral: Vec<f64>,
    /// Overlap tolerance (model units).
    tolerance: f64,
    /// Grid cell size (model units).
    cell: f64,
    /// The face nearest the centroid of all faces (the first seed).
    central: u32,
}

impl<'a> FaceGeometry<'a> {
    fn new(mesh: &'a TriangleMesh, table: &EdgeTable) -> Self {
        let nf = mesh.triangles.len();
        let dihedral = mesh.dihedral_angles(table);
        // The median edge length sets the grid's cells (robust where a few faces are far
        // larger than the rest, as on CAD meshes) and the tolerance.
        let mut lengths: Vec<f64> = table
            .edges
            .iter()
            .map(|&[a, b]| (mesh.positions[a as usize] - mesh.positions[b as usize]).norm())
            .collect();
        let middle = lengths.len() / 2;
        let median_edge = if lengths.is_empty() {
            0.0
        } else {
            *lengths.select_nth_unstable_by(middle, f64::total_cmp).1
        };
        let centroid = |f: usize| {
            let t = mesh.triangles[f];
            (mesh.positions[t[0] as usize] + mesh.positions[t[1] as usize] + mesh.positions[t[2] as usize]) / 3.0
        };
        let middle = (0..nf).map(centroid).sum::<Vec3>() / nf as f64;
        let central = (0..nf)
            .min_by(|&a, &b| (centroid(a) - middle).norm().total_cmp(&(centroid(b) - middle).norm()))
            .unwrap_or(0) as u32;
        Self {
            mesh,
            dihedral,
            tolerance: 1e-9 * median_edge,
            cell: 2.0 * median_edge.max(f64::MIN_POSITIVE),
            central,
        }
    }

    fn corner(&self, f: u32, k: usize) -> Vec3 {
        self.mesh.positions[self.mesh.triangles[f as usize][k % 3] as usize]
    }

    /// Face `f` laid flat with its corner `k` at `a` and corner `k + 1` at `b`: the flat
    /// positions of its three corners (the third on the left of `a → b`).
    fn hinge(&self, f: u32, k: usize, a: Vec2, b: Vec2) -> [Vec2; 3] {
        let (p, q, r) = (self.corner(f, k), self.corner(f, k + 1), self.corner(f, k + 2));
        let (e, w) = (q - p, r - p);
        let length = e.norm();
        let x = w.dot(&e) / length;
        let h = e.cross(&w).norm() / length;
        let u = (b - a).normalize();
        let c = a + u * x + Vec2::new(-u.y, u.x) * h;
        let mut out = [Vec2::zeros(); 3];
        out[k % 3] = a;
        out[(k + 1) % 3] = b;
        out[(k + 2) % 3] = c;
        out
    }

    /// Face `f` laid flat on its own, corner 0 at the origin, edge 0 along +x.
    fn alone(&self, f: u32) -> [Vec2; 3] {
        let length = (self.corner(f, 1) - self.corner(f, 0)).norm();
        self.hinge(f, 0, Vec2::zeros(), Vec2::new(length, 0.0))
    }
}

/// The faces of each piece in a uniform grid of their flat bounding boxes.
#[derive(Default)]
struct OverlapGrid {
    cells: FxHashMap<(i64, i64), Vec<u32>>,
    /// Faces too large for the cells (kept out of them, tested by every query).
    big: Vec<u32>,
    /// Every face, for queries too large for the cells.
    all: Vec<u32>,
}

/// Most grid cells a face is entered in (or a query looks at); larger faces go to the
/// grid's list of big faces, larger queries scan every face. Bounds the grid's memory and
/// work on meshes whose faces differ in size by orders of magnitude.
const MAX_CELLS_PER_FACE: i64 = 256;

impl OverlapGrid {
    fn range(cell: f64, t: &[Vec2; 3]) -> (i64, i64, i64, i64) {
        let lo = t[0].inf(&t[1]).inf(&t[2]);
        let hi = t[0].sup(&t[1]).sup(&t[2]);
        (
            (lo.x / cell).floor() as i64,
            (hi.x / cell).floor() as i64,
            (lo.y / cell).floor() as i64,
            (hi.y / cell).floor() as i64,
        )
    }

    fn too_many((x0, x1, y0, y1): (i64, i64, i64, i64)) -> bool {
        (x1 - x0 + 1).saturating_mul(y1 - y0 + 1) > MAX_CELLS_PER_FACE
    }

    fn insert(&mut self, cell: f64, t: &[Vec2; 3], f: u32) {
        self.all.push(f);
        let range = Self::range(cell, t);
        if Self::too_many(range) {
            self.big.push(f);
            return;
        }
        let (x0, x1, y0, y1) = range;
        for x in x0..=x1 {
            for y in y0..=y1 {
                self.cells.entry((x, y)).or_default().push(f);
            }
        }
    }

    /// Whether `t` overlaps a face of the grid, each face examined taking one test off
    /// `tests_left`; [`Overlap::Unsettled`] when they run out first.
    fn overlaps(
        &self,
        cell: f64,
        t: &[Vec2; 3],
        flat: &[[Vec2; 3]],
        tolerance: f64,
        tests_left: &mut usize,
    ) -> Overlap {
        // `Some(found)` per face examined, `None` once the tests are spent.
        let mut test = |g: &u32, in_box: &dyn Fn(&[Vec2; 3]) -> bool| {
            if *tests_left == 0 {
                return None;
            }
            *tests_left -= 1;
            let u = &flat[*g as usize];
            Some(in_box(u) && triangles_overlap(*t, *u, tolerance))
        };
        let anywhere = |_: &[Vec2; 3]| true;
        let verdict = |found: Option<bool>| match found {
            None => Some(Overlap::Unsettled),
            Some(true) => Some(Overlap::Yes),
            Some(false) => None,
        };
        let range = Self::range(cell, t);
        if Self::too_many(range) {
            // A large query: every face, after a bounding-box check.
            let (lo, hi) = (t[0].inf(&t[1]).inf(&t[2]), t[0].sup(&t[1]).sup(&t[2]));
            let in_box = |u: &[Vec2; 3]| {
                let (a, b) = (u[0].inf(&u[1]).inf(&u[2]), u[0].sup(&u[1]).sup(&u[2]));
                a.x <= hi.x && b.x >= lo.x && a.y <= hi.y && b.y >= lo.y
            };
            return self
                .all
                .iter()
                .find_map(|g| verdict(test(g, &in_box)))
                .unwrap_or(Overlap::No);
        }
        if let Some(v) = self.big.iter().find_map(|g| verdict(test(g, &anywhere))) {
            return v;
        }
        let (x0, x1, y0, y1) = range;
        for x in x0..=x1 {
            for y in y0..=y1 {
                if let Some(list) = self.cells.get(&(x, y)) {
                    if let Some(v) = list.iter().find_map(|g| verdict(test(g, &anywhere))) {
                        return v;
                    }
                }
            }
        }
        Overlap::No
    }
}

/// What [`OverlapGrid::overlaps`] found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Overlap {
    /// The face overlaps none of the grid.
    No,
    /// The face overlaps one of the grid.
    Yes,
    /// The tests ran out before the answer was known.
    Unsettled,
}

/// One growth of a net.
struct Growth {
    /// Flat corners of every face (in its piece's frame).
    flat: Vec<[Vec2; 3]>,
    /// Piece of every face.
    piece: Vec<u32>,
    /// Edges kept whole (a fold or a flat hinge inside a piece).
    kept: Vec<bool>,
    piece_count: usize,
    /// Placements refused only because the overlap tests ran out.
    budget_cuts: usize,
}

impl Growth {
    fn cut_length(&self, faces: &FaceGeometry, table: &EdgeTable) -> f64 {
        (0..table.len())
            .filter(|&e| !self.kept[e] && table.sides(e).len() == 2)
            .map(|e| {
                let [a, b] = table.edges[e];
                (faces.mesh.positions[a as usize] - faces.mesh.positions[b as usize]).norm()
            })
            .sum()
    }
}

/// An edge waiting in the growth's queue: `((flat first, distance bits), from face, its
/// corner starting the edge, face across)`, ordered by the key.
type HingeCandidate = ((u8, u64), u32, u8, u32);

/// Grows a net from `seed` (step 1 of [`unfold_net`]), each face of a piece examined
/// against a face being placed taking one test off `tests_left`; once they are spent, a
/// face is joined only when [`NET_TESTS_PER_FACE_WHEN_SPENT`] tests settle it.
fn grow(faces: &FaceGeometry, table: &EdgeTable, forced_cut: &[bool], seed: u32, tests_left: &mut usize) -> Growth {
    let mesh = faces.mesh;
    let nf = mesh.triangles.len();
    let mut growth = Growth {
        flat: vec![[Vec2::zeros(); 3]; nf],
        piece: vec![u32::MAX; nf],
        kept: vec![false; table.len()],
        piece_count: 0,
        budget_cuts: 0,
    };
    let mut refused: Vec<u32> = Vec::new();
    let mut next_any = 0usize;
    let mut start = Some(seed);
    let mut queue: BinaryHeap<Reverse<HingeCandidate>> = BinaryHeap::new();
    while let Some(s) = start {
        let p = growth.piece_count as u32;
        growth.piece_count += 1;
        let mut grid = OverlapGrid::default();
        growth.flat[s as usize] = faces.alone(s);
        growth.piece[s as usize] = p;
        grid.insert(faces.cell, &growth.flat[s as usize], s);
        let centre = |t: &[Vec2; 3]| (t[0] + t[1] + t[2]) / 3.0;
        let origin = centre(&growth.flat[s as usize]);
        let push = |f: u32, growth: &Growth, queue: &mut BinaryHeap<_>| {
            for k in 0..3 {
                let e = table.face_edges[f as usize][k];
                if e == u32::MAX || forced_cut[e as usize] {
                    continue;
                }
                if let Some(g) = table.opposite(f as usize, k) {
                    if growth.piece[g as usize] == u32::MAX {
                        let class = u8::from(faces.dihedral[e as usize] > FLAT_DIHEDRAL);
                        let t = &growth.flat[f as usize];
                        let middle = (t[k] + t[(k + 1) % 3]) * 0.5;
                        let distance = (middle - origin).norm();
                        queue.push(Reverse(((class, distance.to_bits()), f, k as u8, g)));
                    }
                }
            }
        };
        push(s, &growth, &mut queue);
        while let Some(Reverse((_, f, k, g))) = queue.pop() {
            if growth.piece[g as usize] != u32::MAX {
                continue;
            }
            let k = k as usize;
            let (a, b) = (mesh.triangles[f as usize][k], mesh.triangles[f as usize][(k + 1) % 3]);
            // g runs the edge b → a.
            let Some(j) =
                (0..3).find(|&j| mesh.triangles[g as usize][j] == b && mesh.triangles[g as usize][(j + 1) % 3] == a)
            else {
                continue;
            };
            let t = faces.hinge(g, j, growth.flat[f as usize][(k + 1) % 3], growth.flat[f as usize][k]);
            let mut allowance = NET_TESTS_PER_FACE_WHEN_SPENT;
            let budget = if *tests_left > 0 {
                &mut *tests_left
            } else {
                &mut allowance
            };
            match grid.overlaps(faces.cell, &t, &growth.flat, faces.tolerance, budget) {
                Overlap::No => {}
                Overlap::Yes => {
                    refused.push(g);
                    continue;
                }
                Overlap::Unsettled => {
                    growth.budget_cuts += 1;
                    refused.push(g);
                    continue;
                }
            }
            growth.flat[g as usize] = t;
            growth.piece[g as usize] = p;
            growth.kept[table.face_edges[f as usize][k] as usize] = true;
            grid.insert(faces.cell, &t, g);
            push(g, &growth, &mut queue);
        }
        start = refused
            .drain(..)
            .find(|&f| growth.piece[f as usize] == u32::MAX)
            .or_else(|| {
                while next_any < nf && growth.piece[next_any] != u32::MAX {
                    next_any += 1;
                }
                (next_any < nf).then_some(next_any as u32)
            });
    }
    growth
}

/// Keeps the cut edges whose two faces lie in one piece with the edge in the same place on
/// both (step 4 of [`unfold_net`]): around a flat interior vertex (the centre of a cap,
/// a point of a flat polygon) a tree of faces must leave one edge cut, a slit of zero
/// width that is no cut at all; it is joined again.
fn close_zero_width_slits(faces: &FaceGeometry, table: &EdgeTable, forced_cut: &[bool], growth: &mut Growth) {
    let mesh = faces.mesh;
    for (e, &forced) in forced_cut.iter().enumerate() {
        if growth.kept[e] || forced {
            continue;
        }
        let [f, g] = table.sides(e) else { continue };
        let (f, g) = (f.face as usize, g.face as usize);
        if growth.piece[f] != growth.piece[g] {
            continue;
        }
        let [a, b] = table.edges[e];
        let at = |face: usize, v: u32| {
            let k = mesh.triangles[face].iter().position(|&w| w == v).expect("edge vertex");
            growth.flat[face][k]
        };
        let length = (at(f, a) - at(f, b)).norm();
        let tolerance = 1e-9 * length.max(faces.tolerance);
        if (at(f, a) - at(g, a)).norm() <= tolerance && (at(f, b) - at(g, b)).norm() <= tolerance {
            growth.kept[e] = true;
        }
    }
}

/// Hinges small pieces onto neighbouring pieces where they fit (step 3 of [`unfold_net`]).
fn merge_pieces(
    faces: &FaceGeometry,
    table: &EdgeTable,
    forced_cut: &[bool],
    overlap_tests: usize,
    growth: &mut Growth,
) {
    let mesh = faces.mesh;
    let nf = mesh.triangles.len();
    // Work budget: overlap tests in all (estimated before each trial), and the tests
    // actually made.
    let mut budget = 20 * MAX_NET_WORK;
    let mut tests_left = overlap_tests;
    loop {
        if budget < nf {
            return;
        }
        budget -= nf;
        let mut members: Vec<Vec<u32>> = vec![Vec::new(); growth.piece_count];
        for f in 0..nf {
            members[growth.piece[f] as usize].push(f as u32);
        }
        let mut order: Vec<usize> = (0..members.len()).collect();
        order.sort_by_key(|&p| members[p].len());
        let mut merged = None;
        'pieces: for &p in &order {
            for &f in &members[p] {
                for k in 0..3 {
                    let e = table.face_edges[f as usize][k];
                    if e == u32::MAX || forced_cut[e as usize] || growth.kept[e as usize] {
                        continue;
                    }
                    let Some(g) = table.opposite(f as usize, k) else {
                        continue;
                    };
                    let q = growth.piece[g as usize] as usize;
                    if q == p {
                        continue;
                    }
                    let cost = members[p].len() * 8 + members[q].len();
                    if budget < cost {
                        return;
                    }
                    budget -= cost;
                    // Move piece p so that f's edge k lies on g's copy of the edge.
                    let (a, b) = (mesh.triangles[f as usize][k], mesh.triangles[f as usize][(k + 1) % 3]);
                    let Some(j) = (0..3)
                        .find(|&j| mesh.triangles[g as usize][j] == b && mesh.triangles[g as usize][(j + 1) % 3] == a)
                    else {
                        continue;
                    };
                    let (from_a, from_b) = (growth.flat[f as usize][k], growth.flat[f as usize][(k + 1) % 3]);
                    let (to_a, to_b) = (growth.flat[g as usize][(j + 1) % 3], growth.flat[g as usize][j]);
                    let (u, v) = ((from_b - from_a).normalize(), (to_b - to_a).normalize());
                    let (cos, sin) = (u.dot(&v), u.x * v.y - u.y * v.x);
                    let motion = |x: Vec2| {
                        let d = x - from_a;
                        to_a + Vec2::new(cos * d.x - sin * d.y, sin * d.x + cos * d.y)
                    };
                    let mut grid = OverlapGrid::default();
                    for &h in &members[q] {
                        grid.insert(faces.cell, &growth.flat[h as usize], h);
                    }
                    let moved: Vec<[Vec2; 3]> = members[p]
                        .iter()
                        .map(|&h| growth.flat[h as usize].map(motion))
                        .collect();
                    let mut fits = true;
                    for t in &moved {
                        match grid.overlaps(faces.cell, t, &growth.flat, faces.tolerance, &mut tests_left) {
                            Overlap::No => {}
                            Overlap::Yes => {
                                fits = false;
                                break;
                            }
                            Overlap::Unsettled => {
                                tracing::warn!("net: the budget of overlap tests for merging pieces is spent");
                                return;
                            }
                        }
                    }
                    if !fits {
                        continue;
                    }
                    merged = Some((p, q, e, moved));
                    break 'pieces;
                }
            }
        }
        let Some((p, q, e, moved)) = merged else { return };
        for (&h, t) in members[p].iter().zip(moved) {
            growth.flat[h as usize] = t;
            growth.piece[h as usize] = q as u32;
        }
        growth.kept[e as usize] = true;
        // Renumber: the last piece takes p's number.
        let last = (growth.piece_count - 1) as u32;
        for x in growth.piece.iter_mut() {
            if *x == last {
                *x = p as u32;
            }
        }
        growth.piece_count -= 1;
    }
}

/// Two edges at every saddle vertex (an interior vertex whose angles add up to more than
/// 2π) that split its fan into two chains of nearly equal angle: cut there, neither chain
/// wraps around past itself when laid flat (each is under 2π while the excess is under
/// 2π).
fn saddle_cuts(mesh: &TriangleMesh, table: &EdgeTable, topology: &sheetform_mesh::MeshTopology) -> Vec<usize> {
    let nv = mesh.positions.len();
    // For each vertex: (next neighbour around it, angle of the face between) per face.
    let mut fan: Vec<Vec<(u32, u32, f64)>> = vec![Vec::new(); nv];
    for t in &mesh.triangles {
        for k in 0..3 {
            let (v, a, b) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
            let (p, q) = (
                mesh.positions[a as usize] - mesh.positions[v as usize],
                mesh.positions[b as usize] - mesh.positions[v as usize],
            );
            fan[v as usize].push((a, b, p.cross(&q).norm().atan2(p.dot(&q))));
        }
    }
    let mut cuts = Vec::new();
    for (v, around) in fan.iter().enumerate() {
        if topology.boundary_vertex[v] || around.is_empty() {
            continue;
        }
        let total: f64 = around.iter().map(|x| x.2).sum();
        if total <= std::f64::consts::TAU + 1e-6 {
            continue;
        }
        // Order the fan: a_0 → a_1 → … around v (the first face starting at each
        // neighbour, looked up by it).
        let mut starting: FxHashMap<u32, usize> = FxHashMap::default();
        for (i, x) in around.iter().enumerate() {
            starting.entry(x.0).or_insert(i);
        }
        let mut order = vec![around[0]];
        while order.len() < around.len() {
            let last = order.last().expect("non-empty").1;
            match starting.get(&last).map(|&i| around[i]) {
                Some(next) if next.0 != order[0].0 => order.push(next),
                _ => break,
            }
        }
        if order.len() != around.len() {
            continue;
        }
        let best = if order.len() <= SMALL_FAN {
            halving_split_exhaustive(&order, total)
        } else {
            halving_split_sliding(&order, total)
        };
        for index in [best.1, best.2] {
            if let Some(e) = table.find(v as u32, order[index].0) {
                cuts.push(e);
            }
        }
    }
    cuts
}

/// Fans up to this many faces are split by trying every pair of edges (the result
/// depends on rounding when angles tie, as in symmetric meshes, and stays as it was);
/// larger fans by a sliding window, in time linear in the fan.
const SMALL_FAN: usize = 64;

/// The two edges `(miss, i, j)` of an ordered fan (`(from, to, angle)` per face) that
/// split its angles `total` most nearly in half: faces `i..j` (cyclically) on one side,
/// `miss` the distance of their sum from `total / 2`. Every pair tried, O(k²).
fn halving_split_exhaustive(order: &[(u32, u32, f64)], total: f64) -> (f64, usize, usize) {
    let k = order.len();
    let mut best = (f64::INFINITY, 0, 0);
    for i in 0..k {
        let mut sum = 0.0;
        for j in 1..k {
            sum += order[(i + j - 1) % k].2;
            let miss = (sum - 0.5 * total).abs();
            if miss < best.0 {
                best = (miss, i, (i + j) % k);
            }
        }
    }
    best
}

/// As [`halving_split_exhaustive`], in O(k): the angles are non-negative, so for each
/// start `i` the sums of `j` faces grow with `j`, and the best `j` is where the sum
/// crosses `total / 2` or the one before; that crossing only moves forward with `i`
/// (sums from prefix sums, so ties may go to another pair of equal miss).
fn halving_split_sliding(order: &[(u32, u32, f64)], total: f64) -> (f64, usize, usize) {
    let k = order.len();
    // prefix[n] = sum of the first n angles of the fan run twice.
    let mut prefix = Vec::with_capacity(2 * k + 1);
    prefix.push(0.0);
    for n in 0..2 * k {
        prefix.push(prefix[n] + order[n % k].2);
    }
    let half = 0.5 * total;
    let mut best = (f64::INFINITY, 0, 0);
    let mut j = 1;
    for i in 0..k {
        // Faces i..i+j (j of them, 1 ≤ j ≤ k − 1).
        j = j.max(1);
        while j < k - 1 && prefix[i + j] - prefix[i] < half {
            j += 1;
        }
        for jj in [j.saturating_sub(1).max(1), j] {
            let miss = (prefix[i + jj] - prefix[i] - half).abs();
            if miss < best.0 {
                best = (miss, i, (i + jj) % k);
            }
        }
        j = j.saturating_sub(1);
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 19: a saddle vertex of degree k was split in O(k²) (a fan of 40 000 faces,
    /// 1.6e9 sums). The sliding window finds a split as near to half as every pair tried.
    #[test]
    fn the_sliding_halving_split_is_as_good_as_trying_every_pair() {
        let mut seed = 7u64;
        let mut random = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for k in [3, 4, 5, 17, 65, 300] {
            for _ in 0..20 {
                let order: Vec<(u32, u32, f64)> = (0..k)
                    .map(|i| (i as u32, ((i + 1) % k) as u32, 0.01 + random() * random() * 2.0))
                    .collect();
                let total: f64 = order.iter().map(|x| x.2).sum();
                let exhaustive = halving_split_exhaustive(&order, total);
                let sliding = halving_split_sliding(&order, total);
                assert!(
                    (sliding.0 - exhaustive.0).abs() <= 1e-12 * total,
                    "{k}: {sliding:?} {exhaustive:?}"
                );
                // The split it names has the miss it reports.
                let (i, j) = (sliding.1, sliding.2);
                let count = (j + k - i) % k;
                let sum: f64 = (0..count).map(|n| order[(i + n) % k].2).sum();
                assert!(((sum - 0.5 * total).abs() - sliding.0).abs() <= 1e-12 * total);
            }
        }
    }
}
