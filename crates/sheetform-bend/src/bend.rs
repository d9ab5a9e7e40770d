//! From a validated model to the bent sheet: sample, test, cut, place.

use crate::{
    admissibility::{check_region, RegionAdmissibility},
    flat_layout::{flat_layout, FlatLayout},
    folded_strip::{lift, FoldedStrip},
    rectifying_developable::{sample_rulings, RulingSample},
    ruling_extent::{ruling_extent, RulingExtent},
    BendError, BendModel,
};
use rayon::prelude::*;
use sheetform_geometry::{short_number, RigidMotion, Vec3};
use sheetform_mesh::SheetMesh;

/// One region's sampled rulings, their extents on the sheet and the admissibility test.
#[derive(Debug, Clone)]
pub struct RegionGeometry {
    /// Sampled rulings, `s = 0 … L`.
    pub samples: Vec<RulingSample>,
    /// Where each ruling meets the boundary.
    pub extents: Vec<RulingExtent>,
    /// Eq. 6 and the crossing test.
    pub admissibility: RegionAdmissibility,
}

/// Samples region `k`'s rulings, clips them to the sheet, and tests admissibility.
///
/// # Errors
/// Degenerate curves (see [`sample_rulings`]).
pub fn region_geometry(model: &BendModel, k: usize) -> Result<RegionGeometry, BendError> {
    let r = &model.regions[k];
    let samples = sample_rulings(k, &r.name, &r.curve, &r.flat, r.up, &model.tessellation)?;
    let scale = model.sheet.scale();
    let extent = |s: &RulingSample| ruling_extent(&model.sheet, s.flat_point, s.flat_ruling, scale);
    let extents: Vec<RulingExtent> = if samples.len() >= crate::rectifying_developable::PARALLEL_RULINGS {
        samples.par_iter().map(extent).collect()
    } else {
        samples.iter().map(extent).collect()
    };
    let mut admissibility = check_region(k, &samples, &extents, 1e-9 * scale);
    explain_knot_jump(r, &samples, &mut admissibility);
    Ok(RegionGeometry {
        samples,
        extents,
        admissibility,
    })
}

/// A B-spline of degree ≤ 3 is only C² at its knots, so its torsion (which needs the
/// third derivative) and with it the ruling direction can jump there: the rulings then
/// overlap on one side of the geodesic. Say so when that is what made the shape
/// inadmissible.
fn explain_knot_jump(region: &crate::CurvedRegion, samples: &[RulingSample], admissibility: &mut RegionAdmissibility) {
    let crate::CurveShape::BSpline(spline) = region.curve.shape() else {
        return;
    };
    if spline.degree() > 3 {
        return;
    }
    let Some(failure) = admissibility.failure.as_mut() else {
        return;
    };
    let [s0, s1] = failure.arc_length_range;
    let near = |s: f64| {
        samples
            .iter()
            .min_by(|a, b| (a.arc_length - s).abs().total_cmp(&(b.arc_length - s).abs()))
            .expect("samples")
    };
    let (a, b) = (near(s0), near(s1));
    let pad = (b.arc_length - a.arc_length).max(1e-9 * region.curve.length());
    let (u0, u1) = (
        region.curve.parameter_at(a.arc_length - pad),
        region.curve.parameter_at(b.arc_length + pad),
    );
    if let Some(knot) = spline.breakpoints().into_iter().find(|&u| u > u0 && u < u1) {
        let s = region.curve.length_at(knot);
        let before = samples.iter().rev().find(|x| x.arc_length < s).map(|x| x.angle);
        let after = samples.iter().find(|x| x.arc_length > s).map(|x| x.angle);
        let jump = match (before, after) {
            (Some(x), Some(y)) => format!(" by about {:.1} degrees", (y - x).abs().to_degrees()),
            _ => String::new(),
        };
        failure.message.push_str(&format!(
            ". Cause: the degree-{} B-spline control curve is only C² at its knot u = {} (s = {}); its torsion jumps there and the ruling direction jumps{jump}, so rulings overlap on one side of the geodesic. Use a B-spline of degree 4 or more (C³), or a Bézier curve",
            spline.degree(),
            short_number(knot),
            short_number(s)
        ));
    }
}

/// Where every region and every cell goes.
#[derive(Debug, Clone)]
pub struct Placement {
    /// `W_k`: region `k`'s curve coordinates → world.
    pub region_motions: Vec<RigidMotion>,
    /// Flat → world for every cell.
    pub cell_motions: Vec<RigidMotion>,
}

