"""Mesh functions over numpy arrays: the same results as the CLI on the same mesh, meshes
from trimesh flattened and brought back, patterns of a given layout."""

import copy
import io
import json

import numpy as np
import pytest
import trimesh

import sheetform
from conftest import REPO, assert_close, read_obj, read_report, without_timings


def edge_lengths(vertices, faces):
    edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    return np.linalg.norm(vertices[edges[:, 0]] - vertices[edges[:, 1]], axis=1)


@pytest.mark.parametrize("mesh", ["lamp-shade", "gift-box"])
def test_flatten_of_arrays_equals_the_cli_on_the_same_mesh(mesh, cli, tmp_path):
    path = REPO / "examples/meshes" / f"{mesh}.obj"
    vertices, _, faces = read_obj(path)
    out = tmp_path / "out"
    done = cli("flatten", path.relative_to(REPO), "-o", out)
    assert done.returncode == 0, done.stderr
    run = sheetform.flatten(vertices, faces, name=mesh)
    expected = without_timings(read_report(out))
    actual = without_timings(run.report)
    # The one difference: the CLI records the file it read.
    assert actual.pop("input") is None and expected.pop("input") == str(path.relative_to(REPO))
    assert_close(actual, expected)
    v, vt, _ = read_obj(out / "model.obj")
    np.testing.assert_allclose(run.vertices, v, rtol=0, atol=1e-12 * np.abs(v).max())
    np.testing.assert_allclose(run.uv, vt, rtol=0, atol=1e-12 * np.abs(vt).max())
    for name in ("pattern.svg", "pattern.dxf", "pattern.pdf", "model.obj", "model.glb"):
        assert run.files[name] == (out / name).read_bytes(), name
    # Every output vertex is a copy of the input vertex it names.
    np.testing.assert_array_equal(run.vertices, vertices[run.source_vertices])


def test_check_of_arrays_equals_the_cli(cli, tmp_path):
    path = REPO / "examples/meshes/lamp-shade.obj"
    vertices, _, faces = read_obj(path)
    out = tmp_path / "out"
    done = cli("check", path.relative_to(REPO), "-o", out)
    assert done.returncode == 0, done.stderr
    run = sheetform.check(vertices, faces, name="lamp-shade")
    expected = without_timings(read_report(out))
    actual = without_timings(run.report)
    actual.pop("input"), expected.pop("input")
    # (The CLI also measures the flattening stored in the file's `vt`; arrays have none.)
    for key in ("isometry_error_max_relative", "isometry_error_mean_relative", "flat_area_mm2"):
        expected.pop(key, None), actual.pop(key, None)
    assert_close(actual, expected)
    assert run.report["status"] == "developable"
    assert run.uv is None
    assert run.angle_defects_rad.shape == (len(vertices),)
    assert np.abs(run.angle_defects_rad).max() < 1e-4


def test_a_trimesh_box_unfolds_exactly_into_a_net_and_comes_back():
    box = trimesh.creation.box(extents=(40.0, 30.0, 20.0))
    checked = sheetform.check(box.vertices, box.faces)
    assert checked.report["status"] == "not developable"
    # A box corner has an angle defect of π/2.
    np.testing.assert_allclose(np.abs(checked.angle_defects_rad), np.pi / 2, atol=1e-12)

    run = sheetform.flatten(box.vertices, box.faces)
    assert run.report["layout"] == "net"
    assert run.outcome == "ok"
    # Exact unfolding: every edge keeps its length on the pattern.
    np.testing.assert_allclose(edge_lengths(run.vertices, run.faces), edge_lengths(np.column_stack([run.uv, np.zeros(len(run.uv))]), run.faces), atol=1e-9)
    np.testing.assert_array_equal(run.vertices, box.vertices[run.source_vertices])
    # Back into trimesh with the pattern as texture coordinates, through an OBJ file.
    mesh = trimesh.Trimesh(
        vertices=run.vertices,
        faces=run.faces,
        visual=trimesh.visual.TextureVisuals(uv=run.uv),
        process=False,
    )
    assert np.isclose(mesh.area, box.area)
    text = trimesh.exchange.obj.export_obj(mesh, include_texture=True, digits=15)
    back = trimesh.load(io.BytesIO(text.encode()), file_type="obj", process=False, maintain_order=True)
    np.testing.assert_allclose(back.vertices, run.vertices, atol=1e-9)
    np.testing.assert_allclose(back.visual.uv, run.uv, atol=1e-9)
    np.testing.assert_array_equal(back.faces, run.faces)
    assert sum(1 for _ in trimesh.graph.connected_components(back.face_adjacency)) <= len(run.pieces)


