use nalgebra::SVector;

/// A parametric curve `c(u)`, `u ∈ [u0, u1]`, in `D` dimensions with exact derivatives.
///
/// Implementations return exact derivatives (no finite differences) of every order the
/// caller asks for; orders above the polynomial degree are zero.
pub trait ParametricCurve<const D: usize> {
    /// The parameter interval `[u0, u1]`.
    fn domain(&self) -> (f64, f64);

    /// Writes `c(u), c'(u), …, c^(k)(u)` into `out[0..=k]`, where `k = out.len() - 1`.
    /// Parameters outside the domain are clamped to it.
    fn derivatives_into(&self, u: f64, out: &mut [SVector<f64, D>]);

    /// The point `c(u)`.
    fn point(&self, u: f64) -> SVector<f64, D> {
        let mut out = [SVector::<f64, D>::zeros(); 1];
        self.derivatives_into(u, &mut out);
        out[0]
    }

    /// `[c(u), c'(u), c''(u), c'''(u), c''''(u)]`: position and the first four derivatives.
    fn derivatives4(&self, u: f64) -> [SVector<f64, D>; 5] {
        let mut out = [SVector::<f64, D>::zeros(); 5];
        self.derivatives_into(u, &mut out);
        out
    }
}

/// A 3D parametric curve; the control geodesics of system A are of this kind.
pub trait Curve3: ParametricCurve<3> {}
impl<T: ParametricCurve<3>> Curve3 for T {}
