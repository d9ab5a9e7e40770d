//! The penalty of one strip (Eq. 1–6) as least-squares residuals `r` with `F = Σ r²`,
//! and their exact Jacobian.
//!
//! `F = w1 F_no_gap + w2 F_smooth + w3 F_fair + w4 F_user_control (+ w_scan F_scan)`:
//! - `F_no_gap = (v_L,M)_x² + (v_R,M)_x²` (Eq. 2): rows `√w1 (v_·,M)_x`;
//! - `F_smooth = Σ_j (θ_{j−1} − 2θ_j + θ_{j+1})² + F_end_angle` (Eq. 3) over the
//!   interior ridge lines' angles `θ_1..θ_{M−1}`, and
//!   `F_end_angle = ((v_L,M−1 − v_L,M)·p_os)² + ((v_R,M−1 − v_R,M)·p_os)²`,
//!   `p_os = (0, 1, 0)`, so the last quad leaves the symmetry plane horizontally;
//! - `F_fair = Σ_i 1/|x_L,i − x_L,i−1| + 1/|x_R,i − x_R,i−1|` (Eq. 4): rows
//!   `√w3 (Δx)^(−1/2)`; a step that crosses two ridge lines makes the cost infinite, so
//!   Levenberg–Marquardt never accepts it;
//! - `F_user_control = Σ_anchors |v′ − v|² + dist(v_L,M, c_sym)² + dist(v_R,M, c_sym)²`
//!   (Eq. 5); the seat curve `c_sym` is a polyline and the distance is measured in the
//!   symmetry plane (the `x` part is the gap term's);
//! - `F_scan = Σ_i |nearest(v_i) − v_i|²` over every ridge-line end point (Eq. 6), the
//!   nearest scanned point held fixed within one evaluation (as in ICP; it is piecewise
//!   constant, so this is the exact derivative almost everywhere).
//!
//! Departures from the paper, all documented: (1) lengths enter the penalty divided by
//! `L2 + L3` (the paper's units are not stated; this makes the weights independent of
//! mm or inches and matches the normalised error `E`); (2) `θ_0`, the fold between side
//! panel and strip, is left out of the smoothness sum (it is a designed corner: with it,
//! the 90° start would be smeared over the first quads); (3) `F_end_angle` is applied to
//! both long edges (the text's formula shows the left one only); (4) the gap rows carry a
//! shift `s` (`√w (x/ℓ + s)`) so the solver can enforce the gap as a constraint by the
//! method of multipliers (see [`crate::strip_solver`]); with `s = 0` they are the paper's.

use crate::point_cloud::ScanCloud;
use crate::strip_folding::{fold_strip, left_variable, right_variable, FoldedStrip, RidgeEnd, StripStart, StripState};
use crate::{SeatCurve, WeightsSpec};
use nalgebra::{DMatrix, Vector2, Vector3};

type Vec3 = Vector3<f64>;

/// A position anchor on one strip.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VertexAnchor {
    /// Ridge line index (`1..=M`).
    pub ridge: usize,
    /// Which end.
    pub end: RidgeEnd,
    /// Target position.
    pub position: Vec3,
}

/// Everything the penalty of one strip depends on besides its unknowns.
#[derive(Debug, Clone)]
pub struct StripTerms<'a> {
    /// Where the strip starts.
    pub start: StripStart,
    /// M.
    pub quads: usize,
    /// The weights.
    pub weights: WeightsSpec,
    /// Position anchors.
    pub anchors: Vec<VertexAnchor>,
    /// The seat curve.
    pub seat: Option<&'a SeatCurve>,
    /// Scanned points.
    pub scan: Option<&'a ScanCloud>,
    /// `L2 + L3`: lengths are divided by it.
    pub length_scale: f64,
    /// Weight of the gap rows now (the solver may raise it above `weights.no_gap`).
    pub gap_weight: f64,
    /// Multiplier shifts of the two gap rows.
    pub gap_shift: [f64; 2],
}

