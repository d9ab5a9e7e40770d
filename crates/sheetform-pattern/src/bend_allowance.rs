//! Bend allowance of a sheet with thickness (sheet metal, greyboard, plywood): the flat
//! length each fold takes, by the K-factor rule that sheet-metal tools (FreeCAD
//! SheetMetal, Inventor, SolidWorks) use.
//!
//! A sheet of thickness `T` bent through an angle `A` (radians; the deviation from flat,
//! the dihedral fold angle) around an inner radius `R` keeps its length on the *neutral
//! layer*, which lies `K·T` out from the inner surface (`K`, the K-factor in the ANSI
//! convention, between 0 and 1; the DIN convention's factor is twice it). The flat
//! length of the bend, the **bend allowance**, is
//!
//! ```text
//! BA = A · (R + K·T)
//! ```
//!
//! The model's sharp fold is the *mold line*: where the two flanges' surfaces (the model's
//! surface) would meet. Each flange's flat part ends at its tangent line, set back from
//! the mold line by
//!
//! ```text
//! SB = (R + τ·T) · tan(A/2)
//! ```
//!
//! where `τ·T` is how far the model's surface lies out from the bend's inner surface:
//! `τ = 1` where the model is the outside of the bend, `τ = 0` where it is the inside,
//! `τ = ½` for a model of the mid-surface ([`MaterialSide`]). Across each fold the flat
//! pattern therefore grows by `BA − 2·SB` (negative: the *bend deduction*) over the
//! zero-thickness development. FreeCAD SheetMetal's worked example (T = 2, K = 0.38,
//! R = 1.64, a 90° bend, a 51.76 mm flange to the outer mold line) gives a 48.12 mm flat
//! leg and the bend line 50.00 mm from the end; the tests check these figures.
//!
//! Departures: the model is taken as zero-thickness folds between flat panels; smooth
//! bends (under the pattern's smooth-bend angle) keep the model surface's length (exact
//! for a mid-surface model at K = ½); the corners where cut edges meet (a box's welded
//! corners) are not trimmed for the thickness. Where two bend zones meet at their ends, a
//! square corner relief is cut out ([`corner_reliefs`]).

use crate::{PatternError, Vec2};
use sheetform_geometry::{refused_number, short_number};
use sheetform_mesh::{EdgeTable, SheetMesh, UnionFind};
use std::collections::HashMap;

/// Where the sheet's thickness lies relative to the model's surface, seen from the side
/// its face normals point to (the pattern's printed side).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum MaterialSide {
    /// Behind the surface: the model is the sheet's printed face (a closed model with
    /// outward normals is the outside of the part). Mountain folds have the model on the
    /// outside of the bend, valley folds on the inside.
    #[default]
    Behind,
    /// Centred on the surface: the model is the sheet's mid-surface.
    Centred,
    /// In front of the surface: the model is the sheet's back face.
    InFront,
}

/// Thickness and bending of the material: turns every mountain and valley fold of the
/// pattern into a bend zone of its flat length (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BendAllowance {
    /// Sheet thickness `T` (mm).
    pub thickness_mm: f64,
    /// Inner bend radius `R` (mm; 0 for a sharp fold).
    pub inner_radius_mm: f64,
    /// K-factor (ANSI convention, in `[0, 1]`): where the neutral layer lies across the
    /// thickness, from the inside of the bend.
    pub k_factor: f64,
    /// Where the thickness lies relative to the model's surface.
    pub material_side: MaterialSide,
}

impl Default for BendAllowance {
    /// 1 mm sheet, inner radius equal to the thickness, K = 0.44 (air bending of mild
    /// steel at R ≈ T), the model being the printed face.
    fn default() -> Self {
        Self {
            thickness_mm: 1.0,
            inner_radius_mm: 1.0,
            k_factor: 0.44,
            material_side: MaterialSide::Behind,
        }
    }
}

/// How far the bend zones reach into their flanges before the union, relative to the
/// part's size (at least 1e-6 mm): far below what a cutter resolves, ten times the grid
/// geo's boolean operations snap to (about 1e-7 of the size).
const OVERLAP_RELATIVE: f64 = 1e-6;

/// Holes of a bent part's outline smaller than this across (mm) are closed: specks
/// where the trimmed corners of several flanges meet, under a laser's kerf.
const MIN_HOLE_MM: f64 = 0.1;

/// Largest sheet thickness and inner bend radius accepted (mm).
pub const MAX_THICKNESS_MM: f64 = 100.0;