def test_a_developable_cone_from_trimesh_is_flattened_whole_to_its_exact_sector():
    # An open cone (no cap), cut along one ruling so that it is a disk.
    n, height, radius = 64, 80.0, 50.0
    angles = np.linspace(0.0, 2.0 * np.pi, n + 1)
    rim = np.column_stack([radius * np.cos(angles), radius * np.sin(angles), np.zeros(n + 1)])
    vertices = np.vstack([[0.0, 0.0, height], rim])
    faces = np.array([[0, 1 + i, 2 + i] for i in range(n)])
    run = sheetform.flatten(vertices, faces, name="cone")
    assert run.report["layout"] == "whole" and run.outcome == "ok"
    slant = np.hypot(height, radius)
    apex_flat = run.uv[0]
    distances = np.linalg.norm(run.uv[1:] - apex_flat, axis=1)
    np.testing.assert_allclose(distances, slant, rtol=1e-12)
    # The sector's opening is the sum of the triangles' apex angles, n · 2 asin(c / 2s)
    # with c the rim's chord.
    chord = 2.0 * radius * np.sin(np.pi / n)
    around = np.unwrap(np.arctan2(*(run.uv[1:] - apex_flat).T[::-1]))
    assert np.isclose(abs(around[-1] - around[0]), n * 2.0 * np.arcsin(chord / (2.0 * slant)), rtol=1e-12)


def test_a_sphere_is_cut_into_charts_within_the_distortion_bound():
    sphere = trimesh.creation.icosphere(subdivisions=3, radius=50.0)
    run = sheetform.flatten(sphere.vertices, sphere.faces, charts="smooth", max_distortion=0.02, outputs="preview")
    assert run.report["layout"] == "charts"
    assert len(run.pieces) > 1
    assert run.report["isometry_error_max_relative"] <= 0.02
    assert run.outcome == "ok"
    assert run.face_pieces.min() == 0 and run.face_pieces.max() == len(run.pieces) - 1


def test_methods_and_arrays_of_other_types_are_taken():
    # float32 vertices and int32 faces (Open3D, libigl), a list of lists.
    n, height, radius = 32, 40.0, 20.0
    angles = np.linspace(0.0, np.pi, n + 1)
    ring = lambda z: np.column_stack([radius * np.cos(angles), radius * np.sin(angles), np.full(n + 1, z)])
    vertices = np.vstack([ring(0.0), ring(height)]).astype(np.float32)
    faces = np.array(
        [[i, i + 1, n + 2 + i] for i in range(n)] + [[i, n + 2 + i, n + 1 + i] for i in range(n)], dtype=np.int32
    )
    for method in ("exact", "lscm", "arap"):
        run = sheetform.flatten(vertices, faces.tolist(), method=method, outputs="preview")
        assert run.report["layout"] == "whole", method
        assert run.report["isometry_error_max_relative"] < (1e-6 if method != "lscm" else 0.05), method


