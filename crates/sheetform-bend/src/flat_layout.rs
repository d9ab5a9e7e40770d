//! The flat sheet cut along the rulings: a constrained Delaunay triangulation whose
//! constraint edges are the outline, the holes, every sampled ruling and the flat
//! geodesics, and the cells (connected groups of faces between rulings) that each move
//! rigidly.

use crate::{ruling_extent::BoundaryPoint, BendError, BendModel, InadmissibleDetail, RegionGeometry};
use rustc_hash::{FxHashMap as HashMap, FxHashSet as HashSet};
use sheetform_geometry::Vec2;
use sheetform_geometry::{numbers_apart, segment_intersection, short_number};
use sheetform_mesh::{Piece, PieceKind, Ruling};
use spade::{ConstrainedDelaunayTriangulation, HasPosition, Point2, Triangulation};

/// What a constraint edge of the layout is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum EdgeKind {
    /// Part of the outline or of a hole.
    Boundary,
    /// Part of ruling `ruling` of region `region`.
    Ruling {
        /// Region index.
        region: usize,
        /// Ruling index within the region.
        ruling: usize,
    },
    /// Part of the flat geodesic of a region (inside a strip; not a cut).
    Geodesic,
}

/// A set of faces that moves rigidly. `labels` lists every `(region, part)` the cell was
/// found to belong to, `part` indexing [`crate::FoldedStrip::motions`].
#[derive(Debug, Clone, PartialEq)]
pub struct Cell {
    /// `(region, part)` pairs seen on the cell's ruling edges.
    pub labels: Vec<(usize, usize)>,
    /// Vertices of the cell's faces, for cells with two or more labels (whose placement
    /// [`crate::place`] checks for consistency); empty for the others.
    pub vertices: Vec<u32>,
    /// A point inside the cell (flat).
    pub sample_point: Vec2,
}

/// The flat sheet, triangulated and cut into rigid cells.
#[derive(Debug, Clone)]
pub struct FlatLayout {
    /// Flat vertex positions.
    pub flat: Vec<Vec2>,
    /// Triangles (counter-clockwise in the flat sheet).
    pub triangles: Vec<[u32; 3]>,
    /// Cell of each triangle.
    pub face_cells: Vec<usize>,
    /// The cells.
    pub cells: Vec<Cell>,
    /// Piece of each triangle and the pieces.
    pub face_pieces: Vec<u32>,
    /// Curved pieces (one per region, in region order) then planar pieces.
    pub pieces: Vec<Piece>,
    /// Rulings as vertex chains (moved into the mesh by [`crate::bend`]; empty in a
    /// [`crate::BentSheet`]'s layout, whose mesh holds them).
    pub rulings: Vec<Ruling>,
    /// Per region, per ruling: the vertex of the geodesic point.
    pub geodesic_vertices: Vec<Vec<u32>>,
}

#[derive(Clone, Copy)]
struct LayoutVertex {
    position: Point2<f64>,
    index: usize,
}

impl HasPosition for LayoutVertex {
    type Scalar = f64;
    fn position(&self) -> Point2<f64> {
        self.position
    }
}

/// A boundary point awaiting a vertex index.
struct PendingBoundary {
    key: (usize, usize),
    parameter: f64,
    point: Vec2,
    slot: usize,
}

