//! The output type every sheetform method returns: [`SheetMesh`], a triangle mesh of the
//! bent sheet in which every vertex carries its 3D position *and* its exact position on
//! the flat sheet (same length unit), plus the rulings and a piece label per face.
//! Also the metrics computed on it (isometry error, developability along rulings), and
//! [`TriangleMesh`], any mesh read from a file, with its topology checks and
//! developability measures (angle defects, Gaussian curvature, Wang & Tang's `D[M]`, `G[X]`).

mod corner_angle;
mod developability;
mod edge_cut;
mod edge_table;
mod error;
mod fold_angle;
mod isotropic_remeshing;
mod metrics;
mod mirror_plane;
pub mod primitives;
mod sheet_mesh;
mod shortest_edge_path;
mod surface_distance;
mod topology;
mod triangle_mesh;
mod union_find;
mod unit;
mod vertex_normals;

pub use corner_angle::{corner_angle, corner_angle_gradient, corner_angle_hessian, vertex_angle_sums};
pub use developability::{developability_summary, vertex_developability, DevelopabilitySummary, VertexDevelopability};
pub use edge_cut::{cut_along_edges, CutMesh};
pub use edge_table::{EdgeSide, EdgeTable};
pub use error::MeshError;
pub use fold_angle::{signed_fold_angle, signed_fold_angle_gradients};
pub use isotropic_remeshing::{remesh_isotropic, RemeshOptions, Remeshed};
pub use metrics::{developability_error, isometry_error, IsometryError, RulingNormalError};
pub use mirror_plane::{
    mirror_half, mirror_whole, MirrorHalf, MirrorPlane, MirroredWhole, MIRROR_CUT_SNAP, MIRROR_SNAP,
};
pub use sheet_mesh::{Piece, PieceKind, Ruling, SheetMesh};
pub use shortest_edge_path::shortest_edge_path;
pub use surface_distance::{
    closest_point_on_triangle, surface_distance, vertex_distances, SurfaceDistance, SurfaceDistanceOptions,
    SurfaceIndex,
};
pub use topology::{mesh_topology, mesh_topology_with_edges, MeshTopology};
pub use triangle_mesh::{coincident_vertices, TriangleMesh};
pub use union_find::UnionFind;
pub use unit::{LengthUnit, UpAxis};
pub use vertex_normals::area_weighted_normals;
