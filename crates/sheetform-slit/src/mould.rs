//! The fabrication mould of §4.2: a closed solid under the strips and side panels that a
//! 3D printer can take (the sheet is pressed onto it).
//!
//! The paper closes the strips and panels with faces at the front, back and bottom. Here:
//! the top is the sheet's surface with the slits bridged (one row of the grid per long
//! edge of every strip, columns from the foot of one leg over the strips to the foot of
//! the other); the front and back walls are the first and last edges' profiles closed by
//! a base `base_thickness` below the lowest point, triangulated in their plane
//! (constrained Delaunay, `spade`); the bottom is a rectangle and each end is a planar cap
//! through the feet. The result is watertight and outward oriented (checked in the
//! tests: every edge is shared by exactly two faces in opposite directions, and the
//! volume is positive). A profile that crosses itself (a strip curling over) cannot be
//! closed this way and is an error.
//!
//! With a sheet thickness `T` (`mould.sheet_thickness`) the top lies `T/2` below the
//! model: the model is the sheet's mid-surface (bent with a radius much larger than its
//! thickness, a sheet keeps its length there: the K-factor is ½), so the sheet's
//! underside rests on the mould. Each long edge's profile is offset in the xy-plane by
//! `T/2` towards the mould, with mitred corners (a point `p` between segments of unit
//! normals `n₁`, `n₂` moves by `T/2 · (n₁ + n₂)/(1 + n₁·n₂)`, which keeps both segments
//! `T/2` away); the ends then stand on the offset feet.

use crate::{SlitDesign, SlitError, SlitModel};
use nalgebra::{Vector2, Vector3};
use sheetform_geometry::Polygon;
use spade::{ConstrainedDelaunayTriangulation, HasPosition, Point2, Triangulation};

type Vec3 = Vector3<f64>;

/// A closed triangle mesh (outward oriented).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Mould {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Triangles, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
}

impl Mould {
    /// Every edge is used by exactly two triangles, once in each direction (closed and
    /// consistently oriented).
    pub fn is_watertight(&self) -> bool {
        let table = sheetform_mesh::EdgeTable::new(&self.triangles, self.positions.len());
        !table.is_empty() && (0..table.len()).all(|e| matches!(table.sides(e), [a, b] if a.forward != b.forward))
    }

    /// Enclosed volume (divergence theorem).
    pub fn volume(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.positions[i as usize]);
                a.dot(&b.cross(&c)) / 6.0
            })
            .sum()
    }
}

#[derive(Clone, Copy)]
struct WallVertex {
    position: Point2<f64>,
}

impl HasPosition for WallVertex {
    type Scalar = f64;
    fn position(&self) -> Point2<f64> {
        self.position
    }
}

/// Triangulates a planar wall given as a closed loop of mesh vertices, projected by
/// `project`; triangles are turned so that their normal has a positive component along
/// `outward`.
fn wall(
    mesh: &mut Mould,
    ring: &[u32],
    project: impl Fn(Vec3) -> Vector2<f64>,
    outward: Vec3,
    name: &str,
) -> Result<(), SlitError> {
    let points: Vec<Vector2<f64>> = ring.iter().map(|&i| project(mesh.positions[i as usize])).collect();
    let vertices: Vec<WallVertex> = points
        .iter()
        .map(|p| WallVertex {
            position: Point2::new(p.x, p.y),
        })
        .collect();
    let n = ring.len();
    let constraints: Vec<[usize; 2]> = (0..n).map(|i| [i, (i + 1) % n]).collect();
    let mut conflict = false;
    let cdt =
        ConstrainedDelaunayTriangulation::<WallVertex>::try_bulk_load_cdt(vertices, constraints, |_| conflict = true)
            .map_err(|e| {
            SlitError::Mould(format!(
                "the {name} cannot be triangulated: {}",
                sheetform_geometry::triangulation_problem(&e)
            ))
        })?;
    if conflict || cdt.num_vertices() != n {
        return Err(SlitError::Mould(format!(
            "the {name}'s outline crosses or touches itself (a strip curls over itself or below the base), so no \
             closed mould can be made from the profile"
        )));
    }
    let outline = Polygon::new(points.clone(), vec![])
        .map_err(|e| SlitError::Mould(format!("the {name}'s outline is not a simple polygon: {e}")))?;
    let mut count = 0;
    for face in cdt.inner_faces() {
        let idx = face.vertices().map(|v| v.fix().index());
        let c = idx.iter().fold(Vector2::zeros(), |s, &i| s + points[i]) / 3.0;
        if !outline.contains(c) {
            continue;
        }
        let mut t = idx.map(|i| ring[i]);
        let [a, b, cc] = t.map(|i| mesh.positions[i as usize]);
        if (b - a).cross(&(cc - a)).dot(&outward) < 0.0 {
            t.swap(1, 2);
        }
        mesh.triangles.push(t);
        count += 1;
    }
    if count != n - 2 {
        return Err(SlitError::Mould(format!(
            "the {name} is not a simple polygon ({count} triangles for {n} corners)"
        )));
    }
    Ok(())
}

