//! A strip folded along its ridge lines (§3, Fig. 3 and 4), and the exact derivatives of
//! its ridge-line end points with respect to the ridge parameters.
//!
//! **Flat strip.** Strip-local coordinates `(x, y)`: `x` along the strip from E0 (`x = 0`,
//! where the slits begin) to the middle line (`x = L3`), `y` across it from the left long
//! edge (`y = 0`, end points `v_L,i`) to the right one (`y = w`). Ridge line `E_i` joins
//! `p_L,i = (x_L,i, 0)` and `p_R,i = (x_R,i, w)`; `x_·,0 = 0` and `x_·,M = L3` are fixed.
//!
//! **Folding.** `θ_j` is the dihedral angle at `E_j` (`j = 0..M−1`): quad `j + 1` is quad
//! `j` (or, for `j = 0`, the side panel's last facet) turned by `θ_j` about `E_j`. With the
//! flat rotation `RF_j(p) = p_L,j + Q_j (p − p_L,j)`, `Q_j = Rot(d_j, θ_j)`,
//! `d_j = (p_R,j − p_L,j)/ℓ_j`, quad `i`'s placement is
//! `F_i = F_0 ∘ RF_0 ∘ … ∘ RF_{i−1}` (`F_0`: the panel's frame at E0), and
//! `v_s,i = F_i(p_s,i)`. Every quad is moved rigidly, so it stays congruent to its flat
//! quad: the isometry holds by construction, not by a penalty. (The paper says "quad i is
//! rotated by θ_i about E_{i−1}" and also "θ_0 = 90°"; we index the angle by the ridge it
//! sits on, so `θ_0` is the fold between side panel and strip and the `M` angles are
//! `θ_0..θ_{M−1}`, which gives the paper's `D = 2(M − 1) + M` unknowns.)
//!
//! **Derivatives** (all exact, no finite differences). A point `q` on a quad after ridge
//! `j` moves with the rigid motion of `RF_j`:
//! - `∂q/∂θ_j = D_j × (q − a_j)` with the ridge's world axis `a_j = v_L,j`,
//!   `D_j = R_j d_j`;
//! - moving an end of ridge `j` changes the axis: `δQ Qᵀ = [ω]×` with
//!   `ω = sin θ δd + (1 − cos θ) d × δd` (the left Jacobian of SO(3) applied to `θ δd`,
//!   `δd ⊥ d`), and `δd = ±(e_x − d d_x)/ℓ` for `x_R` / `x_L`. So
//!   `∂q/∂x_L,j = R_j ω_L × (q − a_j) + R_j (I − Q_j) e_x` and
//!   `∂q/∂x_R,j = R_j ω_R × (q − a_j)`;
//! - the ridge's own end point moves along the quad: `∂v_L,j/∂x_L,j = R_j e_x`.

use nalgebra::{Matrix3, Rotation3, Unit, Vector3};

type Vec3 = Vector3<f64>;

/// Where a strip starts (ridge line E0, on the side panel) and its flat size.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StripStart {
    /// `v_L,0` in 3D.
    pub origin: Vec3,
    /// Unit 3D direction of the flat `+x` at E0 before the first fold (the side panel's
    /// direction at its top, away from the foot).
    pub along: Vec3,
    /// Unit 3D direction of the flat `+y` (from `v_L` to `v_R`, the sheet's width).
    pub across: Vec3,
    /// Strip width `w`.
    pub width: f64,
    /// Half-strip length `L3`.
    pub length: f64,
}

impl StripStart {
    /// The frame `F_0`: columns `along`, `across`, `along × across`.
    pub fn rotation(&self) -> Matrix3<f64> {
        Matrix3::from_columns(&[self.along, self.across, self.along.cross(&self.across)])
    }
}