/// Builds the layout. `geometries[k]` holds region `k`'s sampled rulings and extents.
///
/// # Errors
/// [`BendError::Inadmissible`] when rulings of different regions (or of one region)
/// cross on the sheet (§4.3); [`BendError::Composite`] when part of the sheet is not
/// reached by any ruling.
pub fn flat_layout(model: &BendModel, geometries: &[RegionGeometry]) -> Result<FlatLayout, BendError> {
    let sheet = &model.sheet;
    let scale = sheet.scale();
    let eps = 1e-10 * scale;
    let mut points: Vec<Vec2> = Vec::new();
    let mut ring_vertex: Vec<Vec<usize>> = Vec::new();
    for r in 0..sheet.ring_count() {
        ring_vertex.push(
            sheet
                .ring(r)
                .iter()
                .map(|p| {
                    points.push(*p);
                    points.len() - 1
                })
                .collect(),
        );
    }
    // Slots: vertex ids resolved after boundary points are merged.
    let mut slots: Vec<usize> = Vec::new();
    let mut pending: Vec<PendingBoundary> = Vec::new();
    let mut add_boundary = |bp: BoundaryPoint, p: Vec2, slots: &mut Vec<usize>| -> usize {
        slots.push(usize::MAX);
        pending.push(PendingBoundary {
            key: (bp.ring, bp.edge),
            parameter: bp.edge_parameter,
            point: p,
            slot: slots.len() - 1,
        });
        slots.len() - 1
    };
    // Ruling pieces as chains of slot-or-vertex references.
    #[derive(Clone, Copy)]
    enum Ref {
        Slot(usize),
        Vertex(usize),
    }
    // Chains in one array: (region, ruling, start of its refs in `chain_refs`).
    let mut chains: Vec<(usize, usize, usize)> = Vec::new();
    let mut chain_refs: Vec<Ref> = Vec::new();
    let mut geodesic_refs: Vec<Vec<Ref>> = Vec::new();
    let mut bounds: Vec<(f64, BoundaryPoint)> = Vec::new();
    let mut inner: Vec<(f64, Option<BoundaryPoint>)> = Vec::new();
    for (k, g) in geometries.iter().enumerate() {
        let mut geo = Vec::with_capacity(g.samples.len());
        for (j, (s, e)) in g.samples.iter().zip(&g.extents).enumerate() {
            let at = |l: f64| s.flat_point + s.flat_ruling * l;
            // Pieces of [l1, l0] outside the holes.
            bounds.clear();
            bounds.push((e.negative_end, e.ends[0]));
            for (gap, ends) in &e.gaps {
                bounds.push((gap[0], ends[0]));
                bounds.push((gap[1], ends[1]));
            }
            bounds.push((e.positive_end, e.ends[1]));
            let mut geo_ref = None;
            for piece in bounds.chunks(2) {
                let (a, b) = (piece[0], piece[1]);
                if b.0 - a.0 <= eps {
                    continue;
                }
                let ra = Ref::Slot(add_boundary(a.1, at(a.0), &mut slots));
                let rb = Ref::Slot(add_boundary(b.1, at(b.0), &mut slots));
                chains.push((k, j, chain_refs.len()));
                chain_refs.push(ra);
                inner.clear();
                inner.extend(
                    e.touches
                        .iter()
                        .filter(|(t, _)| *t > a.0 + eps && *t < b.0 - eps)
                        .map(|(t, bp)| (*t, Some(*bp))),
                );
                let geo_on_touch = inner.iter().any(|(t, _)| t.abs() <= eps);
                if a.0 < -eps && b.0 > eps && !geo_on_touch {
                    inner.push((0.0, None));
                }
                inner.sort_by(|x, y| x.0.total_cmp(&y.0));
                for &(t, bp) in &inner {
                    let r = match bp {
                        Some(bp) => Ref::Slot(add_boundary(bp, at(t), &mut slots)),
                        None => {
                            // A geodesic point on the boundary (to rounding: outlines are
                            // often typed with the curve length to a few decimals) must
                            // split that boundary edge, not float next to it.
                            let (d, bp) =
                                crate::ruling_extent::locate_on_boundary(sheet, s.flat_point, 0..sheet.ring_count());
                            if d <= eps {
                                let ring = sheet.ring(bp.ring);
                                let (ea, eb) = (ring[bp.edge], ring[(bp.edge + 1) % ring.len()]);
                                Ref::Slot(add_boundary(bp, ea + (eb - ea) * bp.edge_parameter, &mut slots))
                            } else {
                                points.push(s.flat_point);
                                Ref::Vertex(points.len() - 1)
                            }
                        }
                    };
                    if t.abs() <= eps {
                        geo_ref = Some(r);
                    }
                    chain_refs.push(r);
                }
                if a.0.abs() <= eps {
                    geo_ref = Some(ra);
                } else if b.0.abs() <= eps {
                    geo_ref = Some(rb);
                }
                chain_refs.push(rb);
            }
            let geo_ref = match geo_ref {
                Some(r) => r,
                None => {
                    // Degenerate extent (a ruling of zero length on the sheet): the
                    // geodesic point is on the boundary.
                    let (_, bp) = crate::ruling_extent::locate_on_boundary(sheet, s.flat_point, 0..sheet.ring_count());
                    Ref::Slot(add_boundary(bp, s.flat_point, &mut slots))
                }
            };
            geo.push(geo_ref);
        }
        geodesic_refs.push(geo);
    }
    // Merge boundary points per edge; snap to ring vertices.
    // Bucketed by outline edge (counting sort), then by parameter: each bucket comes in
    // ruling order, so it is usually already sorted one way or the other.
    let mut edge_offset: Vec<usize> = Vec::with_capacity(sheet.ring_count() + 1);
    edge_offset.push(0);
    for r in 0..sheet.ring_count() {
        edge_offset.push(edge_offset[r] + sheet.ring(r).len());
    }
    let bucket_of = |p: &PendingBoundary| edge_offset[p.key.0] + p.key.1;
    let mut bucket_start = vec![0usize; edge_offset[sheet.ring_count()] + 1];
    for p in &pending {
        bucket_start[bucket_of(p) + 1] += 1;
    }
    for b in 1..bucket_start.len() {
        bucket_start[b] += bucket_start[b - 1];
    }
    let mut fill = bucket_start.clone();
    let mut order = vec![0usize; pending.len()];
    for (i, p) in pending.iter().enumerate() {
        let b = bucket_of(p);
        order[fill[b]] = i;
        fill[b] += 1;
    }
    for w in bucket_start.windows(2) {
        let bucket = &mut order[w[0]..w[1]];
        let at = |i: &usize| pending[*i].parameter;
        if bucket.windows(2).all(|x| at(&x[0]) >= at(&x[1])) {
            bucket.reverse();
        }
        if !bucket.windows(2).all(|x| at(&x[0]) <= at(&x[1])) {
            bucket.sort_unstable_by(|x, y| at(x).total_cmp(&at(y)));
        }
    }
    let pending: Vec<&PendingBoundary> = order.iter().map(|&i| &pending[i]).collect();
    let mut edge_points: HashMap<(usize, usize), Vec<usize>> = HashMap::default();
    let mut last: Option<((usize, usize), Vec2, usize)> = None;
    for p in pending {
        let ring = sheet.ring(p.key.0);
        let n = ring.len();
        let (a, b) = (ring[p.key.1], ring[(p.key.1 + 1) % n]);
        let vertex = if (p.point - a).norm() <= eps {
            ring_vertex[p.key.0][p.key.1]
        } else if (p.point - b).norm() <= eps {
            ring_vertex[p.key.0][(p.key.1 + 1) % n]
        } else if let Some((key, q, v)) = last.filter(|(key, q, _)| *key == p.key && (q - p.point).norm() <= eps) {
            let _ = (key, q);
            v
        } else {
            points.push(p.point);
            let v = points.len() - 1;
            edge_points.entry(p.key).or_default().push(v);
            v
        };
        slots[p.slot] = vertex;
        last = Some((p.key, p.point, vertex));
    }
    let resolve = |r: Ref| match r {
        Ref::Slot(s) => slots[s],
        Ref::Vertex(v) => v,
    };
    // Constraint edges, each stored once in the direction it was first given (boundary
    // edges in ring order, the sheet on their left), with its kind.
    let mut edges: Vec<[usize; 2]> = Vec::with_capacity(points.len() * 2);
    let mut edge_kinds: Vec<EdgeKind> = Vec::with_capacity(points.len() * 2);
    let mut edge_index: HashMap<[usize; 2], usize> =
        HashMap::with_capacity_and_hasher(points.len(), Default::default());
    // Only an edge between two boundary vertices can be given twice (a ruling running
    // along the outline, a geodesic along it); other edges go in without a lookup.
    let mut is_boundary = vec![false; points.len()];
    for v in ring_vertex.iter().flatten().chain(edge_points.values().flatten()) {
        is_boundary[*v] = true;
    }
    let mut push_edge = |a: usize, b: usize, kind: EdgeKind, edges: &mut Vec<[usize; 2]>, kinds: &mut Vec<EdgeKind>| {
        if a == b {
            return;
        }
        if !(is_boundary[a] && is_boundary[b]) {
            edges.push([a, b]);
            kinds.push(kind);
            return;
        }
        let key = if a < b { [a, b] } else { [b, a] };
        match edge_index.get(&key) {
            Some(&e) => {
                // A geodesic edge that is also a ruling or boundary edge takes that kind.
                if kinds[e] == EdgeKind::Geodesic && kind != EdgeKind::Geodesic {
                    kinds[e] = kind;
                    edges[e] = [a, b];
                }
            }
            None => {
                edge_index.insert(key, edges.len());
                edges.push([a, b]);
                kinds.push(kind);
            }
        }
    };
    // Boundary sub-edges in ring order (the sheet on their left).
    let mut forward_boundary: Vec<[usize; 2]> = Vec::new();
    for (r, verts) in ring_vertex.iter().enumerate() {
        let n = verts.len();
        for i in 0..n {
            let mut along = vec![verts[i]];
            if let Some(list) = edge_points.get(&(r, i)) {
                along.extend(list.iter().copied());
            }
            along.push(verts[(i + 1) % n]);
            forward_boundary.extend(along.windows(2).map(|w| [w[0], w[1]]));
        }
    }
    for &[a, b] in &forward_boundary {
        push_edge(a, b, EdgeKind::Boundary, &mut edges, &mut edge_kinds);
    }
    let mut rulings = Vec::with_capacity(chains.len());
    let mut dedup: Vec<usize> = Vec::new();
    for (c, &(region, ruling, start)) in chains.iter().enumerate() {
        let end = chains.get(c + 1).map_or(chain_refs.len(), |next| next.2);
        dedup.clear();
        for r in &chain_refs[start..end] {
            let v = resolve(*r);
            if dedup.last() != Some(&v) {
                dedup.push(v);
            }
        }
        for w in dedup.windows(2) {
            push_edge(
                w[0],
                w[1],
                EdgeKind::Ruling { region, ruling },
                &mut edges,
                &mut edge_kinds,
            );
        }
        if dedup.len() >= 2 {
            rulings.push(Ruling {
                vertices: dedup.iter().map(|&v| v as u32).collect(),
                piece: region as u32,
                arc_length: geometries[region].samples[ruling].arc_length,
            });
        }
    }
    let geodesic_vertices: Vec<Vec<u32>> = geodesic_refs
        .iter()
        .map(|g| g.iter().map(|r| resolve(*r) as u32).collect())
        .collect();
    for (k, g) in geodesic_vertices.iter().enumerate() {
        // Outline or hole vertices that the flat geodesic passes through (a hole tangent
        // to it, say) must be vertices of its chain too.
        let region = &model.regions[k];
        let length = region.curve.length();
        let (start, dir) = match region.flat {
            crate::FlatPath::Straight { start, direction } => (start, direction),
            // Curved flat paths: their chords rarely pass exactly through an outline vertex.
            _ => (Vec2::zeros(), Vec2::zeros()),
        };
        let mut chain: Vec<(f64, usize)> = g
            .iter()
            .zip(&geometries[k].samples)
            .map(|(&v, s)| (s.arc_length, v as usize))
            .collect();
        for (r, verts) in ring_vertex.iter().enumerate() {
            for (p, &v) in sheet.ring(r).iter().zip(verts) {
                let d = p - start;
                let t = d.dot(&dir);
                if t > eps && t < length - eps && (d.x * dir.y - d.y * dir.x).abs() <= eps {
                    chain.push((t, v));
                }
            }
        }
        chain.sort_by(|a, b| a.0.total_cmp(&b.0));
        for w in chain.windows(2) {
            push_edge(w[0].1, w[1].1, EdgeKind::Geodesic, &mut edges, &mut edge_kinds);
        }
    }

    // §4.3: rulings of different regions must not cross on the sheet (end rulings and
    // flat geodesics against every ruling of the other regions).
    check_region_crossings(model, geometries, scale)?;

    // Faces of the planar graph (half-edge walk), each to the left of its edges.
    let graph = graph_faces(&points, &edges);
    let kind_of_half = |h: usize| edge_kinds[graph.edge(h)];
    let mut outer_halves = Cycles::default();
    let mut outer_cycles = Cycles::default();
    let mut inner_cycles = Cycles::default();
    let mut scratch: Vec<usize> = Vec::new();
    for fi in 0..graph.faces.len() {
        let cycle = graph.faces.get(fi);
        // Left of a boundary edge run backwards is outside the sheet (or in a hole).
        let outside = cycle
            .iter()
            .any(|&h| !graph.forward(h) && kind_of_half(h) == EdgeKind::Boundary);
        if outside {
            continue;
        }
        scratch.clear();
        scratch.extend(cycle.iter().map(|&h| graph.origin(h)));
        // Twice the signed area, from the half-edges' own ends.
        let area: f64 = cycle
            .iter()
            .map(|&h| {
                let (a, b) = (points[graph.origin(h)], points[graph.target(h)]);
                a.x * b.y - b.x * a.y
            })
            .sum();
        if area > 0.0 {
            outer_cycles.push(&scratch);
            outer_halves.push(cycle);
        } else {
            inner_cycles.push(&scratch);
        }
    }
    let faces = outer_cycles.len();
    // Islands (holes no ruling touches) belong to the smallest face around them.
    let mut face_holes: Vec<Vec<usize>> = vec![Vec::new(); if inner_cycles.len() > 0 { faces } else { 0 }];
    for h in 0..inner_cycles.len() {
        let p = points[inner_cycles.get(h)[0]];
        let owner = (0..faces)
            .filter(|&i| cycle_contains(&points, outer_cycles.get(i), p))
            .min_by(|&a, &b| {
                cycle_area(&points, outer_cycles.get(a)).total_cmp(&cycle_area(&points, outer_cycles.get(b)))
            })
            .ok_or_else(|| BendError::Composite {
                message: "a hole boundary is not inside any piece of the sheet".into(),
            })?;
        face_holes[owner].push(h);
    }
    let mut triangles: Vec<[u32; 3]> = Vec::with_capacity(points.len() * 2);
    let mut triangle_face: Vec<usize> = Vec::with_capacity(points.len() * 2);
    for f in 0..faces {
        let holes: Vec<&[usize]> = face_holes
            .get(f)
            .map_or(Vec::new(), |hs| hs.iter().map(|&h| inner_cycles.get(h)).collect());
        let before = triangles.len();
        triangulate_face(&points, outer_cycles.get(f), &holes, &mut triangles)?;
        triangle_face.extend(std::iter::repeat_n(f, triangles.len() - before));
    }
    let triangle_area: f64 = triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| points[i as usize]);
            0.5 * ((b - a).x * (c - a).y - (b - a).y * (c - a).x).abs()
        })
        .sum();
    if (triangle_area - sheet.area()).abs() > 1e-9 * sheet.area() {
        return Err(BendError::Inadmissible(Box::new(InadmissibleDetail {
            message: format!(
                "rulings cross inside the sheet: the pieces between them cover {} {u}² instead of the sheet's {} {u}²",
                numbers_apart(triangle_area, sheet.area())[0],
                numbers_apart(triangle_area, sheet.area())[1],
                u = model.unit.symbol()
            ),
            region: 0,
            arc_length_range: [0.0, 0.0],
            flat_point: [f64::NAN, f64::NAN],
            point: None,
        })));
    }
    // Labels from ruling edges; cells join faces across geodesic edges.
    let mut face_of_half = vec![usize::MAX; graph.origin.len()];
    for f in 0..faces {
        for &h in outer_halves.get(f) {
            face_of_half[h] = f;
        }
    }
    let mut parent: Vec<usize> = (0..faces).collect();
    fn find(parent: &mut [usize], mut x: usize) -> usize {
        while parent[x] != x {
            parent[x] = parent[parent[x]];
            x = parent[x];
        }
        x
    }
    // (face, region, part) for every ruling edge of every face.
    let mut face_labels: Vec<(usize, usize, usize)> = Vec::with_capacity(faces * 2);
    for f in 0..faces {
        for &h in outer_halves.get(f) {
            match kind_of_half(h) {
                EdgeKind::Ruling { region, ruling } => {
                    let s = &geometries[region].samples[ruling];
                    let m = Vec2::new(s.flat_ruling.y, -s.flat_ruling.x);
                    let m = if m.dot(&s.flat_tangent) >= 0.0 { m } else { -m };
                    let d = points[graph.target(h)] - points[graph.origin(h)];
                    let left = Vec2::new(-d.y, d.x);
                    let part = if left.dot(&m) > 0.0 { ruling + 1 } else { ruling };
                    face_labels.push((f, region, part));
                }
                EdgeKind::Geodesic => {
                    let g = face_of_half[graph.twin(h)];
                    if g != usize::MAX {
                        let (ra, rb) = (find(&mut parent, f), find(&mut parent, g));
                        parent[ra] = rb;
                    }
                }
                EdgeKind::Boundary => {}
            }
        }
    }
    // A point inside each face: the centroid of its first triangle.
    let mut face_sample = vec![Vec2::zeros(); faces];
    for (t, &f) in triangles.iter().zip(&triangle_face).rev() {
        face_sample[f] = t.iter().map(|&v| points[v as usize]).sum::<Vec2>() / 3.0;
    }
    // Cells: one per union-find root, numbered in face order.
    let mut cell_of_root = vec![usize::MAX; faces];
    let mut cells: Vec<Cell> = Vec::new();
    let face_cell: Vec<usize> = (0..faces)
        .map(|f| {
            let root = find(&mut parent, f);
            if cell_of_root[root] == usize::MAX {
                cell_of_root[root] = cells.len();
                cells.push(Cell {
                    labels: Vec::new(),
                    vertices: Vec::new(),
                    sample_point: face_sample[f],
                });
            }
            cell_of_root[root]
        })
        .collect();
    for &(f, r, p) in &face_labels {
        let labels = &mut cells[face_cell[f]].labels;
        if !labels.contains(&(r, p)) {
            labels.push((r, p));
        }
    }
    for c in &mut cells {
        c.labels.sort_unstable();
    }
    // Vertices only for cells held by more than one label: their placement is checked.
    let mut cell_vertices: Vec<(usize, u32)> = Vec::new();
    for (f, &c) in face_cell.iter().enumerate() {
        if cells[c].labels.len() < 2 {
            continue;
        }
        cell_vertices.extend(outer_cycles.get(f).iter().map(|&v| (c, v as u32)));
        if let Some(hs) = face_holes.get(f) {
            for &h in hs {
                cell_vertices.extend(inner_cycles.get(h).iter().map(|&v| (c, v as u32)));
            }
        }
    }
    cell_vertices.sort_unstable();
    cell_vertices.dedup();
    for (c, v) in cell_vertices {
        cells[c].vertices.push(v);
    }
    let face_cells: Vec<usize> = triangle_face.iter().map(|&f| face_cell[f]).collect();
    for c in &cells {
        if c.labels.is_empty() {
            return Err(BendError::Composite {
                message: format!(
                    "the part of the sheet around flat ({}, {}) is not reached by any ruling",
                    short_number(c.sample_point.x),
                    short_number(c.sample_point.y)
                ),
            });
        }
    }
    // Pieces: one curved piece per region, one planar piece per cell with only end labels.
    let mut pieces: Vec<Piece> = model
        .regions
        .iter()
        .map(|r| Piece {
            name: r.name.clone(),
            kind: PieceKind::Curved,
        })
        .collect();
    let mut cell_piece = vec![0u32; cells.len()];
    for (ci, c) in cells.iter().enumerate() {
        let curved = c
            .labels
            .iter()
            .find(|(k, part)| *part >= 1 && *part < geometries[*k].samples.len());
        cell_piece[ci] = match curved {
            Some((k, _)) => *k as u32,
            None => {
                pieces.push(Piece {
                    name: format!("planar-{}", pieces.len() - model.regions.len()),
                    kind: PieceKind::Planar,
                });
                (pieces.len() - 1) as u32
            }
        };
    }
    let face_pieces = face_cells.iter().map(|&c| cell_piece[c]).collect();
    Ok(FlatLayout {
        flat: points,
        triangles,
        face_cells,
        cells,
        face_pieces,
        pieces,
        rulings,
        geodesic_vertices,
    })
}

