"""Type stubs of sheetform's native module (PyO3). See the package docstring."""

from os import PathLike
from typing import Any, Callable, Literal, Optional, Sequence, Union, final

import numpy as np
import numpy.typing as npt

__version__: str
__all__ = [
    "__version__",
    "bend",
    "slit",
    "ffd",
    "photo",
    "check",
    "flatten",
    "develop",
    "pattern",
    "Run",
    "_restore_run",
    "Mesh",
    "_restore_mesh",
    "PatternOptions",
    "BendEditor",
    "SheetformError",
    "InvalidInputError",
    "InadmissibleError",
    "NotConvergedError",
    "OutputError",
    "CancelledError",
]

_Scene = Union[dict[str, Any], str, PathLike[str]]
"""A scene as a dict (the JSON the CLI reads; numpy values allowed), its JSON (or SVG) text, or the path of its file."""
_Outputs = Literal["all", "preview"]
_Page = Literal["a4", "letter"]
_PatternUnits = Literal["mm", "cm", "in"]
_Tabs = Literal["auto", "none", "one", "alternate"]
_Unit = Literal["mm", "cm", "m", "in"]
_Point = Sequence[float]

class SheetformError(Exception):
    """Base class of every error sheetform raises."""

class InvalidInputError(SheetformError):
    """The input is malformed, out of range or unreadable; the message names the field or place."""

class InadmissibleError(SheetformError):
    """The input is valid but the shape cannot be made; ``report`` says where."""

    report: dict[str, Any]

class NotConvergedError(SheetformError):
    """A solver or a construction failed on valid input."""

class OutputError(SheetformError):
    """The outputs cannot be written."""

class CancelledError(SheetformError):
    """The run was cancelled."""

@final
class PatternOptions:
    """How the printable pattern is made, as the CLI's pattern flags."""

    def __new__(
        cls,
        *,
        scale: float = 1.0,
        page: _Page = "a4",
        pattern_units: _PatternUnits = "mm",
        min_fold_angle: float = 1.0,
        seam_labels: bool = True,
        tabs: _Tabs = "auto",
        tab_width: float = 5.0,
        tab_angle: float = 45.0,
        sheet: Optional[Union[str, tuple[float, float]]] = None,
        sheet_gap: float = 5.0,
        max_pages: Optional[int] = None,
        seam_allowance: float = 0.0,
        notches: bool = True,
        kerf: float = 0.0,
        grain_lines: bool = False,
        thickness: Optional[float] = None,
        bend_radius: Optional[float] = None,
        k_factor: Optional[float] = None,
        material_side: Optional[Literal["behind", "centred", "in-front"]] = None,
        smooth_folds: Optional[float] = None,
    ) -> PatternOptions: ...
    def __getnewargs_ex__(self) -> tuple[tuple[()], dict[str, Any]]:
        """Pickles as the keywords it was made with."""

@final
class Mesh:
    """A mesh beside a run's model (an FFD run's welded panels)."""

    @property
    def vertices(self) -> npt.NDArray[np.float64]:
        """``(n, 3)`` vertex positions."""
    @property
    def faces(self) -> npt.NDArray[np.int64]:
        """``(m, 3)`` triangles."""
    @property
    def angle_defects_rad(self) -> npt.NDArray[np.float64]:
        """``(n,)`` angle defect at each vertex."""

@final
class Run:
    """A mesh with its flat pattern, the report and the files the CLI would write."""

    @property
    def vertices(self) -> npt.NDArray[np.float64]:
        """``(n, 3)`` vertex positions (model units)."""
    @property
    def faces(self) -> npt.NDArray[np.int64]:
        """``(m, 3)`` triangles, indices into ``vertices``."""
    @property
    def uv(self) -> Optional[npt.NDArray[np.float64]]:
        """``(n, 2)`` flat pattern at 1:1 (model units); ``None`` for ``check``."""
    @property
    def face_pieces(self) -> Optional[npt.NDArray[np.int64]]:
        """``(m,)`` piece of each face (index into ``pieces``)."""
    @property
    def pieces(self) -> list[str]:
        """The pieces' names."""
    @property
    def angle_defects_rad(self) -> Optional[npt.NDArray[np.float64]]:
        """``(n,)`` angle defect at each vertex (``bend``, ``check``)."""
    @property
    def source_vertices(self) -> Optional[npt.NDArray[np.int64]]:
        """``(n,)`` input row each vertex copies (``flatten``, ``check``; after ``weld``, the first merged)."""
    @property
    def report(self) -> dict[str, Any]:
        """The ``report.json`` the CLI writes, as a dict."""
    @property
    def outcome(self) -> Literal["ok", "overlapping", "out_of_tolerance"]:
        """How the run ended."""
    @property
    def meshes(self) -> dict[str, Mesh]:
        """Meshes beside the model (``ffd``: ``"plain"``, ``"restored"``)."""
    @property
    def pipeline_seconds(self) -> float:
        """Seconds the library's pipeline took."""
    @property
    def files(self) -> dict[str, bytes]:
        """The rendered files, ``{name: bytes}``, without ``report.json``."""
    def write(self, directory: Union[str, PathLike[str]]) -> None:
        """Writes the files and ``report.json`` into ``directory`` as one set."""