/// The ridge-line parameters of one half strip.
#[derive(Debug, Clone, PartialEq)]
pub struct StripState {
    /// `θ_0..θ_{M−1}` (radians): the dihedral angle at each ridge line but the last.
    pub angles: Vec<f64>,
    /// `x_L,0..x_L,M`: where each ridge line meets the left long edge (`x_L,0 = 0`,
    /// `x_L,M = L3`).
    pub left: Vec<f64>,
    /// `x_R,0..x_R,M` on the right long edge.
    pub right: Vec<f64>,
}

impl StripState {
    /// The paper's initial state (Fig. 9): ridge lines evenly spaced and square to the
    /// strip, every angle zero but `θ_0 = 90°`.
    pub fn initial(quads: usize, length: f64) -> Self {
        let mut angles = vec![0.0; quads];
        angles[0] = std::f64::consts::FRAC_PI_2;
        let x: Vec<f64> = (0..=quads).map(|i| length * i as f64 / quads as f64).collect();
        Self {
            angles,
            left: x.clone(),
            right: x,
        }
    }

    /// M, the number of quads.
    pub fn quads(&self) -> usize {
        self.angles.len()
    }

    /// `D = 2(M − 1) + M` unknowns.
    pub fn variable_count(&self) -> usize {
        3 * self.quads() - 2
    }

    /// The unknowns `[θ_0..θ_{M−1}, x_L,1..x_L,M−1, x_R,1..x_R,M−1]`.
    pub fn to_vector(&self) -> Vec<f64> {
        let m = self.quads();
        let mut x = self.angles.clone();
        x.extend_from_slice(&self.left[1..m]);
        x.extend_from_slice(&self.right[1..m]);
        x
    }

    /// Sets the unknowns from [`StripState::to_vector`]'s layout.
    pub fn set_vector(&mut self, x: &[f64]) {
        let m = self.quads();
        self.angles.copy_from_slice(&x[..m]);
        self.left[1..m].copy_from_slice(&x[m..2 * m - 1]);
        self.right[1..m].copy_from_slice(&x[2 * m - 1..3 * m - 2]);
    }

    /// Every quad split in two by a new ridge line through the midpoints of its long
    /// edges, with a zero angle (Fig. 13): the folded shape is unchanged, and ridge line
    /// `i` becomes ridge line `2i`.
    pub fn subdivided(&self) -> Self {
        let m = self.quads();
        let mut angles = Vec::with_capacity(2 * m);
        for &a in &self.angles {
            angles.push(a);
            angles.push(0.0);
        }
        let split = |x: &[f64]| {
            let mut out = Vec::with_capacity(2 * m + 1);
            for w in x.windows(2) {
                out.push(w[0]);
                out.push(0.5 * (w[0] + w[1]));
            }
            out.push(x[m]);
            out
        };
        Self {
            angles,
            left: split(&self.left),
            right: split(&self.right),
        }
    }
}

/// Index of `θ_j` in the unknowns.
pub fn angle_variable(j: usize) -> usize {
    j
}

/// Index of `x_L,j` (`1 ≤ j ≤ M − 1`) in the unknowns of an `M`-quad strip.
pub fn left_variable(quads: usize, j: usize) -> usize {
    quads + j - 1
}

/// Index of `x_R,j` (`1 ≤ j ≤ M − 1`) in the unknowns of an `M`-quad strip.
pub fn right_variable(quads: usize, j: usize) -> usize {
    2 * quads - 1 + j - 1
}

/// The infinitesimal motions of the quads after one ridge line.
#[derive(Debug, Clone, Copy, PartialEq)]
struct RidgeMotion {
    /// World point on the axis, `a_j = v_L,j`.
    point: Vec3,
    /// World axis direction `D_j`.
    direction: Vec3,
    /// `∂/∂x_L,j`: angular part.
    left_spin: Vec3,
    /// `∂/∂x_L,j`: translation part.
    left_shift: Vec3,
    /// `∂/∂x_R,j`: angular part.
    right_spin: Vec3,
    /// `R_j`: the frame of the quads before this ridge line.
    frame: Matrix3<f64>,
    /// `d_j` in strip coordinates.
    axis: Vec3,
    /// `θ_j`.
    angle: f64,
    /// `x_R,j − x_L,j`.
    offset: f64,
}

