//! Developable panel assemblies built procedurally (the examples of Wang & Tang's
//! Figs. 1, 2, 6 and 7).
//!
//! Every panel is a grid whose lines of constant `u` are rulings of a cone or a
//! (generalised) cylinder, so every grid cell is planar and every interior vertex has
//! angle defect zero to rounding: the panels are exactly developable before the
//! deformation. Lengths are millimetres.

use nalgebra::Vector3;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use sheetform_mesh::TriangleMesh;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

type Vec3 = Vector3<f64>;

/// A procedural panel assembly (scene field `model.procedural`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum ProceduralModel {
    /// A round duct rolled from one sheet: a cone frustum, its seam vertices linked
    /// (Fig. 1/5; default 41 × 8 = 328 vertices).
    Duct {
        /// Segments around.
        #[serde(default = "default_duct_around")]
        around: usize,
        /// Segments along the axis.
        #[serde(default = "default_duct_along")]
        along: usize,
        /// Radius at the bottom (mm).
        #[serde(default = "default_duct_bottom")]
        bottom_radius: f64,
        /// Radius at the top (mm).
        #[serde(default = "default_duct_top")]
        top_radius: f64,
        /// Height (mm).
        #[serde(default = "default_duct_height")]
        height: f64,
    },
    /// Two panels sharing an edge: a quarter cylinder and the plane tangent to it along
    /// its last ruling (Fig. 2/4; default 2 × 9 × 9 vertices, 153, 144 nodes).
    TwoPanels {
        /// Segments across each panel.
        #[serde(default = "default_two_columns")]
        columns: usize,
        /// Segments along the shared edge.
        #[serde(default = "default_two_rows")]
        rows: usize,
    },
    /// A flared skirt of conical gores (Fig. 6; default 6 gores × 13 × 15 = 1170 vertices).
    Skirt {
        /// Number of gores (panels).
        #[serde(default = "default_gores")]
        gores: usize,
        /// Segments across each gore.
        #[serde(default = "default_gore_across")]
        across: usize,
        /// Segments from hem to waist.
        #[serde(default = "default_gore_along")]
        along: usize,
    },
    /// Trousers (Fig. 7): legs joined at the crotch under a waistband. Four panels
    /// (left and right, front and back), each from the side seam over the waist and
    /// down the centre seam to the crotch, ruled down to the hem, plus a 40 mm
    /// waistband (default 4 panels × 21 × 17 + 37 × 3 = 1539 vertices; see
    /// [`trouser_panels`]).
    Trousers {
        /// Segments across each panel, along its top edge (waist and centre seam; at
        /// least 2).
        #[serde(default = "default_trouser_across")]
        across: usize,
        /// Segments from hem to waist.
        #[serde(default = "default_trouser_along")]
        along: usize,
    },
}

fn default_duct_around() -> usize {
    40
}
fn default_duct_along() -> usize {
    7
}
fn default_duct_bottom() -> f64 {
    100.0
}
fn default_duct_top() -> f64 {
    70.0
}
fn default_duct_height() -> f64 {
    300.0
}
fn default_two_columns() -> usize {
    8
}
fn default_two_rows() -> usize {
    8
}
fn default_gores() -> usize {
    6
}
fn default_gore_across() -> usize {
    12
}
fn default_gore_along() -> usize {
    14
}
fn default_trouser_across() -> usize {
    20
}
fn default_trouser_along() -> usize {
    16
}

/// A panel: `(nu + 1) × (nv + 1)` vertices at `surface(i / nu, j / nv)`; lines of
/// constant `u` must be rulings.
fn panel(name: &str, nu: usize, nv: usize, surface: impl Fn(f64, f64) -> Vec3) -> TriangleMesh {
    let mut mesh = TriangleMesh::grid(nu.max(1), nv.max(1), |u, v| surface(u, v).into());
    mesh.groups = vec![name.to_string()];
    mesh
}

