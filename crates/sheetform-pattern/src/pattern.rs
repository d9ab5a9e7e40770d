use crate::bend_allowance::{corner_reliefs, lay_out_bends, union_less_reliefs, union_loops, BentLayout};
use crate::glue_tabs::{add_glue_tabs, TabOptions, TabReport};
use crate::label_placement::{place_labels, LabelRequest, LabelSpot};
use crate::material_allowance::{add_kerf, add_seam_allowance, MaterialAllowance};
use crate::seam_matching::{match_seams, SeamRun};
use crate::sheet_packing::{pack_pieces, SheetOptions};
use crate::{PatternError, Vec2};
use rustc_hash::{FxHashMap as HashMap, FxHashSet};
use sheetform_geometry::{refused_number, short_number};
use sheetform_mesh::{signed_fold_angle, SheetMesh};

/// How a fold line is folded, seen from the pattern's printed side (the side the mesh's
/// face normals point to).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum FoldStyle {
    /// The crease points towards the viewer (a ridge).
    Mountain,
    /// The crease points away from the viewer (a trough).
    Valley,
    /// A bending guide (a ruling of a smoothly bent sheet; score lightly or just mark).
    Guide,
    /// The base of a glue tab (folded back under the neighbouring piece).
    TabBase,
    /// The design outline inside a seam allowance: where to sew or glue.
    Stitch,
    /// A notch: a short cut into the seam allowance that matches the pieces.
    Notch,
    /// The grain line: how to lay the piece on the fabric's straight grain.
    Grain,
}

/// A fold or score line.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fold {
    /// Start (mm).
    pub a: Vec2,
    /// End (mm).
    pub b: Vec2,
    /// Mountain, valley, guide or tab base.
    pub style: FoldStyle,
    /// Dihedral fold angle (degrees, unsigned; 0 for guides and tab bases).
    pub angle_degrees: f64,
}

/// What a label marks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LabelKind {
    /// The piece's name.
    Piece,
    /// A seam's ID, printed on both pieces it joins.
    Seam,
}

/// A text on the pattern.
#[derive(Debug, Clone, PartialEq)]
pub struct Label {
    /// Anchor (mm), the text's centre.
    pub position: Vec2,
    /// The text.
    pub text: String,
    /// Text height (mm).
    pub height_mm: f64,
    /// Direction of the text baseline (radians from +x).
    pub angle_radians: f64,
    /// Piece name or seam ID.
    pub kind: LabelKind,
}

/// One part to cut out: a connected piece of the flat pattern.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PatternPiece {
    /// Name (the mesh pieces it holds).
    pub name: String,
    /// The mesh pieces it holds (indices into the mesh's pieces, in order of their first
    /// face): what the editor lights up in 3D when the piece is pointed at.
    pub mesh_pieces: Vec<u32>,
    /// Closed loops to cut (outline counter-clockwise, holes clockwise), glue tabs included.
    pub cut: Vec<Vec<Vec2>>,
    /// Fold and score lines.
    pub folds: Vec<Fold>,
    /// Labels.
    pub labels: Vec<Label>,
    /// Sheet the piece is packed on (0 without packing).
    pub sheet: usize,
    /// Where the piece has been moved since the pattern was made (packing turns and
    /// moves pieces): the rigid motion from the pattern's first layout to the piece's
    /// place now, which is where its part of the texture goes.
    pub placement: Placement,
}

/// A rigid motion of the plane, `p ↦ R p + t` with `R = [[a, c], [b, d]]` (column-major,
/// as SVG's and PDF's `matrix(a, b, c, d, e, f)`) and `t = (e, f)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement(pub [f64; 6]);

impl Default for Placement {
    fn default() -> Self {
        Placement([1.0, 0.0, 0.0, 1.0, 0.0, 0.0])
    }
}

impl Placement {
    /// The motion applied to a point.
    pub fn apply(&self, p: Vec2) -> Vec2 {
        let [a, b, c, d, e, f] = self.0;
        Vec2::new(a * p.x + c * p.y + e, b * p.x + d * p.y + f)
    }

    /// This motion followed by the rigid map `g` (read off from three points).
    pub fn then(&self, g: impl Fn(Vec2) -> Vec2) -> Placement {
        let o = g(self.apply(Vec2::zeros()));
        let x = g(self.apply(Vec2::new(1.0, 0.0))) - o;
        let y = g(self.apply(Vec2::new(0.0, 1.0))) - o;
        Placement([x.x, x.y, y.x, y.y, o.x, o.y])
    }
}

/// An image printed on the sheet (a texture of `bend`), stretched over a rectangle of the
/// pattern's first layout.
#[derive(Debug, Clone, PartialEq)]
pub struct PatternTexture {
    /// The encoded image (PNG or JPEG).
    pub bytes: Vec<u8>,
    /// `image/png` or `image/jpeg`.
    pub mime_type: String,
    /// Lower-left corner of the image on the pattern (mm, first layout).
    pub origin: Vec2,
    /// Width and height the image covers (mm).
    pub size: Vec2,
}

/// A cutting pattern in millimetres at print scale.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Pattern {
    /// The pieces.
    pub pieces: Vec<PatternPiece>,
    /// Sheets as `(lower-left corner, size)` in the drawing (mm), when packed.
    pub sheets: Vec<(Vec2, Vec2)>,
    /// Seams: pairs of boundary stretches glued together, with matching IDs.
    pub seam_count: usize,
    /// Glue tabs placed and dropped.
    pub tabs: TabReport,
    /// Labels printed smaller than asked so that they fit inside their piece off every
    /// line.
    pub labels_shrunk: usize,
    /// Labels left out: nowhere in their piece was free of lines and other labels.
    pub labels_dropped: usize,
    /// An image printed on the pieces (each piece shows its part, moved with it).
    pub texture: Option<PatternTexture>,
    /// With a bend allowance: how much longer the pattern grew across each bend than the
    /// zero-thickness development (mm; negative: a bend deduction).
    pub bend_flat_changes_mm: Vec<f64>,
    /// With a bend allowance: corner reliefs cut where two bend zones meet.
    pub corner_relief_count: usize,
}

/// Knobs of [`pattern_from_mesh`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PatternOptions {
    /// Scale factor applied to the pattern (1 = true size).
    pub scale: f64,
    /// At most this many rulings per piece as fold guides (evenly chosen).
    pub max_rulings_per_piece: usize,
    /// Folds whose dihedral angle is below this (degrees) are not drawn.
    pub min_fold_angle_degrees: f64,
    /// Print matching IDs on both sides of every seam.
    pub seam_labels: bool,
    /// Glue tabs along seams (`None`: no tabs).
    pub tabs: Option<TabOptions>,
    /// Pack the pieces onto sheets of this size (`None`: keep the mesh's flat layout).
    pub sheet: Option<SheetOptions>,
    /// Seam allowance, notches, grain lines, kerf.
    pub allowance: MaterialAllowance,
    /// Which model axis points up (the grain lines follow it).
    pub up_axis: sheetform_mesh::UpAxis,
    /// Folds under this dihedral angle (degrees) are the bends of a smooth surface, not
    /// folds to crease: drawn as bending guides, thinned like rulings. 0 (the default):
    /// every fold over `min_fold_angle_degrees` is a mountain or valley fold (nets, where
    /// every edge is creased).
    pub smooth_bend_degrees: f64,
}

impl Default for PatternOptions {
    fn default() -> Self {
        Self {
            scale: 1.0,
            max_rulings_per_piece: 60,
            min_fold_angle_degrees: 1.0,
            seam_labels: true,
            tabs: None,
            sheet: None,
            allowance: MaterialAllowance::default(),
            up_axis: sheetform_mesh::UpAxis::Z,
            smooth_bend_degrees: 0.0,
        }
    }
}

impl Pattern {
    /// Axis-aligned bounds `(min, max)` over the cut loops and sheets.
    pub fn bounds(&self) -> (Vec2, Vec2) {
        let corners: Vec<Vec2> = self.sheets.iter().flat_map(|(o, size)| [*o, o + size]).collect();
        point_bounds(self.cut_loops().flatten().chain(&corners))
    }

    /// Every cut loop of every piece.
    pub fn cut_loops(&self) -> impl Iterator<Item = &Vec<Vec2>> {
        self.pieces.iter().flat_map(|p| p.cut.iter())
    }

