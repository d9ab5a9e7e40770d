//! Cutting a closed or high-genus mesh into charts that each flatten with small
//! distortion and without overlap.

use crate::{distortion, exact_unfold, Distortion, FlattenError, UnfoldOptions, Vec2};
use sheetform_mesh::{mesh_topology, TriangleMesh};
use sheetform_solve::SolverInfo;
use std::collections::{HashMap, VecDeque};

/// Knobs of [`cut_into_charts`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChartOptions {
    /// An edge whose two faces' normals differ by more than this angle (degrees) is a
    /// sharp crease and becomes a seam. Default 30°.
    pub crease_angle_degrees: f64,
    /// A chart whose flattening changes some edge length by more than this relative
    /// amount is split further. Default 0.01 (1 %).
    pub max_edge_distortion: f64,
    /// Upper bound on the number of charts: splitting stops there (the report then shows
    /// charts over the distortion bound), and a mesh whose sharp creases alone cut it
    /// into more regions is refused at once. Default [`MAX_PIECES`].
    pub max_charts: usize,
}

impl ChartOptions {
    /// The acceptance test of a chart's flattening: no overlap, every edge length within
    /// `max_edge_distortion`.
    pub fn accepts(&self, distortion: &Distortion) -> bool {
        distortion.is_overlap_free() && distortion.edge_length_max_relative <= self.max_edge_distortion
    }
}

impl Default for ChartOptions {
    fn default() -> Self {
        Self {
            crease_angle_degrees: 30.0,
            max_edge_distortion: 0.01,
            max_charts: MAX_PIECES,
        }
    }
}

/// Most pieces a pattern is cut into (charts, or a net's islands): a pattern of more
/// cannot be assembled by hand, and a mesh that asks for more (a noisy scan, a
/// hundred-thousand-facet model unfolded facet by facet) is refused before the work is
/// done (issue 35: a 100k-face noisy sheet ran 6 minutes to a 19 595-piece pattern).
pub const MAX_PIECES: usize = 5_000;

/// One chart: a disk-like set of faces and its flattening.
#[derive(Debug, Clone, PartialEq)]
pub struct Chart {
    /// Faces of the mesh in this chart.
    pub faces: Vec<u32>,
    /// Mesh vertex of each chart vertex (seam vertices appear in several charts, and
    /// twice in one chart when a seam inside it, a slit, is cut open).
    pub vertices: Vec<u32>,
    /// The chart's triangles in chart vertex indices (same order as `faces`).
    pub triangles: Vec<[u32; 3]>,
    /// Flat position of each chart vertex (mesh length units).
    pub flat: Vec<Vec2>,
    /// Distortion of the flattening.
    pub distortion: Distortion,
    /// The unfolding's solver report.
    pub solver: SolverInfo,
}

/// The charts of a mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct ChartSet {
    /// The charts, largest first.
    pub charts: Vec<Chart>,
    /// Chart of every mesh face.
    pub face_chart: Vec<u32>,
    /// Mesh edges on a chart boundary that have faces on both sides (cut edges).
    pub seam_edge_count: usize,
    /// Charts from creases and user seams before any splitting.
    pub initial_chart_count: usize,
    /// How many times a chart was split in two.
    pub split_count: usize,
    /// Charts made flat by cutting them open along shortest edge paths (from cone points
    /// to the boundary, between boundary loops) instead of splitting them.
    pub opened_count: usize,
    /// Small charts (slivers left by the splitting) joined to a neighbour.
    pub merged_count: usize,
    /// Borders between split charts moved onto the shortest edge path between their ends.
    pub straightened_count: usize,
}

/// Cuts `mesh` into charts and flattens each.
///
/// 1. **Seams**: user-given seam edges (`mesh.seam_edges`, OBJ `l` lines) and sharp
///    creases (the angle between the two face normals above
///    `options.crease_angle_degrees`) separate the initial charts, the connected sets of
///    faces between them. A user seam with one chart on both sides (a slit from its
///    border) is cut open inside that chart.
/// 2. **Open along straight seams**: a chart is accepted when it is a topological disk
///    (one component, one boundary loop, Euler characteristic 1) and its exact unfolding
///    ([`exact_unfold`], the least-squares layout of its edge lengths) has no flipped face,
///    no crossing boundary edges and no edge length changed by more than
///    `options.max_edge_distortion`. A developable surface that is not yet such a disk —
///    a tube (two boundary loops), a cone (an interior vertex whose angle sum is not 2π,
///    a cone point), a closed surface with a few cone points — is first cut open the way
///    a pattern maker would, along one seam: shortest edge paths (Dijkstra on the edge
///    lengths) join each cone point and each further boundary loop to the boundary (or,
///    without boundary, to the first cone point), nearest first. On a tube or cone
///    meshed along its rulings that seam is one ruling, so it comes out in one piece.
///    This is tried when there are at most [`MAX_CONE_POINTS`] cone points (|angle
///    defect| above [`crate::CONE_POINT_DEFECT`]) and [`MAX_SEAM_LOOPS`] boundary loops and genus 0; the
///    opened chart must pass the same test.
/// 3. **Split until flat**: otherwise the chart is split in two: two seed faces grow
///    breadth-first at the same pace, so both halves are connected. The seeds are the
///    faces on the first two border edges that cross when the chart's flattening
///    overlaps itself (so one split separates the parts that overlap), else the two
///    faces farthest apart (double breadth-first search over the face adjacency). A single triangle
///    always flattens exactly, so the splitting ends.
/// 4. **No slivers**: a chart of at most [`SMALL_CHART_FACES`] faces (and 2 % of the
///    mesh's) is joined to the
///    neighbour it shares the most edges with (across a crease too, never across a user
///    seam) when the union passes the acceptance test.
/// 5. **Straight borders**: each border the splitting left between two charts moves onto
///    the shortest edge path joining its ends through the two charts
///    (`border_straightening.rs`) when both charts still pass the test.
///
/// Departure from published segmenters (D-charts, feature-based seams): borders are
/// shortest edge paths (no smoothness term), so on an irregular mesh they follow its
/// edges. What is guaranteed is the acceptance test above.
///
/// # Errors
/// Non-manifold, degenerate or non-orientable meshes (named), seam edges that are not
/// mesh edges.
pub fn cut_into_charts(mesh: &TriangleMesh, options: &ChartOptions) -> Result<ChartSet, FlattenError> {
    cut_into_charts_until(mesh, options, None)
}