/// Places region 0 as its curve says and every other region and cell by the rigid
/// attachments of §4.2: a cell touched by the end ruling of region `k` moves with `k`,
/// and a region touching an already placed cell is moved so that its own strip there
/// coincides with the cell ("the pieces beyond it moved with it").
///
/// # Errors
/// [`BendError::Composite`] when a cell would need two different motions (a planar piece
/// held by rulings that are not coplanar, or a loop of pieces that does not close).
pub fn place(model: &BendModel, layout: &FlatLayout, strips: &[FoldedStrip]) -> Result<Placement, BendError> {
    let nregions = strips.len();
    let mut region: Vec<Option<RigidMotion>> = vec![None; nregions];
    region[0] = Some(RigidMotion::identity());
    let mut cell: Vec<Option<RigidMotion>> = vec![None; layout.cells.len()];
    loop {
        let mut changed = false;
        for (ci, c) in layout.cells.iter().enumerate() {
            if cell[ci].is_none() {
                if let Some(&(k, part)) = c.labels.iter().find(|(k, _)| region[*k].is_some()) {
                    cell[ci] = Some(region[k].expect("placed").compose(&strips[k].motions[part]));
                    changed = true;
                }
            }
            if let Some(m) = cell[ci] {
                for &(k, part) in &c.labels {
                    if region[k].is_none() {
                        region[k] = Some(m.compose(&strips[k].motions[part].inverse()));
                        changed = true;
                    }
                }
            }
        }
        if !changed {
            break;
        }
    }
    let scale = model.sheet.scale();
    let tolerance = 1e-9 * scale;
    let mut cell_motions = Vec::with_capacity(cell.len());
    for (ci, c) in layout.cells.iter().enumerate() {
        let m = cell[ci].ok_or_else(|| BendError::Composite {
            message: format!(
                "the part of the sheet around flat ({}, {}) is not connected to region 0",
                short_number(c.sample_point.x),
                short_number(c.sample_point.y)
            ),
        })?;
        let pts: Vec<Vec3> = c.vertices.iter().map(|&v| lift(layout.flat[v as usize])).collect();
        for &(k, part) in &c.labels {
            let other = region[k].expect("placed").compose(&strips[k].motions[part]);
            let d = m.max_difference(&other, &pts);
            if d > tolerance {
                let (a, b) = (c.labels[0], (k, part));
                return Err(BendError::Composite {
                    message: format!(
                        "the piece around flat ({}, {}) is attached to region {} (`{}`) and to region {} (`{}`) along rulings whose tangent planes do not agree (they would tear it apart by {:.3e} {}); a planar piece can only follow one curved piece, or the curves must be made consistent",
                        short_number(c.sample_point.x),
                        short_number(c.sample_point.y),
                        a.0,
                        model.regions[a.0].name,
                        b.0,
                        model.regions[b.0].name,
                        d,
                        model.unit.symbol()
                    ),
                });
            }
        }
        cell_motions.push(m);
    }
    Ok(Placement {
        region_motions: region.into_iter().map(|m| m.expect("every region placed")).collect(),
        cell_motions,
    })
}

/// Summary of one curved region of a bent sheet.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct RegionSummary {
    /// Region name.
    pub name: String,
    /// Number of sampled rulings.
    pub ruling_count: usize,
    /// Arc length of the control curve.
    pub curve_length: f64,
    /// Total bending `Σ|φ_j|` (radians).
    pub total_fold_radians: f64,
    /// Largest fold angle between neighbouring strips (radians).
    pub max_fold_radians: f64,
    /// Eq. 6 result.
    pub admissibility: RegionAdmissibility,
    /// Largest distance between the mesh's geodesic vertices and the control curve
    /// (placed in world coordinates): the discretisation error.
    pub curve_deviation: f64,
    /// For closed regions: largest gap between the glued end rulings.
    pub closure_gap: Option<f64>,
}

/// A bent sheet: the mesh with its flat pattern, and everything that produced it.
#[derive(Debug, Clone)]
pub struct BentSheet {
    /// The mesh (3D + flat + rulings + piece labels).
    pub mesh: SheetMesh,
    /// Per-region summaries.
    pub regions: Vec<RegionSummary>,
    /// Per-region ruling geometry.
    pub geometries: Vec<RegionGeometry>,
    /// Per-region folded strips.
    pub strips: Vec<FoldedStrip>,
    /// The flat layout (reused for animation frames).
    pub layout: FlatLayout,
    /// The placement.
    pub placement: Placement,
}

impl BentSheet {
    /// Where each region's curve of regression comes within `reach` times a ruling's
    /// extent of the sheet ([`crate::curve_of_regression_near_sheet`]), placed in the
    /// world as the mesh (model units): what an editor draws to show how close a shape
    /// is to inadmissible (Bo & Wang 2007, Eq. 6).
    pub fn curves_of_regression_near_sheet(&self, reach: f64) -> Vec<Vec<Vec3>> {
        self.geometries
            .iter()
            .zip(&self.placement.region_motions)
            .flat_map(|(geometry, motion)| {
                crate::curve_of_regression_near_sheet(&geometry.samples, &geometry.extents, reach)
                    .into_iter()
                    .map(move |stretch| stretch.iter().map(|p| motion.apply(p)).collect())
            })
            .collect()
    }
}

/// Samples every region and refuses inadmissible shapes.
///
/// # Errors
/// Degenerate curves; [`BendError::Inadmissible`] at the first region that fails Eq. 6.
pub fn region_geometries(model: &BendModel) -> Result<Vec<RegionGeometry>, BendError> {
    let mut out = Vec::with_capacity(model.regions.len());
    for k in 0..model.regions.len() {
        let g = region_geometry(model, k)?;
        if let Some(f) = &g.admissibility.failure {
            return Err(BendError::Inadmissible(Box::new(f.clone())));
        }
        out.push(g);
    }
    Ok(out)
}