/// Several panels as one mesh with one group per panel (vertices not shared; the
/// assembly links coincident ones).
fn combine(panels: Vec<TriangleMesh>) -> TriangleMesh {
    let mut out = TriangleMesh::default();
    for (g, p) in panels.into_iter().enumerate() {
        let offset = out.positions.len() as u32;
        out.positions.extend(p.positions);
        out.triangles.extend(p.triangles.iter().map(|t| t.map(|v| v + offset)));
        out.face_groups
            .extend(std::iter::repeat_n(g as u32, p.face_groups.len()));
        out.groups.push(p.groups[0].clone());
    }
    out
}

/// Most vertices a procedural model may have (a first bound, on the scene alone: how much
/// memory the restoration takes depends on how its vertices are linked, and is bounded by
/// [`crate::MAX_FACTOR_BYTES`] once the linear system is analysed; a mesh of well-spread
/// panels, the 100k duct, takes about 9 kB a vertex).
pub const MAX_PROCEDURAL_VERTICES: usize = 250_000;

impl ProceduralModel {
    /// Checks the sizes (each count at least 1, the vertex count at most
    /// [`MAX_PROCEDURAL_VERTICES`], with checked arithmetic) and the duct's dimensions
    /// (positive, finite, at most 100 m).
    ///
    /// # Errors
    /// A field error naming `model.procedural.FIELD`.
    pub fn validate(&self) -> Result<(), crate::FfdError> {
        let field = |name: &str| format!("model.procedural.{name}");
        let counts: Vec<(&str, usize)> = match *self {
            Self::Duct {
                around,
                along,
                bottom_radius,
                top_radius,
                height,
            } => {
                for (name, value) in [
                    ("bottom_radius", bottom_radius),
                    ("top_radius", top_radius),
                    ("height", height),
                ] {
                    if !(value.is_finite() && value > 0.0 && value <= 1e5) {
                        return Err(crate::FfdError::field(
                            field(name),
                            format!(
                                "must be a positive length up to 100 000 mm, got {}",
                                sheetform_geometry::refused_number(value, &[0.0, 1e5])
                            ),
                        ));
                    }
                }
                vec![("around", around), ("along", along)]
            }
            Self::TwoPanels { columns, rows } => vec![("columns", columns), ("rows", rows)],
            Self::Skirt { gores, across, along } => vec![("gores", gores), ("across", across), ("along", along)],
            Self::Trousers { across, along } => {
                if across < 2 {
                    return Err(crate::FfdError::field(
                        field("across"),
                        "must be at least 2 (the waist and the centre seam take at least one segment each)",
                    ));
                }
                vec![("across", across), ("along", along)]
            }
        };
        let mut vertices: usize = match self {
            Self::TwoPanels { .. } => 2,
            // Four panels (the waistband is added below).
            Self::Trousers { .. } => 4,
            _ => 1,
        };
        for &(name, count) in &counts {
            if count == 0 {
                return Err(crate::FfdError::field(field(name), "must be at least 1"));
            }
            vertices = vertices.saturating_mul(count.saturating_add(1));
        }
        if let Self::Trousers { across, .. } = *self {
            // The waistband: 3 rows of at most 4 across + 1 vertices.
            vertices = vertices.saturating_add(across.saturating_mul(4).saturating_add(1).saturating_mul(3));
        }
        if vertices > MAX_PROCEDURAL_VERTICES {
            let names: Vec<&str> = counts.iter().map(|(n, _)| *n).collect();
            return Err(crate::FfdError::field(
                field(names[0]),
                format!(
                    "{} gives about {} vertices, more than the {MAX_PROCEDURAL_VERTICES} a restoration may have",
                    names.join(" × "),
                    sheetform_geometry::short_number(vertices as f64)
                ),
            ));
        }
        Ok(())
    }