/// The penalty split into the paper's terms (each already multiplied by its weight).
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
pub struct PenaltyTerms {
    /// `w1 F_no_gap`.
    pub no_gap: f64,
    /// `w2 F_smooth` (with the end angle).
    pub smooth: f64,
    /// `w3 F_fair`.
    pub fair: f64,
    /// `w4 F_user_control`.
    pub user_control: f64,
    /// `w_scan F_scan`.
    pub scan: f64,
    /// The sum, `F`.
    pub total: f64,
}

impl<'a> StripTerms<'a> {
    /// Rows of the residual vector.
    pub fn residual_count(&self) -> usize {
        let m = self.quads;
        2 + m.saturating_sub(3)
            + 2
            + 2 * m
            + 3 * self.anchors.len()
            + if self.seat.is_some() { 4 } else { 0 }
            + if self.scan.is_some() { 6 * m } else { 0 }
    }

    fn state(&self, x: &[f64]) -> StripState {
        let mut s = StripState::initial(self.quads, self.start.length);
        s.set_vector(x);
        s
    }

    /// The residuals at `x` (layout of [`StripState::to_vector`]) into `out`.
    pub fn residuals_into(&self, x: &[f64], out: &mut [f64]) {
        self.evaluate(x, out, None, None);
    }

    /// The residuals and the Jacobian block (rows `row0..`, columns `col0..`).
    pub fn jacobian_into(&self, x: &[f64], jacobian: &mut DMatrix<f64>, row0: usize, col0: usize) {
        let mut r = vec![0.0; self.residual_count()];
        self.evaluate(x, &mut r, Some((jacobian, row0, col0)), None);
    }

    /// The residuals' own curvature `Σ_i r_i ∇²r_i`, added into `out` at
    /// `(col0, col0)`: the part of the penalty's Hessian the Gauss–Newton `JᵀJ` misses.
    ///
    /// Every row that depends on the folded shape is a linear function `gᵀ v` of one
    /// ridge-line end point `v` (gap, end angle, anchors, scanned points), so
    /// `Σ r_i ∇²r_i = Σ_v (Σ_i r_i g_i) · ∇²v` with the exact second derivatives of
    /// [`crate::strip_folding::FoldedStrip::add_weighted_hessian`]. Two
    /// approximations, both documented: the seat-curve rows take the projection onto
    /// the polyline as locally straight (`g = (I − t tᵀ)` in the symmetry plane; a
    /// polyline is straight between its vertices), and the scanned point nearest to a
    /// vertex is held fixed (as in the Jacobian). The fairness rows add
    /// [`StripTerms::fairness_curvature_into`].
    pub fn residual_curvature_into(&self, x: &[f64], out: &mut DMatrix<f64>, col0: usize) {
        let m = self.quads;
        let mut r = vec![0.0; self.residual_count()];
        let mut weights = vec![Vec3::zeros(); 2 * (m + 1)];
        let folded = self.evaluate(x, &mut r, None, Some(&mut weights));
        folded.add_weighted_hessian(&weights, out, col0);
        self.fairness_curvature_into(x, out, col0);
    }

    /// The gap constraints' curvature `Σ_e λ_e ∇²g_e` (exact), added into `out` at
    /// `(col0, col0)`.
    pub fn gap_curvature_into(&self, x: &[f64], multipliers: [f64; 2], out: &mut DMatrix<f64>, col0: usize) {
        let folded = fold_strip(&self.start, &self.state(x));
        let m = self.quads;
        let mut weights = vec![Vec3::zeros(); 2 * (m + 1)];
        for e in 0..2 {
            weights[2 * m + e] = Vec3::x() * (multipliers[e] / self.length_scale);
        }
        folded.add_weighted_hessian(&weights, out, col0);
    }