    /// Every fold of every piece.
    pub fn folds(&self) -> impl Iterator<Item = &Fold> {
        self.pieces.iter().flat_map(|p| p.folds.iter())
    }

    /// Every label of every piece.
    pub fn labels(&self) -> impl Iterator<Item = &Label> {
        self.pieces.iter().flat_map(|p| p.labels.iter())
    }

    /// Seams whose ID is printed on both copies: the seam IDs (1 to `seam_count`) that
    /// appear on exactly two seam labels, counted from the labels drawn.
    pub fn seams_labelled_on_both_sides(&self) -> usize {
        let mut printed: HashMap<&str, usize> = HashMap::default();
        for label in self.labels().filter(|l| l.kind == LabelKind::Seam) {
            *printed.entry(label.text.as_str()).or_default() += 1;
        }
        (1..=self.seam_count)
            .filter(|id| printed.get(id.to_string().as_str()) == Some(&2))
            .count()
    }

    /// The pieces on sheet `sheet`, moved so that the sheet's corner is the origin, with
    /// that sheet alone (for one cutter file per sheet). This looks at every piece: for
    /// all sheets, [`Pattern::sheet_patterns`] sorts the pieces out in one pass.
    pub fn sheet_pattern(&self, sheet: usize) -> Pattern {
        let pieces = self.pieces.iter().filter(|p| p.sheet == sheet).collect();
        self.with_sheet_pieces(sheet, pieces, true)
    }

    /// [`Pattern::sheet_pattern`] of every sheet in order, in one pass over the pieces
    /// (pieces on no sheet of the list are left out).
    pub fn sheet_patterns(&self) -> Vec<Pattern> {
        self.split_into_sheets(true)
    }

    /// The sheets' patterns, with or without (a copy of) the texture and the bend
    /// changes each (without: only what is drawn, for the PDF, which embeds the texture
    /// once).
    pub(crate) fn split_into_sheets(&self, whole: bool) -> Vec<Pattern> {
        let mut on_sheet: Vec<Vec<&PatternPiece>> = vec![Vec::new(); self.sheets.len()];
        for p in &self.pieces {
            if let Some(list) = on_sheet.get_mut(p.sheet) {
                list.push(p);
            }
        }
        on_sheet
            .into_iter()
            .enumerate()
            .map(|(sheet, pieces)| self.with_sheet_pieces(sheet, pieces, whole))
            .collect()
    }

    /// The pattern of sheet `sheet` made of `pieces` (those on it), with the texture and
    /// the bend changes when `whole`.
    fn with_sheet_pieces(&self, sheet: usize, pieces: Vec<&PatternPiece>, whole: bool) -> Pattern {
        let (origin, size) = self
            .sheets
            .get(sheet)
            .copied()
            .unwrap_or((Vec2::zeros(), Vec2::zeros()));
        Pattern {
            pieces: pieces.into_iter().map(|p| p.translated(-origin)).collect(),
            sheets: vec![(Vec2::zeros(), size)],
            seam_count: self.seam_count,
            tabs: self.tabs,
            labels_shrunk: self.labels_shrunk,
            labels_dropped: self.labels_dropped,
            texture: if whole { self.texture.clone() } else { None },
            bend_flat_changes_mm: if whole {
                self.bend_flat_changes_mm.clone()
            } else {
                Vec::new()
            },
            corner_relief_count: self.corner_relief_count,
        }
    }
}

impl PatternPiece {
    /// The piece moved by `offset`.
    pub fn translated(&self, offset: Vec2) -> PatternPiece {
        self.transformed(|p| p + offset, 0.0)
    }

    /// The piece mapped point by point by `f` (a rigid motion turning by `turn` radians).
    pub fn transformed(&self, f: impl Fn(Vec2) -> Vec2, turn: f64) -> PatternPiece {
        PatternPiece {
            name: self.name.clone(),
            mesh_pieces: self.mesh_pieces.clone(),
            cut: self.cut.iter().map(|l| l.iter().map(|&p| f(p)).collect()).collect(),
            folds: self
                .folds
                .iter()
                .map(|x| Fold {
                    a: f(x.a),
                    b: f(x.b),
                    ..*x
                })
                .collect(),
            labels: self
                .labels
                .iter()
                .map(|l| Label {
                    position: f(l.position),
                    angle_radians: upright(l.angle_radians + turn),
                    ..l.clone()
                })
                .collect(),
            sheet: self.sheet,
            placement: self.placement.then(&f),
        }
    }

    /// Axis-aligned bounds of the cut loops.
    pub fn bounds(&self) -> (Vec2, Vec2) {
        point_bounds(self.cut.iter().flatten())
    }
}

/// A text direction turned by half a turn if needed so that the text reads upright:
/// within (−90°, 90°] of +x.
pub(crate) fn upright(angle: f64) -> f64 {
    use std::f64::consts::{FRAC_PI_2, PI, TAU};
    let a = (angle + PI).rem_euclid(TAU) - PI;
    if a > FRAC_PI_2 {
        a - PI
    } else if a <= -FRAC_PI_2 {
        a + PI
    } else {
        a
    }
}

/// Axis-aligned bounds `(min, max)` of points (infinite, inverted, when there are none).
pub fn point_bounds<'a>(points: impl IntoIterator<Item = &'a Vec2>) -> (Vec2, Vec2) {
    points.into_iter().fold(
        (Vec2::repeat(f64::INFINITY), Vec2::repeat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.inf(p), hi.sup(p)),
    )
}