/// Folds sharper than this (degrees) cannot be given a bend allowance: the setback
/// `tan(A/2)` grows without bound as a fold closes flat on itself (a hem).
pub const MAX_BEND_DEGREES: f64 = 170.0;

/// The flat geometry of one bend (mm).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BendGeometry {
    /// Distance from the mold line to each flange's tangent line, `SB`.
    pub setback_mm: f64,
    /// Flat length of the bend zone between the two tangent lines, `BA`.
    pub allowance_mm: f64,
}

impl BendGeometry {
    /// How much longer the flat pattern is across this fold than the zero-thickness
    /// development: `BA − 2·SB` (negative for a bend deduction).
    pub fn flat_change_mm(&self) -> f64 {
        self.allowance_mm - 2.0 * self.setback_mm
    }
}

impl BendAllowance {
    /// Checks the figures: thickness positive, radius non-negative, both at most
    /// [`MAX_THICKNESS_MM`]; K-factor in `[0, 1]`.
    ///
    /// # Errors
    /// The option named with its value and bounds.
    pub fn validate(&self) -> Result<(), PatternError> {
        let bad = |option: &'static str, message: String| Err(PatternError::Option { option, message });
        if !(self.thickness_mm.is_finite() && self.thickness_mm > 0.0 && self.thickness_mm <= MAX_THICKNESS_MM) {
            return bad(
                "thickness_mm",
                format!(
                    "must be above 0 and at most {MAX_THICKNESS_MM} mm, got {}",
                    refused_number(self.thickness_mm, &[0.0, MAX_THICKNESS_MM])
                ),
            );
        }
        if !(self.inner_radius_mm.is_finite() && (0.0..=MAX_THICKNESS_MM).contains(&self.inner_radius_mm)) {
            return bad(
                "inner_radius_mm",
                format!(
                    "must be between 0 and {MAX_THICKNESS_MM} mm, got {}",
                    refused_number(self.inner_radius_mm, &[0.0, MAX_THICKNESS_MM])
                ),
            );
        }
        if !(self.k_factor.is_finite() && (0.0..=1.0).contains(&self.k_factor)) {
            return bad(
                "k_factor",
                format!(
                    "must be between 0 and 1, got {}",
                    refused_number(self.k_factor, &[0.0, 1.0])
                ),
            );
        }
        Ok(())
    }

    /// The bend of a fold with signed dihedral angle `signed_angle` (radians; positive for
    /// a mountain seen from the printed side): `SB = (R + τ·T)·tan(A/2)` and
    /// `BA = A·(R + K·T)` with `A = |signed_angle|` and `τ` from the material side.
    pub fn bend(&self, signed_angle: f64) -> BendGeometry {
        let angle = signed_angle.abs();
        let outside = match self.material_side {
            MaterialSide::Centred => 0.5,
            MaterialSide::Behind if signed_angle > 0.0 => 1.0,
            MaterialSide::InFront if signed_angle < 0.0 => 1.0,
            _ => 0.0,
        };
        BendGeometry {
            setback_mm: (self.inner_radius_mm + outside * self.thickness_mm) * (0.5 * angle).tan(),
            allowance_mm: angle * (self.inner_radius_mm + self.k_factor * self.thickness_mm),
        }
    }
}

/// One fold given its bend allowance, on the pattern.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct BendZone {
    /// The pattern part holding it.
    pub part: usize,
    /// The mold line's ends (mm) where the first side's panel lies on the pattern.
    pub a: Vec2,
    /// See `a`.
    pub b: Vec2,
    /// Unit normal of the mold line, from the first side's panel towards the other.
    pub across: Vec2,
    /// Setback and allowance.
    pub bend: BendGeometry,
    /// Signed dihedral angle (radians).
    pub signed_angle: f64,
}

impl BendZone {
    /// The mold line moved `distance` (mm) across, towards the second side.
    pub fn line(&self, distance: f64) -> (Vec2, Vec2) {
        (self.a + self.across * distance, self.b + self.across * distance)
    }

    /// The bend line: the middle of the bend zone.
    pub fn centre_line(&self) -> (Vec2, Vec2) {
        self.line(0.5 * self.bend.allowance_mm - self.bend.setback_mm)
    }

    /// The two tangent lines, where the flanges end and the bend begins.
    pub fn tangent_lines(&self) -> [(Vec2, Vec2); 2] {
        [
            self.line(-self.bend.setback_mm),
            self.line(self.bend.allowance_mm - self.bend.setback_mm),
        ]
    }