    /// The gap rows' raw values `(v_L,M)_x / ℓ`, `(v_R,M)_x / ℓ`.
    pub fn gaps(&self, x: &[f64]) -> [f64; 2] {
        let f = fold_strip(&self.start, &self.state(x));
        let m = self.quads;
        [f.left[m].x / self.length_scale, f.right[m].x / self.length_scale]
    }

    /// The gap rows' derivatives: `∂g_e/∂x` into rows `row0, row0 + 1` of `out` from column
    /// `col0`.
    pub fn gap_jacobian_into(&self, x: &[f64], out: &mut DMatrix<f64>, row0: usize, col0: usize) {
        let f = fold_strip(&self.start, &self.state(x));
        let m = self.quads;
        let mut d = vec![Vec3::zeros(); 3 * m - 2];
        for (e, end) in [RidgeEnd::Left, RidgeEnd::Right].into_iter().enumerate() {
            f.vertex_derivatives(end, m, &mut d);
            for (k, dk) in d.iter().enumerate() {
                out[(row0 + e, col0 + k)] = dk.x / self.length_scale;
            }
        }
    }

    /// The fairness rows' own curvature `Σ_i r_i ∇²r_i`, added into `out` at
    /// `(col0, col0)`.
    ///
    /// A fairness row is `r = √w3 Δ^(−1/2)` with `Δ = (x_i − x_{i−1}) / ℓ`, so
    /// `∇²r = ¾ √w3 Δ^(−5/2) / ℓ² · [1 −1; −1 1]` on `(x_i, x_{i−1})` and
    /// `r ∇²r = ¾ w3 Δ^(−3) / ℓ² · [1 −1; −1 1]`: three times the Gauss–Newton part
    /// `(∇r)(∇r)ᵀ = ¼ w3 Δ^(−3) / ℓ² · [..]`. These rows dominate `F` (Eq. 4 is never
    /// small), so without this term every step is about four times too long.
    pub fn fairness_curvature_into(&self, x: &[f64], out: &mut DMatrix<f64>, col0: usize) {
        let scale = 1.0 / self.length_scale;
        let w = self.weights.fair;
        for (dx, upper, lower) in self.fairness_spans(&self.state(x)) {
            if dx <= 0.0 {
                continue;
            }
            let h = 0.75 * w * dx.powi(-3) * scale * scale;
            let (upper, lower) = (upper.map(|u| col0 + u), lower.map(|l| col0 + l));
            if let Some(u) = upper {
                out[(u, u)] += h;
            }
            if let Some(l) = lower {
                out[(l, l)] += h;
            }
            if let (Some(u), Some(l)) = (upper, lower) {
                out[(u, l)] -= h;
                out[(l, u)] -= h;
            }
        }
    }

    /// The fairness rows' spans in row order (left edge `i = 1..=M`, then right): the
    /// normalised length `Δ = (x_i − x_{i−1}) / ℓ` and the unknowns of its two ends
    /// (`None` for the fixed `x_0` and `x_M`).
    fn fairness_spans(&self, state: &StripState) -> Vec<(f64, Option<usize>, Option<usize>)> {
        let m = self.quads;
        let scale = 1.0 / self.length_scale;
        let mut spans = Vec::with_capacity(2 * m);
        for (xs, var) in [
            (&state.left, left_variable as fn(usize, usize) -> usize),
            (&state.right, right_variable),
        ] {
            for i in 1..=m {
                spans.push((
                    (xs[i] - xs[i - 1]) * scale,
                    (i < m).then(|| var(m, i)),
                    (i > 1).then(|| var(m, i - 1)),
                ));
            }
        }
        spans
    }

