"""sheetform: design with developable surfaces from Python.

Shapes made by bending sheet material without stretching or tearing, each returned as a
mesh that carries its exact flat pattern, over the same library pipeline as the
``sheetform`` command:

- ``bend(scene)``: a sheet bent along 3D control curves (Bo & Wang 2007);
- ``slit(scene)``: furniture from one sheet with parallel slits (Tsuruta et al.);
- ``ffd(scene)``: panels deformed in a lattice, developability restored (Wang & Tang);
- ``photo(annotation)``: a developable model and pattern from a photograph (Fondevilla et al.);
- ``check(V, F)``, ``flatten(V, F)``, ``develop(V, F)``, ``pattern(V, F, UV)``: any mesh
  as numpy arrays;
- ``BendEditor``: the web editor's curve edits, for notebooks;
- ``sheetform.batch``: many jobs on a Dask cluster, each job's result or error in order.

Every function returns a ``Run``: ``vertices`` (n, 3), ``faces`` (m, 3), ``uv`` (n, 2) the
flat pattern at 1:1, ``face_pieces``, ``pieces``, ``report`` (the CLI's ``report.json`` as a
dict), ``files`` (the files the CLI writes, as bytes) and ``write(directory)``.

Every run takes ``pattern=PatternOptions(...)`` (or a dict of its keywords: scale, paper,
glue tabs, sheet packing, seam allowance, kerf, sheet thickness, ... as the CLI's pattern
flags), ``outputs="preview"`` (only the GLB, the SVG and the report: faster) and
``progress``, called as ``progress(stage, fraction)`` as the run advances; Ctrl-C (a
notebook's interrupt) or an exception raised in ``progress`` stops the run at its next
stage and is raised.

Errors are ``SheetformError`` subclasses: ``InvalidInputError`` (the message names the
field), ``InadmissibleError`` (``.report`` says where), ``NotConvergedError``,
``OutputError``, ``CancelledError``.
"""

from ._native import (
    BendEditor,
    CancelledError,
    InadmissibleError,
    InvalidInputError,
    Mesh,
    NotConvergedError,
    OutputError,
    PatternOptions,
    Run,
    SheetformError,
    __version__,
    bend,
    check,
    ffd,
    develop,
    flatten,
    pattern,
    photo,
    slit,
)

__all__ = [
    "BendEditor",
    "CancelledError",
    "InadmissibleError",
    "InvalidInputError",
    "Mesh",
    "NotConvergedError",
    "OutputError",
    "PatternOptions",
    "Run",
    "SheetformError",
    "__version__",
    "bend",
    "check",
    "ffd",
    "develop",
    "flatten",
    "pattern",
    "photo",
    "slit",
]