    /// The bend zone, counter-clockwise, reaching `overlap` (mm) into both flanges so that
    /// the union with them leaves no hairline gap from rounding.
    fn region(&self, overlap: f64) -> Vec<Vec2> {
        let (a0, b0) = self.line(-self.bend.setback_mm - overlap);
        let (a1, b1) = self.line(self.bend.allowance_mm - self.bend.setback_mm + overlap);
        counter_clockwise(vec![a0, b0, b1, a1])
    }
}

/// The pattern laid out with bend allowances: each panel (faces joined by unfolded edges)
/// moved across its folds, the bend zones between them, and the region of every part
/// that has a bend (its faces trimmed at their tangent lines, and the bend zones).
#[derive(Debug, Clone, Default)]
pub(crate) struct BentLayout {
    /// How far each face moved on the pattern (mm).
    pub face_offset: Vec<Vec2>,
    /// The bend zones.
    pub zones: Vec<BendZone>,
    /// Per part: the polygons whose union is its region (counter-clockwise), empty for a
    /// part without a bend (its outline stays the mesh's boundary).
    pub part_polygons: Vec<Vec<Vec<Vec2>>>,
}

/// Gives every fold of `folds` (vertex chains of straight fold lines with their signed
/// angle, radians) its bend allowance: the faces of the pattern are grouped into flat
/// panels joined at the folds; from the largest panel of each part outwards, the panel
/// across a fold moves by `BA − 2·SB` along the fold's normal; each face touching a fold
/// is trimmed at the tangent line (`SB` from the mold line); the bend zone (`BA` wide)
/// joins the two flanges. `at` gives a vertex's place on the pattern (mm).
///
/// # Errors
/// [`PatternError::BendLoop`] when the folds of a part close a loop of panels whose moves
/// disagree (folds all round an inner vertex: such a sheet cannot be bent with thickness
/// without a cut there).
pub(crate) fn lay_out_bends(
    mesh: &SheetMesh,
    table: &EdgeTable,
    at: &impl Fn(u32) -> Vec2,
    face_part: &[usize],
    part_names: &[String],
    folds: &[(Vec<u32>, f64)],
    allowance: &BendAllowance,
) -> Result<BentLayout, PatternError> {
    if let Some((chain, angle)) = folds
        .iter()
        .find(|(_, angle)| angle.abs() > MAX_BEND_DEGREES.to_radians())
    {
        let point = at(chain[0]);
        return Err(PatternError::Option {
            option: "thickness_mm",
            message: format!(
                "the fold at ({}, {}) mm on the pattern turns by {:.1}°, closer to flat on itself than a bend allowance can take (at most {MAX_BEND_DEGREES}°)",
                short_number(point.x),
                short_number(point.y),
                angle.abs().to_degrees()
            ),
        });
    }
    let face_count = mesh.triangles.len();
    let key = |a: u32, b: u32| if a < b { [a, b] } else { [b, a] };
    let mut chain_of_edge: HashMap<[u32; 2], usize> = HashMap::new();
    for (c, (chain, _)) in folds.iter().enumerate() {
        for w in chain.windows(2) {
            chain_of_edge.insert(key(w[0], w[1]), c);
        }
    }
    // Panels: faces joined across every two-sided edge that is no fold.
    let mut panels = UnionFind::new(face_count);
    for e in 0..table.len() {
        if let [f, g] = table.sides(e) {
            if !chain_of_edge.contains_key(&table.edges[e]) {
                panels.union(f.face, g.face);
            }
        }
    }
    let panel: Vec<u32> = (0..face_count as u32).map(|f| panels.find(f)).collect();
    let third = |f: u32, a: u32, b: u32| {
        mesh.triangles[f as usize]
            .into_iter()
            .find(|&v| v != a && v != b)
            .unwrap_or(a)
    };
    // A straight fold line joins one pair of panels along each stretch; where the panels
    // on one side change (another cut or fold reaching its vertex from that side), each
    // stretch gets its own bend zone, as the panels there move differently.
    let side_panels = |a: u32, b: u32| {
        let e = table.find(a, b)?;
        let [f, g] = table.sides(e) else { return None };
        let d = at(b) - at(a);
        let left = |face: u32| {
            let r = at(third(face, a, b)) - at(a);
            sheetform_geometry::cross2(d, r) > 0.0
        };
        let (pf, pg) = (panel[f.face as usize], panel[g.face as usize]);
        Some(if left(f.face) { (pf, pg) } else { (pg, pf) })
    };
    let mut lines: Vec<(Vec<u32>, f64)> = Vec::with_capacity(folds.len());
    for (chain, angle) in folds {
        let mut line = vec![chain[0]];
        let mut pair = None;
        for w in chain.windows(2) {
            let here = side_panels(w[0], w[1]);
            if pair.is_some() && here != pair {
                lines.push((std::mem::replace(&mut line, vec![w[0]]), *angle));
            }
            pair = here;
            line.push(w[1]);
        }
        lines.push((line, *angle));
    }
    let folds = lines.as_slice();
    chain_of_edge.clear();
    for (c, (chain, _)) in folds.iter().enumerate() {
        for w in chain.windows(2) {
            chain_of_edge.insert(key(w[0], w[1]), c);
        }
    }
    // The unit normal of edge `a → b` pointing into face `f` (on the pattern).
    let normal_into = |a: u32, b: u32, f: u32| {
        let d = at(b) - at(a);
        let n = Vec2::new(-d.y, d.x) / d.norm().max(f64::MIN_POSITIVE);
        if (at(third(f, a, b)) - at(a)).dot(&n) >= 0.0 {
            n
        } else {
            -n
        }
    };

    // Links between panels: (first side's face, second side's face, chain, normal from
    // the first towards the second).
    let mut links: HashMap<u32, Vec<(u32, usize, Vec2)>> = HashMap::new();
    // The panels on either side of each fold line.
    let mut sides: Vec<Vec<u32>> = vec![Vec::new(); folds.len()];
    for (c, (chain, _)) in folds.iter().enumerate() {
        for w in chain.windows(2) {
            let Some(e) = table.find(w[0], w[1]) else { continue };
            let [f, g] = table.sides(e) else { continue };
            for face in [f.face, g.face] {
                if !sides[c].contains(&panel[face as usize]) {
                    sides[c].push(panel[face as usize]);
                }
            }
            let across = normal_into(w[0], w[1], g.face);
            links
                .entry(panel[f.face as usize])
                .or_default()
                .push((panel[g.face as usize], c, across));
            links
                .entry(panel[g.face as usize])
                .or_default()
                .push((panel[f.face as usize], c, -across));
        }
    }
    let bends: Vec<BendGeometry> = folds.iter().map(|(_, angle)| allowance.bend(*angle)).collect();

    // Moves, from the largest panel of each connected set of panels outwards.
    let mut area: HashMap<u32, f64> = HashMap::new();
    for (f, t) in mesh.triangles.iter().enumerate() {
        let [a, b, c] = t.map(at);
        *area.entry(panel[f]).or_default() += 0.5 * ((b - a).x * (c - a).y - (b - a).y * (c - a).x).abs();
    }
    let mut roots: Vec<(u32, f64)> = area.into_iter().collect();
    roots.sort_by(|x, y| y.1.total_cmp(&x.1).then(x.0.cmp(&y.0)));
    let mut offset: HashMap<u32, Vec2> = HashMap::new();
    for &(root, _) in &roots {
        if offset.contains_key(&root) {
            continue;
        }
        offset.insert(root, Vec2::zeros());
        let mut stack = vec![root];
        while let Some(p) = stack.pop() {
            let here = offset[&p];
            for &(q, c, across) in links.get(&p).map_or(&[][..], |l| l.as_slice()) {
                let there = here + across * bends[c].flat_change_mm();
                match offset.get(&q) {
                    None => {
                        offset.insert(q, there);
                        stack.push(q);
                    }
                    Some(known) if (known - there).norm() > 1e-6 * (1.0 + known.norm()) => {
                        let vertex = folds[c].0[0];
                        let f = mesh.triangles.iter().position(|t| t.contains(&vertex)).unwrap_or(0);
                        let point = at(vertex);
                        return Err(PatternError::BendLoop {
                            piece: part_names[face_part[f]].clone(),
                            x_mm: point.x,
                            y_mm: point.y,
                        });
                    }
                    Some(_) => {}
                }
            }
        }
    }
    let face_offset: Vec<Vec2> = panel.iter().map(|p| offset[p]).collect();

    // Bend zones, seen from each chain's first edge's first side.
    // (Fold lines are chains of two-sided edges: every one has its zone.)
    let mut zones: Vec<Option<BendZone>> = Vec::with_capacity(folds.len());
    for (c, (chain, angle)) in folds.iter().enumerate() {
        let (first, last) = (chain[0], *chain.last().expect("a fold line has two ends"));
        let sides = table.find(chain[0], chain[1]).map(|e| table.sides(e));
        let Some([f, g]) = sides else {
            zones.push(None);
            continue;
        };
        let o = face_offset[f.face as usize];
        zones.push(Some(BendZone {
            part: face_part[f.face as usize],
            a: at(first) + o,
            b: at(last) + o,
            across: normal_into(chain[0], chain[1], g.face),
            bend: bends[c],
            signed_angle: *angle,
        }));
    }

    // Trimming: each panel's faces stop at the tangent line of every fold on its border
    // (faces along the fold, and faces at its ends lying within its length).
    let parts = face_part.iter().copied().max().map_or(0, |p| p + 1);
    let mut part_polygons: Vec<Vec<Vec<Vec2>>> = vec![Vec::new(); parts];
    let mut chains_at: HashMap<u32, Vec<usize>> = HashMap::new();
    for (c, (chain, _)) in folds.iter().enumerate() {
        for &v in chain {
            chains_at.entry(v).or_default().push(c);
        }
    }
    let bent_part: Vec<bool> = {
        let mut bent = vec![false; parts];
        for z in zones.iter().flatten() {
            bent[z.part] = true;
        }
        bent
    };
    let mut kept_panels: std::collections::HashSet<u32> = std::collections::HashSet::new();
    for (f, t) in mesh.triangles.iter().enumerate() {
        if !bent_part[face_part[f]] {
            kept_panels.insert(panel[f]);
            continue;
        }
        let o = face_offset[f];
        let mut polygon: Vec<Vec2> = t.iter().map(|&v| at(v) + o).collect();
        let mut candidates: Vec<usize> = t
            .iter()
            .flat_map(|v| chains_at.get(v).into_iter().flatten().copied())
            .collect();
        candidates.sort_unstable();
        candidates.dedup();
        for c in candidates {
            // Only the flanges of this fold stop at its tangent lines.
            if !sides[c].contains(&panel[f]) {
                continue;
            }
            let Some(zone) = &zones[c] else { continue };
            // Which side of the fold this face is on: its moved corners against the
            // zone's mold line (the first side lies behind `across`).
            let chain = &folds[c].0;
            let on_edge = (0..3).any(|k| chain_of_edge.get(&key(t[k], t[(k + 1) % 3])) == Some(&c));
            let (a0, b0) = (at(chain[0]), at(*chain.last().expect("two ends")));
            let length = (b0 - a0).norm();
            let along = (b0 - a0) / length.max(f64::MIN_POSITIVE);
            let within = t.iter().all(|&v| {
                let s = (at(v) - a0).dot(&along);
                s >= -1e-9 * length && s <= length * (1.0 + 1e-9)
            });
            if !on_edge && !within {
                continue;
            }
            let centroid = t.iter().map(|&v| at(v)).sum::<Vec2>() / 3.0;
            let outward = if (centroid - a0).dot(&zone.across) < 0.0 {
                zone.across
            } else {
                -zone.across
            };
            // Keep the flange: behind the tangent line, `SB` in from the mold line where
            // this face's panel has moved it.
            polygon = clip_half_plane(&polygon, a0 + o - outward * zone.bend.setback_mm, outward);
            if polygon.len() < 3 {
                break;
            }
        }
        if polygon.len() >= 3 && sheetform_geometry::signed_area(&polygon).abs() > 0.0 {
            kept_panels.insert(panel[f]);
            part_polygons[face_part[f]].push(counter_clockwise(polygon));
        }
    }
    // A flange narrower than its bends' setbacks is trimmed away whole: its bends cannot
    // be made at this radius and thickness.
    for (c, zone) in zones.iter().enumerate() {
        let Some(zone) = zone else { continue };
        if let Some(&lost) = sides[c].iter().find(|p| !kept_panels.contains(p)) {
            let f = panel.iter().position(|&q| q == lost).unwrap_or(0);
            let point = zone.a;
            return Err(PatternError::Option {
                option: "thickness_mm",
                message: format!(
                    "piece `{}`: the flange at the fold near ({}, {}) mm is narrower than the setbacks of its bends ({} mm here): it cannot be bent at this thickness and radius",
                    part_names[face_part[f]],
                    short_number(point.x),
                    short_number(point.y),
                    short_number(zone.bend.setback_mm)
                ),
            });
        }
    }
    let zones: Vec<BendZone> = zones.into_iter().flatten().collect();
    let mut part_size = vec![0.0f64; parts];
    for (part, polygons) in part_polygons.iter().enumerate() {
        let (lo, hi) = crate::point_bounds(polygons.iter().flatten());
        if lo.x <= hi.x {
            part_size[part] = (hi - lo).norm();
        }
    }
    for z in &zones {
        let overlap = (OVERLAP_RELATIVE * part_size[z.part]).max(1e-6);
        part_polygons[z.part].push(z.region(overlap));
    }
    Ok(BentLayout {
        face_offset,
        zones,
        part_polygons,
    })
}