/// The second derivatives of one ridge line's flat rotation `RF_j` with respect to its
/// own parameters `(θ_j, x_L,j, x_R,j)`, in world coordinates: a point `q` after the ridge
/// has `∂²q/∂a∂b = W_ab (q − a_j) + c_ab`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct RidgeCurvature {
    /// `W_ab = R_j (∂²Q_j/∂a∂b) Q_jᵀ R_jᵀ`.
    matrix: [[Matrix3<f64>; 3]; 3],
    /// `c_ab = −R_j (∂Q_j/∂a e_x [b = x_L] + ∂Q_j/∂b e_x [a = x_L])`.
    shift: [[Vec3; 3]; 3],
}

impl RidgeMotion {
    /// `ω_a` of the ridge's parameters `(θ_j, x_L,j, x_R,j)`.
    fn spins(&self) -> [Vec3; 3] {
        [self.direction, self.left_spin, self.right_spin]
    }

    /// The ridge's own second derivatives (see [`RidgeCurvature`]).
    ///
    /// `Q = I + sin θ K + (1 − cos θ) K²`, `K = [d]×`, and `d` depends on
    /// `δ = x_R − x_L` only: with `ℓ = √(δ² + w²)`, `d = (δ, w, 0)/ℓ`,
    /// `d⊥ = (w, −δ, 0)/ℓ` and `κ = w/ℓ²`, `d′ = κ d⊥` and
    /// `d″ = −(2δw/ℓ⁴) d⊥ − κ² d`. Then
    /// `Q_θ = cos θ K + sin θ K²`, `Q_θθ = −sin θ K + cos θ K²`,
    /// `Q_δ = sin θ K′ + (1 − cos θ)(K′K + KK′)`, `Q_θδ = cos θ K′ + sin θ (K′K + KK′)`,
    /// `Q_δδ = sin θ K″ + (1 − cos θ)(K″K + 2K′K′ + KK″)`, and `∂/∂x_L = −∂/∂δ`,
    /// `∂/∂x_R = ∂/∂δ`. Differentiating `RF(z) = Q (z − p_L) + p_L`, `p_L = (x_L, 0, 0)`,
    /// twice gives `Q_ab (z − p_L) − Q_a ∂p_L/∂b − Q_b ∂p_L/∂a`; `z − p_L = Qᵀ R_jᵀ (q − a_j)`.
    fn curvature(&self, width: f64) -> RidgeCurvature {
        let d = self.axis;
        let delta = self.offset;
        let l2 = delta * delta + width * width;
        let l = l2.sqrt();
        let kappa = width / l2;
        let perp = Vec3::new(width, -delta, 0.0) / l;
        let d1 = perp * kappa;
        let d2 = perp * (-2.0 * delta * width / (l2 * l2)) - d * (kappa * kappa);
        let k0 = d.cross_matrix();
        let k1 = d1.cross_matrix();
        let k2 = d2.cross_matrix();
        let (sin, cos) = self.angle.sin_cos();
        let k0k0 = k0 * k0;
        let sym1 = k1 * k0 + k0 * k1;
        let q_t = k0 * cos + k0k0 * sin;
        let q_tt = k0 * (-sin) + k0k0 * cos;
        let q_d = k1 * sin + sym1 * (1.0 - cos);
        let q_td = k1 * cos + sym1 * sin;
        let q_dd = k2 * sin + (k2 * k0 + k1 * k1 * 2.0 + k0 * k2) * (1.0 - cos);
        let first = [q_t, -q_d, q_d];
        let second = [[q_tt, -q_td, q_td], [-q_td, q_dd, -q_dd], [q_td, -q_dd, q_dd]];
        let rotation = Rotation3::from_axis_angle(&Unit::new_unchecked(d), self.angle).into_inner();
        let back = rotation.transpose() * self.frame.transpose();
        let ex = Vec3::x();
        let mut matrix = [[Matrix3::zeros(); 3]; 3];
        let mut shift = [[Vec3::zeros(); 3]; 3];
        for a in 0..3 {
            for b in 0..3 {
                matrix[a][b] = self.frame * second[a][b] * back;
                let mut c = Vec3::zeros();
                if b == 1 {
                    c -= first[a] * ex;
                }
                if a == 1 {
                    c -= first[b] * ex;
                }
                shift[a][b] = self.frame * c;
            }
        }
        RidgeCurvature { matrix, shift }
    }
}