/// The pattern of a mesh in millimetres (`mesh.unit`) times `options.scale`: one piece per
/// connected part of the flat pattern with its boundary loops to cut; folds from the
/// signed dihedral angle of every interior edge (mountain / valley, those below
/// `options.min_fold_angle_degrees` hidden) and the rulings as bending guides; piece
/// names; matching IDs on both sides of every seam (boundary edges that meet another
/// boundary edge in 3D); optional glue tabs; optional packing onto sheets.
///
/// # Errors
/// A scale that is not a positive finite number; bad tab or sheet options; a piece larger
/// than the sheet (named).
pub fn pattern_from_mesh(mesh: &SheetMesh, options: &PatternOptions) -> Result<Pattern, PatternError> {
    if !(options.scale.is_finite() && options.scale > 0.0) {
        return Err(PatternError::Option {
            option: "scale",
            message: format!("must be a positive number, got {}", short_number(options.scale)),
        });
    }
    if !(options.smooth_bend_degrees.is_finite() && (0.0..=180.0).contains(&options.smooth_bend_degrees)) {
        return Err(PatternError::Option {
            option: "smooth_bend_degrees",
            message: format!(
                "must be between 0 and 180 degrees, got {}",
                refused_number(options.smooth_bend_degrees, &[0.0, 180.0])
            ),
        });
    }
    if !(options.min_fold_angle_degrees.is_finite() && options.min_fold_angle_degrees >= 0.0) {
        return Err(PatternError::Option {
            option: "min_fold_angle_degrees",
            message: format!(
                "must be a non-negative number, got {}",
                short_number(options.min_fold_angle_degrees)
            ),
        });
    }
    options.allowance.validate()?;
    if options.allowance.bend.is_some() && options.tabs.is_some() {
        return Err(PatternError::Option {
            option: "tabs",
            message: "glue tabs are for paper: a sheet with thickness is joined edge to edge (welded, riveted, glued with a strip); leave out the tabs or the thickness".into(),
        });
    }
    if options.allowance.seam_allowance_mm > 0.0 && options.tabs.is_some() {
        return Err(PatternError::Option {
            option: "seam_allowance_mm",
            message: "a seam allowance and glue tabs both add material along the seams: choose one".into(),
        });
    }
    let k = mesh.unit.millimetres() * options.scale;
    let at = |v: u32| mesh.flat[v as usize] * k;

    // Connected parts of the flat pattern (by shared vertices of faces).
    let nv = mesh.flat.len();
    let mut parent: Vec<u32> = (0..nv as u32).collect();
    fn find(parent: &mut [u32], mut x: u32) -> u32 {
        while parent[x as usize] != x {
            parent[x as usize] = parent[parent[x as usize] as usize];
            x = parent[x as usize];
        }
        x
    }
    for t in &mesh.triangles {
        for k in 1..3 {
            let (a, b) = (find(&mut parent, t[0]), find(&mut parent, t[k]));
            parent[a as usize] = b;
        }
    }
    let mut part_of_root: HashMap<u32, usize> = HashMap::default();
    let mut face_part = Vec::with_capacity(mesh.triangles.len());
    for t in &mesh.triangles {
        let root = find(&mut parent, t[0]);
        let next = part_of_root.len();
        face_part.push(*part_of_root.entry(root).or_insert(next));
    }
    let parts = part_of_root.len();
    let vertex_part = |v: u32, parent: &mut [u32]| part_of_root[&find(parent, v)];

    // Piece names: the mesh pieces each part holds.
    let mut names: Vec<Vec<String>> = vec![Vec::new(); parts];
    let mut held: Vec<Vec<u32>> = vec![Vec::new(); parts];
    for (f, &piece) in mesh.face_pieces.iter().enumerate() {
        if !held[face_part[f]].contains(&piece) {
            held[face_part[f]].push(piece);
        }
        let name = &mesh.pieces[piece as usize].name;
        if !names[face_part[f]].contains(name) {
            names[face_part[f]].push(name.clone());
        }
    }
    let mut pieces: Vec<PatternPiece> = names
        .iter()
        .zip(held)
        .map(|(n, mesh_pieces)| PatternPiece {
            name: if n.len() <= 3 {
                n.join(" + ")
            } else {
                format!("{} + {} more", n[..2].join(" + "), n.len() - 2)
            },
            mesh_pieces,
            cut: Vec::new(),
            folds: Vec::new(),
            labels: Vec::new(),
            sheet: 0,
            placement: Placement::default(),
        })
        .collect();

    // Cut loops, as vertex cycles kept for seams and tabs.
    let loops = mesh.boundary_loops();
    let mut loop_part = Vec::with_capacity(loops.len());
    for l in &loops {
        loop_part.push(vertex_part(l[0], &mut parent));
    }

    // Folds: interior edges by dihedral sign; ruling edges are guides.
    let mut ruling_edge: FxHashSet<[u32; 2]> = FxHashSet::default();
    let key = |a: u32, b: u32| if a < b { [a, b] } else { [b, a] };
    for r in &mesh.rulings {
        for w in r.vertices.windows(2) {
            ruling_edge.insert(key(w[0], w[1]));
        }
    }
    // Smooth edges (between the rulings of a strip) are no folds either.
    for e in &mesh.smooth_edges {
        ruling_edge.insert(key(e[0], e[1]));
    }
    let table = mesh.edge_table();
    let min_fold = options.min_fold_angle_degrees.to_radians();
    let mut fold_edges: Vec<([u32; 2], f64)> = (0..table.len())
        .filter_map(|k| match table.sides(k) {
            [f, g] if !ruling_edge.contains(&table.edges[k]) => Some((&table.edges[k], f.face, g.face)),
            _ => None,
        })
        .filter_map(|(e, f, g)| {
            let t = mesh.triangles[f as usize];
            // The edge as the first face runs it, and that face's third vertex.
            let j = (0..3).find(|&j| key(t[j], t[(j + 1) % 3]) == *e)?;
            let (a, b, c) = (t[j], t[(j + 1) % 3], t[(j + 2) % 3]);
            let d = *mesh.triangles[g as usize].iter().find(|&&v| v != a && v != b)?;
            let angle = signed_fold_angle([a, b, c, d].map(|v| mesh.positions[v as usize]));
            (angle.abs() >= min_fold.max(1e-9)).then_some((*e, angle))
        })
        .collect();
    fold_edges.sort_by_key(|x| x.0);
    // Bends of a smooth surface (folds under `smooth_bend_degrees`) are bending guides,
    // thinned to `max_rulings_per_piece` per piece; the rest mountain or valley folds.
    let smooth = options.smooth_bend_degrees.to_radians();
    let (creased, smooth_lines): (Vec<_>, Vec<_>) = merge_collinear_folds(&fold_edges, at)
        .into_iter()
        .partition(|(_, angle)| angle.abs() >= smooth);
    // With a sheet thickness, the creased folds become bend zones and the panels between
    // them move apart or together by each bend's flat change.
    let bent: Option<BentLayout> = match &options.allowance.bend {
        Some(bend) => {
            let names: Vec<String> = pieces.iter().map(|p| p.name.clone()).collect();
            Some(lay_out_bends(mesh, &table, &at, &face_part, &names, &creased, bend)?)
        }
        None => None,
    };
    // A bent part's outline: the union of its flanges and bend zones, less the corner
    // reliefs where two of its bend zones meet on it (those that leave it whole).
    type Loops = Vec<Vec<Vec2>>;
    let (bent_loops, part_reliefs): (Vec<Loops>, Vec<Loops>) =
        bent.as_ref().map_or((Vec::new(), Vec::new()), |layout| {
            let thickness = options.allowance.bend.map_or(0.0, |b| b.thickness_mm);
            layout
                .part_polygons
                .iter()
                .enumerate()
                .map(|(part, polygons)| {
                    let zones: Vec<_> = layout.zones.iter().filter(|z| z.part == part).collect();
                    let outline = union_loops(polygons);
                    let reliefs = corner_reliefs(&zones, thickness, &outline);
                    let (loops, kept) = union_less_reliefs(polygons, &reliefs);
                    (loops.into_iter().map(without_collinear_points).collect(), kept)
                })
                .unzip()
        });
    let moved = |f: u32| bent.as_ref().map_or(Vec2::zeros(), |l| l.face_offset[f as usize]);
    // How far the face along edge `a b` moved (a boundary or fold edge's face).
    let edge_moved = |a: u32, b: u32| table.faces_of(a, b).next().map_or(Vec2::zeros(), moved);
    let mut bends: Vec<Vec<Fold>> = vec![Vec::new(); pieces.len()];
    for (chain, _) in &smooth_lines {
        let (a, b) = (chain[0], *chain.last().expect("a chain has two ends"));
        let o = edge_moved(chain[0], chain[1]);
        bends[vertex_part(a, &mut parent)].push(Fold {
            a: at(a) + o,
            b: at(b) + o,
            style: FoldStyle::Guide,
            angle_degrees: 0.0,
        });
    }
    let fold_style = |angle: f64| {
        if angle > 0.0 {
            FoldStyle::Mountain
        } else {
            FoldStyle::Valley
        }
    };
    match &bent {
        Some(layout) => {
            // The bend line in the middle of each bend zone, its tangent lines as guides,
            // each drawn where material is left (not across a corner relief).
            for zone in &layout.zones {
                let reliefs = &part_reliefs[zone.part];
                let (a, b) = zone.centre_line();
                for (a, b) in outside_polygons(a, b, reliefs) {
                    pieces[zone.part].folds.push(Fold {
                        a,
                        b,
                        style: fold_style(zone.signed_angle),
                        angle_degrees: zone.signed_angle.abs().to_degrees(),
                    });
                }
                for (a, b) in zone.tangent_lines() {
                    for (a, b) in outside_polygons(a, b, reliefs) {
                        pieces[zone.part].folds.push(Fold {
                            a,
                            b,
                            style: FoldStyle::Guide,
                            angle_degrees: 0.0,
                        });
                    }
                }
            }
        }
        None => {
            for (chain, angle) in &creased {
                let (a, b) = (chain[0], *chain.last().expect("a chain has two ends"));
                pieces[vertex_part(a, &mut parent)].folds.push(Fold {
                    a: at(a),
                    b: at(b),
                    style: fold_style(*angle),
                    angle_degrees: angle.abs().to_degrees(),
                });
            }
        }
    }
    for (piece, guides) in pieces.iter_mut().zip(bends) {
        let step = guides.len().div_ceil(options.max_rulings_per_piece.max(1)).max(1);
        let last = guides.len().saturating_sub(1);
        piece.folds.extend(
            guides
                .into_iter()
                .enumerate()
                .filter(|(i, _)| i % step == 0 || *i == last)
                .map(|(_, g)| g),
        );
    }
    for piece in 0..mesh.pieces.len() {
        let rulings: Vec<_> = mesh.rulings.iter().filter(|r| r.piece as usize == piece).collect();
        let step = rulings.len().div_ceil(options.max_rulings_per_piece.max(1)).max(1);
        for (i, r) in rulings.iter().enumerate() {
            if i % step == 0 || i + 1 == rulings.len() {
                let (a, b) = (r.vertices[0], *r.vertices.last().expect("ruling has vertices"));
                let o = r.vertices.get(1).map_or(Vec2::zeros(), |&next| edge_moved(a, next));
                pieces[vertex_part(a, &mut parent)].folds.push(Fold {
                    a: at(a) + o,
                    b: at(b) + o,
                    style: FoldStyle::Guide,
                    angle_degrees: 0.0,
                });
            }
        }
    }

    if options.allowance.grain_lines {
        for (part, grain) in grain_lines(mesh, &face_part, &at, k, options.up_axis) {
            pieces[part].folds.push(grain);
        }
    }

    // Piece names: spots at the centroids of each mesh piece's largest triangles.
    let label_height = 4.0;
    let mut requests: Vec<LabelRequest> = Vec::new();
    let mut by_piece: Vec<Vec<(f64, Vec2, usize)>> = vec![Vec::new(); mesh.pieces.len()];
    for (f, t) in mesh.triangles.iter().enumerate() {
        let [a, b, c] = t.map(at);
        let area = ((b - a).x * (c - a).y - (b - a).y * (c - a).x).abs();
        by_piece[mesh.face_pieces[f] as usize].push((area, (a + b + c) / 3.0 + moved(f as u32), f));
    }
    for (p, piece) in mesh.pieces.iter().enumerate() {
        let spots = &mut by_piece[p];
        spots.sort_by(|x, y| y.0.total_cmp(&x.0));
        let Some(&(_, _, f)) = spots.first() else { continue };
        // The largest triangles' centroids first, then a grid over the piece from its
        // area centroid outwards (for pieces of narrow faces, where the open room lies
        // across several faces).
        let total: f64 = spots.iter().map(|x| x.0).sum();
        let centre = spots.iter().map(|x| x.1 * x.0).sum::<Vec2>() / total.max(f64::MIN_POSITIVE);
        let (lo, hi) = point_bounds(spots.iter().map(|x| &x.1));
        let mut grid: Vec<Vec2> = (0..NAME_GRID * NAME_GRID)
            .map(|i| {
                let (u, v) = ((i % NAME_GRID) as f64 + 0.5, (i / NAME_GRID) as f64 + 0.5);
                lo + (hi - lo).component_mul(&Vec2::new(u, v)) / NAME_GRID as f64
            })
            .collect();
        grid.sort_by(|a, b| (a - centre).norm().total_cmp(&(b - centre).norm()));
        let points: Vec<Vec2> = spots.iter().take(MAX_LABEL_SPOTS).map(|x| x.1).chain(grid).collect();
        // Level first; then along the piece's longest fold (a name fits between the folds
        // of a faceted tube running with them), then upright.
        let along_fold = pieces[face_part[f]]
            .folds
            .iter()
            .max_by(|a, b| (a.b - a.a).norm().total_cmp(&(b.b - b.a).norm()))
            .map(|fold| upright((fold.b - fold.a).y.atan2((fold.b - fold.a).x)));
        let directions = [Some(0.0), along_fold, Some(std::f64::consts::FRAC_PI_2)];
        requests.push(LabelRequest {
            piece: face_part[f],
            text: piece.name.clone(),
            kind: LabelKind::Piece,
            anchor: Vec::new(),
            height_mm: label_height,
            spots: directions
                .into_iter()
                .flatten()
                .flat_map(|direction| {
                    points.iter().map(move |&point| LabelSpot {
                        point,
                        inward: Vec2::zeros(),
                        direction,
                    })
                })
                .collect(),
        });
    }

    // Seams: boundary stretches that meet in 3D, with matching IDs; spots along the run
    // from its middle edge outwards, the text along the edge inside the piece.
    let runs: Vec<SeamRun> = match_seams(mesh, &loops, 1e-9 * mesh_scale(mesh));
    let seam_count = runs.iter().map(|r| r.seam + 1).max().unwrap_or(0);
    if options.seam_labels {
        let seam_height = 3.0;
        for r in &runs {
            let l = &loops[r.loop_index];
            let middle = r.edges / 2;
            let mut spots = Vec::new();
            for step in 0..r.edges.min(MAX_LABEL_SPOTS) {
                // 0, +1, −1, +2, −2, … from the middle edge.
                let offset = (step as isize + 1) / 2 * if step % 2 == 1 { 1 } else { -1 };
                let k = middle as isize + offset;
                if k < 0 || k >= r.edges as isize {
                    continue;
                }
                let i = r.start + k as usize;
                let o = edge_moved(l[i % l.len()], l[(i + 1) % l.len()]);
                let (a, b) = (at(l[i % l.len()]) + o, at(l[(i + 1) % l.len()]) + o);
                let d = b - a;
                if d.norm() == 0.0 {
                    continue;
                }
                let inward = Vec2::new(-d.y, d.x).normalize();
                let fractions: &[f64] = if step == 0 { &[0.5, 0.3, 0.7] } else { &[0.5] };
                for &t in fractions {
                    spots.push(LabelSpot {
                        point: a + d * t,
                        inward,
                        direction: d.y.atan2(d.x),
                    });
                }
            }
            // Then the same spots further in, for edges at tight corners.
            let deeper: Vec<LabelSpot> = [1.5, 3.0]
                .iter()
                .flat_map(|&depth| {
                    spots.iter().map(move |s| LabelSpot {
                        point: s.point + s.inward * depth * seam_height,
                        ..*s
                    })
                })
                .collect();
            spots.extend(deeper);
            // The run's edges as drawn: the ID goes where they are the nearest cut line.
            let anchor = (r.start..r.start + r.edges)
                .map(|i| {
                    let (a, b) = (l[i % l.len()], l[(i + 1) % l.len()]);
                    let o = edge_moved(a, b);
                    (at(a) + o, at(b) + o)
                })
                .collect();
            requests.push(LabelRequest {
                piece: loop_part[r.loop_index],
                text: format!("{}", r.seam + 1),
                kind: LabelKind::Seam,
                height_mm: seam_height,
                spots,
                anchor,
            });
        }
    }

    // Labels placed against the pieces' own outlines and folds (tabs lie outside).
    let mut loop_points: Vec<Vec<Vec2>> = loops.iter().map(|l| l.iter().map(|&v| at(v)).collect()).collect();
    let bent_part = |part: usize| bent.as_ref().is_some_and(|l| !l.part_polygons[part].is_empty());
    for (i, points) in loop_points.iter().enumerate() {
        if !bent_part(loop_part[i]) {
            pieces[loop_part[i]].cut.push(points.clone());
        }
    }
    let relief_count = part_reliefs.iter().map(Vec::len).sum();
    for (part, loops) in bent_loops.iter().enumerate() {
        if bent_part(part) {
            pieces[part].cut = loops.clone();
        }
    }
    // Each part's bounds before any bend moved it (only needed with bends).
    let mut original_bounds = vec![point_bounds(&[]); if bent.is_some() { pieces.len() } else { 0 }];
    for (points, &part) in loop_points.iter().zip(&loop_part).filter(|_| bent.is_some()) {
        let (lo, hi) = point_bounds(points);
        let bounds = &mut original_bounds[part];
        *bounds = (bounds.0.inf(&lo), bounds.1.sup(&hi));
    }
    // Seam IDs first (they belong at their edge), names where room is left.
    requests.sort_by_key(|r| r.kind == LabelKind::Piece);
    let placement = place_labels(&mut pieces, &requests);
    for piece in &mut pieces {
        piece.cut.clear();
    }

    // Cut loops, then tabs on them.
    let mut tabs = TabReport::default();
    let mut tab_folds: Vec<Vec<Fold>> = vec![Vec::new(); loops.len()];
    if let Some(tab_options) = &options.tabs {
        let (new_loops, folds, report) = add_glue_tabs(&loop_points, &runs, tab_options)?;
        loop_points = new_loops;
        tab_folds = folds;
        tabs = report;
    }
    for (i, points) in loop_points.into_iter().enumerate() {
        if !bent_part(loop_part[i]) {
            pieces[loop_part[i]].cut.push(without_collinear_points(points));
            pieces[loop_part[i]].folds.append(&mut tab_folds[i]);
        }
    }
    for (part, loops) in bent_loops.into_iter().enumerate() {
        if bent_part(part) {
            pieces[part].cut = loops;
        }
    }
    if bent.is_some() && options.sheet.is_none() {
        separate_grown_pieces(&mut pieces, &original_bounds);
    }

    // Material allowances: the seam allowance (notches at both ends and the middle of
    // every seam run), then the kerf.
    let allowance = options.allowance;
    if allowance.seam_allowance_mm > 0.0 {
        let mut notches: Vec<Vec<(Vec2, Vec2)>> = vec![Vec::new(); pieces.len()];
        if allowance.notches {
            for r in &runs {
                let l = &loops[r.loop_index];
                let n = l.len();
                // Both ends (outward: right of the counter-clockwise loop, averaged over the
                // two edges there) and the point halfway along the run.
                for i in [r.start, r.start + r.edges] {
                    let (prev, here, next) = (at(l[(i + n - 1) % n]), at(l[i % n]), at(l[(i + 1) % n]));
                    let d = (here - prev).normalize() + (next - here).normalize();
                    if d.norm() > 1e-9 {
                        notches[loop_part[r.loop_index]].push((here, Vec2::new(d.y, -d.x).normalize()));
                    }
                }
                let edge = |j: usize| (at(l[(r.start + j) % n]), at(l[(r.start + j + 1) % n]));
                let total: f64 = (0..r.edges).map(|j| (edge(j).1 - edge(j).0).norm()).sum();
                let mut walked = 0.0;
                for j in 0..r.edges {
                    let (a, b) = edge(j);
                    let length = (b - a).norm();
                    if walked + length >= 0.5 * total && length > 0.0 {
                        let t = (0.5 * total - walked) / length;
                        let d = (b - a) / length;
                        notches[loop_part[r.loop_index]].push((a + (b - a) * t, Vec2::new(d.y, -d.x)));
                        break;
                    }
                    walked += length;
                }
            }
        }
        for (piece, points) in pieces.iter_mut().zip(&notches) {
            add_seam_allowance(piece, allowance.seam_allowance_mm, points)?;
        }
    }
    if allowance.kerf_mm > 0.0 {
        for piece in &mut pieces {
            add_kerf(piece, allowance.kerf_mm)?;
        }
    }

    let mut pattern = Pattern {
        pieces,
        sheets: Vec::new(),
        seam_count,
        tabs,
        labels_shrunk: placement.shrunk,
        labels_dropped: placement.dropped,
        texture: None,
        bend_flat_changes_mm: bent.map_or(Vec::new(), |l| {
            l.zones.iter().map(|z| z.bend.flat_change_mm()).collect()
        }),
        corner_relief_count: relief_count,
    };
    if let Some(sheet) = &options.sheet {
        pack_pieces(&mut pattern, sheet)?;
    }
    Ok(pattern)
}