/// The part of a convex polygon where `(p − point)·outward ≤ 0` (Sutherland–Hodgman
/// against one line).
fn clip_half_plane(polygon: &[Vec2], point: Vec2, outward: Vec2) -> Vec<Vec2> {
    let side = |p: &Vec2| (p - point).dot(&outward);
    let mut out = Vec::with_capacity(polygon.len() + 1);
    for i in 0..polygon.len() {
        let (p, q) = (polygon[i], polygon[(i + 1) % polygon.len()]);
        let (sp, sq) = (side(&p), side(&q));
        if sp <= 0.0 {
            out.push(p);
        }
        if (sp < 0.0 && sq > 0.0) || (sp > 0.0 && sq < 0.0) {
            out.push(p + (q - p) * (sp / (sp - sq)));
        }
    }
    out
}

fn counter_clockwise(mut polygon: Vec<Vec2>) -> Vec<Vec2> {
    if sheetform_geometry::signed_area(&polygon) < 0.0 {
        polygon.reverse();
    }
    polygon
}

/// Corner reliefs of one part: where two bend zones meet at their ends on the part's
/// outline (a box's flanges folded up around one corner of its base), the material in
/// both zones can bend with neither, and tears or bulges. As FreeCAD SheetMetal's square
/// corner relief, a square is cut out there: centred where the two bend lines cross,
/// aligned with the first zone, reaching past both zones' tangent lines by half the
/// sheet's `thickness_mm`. Zones that cross in the middle of one of them, or meet inside
/// the part away from its `outline` (folds around an inner vertex of a net, which no
/// relief frees), get none. Counter-clockwise squares (mm).
pub(crate) fn corner_reliefs(zones: &[&BendZone], thickness_mm: f64, outline: &[Vec<Vec2>]) -> Vec<Vec<Vec2>> {
    let mut reliefs = Vec::new();
    for (i, first) in zones.iter().enumerate() {
        for second in &zones[i + 1..] {
            let (a0, a1) = first.centre_line();
            let (b0, b1) = second.centre_line();
            let (u, v) = (a1 - a0, b1 - b0);
            let denominator = u.x * v.y - u.y * v.x;
            if denominator.abs() <= 1e-9 * u.norm() * v.norm() {
                continue;
            }
            // The crossing of the two bend lines: a0 + s·u = b0 + t·v.
            let w = b0 - a0;
            let (s, t) = (
                (w.x * v.y - w.y * v.x) / denominator,
                (w.x * u.y - w.y * u.x) / denominator,
            );
            let crossing = a0 + u * s;
            let (half_first, half_second) = (0.5 * first.bend.allowance_mm, 0.5 * second.bend.allowance_mm);
            // At an end of each: within the other's half width (and the thickness) of it.
            let at_end = |parameter: f64, length: f64, reach: f64| {
                let along = parameter * length;
                along <= reach || along >= length - reach
            };
            let reach = |half: f64| half + thickness_mm;
            if !at_end(s, u.norm(), reach(half_second)) || !at_end(t, v.norm(), reach(half_first)) {
                continue;
            }
            // Beyond either end by more than that: the zones do not meet.
            let outside = |parameter: f64, length: f64, reach: f64| {
                parameter * length < -reach || parameter * length > length + reach
            };
            if outside(s, u.norm(), reach(half_second)) || outside(t, v.norm(), reach(half_first)) {
                continue;
            }
            // On the outline: within reach of one of its edges.
            let near_outline = outline.iter().any(|l| {
                (0..l.len()).any(|k| {
                    sheetform_geometry::segment_distance([l[k], l[(k + 1) % l.len()]], [crossing, crossing])
                        <= reach(half_first.max(half_second))
                })
            });
            if !near_outline {
                continue;
            }
            let along = u / u.norm();
            let across = Vec2::new(-along.y, along.x);
            // Half sizes: along the first zone, the second's half width; across it, its own.
            // The sine of the angle between the two zones: the second's width measured
            // along the first.
            let sine = (u.x * v.y - u.y * v.x).abs() / (u.norm() * v.norm());
            let (h_along, h_across) = (
                half_second / sine.max(1e-9) + 0.5 * thickness_mm,
                half_first + 0.5 * thickness_mm,
            );
            reliefs.push(counter_clockwise(vec![
                crossing - along * h_along - across * h_across,
                crossing + along * h_along - across * h_across,
                crossing + along * h_along + across * h_across,
                crossing - along * h_along + across * h_across,
            ]));
        }
    }
    reliefs
}

