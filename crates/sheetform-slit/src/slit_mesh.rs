//! The whole symmetric sheet as a [`SheetMesh`]: the modelled half, its mirror image
//! (`x → −x`), both side panels, every strip's quads, with the flat sheet of Fig. 2 as the
//! flat pattern (1:1, `u` along the sheet's length with `u = 0` on the middle line, `v`
//! across it).
//!
//! The panels are the leg polyline swept along `z` (exactly isometric, see
//! [`crate::SidePanel`]); every strip quad is congruent to its flat quad by
//! construction. The two halves of a strip meet on the middle line, where their end points
//! are welded onto the symmetry plane: the only place the mesh departs from an exact
//! isometry, by the remaining gap `G`.

use crate::strip_folding::FoldedStrip;
use crate::{SlitDesign, SlitModel};
use nalgebra::{Vector2, Vector3};
use sheetform_mesh::{Piece, PieceKind, Ruling, SheetMesh};

type Vec2 = Vector2<f64>;
type Vec3 = Vector3<f64>;

/// Ridge lines whose dihedral angle is below this (radians) are drawn as guides
/// (score lines) on the pattern instead of mountain/valley folds.
const GUIDE_ANGLE: f64 = 1.0 * std::f64::consts::PI / 180.0;

struct Builder {
    mesh: SheetMesh,
}

impl Builder {
    fn vertex(&mut self, p: Vec3, f: Vec2) -> u32 {
        self.mesh.positions.push(p);
        self.mesh.flat.push(f);
        (self.mesh.positions.len() - 1) as u32
    }

    /// A triangle, wound counter-clockwise on the flat sheet.
    fn triangle(&mut self, t: [u32; 3], piece: u32) {
        let [a, b, c] = t.map(|i| self.mesh.flat[i as usize]);
        let area = (b - a).perp(&(c - a));
        self.mesh
            .triangles
            .push(if area >= 0.0 { t } else { [t[0], t[2], t[1]] });
        self.mesh.face_pieces.push(piece);
    }

    fn quad(&mut self, [a, b, c, d]: [u32; 4], piece: u32) {
        self.triangle([a, b, c], piece);
        self.triangle([a, c, d], piece);
    }
}

/// Builds the full sheet of a design.
pub fn slit_mesh(model: &SlitModel, design: &SlitDesign) -> SheetMesh {
    let layout = &model.layout;
    let folded: Vec<FoldedStrip> = design.folded(model);
    let profile = &model.panel.profile;
    let segments = profile.len() - 1;
    let chord = layout.panel_length / segments as f64;
    let curved_leg = profile
        .windows(3)
        .any(|w| (w[1] - w[0]).perp(&(w[2] - w[1])).abs() > 1e-12 * chord * chord);
    let mut b = Builder {
        mesh: SheetMesh {
            unit: model.unit,
            ..Default::default()
        },
    };
    let panel_kind = if curved_leg {
        PieceKind::Curved
    } else {
        PieceKind::Planar
    };
    b.mesh.pieces.push(Piece {
        name: "side panel (x > 0)".into(),
        kind: panel_kind,
    });
    b.mesh.pieces.push(Piece {
        name: "side panel (x < 0)".into(),
        kind: panel_kind,
    });
    for k in 0..layout.strip_count {
        b.mesh.pieces.push(Piece {
            name: format!("strip {k}"),
            kind: PieceKind::Planar,
        });
    }
    // The long edges of every strip, across the sheet (`v`).
    let edges: Vec<f64> = (0..layout.strip_count)
        .flat_map(|k| {
            let z = layout.strip_left_edge(k);
            [z, z + layout.strip_width]
        })
        .collect();
    // Welded middle-line vertices, shared by both halves: [strip][left/right][ridge M].
    let mut middle: Vec<[u32; 2]> = Vec::with_capacity(layout.strip_count);
    for (k, f) in folded.iter().enumerate() {
        let m = f.quads();
        let z = layout.strip_left_edge(k);
        let at = |p: Vec3| Vec3::new(0.0, p.y, p.z);
        let l = b.vertex(at(f.left[m]), Vec2::new(0.0, z));
        let r = b.vertex(at(f.right[m]), Vec2::new(0.0, z + layout.strip_width));
        middle.push([l, r]);
    }
    for (half, sign) in [(0u32, 1.0), (1u32, -1.0)] {
        let mirror = |p: Vec3| Vec3::new(sign * p.x, p.y, p.z);
        // Side panel grid: rows along the leg (foot → top), columns across.
        let mut rows: Vec<Vec<u32>> = Vec::with_capacity(segments + 1);
        for (i, p) in profile.iter().enumerate() {
            let u = sign * (layout.strip_length + layout.panel_length - chord * i as f64);
            rows.push(
                edges
                    .iter()
                    .map(|&v| b.vertex(mirror(Vec3::new(p.x, p.y, v)), Vec2::new(u, v)))
                    .collect(),
            );
        }
        for i in 0..segments {
            for c in 0..edges.len() - 1 {
                b.quad([rows[i][c], rows[i][c + 1], rows[i + 1][c + 1], rows[i + 1][c]], half);
            }
            // Bending lines of a curved leg as guides.
            if i > 0 {
                let turn = (profile[i] - profile[i - 1]).perp(&(profile[i + 1] - profile[i])).abs();
                if turn > 1e-12 * chord * chord {
                    b.mesh.rulings.push(Ruling {
                        vertices: rows[i].clone(),
                        piece: half,
                        arc_length: chord * i as f64,
                    });
                }
            }
        }
        let top = &rows[segments];
        // Strips.
        for (k, f) in folded.iter().enumerate() {
            let piece = 2 + k as u32;
            let m = f.quads();
            let state = &design.states[k];
            let z = layout.strip_left_edge(k);
            let mut left = vec![top[2 * k]];
            let mut right = vec![top[2 * k + 1]];
            for i in 1..m {
                let u = |x: f64| sign * (layout.strip_length - x);
                left.push(b.vertex(mirror(f.left[i]), Vec2::new(u(state.left[i]), z)));
                right.push(b.vertex(mirror(f.right[i]), Vec2::new(u(state.right[i]), z + layout.strip_width)));
            }
            left.push(middle[k][0]);
            right.push(middle[k][1]);
            for i in 1..=m {
                b.quad([left[i - 1], right[i - 1], right[i], left[i]], piece);
            }
            for j in 1..m {
                if state.angles[j].abs() < GUIDE_ANGLE {
                    b.mesh.rulings.push(Ruling {
                        vertices: vec![left[j], right[j]],
                        piece,
                        arc_length: state.left[j],
                    });
                }
            }
        }
    }
    b.mesh
}