    /// The panels as a triangle mesh, one group per panel (mm).
    pub fn build(&self) -> TriangleMesh {
        match *self {
            Self::Duct {
                around,
                along,
                bottom_radius,
                top_radius,
                height,
            } => combine(vec![panel("duct", around.max(3), along, |u, v| {
                let r = bottom_radius + (top_radius - bottom_radius) * v;
                let a = TAU * u;
                Vec3::new(r * a.cos(), r * a.sin(), height * v)
            })]),
            Self::TwoPanels { columns, rows } => {
                let (radius, height, width) = (100.0, 150.0, 120.0);
                combine(vec![
                    panel("cylinder", columns, rows, |u, v| {
                        let a = FRAC_PI_2 * u;
                        Vec3::new(radius * a.cos(), radius * a.sin(), height * v)
                    }),
                    panel("plane", columns, rows, |u, v| Vec3::new(-width * u, radius, height * v)),
                ])
            }
            Self::Skirt { gores, across, along } => {
                let gores = gores.max(2);
                let (hem, waist, length) = (300.0, 140.0, 600.0);
                combine(
                    (0..gores)
                        .map(|g| {
                            panel(&format!("gore-{}", g + 1), across, along, |u, v| {
                                let a = TAU * (g as f64 + u) / gores as f64;
                                let r = hem + (waist - hem) * v;
                                Vec3::new(r * a.cos(), r * a.sin(), length * v)
                            })
                        })
                        .collect(),
                )
            }
            Self::Trousers { across, along } => trouser_panels(across.max(2), along),
        }
    }
}