/// [`cut_into_charts`] that stops once `stop` is set (from another thread: Ctrl-C, an
/// abandoned editor request), before each chart it flattens.
///
/// # Errors
/// As [`cut_into_charts`]; [`FlattenError::Cancelled`] when stopped.
pub fn cut_into_charts_until(
    mesh: &TriangleMesh,
    options: &ChartOptions,
    stop: Option<&std::sync::atomic::AtomicBool>,
) -> Result<ChartSet, FlattenError> {
    let stopped = || stop.is_some_and(|s| s.load(std::sync::atomic::Ordering::Relaxed));
    let topology = mesh_topology(mesh);
    let problems = crate::exact_unfolding::topology_problems(&topology);
    if !problems.is_empty() {
        return Err(FlattenError::Topology {
            problem: problems.join("; "),
        });
    }
    let nf = mesh.triangles.len();
    let key = |a: u32, b: u32| if a < b { [a, b] } else { [b, a] };
    let table = sheetform_mesh::EdgeTable::new(&mesh.triangles, mesh.positions.len());
    let seams: std::collections::HashSet<[u32; 2]> = crate::user_seam_edges(mesh, &table)?
        .into_iter()
        .map(|e| table.edges[e])
        .collect();
    let cos_crease = options.crease_angle_degrees.to_radians().cos();
    let normals: Vec<_> = (0..nf).map(|f| mesh.face_normal(f)).collect();
    // Face adjacency across edges that are not seams (built in face order, so the
    // result does not depend on hash order).
    let mut neighbours: Vec<Vec<u32>> = vec![Vec::new(); nf];
    for (f, t) in mesh.triangles.iter().enumerate() {
        for k in 0..3 {
            let e = key(t[k], t[(k + 1) % 3]);
            if let Some(g) = table.opposite(f, k) {
                let crease = normals[f].dot(&normals[g as usize]) < cos_crease;
                if !crease && !seams.contains(&e) {
                    neighbours[f].push(g);
                }
            }
        }
    }
    // Initial charts: connected components.
    let mut pending: Vec<Vec<u32>> = Vec::new();
    let mut seen = vec![false; nf];
    for f0 in 0..nf {
        if seen[f0] {
            continue;
        }
        seen[f0] = true;
        let mut component = vec![f0 as u32];
        let mut i = 0;
        while i < component.len() {
            let f = component[i] as usize;
            i += 1;
            for &g in &neighbours[f] {
                if !seen[g as usize] {
                    seen[g as usize] = true;
                    component.push(g);
                }
            }
        }
        pending.push(component);
    }
    let initial_chart_count = pending.len();
    if initial_chart_count > options.max_charts {
        return Err(FlattenError::TooManyPieces {
            what: format!(
                "folds sharper than the {}° crease angle cut it into more regions than pieces",
                options.crease_angle_degrees
            ),
            count: initial_chart_count,
            bound: options.max_charts,
            advice: "smooth or remesh it, or raise --crease-angle so that fewer edges are creases".into(),
        });
    }
    let mut charts: Vec<Chart> = Vec::new();
    let mut split_count = 0;
    let mut opened_count = 0;
    let mut opened_cut_edges = 0;
    let mut in_chart = vec![u32::MAX; nf];
    while let Some(faces) = pending.pop() {
        if stopped() {
            return Err(FlattenError::Cancelled);
        }
        let (sub, vertices) = submesh(mesh, &faces);
        let out_of_budget = charts.len() + pending.len() + 1 >= options.max_charts;
        let attempt = flatten_chart(&sub);
        let accept = match &attempt {
            Some((_, d)) => options.accepts(d),
            None => false,
        };
        // Where an opened chart that overlaps itself is split (see below).
        let mut opened_seeds = None;
        if !accept && !out_of_budget {
            if let Some((opened, origin, unfolding, d, cut_edges)) = open_to_disk(&sub) {
                if !options.accepts(&d) {
                    opened_seeds = d.first_crossing.and_then(|pair| crossing_faces(&opened, pair));
                } else {
                    opened_count += 1;
                    opened_cut_edges += cut_edges;
                    charts.push(Chart {
                        faces,
                        vertices: origin.iter().map(|&v| vertices[v as usize]).collect(),
                        triangles: opened.triangles,
                        flat: unfolding.flat,
                        distortion: d,
                        solver: unfolding.solver,
                    });
                    continue;
                }
            }
        }
        if accept || faces.len() == 1 || (out_of_budget && attempt.is_some()) {
            // Only a single triangle can come here without an unfolding: one too thin for
            // the solver (a fuzzed 60 × 3e7 needle panicked here). Refused, naming it by
            // its face of the mesh.
            let Some((unfolding, d)) = attempt else {
                return Err(FlattenError::Solver {
                    message: crate::exact_unfolding::layout_not_fixed_numbered(&sub, |f| faces[f] as usize),
                });
            };
            charts.push(Chart {
                faces,
                vertices,
                triangles: sub.triangles,
                flat: unfolding.flat,
                distortion: d,
                solver: unfolding.solver,
            });
            continue;
        }
        split_count += 1;
        tracing::debug!(
            faces = faces.len(),
            flipped = attempt.as_ref().map(|(_, d)| d.flipped_faces.len()),
            crossings = attempt.as_ref().map(|(_, d)| d.boundary_crossings),
            edge = attempt.as_ref().map(|(_, d)| d.edge_length_max_relative),
            "charts: a chart split in two (no counts: it is not a disk)"
        );
        for (i, &f) in faces.iter().enumerate() {
            in_chart[f as usize] = i as u32;
        }
        // An exact chart that overlaps itself is split between the two parts that
        // overlap (the faces on the first pair of crossing border edges seed the halves):
        // the farthest faces would split it anywhere, and the half still holding the
        // overlap again and again (a developed piece whose slit's lips overlap near its
        // end: split 5 times, session 33).
        let seeds = attempt
            .as_ref()
            .and_then(|(_, d)| d.first_crossing)
            .and_then(|pair| crossing_faces(&sub, pair))
            .or(opened_seeds);
        let (a, b) = split_in_two(&faces, &neighbours, &in_chart, seeds);
        for &f in &faces {
            in_chart[f as usize] = u32::MAX;
        }
        pending.push(a);
        pending.push(b);
    }
    if stopped() {
        return Err(FlattenError::Cancelled);
    }
    let merged_count = merge_small_charts(mesh, &table, &seams, &mut charts, options);
    if stopped() {
        return Err(FlattenError::Cancelled);
    }
    // Borders that splitting left (not creases, not user seams) moved onto shortest paths.
    let fixed: Vec<bool> = (0..table.len())
        .map(|e| match table.sides(e) {
            [f, g] => {
                normals[f.face as usize].dot(&normals[g.face as usize]) < cos_crease || seams.contains(&table.edges[e])
            }
            _ => true,
        })
        .collect();
    let straightened_count =
        crate::border_straightening::straighten_chart_borders(mesh, &table, &fixed, &mut charts, options);
    charts.sort_by(|a, b| b.faces.len().cmp(&a.faces.len()).then(a.faces[0].cmp(&b.faces[0])));
    let mut face_chart = vec![0u32; nf];
    for (c, chart) in charts.iter().enumerate() {
        for &f in &chart.faces {
            face_chart[f as usize] = c as u32;
        }
    }
    // Edges between charts, those cut open inside a chart, and the user's seams inside
    // a chart (slits, cut open by `submesh`).
    let seam_edge_count = (0..table.len())
        .filter(|&e| match table.sides(e) {
            [f, g] => face_chart[f.face as usize] != face_chart[g.face as usize] || seams.contains(&table.edges[e]),
            _ => false,
        })
        .count()
        + opened_cut_edges;
    Ok(ChartSet {
        charts,
        face_chart,
        seam_edge_count,
        initial_chart_count,
        split_count,
        opened_count,
        merged_count,
        straightened_count,
    })
}