def bend(
    scene: _Scene,
    *,
    root: Optional[Union[str, PathLike[str]]] = None,
    outputs: _Outputs = "all",
    progress: Optional[Callable[[str, float], Any]] = None,
    animate: int = 0,
    pattern: Optional[Union[PatternOptions, dict[str, Any]]] = None,
) -> Run:
    """Bends a sheet along 3D control curves (system A, Bo & Wang 2007)."""

def slit(
    scene: _Scene,
    *,
    root: Optional[Union[str, PathLike[str]]] = None,
    outputs: _Outputs = "all",
    progress: Optional[Callable[[str, float], Any]] = None,
    pattern: Optional[Union[PatternOptions, dict[str, Any]]] = None,
) -> Run:
    """Solves a slit sheet (system B, Tsuruta et al.)."""

def ffd(
    scene: _Scene,
    *,
    root: Optional[Union[str, PathLike[str]]] = None,
    outputs: _Outputs = "all",
    progress: Optional[Callable[[str, float], Any]] = None,
    solver: Optional[Literal["constrained", "paper", "none"]] = None,
    warm_start: Optional[Run] = None,
    pattern: Optional[Union[PatternOptions, dict[str, Any]]] = None,
) -> Run:
    """Deforms panels in a lattice and restores their developability (system C, Wang & Tang 2004)."""

def photo(
    annotation: _Scene,
    *,
    root: Optional[Union[str, PathLike[str]]] = None,
    outputs: _Outputs = "all",
    progress: Optional[Callable[[str, float], Any]] = None,
    pattern: Optional[Union[PatternOptions, dict[str, Any]]] = None,
    back_side: Optional[Literal["visible", "revolve"]] = None,
) -> Run:
    """Reconstructs a developable model and its pattern from an annotated photograph (system D)."""

def check(
    vertices: npt.ArrayLike,
    faces: npt.ArrayLike,
    *,
    weld: Optional[float] = None,
    tolerance: Optional[float] = None,
    units: _Unit = "mm",
    name: str = "mesh",
    outputs: _Outputs = "all",
    progress: Optional[Callable[[str, float], Any]] = None,
) -> Run:
    """Measures the developability of a triangle mesh, as ``sheetform check``."""

def flatten(
    vertices: npt.ArrayLike,
    faces: npt.ArrayLike,
    *,
    drawn_seams: Optional[npt.ArrayLike] = None,
    method: Literal["exact", "lscm", "arap"] = "exact",
    charts: Literal["auto", "smooth", "net", "never"] = "auto",
    crease_angle: Optional[float] = None,
    max_distortion: Optional[float] = None,
    weld: Optional[float] = None,
    units: _Unit = "mm",
    size: Optional[float] = None,
    name: str = "mesh",
    outputs: _Outputs = "all",
    progress: Optional[Callable[[str, float], Any]] = None,
    pattern: Optional[Union[PatternOptions, dict[str, Any]]] = None,
) -> Run:
    """Lays a mesh out flat, as ``sheetform flatten`` (``size``: the model's height as
    printed in mm, as ``--size``)."""

def develop(
    vertices: npt.ArrayLike,
    faces: npt.ArrayLike,
    *,
    drawn_seams: Optional[npt.ArrayLike] = None,
    seams: Optional[Literal["automatic", "drawn"]] = None,
    max_pieces: int = 12,
    normal_tolerance: float = 2.0,
    cone_angle: float = 60.0,
    fixed: Optional[npt.ArrayLike] = None,
    max_distance: Optional[Union[float, str]] = None,
    work_faces: Optional[int] = None,
    mirror: Optional[str] = None,
    seam_smoothing: int = 6,
    smoothness: float = 0.1,
    tolerance: float = 1e-10,
    max_iterations: int = 100,
    units: _Unit = "mm",
    size: Optional[float] = None,
    name: str = "mesh",
    outputs: _Outputs = "all",
    progress: Optional[Callable[[str, float], Any]] = None,
    pattern: Optional[Union[PatternOptions, dict[str, Any]]] = None,
) -> Run:
    """Develops a target shape, as ``sheetform develop``: the nearest surface made of
    exactly developable pieces, unfolded exactly (``seams``: ``"automatic"`` (the default,
    also ``None``) or ``"drawn"`` as ``--seams``, ``drawn_seams`` the edges drawn; ``max_distance``: a length in ``units``
    or a percentage of the size, ``"0.5%"``; ``work_faces``, default 10 000: a finer
    target is remeshed to about this many faces first, and ``source_vertices`` is -1
    for the vertices the remeshing made and the mirror images; ``mirror``: a mirror
    plane kept, ``"x"``, ``"y"``, ``"z"`` through the middle of the mesh or placed,
    ``"x=0"``)."""

