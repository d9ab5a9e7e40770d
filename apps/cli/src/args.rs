//! The command line: subcommands, their arguments and how they become the library's
//! options (clap).

use clap::{Parser, Subcommand};
use sheetform::pattern::{DxfUnit, PageSize, SheetOptions, TabOptions, TabSides};
use sheetform::pipeline::PatternOutputOptions;
use std::path::PathBuf;

#[derive(Parser)]
#[command(
    name = "sheetform",
    version,
    about = "Design with developable surfaces: bend a virtual sheet, get the 3D model and the flat pattern to cut"
)]
pub(crate) struct Cli {
    #[command(subcommand)]
    pub(crate) command: Command,
    /// No progress bar.
    #[arg(long, short, global = true)]
    pub(crate) quiet: bool,
    /// Let scenes read files (textures, scans, meshes, photos) anywhere inside this
    /// directory, by absolute paths or paths leaving the scene's directory; by default
    /// only files inside the scene's own directory are read.
    #[arg(long, global = true, value_name = "DIR")]
    pub(crate) assets_within: Option<PathBuf>,
}

#[derive(Subcommand)]
pub(crate) enum Command {
    /// Bend a sheet with 3D control curves (Bo & Wang): writes model.obj (vt = flat
    /// pattern at 1:1), model.glb, model.stl, pattern.svg and report.json.
    Bend {
        /// Scene file (JSON; schema: `sheetform schema bend`).
        scene: PathBuf,
        /// Output directory (created if missing).
        #[arg(short, long)]
        output: PathBuf,
        /// Also write N frames of the isometric deformation from flat to bent
        /// (frames/frame-0000.obj …).
        #[arg(long, value_name = "N", default_value_t = 0)]
        animate: usize,
        #[command(flatten)]
        pattern: PatternArgs,
    },
    /// Design furniture from one sheet with parallel slits (Tsuruta et al.): solves every
    /// strip, writes the full symmetric model (model.obj with vt = flat sheet at 1:1,
    /// model.glb, model.stl), the cutting pattern (pattern.svg/.dxf/.pdf: outline and
    /// slits to cut, ridge lines to fold or score), mould.stl and report.json.
    Slit {
        /// Scene file (JSON; schema: `sheetform schema slit`).
        scene: PathBuf,
        /// Output directory (created if missing).
        #[arg(short, long)]
        output: PathBuf,
        #[command(flatten)]
        pattern: PatternArgs,
    },
    /// Reconstruct a piecewise-developable object from curves traced over one photograph
    /// (Fondevilla et al.): writes the model (model.obj with one group per patch and vt =
    /// each patch's flat pattern at 1:1, model.glb with the photo projected onto it,
    /// model.stl), the pattern (pattern.svg/.dxf/.pdf), overlay.svg (patches, rulings,
    /// symmetric pairs and the reprojected 3D curves over the photo) and report.json.
    Photo {
        /// Annotation file (JSON; schema: `sheetform schema photo`).
        annotation: PathBuf,
        /// Output directory (created if missing).
        #[arg(short, long)]
        output: PathBuf,
        /// The side the photo does not show: `visible` makes only what the drawing shows;
        /// `revolve` closes every band round one axis (a cup, a lamp shade, a vase of
        /// cones and cylinders), cut open along a seam at the back, so that the pattern is
        /// the whole product. Default: the annotation's `back_side` (`visible`).
        #[arg(long, value_enum, value_name = "SIDE")]
        back_side: Option<BackSideArg>,
        #[command(flatten)]
        pattern: PatternArgs,
    },
    /// Deform developable panels with a NURBS lattice and restore their developability
    /// (Wang & Tang): writes the restored object (model.obj with one group per panel and
    /// vt = each panel's exact flat pattern at 1:1, model.glb, model.stl), the plain FFD
    /// (deformed.obj/.glb), developability colour maps before/after
    /// (developability-before/after.ply/.glb), the pattern (pattern.svg/.dxf/.pdf) and
    /// report.json.
    Ffd {
        /// Scene file (JSON; schema: `sheetform schema ffd`).
        scene: PathBuf,
        /// Output directory (created if missing).
        #[arg(short, long)]
        output: PathBuf,
        /// Restoration method (default: the scene's, which defaults to `constrained`).
        #[arg(long, value_enum)]
        solver: Option<SolverArg>,
        #[command(flatten)]
        pattern: PatternArgs,
    },
    /// Measure the developability of any triangle mesh (OBJ, PLY, STL, OFF): topology,
    /// angle defects, Gaussian curvature, `D[M]` and `G[X]`, the isometry error of the stored
    /// `vt` flattening. Writes report.json and a colour map (developability.ply/.glb).
    Check {
        /// Mesh file.
        mesh: PathBuf,
        /// Output directory (created if missing).
        #[arg(short, long)]
        output: PathBuf,
        /// Merge vertices closer than this distance (model units) before measuring.
        #[arg(long, value_name = "DISTANCE")]
        weld: Option<f64>,
        /// Angle defects up to this (radians) count as developable.
        #[arg(long, value_name = "RADIANS", default_value_t = sheetform::pipeline::DEFAULT_ANGLE_TOLERANCE)]
        tolerance: f64,
        /// Length unit of the mesh file.
        #[arg(long, value_enum, default_value_t = Unit::Mm)]
        units: Unit,
    },
    /// Flatten a developable (or nearly developable) mesh into its cutting pattern: a
    /// disk-like mesh whole (exact unfolding from its edge lengths, or LSCM / ARAP); a
    /// closed or high-genus mesh, or one with seams (OBJ `l` lines), cut into charts along
    /// sharp creases and split until each flattens without overlap within the distortion
    /// bound. Writes model.obj (vt = the pattern at 1:1), model.glb, pattern.svg/.dxf/.pdf
    /// and report.json (distortion per chart). Exit code 4 when the pattern overlaps
    /// itself (written, see the report).
    Flatten {
        /// Mesh file (OBJ, PLY, STL, OFF).
        mesh: PathBuf,
        /// Layout: `exact` unfolding from the edge lengths; for meshes that are only nearly
        /// developable `lscm` (least-squares conformal maps) or `arap` (as rigid as
        /// possible, started from LSCM).
        #[arg(long, value_enum, default_value_t = Method::Exact)]
        method: Method,
        /// Output directory (created if missing).
        #[arg(short, long)]
        output: PathBuf,
        /// Merge vertices closer than this distance (model units) first.
        #[arg(long, value_name = "DISTANCE")]
        weld: Option<f64>,
        /// Length unit of the mesh file.
        #[arg(long, value_enum, default_value_t = Unit::Mm)]
        units: Unit,
        /// The model's final height as printed (mm, along +y, the up axis of OBJ and
        /// glTF): the pattern is scaled to it, whatever the file's unit (instead of
        /// --scale).
        #[arg(long, value_name = "HEIGHT")]
        size: Option<f64>,
        #[command(flatten)]
        charts: ChartArgs,
        #[command(flatten)]
        pattern: PatternArgs,
    },
    /// Develop a target shape: the nearest surface made of exactly developable pieces.
    /// The target is cut into a few pieces that are each close to a cone, cylinder or
    /// plane (automatic seams, always including those drawn in the mesh as OBJ `l`
    /// polylines along its edges), each piece is moved as little as possible until every
    /// vertex inside it is flat, then unfolded exactly. Writes model.obj (the developed shape, vt = its pattern at 1:1),
    /// model.glb, pattern.svg/.dxf/.pdf, distance.ply/.glb (a colour map of each
    /// vertex's distance to the target) and report.json (`develop`: angle defects before
    /// and after, Hausdorff and mean distance to the target). Exit code 5 when a piece
    /// stays out of tolerance (written, see the report).
    Develop {
        /// Target mesh file (OBJ with `l` seam polylines, PLY, STL, OFF).
        mesh: PathBuf,
        /// Output directory (created if missing).
        #[arg(short, long)]
        output: PathBuf,
        /// Length unit of the mesh file.
        #[arg(long, value_enum, default_value_t = Unit::Mm)]
        units: Unit,
        /// The model's final height as printed (mm, along +y, the up axis of OBJ and
        /// glTF): the pattern is scaled to it, whatever the file's unit (instead of
        /// --scale).
        #[arg(long, value_name = "HEIGHT")]
        size: Option<f64>,
        /// Where to cut: `automatic` finds seams (the drawn ones among them), `drawn`
        /// cuts along the OBJ `l` polylines only.
        #[arg(long, value_enum, default_value_t = Seams::Automatic)]
        seams: Seams,
        /// Most pieces the automatic seams cut (pieces the drawn seams make count too). A
        /// developed piece that would overlap itself flat is printed cut in two, so the
        /// pattern may have more: the report counts them and warns.
        #[arg(long, value_name = "N", default_value_t = 12)]
        max_pieces: usize,
        /// Automatic seams: add pieces (up to --max-pieces) until every piece's normals
        /// are within this RMS angle of a cone, cylinder or plane (degrees).
        #[arg(long, value_name = "DEGREES", default_value_t = 2.0)]
        normal_tolerance: f64,
        /// Automatic seams: a vertex inside a piece whose angle defect is larger than
        /// this (degrees) is a cone point (a box's corner) and gets a slit to its piece's
        /// border instead of being flattened. Smaller values bring the pieces closer to
        /// the target, at the price of more slits and, where the slits make a piece
        /// overlap itself in the plane, more pieces.
        #[arg(long, value_name = "DEGREES", default_value_t = 60.0)]
        cone_angle: f64,
        /// The farthest the developed surface may be from the target (two-sided
        /// Hausdorff distance): a length in the mesh's units (`2`) or a percentage of its
        /// bounding-box diagonal (`0.5%`). With automatic seams, pieces are added (up to
        /// --max-pieces) until it holds; farther: exit 5, the closest result written.
        #[arg(long, value_name = "DISTANCE", value_parser = str::parse::<sheetform::pipeline::DistanceBound>)]
        max_distance: Option<sheetform::pipeline::DistanceBound>,
        /// Keep the faces of this mesh group (OBJ `g` name) where they are: their
        /// vertices do not move (repeat for more groups). A region that is not
        /// developable itself gets slits with automatic seams.
        #[arg(long, value_name = "GROUP")]
        fixed: Vec<String>,
        /// Most faces to work on: a finer target (a scan) is remeshed first into about
        /// this many even triangles, its boundary, drawn seams and --fixed groups kept
        /// as they are; the result has these faces and its distances are to the target
        /// as read. More faces: slower, not closer.
        #[arg(long, value_name = "N", default_value_t = sheetform::pipeline::DEFAULT_WORK_FACES)]
        work_faces: usize,
        /// Keep the result symmetric in a mirror plane: `x`, `y` or `z` (the plane of
        /// that normal through the middle of the mesh) or placed, `x=0`. The half with
        /// more area is developed and joined with its mirror image (no seam on the
        /// plane unless one is needed); pieces come in mirrored pairs.
        #[arg(long, value_name = "PLANE", value_parser = str::parse::<sheetform::pipeline::Mirror>)]
        mirror: Option<sheetform::pipeline::Mirror>,
        /// Automatic seams: sweeps that slide the seams found over the developed
        /// surface onto smooth curves, removing the staircase of mesh edges, before the
        /// pieces are made exact again (0: seams along the mesh's edges as found).
        #[arg(long, value_name = "SWEEPS", default_value_t = sheetform::pipeline::SeamSmoothingOptions::default().iterations)]
        seam_smoothing: usize,
        /// Smoothness against closeness: 0 moves each vertex as little as possible,
        /// larger values spread the change over its neighbours.
        #[arg(long, value_name = "WEIGHT", default_value_t = 0.1)]
        smoothness: f64,
        /// Largest angle defect accepted inside a piece (radians).
        #[arg(long, value_name = "RADIANS", default_value_t = 1e-10)]
        tolerance: f64,
        /// Most Gauss-Newton steps.
        #[arg(long, value_name = "N", default_value_t = 100)]
        max_iterations: usize,
        #[command(flatten)]
        pattern: PatternArgs,
    },
    /// Serve the web editor on this machine: bend a sheet live in the browser, on the
    /// same pipeline as `sheetform bend`; open and save the scene files of a directory.
    Serve {
        /// Interface to listen on (default: loopback only, 127.0.0.1). Give another
        /// explicitly to let other machines connect.
        #[arg(long)]
        host: Option<std::net::IpAddr>,
        /// Port (default: a free one, printed).
        #[arg(long, default_value_t = 0)]
        port: u16,
        /// Directory whose scene files the editor may open and save.
        #[arg(long, default_value = ".")]
        root: PathBuf,
        /// Open the editor in the default browser.
        #[arg(long)]
        open: bool,
    },
    /// Print the JSON Schema of a scene format.
    Schema {
        /// Which format.
        #[arg(value_enum)]
        format: SchemaFormat,
    },
}