/// Charts of at most this many faces (and at most 2 % of the mesh's faces) are slivers:
/// [`cut_into_charts`] tries to merge them into a neighbour.
pub const SMALL_CHART_FACES: usize = 32;

/// Step 4 of [`cut_into_charts`]: each chart of at most [`SMALL_CHART_FACES`] faces (and
/// 2 % of the mesh's),
/// smallest first, is joined to the neighbouring chart it shares the most edges with
/// (across creases too, never across a user seam) when the union still passes the
/// acceptance test; returns how many were merged.
fn merge_small_charts(
    mesh: &TriangleMesh,
    table: &sheetform_mesh::EdgeTable,
    seams: &std::collections::HashSet<[u32; 2]>,
    charts: &mut Vec<Chart>,
    options: &ChartOptions,
) -> usize {
    let nf = mesh.triangles.len();
    let mut merged = 0;
    // Work budget in faces unfolded.
    let mut budget = 50 * nf + 10_000;
    let small = SMALL_CHART_FACES.min(nf / 50);
    // Passes over the small charts, smallest first; a chart merged away is left empty
    // until the end. (Restarting after every merge, as before, made the bookkeeping
    // quadratic in the number of charts: 14 000 merges on a noisy 100k-face sheet.)
    let mut face_chart = vec![u32::MAX; nf];
    for (c, chart) in charts.iter().enumerate() {
        for &f in &chart.faces {
            face_chart[f as usize] = c as u32;
        }
    }
    'passes: loop {
        let mut order: Vec<usize> = (0..charts.len())
            .filter(|&c| !charts[c].faces.is_empty() && charts[c].faces.len() <= small)
            .collect();
        order.sort_by_key(|&c| (charts[c].faces.len(), c));
        let mut joined_in_pass = false;
        for c in order {
            // Grown by a merge in this pass, or merged away.
            if charts[c].faces.is_empty() || charts[c].faces.len() > small {
                continue;
            }
            // Neighbours by the number of edges shared (user seams excluded).
            let mut shared: HashMap<u32, usize> = HashMap::new();
            for &f in &charts[c].faces {
                for k in 0..3 {
                    let t = mesh.triangles[f as usize];
                    let (a, b) = (t[k], t[(k + 1) % 3]);
                    if seams.contains(&[a.min(b), a.max(b)]) {
                        continue;
                    }
                    if let Some(g) = table.opposite(f as usize, k) {
                        let d = face_chart[g as usize];
                        if d != c as u32 {
                            *shared.entry(d).or_default() += 1;
                        }
                    }
                }
            }
            // Charts that share a user seam stay apart (the user cut there).
            let mut across_seam: std::collections::HashSet<u32> = std::collections::HashSet::new();
            for &f in &charts[c].faces {
                let t = mesh.triangles[f as usize];
                for k in 0..3 {
                    let (a, b) = (t[k], t[(k + 1) % 3]);
                    if seams.contains(&[a.min(b), a.max(b)]) {
                        if let Some(g) = table.opposite(f as usize, k) {
                            across_seam.insert(face_chart[g as usize]);
                        }
                    }
                }
            }
            let mut neighbours: Vec<(u32, usize)> =
                shared.into_iter().filter(|(d, _)| !across_seam.contains(d)).collect();
            neighbours.sort_by(|x, y| y.1.cmp(&x.1).then(x.0.cmp(&y.0)));
            for (d, _) in neighbours {
                let d = d as usize;
                let faces: Vec<u32> = charts[d].faces.iter().chain(&charts[c].faces).copied().collect();
                if budget < faces.len() {
                    break 'passes;
                }
                budget -= faces.len();
                let (sub, vertices) = submesh(mesh, &faces);
                if let Some((unfolding, dist)) = flatten_chart(&sub) {
                    if options.accepts(&dist) {
                        for &f in &charts[c].faces {
                            face_chart[f as usize] = d as u32;
                        }
                        charts[d] = Chart {
                            faces,
                            vertices,
                            triangles: sub.triangles,
                            flat: unfolding.flat,
                            distortion: dist,
                            solver: unfolding.solver,
                        };
                        charts[c].faces.clear();
                        merged += 1;
                        joined_in_pass = true;
                        break;
                    }
                }
            }
        }
        if !joined_in_pass {
            break;
        }
    }
    charts.retain(|chart| !chart.faces.is_empty());
    merged
}