/// A folded half strip: its ridge-line end points in 3D and what is needed for their
/// derivatives.
#[derive(Debug, Clone, PartialEq)]
pub struct FoldedStrip {
    /// `v_L,0..v_L,M`.
    pub left: Vec<Vec3>,
    /// `v_R,0..v_R,M`.
    pub right: Vec<Vec3>,
    /// World direction of the flat `+x` on quad `i` (`i = 0`: the side panel), `R_i e_x`.
    along: Vec<Vec3>,
    ridges: Vec<RidgeMotion>,
    width: f64,
}

/// Which end of a ridge line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RidgeEnd {
    /// `v_L,i`.
    Left,
    /// `v_R,i`.
    Right,
}

/// Folds a strip: places every quad by the chain of rotations (see the module docs).
pub fn fold_strip(start: &StripStart, state: &StripState) -> FoldedStrip {
    let m = state.quads();
    let w = start.width;
    let mut rotation = start.rotation();
    let mut shift = start.origin;
    let mut left = Vec::with_capacity(m + 1);
    let mut right = Vec::with_capacity(m + 1);
    let mut along = Vec::with_capacity(m + 1);
    let mut ridges = Vec::with_capacity(m);
    let ex = Vec3::x();
    for j in 0..=m {
        let pl = Vec3::new(state.left[j], 0.0, 0.0);
        let pr = Vec3::new(state.right[j], w, 0.0);
        left.push(rotation * pl + shift);
        right.push(rotation * pr + shift);
        along.push(rotation.column(0).into_owned());
        if j == m {
            break;
        }
        let span = pr - pl;
        let length = span.norm();
        let d = span / length;
        let theta = state.angles[j];
        let (sin, cos) = theta.sin_cos();
        let q = Rotation3::from_axis_angle(&Unit::new_unchecked(d), theta).into_inner();
        let dd = (ex - d * d.x) / length;
        let spin = |delta: Vec3| rotation * (delta * sin + d.cross(&delta) * (1.0 - cos));
        ridges.push(RidgeMotion {
            point: left[j],
            direction: rotation * d,
            left_spin: spin(-dd),
            left_shift: rotation * (ex - q * ex),
            right_spin: spin(dd),
            frame: rotation,
            axis: d,
            angle: theta,
            offset: span.x,
        });
        shift += rotation * (pl - q * pl);
        rotation *= q;
    }
    FoldedStrip {
        left,
        right,
        along,
        ridges,
        width: w,
    }
}

impl FoldedStrip {
    /// M.
    pub fn quads(&self) -> usize {
        self.ridges.len()
    }

    /// `v_end,i`.
    pub fn vertex(&self, end: RidgeEnd, i: usize) -> Vec3 {
        match end {
            RidgeEnd::Left => self.left[i],
            RidgeEnd::Right => self.right[i],
        }
    }

    /// `∂v_end,i/∂(unknowns)`, one 3-vector per unknown, written into `out` (length
    /// `D = 3M − 2`; entries the vertex does not depend on are set to zero).
    pub fn vertex_derivatives(&self, end: RidgeEnd, i: usize, out: &mut [Vec3]) {
        let m = self.quads();
        out.fill(Vec3::zeros());
        if i == 0 {
            return;
        }
        let q = self.vertex(end, i);
        for (j, ridge) in self.ridges.iter().enumerate().take(i) {
            let arm = q - ridge.point;
            out[angle_variable(j)] = ridge.direction.cross(&arm);
            if j >= 1 {
                out[left_variable(m, j)] = ridge.left_spin.cross(&arm) + ridge.left_shift;
                out[right_variable(m, j)] = ridge.right_spin.cross(&arm);
            }
        }
        if i < m {
            match end {
                RidgeEnd::Left => out[left_variable(m, i)] = self.along[i],
                RidgeEnd::Right => out[right_variable(m, i)] = self.along[i],
            }
        }
    }

