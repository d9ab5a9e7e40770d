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
use std::f64::consts::{FRAC_PI_2, TAU};

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
    /// Trousers: two legs, oblique cone frustums, each of a front and a back panel
    /// (Fig. 7; default 4 panels × 19 × 20 = 1520 vertices).
    Trousers {
        /// Segments across each panel.
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
    18
}
fn default_trouser_along() -> usize {
    19
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

/// Most vertices a procedural model may have: the restoration needs about 28 kB per
/// vertex (the 100k duct: 2.8 GB), so 250 000 stay within 8 GB.
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
                                sheetform_geometry::short_number(value)
                            ),
                        ));
                    }
                }
                vec![("around", around), ("along", along)]
            }
            Self::TwoPanels { columns, rows } => vec![("columns", columns), ("rows", rows)],
            Self::Skirt { gores, across, along } => vec![("gores", gores), ("across", across), ("along", along)],
            Self::Trousers { across, along } => vec![("across", across), ("along", along)],
        };
        let mut vertices: usize = if matches!(self, Self::TwoPanels { .. }) { 2 } else { 1 };
        for &(name, count) in &counts {
            if count == 0 {
                return Err(crate::FfdError::field(field(name), "must be at least 1"));
            }
            vertices = vertices.saturating_mul(count.saturating_add(1));
        }
        if vertices > MAX_PROCEDURAL_VERTICES {
            let names: Vec<&str> = counts.iter().map(|(n, _)| *n).collect();
            return Err(crate::FfdError::field(
                field(names[0]),
                format!(
                    "{} gives about {} vertices, more than the {MAX_PROCEDURAL_VERTICES} a restoration can hold in memory (about 28 kB each)",
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
            Self::Trousers { across, along } => {
                let length = 1000.0;
                let mut panels = Vec::new();
                for (side, sign) in [("left", -1.0), ("right", 1.0)] {
                    // Oblique cone frustum: hem circle (radius 110) 60 mm further out than
                    // the top circle (radius 170), joined by straight rulings.
                    let bottom = Vec3::new(sign * 200.0, 0.0, 0.0);
                    let top = Vec3::new(sign * 175.0, 0.0, length);
                    for (half, a0) in [("front", 0.0), ("back", 0.5 * TAU)] {
                        panels.push(panel(&format!("{side}-{half}"), across, along, |u, v| {
                            let a = a0 + 0.5 * TAU * u;
                            let r = 110.0 + 60.0 * v;
                            bottom + (top - bottom) * v + Vec3::new(r * a.cos(), r * a.sin(), 0.0)
                        }));
                    }
                }
                combine(panels)
            }
        }
    }
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
            (r#"{"kind": "trousers"}"#, 1520),
        ] {
            let model: ProceduralModel = serde_json::from_str(json).unwrap();
            let mesh = model.build();
            assert_eq!(mesh.positions.len(), vertices, "{json}");
            let t = mesh_topology(&mesh);
            let s = developability_summary(&mesh, &t, &vertex_developability(&mesh, &t), 1e-10);
            assert!(s.angle_defect_max_rad < 1e-12, "{json}: {s:?}");
        }
    }
}