    /// The paper's penalty `F` at `x` with the nominal weights and no shift, term by term.
    pub fn penalty(&self, x: &[f64]) -> PenaltyTerms {
        let plain = StripTerms {
            gap_weight: self.weights.no_gap,
            gap_shift: [0.0; 2],
            ..self.clone()
        };
        let mut r = vec![0.0; self.residual_count()];
        plain.evaluate(x, &mut r, None, None);
        let m = self.quads;
        let mut at = 0;
        let mut take = |n: usize| {
            let s: f64 = r[at..at + n].iter().map(|v| v * v).sum();
            at += n;
            s
        };
        let no_gap = take(2);
        let smooth = take(m.saturating_sub(3) + 2);
        let fair = take(2 * m);
        let user_control = take(3 * self.anchors.len() + if self.seat.is_some() { 4 } else { 0 });
        let scan = take(if self.scan.is_some() { 6 * m } else { 0 });
        PenaltyTerms {
            no_gap,
            smooth,
            fair,
            user_control,
            scan,
            total: no_gap + smooth + fair + user_control + scan,
        }
    }

    /// Residuals into `r`; optionally the Jacobian block, and optionally, per ridge-line
    /// end point `v_end,i` (index `2i + end`), `Σ r_k g_k` over the rows `r_k = g_kᵀ v + …`
    /// that depend on it (for [`StripTerms::residual_curvature_into`]). Returns the
    /// folded strip.
    fn evaluate(
        &self,
        x: &[f64],
        r: &mut [f64],
        mut jacobian: Option<(&mut DMatrix<f64>, usize, usize)>,
        mut weights: Option<&mut [Vec3]>,
    ) -> FoldedStrip {
        let m = self.quads;
        let n = 3 * m - 2;
        let scale = 1.0 / self.length_scale;
        let state = self.state(x);
        let folded = fold_strip(&self.start, &state);
        let mut d = vec![Vec3::zeros(); n];
        let mut row = 0;
        let mut weigh = |end: RidgeEnd, i: usize, w: Vec3| {
            if let Some(ws) = weights.as_mut() {
                ws[2 * i + end as usize] += w;
            }
        };
        // Writes one residual row that depends on vertex (end, i) through `g · v`.
        let vertex_row = |row: usize,
                          end: RidgeEnd,
                          i: usize,
                          g: Vec3,
                          jac: &mut Option<(&mut DMatrix<f64>, usize, usize)>,
                          d: &mut Vec<Vec3>| {
            if let Some((j, r0, c0)) = jac.as_mut() {
                folded.vertex_derivatives(end, i, d);
                for (k, dk) in d.iter().enumerate() {
                    j[(*r0 + row, *c0 + k)] = g.dot(dk);
                }
            }
        };
        // Gap (Eq. 2).
        let gw = self.gap_weight.sqrt();
        for (e, end) in [RidgeEnd::Left, RidgeEnd::Right].into_iter().enumerate() {
            let v = folded.vertex(end, m);
            r[row] = gw * (v.x * scale + self.gap_shift[e]);
            vertex_row(row, end, m, Vec3::x() * gw * scale, &mut jacobian, &mut d);
            weigh(end, m, Vec3::x() * (gw * scale * r[row]));
            row += 1;
        }
        // Smoothness over θ_1..θ_{M−1} (Eq. 3).
        let sw = self.weights.smooth.sqrt();
        for j in 2..m.saturating_sub(1) {
            r[row] = sw * (state.angles[j - 1] - 2.0 * state.angles[j] + state.angles[j + 1]);
            if let Some((jac, r0, c0)) = jacobian.as_mut() {
                jac[(*r0 + row, *c0 + j - 1)] = sw;
                jac[(*r0 + row, *c0 + j)] = -2.0 * sw;
                jac[(*r0 + row, *c0 + j + 1)] = sw;
            }
            row += 1;
        }
        // End angle: (v_M−1 − v_M)·(0, 1, 0).
        for end in [RidgeEnd::Left, RidgeEnd::Right] {
            let a = folded.vertex(end, m - 1);
            let b = folded.vertex(end, m);
            r[row] = sw * (a.y - b.y) * scale;
            weigh(end, m - 1, Vec3::y() * (sw * scale * r[row]));
            weigh(end, m, Vec3::y() * (-sw * scale * r[row]));
            if let Some((jac, r0, c0)) = jacobian.as_mut() {
                folded.vertex_derivatives(end, m - 1, &mut d);
                let mut e = vec![Vec3::zeros(); n];
                folded.vertex_derivatives(end, m, &mut e);
                for k in 0..n {
                    jac[(*r0 + row, *c0 + k)] = sw * scale * (d[k].y - e[k].y);
                }
            }
            row += 1;
        }
        // Fairness (Eq. 4).
        let fw = self.weights.fair.sqrt();
        for (dx, upper, lower) in self.fairness_spans(&state) {
            if dx <= 0.0 {
                r[row] = f64::INFINITY;
            } else {
                r[row] = fw / dx.sqrt();
                if let Some((jac, r0, c0)) = jacobian.as_mut() {
                    let g = -0.5 * fw * dx.powf(-1.5) * scale;
                    if let Some(u) = upper {
                        jac[(*r0 + row, *c0 + u)] = g;
                    }
                    if let Some(l) = lower {
                        jac[(*r0 + row, *c0 + l)] = -g;
                    }
                }
            }
            row += 1;
        }
        // Position anchors (Eq. 5).
        let uw = self.weights.user_control.sqrt();
        for a in &self.anchors {
            let v = folded.vertex(a.end, a.ridge);
            let diff = (v - a.position) * (uw * scale);
            for c in 0..3 {
                r[row + c] = diff[c];
            }
            weigh(a.end, a.ridge, diff * (uw * scale));
            if let Some((jac, r0, c0)) = jacobian.as_mut() {
                folded.vertex_derivatives(a.end, a.ridge, &mut d);
                for (k, dk) in d.iter().enumerate() {
                    for c in 0..3 {
                        jac[(*r0 + row + c, *c0 + k)] = uw * scale * dk[c];
                    }
                }
            }
            row += 3;
        }
        // Seat curve, measured in the symmetry plane ([z, y]).
        if let Some(seat) = self.seat {
            for end in [RidgeEnd::Left, RidgeEnd::Right] {
                let v = folded.vertex(end, m);
                let p = Vector2::new(v.z, v.y);
                let hit = seat.project(p);
                let diff = (p - hit.point) * (uw * scale);
                r[row] = diff.x;
                r[row + 1] = diff.y;
                let g = match hit.tangent {
                    Some(t) => diff - t * t.dot(&diff),
                    None => diff,
                } * (uw * scale);
                weigh(end, m, Vec3::new(0.0, g.y, g.x));
                if let Some((jac, r0, c0)) = jacobian.as_mut() {
                    folded.vertex_derivatives(end, m, &mut d);
                    for (k, dk) in d.iter().enumerate() {
                        let dp = Vector2::new(dk.z, dk.y);
                        let dr = match hit.tangent {
                            Some(t) => dp - t * t.dot(&dp),
                            None => dp,
                        } * (uw * scale);
                        jac[(*r0 + row, *c0 + k)] = dr.x;
                        jac[(*r0 + row + 1, *c0 + k)] = dr.y;
                    }
                }
                row += 2;
            }
        }
        // Scanned points (Eq. 6).
        if let Some(scan) = self.scan {
            let cw = self.weights.scan.sqrt();
            for end in [RidgeEnd::Left, RidgeEnd::Right] {
                for i in 1..=m {
                    let v = folded.vertex(end, i);
                    let diff = (v - scan.nearest(&v)) * (cw * scale);
                    for c in 0..3 {
                        r[row + c] = diff[c];
                    }
                    weigh(end, i, diff * (cw * scale));
                    if let Some((jac, r0, c0)) = jacobian.as_mut() {
                        folded.vertex_derivatives(end, i, &mut d);
                        for (k, dk) in d.iter().enumerate() {
                            for c in 0..3 {
                                jac[(*r0 + row + c, *c0 + k)] = cw * scale * dk[c];
                            }
                        }
                    }
                    row += 3;
                }
            }
        }
        debug_assert_eq!(row, self.residual_count());
        folded
    }
}
