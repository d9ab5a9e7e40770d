//! The islands of a net and the one move that builds them: hinging two islands together
//! across a mesh edge, kept only when the union overlaps nowhere, keeps a cutting
//! clearance between its cut lines and fits the sheet.

use crate::edge_unfolding::{FaceGeometry, Growth};
use crate::Vec2;
use rustc_hash::FxHashMap;
use sheetform_geometry::{convex_hull, fits_turned, fitting_rotation, segment_distance, triangles_overlap};
use sheetform_mesh::EdgeTable;

/// What every island of a net keeps (model units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct IslandLimits {
    /// Two cut lines of one island that share no point stay this far apart (0: only no
    /// overlap).
    pub(crate) clearance: f64,
    /// Two cut lines of one island that share no point but end at the same mesh vertex
    /// (the sides of a slit, where a seam folds back on itself and both copies face each
    /// other) stay this far apart: room for a glue tab between them.
    pub(crate) slit_clearance: f64,
    /// Every island fits a rectangle of this size, turned as needed (`None`: any size).
    pub(crate) sheet: Option<(f64, f64)>,
}

/// Most grid cells a face or a cut line is entered in; larger ones go to their island's
/// list of big items, tested by every query.
const MAX_CELLS_PER_ITEM: i64 = 256;

/// Items (faces, or a face's edge `(face, corner)`) of each island in a uniform grid;
/// entries of islands since joined to another stay behind and are skipped by the caller.
struct IslandGrid<T> {
    cell: f64,
    cells: FxHashMap<(u32, i64, i64), Vec<T>>,
    big: FxHashMap<u32, Vec<T>>,
}

impl<T: Copy> IslandGrid<T> {
    fn new(cell: f64) -> Self {
        Self {
            cell,
            cells: FxHashMap::default(),
            big: FxHashMap::default(),
        }
    }

    fn range(&self, lo: Vec2, hi: Vec2) -> Option<(i64, i64, i64, i64)> {
        let r = (
            (lo.x / self.cell).floor() as i64,
            (hi.x / self.cell).floor() as i64,
            (lo.y / self.cell).floor() as i64,
            (hi.y / self.cell).floor() as i64,
        );
        ((r.1 - r.0 + 1).saturating_mul(r.3 - r.2 + 1) <= MAX_CELLS_PER_ITEM).then_some(r)
    }

    fn insert(&mut self, island: u32, lo: Vec2, hi: Vec2, item: T) {
        match self.range(lo, hi) {
            Some((x0, x1, y0, y1)) => {
                for x in x0..=x1 {
                    for y in y0..=y1 {
                        self.cells.entry((island, x, y)).or_default().push(item);
                    }
                }
            }
            None => self.big.entry(island).or_default().push(item),
        }
    }

    /// Calls `visit` on the items of `island` near the box `lo..hi` (some more than once,
    /// and stale ones) until it returns `false`; a query too large for the cells visits
    /// the island's every item (`all()`). Returns whether every call returned `true`.
    fn visit(
        &self,
        island: u32,
        lo: Vec2,
        hi: Vec2,
        all: impl FnOnce() -> Vec<T>,
        mut visit: impl FnMut(T) -> bool,
    ) -> bool {
        match self.range(lo, hi) {
            Some((x0, x1, y0, y1)) => {
                if let Some(list) = self.big.get(&island) {
                    if !list.iter().all(|&item| visit(item)) {
                        return false;
                    }
                }
                for x in x0..=x1 {
                    for y in y0..=y1 {
                        if let Some(list) = self.cells.get(&(island, x, y)) {
                            if !list.iter().all(|&item| visit(item)) {
                                return false;
                            }
                        }
                    }
                }
                true
            }
            None => all().into_iter().all(visit),
        }
    }
}

fn bounds(points: &[Vec2]) -> (Vec2, Vec2) {
    points.iter().fold(
        (Vec2::repeat(f64::INFINITY), Vec2::repeat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.inf(p), hi.sup(p)),
    )
}