def pattern(
    vertices: npt.ArrayLike,
    faces: npt.ArrayLike,
    uv: npt.ArrayLike,
    *,
    face_pieces: Optional[npt.ArrayLike] = None,
    piece_names: Optional[Sequence[str]] = None,
    units: _Unit = "mm",
    name: str = "pattern",
    outputs: _Outputs = "all",
    progress: Optional[Callable[[str, float], Any]] = None,
    pattern: Optional[Union[PatternOptions, dict[str, Any]]] = None,
) -> Run:
    """The printable pattern of a mesh that already has its flat layout."""

@final
class BendEditor:
    """An editable bend scene (Bo & Wang 2007, §4.1)."""

    def __new__(cls, scene: _Scene, *, root: Optional[Union[str, PathLike[str]]] = None) -> BendEditor: ...
    @property
    def scene(self) -> dict[str, Any]:
        """The current scene as a dict."""
    def control_points(self, region: int) -> npt.NDArray[np.float64]:
        """The control points of ``region``'s curve (Bézier or B-spline), ``(k, 3)``."""
    def move_control_point(
        self, region: int, index: int, position: _Point, *, stop_at_boundary: bool = False
    ) -> dict[str, Any]:
        """Moves one control point (§4.1.1); returns the edit info. ``stop_at_boundary``:
        a move past the admissible shapes goes as far as they allow (``moved_fraction``)."""
    def drag_preserving_length(
        self,
        region: int,
        index: int,
        position: _Point,
        method: Literal["trim", "scale"] = "trim",
        *,
        stop_at_boundary: bool = False,
    ) -> dict[str, Any]:
        """Moves one control point and restores the curve's length (§4.1.3)."""
    def drag_end_handles(
        self,
        region: int,
        *,
        start_position: Optional[_Point] = None,
        start_normal: Optional[_Point] = None,
        end_position: Optional[_Point] = None,
        end_normal: Optional[_Point] = None,
        stop_at_boundary: bool = False,
    ) -> dict[str, Any]:
        """Drags the end handles (§4.1.2)."""
    def move_outline_vertex(
        self,
        index: int,
        position: Sequence[float],
        *,
        hole: Optional[int] = None,
        stop_at_boundary: bool = False,
    ) -> dict[str, Any]:
        """Moves a vertex of the outline (or of a hole) on the flat sheet."""
    def insert_outline_vertex(
        self, after: int, position: Sequence[float], *, hole: Optional[int] = None
    ) -> dict[str, Any]:
        """Inserts a vertex after vertex ``after`` of the outline (or of a hole)."""
    def delete_outline_vertex(self, index: int, *, hole: Optional[int] = None) -> dict[str, Any]:
        """Deletes a vertex of the outline (or of a hole); three must remain."""
    def move_flat_segment(
        self,
        region: int,
        *,
        start: Optional[Sequence[float]] = None,
        direction: Optional[Sequence[float]] = None,
        stop_at_boundary: bool = False,
    ) -> dict[str, Any]:
        """Moves a region's flat segment: its start, its direction, or both."""
    def set_helix(
        self,
        region: int,
        *,
        radius: Optional[float] = None,
        rise_per_radian: Optional[float] = None,
        start_angle: Optional[float] = None,
        end_angle: Optional[float] = None,
        stop_at_boundary: bool = False,
    ) -> dict[str, Any]:
        """Changes a region's helix; each parameter left out is kept."""
    def set_flat_arc(self, region: int, radius: float, *, stop_at_boundary: bool = False) -> dict[str, Any]:
        """Changes the radius of a region's flat arc."""
    def undo(self) -> bool:
        """Takes the last applied edit back; ``False`` when there is none."""
    def bend(self, *, outputs: _Outputs = "preview") -> Run:
        """Bends the current scene."""

def _restore_run(state: dict[str, Any]) -> Run:
    """Rebuilds a pickled ``Run`` (pickle calls it; not for direct use)."""

def _restore_mesh(
    vertices: npt.NDArray[np.float64],
    faces: npt.NDArray[np.int64],
    angle_defects_rad: npt.NDArray[np.float64],
) -> Mesh:
    """Rebuilds a pickled ``Mesh`` (pickle calls it; not for direct use)."""