/// How the printable pattern (pattern.svg, .dxf, .pdf) is written.
#[derive(clap::Args, Clone, Copy)]
pub(crate) struct PatternArgs {
    /// Scale factor for the pattern (1 = true size).
    #[arg(long, default_value_t = 1.0)]
    pub(crate) scale: f64,
    /// Paper for the tiled PDF.
    #[arg(long, value_enum, default_value_t = Page::A4)]
    pub(crate) page: Page,
    /// Unit of the DXF coordinates.
    #[arg(long, value_enum, default_value_t = PatternUnit::Mm)]
    pub(crate) pattern_units: PatternUnit,
    /// Folds with a smaller dihedral angle (degrees) are not drawn.
    #[arg(long, value_name = "DEGREES", default_value_t = 1.0)]
    pub(crate) min_fold_angle: f64,
    /// Leave out the seam IDs printed on both sides of every seam.
    #[arg(long)]
    pub(crate) no_seam_labels: bool,
    /// Glue tabs along seams: on one side of each seam, alternating between seams, or
    /// none; `auto`: on one side of each seam of a net (`flatten`) and of the pieces of
    /// `develop`, none otherwise.
    #[arg(long, value_enum, default_value_t = Tabs::Auto)]
    pub(crate) tabs: Tabs,
    /// Glue tab depth (mm).
    #[arg(long, value_name = "MM", default_value_t = 5.0)]
    pub(crate) tab_width: f64,
    /// Angle of the tabs' slanted sides (degrees; 90 = straight tabs).
    #[arg(long, value_name = "DEGREES", default_value_t = 45.0)]
    pub(crate) tab_angle: f64,
    /// Pack the pieces onto sheets of this size, `WIDTHxHEIGHT` in mm (e.g. 600x400 for a
    /// cutter's bed), or a4 / letter: the paper's printable area when it is the PDF's
    /// --page, so every sheet prints on one page; a net is cut into pieces that fit, with
    /// room for their tabs. Writes sheets/sheet-NN.svg and .dxf too.
    #[arg(long, value_name = "WxH", value_parser = parse_sheet)]
    pub(crate) sheet: Option<(f64, f64)>,
    /// Gap between packed pieces and from the sheet's edges (mm, at most 1000).
    #[arg(long, value_name = "MM", default_value_t = 5.0)]
    pub(crate) sheet_gap: f64,
    /// Most pages the PDF may print; a pattern that needs more is refused.
    #[arg(long, value_name = "PAGES", default_value_t = sheetform::pattern::DEFAULT_MAX_PAGES)]
    pub(crate) max_pages: usize,
    /// Seam allowance (mm) outside every piece for fabric or leather: the design outline
    /// becomes a stitch line, notches mark both ends and the middle of every seam.
    #[arg(long, value_name = "MM", default_value_t = 0.0)]
    pub(crate) seam_allowance: f64,
    /// Leave out the notches of a seam allowance.
    #[arg(long)]
    pub(crate) no_notches: bool,
    /// Laser kerf (mm): cut lines move out by half of it so parts keep their size.
    #[arg(long, value_name = "MM", default_value_t = 0.0)]
    pub(crate) kerf: f64,
    /// A grain line on every piece along the direction that runs up the model (+z).
    #[arg(long)]
    pub(crate) grain_lines: bool,
    /// Sheet thickness (mm) for sheet metal, greyboard or plywood: every mountain and
    /// valley fold becomes a bend zone of its flat length (K-factor rule, as FreeCAD
    /// SheetMetal unfolds), with the bend line in its middle.
    #[arg(long, value_name = "MM")]
    pub(crate) thickness: Option<f64>,
    /// Inner bend radius (mm) with --thickness (default: the thickness).
    #[arg(long, value_name = "MM", requires = "thickness")]
    pub(crate) bend_radius: Option<f64>,
    /// K-factor with --thickness (ANSI: where the neutral layer lies, 0 = inside of the
    /// bend, 1 = outside; the DIN factor is twice it).
    #[arg(long, value_name = "K", default_value_t = 0.44, requires = "thickness")]
    pub(crate) k_factor: f64,
    /// Where the thickness lies with --thickness: behind the model's surface (the model is
    /// the printed face, e.g. the outside of a closed model), centred on it, or in front.
    #[arg(long, value_enum, default_value_t = MaterialSideArg::Behind, requires = "thickness")]
    pub(crate) material_side: MaterialSideArg,
    /// Folds under this angle (degrees) are the bends of a smooth surface: drawn as light
    /// bending guides, not folds (default: 10 for `ffd`, `photo` and smooth charts, 0 for
    /// nets, `bend` and `slit`).
    #[arg(long, value_name = "DEGREES")]
    pub(crate) smooth_folds: Option<f64>,
}