/// The parts of the segment `a b` outside every convex polygon of `polygons`
/// (counter-clockwise): each polygon's inside cut from it (Cyrus–Beck), what is left in
/// order.
fn outside_polygons(a: Vec2, b: Vec2, polygons: &[Vec<Vec2>]) -> Vec<(Vec2, Vec2)> {
    let d = b - a;
    // Parameter intervals of the segment inside each polygon.
    let mut inside: Vec<(f64, f64)> = polygons
        .iter()
        .filter_map(|polygon| {
            let (mut t0, mut t1) = (0.0f64, 1.0f64);
            let n = polygon.len();
            for i in 0..n {
                let (p, q) = (polygon[i], polygon[(i + 1) % n]);
                // Inside: left of every edge, cross(q − p, x − p) ≥ 0.
                let e = q - p;
                let (at_a, rate) = (e.x * (a - p).y - e.y * (a - p).x, e.x * d.y - e.y * d.x);
                if rate == 0.0 {
                    if at_a < 0.0 {
                        return None;
                    }
                } else if rate > 0.0 {
                    t0 = t0.max(-at_a / rate);
                } else {
                    t1 = t1.min(-at_a / rate);
                }
            }
            (t0 < t1).then_some((t0, t1))
        })
        .collect();
    inside.sort_by(|x, y| x.0.total_cmp(&y.0));
    let mut parts = Vec::new();
    let mut from = 0.0;
    for (t0, t1) in inside {
        if t0 > from {
            parts.push((a + d * from, a + d * t0));
        }
        from = from.max(t1);
    }
    if from < 1.0 {
        parts.push((a + d * from, b));
    }
    parts
}