def test_pattern_of_a_given_layout_renders_the_files_and_measures_it():
    # A half cylinder and its exact development.
    n, height, radius = 16, 30.0, 20.0
    angles = np.linspace(0.0, np.pi, n + 1)
    vertices = np.vstack(
        [np.column_stack([radius * np.cos(angles), radius * np.sin(angles), np.full(n + 1, z)]) for z in (0.0, height)]
    )
    # Developed exactly: the flat rim is as long as the polygon's.
    chord = 2.0 * radius * np.sin(np.pi / (2 * n))
    along = chord * np.arange(n + 1)
    uv = np.vstack([np.column_stack([along, np.full(n + 1, z)]) for z in (0.0, height)])
    faces = np.array([[i, i + 1, n + 2 + i] for i in range(n)] + [[i, n + 2 + i, n + 1 + i] for i in range(n)])
    run = sheetform.pattern(vertices, faces, uv, name="half-cylinder")
    assert sorted(run.files) == ["pattern.dxf", "pattern.pdf", "pattern.svg"]
    assert run.report["command"] == "pattern"
    assert run.report["isometry_error_max_relative"] < 1e-12
    assert run.outcome == "ok"
    assert np.isclose(run.report["pattern"]["width_mm"], n * chord, rtol=1e-9)
    assert np.isclose(run.report["pattern"]["height_mm"], height, rtol=1e-9)
    svg = run.files["pattern.svg"].decode()
    assert "<svg" in svg and 'id="cut"' in svg, svg[:300]
    # Two pieces by label, named.
    labels = np.array([0] * n + [1] * n)
    two = sheetform.pattern(vertices, faces, uv, face_pieces=labels, piece_names=["front", "back"], outputs="preview")
    assert two.pieces == ["front", "back"]
    assert b"front" in two.files["pattern.svg"]
    # A layout folded over itself is reported as overlapping.
    folded = uv.copy()
    folded[:, 0] = np.abs(folded[:, 0] - n * chord / 2)
    over = sheetform.pattern(vertices, faces, folded, outputs="preview")
    assert over.outcome == "overlapping" and over.report["status"] == "overlapping"


def test_seams_given_as_arrays_open_the_mesh_before_it_is_flattened():
    # A closed band (a cylinder without caps) is not a disk; one seam along a ruling
    # opens it into a rectangle, flattened whole and exactly.
    n, height, radius = 24, 50.0, 20.0
    angles = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    ring = lambda z: np.column_stack([radius * np.cos(angles), radius * np.sin(angles), np.full(n, z)])
    vertices = np.vstack([ring(0.0), ring(height)])
    faces = np.array([[i, (i + 1) % n, n + (i + 1) % n] for i in range(n)] + [[i, n + (i + 1) % n, n + i] for i in range(n)])
    with pytest.raises(sheetform.InvalidInputError):
        sheetform.flatten(vertices, faces, charts="never")
    run = sheetform.flatten(vertices, faces, drawn_seams=[[0, n]], charts="never", outputs="preview")
    assert run.report["layout"] == "whole" and run.outcome == "ok"
    assert len(run.vertices) == len(vertices) + 2, "the seam's two vertices are doubled"
    np.testing.assert_array_equal(run.vertices, vertices[run.source_vertices])
    chord = 2.0 * radius * np.sin(np.pi / n)
    width = np.ptp(run.uv @ np.linalg.svd(run.uv - run.uv.mean(0))[2].T, axis=0)
    np.testing.assert_allclose(sorted(width), sorted([height, n * chord]), rtol=1e-9)
    with pytest.raises(sheetform.InvalidInputError, match=r"seams.*row 0 \(0, 5\) is not an edge"):
        sheetform.flatten(vertices, faces, drawn_seams=[[0, 5]])


def test_develop_cuts_along_the_drawn_seams_only_when_told_to():
    """`seams="drawn"` is `--seams drawn`: a closed band (a developable cylinder) opened by
    one seam drawn along a ruling is one exact piece, the rectangle of its height and
    girth; `seams="automatic"` (the default) may add seams of its own. An array given as
    `seams` (its old meaning) is refused naming `drawn_seams`."""
    n, height, radius = 24, 50.0, 20.0
    angles = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    ring = lambda z: np.column_stack([radius * np.cos(angles), radius * np.sin(angles), np.full(n, z)])
    vertices = np.vstack([ring(0.0), ring(height)])
    faces = np.array([[i, (i + 1) % n, n + (i + 1) % n] for i in range(n)] + [[i, n + (i + 1) % n, n + i] for i in range(n)])
    run = sheetform.develop(vertices, faces, drawn_seams=[[0, n]], seams="drawn", outputs="preview")
    assert run.outcome == "ok"
    assert run.report["develop"]["seams"] == "drawn"
    assert len(run.pieces) == 1 and len(run.vertices) == len(vertices) + 2
    np.testing.assert_allclose(run.vertices, vertices[run.source_vertices], rtol=0, atol=1e-9)
    chord = 2.0 * radius * np.sin(np.pi / n)
    width = np.ptp(run.uv @ np.linalg.svd(run.uv - run.uv.mean(0))[2].T, axis=0)
    np.testing.assert_allclose(sorted(width), sorted([height, n * chord]), rtol=1e-9)
    with pytest.raises(sheetform.InvalidInputError, match="^seams: .*`drawn_seams`"):
        sheetform.develop(vertices, faces, seams=[[0, n]])
    with pytest.raises(sheetform.InvalidInputError, match="^seams: `manual`"):
        sheetform.develop(vertices, faces, seams="manual")


