//! Edge unfolding of a faceted mesh into a net: pieces that are exact copies of the faces,
//! joined along the edges that are folded, with no piece overlapping itself.

use crate::island_joining::{IslandLimits, Islands, Join};
use crate::{distortion, Chart, FlattenError, Vec2};
use rustc_hash::FxHashMap;
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
    /// Cutting clearance (model units): two cut lines of one piece that share no point
    /// stay this far apart. Default 0 (no overlap only).
    pub clearance: f64,
    /// Two cut lines of one piece that share no point but end at the same mesh vertex
    /// (the sides of a slit beyond its apex, two copies of one seam facing each other)
    /// stay this far apart (model units): with glue tabs, room for the smallest tab and
    /// its clearance. Default 0.
    pub slit_clearance: f64,
    /// Every piece fits a rectangle of this size (model units), turned as needed
    /// (`None`, the default: any size).
    pub sheet: Option<(f64, f64)>,
}

impl Default for NetOptions {
    fn default() -> Self {
        Self {
            attempts: 12,
            merge_pieces: true,
            overlap_tests: MAX_NET_OVERLAP_TESTS,
            clearance: 0.0,
            slit_clearance: 0.0,
            sheet: None,
        }
    }
}

/// Most faces [`unfold_net`] unfolds: a net is a papercraft model's pattern, facet by
/// facet; a mesh of more facets makes a pattern of thousands of pieces nobody assembles
/// (Blender's Export Paper Model asks for an island-size limit long before). `flatten`
/// lays out larger faceted meshes in smooth charts.
pub const MAX_NET_FACES: usize = 50_000;

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
/// by hinging every face about its parent edge, every piece one a maker can cut and glue.
///
/// Every join goes through one move (`Islands::try_join`, island_joining.rs): the
/// smaller island is hinged onto the larger across the edge — every face an exact copy,
/// the third corner from the law of cosines, `x = (w·e)/|e|`, `h = |e×w|/|e|` — and kept
/// only when no face of one overlaps a face of the other (the separating-axis test,
/// tolerance `1e-9 ×` the median edge length, faces found in uniform grids), no cut line
/// of one comes within `options.clearance` of a cut line of the other unless the two
/// meet, the two sides of a slit (cut lines ending at one mesh vertex) stay
/// `options.slit_clearance` apart (room for a glue tab), and the union fits
/// `options.sheet`. Otherwise the edge stays cut.
///
/// 1. **Growth** from a seed face: the edges of a piece's border wait in a priority
///    queue, coplanar neighbours first (so flat polygons of a faceted model stay whole,
///    their diagonals never drawn), then either nearest to the seed first (a **compact**
///    disk, which keeps nets of convex and nearly convex shapes in few pieces) or newest
///    first (depth first: a winding **strip**, every vertex on its border, which needs no
///    narrow slit on a curved shape where a disk does). A refused face waits for another
///    edge or a later piece; a new piece starts from a face that was refused (so pieces
///    follow one another across the surface), else from any face left. User seams
///    (`mesh.seam_edges`) are always cut.
/// 2. **Attempts**: compact and strip growths take turns from `options.attempts` seeds
///    spread over the mesh (the first two from the central face), and the net with the
///    fewest pieces, then the shortest total cut, is kept. The work is bounded: attempts
///    × faces by [`MAX_NET_WORK`], overlap tests by [`MAX_NET_OVERLAP_TESTS`] (fewer
///    attempts, then cuts counted in [`Net::budget_cut_count`], when they run out).
/// 3. **Joining pieces**: the edges cut between two pieces, those of the smallest pieces
///    first, hinge them together where they fit (this gathers the single faces and slivers
///    a greedy growth leaves behind), in passes until one joins nothing; on a growth with
///    the saddles' fans cut, then across those cuts too.
/// 4. **No zero-width slits**: a cut edge but a user's seam whose two faces lie in one
///    piece with the edge on the same place of both (around a flat interior vertex,
///    where a tree of faces has to leave one edge cut, or a saddle's cut the growth
///    closed around after all) is joined again.
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
/// A mesh of more than [`MAX_NET_FACES`] faces is refused.
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
    if nf > MAX_NET_FACES {
        return Err(FlattenError::TooManyPieces {
            what: "a net unfolds every facet and this mesh has more facets than a net is made of".into(),
            count: nf,
            bound: MAX_NET_FACES,
            advice: "decimate it to a papercraft model first, or flatten it in smooth charts (--charts smooth)".into(),
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
    let non_negative = |x: f64| if x.is_finite() { x.max(0.0) } else { 0.0 };
    let limits = IslandLimits {
        clearance: non_negative(options.clearance),
        slit_clearance: non_negative(options.slit_clearance),
        sheet: options.sheet,
    };
    // (growth, its variant, pieces before they were joined to each other)
    let mut best: Option<(Growth, usize, usize)> = None;
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
        let mut islands = Islands::new(&faces, &table, limits);
        // Compact and strip growths take turns (the first seed grows both).
        let order = if i % 2 == 0 {
            GrowthOrder::Compact
        } else {
            GrowthOrder::Strip
        };
        let seed = if i == 1 { faces.central } else { seed };
        grow(
            &mut islands,
            &faces,
            &table,
            variants[variant],
            seed,
            order,
            &mut tests_left,
        );
        let grown = islands.count();
        if options.merge_pieces {
            join_pieces(&mut islands, &faces, &table, variants[variant], &mut tests_left);
            if variant > 0 {
                // The saddles' cuts kept the growth from closing around them; pieces that
                // meet across one are joined where they fit.
                join_pieces(&mut islands, &faces, &table, &forced_cut, &mut tests_left);
            }
        }
        let mut growth = islands.into_growth();
        close_zero_width_slits(&faces, &table, &forced_cut, &mut growth);
        let better = best.as_ref().is_none_or(|(b, _, _)| {
            (growth.piece_count, growth.cut_length(&faces, &table)) < (b.piece_count, b.cut_length(&faces, &table))
        });
        tracing::debug!(seed, variant, grown, pieces = growth.piece_count, "net attempt");
        if better {
            best = Some((growth, variant, grown));
        }
    }
    let (growth, _, grown) = best.expect("at least one attempt");
    let attempts = tried;
    let merged_piece_count = grown - growth.piece_count;

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
pub(crate) const FLAT_DIHEDRAL: f64 = 1e-6;

/// What the growth needs of every face and edge, computed once.
pub(crate) struct FaceGeometry<'a> {
    pub(crate) mesh: &'a TriangleMesh,
    /// Unsigned angle between the normals of the two faces on each edge (0 on the boundary).
    pub(crate) dihedral: Vec<f64>,
    /// Overlap tolerance (model units).
    pub(crate) tolerance: f64,
    /// Grid cell size (model units).
    pub(crate) cell: f64,
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
    pub(crate) fn alone(&self, f: u32) -> [Vec2; 3] {
        let length = (self.corner(f, 1) - self.corner(f, 0)).norm();
        self.hinge(f, 0, Vec2::zeros(), Vec2::new(length, 0.0))
    }
}

/// One growth of a net.
pub(crate) struct Growth {
    /// Flat corners of every face (in its piece's frame).
    pub(crate) flat: Vec<[Vec2; 3]>,
    /// Piece of every face.
    pub(crate) piece: Vec<u32>,
    /// Edges kept whole (a fold or a flat hinge inside a piece).
    pub(crate) kept: Vec<bool>,
    pub(crate) piece_count: usize,
    /// Placements refused only because the overlap tests ran out.
    pub(crate) budget_cuts: usize,
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

/// In which order a piece of a net grows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum GrowthOrder {
    /// Nearest to the seed first: the piece grows as a compact disk (few pieces on convex
    /// and nearly convex shapes, narrow slits between its arms on curved ones).
    Compact,
    /// Newest neighbour first (depth first): the piece grows as a winding strip, every
    /// vertex on its border, with room between its turns (no narrow slits on curved
    /// shapes, where a disk has them).
    Strip,
}

/// Grows the pieces of a net from `seed` (step 1 of [`unfold_net`]): the edges of a
/// piece's border wait in a priority queue, coplanar neighbours first, then in `order`;
/// a popped face not yet in a piece is hinged on ([`Islands::try_join`]), or waits for
/// another edge or a later piece. A new piece starts from a face that was refused, else
/// from any face left. Once the overlap tests are spent, a face is joined only when
/// [`NET_TESTS_PER_FACE_WHEN_SPENT`] tests settle it.
fn grow(
    islands: &mut Islands,
    faces: &FaceGeometry,
    table: &EdgeTable,
    forced_cut: &[bool],
    seed: u32,
    order: GrowthOrder,
    tests_left: &mut usize,
) {
    let nf = faces.mesh.triangles.len();
    let mut grown = vec![false; nf];
    let mut refused: Vec<u32> = Vec::new();
    let mut next_any = 0usize;
    let mut start = Some(seed);
    let mut queue: BinaryHeap<Reverse<HingeCandidate>> = BinaryHeap::new();
    // Candidates pushed so far (the strip order takes the newest first).
    let mut pushed = 0u64;
    while let Some(s) = start {
        grown[s as usize] = true;
        let centre = |t: &[Vec2; 3]| (t[0] + t[1] + t[2]) / 3.0;
        let origin = centre(islands.flat(s));
        let push = |f: u32, islands: &Islands, grown: &[bool], queue: &mut BinaryHeap<_>, pushed: &mut u64| {
            for k in 0..3 {
                let e = table.face_edges[f as usize][k];
                if e == u32::MAX || forced_cut[e as usize] {
                    continue;
                }
                if let Some(g) = table.opposite(f as usize, k) {
                    if !grown[g as usize] {
                        let class = u8::from(faces.dihedral[e as usize] > FLAT_DIHEDRAL);
                        let t = islands.flat(f);
                        let middle = (t[k] + t[(k + 1) % 3]) * 0.5;
                        let d: Vec2 = middle - origin;
                        let key = match order {
                            GrowthOrder::Compact => d.norm().to_bits(),
                            GrowthOrder::Strip => u64::MAX - *pushed,
                        };
                        *pushed += 1;
                        queue.push(Reverse(((class, key), f, k as u8, g)));
                    }
                }
            }
        };
        push(s, islands, &grown, &mut queue, &mut pushed);
        while let Some(Reverse((_, f, k, g))) = queue.pop() {
            if grown[g as usize] {
                continue;
            }
            let e = table.face_edges[f as usize][k as usize] as usize;
            let mut allowance = NET_TESTS_PER_FACE_WHEN_SPENT;
            let budget = if *tests_left > 0 {
                &mut *tests_left
            } else {
                &mut allowance
            };
            match islands.try_join(e, budget) {
                Join::Joined => {
                    grown[g as usize] = true;
                    push(g, islands, &grown, &mut queue, &mut pushed);
                }
                Join::Refused | Join::Unsettled => refused.push(g),
            }
        }
        start = refused.drain(..).find(|&f| !grown[f as usize]).or_else(|| {
            while next_any < nf && grown[next_any] {
                next_any += 1;
            }
            (next_any < nf).then_some(next_any as u32)
        });
    }
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

/// Joins the pieces of a grown net to each other where they fit (step 3 of
/// [`unfold_net`]): the edges cut between two pieces, those of the smallest pieces first
/// (the single faces and slivers a greedy growth leaves behind), then by dihedral angle,
/// each tried once ([`Islands::try_join`]: the smaller piece hinged onto the larger), in
/// passes until one joins nothing; no further join once the overlap tests are spent.
fn join_pieces(
    islands: &mut Islands,
    faces: &FaceGeometry,
    table: &EdgeTable,
    forced_cut: &[bool],
    tests_left: &mut usize,
) {
    let mut refused: FxHashMap<usize, (usize, usize)> = FxHashMap::default();
    loop {
        let cut: Vec<usize> = (0..table.len())
            .filter(|&e| !forced_cut[e] && !islands.is_kept(e))
            .filter(|&e| match table.sides(e) {
                [f, g] => islands.island_of(f.face) != islands.island_of(g.face),
                _ => false,
            })
            .collect();
        let smaller = |e: usize| {
            let [f, g] = table.sides(e) else { return 0 };
            islands.size_of(f.face).min(islands.size_of(g.face))
        };
        // Keys computed once per pass (the comparisons looked the sizes up again and
        // took a third of a large net's time).
        let mut keyed: Vec<(usize, f64, usize)> = cut.iter().map(|&e| (smaller(e), faces.dihedral[e], e)).collect();
        keyed.sort_unstable_by(|x, y| x.0.cmp(&y.0).then(x.1.total_cmp(&y.1)).then(x.2.cmp(&y.2)));
        let cut: Vec<usize> = keyed.into_iter().map(|(_, _, e)| e).collect();
        let mut joined = false;
        for e in cut {
            if *tests_left == 0 {
                tracing::warn!("net: the budget of overlap tests for joining pieces is spent");
                return;
            }
            // An edge refused between two pieces is tried again only once one of them
            // has grown (the same two pieces hinge the same way).
            let [f, g] = table.sides(e) else { continue };
            let sizes = (islands.size_of(f.face), islands.size_of(g.face));
            if refused.get(&e) == Some(&sizes) {
                continue;
            }
            match islands.try_join(e, tests_left) {
                Join::Joined => joined = true,
                _ => {
                    refused.insert(e, sizes);
                }
            }
        }
        if !joined {
            return;
        }
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

    /// Issue 35: a mesh of more facets than a net is made of is refused before any
    /// work, naming the count and the bound.
    #[test]
    fn a_mesh_of_more_faces_than_a_net_is_refused_before_the_work() {
        let side = 1 + (MAX_NET_FACES as f64 / 2.0).sqrt() as usize;
        let mut mesh = TriangleMesh::default();
        for i in 0..=side {
            for j in 0..=side {
                mesh.positions
                    .push(nalgebra::Vector3::new(i as f64, j as f64, ((i * j) % 3) as f64));
            }
        }
        let at = |i: usize, j: usize| (i * (side + 1) + j) as u32;
        for i in 0..side {
            for j in 0..side {
                mesh.triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                mesh.triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
        assert!(mesh.triangles.len() > MAX_NET_FACES);
        let error = unfold_net(&mesh, &NetOptions::default()).unwrap_err();
        assert!(
            matches!(error, FlattenError::TooManyPieces { count, bound, .. } if count == mesh.triangles.len() && bound == MAX_NET_FACES),
            "{error}"
        );
        assert!(error.to_string().contains("--charts smooth"), "{error}");
    }

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