fn cycle_area(points: &[Vec2], cycle: &[usize]) -> f64 {
    let n = cycle.len();
    (0..n)
        .map(|i| {
            let (a, b) = (points[cycle[i]], points[cycle[(i + 1) % n]]);
            a.x * b.y - b.x * a.y
        })
        .sum::<f64>()
        * 0.5
}

fn cycle_contains(points: &[Vec2], cycle: &[usize], p: Vec2) -> bool {
    let n = cycle.len();
    let mut inside = false;
    let mut j = n - 1;
    for i in 0..n {
        let (a, b) = (points[cycle[i]], points[cycle[j]]);
        if (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y) {
            inside = !inside;
        }
        j = i;
    }
    inside
}

/// The half-edges of a planar straight-line graph and its faces. Indices are `u32`
/// (half the memory traffic of `usize` on the hot path of every bend).
struct PlanarGraph {
    /// Start vertex of each half-edge.
    origin: Vec<u32>,
    /// End vertex of each half-edge.
    target: Vec<u32>,
    /// The opposite half-edge.
    twin: Vec<u32>,
    /// `2e` for the half-edge that runs along input edge `e` as given, `2e + 1` for the
    /// reverse one.
    directed_edge: Vec<u32>,
    /// Faces as cycles of half-edges, each face to the left of its half-edges.
    faces: Cycles,
}