/// Most cone points a chart may have to be opened along seams rather than split.
pub const MAX_CONE_POINTS: usize = 8;
/// Most boundary loops a chart may have to be opened along seams rather than split.
pub const MAX_SEAM_LOOPS: usize = 16;

/// Step 2 of [`cut_into_charts`]: `sub` cut open along shortest edge paths into a disk
/// with no interior cone point, with the vertex of `sub` each new vertex copies, its
/// exact unfolding and distortion, and the number of edges cut; `None` when the chart is
/// not a genus-0 surface with few cone points and loops, or needs no cut, or does not
/// unfold.
fn open_to_disk(sub: &TriangleMesh) -> Option<(TriangleMesh, Vec<u32>, crate::Unfolding, Distortion, usize)> {
    let topology = mesh_topology(sub);
    let loops = topology.boundary_loop_count;
    // Genus 0: χ = 2 − b.
    if topology.component_count != 1 || topology.euler_characteristic + loops as i64 != 2 || loops > MAX_SEAM_LOOPS {
        return None;
    }
    let defects = sheetform_mesh::vertex_developability(sub, &topology).angle_defect;
    let mut cone_points: Vec<u32> = (0..sub.positions.len() as u32)
        .filter(|&v| defects[v as usize].abs() > crate::CONE_POINT_DEFECT)
        .collect();
    if cone_points.len() > MAX_CONE_POINTS || (loops <= 1 && cone_points.is_empty()) {
        return None;
    }
    let nv = sub.positions.len();
    let table = sheetform_mesh::EdgeTable::new(&sub.triangles, nv);
    let mut adjacency: Vec<Vec<(u32, f64)>> = vec![Vec::new(); nv];
    for &[a, b] in &table.edges {
        let l = (sub.positions[a as usize] - sub.positions[b as usize]).norm();
        adjacency[a as usize].push((b, l));
        adjacency[b as usize].push((a, l));
    }
    // Boundary loop of every boundary vertex (union–find over boundary edges).
    let mut loops = sheetform_mesh::UnionFind::new(nv);
    for [a, b] in table.boundary_edges() {
        loops.union(a, b);
    }
    let mut loop_of = vec![u32::MAX; nv];
    let mut members: HashMap<u32, Vec<u32>> = HashMap::new();
    for v in 0..nv as u32 {
        if topology.boundary_vertex[v as usize] {
            loop_of[v as usize] = loops.find(v);
            members.entry(loop_of[v as usize]).or_default().push(v);
        }
    }
    // The cut tree grows from the first boundary loop (or the first cone point); reaching
    // a loop adds the whole loop.
    let mut in_tree = vec![false; nv];
    let first_loop = (0..nv).find(|&v| loop_of[v] != u32::MAX).map(|v| loop_of[v]);
    let add_to_tree = |v: u32, in_tree: &mut Vec<bool>| {
        if !in_tree[v as usize] && loop_of[v as usize] != u32::MAX {
            for &w in &members[&loop_of[v as usize]] {
                in_tree[w as usize] = true;
            }
        }
        in_tree[v as usize] = true;
    };
    match first_loop {
        Some(l) => {
            let v = loop_of.iter().position(|&x| x == l)? as u32;
            add_to_tree(v, &mut in_tree);
        }
        None => {
            let c = cone_points.remove(0);
            add_to_tree(c, &mut in_tree);
        }
    }
    let mut cut: Vec<[u32; 2]> = Vec::new();
    loop {
        let is_target =
            |v: usize, in_tree: &[bool]| !in_tree[v] && (cone_points.contains(&(v as u32)) || loop_of[v] != u32::MAX);
        if !(0..nv).any(|v| is_target(v, &in_tree)) {
            break;
        }
        // The shortest edge path from the tree to the nearest target joins the tree.
        let path = sheetform_mesh::shortest_edge_path(
            (0..nv as u32).filter(|&v| in_tree[v as usize]),
            |v| is_target(v as usize, &in_tree),
            |v| adjacency[v as usize].iter().copied(),
            f64::INFINITY,
        )?;
        for pair in path.windows(2) {
            cut.push([pair[1], pair[0]]);
        }
        for &v in &path {
            add_to_tree(v, &mut in_tree);
        }
    }
    let opened = sheetform_mesh::cut_along_edges(sub, &cut);
    let (unfolding, d) = flatten_chart(&opened.mesh)?;
    Some((opened.mesh, opened.origin, unfolding, d, cut.len()))
}