/// What [`Islands::try_join`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Join {
    /// The two islands are one now.
    Joined,
    /// The union would overlap, come too close or not fit (or the faces were in one
    /// island already): the edge stays cut.
    Refused,
    /// The overlap tests ran out before the answer was known: the edge stays cut.
    Unsettled,
}

/// The islands of a net being built: every face an exact flat copy in its island's frame,
/// the edges kept whole, and spatial grids of each island's faces and cut lines.
pub(crate) struct Islands<'a> {
    faces: &'a FaceGeometry<'a>,
    table: &'a EdgeTable,
    limits: IslandLimits,
    /// Flat corners of every face, in its island's frame.
    flat: Vec<[Vec2; 3]>,
    /// Island of every face (an island is named after one of its faces).
    island: Vec<u32>,
    /// Faces of every island (empty for names no longer used).
    members: Vec<Vec<u32>>,
    /// Edges kept whole.
    kept: Vec<bool>,
    /// Convex hull of every island (with a sheet to fit only).
    hull: Vec<Vec<Vec2>>,
    /// The turn that last fitted each island in the sheet (tried first on the next join).
    turn: Vec<f64>,
    face_grid: IslandGrid<u32>,
    edge_grid: IslandGrid<(u32, u8)>,
    /// Joins refused because the tests ran out.
    budget_cuts: usize,
}

impl<'a> Islands<'a> {
    /// Every face an island of its own, laid flat by [`FaceGeometry::alone`].
    pub(crate) fn new(faces: &'a FaceGeometry<'a>, table: &'a EdgeTable, limits: IslandLimits) -> Self {
        let nf = faces.mesh.triangles.len();
        let flat: Vec<[Vec2; 3]> = (0..nf as u32).map(|f| faces.alone(f)).collect();
        let mut face_grid = IslandGrid::new(faces.cell);
        let mut edge_grid = IslandGrid::new(faces.cell);
        for (f, t) in flat.iter().enumerate() {
            let (lo, hi) = bounds(t);
            face_grid.insert(f as u32, lo, hi, f as u32);
            for k in 0..3u8 {
                let (a, b) = (t[k as usize], t[(k as usize + 1) % 3]);
                edge_grid.insert(f as u32, a.inf(&b), a.sup(&b), (f as u32, k));
            }
        }
        Self {
            hull: if limits.sheet.is_some() {
                flat.iter().map(|t| convex_hull(t.to_vec())).collect()
            } else {
                Vec::new()
            },
            turn: vec![0.0; if limits.sheet.is_some() { nf } else { 0 }],
            faces,
            table,
            limits,
            flat,
            island: (0..nf as u32).collect(),
            members: (0..nf as u32).map(|f| vec![f]).collect(),
            kept: vec![false; table.len()],
            face_grid,
            edge_grid,
            budget_cuts: 0,
        }
    }

    /// The number of islands.
    pub(crate) fn count(&self) -> usize {
        self.members.iter().filter(|m| !m.is_empty()).count()
    }

    /// The island of face `f`.
    pub(crate) fn island_of(&self, f: u32) -> u32 {
        self.island[f as usize]
    }

    /// The number of faces in face `f`'s island.
    pub(crate) fn size_of(&self, f: u32) -> usize {
        self.members[self.island[f as usize] as usize].len()
    }

    /// Face `f`'s flat corners in its island's frame.
    pub(crate) fn flat(&self, f: u32) -> &[Vec2; 3] {
        &self.flat[f as usize]
    }

    /// Whether edge `e` is kept whole.
    pub(crate) fn is_kept(&self, e: usize) -> bool {
        self.kept[e]
    }