impl PlanarGraph {
    fn origin(&self, h: usize) -> usize {
        self.origin[h] as usize
    }
    fn target(&self, h: usize) -> usize {
        self.target[h] as usize
    }
    fn twin(&self, h: usize) -> usize {
        self.twin[h] as usize
    }
    /// The input edge of half-edge `h`.
    fn edge(&self, h: usize) -> usize {
        (self.directed_edge[h] >> 1) as usize
    }
    /// Whether `h` runs along its input edge as given.
    fn forward(&self, h: usize) -> bool {
        self.directed_edge[h] & 1 == 0
    }
}

/// Many short index cycles in one array (`items[start[i]..start[i + 1]]` is cycle `i`).
#[derive(Debug, Default)]
struct Cycles {
    start: Vec<usize>,
    items: Vec<usize>,
}

impl Cycles {
    fn len(&self) -> usize {
        self.start.len()
    }
    fn get(&self, i: usize) -> &[usize] {
        let end = self.start.get(i + 1).copied().unwrap_or(self.items.len());
        &self.items[self.start[i]..end]
    }
    fn push(&mut self, cycle: &[usize]) {
        self.start.push(self.items.len());
        self.items.extend_from_slice(cycle);
    }
}

/// Monotone in the polar angle of `d` (the "diamond angle", in [0, 4)): sorts directions
/// like `atan2` without trigonometry.
fn pseudo_angle(d: Vec2) -> f64 {
    let p = d.y / (d.x.abs() + d.y.abs());
    if d.x < 0.0 {
        2.0 - p
    } else if d.y < 0.0 {
        4.0 + p
    } else {
        p
    }
}