    /// The unknowns of ridge line `j`, `(θ_j, x_L,j, x_R,j)`, as indices (`None` for the
    /// fixed ends of `E_0`).
    fn ridge_variables(&self, j: usize) -> [Option<usize>; 3] {
        let m = self.quads();
        if j == 0 {
            [Some(angle_variable(0)), None, None]
        } else {
            [
                Some(angle_variable(j)),
                Some(left_variable(m, j)),
                Some(right_variable(m, j)),
            ]
        }
    }

    /// Adds `Σ_v w_v · ∂²v/∂a∂b` over every ridge-line end point `v = v_end,i` into `out`
    /// (at `(col0, col0)`; `D × D`), with `weights[2i + end] = w_v` (length `2(M + 1)`).
    /// This is the curvature part of any Hessian whose rows are linear in the vertices
    /// (`Σ_k r_k ∇²r_k`, `Σ_e λ_e ∇²g_e`).
    ///
    /// Second derivatives of a vertex `v` after ridge lines `j < k`:
    /// - `a` of ridge `j`, `b` of a later ridge `k` (or `b = x_end,i`, the vertex's own
    ///   position on its ridge line): the twist of `b` is carried by the rigid motion of
    ///   `a`, so `∂²v/∂a∂b = ω_a × ∂v/∂b` (`ω_a` the angular part of `∂v/∂a`), with
    ///   `∂v/∂b = ω_b × (v − a_k) + s_b`;
    /// - `a`, `b` of the same ridge: `W_ab (v − a_j) + c_ab`, from the second derivatives
    ///   of Rodrigues' formula `Q = I + sin θ K + (1 − cos θ) K²` in `θ` and in the
    ///   ridge's direction (which depends on `x_R − x_L`; derivation at the private
    ///   `RidgeMotion::curvature`); `∂²v/∂x_end,i² = 0`.
    ///
    /// Summed over the vertices after ridge `k` with suffix sums `S = Σ w`,
    /// `A = Σ v wᵀ` (`(u × w)` expanded by `(ω × p) × w = p (ω·w) − ω (p·w)`):
    /// `Σ w·(ω_a × ∂v/∂b) = ω_a · [A ω_b − a_k (S·ω_b) − ω_b (tr A − a_k·S) + s_b × S]`
    /// and `Σ w·(W (v − a_j) + c) = tr(W (A − a_j Sᵀ)) + c·S`, so the whole Hessian
    /// costs `O(D²)`, not `O(M D²)`.
    pub fn add_weighted_hessian(&self, weights: &[Vec3], out: &mut nalgebra::DMatrix<f64>, col0: usize) {
        let m = self.quads();
        assert_eq!(weights.len(), 2 * (m + 1), "one weight per ridge-line end point");
        // Suffix sums over the vertices of ridge lines t..=M.
        let mut sum = vec![Vec3::zeros(); m + 2];
        let mut outer = vec![Matrix3::zeros(); m + 2];
        for i in (1..=m).rev() {
            let (wl, wr) = (weights[2 * i], weights[2 * i + 1]);
            sum[i] = sum[i + 1] + wl + wr;
            outer[i] = outer[i + 1] + self.left[i] * wl.transpose() + self.right[i] * wr.transpose();
        }
        let mut add = |a: usize, b: usize, value: f64| {
            out[(col0 + a, col0 + b)] += value;
            if a != b {
                out[(col0 + b, col0 + a)] += value;
            }
        };
        // e_b for every parameter b of ridge k, over the vertices after it (i ≥ k + 1).
        let mut carried: Vec<(usize, Vec3)> = Vec::with_capacity(3 * m);
        for k in (0..m).rev() {
            let ridge = &self.ridges[k];
            let (s, a) = (sum[k + 1], outer[k + 1]);
            let point = ridge.point;
            let spins = ridge.spins();
            let shifts = [Vec3::zeros(), ridge.left_shift, Vec3::zeros()];
            let vars = self.ridge_variables(k);
            let own: Vec<(usize, Vec3)> = vars
                .iter()
                .enumerate()
                .filter_map(|(p, v)| v.map(|v| (p, v)))
                .map(|(p, v)| {
                    let w = spins[p];
                    let e = a * w - point * s.dot(&w) - w * (a.trace() - point.dot(&s)) + shifts[p].cross(&s);
                    (v, e)
                })
                .collect();
            // Pairs with the parameters of later ridges (already in `carried`) and with
            // the own positions of later vertices.
            for (p, v) in vars.iter().enumerate() {
                let Some(va) = *v else { continue };
                for &(vb, e) in &carried {
                    add(va, vb, spins[p].dot(&e));
                }
                for i in k + 1..m {
                    let along = self.along[i];
                    let l = along.cross(&weights[2 * i]);
                    let r = along.cross(&weights[2 * i + 1]);
                    add(va, left_variable(m, i), spins[p].dot(&l));
                    add(va, right_variable(m, i), spins[p].dot(&r));
                }
            }
            // Within the ridge.
            let curvature = ridge.curvature(self.width);
            let moment = a - point * s.transpose();
            for (pa, &va) in vars.iter().enumerate() {
                let Some(va) = va else { continue };
                for (pb, &vb) in vars.iter().enumerate().skip(pa) {
                    let Some(vb) = vb else { continue };
                    let value = (curvature.matrix[pa][pb] * moment).trace() + curvature.shift[pa][pb].dot(&s);
                    add(va, vb, value);
                }
            }
            carried.extend(own);
        }
    }