/// A profile (a polyline running from the right foot over the top to the left foot, in
/// a plane `z` = const up to the strips' folding) moved `distance` towards the mould in
/// the xy-plane (to its left, seen along it), corners mitred; consecutive repeated
/// points keep their neighbour's direction.
///
/// # Errors
/// [`SlitError::Mould`] when a segment would turn round (a bend of the sheet tighter
/// than the offset: the mould's top would fold over itself).
fn offset_profile(chain: &[Vec3], distance: f64) -> Result<Vec<Vec3>, SlitError> {
    if distance == 0.0 {
        return Ok(chain.to_vec());
    }
    let normal = |a: Vec3, b: Vec3| {
        let d = Vector2::new(b.x - a.x, b.y - a.y);
        let length = d.norm();
        (length > 0.0).then(|| Vector2::new(-d.y, d.x) / length)
    };
    let n = chain.len();
    let segment_normals: Vec<Option<Vector2<f64>>> = (0..n - 1).map(|i| normal(chain[i], chain[i + 1])).collect();
    let moved = (0..n)
        .map(|i| {
            let before = (0..i).rev().find_map(|j| segment_normals[j]);
            let after = (i..n - 1).find_map(|j| segment_normals[j]);
            let shift = match (before, after) {
                (Some(a), Some(b)) if 1.0 + a.dot(&b) > 1e-9 => (a + b) / (1.0 + a.dot(&b)),
                (Some(a), _) | (None, Some(a)) => a,
                (None, None) => Vector2::zeros(),
            };
            chain[i] + Vec3::new(shift.x, shift.y, 0.0) * distance
        })
        .collect::<Vec<Vec3>>();
    for i in 0..n - 1 {
        let (before, after) = ((chain[i + 1] - chain[i]).xy(), (moved[i + 1] - moved[i]).xy());
        if before.norm() > 0.0 && before.dot(&after) <= 0.0 {
            return Err(SlitError::Mould(format!(
                "lowered by half the sheet's thickness ({}), the mould's top folds over itself near ({}, {}): the sheet bends tighter there than its thickness allows",
                sheetform_geometry::short_number(distance),
                sheetform_geometry::short_number(chain[i].x),
                sheetform_geometry::short_number(chain[i].y)
            )));
        }
    }
    Ok(moved)
}