/// The faces as a mesh of their own (vertices renumbered), with the mesh vertex of each,
/// cut open along the user's seams that run inside them (`mesh.seam_edges` with faces
/// of the set on both sides: a slit from the border, which does not split the set but
/// must open for it to unfold; develop's slits are such seams). Left closed, the slit's
/// vertices are ordinary vertices of the chart whose angle sums the seam left free: the
/// chart does not unfold exactly, or is opened along a shortest path instead of the
/// drawn one (session 33: every developed koala piece with a slit was split for that,
/// 18 % edge error, rather than printed opened along its slit).
pub(crate) fn submesh(mesh: &TriangleMesh, faces: &[u32]) -> (TriangleMesh, Vec<u32>) {
    let mut local: HashMap<u32, u32> = HashMap::with_capacity(faces.len());
    let mut vertices = Vec::new();
    let triangles = faces
        .iter()
        .map(|&f| {
            mesh.triangles[f as usize].map(|v| {
                *local.entry(v).or_insert_with(|| {
                    vertices.push(v);
                    vertices.len() as u32 - 1
                })
            })
        })
        .collect::<Vec<_>>();
    let sub = TriangleMesh {
        positions: vertices.iter().map(|&v| mesh.positions[v as usize]).collect(),
        face_groups: vec![0; triangles.len()],
        triangles,
        groups: vec!["chart".into()],
        corner_uvs: None,
        seam_edges: Vec::new(),
    };
    // The seams with faces of the set on both sides (not those along its border, which
    // cut nothing: the set is then not cut at all, and its vertices stay one per mesh
    // vertex).
    let candidates: Vec<[u32; 2]> = mesh
        .seam_edges
        .iter()
        .filter_map(|&[a, b]| Some([*local.get(&a)?, *local.get(&b)?]))
        .collect();
    if candidates.is_empty() {
        return (sub, vertices);
    }
    let table = sheetform_mesh::EdgeTable::new(&sub.triangles, sub.positions.len());
    let inside: Vec<[u32; 2]> = candidates
        .into_iter()
        .filter(|&[a, b]| table.find(a, b).is_some_and(|e| table.sides(e).len() == 2))
        .collect();
    if inside.is_empty() {
        return (sub, vertices);
    }
    let opened = sheetform_mesh::cut_along_edges(&sub, &inside);
    let vertices = opened.origin.iter().map(|&v| vertices[v as usize]).collect();
    (opened.mesh, vertices)
}

/// Exact unfolding of a chart and its distortion; `None` when it is not a disk.
pub(crate) fn flatten_chart(sub: &TriangleMesh) -> Option<(crate::Unfolding, Distortion)> {
    let unfolding = exact_unfold(sub, &UnfoldOptions::default()).ok()?;
    let d = distortion(sub, &unfolding.flat);
    Some((unfolding, d))
}