    /// The 3D corners of quad `i` (`1..=M`): `v_L,i−1, v_R,i−1, v_R,i, v_L,i`.
    pub fn quad(&self, i: usize) -> [Vec3; 4] {
        [self.left[i - 1], self.right[i - 1], self.right[i], self.left[i]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn start() -> StripStart {
        StripStart {
            origin: Vec3::new(450.0, 400.0, 0.0),
            along: Vec3::new(0.0, 1.0, 0.0),
            across: Vec3::new(0.0, 0.0, 1.0),
            width: 60.0,
            length: 450.0,
        }
    }

    fn wavy(quads: usize) -> StripState {
        let mut s = StripState::initial(quads, 450.0);
        for i in 1..quads {
            s.angles[i] = 0.3 * (i as f64 * 1.3).sin();
            s.left[i] += 7.0 * (i as f64 * 0.7).cos();
            s.right[i] -= 5.0 * (i as f64 * 0.9).sin();
        }
        s
    }

    #[test]
    fn initial_strip_is_horizontal_and_reaches_the_symmetry_plane() {
        let f = fold_strip(&start(), &StripState::initial(10, 450.0));
        assert!(f.left[10].x.abs() < 1e-12 && f.right[10].x.abs() < 1e-12);
        assert!((f.left[10].y - 400.0).abs() < 1e-12 && (f.right[10].z - 60.0).abs() < 1e-12);
    }

    #[test]
    fn quads_stay_congruent_to_their_flat_quads() {
        let s = wavy(12);
        let f = fold_strip(&start(), &s);
        for i in 1..=12 {
            let flat = [
                Vec3::new(s.left[i - 1], 0.0, 0.0),
                Vec3::new(s.right[i - 1], 60.0, 0.0),
                Vec3::new(s.right[i], 60.0, 0.0),
                Vec3::new(s.left[i], 0.0, 0.0),
            ];
            let q = f.quad(i);
            for a in 0..4 {
                for b in a + 1..4 {
                    let d3 = (q[a] - q[b]).norm();
                    let d2 = (flat[a] - flat[b]).norm();
                    assert!((d3 - d2).abs() <= 1e-12 * d2.max(1.0), "quad {i} {a}-{b}: {d3} vs {d2}");
                }
            }
        }
    }

    #[test]
    fn vertex_derivatives_match_finite_differences() {
        let m = 9;
        let s = wavy(m);
        let st = start();
        let f = fold_strip(&st, &s);
        let x0 = s.to_vector();
        let mut out = vec![Vec3::zeros(); x0.len()];
        for end in [RidgeEnd::Left, RidgeEnd::Right] {
            for i in 1..=m {
                f.vertex_derivatives(end, i, &mut out);
                for (k, exact) in out.iter().enumerate() {
                    let h = 1e-6;
                    let mut plus = s.clone();
                    let mut xp = x0.clone();
                    xp[k] += h;
                    plus.set_vector(&xp);
                    let mut minus = s.clone();
                    let mut xm = x0.clone();
                    xm[k] -= h;
                    minus.set_vector(&xm);
                    let fd =
                        (fold_strip(&st, &plus).vertex(end, i) - fold_strip(&st, &minus).vertex(end, i)) / (2.0 * h);
                    assert!(
                        (fd - exact).norm() <= 1e-6 * (1.0 + exact.norm()),
                        "{end:?} {i} var {k}: exact {exact:?} fd {fd:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn weighted_second_derivatives_match_differences_of_the_exact_first() {
        let m = 7;
        let s = wavy(m);
        let st = start();
        let x0 = s.to_vector();
        let n = x0.len();
        let folded = |x: &[f64]| {
            let mut t = s.clone();
            t.set_vector(x);
            fold_strip(&st, &t)
        };
        // A different weight on every vertex (E_0's are ignored: E_0 is fixed).
        let weights: Vec<Vec3> = (0..2 * (m + 1))
            .map(|k| {
                let t = k as f64;
                Vec3::new((0.7 * t).sin(), (1.3 * t).cos() - 0.4, 0.2 + 0.1 * t)
            })
            .collect();
        let weighted_first = |x: &[f64]| {
            let f = folded(x);
            let mut total = vec![0.0; n];
            let mut d = vec![Vec3::zeros(); n];
            for i in 1..=m {
                for (e, end) in [RidgeEnd::Left, RidgeEnd::Right].into_iter().enumerate() {
                    f.vertex_derivatives(end, i, &mut d);
                    for (t, dk) in total.iter_mut().zip(&d) {
                        *t += dk.dot(&weights[2 * i + e]);
                    }
                }
            }
            total
        };
        let mut exact = nalgebra::DMatrix::zeros(n + 3, n + 3);
        folded(&x0).add_weighted_hessian(&weights, &mut exact, 3);
        assert!((&exact - exact.transpose()).norm() < 1e-9 * exact.norm());
        let h = 1e-5;
        for k in 0..n {
            let mut xp = x0.clone();
            xp[k] += h;
            let mut xm = x0.clone();
            xm[k] -= h;
            let (plus, minus) = (weighted_first(&xp), weighted_first(&xm));
            for a in 0..n {
                let fd = (plus[a] - minus[a]) / (2.0 * h);
                let e = exact[(3 + a, 3 + k)];
                assert!(
                    (fd - e).abs() <= 1e-5 * (1.0 + e.abs()),
                    "({a}, {k}): exact {e} fd {fd}"
                );
            }
        }
    }

    #[test]
    fn subdivision_keeps_the_shape() {
        let s = wavy(7);
        let f = fold_strip(&start(), &s);
        let g = fold_strip(&start(), &s.subdivided());
        for i in 0..=7 {
            assert!((f.left[i] - g.left[2 * i]).norm() < 1e-9);
            assert!((f.right[i] - g.right[2 * i]).norm() < 1e-9);
        }
    }
}