def test_source_vertices_name_input_rows_after_welding():
    # Two triangles given apart (six vertices), welded into a square of four.
    vertices = np.array([[0, 0, 0], [10, 0, 0], [10, 10, 0], [0, 0, 0], [10, 10, 0], [0, 10, 0]], dtype=float)
    faces = np.array([[0, 1, 2], [3, 4, 5]])
    for function in (sheetform.check, sheetform.flatten):
        run = function(vertices, faces, weld=1e-6, outputs="preview")
        assert run.report["welded_vertex_count"] == 2
        assert len(run.vertices) == 4
        np.testing.assert_array_equal(run.vertices, vertices[run.source_vertices])
        assert set(run.source_vertices.tolist()) == {0, 1, 2, 5}


def test_a_scene_may_hold_numpy_values_or_be_json_text():
    scene = json.loads((REPO / "examples/bent-rectangle.json").read_text())
    expected = sheetform.bend(scene, outputs="preview")
    with_numpy = copy.deepcopy(scene)
    with_numpy["regions"][0]["curve"]["control_points"] = np.array(scene["regions"][0]["curve"]["control_points"], dtype=float)
    with_numpy["outline"] = [np.array(p, dtype=np.float32).astype(float) for p in scene["outline"]]
    np.testing.assert_array_equal(sheetform.bend(with_numpy, outputs="preview").vertices, expected.vertices)
    as_text = sheetform.bend(json.dumps(scene), outputs="preview")
    np.testing.assert_array_equal(as_text.vertices, expected.vertices)


def test_a_name_is_kept_whole_in_the_pieces():
    box = trimesh.creation.box()
    run = sheetform.flatten(box.vertices, box.faces, name="part.v2", outputs="preview")
    assert run.pieces == ["part.v2-01"] or all(p.startswith("part.v2") for p in run.pieces), run.pieces


def test_develop_of_arrays_equals_the_cli_on_the_same_mesh(cli, tmp_path):
    """A closed box with automatic seams: the same report and files as the CLI, whole
    sides, nothing moved, every piece unfolded exactly."""
    path = REPO / "examples/meshes/gift-box.obj"
    vertices, _, faces = read_obj(path)
    out = tmp_path / "out"
    done = cli("develop", path.relative_to(REPO), "-o", out)
    assert done.returncode == 0, done.stderr
    run = sheetform.develop(vertices, faces, name="gift-box")
    expected = without_timings(read_report(out))
    actual = without_timings(run.report)
    assert actual.pop("input") is None and expected.pop("input") == str(path.relative_to(REPO))
    assert_close(actual, expected)
    assert run.outcome == "ok"
    assert run.report["develop"]["seams"] == "automatic"
    for name in ("pattern.svg", "model.obj", "distance.ply"):
        assert run.files[name] == (out / name).read_bytes(), name
    # Nothing moved: every output vertex is the target vertex it copies.
    np.testing.assert_allclose(run.vertices, vertices[run.source_vertices], rtol=0, atol=1e-12)
    # The pattern is the model at 1:1.
    uv3 = np.column_stack([run.uv, np.zeros(len(run.uv))])
    np.testing.assert_allclose(edge_lengths(uv3, run.faces), edge_lengths(run.vertices, run.faces), rtol=1e-9)