/// [`union_loops`] less the `reliefs` (geo's boolean difference) that do not cut the part
/// in two, and those kept.
pub(crate) fn union_less_reliefs(polygons: &[Vec<Vec2>], reliefs: &[Vec<Vec2>]) -> (Vec<Vec<Vec2>>, Vec<Vec<Vec2>>) {
    use geo::{BooleanOps, LineString, MultiPolygon, Polygon};
    let shape = |p: &Vec<Vec2>| {
        let p = counter_clockwise(p.clone());
        Polygon::new(
            LineString::from(p.iter().map(|q| (q.x, q.y)).collect::<Vec<_>>()),
            vec![],
        )
    };
    let mut remaining: MultiPolygon = geo::unary_union(&polygons.iter().map(shape).collect::<Vec<_>>());
    let pieces = remaining.0.len();
    let mut kept = Vec::new();
    for relief in reliefs {
        let cut = remaining.difference(&MultiPolygon::new(vec![shape(relief)]));
        if cut.0.len() == pieces {
            remaining = cut;
            kept.push(relief.clone());
        }
    }
    (polygon_loops(&remaining), kept)
}

/// The loops of geo polygons: outlines counter-clockwise, holes clockwise, holes under
/// [`MIN_HOLE_MM`] across left out.
fn polygon_loops(shapes: &geo::MultiPolygon) -> Vec<Vec<Vec2>> {
    use crate::material_allowance::ring_loop;
    let mut loops = Vec::new();
    for polygon in shapes {
        loops.push(ring_loop(polygon.exterior(), true));
        for hole in polygon.interiors() {
            let hole = ring_loop(hole, false);
            let (lo, hi) = crate::point_bounds(&hole);
            // Specks left where several trimmed corners meet: closed (a slit, however
            // narrow, is long and stays a cut).
            if (hi - lo).norm() >= MIN_HOLE_MM {
                loops.push(hole);
            }
        }
    }
    loops
}