/// Pieces that a bend allowance made grow into each other's bounding rectangles (where
/// their rectangles did not meet before) moved right until they are clear, in order of
/// their left edges.
fn separate_grown_pieces(pieces: &mut [PatternPiece], before: &[(Vec2, Vec2)]) {
    let meets =
        |a: &(Vec2, Vec2), b: &(Vec2, Vec2)| a.0.x <= b.1.x && b.0.x <= a.1.x && a.0.y <= b.1.y && b.0.y <= a.1.y;
    let mut order: Vec<usize> = (0..pieces.len()).collect();
    order.sort_by(|&i, &j| before[i].0.x.total_cmp(&before[j].0.x));
    let mut placed: Vec<usize> = Vec::new();
    for &i in &order {
        for _ in 0..pieces.len() {
            let here = pieces[i].bounds();
            let Some(&j) = placed
                .iter()
                .find(|&&j| meets(&here, &pieces[j].bounds()) && !meets(&before[i], &before[j]))
            else {
                break;
            };
            let gap = 0.02 * (here.1 - here.0).norm().max(1.0);
            let shift = Vec2::new(pieces[j].bounds().1.x + gap - here.0.x, 0.0);
            pieces[i] = pieces[i].translated(shift);
        }
        placed.push(i);
    }
}

/// Fold edges `([a, b], signed angle)` joined into straight lines: at a vertex where
/// exactly two fold edges meet, run on in a straight line (within `1e-9` of their length)
/// and fold the same way by the same angle (within 0.5°), they become one line. Returns
/// each line's vertex chain and its mean signed angle (radians).
fn merge_collinear_folds(edges: &[([u32; 2], f64)], at: impl Fn(u32) -> Vec2) -> Vec<(Vec<u32>, f64)> {
    let mut at_vertex: HashMap<u32, Vec<usize>> = HashMap::default();
    for (i, ([a, b], _)) in edges.iter().enumerate() {
        at_vertex.entry(*a).or_default().push(i);
        at_vertex.entry(*b).or_default().push(i);
    }
    let other = |i: usize, v: u32| {
        if edges[i].0[0] == v {
            edges[i].0[1]
        } else {
            edges[i].0[0]
        }
    };
    // The edge continuing edge `i` straight on through its end `v`, if any.
    let continues = |i: usize, v: u32| -> Option<usize> {
        let here = &at_vertex[&v];
        let [x, y] = here.as_slice() else { return None };
        let j = if *x == i { *y } else { *x };
        let (p, q, r) = (at(other(i, v)), at(v), at(other(j, v)));
        let (d1, d2) = (q - p, r - q);
        let straight = (d1.x * d2.y - d1.y * d2.x).abs() <= 1e-9 * d1.norm() * d2.norm() && d1.dot(&d2) > 0.0;
        let same = (edges[i].1 - edges[j].1).abs() <= 0.5f64.to_radians() && edges[i].1.signum() == edges[j].1.signum();
        (straight && same).then_some(j)
    };
    let mut used = vec![false; edges.len()];
    let mut lines = Vec::new();
    for start in 0..edges.len() {
        if used[start] {
            continue;
        }
        // Walk back to one end of the line, then forward along it.
        let (mut i, mut v) = (start, edges[start].0[0]);
        let mut steps = 0;
        while let Some(j) = continues(i, v) {
            if j == start || steps > edges.len() {
                break;
            }
            v = other(j, v);
            i = j;
            steps += 1;
        }
        // `i` is the end edge, `v` its free end: walk forward.
        let mut chain = vec![v];
        let mut angles = 0.0;
        let mut count = 0;
        loop {
            used[i] = true;
            angles += edges[i].1;
            count += 1;
            v = other(i, v);
            chain.push(v);
            match continues(i, v) {
                Some(j) if !used[j] => i = j,
                _ => break,
            }
        }
        lines.push((chain, angles / count as f64));
    }
    lines
}