def test_develop_keeps_fixed_vertices_exactly_where_they_are():
    """`fixed=`: the vertices listed do not move (the output's copies of them sit exactly
    where they were); the rest is made developable around them. Out of range refused."""
    sphere = trimesh.creation.icosphere(subdivisions=2, radius=50.0)
    fixed = np.flatnonzero(sphere.vertices[:, 2] > 35.0)
    run = sheetform.develop(sphere.vertices, sphere.faces, fixed=fixed, outputs="preview")
    assert run.report["develop"]["fixed_vertex_count"] == len(fixed)
    assert run.report["develop"]["angle_defect_max_rad"] <= 1e-10
    kept = np.isin(run.source_vertices, fixed)
    assert kept.sum() >= len(fixed)
    np.testing.assert_array_equal(run.vertices[kept], sphere.vertices[run.source_vertices[kept]])
    free = sheetform.develop(sphere.vertices, sphere.faces, outputs="preview")
    moved = np.isin(free.source_vertices, fixed)
    assert np.abs(free.vertices[moved] - sphere.vertices[free.source_vertices[moved]]).max() > 1e-3
    with pytest.raises(sheetform.InvalidInputError, match="fixed"):
        sheetform.develop(sphere.vertices, sphere.faces, fixed=[len(sphere.vertices)])


def test_develop_remeshes_a_fine_target_to_its_working_size():
    """`work_faces=`: a 20 480-face sphere is developed on about 2 000 faces; the fixed
    vertices (spread over it) are kept exactly (source_vertices names them), the
    vertices the remeshing made are -1, and the distance is to the sphere as given."""
    sphere = trimesh.creation.icosphere(subdivisions=5, radius=50.0)
    fixed = np.arange(0, len(sphere.vertices), 211)
    run = sheetform.develop(sphere.vertices, sphere.faces, fixed=fixed, work_faces=2000, outputs="preview")
    develop = run.report["develop"]
    assert develop["target_face_count"] == 20480
    assert 1500 <= develop["work_face_count"] <= 2800 and len(run.faces) == develop["work_face_count"]
    assert develop["angle_defect_max_rad"] <= 1e-10
    assert (run.source_vertices == -1).sum() > 0.5 * len(run.vertices)
    kept = np.isin(run.source_vertices, fixed)
    assert kept.sum() >= len(fixed)
    np.testing.assert_array_equal(run.vertices[kept], sphere.vertices[run.source_vertices[kept]])
    # The distance is to the sphere as given: no vertex farther from it than reported.
    radii = np.linalg.norm(run.vertices, axis=1)
    assert np.abs(radii - 50.0).max() <= develop["hausdorff_mm"] + 0.05
    assert develop["hausdorff_relative"] <= 0.03
    with pytest.raises(sheetform.InvalidInputError, match="work_faces"):
        sheetform.develop(sphere.vertices, sphere.faces, work_faces=10)