/// The faces of a planar straight-line graph: at each vertex the walk takes the next
/// outgoing edge clockwise from the one it came in on, so every face lies to the left of
/// its half-edges. Half-edges live in arrays (adjacency sorted by angle per vertex), so
/// the walk is linear after the per-vertex sorts.
fn graph_faces(points: &[Vec2], edges: &[[usize; 2]]) -> PlanarGraph {
    let nv = points.len();
    let mut start = vec![0u32; nv + 1];
    for &[a, b] in edges {
        start[a + 1] += 1;
        start[b + 1] += 1;
    }
    for v in 0..nv {
        start[v + 1] += start[v];
    }
    let halves = start[nv] as usize;
    let end_of = |d: u32| {
        let [a, b] = edges[(d >> 1) as usize];
        if d & 1 == 0 {
            b
        } else {
            a
        }
    };
    // Bucket the directed edges by origin, then sort each bucket by angle.
    let mut directed_edge = vec![0u32; halves];
    let mut fill = start.clone();
    for (e, &[a, b]) in edges.iter().enumerate() {
        directed_edge[fill[a] as usize] = 2 * e as u32;
        fill[a] += 1;
        directed_edge[fill[b] as usize] = 2 * e as u32 + 1;
        fill[b] += 1;
    }
    drop(fill);
    let mut order: Vec<(f64, u32)> = Vec::new();
    let mut origin = vec![0u32; halves];
    let mut target = vec![0u32; halves];
    // position[d]: the half-edge of directed edge d after sorting.
    let mut position = vec![0u32; halves];
    for v in 0..nv {
        let p = points[v];
        let range = start[v] as usize..start[v + 1] as usize;
        order.clear();
        order.extend(
            directed_edge[range.clone()]
                .iter()
                .map(|&d| (pseudo_angle(points[end_of(d)] - p), d)),
        );
        // Degrees are small (mostly 2 to 4): insertion sort.
        for i in 1..order.len() {
            let mut j = i;
            while j > 0 && order[j - 1].0 > order[j].0 {
                order.swap(j - 1, j);
                j -= 1;
            }
        }
        for (h, &(_, d)) in range.zip(order.iter()) {
            directed_edge[h] = d;
            position[d as usize] = h as u32;
            origin[h] = v as u32;
            target[h] = end_of(d) as u32;
        }
    }
    // twin[h]: the half-edge w→v for h = v→w (the other direction of the same edge).
    let twin: Vec<u32> = directed_edge.iter().map(|&d| position[(d ^ 1) as usize]).collect();
    drop(position);
    let mut used = vec![false; halves];
    let mut faces = Cycles {
        start: Vec::with_capacity(halves / 3),
        items: Vec::with_capacity(halves),
    };
    for h0 in 0..halves {
        if used[h0] {
            continue;
        }
        faces.start.push(faces.items.len());
        let mut h = h0;
        loop {
            used[h] = true;
            faces.items.push(h);
            // At v = target[h] the reverse half-edge is twin[h]; take the next one clockwise.
            let v = target[h] as usize;
            let (s, e) = (start[v] as usize, start[v + 1] as usize);
            let i = twin[h] as usize;
            h = if i == s { e - 1 } else { i - 1 };
            if h == h0 || used[h] {
                break;
            }
        }
    }
    PlanarGraph {
        origin,
        target,
        twin,
        directed_edge,
        faces,
    }
}

