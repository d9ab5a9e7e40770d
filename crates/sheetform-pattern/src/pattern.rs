use crate::{PatternError, Vec2};
use sheetform_mesh::SheetMesh;

/// A cutting pattern in millimetres at print scale: closed cut loops (outline and holes),
/// fold/score segments (the rulings, as bending guides), and piece labels.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Pattern {
    /// Closed loops to cut (outline counter-clockwise, holes clockwise).
    pub cut: Vec<Vec<Vec2>>,
    /// Segments to score or fold.
    pub fold: Vec<[Vec2; 2]>,
    /// Label positions and texts.
    pub labels: Vec<(Vec2, String)>,
}

/// Knobs of [`pattern_from_mesh`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PatternOptions {
    /// Scale factor applied to the pattern (1 = true size).
    pub scale: f64,
    /// At most this many rulings per piece as fold guides (evenly chosen).
    pub max_rulings_per_piece: usize,
}

impl Default for PatternOptions {
    fn default() -> Self {
        Self {
            scale: 1.0,
            max_rulings_per_piece: 60,
        }
    }
}

impl Pattern {
    /// Axis-aligned bounds `(min, max)` over the cut loops.
    pub fn bounds(&self) -> (Vec2, Vec2) {
        let mut lo = Vec2::repeat(f64::INFINITY);
        let mut hi = Vec2::repeat(f64::NEG_INFINITY);
        for p in self.cut.iter().flatten() {
            lo = lo.inf(p);
            hi = hi.sup(p);
        }
        (lo, hi)
    }
}

/// The pattern of a mesh: its flat boundary loops to cut, its rulings to score, its piece
/// names, converted to millimetres (`mesh.unit`) and multiplied by `options.scale`.
///
/// # Errors
/// A scale that is not a positive finite number.
pub fn pattern_from_mesh(mesh: &SheetMesh, options: &PatternOptions) -> Result<Pattern, PatternError> {
    if !(options.scale.is_finite() && options.scale > 0.0) {
        return Err(PatternError::Option {
            option: "scale",
            message: format!("must be a positive number, got {}", options.scale),
        });
    }
    let k = mesh.unit.millimetres() * options.scale;
    let at = |v: u32| mesh.flat[v as usize] * k;
    let cut = mesh
        .boundary_loops()
        .iter()
        .map(|l| l.iter().map(|&v| at(v)).collect())
        .collect();
    let mut fold = Vec::new();
    for piece in 0..mesh.pieces.len() {
        let rulings: Vec<_> = mesh.rulings.iter().filter(|r| r.piece as usize == piece).collect();
        let step = rulings.len().div_ceil(options.max_rulings_per_piece.max(1)).max(1);
        for (i, r) in rulings.iter().enumerate() {
            if i % step == 0 || i + 1 == rulings.len() {
                fold.push([at(r.vertices[0]), at(*r.vertices.last().expect("ruling has vertices"))]);
            }
        }
    }
    let mut labels = Vec::new();
    for (p, piece) in mesh.pieces.iter().enumerate() {
        let best = mesh
            .triangles
            .iter()
            .zip(&mesh.face_pieces)
            .filter(|(_, &fp)| fp as usize == p)
            .map(|(t, _)| {
                let [a, b, c] = t.map(at);
                (((b - a).x * (c - a).y - (b - a).y * (c - a).x).abs(), (a + b + c) / 3.0)
            })
            .max_by(|x, y| x.0.total_cmp(&y.0));
        if let Some((_, c)) = best {
            labels.push((c, piece.name.clone()));
        }
    }
    Ok(Pattern { cut, fold, labels })
}
