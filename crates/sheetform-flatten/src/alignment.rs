use crate::Vec2;

/// The rigid motion (rotation, optionally with a reflection, and translation) that best
/// maps one 2D point set onto another in the least-squares sense.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigidAlignment {
    /// Rotation angle (radians).
    pub angle: f64,
    /// Whether the first set is mirrored before rotating.
    pub reflected: bool,
    /// Translation applied after the rotation.
    pub translation: Vec2,
    /// Largest distance between the moved first set and the second.
    pub max_distance: f64,
    /// Root mean square distance.
    pub rms_distance: f64,
}

impl RigidAlignment {
    /// Applies the motion to a point of the first set.
    pub fn apply(&self, p: Vec2) -> Vec2 {
        let q = if self.reflected { Vec2::new(p.x, -p.y) } else { p };
        let (s, c) = self.angle.sin_cos();
        Vec2::new(c * q.x - s * q.y, s * q.x + c * q.y) + self.translation
    }
}

/// Least-squares rigid alignment of `from` onto `to` (same length, paired by index):
/// the 2D Kabsch/Umeyama solution, `θ = atan2(Σ a×b, Σ a·b)` on centred points; with
/// `allow_reflection` the mirrored fit is also tried and the better one kept.
pub fn align_rigid(from: &[Vec2], to: &[Vec2], allow_reflection: bool) -> RigidAlignment {
    let n = from.len().max(1) as f64;
    let fit = |reflected: bool| {
        let src: Vec<Vec2> = from
            .iter()
            .map(|p| if reflected { Vec2::new(p.x, -p.y) } else { *p })
            .collect();
        let cs = src.iter().sum::<Vec2>() / n;
        let ct = to.iter().sum::<Vec2>() / n;
        let (mut dot, mut cross) = (0.0, 0.0);
        for (a, b) in src.iter().zip(to) {
            let (a, b) = (a - cs, b - ct);
            dot += a.dot(&b);
            cross += a.x * b.y - a.y * b.x;
        }
        let angle = cross.atan2(dot);
        let (s, c) = angle.sin_cos();
        let translation = ct - Vec2::new(c * cs.x - s * cs.y, s * cs.x + c * cs.y);
        let mut a = RigidAlignment {
            angle,
            reflected,
            translation,
            max_distance: 0.0,
            rms_distance: 0.0,
        };
        let mut sum = 0.0;
        for (p, q) in from.iter().zip(to) {
            let d = (a.apply(*p) - q).norm();
            a.max_distance = a.max_distance.max(d);
            sum += d * d;
        }
        a.rms_distance = (sum / n).sqrt();
        a
    };
    let plain = fit(false);
    if allow_reflection {
        let mirrored = fit(true);
        if mirrored.rms_distance < plain.rms_distance {
            return mirrored;
        }
    }
    plain
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recovers_a_rigid_motion() {
        let from = vec![
            Vec2::new(0.0, 0.0),
            Vec2::new(2.0, 0.0),
            Vec2::new(1.0, 3.0),
            Vec2::new(-1.0, 1.0),
        ];
        let (s, c) = 0.7f64.sin_cos();
        let to: Vec<Vec2> = from
            .iter()
            .map(|p| Vec2::new(c * p.x - s * p.y + 5.0, s * p.x + c * p.y - 2.0))
            .collect();
        let a = align_rigid(&from, &to, true);
        assert!(!a.reflected && (a.angle - 0.7).abs() < 1e-12 && a.max_distance < 1e-12);
        let mirrored: Vec<Vec2> = to.iter().map(|p| Vec2::new(p.x, -p.y)).collect();
        assert!(align_rigid(&from, &mirrored, true).max_distance < 1e-12);
        assert!(align_rigid(&from, &mirrored, false).max_distance > 0.1);
    }
}