/// Builds the mould of a solved design.
///
/// # Errors
/// [`SlitError::Mould`] when a wall's profile crosses itself or the top, lowered for the
/// sheet's thickness, folds over itself.
pub fn build_mould(model: &SlitModel, design: &SlitDesign) -> Result<Mould, SlitError> {
    let layout = &model.layout;
    let folded = design.folded(model);
    let profile = &model.panel.profile;
    // One chain per long edge: right foot → top → strip (x > 0) → middle → mirror → left foot.
    let mut chains: Vec<Vec<Vec3>> = Vec::new();
    for (k, f) in folded.iter().enumerate() {
        for side in 0..2 {
            let z = layout.strip_left_edge(k) + side as f64 * layout.strip_width;
            let edge = if side == 0 { &f.left } else { &f.right };
            let m = f.quads();
            let mut chain: Vec<Vec3> = profile.iter().map(|p| Vec3::new(p.x, p.y, z)).collect();
            chain.extend(edge[1..m].iter().copied());
            chain.push(Vec3::new(0.0, edge[m].y, edge[m].z));
            chain.extend(edge[1..m].iter().rev().map(|p| Vec3::new(-p.x, p.y, p.z)));
            chain.extend(profile.iter().rev().map(|p| Vec3::new(-p.x, p.y, z)));
            chains.push(offset_profile(&chain, 0.5 * model.mould.sheet_thickness)?);
        }
    }
    let columns = chains[0].len();
    let lowest = chains.iter().flatten().map(|p| p.y).fold(f64::INFINITY, f64::min);
    let base = lowest - model.mould.base_thickness;
    let mut mould = Mould::default();
    let mut rows: Vec<Vec<u32>> = Vec::new();
    for chain in &chains {
        rows.push(
            chain
                .iter()
                .map(|p| {
                    mould.positions.push(*p);
                    (mould.positions.len() - 1) as u32
                })
                .collect(),
        );
    }
    // Top: the sheet with the slits bridged; (−x along a row) × (+z across rows) = +y.
    for r in 0..rows.len() - 1 {
        for c in 0..columns - 1 {
            let (a, b, cc, d) = (rows[r][c], rows[r][c + 1], rows[r + 1][c + 1], rows[r + 1][c]);
            mould.triangles.push([a, b, cc]);
            mould.triangles.push([a, cc, d]);
        }
    }
    let foot = chains[0][0];
    let (z0, z1) = (0.0, layout.width);
    let mut corner = |x: f64, z: f64| {
        mould.positions.push(Vec3::new(x, base, z));
        (mould.positions.len() - 1) as u32
    };
    let (front_right, front_left) = (corner(foot.x, z0), corner(-foot.x, z0));
    let (back_right, back_left) = (corner(foot.x, z1), corner(-foot.x, z1));
    let xy = |p: Vec3| Vector2::new(p.x, p.y);
    // Front and back walls.
    let mut front: Vec<u32> = rows[0].clone();
    front.extend([front_left, front_right]);
    wall(&mut mould, &front, xy, -Vec3::z(), "front wall")?;
    let mut back: Vec<u32> = rows[rows.len() - 1].clone();
    back.extend([back_left, back_right]);
    wall(&mut mould, &back, xy, Vec3::z(), "back wall")?;
    // End caps through the feet (planes x = ±foot.x).
    let zy = |p: Vec3| Vector2::new(p.z, p.y);
    let mut right: Vec<u32> = rows.iter().map(|r| r[0]).collect();
    right.extend([back_right, front_right]);
    wall(&mut mould, &right, zy, Vec3::x(), "right end")?;
    let mut left: Vec<u32> = rows.iter().map(|r| r[columns - 1]).collect();
    left.extend([back_left, front_left]);
    wall(&mut mould, &left, zy, -Vec3::x(), "left end")?;
    // Bottom.
    mould.triangles.push([front_right, front_left, back_left]);
    mould.triangles.push([front_right, back_left, back_right]);
    let [a, b, c] = [front_right, front_left, back_left].map(|i| mould.positions[i as usize]);
    if (b - a).cross(&(c - a)).y > 0.0 {
        let n = mould.triangles.len();
        for t in &mut mould.triangles[n - 2..] {
            t.swap(1, 2);
        }
    }
    if mould.volume() <= 0.0 {
        return Err(SlitError::Mould("the closed surface encloses no volume".into()));
    }
    Ok(mould)
}