/// The trousers of [`ProceduralModel::Trousers`] (mm; z up, the hem at z = 0, the
/// waist at 1000, the crotch at 740, x across, y from back to front).
///
/// Each panel is a *discrete developable*: a strip of planar quads between straight
/// rulings, every two neighbouring rulings in one plane `Πᵢ`, so every interior vertex
/// has angle sum 2π to rounding (two straight angles, one in each plane). The left
/// front panel is built from its top edge `B₀ … Bₙ`: a quarter of the waist ellipse
/// (half width 180, half depth 130) from the side to the centre front, then the centre
/// seam in the plane x = 0, a quarter ellipse curving from the belly down and under to
/// the crotch point, in equal steps of the ellipse's angle (steps shorter near the waist
/// left the quads at the centre front nearly coplanar, 0.8°–4.6° apart, and the
/// example's second deformation could not be restored: a flat vertex star's angle sum
/// has no gradient, so its defect row of the restoration's system vanishes). The first
/// ruling is the side seam, from the waist's side point to the hem's (x = −350, in the
/// plane y = 0). Marching along the top edge, ruling `i` lies in the plane `Πᵢ₋₁`
/// through ruling `i − 1` and the segment `Bᵢ₋₁Bᵢ`, so only its hem point `Hᵢ` on the
/// line `Πᵢ₋₁ ∩ {z = 0}` is free: under the waist the hem steps 150/180 of the waist's
/// step (the hem's front is a scaled copy of the waist's), under the centre seam a
/// fixed fraction of the seam's step (about 0.46, found by bisection so that the last
/// hem step is as long as the others, not a sliver), and the last ruling (the inseam)
/// is where `Πₙ₋₁` meets the plane y = 0. The back panel is the front's mirror image in y = 0 (their side seams and
/// inseams are the same lines), the right leg the left's in x = 0, so the four panels
/// meet exactly along the side seams, the inseams and the centre seams: the legs part
/// at the crotch point, where the four panels meet. The fronts (and the backs) meet
/// smoothly over the belly and at a sharp fold near the crotch, as cloth does. The
/// waistband is a vertical band on the waist (a generalised cylinder).
///
/// Departure from the paper: Wang & Tang's Fig. 7 trousers come from a garment
/// pattern that is not published; these have its structure (legs joined at the crotch,
/// a waistband) and size (1 539 vertices against its 1 494 nodes).
pub fn trouser_panels(across: usize, along: usize) -> TriangleMesh {
    const WAIST_HEIGHT: f64 = 1000.0;
    const CROTCH_HEIGHT: f64 = 740.0;
    const WAIST_HALF_WIDTH: f64 = 180.0;
    const WAIST_HALF_DEPTH: f64 = 130.0;
    const HEM_SIDE_X: f64 = -350.0;
    const HEM_PER_WAIST: f64 = 150.0 / 180.0;
    const BAND_HEIGHT: f64 = 40.0;
    const BAND_ROWS: usize = 2;
    let (across, along) = (across.max(2), along.max(1));
    let waist_segments = ((across as f64 * 0.45).round() as usize).clamp(1, across - 1);
    let seam_segments = across - waist_segments;
    let mut top = Vec::with_capacity(across + 1);
    for i in 0..=waist_segments {
        let angle = PI - FRAC_PI_2 * i as f64 / waist_segments as f64;
        top.push(Vec3::new(
            WAIST_HALF_WIDTH * angle.cos(),
            WAIST_HALF_DEPTH * angle.sin(),
            WAIST_HEIGHT,
        ));
    }
    // The side point exactly on y = 0 and the centre front on x = 0 (sin π and cos π/2
    // are not zero in floating point), so that mirrored panels share them exactly.
    top[0].y = 0.0;
    top[waist_segments].x = 0.0;
    for i in 1..=seam_segments {
        let angle = FRAC_PI_2 * i as f64 / seam_segments as f64;
        top.push(Vec3::new(
            0.0,
            if i == seam_segments {
                0.0
            } else {
                WAIST_HALF_DEPTH * angle.cos()
            },
            WAIST_HEIGHT - (WAIST_HEIGHT - CROTCH_HEIGHT) * angle.sin(),
        ));
    }
    // The hem's step under the centre seam, as a fraction of the seam's step: the one
    // whose last step (to the inseam) is as long as that fraction of the seam's last step,
    // so the hem has no sliver edge at the inseam. Bisection: a larger fraction brings
    // the hem to y = 0 sooner; past it the hem would cross y = 0 before the inseam.
    let last_seam_step = (top[across] - top[across - 1]).norm();
    let excess = |fraction: f64| {
        let hem = hem_under(&top, waist_segments, HEM_SIDE_X, HEM_PER_WAIST, fraction);
        if hem[across - 1].y <= 0.0 {
            return f64::NEG_INFINITY;
        }
        (hem[across] - hem[across - 1]).norm() - fraction * last_seam_step
    };
    let (mut low, mut high) = (0.05, 1.0);
    for _ in 0..60 {
        let middle = 0.5 * (low + high);
        if excess(middle) > 0.0 {
            low = middle;
        } else {
            high = middle;
        }
    }
    let hem = hem_under(&top, waist_segments, HEM_SIDE_X, HEM_PER_WAIST, low);
    let left_front: Vec<Vec<Vec3>> = (0..=across)
        .map(|i| {
            (0..=along)
                .map(|j| hem[i] + (top[i] - hem[i]) * (j as f64 / along as f64))
                .collect()
        })
        .collect();
    let mirrored = |reverse: bool, flip: Vec3| -> Vec<Vec<Vec3>> {
        let mut rulings: Vec<Vec<Vec3>> = left_front
            .iter()
            .map(|ruling| ruling.iter().map(|p| p.component_mul(&flip)).collect())
            .collect();
        if reverse {
            rulings.reverse();
        }
        rulings
    };
    let waist: Vec<Vec3> = top[..=waist_segments].to_vec();
    let flip_y = Vec3::new(1.0, -1.0, 1.0);
    let flip_x = Vec3::new(-1.0, 1.0, 1.0);
    // Around the waist: centre back, left side, centre front, right side, centre back.
    let mut ring: Vec<Vec3> = Vec::with_capacity(4 * waist_segments + 1);
    ring.extend(
        waist
            .iter()
            .rev()
            .map(|p| p.component_mul(&flip_y))
            .take(waist_segments),
    );
    ring.extend(waist.iter().copied().take(waist_segments));
    ring.extend(
        waist
            .iter()
            .rev()
            .map(|p| p.component_mul(&flip_x))
            .take(waist_segments),
    );
    ring.extend(
        waist
            .iter()
            .map(|p| p.component_mul(&flip_x).component_mul(&flip_y))
            .take(waist_segments),
    );
    ring.push(ring[0]);
    let band: Vec<Vec<Vec3>> = ring
        .iter()
        .map(|p| {
            (0..=BAND_ROWS)
                .map(|j| p + Vec3::z() * (BAND_HEIGHT * j as f64 / BAND_ROWS as f64))
                .collect()
        })
        .collect();
    combine(vec![
        grid_panel("left-front", &left_front),
        grid_panel("left-back", &mirrored(true, flip_y)),
        grid_panel("right-front", &mirrored(true, flip_x)),
        grid_panel("right-back", &mirrored(false, flip_x.component_mul(&flip_y))),
        grid_panel("waistband", &band),
    ])
}