pub(crate) fn parse_sheet(text: &str) -> Result<(f64, f64), String> {
    sheetform::pattern::sheet_size_from_text(text)
}

#[derive(Clone, Copy, PartialEq, clap::ValueEnum)]
pub(crate) enum MaterialSideArg {
    Behind,
    Centred,
    InFront,
}

#[derive(Clone, Copy, PartialEq, clap::ValueEnum)]
pub(crate) enum BackSideArg {
    Visible,
    Revolve,
}

impl From<BackSideArg> for sheetform::photo::BackSide {
    fn from(side: BackSideArg) -> Self {
        match side {
            BackSideArg::Visible => Self::Visible,
            BackSideArg::Revolve => Self::Revolve,
        }
    }
}

#[derive(Clone, Copy, PartialEq, clap::ValueEnum)]
pub(crate) enum Tabs {
    Auto,
    None,
    One,
    Alternate,
}

/// How `flatten` cuts a mesh into charts.
#[derive(clap::Args, Clone, Copy)]
pub(crate) struct ChartArgs {
    /// Layout: `auto` picks what a maker expects (a developable disk whole; a tube or
    /// cone in one piece cut along a ruling; a faceted model as a net; a finely meshed
    /// curved surface in charts within --max-distortion); `net` unfolds the facets edge
    /// by edge (exact, folds on kept edges, glue tabs on cut ones); `smooth` always cuts
    /// smooth charts; `never` flattens whole (opening only the user's seams).
    #[arg(long, value_enum, default_value_t = Charts::Auto)]
    pub(crate) charts: Charts,
    /// Edges folded by more than this (degrees) become seams between charts.
    #[arg(long, value_name = "DEGREES", default_value_t = 30.0)]
    pub(crate) crease_angle: f64,
    /// Charts that stretch an edge by more than this (relative) are split further.
    #[arg(long, value_name = "RELATIVE", default_value_t = 0.01)]
    pub(crate) max_distortion: f64,
}