/// The union of counter-clockwise polygons as cut loops: outlines counter-clockwise,
/// holes clockwise (geo's boolean union), holes under [`MIN_HOLE_MM`] across left out.
pub(crate) fn union_loops(polygons: &[Vec<Vec2>]) -> Vec<Vec<Vec2>> {
    use geo::{LineString, Polygon};
    let shapes: Vec<Polygon> = polygons
        .iter()
        .map(|p| {
            let p = counter_clockwise(p.clone());
            Polygon::new(
                LineString::from(p.iter().map(|q| (q.x, q.y)).collect::<Vec<_>>()),
                vec![],
            )
        })
        .collect();
    polygon_loops(&geo::unary_union(&shapes))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A zone whose bend line runs from `a` to `b`, `width` wide (allowance), no setback.
    fn zone(a: Vec2, b: Vec2, width: f64) -> BendZone {
        let d = (b - a).normalize();
        let across = Vec2::new(-d.y, d.x);
        BendZone {
            part: 0,
            a: a - across * (0.5 * width),
            b: b - across * (0.5 * width),
            across,
            bend: BendGeometry {
                setback_mm: 0.0,
                allowance_mm: width,
            },
            signed_angle: std::f64::consts::FRAC_PI_2,
        }
    }

    /// Issue 34: the two bend zones of a box's base meeting at its corner on the outline
    /// get one square relief, centred where their bend lines cross, reaching half the
    /// thickness past both tangent lines; zones crossing in their middles, or meeting
    /// away from the outline, get none.
    #[test]
    fn bend_zones_meeting_at_a_corner_of_the_outline_get_a_square_relief() {
        let v = Vec2::new;
        let (width, thickness) = (4.0, 1.0);
        // Bend lines along x = 0 (upwards) and y = 0 (rightwards), both starting at the
        // origin, the outline's corner.
        let (up, right) = (
            zone(v(0.0, 0.0), v(0.0, 50.0), width),
            zone(v(0.0, 0.0), v(60.0, 0.0), width),
        );
        let outline = vec![vec![v(-2.0, -2.0), v(60.0, -2.0), v(60.0, 50.0), v(-2.0, 50.0)]];
        let reliefs = corner_reliefs(&[&up, &right], thickness, &outline);
        assert_eq!(reliefs.len(), 1);
        let (lo, hi) = crate::point_bounds(&reliefs[0]);
        for k in 0..2 {
            assert!(
                (lo[k] + 2.5).abs() < 1e-12 && (hi[k] - 2.5).abs() < 1e-12,
                "{lo:?} {hi:?}"
            );
        }
        // Crossing in the middle of both: an X of folds, no corner.
        let (x1, x2) = (
            zone(v(-30.0, 0.0), v(30.0, 0.0), width),
            zone(v(0.0, -30.0), v(0.0, 30.0), width),
        );
        let around = vec![vec![v(-40.0, -40.0), v(40.0, -40.0), v(40.0, 40.0), v(-40.0, 40.0)]];
        assert!(corner_reliefs(&[&x1, &x2], thickness, &around).is_empty());
        // Meeting at their ends, but inside the part (an inner vertex of a net).
        assert!(corner_reliefs(&[&up, &right], thickness, &around).is_empty());
    }

    #[test]
    fn freecad_sheet_metal_worked_example() {
        // FreeCAD SheetMetal's README: T = 2, K = 0.38 (ANSI), R = 1.64, 90°; a flange of
        // 51.76 mm to the outer mold line has a 48.12 mm flat leg, the bend line 50 mm from
        // its end.
        let sheet = BendAllowance {
            thickness_mm: 2.0,
            inner_radius_mm: 1.64,
            k_factor: 0.38,
            material_side: MaterialSide::Behind,
        };
        let bend = sheet.bend(std::f64::consts::FRAC_PI_2); // a mountain: the model outside
        assert!((51.76 - bend.setback_mm - 48.12).abs() < 1e-12);
        let bend_line = 51.76 - bend.setback_mm + 0.5 * bend.allowance_mm;
        assert!((bend_line - 50.0).abs() < 0.01, "{bend_line}");
        // Seen from the other side the model is the inside of the bend: setback R·tan 45°.
        let valley = sheet.bend(-std::f64::consts::FRAC_PI_2);
        assert!((valley.setback_mm - 1.64).abs() < 1e-12);
        assert_eq!(valley.allowance_mm, bend.allowance_mm);
        let middle = BendAllowance {
            material_side: MaterialSide::Centred,
            ..sheet
        };
        assert!((middle.bend(0.3).setback_mm - 2.64 * 0.15f64.tan()).abs() < 1e-12);
    }

    #[test]
    fn a_thin_sheet_bent_gently_keeps_its_mid_surface_length() {
        // K = ½, model centred, no radius: the flat change is T/2·(A − 2 tan(A/2)) → 0 to
        // third order in A.
        let sheet = BendAllowance {
            thickness_mm: 1.0,
            inner_radius_mm: 0.0,
            k_factor: 0.5,
            material_side: MaterialSide::Centred,
        };
        let small = sheet.bend(1e-2).flat_change_mm();
        assert!(small.abs() < 1e-6, "{small}");
    }

    #[test]
    fn figures_are_bounded() {
        let ok = BendAllowance::default();
        assert!(ok.validate().is_ok());
        for bad in [
            BendAllowance {
                thickness_mm: 0.0,
                ..ok
            },
            BendAllowance {
                thickness_mm: f64::NAN,
                ..ok
            },
            BendAllowance {
                inner_radius_mm: -1.0,
                ..ok
            },
            BendAllowance { k_factor: 1.5, ..ok },
        ] {
            assert!(bad.validate().is_err(), "{bad:?}");
        }
    }

    #[test]
    fn half_plane_clip_of_a_square() {
        let square = [
            Vec2::new(0.0, 0.0),
            Vec2::new(2.0, 0.0),
            Vec2::new(2.0, 2.0),
            Vec2::new(0.0, 2.0),
        ];
        let kept = clip_half_plane(&square, Vec2::new(1.5, 0.0), Vec2::new(1.0, 0.0));
        assert!((sheetform_geometry::signed_area(&kept) - 3.0).abs() < 1e-12);
    }
}