/// Triangulates one face (a counter-clockwise cycle, with clockwise island cycles): a fan
/// for convex faces without islands, otherwise a constrained Delaunay triangulation of
/// the face alone (spade) keeping the triangles inside.
fn triangulate_face(
    points: &[Vec2],
    cycle: &[usize],
    holes: &[&[usize]],
    out: &mut Vec<[u32; 3]>,
) -> Result<(), BendError> {
    let n = cycle.len();
    let convex = holes.is_empty()
        && (0..n).all(|i| {
            let (a, b, c) = (points[cycle[i]], points[cycle[(i + 1) % n]], points[cycle[(i + 2) % n]]);
            // Strictly convex: collinear runs (touch points, hole gaps) go to the CDT,
            // so a fan never makes a zero-area triangle.
            let turn = (b - a).x * (c - b).y - (b - a).y * (c - b).x;
            turn > 0.0 && turn * turn > 1e-24 * (b - a).norm_squared() * (c - b).norm_squared()
        });
    if convex {
        // Fan from the vertex that gives the best smallest angle is overkill here; fan from
        // a vertex that is not collinear with its neighbours.
        let apex = (0..n)
            .find(|&i| {
                let (a, b, c) = (
                    points[cycle[(i + n - 1) % n]],
                    points[cycle[i]],
                    points[cycle[(i + 1) % n]],
                );
                (b - a).x * (c - b).y - (b - a).y * (c - b).x > 0.0
            })
            .unwrap_or(0);
        for k in 1..n - 1 {
            let (i, j) = ((apex + k) % n, (apex + k + 1) % n);
            let t = [cycle[apex], cycle[i], cycle[j]];
            let [a, b, c] = t.map(|v| points[v]);
            if ((b - a).x * (c - a).y - (b - a).y * (c - a).x) > 0.0 {
                out.push(t.map(|v| v as u32));
            }
        }
        return Ok(());
    }
    let mut local: Vec<usize> = cycle.to_vec();
    for h in holes {
        local.extend(h.iter().copied());
    }
    let index_of: HashMap<usize, usize> = local.iter().enumerate().map(|(i, &v)| (v, i)).collect();
    let vertices: Vec<LayoutVertex> = local
        .iter()
        .map(|&v| LayoutVertex {
            position: Point2::new(points[v].x, points[v].y),
            index: v,
        })
        .collect();
    let mut cons: Vec<[usize; 2]> = Vec::new();
    let mut directed: HashSet<[usize; 2]> = HashSet::default();
    for ring in std::iter::once(cycle).chain(holes.iter().copied()) {
        for i in 0..ring.len() {
            let (a, b) = (ring[i], ring[(i + 1) % ring.len()]);
            cons.push([index_of[&a], index_of[&b]]);
            directed.insert([a, b]);
        }
    }
    let mut conflict = false;
    let cdt = ConstrainedDelaunayTriangulation::<LayoutVertex>::try_bulk_load_cdt(vertices, cons, |_| conflict = true)
        .map_err(|e| BendError::Composite {
            message: format!(
                "triangulating a piece of the sheet failed: {}",
                sheetform_geometry::triangulation_problem(&e)
            ),
        })?;
    if conflict || cdt.num_vertices() != local.len() {
        return Err(BendError::Inadmissible(Box::new(InadmissibleDetail {
            message: "rulings cross or touch inside the sheet (a piece between them is not a simple polygon)".into(),
            region: 0,
            arc_length_range: [0.0, 0.0],
            flat_point: [points[cycle[0]].x, points[cycle[0]].y],
            point: None,
        })));
    }
    // Inside = odd number of constraint edges crossed from the outer face (robust for
    // slivers whose centroid lies on the boundary).
    let is_constraint = |e: spade::handles::DirectedEdgeHandle<LayoutVertex, (), spade::CdtEdge<()>, ()>| {
        let [a, b] = e.vertices().map(|v| v.data().index);
        cdt.is_constraint_edge(e.as_undirected().fix()) && (directed.contains(&[a, b]) || directed.contains(&[b, a]))
    };
    let mut inside: HashMap<usize, bool> = HashMap::default();
    let mut queue = std::collections::VecDeque::new();
    for edge in cdt.directed_edges() {
        if edge.face().fix() == cdt.outer_face().fix() {
            if let Some(f) = edge.rev().face().as_inner() {
                if let std::collections::hash_map::Entry::Vacant(slot) = inside.entry(f.fix().index()) {
                    slot.insert(is_constraint(edge));
                    queue.push_back(f.fix());
                }
            }
        }
    }
    while let Some(h) = queue.pop_front() {
        let state = inside[&h.index()];
        for edge in cdt.face(h).adjacent_edges() {
            if let Some(next) = edge.rev().face().as_inner() {
                if let std::collections::hash_map::Entry::Vacant(slot) = inside.entry(next.fix().index()) {
                    slot.insert(state ^ is_constraint(edge));
                    queue.push_back(next.fix());
                }
            }
        }
    }
    for face in cdt.inner_faces() {
        if inside.get(&face.fix().index()).copied().unwrap_or(false) {
            out.push(face.vertices().map(|v| v.data().index as u32));
        }
    }
    Ok(())
}