#[derive(Clone, Copy, clap::ValueEnum)]
pub(crate) enum Charts {
    Auto,
    Net,
    #[value(alias = "always")]
    Smooth,
    Never,
}

#[derive(Clone, Copy, clap::ValueEnum)]
pub(crate) enum Method {
    Exact,
    Lscm,
    Arap,
}

#[derive(Clone, Copy, clap::ValueEnum)]
pub(crate) enum Page {
    A4,
    Letter,
}

#[derive(Clone, Copy, clap::ValueEnum)]
pub(crate) enum PatternUnit {
    Mm,
    Cm,
    In,
}

impl From<PatternArgs> for PatternOutputOptions {
    fn from(a: PatternArgs) -> Self {
        PatternOutputOptions {
            scale: a.scale,
            page: match a.page {
                Page::A4 => PageSize::A4,
                Page::Letter => PageSize::Letter,
            },
            dxf_unit: match a.pattern_units {
                PatternUnit::Mm => DxfUnit::Mm,
                PatternUnit::Cm => DxfUnit::Cm,
                PatternUnit::In => DxfUnit::In,
            },
            min_fold_angle_degrees: a.min_fold_angle,
            seam_labels: !a.no_seam_labels,
            tabs: matches!(a.tabs, Tabs::One | Tabs::Alternate).then_some(TabOptions {
                width_mm: a.tab_width,
                angle_degrees: a.tab_angle,
                sides: if a.tabs == Tabs::Alternate {
                    TabSides::Alternate
                } else {
                    TabSides::One
                },
                ..Default::default()
            }),
            sheet: a.sheet.map(|(w, h)| SheetOptions {
                width_mm: w,
                height_mm: h,
                gap_mm: a.sheet_gap,
            }),
            max_pdf_pages: a.max_pages,
            allowance: sheetform::pattern::MaterialAllowance {
                seam_allowance_mm: a.seam_allowance,
                notches: !a.no_notches,
                kerf_mm: a.kerf,
                grain_lines: a.grain_lines,
                bend: a.thickness.map(|thickness| sheetform::pattern::BendAllowance {
                    thickness_mm: thickness,
                    inner_radius_mm: a.bend_radius.unwrap_or(thickness),
                    k_factor: a.k_factor,
                    material_side: match a.material_side {
                        MaterialSideArg::Behind => sheetform::pattern::MaterialSide::Behind,
                        MaterialSideArg::Centred => sheetform::pattern::MaterialSide::Centred,
                        MaterialSideArg::InFront => sheetform::pattern::MaterialSide::InFront,
                    },
                }),
            },
            smooth_bend_degrees: a.smooth_folds,
        }
    }
}