def test_develop_keeps_a_mirror_plane():
    """`mirror="x"`: a capsule along z develops into exact pieces whose vertices are
    mirror images of each other in x = 0 (source_vertices pair each with a target
    vertex on its side); a bad plane is refused naming `mirror`."""
    capsule = trimesh.creation.capsule(height=60.0, radius=25.0)
    run = sheetform.develop(capsule.vertices, capsule.faces, mirror="x", outputs="preview")
    develop = run.report["develop"]
    assert run.report["status"] == "ok" and develop["mirror_plane"] == "x = 0"
    assert isinstance(develop["mirror_seam"], bool)
    assert develop["mirror_asymmetry_relative"] < 1e-9 and "warnings" not in run.report
    assert develop["angle_defect_max_rad"] <= 1e-10 and develop["piece_count"] <= 12
    # Every vertex's mirror image is a vertex.
    image = run.vertices * np.array([-1.0, 1.0, 1.0])
    distances = np.linalg.norm(image[:, None, :] - run.vertices[None, :, :], axis=2).min(axis=1)
    assert distances.max() <= 1e-9
    # Kept source vertices are on the side developed (new ones, on the cut, are -1).
    kept = run.source_vertices >= 0
    assert kept.sum() > 0.3 * len(run.vertices)
    # Images copy no target vertex: -1, as the vertices a remeshing makes.
    assert (run.source_vertices == -1).sum() >= 0.4 * len(run.vertices)
    with pytest.raises(sheetform.InvalidInputError, match="mirror"):
        sheetform.develop(capsule.vertices, capsule.faces, mirror="w")
    # A region fixed on both sides, symmetrically, stays where it is (each fixed target
    # vertex is a vertex of the result); fixed where its mirror image is not fixed, it
    # cannot stay (whichever side is kept), and is refused naming `fixed`.
    ends = np.flatnonzero(np.abs(capsule.vertices[:, 2]) > 50.0)
    run = sheetform.develop(capsule.vertices, capsule.faces, mirror="x", fixed=ends, outputs="preview")
    gaps = np.linalg.norm(capsule.vertices[ends][:, None, :] - run.vertices[None, :, :], axis=2).min(axis=1)
    assert run.report["status"] == "ok" and gaps.max() <= 1e-9
    x, y = capsule.vertices[:, 0], capsule.vertices[:, 1]
    lopsided = np.flatnonzero(((x < -10.0) & (y > 0.0)) | ((x > 10.0) & (y < 0.0)))
    with pytest.raises(sheetform.InvalidInputError, match="fixed"):
        sheetform.develop(capsule.vertices, capsule.faces, mirror="x", fixed=lopsided)


def test_develop_with_a_distance_bound_and_its_refusals():
    """A trimesh sphere within 3 % of its size, and an impossible bound: out of
    tolerance, the closest result returned; bad arguments named."""
    sphere = trimesh.creation.icosphere(subdivisions=2, radius=50.0)
    run = sheetform.develop(sphere.vertices, sphere.faces, max_distance="3%", max_pieces=20, outputs="preview")
    develop = run.report["develop"]
    assert run.outcome == "ok", develop
    assert develop["hausdorff_relative"] <= 0.03
    assert develop["angle_defect_max_rad"] <= 1e-10
    far = sheetform.develop(sphere.vertices, sphere.faces, max_distance=0.001, max_pieces=3, outputs="preview")
    assert far.outcome == "out_of_tolerance"
    assert far.report["develop"]["hausdorff_mm"] > far.report["develop"]["max_distance_mm"]
    with pytest.raises(sheetform.InvalidInputError, match="max_distance"):
        sheetform.develop(sphere.vertices, sphere.faces, max_distance="far")
    with pytest.raises(sheetform.InvalidInputError, match="max_pieces"):
        sheetform.develop(sphere.vertices, sphere.faces, max_pieces=0)


def test_develop_slides_automatic_seams_onto_smooth_curves_unless_told_not_to():
    """An icosphere's automatic seams step along its edges: with the default smoothing the
    report counts the seam vertices slid onto smooth curves and the printed cut is
    shorter; `seam_smoothing=0` keeps them on the mesh's edges. Both are exact."""
    sphere = trimesh.creation.icosphere(subdivisions=3, radius=50.0)
    smooth = sheetform.develop(sphere.vertices, sphere.faces, outputs="preview")
    stepped = sheetform.develop(sphere.vertices, sphere.faces, seam_smoothing=0, outputs="preview")
    assert smooth.report["develop"]["seam_smoothed_vertex_count"] > 50
    assert stepped.report["develop"]["seam_smoothed_vertex_count"] == 0
    assert smooth.outcome == stepped.outcome == "ok"

    def cut_length(run):
        # Border edges of the flat pattern: edges of one face only.
        edges = np.sort(np.concatenate([run.faces[:, [0, 1]], run.faces[:, [1, 2]], run.faces[:, [2, 0]]]), axis=1)
        unique, counts = np.unique(edges, axis=0, return_counts=True)
        border = unique[counts == 1]
        return np.linalg.norm(run.uv[border[:, 0]] - run.uv[border[:, 1]], axis=1).sum()

    assert cut_length(smooth) < 0.97 * cut_length(stepped)
    with pytest.raises(sheetform.InvalidInputError, match="seam_smoothing"):
        sheetform.develop(sphere.vertices, sphere.faces, seam_smoothing=1000, outputs="preview")