/// Bends the sheet: samples the rectifying developable of every control curve (Eq. 1),
/// tests admissibility (Eq. 6, §4.3), cuts the flat sheet along the rulings, folds every
/// strip rigidly and attaches planar pieces and further curved pieces (§3.4, §4.2).
///
/// # Errors
/// See [`region_geometries`], [`flat_layout`] and [`place`].
pub fn bend(model: &BendModel) -> Result<BentSheet, BendError> {
    let geometries = region_geometries(model)?;
    let strips: Vec<FoldedStrip> = geometries.iter().map(|g| FoldedStrip::new(&g.samples)).collect();
    let layout = flat_layout(model, &geometries)?;
    assemble(model, geometries, strips, layout)
}

fn assemble(
    model: &BendModel,
    geometries: Vec<RegionGeometry>,
    strips: Vec<FoldedStrip>,
    mut layout: FlatLayout,
) -> Result<BentSheet, BendError> {
    let placement = place(model, &layout, &strips)?;
    let rulings = std::mem::take(&mut layout.rulings);
    let mesh = mesh_from(model, &layout, &placement, rulings);
    let regions = summaries(model, &geometries, &strips, &layout, &placement, &mesh);
    Ok(BentSheet {
        mesh,
        regions,
        geometries,
        strips,
        layout,
        placement,
    })
}

fn mesh_from(
    model: &BendModel,
    layout: &FlatLayout,
    placement: &Placement,
    rulings: Vec<sheetform_mesh::Ruling>,
) -> SheetMesh {
    let mut positions = vec![Vec3::zeros(); layout.flat.len()];
    let mut done = vec![false; layout.flat.len()];
    for (f, t) in layout.triangles.iter().enumerate() {
        let m = &placement.cell_motions[layout.face_cells[f]];
        for &v in t {
            let v = v as usize;
            if !done[v] {
                positions[v] = m.apply(&lift(layout.flat[v]));
                done[v] = true;
            }
        }
    }
    SheetMesh {
        positions,
        flat: layout.flat.clone(),
        triangles: layout.triangles.clone(),
        face_pieces: layout.face_pieces.clone(),
        pieces: layout.pieces.clone(),
        rulings,
        smooth_edges: vec![],
        unit: model.unit,
    }
}

fn summaries(
    model: &BendModel,
    geometries: &[RegionGeometry],
    strips: &[FoldedStrip],
    layout: &FlatLayout,
    placement: &Placement,
    mesh: &SheetMesh,
) -> Vec<RegionSummary> {
    geometries
        .iter()
        .enumerate()
        .map(|(k, g)| {
            let w = placement.region_motions[k];
            let curve_deviation = layout.geodesic_vertices[k]
                .iter()
                .zip(&g.samples)
                .map(|(&v, s)| (mesh.positions[v as usize] - w.apply(&s.point)).norm())
                .fold(0.0, f64::max);
            let closure_gap = model.regions[k].closed.then(|| {
                let n = g.samples.len();
                let (s0, s1) = (&g.samples[0], &g.samples[n - 1]);
                let e0 = &g.extents[0];
                let (m0, m1) = (&strips[k].motions[1], &strips[k].motions[n - 1]);
                [e0.negative_end, 0.0, e0.positive_end]
                    .iter()
                    .map(|&t| {
                        let p = m0.apply(&lift(s0.flat_point + s0.flat_ruling * t));
                        let q = m1.apply(&lift(s1.flat_point + s1.flat_ruling * t));
                        (p - q).norm()
                    })
                    .fold(0.0, f64::max)
            });
            RegionSummary {
                name: model.regions[k].name.clone(),
                ruling_count: g.samples.len(),
                curve_length: model.regions[k].curve.length(),
                total_fold_radians: strips[k].fold_angles.iter().map(|a| a.abs()).sum(),
                max_fold_radians: strips[k].fold_angles.iter().map(|a| a.abs()).fold(0.0, f64::max),
                admissibility: g.admissibility.clone(),
                curve_deviation,
                closure_gap,
            }
        })
        .collect()
}

impl BentSheet {
    /// Frame `t ∈ [0, 1]` of the continuous isometric deformation from the flat sheet
    /// (`t = 0`) to the bent sheet (`t = 1`): every fold angle scaled by `t`. Every frame
    /// is an exact isometry of the flat pattern.
    ///
    /// # Errors
    /// A composite that cannot be placed consistently at this frame.
    pub fn frame(&self, model: &BendModel, t: f64) -> Result<SheetMesh, BendError> {
        let strips: Vec<FoldedStrip> = self
            .strips
            .iter()
            .zip(&self.geometries)
            .map(|(s, g)| s.scaled(&g.samples, t))
            .collect();
        let placement = place(model, &self.layout, &strips)?;
        Ok(mesh_from(model, &self.layout, &placement, self.mesh.rulings.clone()))
    }
}