/// Where `develop` cuts the target.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum Seams {
    /// Seams found automatically, the drawn ones among them.
    Automatic,
    /// The drawn seams (OBJ `l` polylines) only.
    Drawn,
}

impl From<Seams> for sheetform::pipeline::SeamSource {
    fn from(seams: Seams) -> Self {
        match seams {
            Seams::Automatic => Self::Automatic,
            Seams::Drawn => Self::Drawn,
        }
    }
}

#[derive(Clone, Copy, clap::ValueEnum)]
pub(crate) enum Unit {
    Mm,
    Cm,
    M,
    In,
}

impl From<Unit> for sheetform::mesh::LengthUnit {
    fn from(u: Unit) -> Self {
        match u {
            Unit::Mm => Self::Mm,
            Unit::Cm => Self::Cm,
            Unit::M => Self::M,
            Unit::In => Self::In,
        }
    }
}

/// `--solver` of `ffd`.
#[derive(Clone, Copy, clap::ValueEnum)]
pub(crate) enum SolverArg {
    /// Constrained Gauss–Newton with exact gradients (defects to 1e-10 rad).
    Constrained,
    /// The paper's penalty method with conjugate gradients.
    Paper,
    /// No restoration (plain FFD).
    None,
}

#[derive(Clone, Copy, clap::ValueEnum)]
pub(crate) enum SchemaFormat {
    /// The bend scene.
    Bend,
    /// The slit scene.
    Slit,
    /// The FFD scene.
    Ffd,
    /// The photo annotation.
    Photo,
    /// report.json, which every command writes.
    Report,
}