/// The hem points of a panel ruled from `top` (see [`trouser_panels`]): the first at
/// `(side_x, 0, 0)`, each next one on the line where the plane of the previous ruling
/// and the next top segment meets z = 0, `per_waist` (under the first `waist_segments`
/// segments) or `per_seam` times the top segment's length further on, the last where
/// that line crosses y = 0.
fn hem_under(top: &[Vec3], waist_segments: usize, side_x: f64, per_waist: f64, per_seam: f64) -> Vec<Vec3> {
    let last = top.len() - 1;
    let mut hem = Vec::with_capacity(top.len());
    hem.push(Vec3::new(side_x, 0.0, 0.0));
    for i in 1..=last {
        let previous = hem[i - 1];
        let step = top[i] - top[i - 1];
        let plane_normal = (previous - top[i - 1]).cross(&step);
        // The hem line of the plane: horizontal, perpendicular to the plane's normal.
        let mut direction = plane_normal.cross(&Vec3::z()).normalize();
        let next = if i == last {
            Vec3::new(previous.x - direction.x * (previous.y / direction.y), 0.0, 0.0)
        } else if i <= waist_segments {
            if direction.dot(&step) < 0.0 {
                direction = -direction;
            }
            previous + direction * (per_waist * step.norm())
        } else {
            if direction.x < 0.0 {
                direction = -direction;
            }
            previous + direction * (per_seam * step.norm())
        };
        hem.push(next);
    }
    hem
}