/// §4.3: the end rulings and the flat geodesic of each region must not cross any ruling
/// of another region on the sheet.
fn check_region_crossings(model: &BendModel, geometries: &[RegionGeometry], scale: f64) -> Result<(), BendError> {
    let eps = 1e-9 * scale;
    let segment = |g: &RegionGeometry, j: usize| {
        let (s, e) = (&g.samples[j], &g.extents[j]);
        (
            s.flat_point + s.flat_ruling * e.negative_end,
            s.flat_point + s.flat_ruling * e.positive_end,
        )
    };
    for (a, ga) in geometries.iter().enumerate() {
        let n = ga.samples.len();
        let mut tests = vec![segment(ga, 0), segment(ga, n - 1)];
        tests.push((ga.samples[0].flat_point, ga.samples[n - 1].flat_point));
        for (b, gb) in geometries.iter().enumerate() {
            if a == b {
                continue;
            }
            for j in 0..gb.samples.len() {
                let (q0, q1) = segment(gb, j);
                for &(p0, p1) in &tests {
                    if let Some((t, _)) = segment_intersection(p0, p1, q0, q1) {
                        let p = p0 + (p1 - p0) * t;
                        if [p0, p1, q0, q1].iter().all(|x| (x - p).norm() > eps) {
                            return Err(BendError::Inadmissible(Box::new(InadmissibleDetail {
                                message: format!(
                                    "rulings of region {a} (`{}`) and region {b} (`{}`) cross on the sheet at flat ({}, {}) (§4.3)",
                                    model.regions[a].name,
                                    model.regions[b].name,
                                    short_number(p.x),
                                    short_number(p.y)
                                ),
                                region: b,
                                arc_length_range: [gb.samples[j].arc_length, gb.samples[j].arc_length],
                                flat_point: [p.x, p.y],
                                point: None,
                            })));
                        }
                    }
                }
            }
        }
    }
    Ok(())
}