/// A closed loop without the points that lie on the straight line through their
/// neighbours (within `1e-9` of the neighbours' distance): the same outline, fewer points.
fn without_collinear_points(points: Vec<Vec2>) -> Vec<Vec2> {
    let n = points.len();
    if n <= 3 {
        return points;
    }
    let mut kept: Vec<Vec2> = Vec::with_capacity(n);
    for i in 0..n {
        let p = points[i];
        let previous = *kept.last().unwrap_or(&points[n - 1]);
        let next = points[(i + 1) % n];
        let (d1, d2) = (p - previous, next - p);
        let collinear =
            (d1.x * d2.y - d1.y * d2.x).abs() <= 1e-9 * (next - previous).norm_squared() && d1.dot(&d2) > 0.0;
        if !collinear {
            kept.push(p);
        }
    }
    if kept.len() < 3 {
        points
    } else {
        kept
    }
}

/// The grain line of every mesh piece on the pattern part holding it: the flat direction
/// of steepest ascent of the model's height (its `up` coordinate; the area-weighted mean
/// over the piece's faces of the gradient of the height, linear on each flat triangle),
/// drawn through the piece's area centroid over 40 % of its extent that way (shortened
/// to 20 % or 10 % when it would leave the piece, left out when even that does), with
/// arrow heads; a piece whose mean slope is under 0.2 (lying nearly level) gets none.
/// `k` is pattern millimetres per model unit.
fn grain_lines(
    mesh: &SheetMesh,
    face_part: &[usize],
    at: &impl Fn(u32) -> Vec2,
    k: f64,
    up: sheetform_mesh::UpAxis,
) -> Vec<(usize, Fold)> {
    let height = |v: u32| {
        let p = mesh.positions[v as usize];
        match up {
            sheetform_mesh::UpAxis::Z => p.z,
            sheetform_mesh::UpAxis::Y => p.y,
        }
    };
    let mut faces_of: Vec<Vec<usize>> = vec![Vec::new(); mesh.pieces.len()];
    for (f, &p) in mesh.face_pieces.iter().enumerate() {
        faces_of[p as usize].push(f);
    }
    let mut out = Vec::new();
    for faces in &faces_of {
        let Some(&first) = faces.first() else { continue };
        let part = face_part[first];
        let (mut gradient, mut centre, mut area) = (Vec2::zeros(), Vec2::zeros(), 0.0);
        let triangles: Vec<[Vec2; 3]> = faces.iter().map(|&f| mesh.triangles[f].map(at)).collect();
        for (&f, &[a, b, c]) in faces.iter().zip(&triangles) {
            let [za, zb, zc] = mesh.triangles[f].map(height);
            let (e1, e2) = (b - a, c - a);
            let det = e1.x * e2.y - e1.y * e2.x;
            if det.abs() <= f64::MIN_POSITIVE {
                continue;
            }
            // Solve [e1ᵀ; e2ᵀ] g = [zb − za; zc − za] (model units per pattern mm).
            let (r1, r2) = (zb - za, zc - za);
            let g = Vec2::new(r1 * e2.y - r2 * e1.y, e1.x * r2 - e2.x * r1) / det;
            let weight = 0.5 * det.abs();
            gradient += g * weight;
            centre += (a + b + c) / 3.0 * weight;
            area += weight;
        }
        if area <= 0.0 {
            continue;
        }
        let (g, centre) = (gradient / area, centre / area);
        // The slope in the model: height per length along the piece (k pattern mm per
        // model unit, the print scale included).
        if g.norm() * k < 0.2 {
            continue;
        }
        let d = g.normalize();
        let extent = triangles
            .iter()
            .flatten()
            .map(|q| (q - centre).dot(&d))
            .fold(0.0f64, |m, x| m.max(x.abs()));
        // Closed triangles (edges included: the centre of a piece often lies on an edge
        // between two of its faces, where the even–odd `rings_contain` may say neither).
        let on_piece = |p: Vec2| {
            triangles.iter().any(|&[a, b, c]| {
                let s = |u: Vec2, v: Vec2| sheetform_geometry::cross2(v - u, p - u);
                let (x, y, z) = (s(a, b), s(b, c), s(c, a));
                (x >= 0.0 && y >= 0.0 && z >= 0.0) || (x <= 0.0 && y <= 0.0 && z <= 0.0)
            })
        };
        let Some(half) = [0.4, 0.2, 0.1]
            .into_iter()
            .map(|f| f * extent)
            .find(|&h| on_piece(centre) && on_piece(centre - d * h) && on_piece(centre + d * h))
        else {
            continue;
        };
        let (a, b) = (centre - d * half, centre + d * half);
        out.push((
            part,
            Fold {
                a,
                b,
                style: FoldStyle::Grain,
                angle_degrees: 0.0,
            },
        ));
        // Arrow heads at both ends.
        let head = (0.1 * half).clamp(2.0, 8.0);
        let side = Vec2::new(-d.y, d.x);
        for (tip, back) in [(b, -d), (a, d)] {
            for s in [1.0, -1.0] {
                out.push((
                    part,
                    Fold {
                        a: tip,
                        b: tip + (back + side * s * 0.5) * head,
                        style: FoldStyle::Grain,
                        angle_degrees: 0.0,
                    },
                ));
            }
        }
    }
    out
}

/// Spots tried per label (the largest triangles for a name, edges along the seam for an
/// ID).
const MAX_LABEL_SPOTS: usize = 24;
/// Grid of further spots for a piece name (per side).
const NAME_GRID: usize = 12;

/// Largest extent of the mesh's 3D bounding box (for tolerances).
fn mesh_scale(mesh: &SheetMesh) -> f64 {
    let (lo, hi) = mesh.bounds();
    (hi - lo).amax().max(f64::MIN_POSITIVE)
}

#[cfg(test)]
mod tests {
    use super::*;
    type Vec3 = nalgebra::Vector3<f64>;

