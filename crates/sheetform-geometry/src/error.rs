use thiserror::Error;

/// Why a geometric object could not be built or evaluated.
///
/// Every variant names the offending item so that the message can be shown to a user
/// as it is.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum GeometryError {
    /// A coordinate is NaN or infinite.
    #[error("{what} has a non-finite coordinate (NaN or infinity) at index {index}")]
    NonFinite {
        /// What was being read (e.g. "control point", "outline vertex").
        what: String,
        /// Index of the offending item.
        index: usize,
    },
    /// Too few control points for the requested degree.
    #[error("a curve of degree {degree} needs at least {needed} control points, got {got}")]
    TooFewControlPoints {
        /// The curve degree.
        degree: usize,
        /// How many points that degree needs.
        needed: usize,
        /// How many were given.
        got: usize,
    },
    /// The degree is not allowed here.
    #[error("degree {degree} is not allowed: {reason}")]
    BadDegree {
        /// The degree given.
        degree: usize,
        /// Why it is refused.
        reason: String,
    },
    /// A knot vector is malformed.
    #[error("knot vector is invalid: {reason}")]
    BadKnots {
        /// What is wrong with it.
        reason: String,
    },
    /// The curve has (numerically) zero length or zero speed.
    #[error("the curve is degenerate: {reason}")]
    DegenerateCurve {
        /// What is degenerate.
        reason: String,
    },
    /// A polygon ring has fewer than three distinct vertices or zero area.
    #[error("{ring} is degenerate: {reason}")]
    DegeneratePolygon {
        /// Which ring ("outline" or "hole k").
        ring: String,
        /// What is wrong.
        reason: String,
    },
    /// Two edges of a polygon cross or touch.
    #[error(
        "{ring_a} edge {edge_a} crosses {ring_b} edge {edge_b} near ({}, {})",
        crate::short_number(*.x),
        crate::short_number(*.y)
    )]
    SelfIntersection {
        /// Ring of the first edge.
        ring_a: String,
        /// Index of the first edge within its ring.
        edge_a: usize,
        /// Ring of the second edge.
        ring_b: String,
        /// Index of the second edge within its ring.
        edge_b: usize,
        /// Approximate crossing point, x.
        x: f64,
        /// Approximate crossing point, y.
        y: f64,
    },
    /// A hole lies (partly) outside the outline or inside another hole.
    #[error("hole {hole} is not inside the outline or lies inside another hole")]
    HoleOutside {
        /// Index of the hole.
        hole: usize,
    },
}