/// The faces of `sub` (indices into its triangles, the chart's `faces` order) on the two
/// border edges of `pair` (vertex pairs of `sub`), when they are two faces.
fn crossing_faces(sub: &TriangleMesh, pair: [[u32; 2]; 2]) -> Option<(usize, usize)> {
    let table = sheetform_mesh::EdgeTable::new(&sub.triangles, sub.positions.len());
    let face = |[a, b]: [u32; 2]| match table.sides(table.find(a, b)?) {
        [side] => Some(side.face as usize),
        _ => None,
    };
    let (f, g) = (face(pair[0])?, face(pair[1])?);
    (f != g).then_some((f, g))
}

/// Splits a connected face set in two connected halves grown at the same pace from two
/// seed faces (indices into `faces`): `seeds`, or by default its two faces farthest
/// apart. `position[f]` is `f`'s index in `faces` (`u32::MAX` outside).
fn split_in_two(
    faces: &[u32],
    neighbours: &[Vec<u32>],
    position: &[u32],
    seeds: Option<(usize, usize)>,
) -> (Vec<u32>, Vec<u32>) {
    let n = faces.len();
    let bfs_last = |start: usize| {
        let mut dist = vec![usize::MAX; n];
        let mut queue = VecDeque::from([start]);
        dist[start] = 0;
        let mut last = start;
        while let Some(i) = queue.pop_front() {
            last = i;
            for &g in &neighbours[faces[i] as usize] {
                let j = position[g as usize];
                if j != u32::MAX && dist[j as usize] == usize::MAX {
                    dist[j as usize] = dist[i] + 1;
                    queue.push_back(j as usize);
                }
            }
        }
        last
    };
    let (s1, s2) = seeds.unwrap_or_else(|| {
        let s1 = bfs_last(0);
        let s2 = bfs_last(s1);
        (s1, if s2 == s1 { (s1 + 1) % n } else { s2 })
    });
    // Grow both at the same pace (one queue, labels carried along).
    let mut label = vec![u8::MAX; n];
    label[s1] = 0;
    label[s2] = 1;
    let mut queue = VecDeque::from([s1, s2]);
    while let Some(i) = queue.pop_front() {
        for &g in &neighbours[faces[i] as usize] {
            let j = position[g as usize];
            if j != u32::MAX && label[j as usize] == u8::MAX {
                label[j as usize] = label[i];
                queue.push_back(j as usize);
            }
        }
    }
    let (mut a, mut b) = (Vec::new(), Vec::new());
    for (i, &f) in faces.iter().enumerate() {
        // Faces reached by neither seed cannot occur in a connected set; keep them with `a`.
        if label[i] == 1 {
            b.push(f);
        } else {
            a.push(f);
        }
    }
    (a, b)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A grid sheet of `n × n` squares (two triangles each) with a pseudo-random height
    /// of amplitude `noise` at every vertex: a noisy scan of a flat sheet.
    pub(crate) fn noisy_sheet(n: usize, noise: f64) -> TriangleMesh {
        let mut seed = 12_345u64;
        let mut random = || {
            seed = seed
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let mut mesh = TriangleMesh::grid(n, n, |u, v| [u * n as f64, v * n as f64, 0.0]);
        for p in &mut mesh.positions {
            p.z = 2.0 * noise * random();
        }
        mesh
    }

    /// Issue 35: a mesh whose creases alone cut it into more regions than a pattern may
    /// have pieces is refused at once, naming the count, the bound and what to do (a
    /// 100k-face noisy sheet ran 6 minutes to a 19 595-piece pattern).
    #[test]
    fn a_mesh_creased_into_more_regions_than_pieces_is_refused_at_once() {
        let mesh = noisy_sheet(40, 0.4);
        let options = ChartOptions {
            max_charts: 50,
            ..Default::default()
        };
        let error = cut_into_charts(&mesh, &options).unwrap_err();
        let FlattenError::TooManyPieces { count, bound, .. } = &error else {
            panic!("{error}");
        };
        assert!(*count > 50 && *bound == 50, "{error}");
        let message = error.to_string();
        assert!(
            message.contains("--crease-angle") && message.contains("noisy"),
            "{message}"
        );
        // The same sheet with a crease angle no fold reaches is cut into charts.
        let calm = ChartOptions {
            crease_angle_degrees: 180.0,
            max_charts: 50,
            ..Default::default()
        };
        assert!(cut_into_charts(&mesh, &calm).is_ok());
    }

    /// A closed cube made of 12 triangles per face side subdivided `n` times.
    fn cube(n: usize) -> TriangleMesh {
        let mut mesh = TriangleMesh::default();
        let mut index: HashMap<[i64; 3], u32> = HashMap::new();
        let mut vertex = |p: [i64; 3], mesh: &mut TriangleMesh| {
            *index.entry(p).or_insert_with(|| {
                mesh.positions
                    .push(nalgebra::Vector3::new(p[0] as f64, p[1] as f64, p[2] as f64) / n as f64);
                mesh.positions.len() as u32 - 1
            })
        };
        let n = n as i64;
        // Each face: origin, two axes, outward normal = u × v.
        let sides: [([i64; 3], [i64; 3], [i64; 3]); 6] = [
            ([0, 0, 0], [0, 1, 0], [1, 0, 0]),
            ([0, 0, n], [1, 0, 0], [0, 1, 0]),
            ([0, 0, 0], [1, 0, 0], [0, 0, 1]),
            ([0, n, 0], [0, 0, 1], [1, 0, 0]),
            ([0, 0, 0], [0, 0, 1], [0, 1, 0]),
            ([n, 0, 0], [0, 1, 0], [0, 0, 1]),
        ];
        for (o, u, v) in sides {
            let at = |i: i64, j: i64| {
                [
                    o[0] + u[0] * i + v[0] * j,
                    o[1] + u[1] * i + v[1] * j,
                    o[2] + u[2] * i + v[2] * j,
                ]
            };
            for i in 0..n {
                for j in 0..n {
                    let a = vertex(at(i, j), &mut mesh);
                    let b = vertex(at(i + 1, j), &mut mesh);
                    let c = vertex(at(i + 1, j + 1), &mut mesh);
                    let d = vertex(at(i, j + 1), &mut mesh);
                    mesh.triangles.push([a, b, c]);
                    mesh.triangles.push([a, c, d]);
                }
            }
        }
        mesh.face_groups = vec![0; mesh.triangles.len()];
        mesh.groups = vec!["cube".into()];
        mesh
    }

    #[test]
    fn a_cube_is_cut_along_its_creases_into_six_exact_squares() {
        let mesh = cube(3);
        assert_eq!(mesh_topology(&mesh).euler_characteristic, 2);
        let set = cut_into_charts(&mesh, &ChartOptions::default()).unwrap();
        assert_eq!(set.charts.len(), 6);
        assert_eq!(set.split_count, 0);
        assert_eq!(set.seam_edge_count, 12 * 3);
        for c in &set.charts {
            assert_eq!(c.faces.len(), 18);
            assert!(c.distortion.edge_length_max_relative < 1e-12);
            assert!(c.distortion.is_overlap_free());
        }
    }

    #[test]
    fn without_creases_a_cube_is_opened_along_seams_through_its_eight_corners() {
        let mesh = cube(3);
        let options = ChartOptions {
            crease_angle_degrees: 180.0,
            ..Default::default()
        };
        let set = cut_into_charts(&mesh, &options).unwrap();
        assert_eq!((set.initial_chart_count, set.opened_count, set.split_count), (1, 1, 0));
        assert_eq!(set.charts.len(), 1);
        assert!(set.charts[0].distortion.edge_length_max_relative < 1e-10);
        assert!(set.charts[0].distortion.is_overlap_free());
    }

    #[test]
    fn without_creases_a_sphere_is_split_until_every_chart_is_a_flat_disk() {
        let mesh = sheetform_mesh::primitives::icosphere(1.0, 2);
        let options = ChartOptions {
            crease_angle_degrees: 180.0,
            ..Default::default()
        };
        let set = cut_into_charts(&mesh, &options).unwrap();
        assert!(set.split_count >= 1 && set.initial_chart_count == 1);
        let total: usize = set.charts.iter().map(|c| c.faces.len()).sum();
        assert_eq!(total, mesh.triangles.len());
        for c in &set.charts {
            assert!(c.distortion.is_overlap_free());
            assert!(c.distortion.edge_length_max_relative <= options.max_edge_distortion);
        }
    }

    #[test]
    fn user_seams_cut_where_no_crease_is() {
        // Without creases, a seam ring around the cube's middle leaves two open boxes.
        let mut mesh = cube(2);
        let mid = |v: u32| (mesh.positions[v as usize].z - 0.5).abs() < 1e-12;
        let mut ring = Vec::new();
        for t in &mesh.triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                if a < b && mid(a) && mid(b) {
                    ring.push([a, b]);
                }
            }
        }
        assert_eq!(ring.len(), 8);
        mesh.seam_edges = ring;
        let options = ChartOptions {
            crease_angle_degrees: 180.0,
            max_edge_distortion: 1.0,
            ..Default::default()
        };
        let set = cut_into_charts(&mesh, &options).unwrap();
        assert_eq!(set.initial_chart_count, 2);
        assert!(set.seam_edge_count >= 8);
    }

    #[test]
    fn a_user_seam_inside_a_chart_is_opened_where_it_is_drawn() {
        // An open cone (apex 0; rings 1..=R of n vertices, ring k at k/R of the slant)
        // with a seam drawn from the apex to the rim along a spiral of quad diagonals:
        // a slit that does not split the cone. Its chart opens along the spiral, not
        // along a shortest path of its own, and unfolds exactly into one piece.
        let (n, rings) = (12usize, 4usize);
        let mut mesh = TriangleMesh::default();
        mesh.positions.push(nalgebra::Vector3::new(0.0, 0.0, 1.0));
        for k in 1..=rings {
            let t = k as f64 / rings as f64;
            for j in 0..n {
                let a = std::f64::consts::TAU * j as f64 / n as f64;
                mesh.positions
                    .push(nalgebra::Vector3::new(t * a.cos(), t * a.sin(), 1.0 - t));
            }
        }
        let at = |k: usize, j: usize| (1 + (k - 1) * n + j % n) as u32;
        for j in 0..n {
            mesh.triangles.push([0, at(1, j), at(1, j + 1)]);
        }
        for k in 1..rings {
            for j in 0..n {
                let (a, b, c, d) = (at(k, j), at(k, j + 1), at(k + 1, j), at(k + 1, j + 1));
                mesh.triangles.push([a, d, b]);
                mesh.triangles.push([a, c, d]);
            }
        }
        mesh.face_groups = vec![0; mesh.triangles.len()];
        mesh.groups = vec!["cone".into()];
        let spiral: Vec<u32> = std::iter::once(0).chain((1..=rings).map(|k| at(k, k - 1))).collect();
        mesh.seam_edges = spiral.windows(2).map(|w| [w[0], w[1]]).collect();
        let options = ChartOptions {
            crease_angle_degrees: 180.0,
            max_edge_distortion: 1e-9,
            ..Default::default()
        };
        let set = cut_into_charts(&mesh, &options).unwrap();
        assert_eq!(set.charts.len(), 1);
        assert_eq!(
            (set.split_count, set.opened_count),
            (0, 0),
            "opened by the drawn seam itself"
        );
        let chart = &set.charts[0];
        assert!(chart.distortion.is_overlap_free());
        assert!(chart.distortion.edge_length_max_relative < 1e-12);
        // The copied vertices are the spiral's, apex (the slit's end) excepted.
        let mut seen = std::collections::HashSet::new();
        let mut doubled: Vec<u32> = chart.vertices.iter().copied().filter(|&v| !seen.insert(v)).collect();
        doubled.sort_unstable();
        let mut expected = spiral[1..].to_vec();
        expected.sort_unstable();
        assert_eq!(doubled, expected);
    }

    #[test]
    fn a_chart_that_overlaps_itself_is_split_between_the_parts_that_overlap() {
        // A long strip of 24 × 4 unit squares with a saddle near one end: the six
        // neighbours of vertex (1, 2) raised and lowered in turn, so its angle sum passes
        // 2π, and a slit drawn from the strip's end (0, 2) to it. Opened, the slit's lips
        // overlap. One split between them ends it; halves grown from the strip's two
        // ends would leave the overlap in the near half, split again and again.
        let (nx, ny) = (24u32, 4u32);
        let id = |i: u32, j: u32| j * (nx + 1) + i;
        let mut mesh = TriangleMesh::default();
        for j in 0..=ny {
            for i in 0..=nx {
                mesh.positions.push(nalgebra::Vector3::new(i as f64, j as f64, 0.0));
            }
        }
        for j in 0..ny {
            for i in 0..nx {
                mesh.triangles.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                mesh.triangles.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        // The neighbours of (1, 2) in turn round it.
        for (k, (i, j)) in [(2, 2), (2, 3), (1, 3), (0, 2), (0, 1), (1, 1)].into_iter().enumerate() {
            mesh.positions[id(i, j) as usize].z = if k % 2 == 0 { 0.6 } else { -0.6 };
        }
        mesh.face_groups = vec![0; mesh.triangles.len()];
        mesh.groups = vec!["strip".into()];
        mesh.seam_edges = vec![[id(0, 2), id(1, 2)]];
        let options = ChartOptions {
            crease_angle_degrees: 180.0,
            max_edge_distortion: 0.5,
            ..Default::default()
        };
        let set = cut_into_charts(&mesh, &options).unwrap();
        assert_eq!(set.split_count, 1, "split once");
        assert_eq!(set.charts.len(), 2);
        assert!(set.charts.iter().all(|c| c.distortion.is_overlap_free()));
    }

    #[test]
    fn user_seams_must_be_mesh_edges() {
        let mut mesh = cube(1);
        // Opposite corners of the cube are never joined by an edge.
        let corner = |p: [f64; 3]| {
            mesh.positions
                .iter()
                .position(|q| (q - nalgebra::Vector3::from(p)).norm() < 1e-12)
                .unwrap() as u32
        };
        mesh.seam_edges = vec![[corner([0.0, 0.0, 0.0]), corner([1.0, 1.0, 1.0])]];
        let e = cut_into_charts(&mesh, &ChartOptions::default()).unwrap_err();
        assert!(e.to_string().contains("seam edge 0"), "{e}");
    }

    /// A triangle too thin to lay flat, alone in its chart (found by the serve fuzz
    /// target: a gift box with one corner moved to 3e7), is refused naming it; it
    /// panicked ("a single triangle or an accepted chart unfolds").
    #[test]
    fn a_needle_triangle_alone_is_refused_not_a_panic() {
        let p = |x: f64, y: f64, z: f64| nalgebra::Vector3::new(x, y, z);
        let mesh = TriangleMesh {
            positions: vec![
                p(0.0, 0.0, 0.0),
                p(0.0, 40.0, 30.0),
                p(0.0, 40.0, 0.0),
                p(60.0, 0.0, 0.0),
                p(60.0, 40.0, 0.0),
                p(60.0, 40.0, 3e7),
                p(60.0, 0.0, 30.0),
            ],
            // The third: 30 wide at one end, 3e7 long, 4e-5 across its longest edge.
            triangles: vec![[0, 1, 2], [3, 4, 5], [3, 5, 6]],
            face_groups: vec![0, 0, 0],
            groups: vec!["box".into()],
            corner_uvs: None,
            seam_edges: Vec::new(),
        };
        let e = cut_into_charts(&mesh, &ChartOptions::default()).unwrap_err();
        assert!(
            e.to_string().contains("needle-thin") && e.to_string().contains("face 2 near"),
            "{e}"
        );
    }
}