    /// Two unit squares hinged along the x axis, the second one turned by `angle`
    /// (radians, positive = down, away from the +z normals): a mountain.
    fn roof(angle: f64) -> SheetMesh {
        let (s, c) = angle.sin_cos();
        let positions = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, -c, -s),
            Vec3::new(1.0, -c, -s),
        ];
        let flat = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0), (0.0, -1.0), (1.0, -1.0)]
            .map(|(x, y)| Vec2::new(x, y))
            .to_vec();
        one_piece(
            "roof",
            positions,
            flat,
            vec![[0, 1, 2], [0, 2, 3], [4, 5, 1], [4, 1, 0]],
            sheetform_mesh::LengthUnit::Cm,
        )
    }

    /// A sheet mesh of one chart piece.
    fn one_piece(
        name: &str,
        positions: Vec<Vec3>,
        flat: Vec<Vec2>,
        triangles: Vec<[u32; 3]>,
        unit: sheetform_mesh::LengthUnit,
    ) -> SheetMesh {
        SheetMesh {
            positions,
            flat,
            face_pieces: vec![0; triangles.len()],
            triangles,
            pieces: vec![sheetform_mesh::Piece {
                name: name.into(),
                kind: sheetform_mesh::PieceKind::Chart,
            }],
            rulings: vec![],
            smooth_edges: vec![],
            unit,
        }
    }

    #[test]
    fn a_bracket_with_thickness_unfolds_as_sheet_metal_tools_do() {
        // FreeCAD SheetMetal's worked example: 2 mm sheet, K = 0.38, inner radius 1.64 mm,
        // a 90° bend, flanges 51.76 mm to the outer mold line (the roof's 10 mm squares
        // scaled up): each flat leg 48.12 mm, the bend zone π/2·(1.64 + 0.38·2) long.
        let sheet = crate::BendAllowance {
            thickness_mm: 2.0,
            inner_radius_mm: 1.64,
            k_factor: 0.38,
            material_side: crate::MaterialSide::Behind,
        };
        let options = PatternOptions {
            scale: 5.176,
            allowance: MaterialAllowance {
                bend: Some(sheet),
                ..Default::default()
            },
            seam_labels: false,
            ..Default::default()
        };
        let allowance = std::f64::consts::FRAC_PI_2 * (1.64 + 0.38 * 2.0);
        for (angle, setback) in [(90.0f64, 3.64), (-90.0, 1.64)] {
            let pattern = pattern_from_mesh(&roof(angle.to_radians()), &options).unwrap();
            assert_eq!(pattern.pieces.len(), 1);
            let piece = &pattern.pieces[0];
            assert_eq!(piece.cut.len(), 1, "{:?}", piece.cut);
            let (lo, hi) = piece.bounds();
            let length = 2.0 * (51.76 - setback) + allowance;
            assert!(((hi.y - lo.y) - length).abs() < 1e-6, "{} vs {length}", hi.y - lo.y);
            assert!(((hi.x - lo.x) - 51.76).abs() < 1e-6);
            let area: f64 = piece.cut.iter().map(|l| sheetform_geometry::signed_area(l)).sum();
            assert!((area - 51.76 * length).abs() < 1e-3, "{area}");
            // The bend line in the middle of the zone: 50.00 mm from the end of the leg
            // for the mountain fold (the model outside the bend); two tangent lines.
            let fold = piece
                .folds
                .iter()
                .find(|f| matches!(f.style, FoldStyle::Mountain | FoldStyle::Valley))
                .unwrap();
            assert_eq!(fold.style == FoldStyle::Mountain, angle > 0.0);
            assert!((fold.a.y - fold.b.y).abs() < 1e-9 && (fold.angle_degrees - 90.0).abs() < 1e-9);
            let from_end = hi.y - fold.a.y;
            assert!((from_end - (51.76 - setback + 0.5 * allowance)).abs() < 1e-6);
            if angle > 0.0 {
                assert!((from_end - 50.0).abs() < 0.01, "{from_end}");
            }
            assert_eq!(piece.folds.iter().filter(|f| f.style == FoldStyle::Guide).count(), 2);
            assert_eq!(pattern.bend_flat_changes_mm.len(), 1);
            assert!((pattern.bend_flat_changes_mm[0] - (allowance - 2.0 * setback)).abs() < 1e-9);
        }
        // A seam allowance and a thickness do not go together.
        let both = PatternOptions {
            allowance: MaterialAllowance {
                seam_allowance_mm: 5.0,
                bend: Some(sheet),
                ..Default::default()
            },
            ..options
        };
        assert!(pattern_from_mesh(&roof(1.0), &both).is_err());
        // A 10 mm flange cannot take a bend whose setback is 20 mm: refused, not dropped.
        let thick = PatternOptions {
            allowance: MaterialAllowance {
                bend: Some(crate::BendAllowance {
                    thickness_mm: 10.0,
                    inner_radius_mm: 10.0,
                    ..sheet
                }),
                ..Default::default()
            },
            ..Default::default()
        };
        let error = pattern_from_mesh(&roof(90f64.to_radians()), &thick)
            .unwrap_err()
            .to_string();
        assert!(error.contains("narrower than the setbacks"), "{error}");
    }

    /// A Miura-ori vertex: four creases around an inner vertex, sector angles α, π − α,
    /// π − α, α (flat-foldable), rigidly folded so that the straight crease pair makes an
    /// angle of π − 2γ; side `length`.
    fn miura_vertex(alpha: f64, gamma: f64, length: f64) -> SheetMesh {
        // Symmetric about the xz-plane: r1, r3 in it, r2 and r4 mirror images with
        // r1·r2 = cos α, r3·r2 = −cos α, which puts r2 in the xy-plane.
        let a = alpha.cos() / gamma.cos();
        let b = (1.0 - a * a).sqrt();
        let rays3 = [
            Vec3::new(gamma.cos(), 0.0, gamma.sin()),
            Vec3::new(a, b, 0.0),
            Vec3::new(-gamma.cos(), 0.0, gamma.sin()),
            Vec3::new(a, -b, 0.0),
        ];
        let angles = [0.0, alpha, std::f64::consts::PI, std::f64::consts::TAU - alpha];
        let mut positions = vec![Vec3::zeros()];
        positions.extend(rays3.iter().map(|r| r * length));
        let mut flat = vec![Vec2::zeros()];
        flat.extend(angles.iter().map(|t| Vec2::new(t.cos(), t.sin()) * length));
        one_piece(
            "vertex",
            positions,
            flat,
            vec![[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 1]],
            sheetform_mesh::LengthUnit::Mm,
        )
    }

    #[test]
    fn folds_all_round_an_inner_vertex_cannot_take_a_thickness() {
        let mesh = miura_vertex(60f64.to_radians(), 20f64.to_radians(), 50.0);
        // The model is isometric to its flat layout.
        for t in &mesh.triangles {
            for k in 0..3 {
                let (i, j) = (t[k] as usize, t[(k + 1) % 3] as usize);
                let d3 = (mesh.positions[i] - mesh.positions[j]).norm();
                let d2 = (mesh.flat[i] - mesh.flat[j]).norm();
                assert!((d3 - d2).abs() < 1e-12);
            }
        }
        // Paper folds it (four creases, Maekawa: mountains and valleys differ by two).
        let paper = pattern_from_mesh(&mesh, &PatternOptions::default()).unwrap();
        let count = |style| paper.folds().filter(|f| f.style == style).count() as i64;
        assert_eq!(count(FoldStyle::Mountain) + count(FoldStyle::Valley), 4);
        assert_eq!((count(FoldStyle::Mountain) - count(FoldStyle::Valley)).abs(), 2);
        // With a thickness the flanges round the vertex cannot all keep their bend
        // allowances: a clear error naming the piece and the place.
        let options = PatternOptions {
            allowance: MaterialAllowance {
                bend: Some(crate::BendAllowance::default()),
                ..Default::default()
            },
            ..Default::default()
        };
        let error = pattern_from_mesh(&mesh, &options).unwrap_err();
        assert!(matches!(error, PatternError::BendLoop { .. }), "{error}");
        assert!(error.to_string().contains("`vertex`"), "{error}");
    }

    #[test]
    fn folds_are_mountain_or_valley_by_sign_and_small_ones_hidden() {
        let count = |mesh: &SheetMesh, min: f64, style: FoldStyle| {
            let options = PatternOptions {
                min_fold_angle_degrees: min,
                ..Default::default()
            };
            pattern_from_mesh(mesh, &options)
                .unwrap()
                .folds()
                .filter(|f| f.style == style)
                .count()
        };
        let down = roof(40f64.to_radians());
        let up = roof(-40f64.to_radians());
        assert_eq!(count(&down, 1.0, FoldStyle::Mountain), 1);
        assert_eq!(count(&down, 1.0, FoldStyle::Valley), 0);
        assert_eq!(count(&up, 1.0, FoldStyle::Valley), 1);
        assert_eq!(count(&up, 1.0, FoldStyle::Mountain), 0);
        // Hidden below the threshold; the flat diagonals are never folds.
        assert_eq!(count(&down, 45.0, FoldStyle::Mountain), 0);
        let pattern = pattern_from_mesh(&down, &PatternOptions::default()).unwrap();
        let fold = pattern.folds().next().unwrap();
        assert!((fold.angle_degrees - 40.0).abs() < 1e-9);
        // Centimetres to millimetres: the hinge is 10 mm long on the pattern.
        assert!(((fold.b - fold.a).norm() - 10.0).abs() < 1e-12);
        // A smooth edge (between the rulings of a bent strip) is neither fold nor guide.
        let smooth = SheetMesh {
            smooth_edges: vec![[0, 1]],
            ..down.clone()
        };
        let pattern = pattern_from_mesh(&smooth, &PatternOptions::default()).unwrap();
        assert_eq!(pattern.folds().count(), 0);
    }

    #[test]
    fn seams_found_in_3d_get_one_id_on_both_sides_and_tabs_outside() {
        // The roof cut along its hinge: two pieces whose hinge edges meet in 3D.
        let mut mesh = roof(30f64.to_radians());
        mesh.positions.extend([mesh.positions[0], mesh.positions[1]]);
        mesh.flat.extend([Vec2::new(0.0, -1.5), Vec2::new(1.0, -1.5)]);
        mesh.flat[4] = Vec2::new(0.0, -2.5);
        mesh.flat[5] = Vec2::new(1.0, -2.5);
        mesh.triangles[2] = [4, 5, 7];
        mesh.triangles[3] = [4, 7, 6];
        let options = PatternOptions {
            tabs: Some(TabOptions {
                width_mm: 2.0,
                ..Default::default()
            }),
            ..Default::default()
        };
        let pattern = pattern_from_mesh(&mesh, &options).unwrap();
        assert_eq!(pattern.pieces.len(), 2);
        assert_eq!(pattern.seam_count, 1);
        let ids: Vec<&str> = pattern
            .labels()
            .filter(|l| l.kind == LabelKind::Seam)
            .map(|l| l.text.as_str())
            .collect();
        assert_eq!(ids, ["1", "1"]);
        assert_eq!(pattern.tabs.placed, 1);
        // The tab adds a 2 mm deep trapezoid (45°, 10 mm base) to one piece's outline.
        let areas: Vec<f64> = pattern
            .cut_loops()
            .map(|l| {
                0.5 * (0..l.len())
                    .map(|i| {
                        let (a, b) = (l[i], l[(i + 1) % l.len()]);
                        a.x * b.y - b.x * a.y
                    })
                    .sum::<f64>()
            })
            .collect();
        let tab_area = 0.5 * (10.0 + 6.0) * 2.0;
        let mut sorted = areas.clone();
        sorted.sort_by(f64::total_cmp);
        assert!(
            (sorted[0] - 100.0).abs() < 1e-9 && (sorted[1] - 100.0 - tab_area).abs() < 1e-9,
            "{areas:?}"
        );
        assert!(pattern.folds().any(|f| f.style == FoldStyle::TabBase));
    }

    #[test]
    fn collinear_folds_merge_into_one_line_and_collinear_cut_points_go() {
        // Five vertices on the x axis, then a turn up: edges 0-1-2-3 straight, same angle;
        // 3-4 a different angle; 2-5 a branch (three edges meet at 2: no merge there).
        let points = [(0.0, 0.0), (1.0, 0.0), (2.0, 0.0), (3.0, 0.0), (4.0, 0.0), (2.0, 1.0)];
        let at = |v: u32| Vec2::new(points[v as usize].0, points[v as usize].1);
        let a = 0.5;
        let lines = merge_collinear_folds(&[([0, 1], a), ([1, 2], a), ([2, 3], a), ([3, 4], -a)], at);
        // Each line from its lower end.
        let mut chains: Vec<Vec<u32>> = lines
            .iter()
            .map(|l| {
                let mut c = l.0.clone();
                if c[0] > c[c.len() - 1] {
                    c.reverse();
                }
                c
            })
            .collect();
        chains.sort();
        assert_eq!(chains, vec![vec![0, 1, 2, 3], vec![3, 4]]);
        let merged = lines.iter().find(|l| l.0.len() == 4).unwrap();
        assert!((merged.1 - a).abs() < 1e-15);
        let branched = merge_collinear_folds(&[([0, 1], a), ([1, 2], a), ([2, 3], a), ([2, 5], a)], at);
        assert_eq!(branched.len(), 3);
        // A square with points along its sides keeps its four corners.
        let square: Vec<Vec2> = [
            (0.0, 0.0),
            (0.5, 0.0),
            (1.0, 0.0),
            (1.0, 0.5),
            (1.0, 1.0),
            (0.0, 1.0),
            (0.0, 0.5),
        ]
        .iter()
        .map(|&(x, y)| Vec2::new(x, y))
        .collect();
        assert_eq!(without_collinear_points(square).len(), 4);
    }

    /// A standing panel, 100 wide (x) and 300 tall (z), laid flat turned by `turn`: its
    /// grain line must run along the flat image of +z, through the panel, for either up
    /// axis stated the same way.
    #[test]
    fn the_grain_line_runs_up_the_model_on_the_flat_piece() {
        let turn = 0.7f64;
        let rotate = |x: f64, y: f64| Vec2::new(turn.cos() * x - turn.sin() * y, turn.sin() * x + turn.cos() * y);
        let corners = [(0.0, 0.0), (100.0, 0.0), (100.0, 300.0), (0.0, 300.0)];
        for up in [sheetform_mesh::UpAxis::Z, sheetform_mesh::UpAxis::Y] {
            let positions = corners
                .iter()
                .map(|&(x, h)| match up {
                    sheetform_mesh::UpAxis::Z => Vec3::new(x, 0.0, h),
                    sheetform_mesh::UpAxis::Y => Vec3::new(x, h, 0.0),
                })
                .collect();
            let mesh = SheetMesh {
                positions,
                flat: corners.iter().map(|&(x, h)| rotate(x, h)).collect(),
                triangles: vec![[0, 1, 2], [0, 2, 3]],
                face_pieces: vec![0, 0],
                pieces: vec![sheetform_mesh::Piece {
                    name: "panel".into(),
                    kind: sheetform_mesh::PieceKind::Chart,
                }],
                rulings: vec![],
                smooth_edges: vec![],
                unit: sheetform_mesh::LengthUnit::Mm,
            };
            let options = PatternOptions {
                allowance: MaterialAllowance {
                    grain_lines: true,
                    ..Default::default()
                },
                up_axis: up,
                ..Default::default()
            };
            let pattern = pattern_from_mesh(&mesh, &options).unwrap();
            let grain: Vec<&Fold> = pattern.folds().filter(|f| f.style == FoldStyle::Grain).collect();
            assert_eq!(grain.len(), 5, "a shaft and four arrow-head strokes");
            let shaft = grain
                .iter()
                .max_by(|a, b| (a.b - a.a).norm().total_cmp(&(b.b - b.a).norm()))
                .unwrap();
            let along = (shaft.b - shaft.a).normalize();
            let up_flat = rotate(0.0, 1.0);
            assert!((along - up_flat).norm() < 1e-9, "{along:?} vs {up_flat:?}");
            // 40 % of the half height either side of the centre (150 mm up the panel).
            assert!(((shaft.b - shaft.a).norm() - 0.8 * 150.0).abs() < 1e-9);
            assert!(((shaft.a + shaft.b) * 0.5 - rotate(50.0, 150.0)).norm() < 1e-9);
        }
        // Lying level (a flat panel in the xy plane, z up): no grain line.
        let mut level = roof(0.0);
        level.positions.iter_mut().for_each(|p| p.z = 0.0);
        let options = PatternOptions {
            allowance: MaterialAllowance {
                grain_lines: true,
                ..Default::default()
            },
            ..Default::default()
        };
        let pattern = pattern_from_mesh(&level, &options).unwrap();
        assert_eq!(pattern.folds().filter(|f| f.style == FoldStyle::Grain).count(), 0);
    }

    #[test]
    fn a_piece_placement_follows_every_motion_applied_to_the_piece() {
        let piece = PatternPiece {
            name: "p".into(),
            mesh_pieces: vec![],
            cut: vec![vec![Vec2::new(0.0, 0.0), Vec2::new(2.0, 0.0), Vec2::new(0.0, 1.0)]],
            folds: vec![],
            labels: vec![],
            sheet: 0,
            placement: Placement::default(),
        };
        let turn = |a: f64, t: Vec2| {
            move |p: Vec2| Vec2::new(a.cos() * p.x - a.sin() * p.y, a.sin() * p.x + a.cos() * p.y) + t
        };
        let moved = piece
            .transformed(turn(0.4, Vec2::new(3.0, -1.0)), 0.4)
            .transformed(turn(-1.1, Vec2::new(-2.0, 5.0)), -1.1);
        // The placement maps the first layout onto where the piece is now.
        for (before, after) in piece.cut[0].iter().zip(&moved.cut[0]) {
            assert!((moved.placement.apply(*before) - after).norm() < 1e-12);
        }
    }

    #[test]
    fn bends_of_a_smooth_surface_are_guides_and_creases_stay_folds() {
        let options = PatternOptions {
            smooth_bend_degrees: 10.0,
            ..Default::default()
        };
        let count = |mesh: &SheetMesh, style: FoldStyle| {
            pattern_from_mesh(mesh, &options)
                .unwrap()
                .folds()
                .filter(|f| f.style == style)
                .count()
        };
        let gentle = roof(5f64.to_radians());
        assert_eq!(
            (count(&gentle, FoldStyle::Mountain), count(&gentle, FoldStyle::Guide)),
            (0, 1)
        );
        let crease = roof(40f64.to_radians());
        assert_eq!(
            (count(&crease, FoldStyle::Mountain), count(&crease, FoldStyle::Guide)),
            (1, 0)
        );
        let bad = PatternOptions {
            smooth_bend_degrees: f64::NAN,
            ..Default::default()
        };
        assert!(pattern_from_mesh(&crease, &bad)
            .unwrap_err()
            .to_string()
            .contains("smooth_bend_degrees"));
    }
}