    /// Hinges the islands on either side of edge `e` together: the smaller one moves
    /// (a rigid motion) so that its copy of the edge lies on the larger one's. Kept only
    /// when no moved face overlaps a face of the larger island ([`triangles_overlap`],
    /// tolerance `faces.tolerance`; each pair examined takes one test off `tests_left`),
    /// no cut line of the one comes within `limits.clearance` of a cut line of the other
    /// unless the two share an end point on the pattern (a wedge's two sides meet at its
    /// apex), nor within `limits.slit_clearance` when the two end at the same mesh
    /// vertex (the sides of a slit beyond its apex: a narrow slit shows as the lines
    /// beyond its mouth, which share no point), and the union's convex hull fits
    /// `limits.sheet` ([`fitting_rotation`]; the turn that fitted it last, first).
    pub(crate) fn try_join(&mut self, e: usize, tests_left: &mut usize) -> Join {
        let mesh = self.faces.mesh;
        let table = self.table;
        let [f, g] = table.sides(e) else { return Join::Refused };
        let (f, g) = (f.face, g.face);
        let (i_f, i_g) = (self.island[f as usize], self.island[g as usize]);
        if i_f == i_g {
            return Join::Refused;
        }
        // The edge as f runs it (corner k → k + 1), and g's corner j starting it the other
        // way.
        let Some(k) = (0..3).find(|&k| table.face_edges[f as usize][k] as usize == e) else {
            return Join::Refused;
        };
        let (a, b) = (mesh.triangles[f as usize][k], mesh.triangles[f as usize][(k + 1) % 3]);
        let Some(j) =
            (0..3).find(|&j| mesh.triangles[g as usize][j] == b && mesh.triangles[g as usize][(j + 1) % 3] == a)
        else {
            return Join::Refused;
        };
        let f_copy = (self.flat[f as usize][k], self.flat[f as usize][(k + 1) % 3]);
        let g_copy = (self.flat[g as usize][(j + 1) % 3], self.flat[g as usize][j]);
        let (big, small, from, to) = if self.members[i_f as usize].len() >= self.members[i_g as usize].len() {
            (i_f, i_g, g_copy, f_copy)
        } else {
            (i_g, i_f, f_copy, g_copy)
        };
        let (u, v) = ((from.1 - from.0).normalize(), (to.1 - to.0).normalize());
        let (cos, sin) = (u.dot(&v), u.x * v.y - u.y * v.x);
        let motion = |x: Vec2| {
            let d = x - from.0;
            to.0 + Vec2::new(cos * d.x - sin * d.y, sin * d.x + cos * d.y)
        };
        // The sheet: the union's hull fits.
        let mut union_hull = Vec::new();
        if let Some((w, h)) = self.limits.sheet {
            let points: Vec<Vec2> = self.hull[big as usize]
                .iter()
                .copied()
                .chain(self.hull[small as usize].iter().map(|&p| motion(p)))
                .collect();
            union_hull = convex_hull(points);
            if !fits_turned(&union_hull, self.turn[big as usize], w, h) {
                match fitting_rotation(&union_hull, w, h) {
                    Some((turn, _)) => self.turn[big as usize] = turn,
                    None => return Join::Refused,
                }
            }
        }
        let moved: Vec<[Vec2; 3]> = self.members[small as usize]
            .iter()
            .map(|&h| self.flat[h as usize].map(motion))
            .collect();
        // No overlap.
        let tolerance = self.faces.tolerance;
        let (island, flat) = (&self.island, &self.flat);
        let all_faces = &self.members[big as usize];
        for t in &moved {
            let (lo, hi) = bounds(t);
            let (lo, hi) = (lo - Vec2::repeat(tolerance), hi + Vec2::repeat(tolerance));
            let mut spent = false;
            let clear = self.face_grid.visit(
                big,
                lo,
                hi,
                || all_faces.clone(),
                |h| {
                    if island[h as usize] != big {
                        return true;
                    }
                    if *tests_left == 0 {
                        spent = true;
                        return false;
                    }
                    *tests_left -= 1;
                    !triangles_overlap(*t, flat[h as usize], tolerance)
                },
            );
            if spent {
                self.budget_cuts += 1;
                return Join::Unsettled;
            }
            if !clear {
                return Join::Refused;
            }
        }
        // The clearance between cut lines that share no point.
        let (c, slit_clearance) = (self.limits.clearance, self.limits.slit_clearance);
        let reach = c.max(slit_clearance);
        if reach > 0.0 {
            let kept = &self.kept;
            let edge_of = |h: u32, q: u8| table.face_edges[h as usize][q as usize] as usize;
            let near2 = (1e3 * tolerance.max(f64::MIN_POSITIVE)).powi(2);
            let same_point = |p: Vec2, q: Vec2| (p - q).norm_squared() <= near2;
            let all_edges = || all_faces.iter().flat_map(|&h| (0..3u8).map(move |q| (h, q))).collect();
            for (&h, t) in self.members[small as usize].iter().zip(&moved) {
                for q in 0..3u8 {
                    let edge = edge_of(h, q);
                    if edge == e || kept[edge] {
                        continue;
                    }
                    let (p0, p1) = (t[q as usize], t[(q as usize + 1) % 3]);
                    let v = &mesh.triangles[h as usize];
                    let (v0, v1) = (v[q as usize], v[(q as usize + 1) % 3]);
                    let (lo, hi) = (p0.inf(&p1) - Vec2::repeat(reach), p0.sup(&p1) + Vec2::repeat(reach));
                    let clear = self.edge_grid.visit(big, lo, hi, all_edges, |(other, r)| {
                        let edge = edge_of(other, r);
                        if island[other as usize] != big || edge == e || kept[edge] {
                            return true;
                        }
                        let o = &flat[other as usize];
                        let (q0, q1) = (o[r as usize], o[(r as usize + 1) % 3]);
                        if same_point(p0, q0) || same_point(p0, q1) || same_point(p1, q0) || same_point(p1, q1) {
                            return true;
                        }
                        // Two copies around one mesh vertex: the sides of a slit, a
                        // seam that folds back on itself (not two parts of the net
                        // that happen to come close), kept apart by the slit
                        // clearance.
                        let w = &mesh.triangles[other as usize];
                        let (w0, w1) = (w[r as usize], w[(r as usize + 1) % 3]);
                        let slit = v0 == w0 || v0 == w1 || v1 == w0 || v1 == w1;
                        let need = if slit { slit_clearance } else { c };
                        // (Boxes that far apart need no exact distance.)
                        let gap = (q0.inf(&q1) - p0.sup(&p1)).sup(&(p0.inf(&p1) - q0.sup(&q1)));
                        gap.x >= need || gap.y >= need || segment_distance([p0, p1], [q0, q1]) >= need
                    });
                    if !clear {
                        return Join::Refused;
                    }
                }
            }
        }
        // Join: the small island's faces move into the big one.
        self.kept[e] = true;
        let moving = std::mem::take(&mut self.members[small as usize]);
        for (&h, t) in moving.iter().zip(moved) {
            self.flat[h as usize] = t;
            self.island[h as usize] = big;
            let (lo, hi) = bounds(&t);
            self.face_grid.insert(big, lo, hi, h);
            for q in 0..3u8 {
                let (p0, p1) = (t[q as usize], t[(q as usize + 1) % 3]);
                self.edge_grid.insert(big, p0.inf(&p1), p0.sup(&p1), (h, q));
            }
        }
        self.members[big as usize].extend(moving);
        if self.limits.sheet.is_some() {
            self.hull[big as usize] = union_hull;
            self.hull[small as usize] = Vec::new();
        }
        Join::Joined
    }

    /// The net: islands numbered in order of their first face.
    pub(crate) fn into_growth(self) -> Growth {
        let mut number: FxHashMap<u32, u32> = FxHashMap::default();
        let piece: Vec<u32> = self
            .island
            .iter()
            .map(|&i| {
                let next = number.len() as u32;
                *number.entry(i).or_insert(next)
            })
            .collect();
        Growth {
            flat: self.flat,
            piece,
            kept: self.kept,
            piece_count: number.len(),
            budget_cuts: self.budget_cuts,
        }
    }
}