/// A panel from its rulings' vertices (`rulings[i][j]`, each ruling a column).
fn grid_panel(name: &str, rulings: &[Vec<Vec3>]) -> TriangleMesh {
    let (nu, nv) = (rulings.len() - 1, rulings[0].len() - 1);
    panel(name, nu, nv, |u, v| {
        rulings[(u * nu as f64).round() as usize][(v * nv as f64).round() as usize]
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use sheetform_mesh::{developability_summary, mesh_topology, vertex_developability};

    #[test]
    fn panels_are_developable_at_the_papers_sizes() {
        for (json, vertices) in [
            (r#"{"kind": "duct"}"#, 328),
            (r#"{"kind": "two_panels"}"#, 162),
            (r#"{"kind": "skirt"}"#, 1170),
            (r#"{"kind": "trousers"}"#, 1539),
        ] {
            let model: ProceduralModel = serde_json::from_str(json).unwrap();
            let mesh = model.build();
            assert_eq!(mesh.positions.len(), vertices, "{json}");
            let t = mesh_topology(&mesh);
            let s = developability_summary(&mesh, &t, &vertex_developability(&mesh, &t), 1e-10);
            assert!(s.angle_defect_max_rad < 1e-12, "{json}: {s:?}");
        }
    }

    /// The panels of `mesh` welded at their seams (one vertex per node).
    fn welded(mesh: &TriangleMesh) -> TriangleMesh {
        let assembly = crate::PanelAssembly::from_mesh(mesh).unwrap();
        TriangleMesh {
            positions: assembly.node_positions(),
            face_groups: vec![0; assembly.node_triangles.len()],
            triangles: assembly.node_triangles,
            groups: vec!["welded".into()],
            ..TriangleMesh::default()
        }
    }

    /// The trousers are one garment: welded at their seams, the four panels and the
    /// waistband make a consistently oriented surface with three openings (the two hems
    /// and the top of the waistband; Euler characteristic −1, a pair of pants), the legs
    /// parted at the crotch point where the four leg panels meet, each leg on its own
    /// side, the hems on the floor. `across` below 2 is refused.
    #[test]
    fn the_trousers_are_joined_at_the_crotch_under_a_waistband() {
        let model: ProceduralModel = serde_json::from_str(r#"{"kind": "trousers"}"#).unwrap();
        let mesh = model.build();
        assert_eq!(
            mesh.groups,
            ["left-front", "left-back", "right-front", "right-back", "waistband"]
        );
        let topology = mesh_topology(&welded(&mesh));
        assert!(topology.is_clean() && topology.consistently_oriented, "{topology:?}");
        assert_eq!(topology.component_count, 1);
        assert_eq!(topology.boundary_loop_count, 3);
        assert_eq!(topology.euler_characteristic, -1);
        // The crotch point: one node shared by the four leg panels, nothing below it
        // between the legs.
        let crotch = Vec3::new(0.0, 0.0, 740.0);
        let panels_at_crotch: std::collections::BTreeSet<u32> = mesh
            .triangles
            .iter()
            .zip(&mesh.face_groups)
            .filter(|(t, _)| t.iter().any(|&v| (mesh.positions[v as usize] - crotch).norm() < 1e-9))
            .map(|(_, &g)| g)
            .collect();
        assert_eq!(panels_at_crotch.into_iter().collect::<Vec<_>>(), [0, 1, 2, 3]);
        for (t, &g) in mesh.triangles.iter().zip(&mesh.face_groups) {
            let centre = t.iter().map(|&v| mesh.positions[v as usize]).sum::<Vec3>() / 3.0;
            match g {
                0 | 1 => assert!(centre.x < 0.0, "a left panel at {centre:?}"),
                2 | 3 => assert!(centre.x > 0.0, "a right panel at {centre:?}"),
                _ => assert!(centre.z > 1000.0, "the waistband at {centre:?}"),
            }
        }
        // Below the crotch the legs are apart, the hems (at least 250 mm apart at the inner points).
        for p in &mesh.positions {
            if p.z < 740.0 {
                assert!(p.x.abs() > 0.0, "between the legs at {p:?}");
            }
            if p.z == 0.0 {
                assert!(p.x.abs() > 125.0, "a hem at {p:?}");
            }
        }
        let lowest = mesh.positions.iter().map(|p| p.z).fold(f64::INFINITY, f64::min);
        assert_eq!(lowest, 0.0);
        // Every resolution gives clean, developable, joined panels.
        for across in [2, 3, 5, 8, 13, 40, 90] {
            for along in [1, 7, 30] {
                let mesh = trouser_panels(across, along);
                let label = format!("across {across}, along {along}");
                assert!(
                    mesh.positions.iter().all(|p| p.iter().all(|c| c.is_finite())),
                    "{label}"
                );
                let t = mesh_topology(&mesh);
                assert!(t.is_clean() && t.consistently_oriented, "{label}: {t:?}");
                let s = developability_summary(&mesh, &t, &vertex_developability(&mesh, &t), 1e-10);
                assert!(s.angle_defect_max_rad < 1e-12, "{label}: {s:?}");
                let t = mesh_topology(&welded(&mesh));
                assert!(t.is_clean() && t.consistently_oriented, "{label}: {t:?}");
                assert_eq!((t.boundary_loop_count, t.euler_characteristic), (3, -1), "{label}");
            }
        }
        let error = serde_json::from_str::<ProceduralModel>(r#"{"kind": "trousers", "across": 1}"#)
            .unwrap()
            .validate()
            .unwrap_err()
            .to_string();
        assert!(error.contains("model.procedural.across"), "{error}");
        // The waistband counts towards the size bound (4 × 20 001 × 2 + 240 003 > 250k).
        let error = serde_json::from_str::<ProceduralModel>(r#"{"kind": "trousers", "across": 20000, "along": 1}"#)
            .unwrap()
            .validate()
            .unwrap_err()
            .to_string();
        assert!(error.contains("vertices"), "{error}");
        // Called directly with no segment along, one is taken.
        assert!(trouser_panels(5, 0)
            .positions
            .iter()
            .all(|p| p.iter().all(|c| c.is_finite())));
    }
}
