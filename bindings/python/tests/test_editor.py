"""The bend editor class: the web editor's edits (Bo & Wang 2007, §4.1), an inadmissible
edit refused with the scene kept, the edited scene bent as `bend` bends it."""

import json

import numpy as np
import pytest

import sheetform
from conftest import REPO

TORSION = {
    "outline": [[0, -60], [240, -60], [240, 60], [0, 60]],
    "regions": [
        {
            "flat_start": [0, 0],
            "flat_direction": [1, 0],
            "curve": {"type": "bezier", "control_points": [[0, 0, 0], [80, 10, 0], [150, -10, 60], [170, 10, 120]]},
        }
    ],
}


def curve_length(points, samples=20_000):
    t = np.linspace(0.0, 1.0, samples)[:, None]
    n = len(points) - 1
    from math import comb

    basis = np.hstack([comb(n, k) * t**k * (1 - t) ** (n - k) for k in range(n + 1)])
    curve = basis @ points
    return np.linalg.norm(np.diff(curve, axis=0), axis=1).sum()


def test_an_inadmissible_edit_is_refused_and_the_scene_kept():
    editor = sheetform.BendEditor(TORSION)
    before = editor.control_points(0).copy()
    info = editor.move_control_point(0, 2, [150.0, -20.0, 60.0])
    assert info["applied"] is False
    assert "regression" in info["rejected_because"]
    np.testing.assert_array_equal(editor.control_points(0), before)
    assert editor.scene == json.loads(json.dumps(editor.scene))
    assert editor.undo() is False, "nothing was applied"
    # A small move of the same point is admissible, and undone.
    info = editor.move_control_point(0, 2, [148.0, -8.0, 62.0])
    assert info["applied"] is True and info["rejected_because"] is None
    np.testing.assert_array_equal(editor.control_points(0)[2], [148.0, -8.0, 62.0])
    assert editor.undo() is True
    np.testing.assert_array_equal(editor.control_points(0), before)


def test_a_move_past_the_boundary_stops_there_when_asked():
    editor = sheetform.BendEditor(TORSION)
    before = editor.control_points(0).copy()
    info = editor.move_control_point(0, 2, [150.0, -20.0, 60.0], stop_at_boundary=True)
    assert info["applied"] is True
    t = info["moved_fraction"]
    assert 0.0 < t < 1.0
    assert "regression" in info["stopped_because"]
    np.testing.assert_allclose(editor.control_points(0)[2], before[2] + t * (np.array([150.0, -20.0, 60.0]) - before[2]))
    assert editor.bend().report["status"] == "ok"
    # One bisection step further is inadmissible.
    further = before[2] + (t + 1 / 256) * (np.array([150.0, -20.0, 60.0]) - before[2])
    assert sheetform.BendEditor(TORSION).move_control_point(0, 2, list(further))["applied"] is False
    # The desk's legs are B-splines: their points move too.
    desk = sheetform.BendEditor(REPO / "examples/desk.json")
    assert desk.control_points(1).shape == (6, 3)
    info = desk.move_control_point(1, 3, [100.0, 0.0, -110.0])
    assert info["applied"] and info["moved_fraction"] == 1.0 and info["stopped_because"] is None


def test_a_length_preserving_drag_keeps_the_length_and_bends_as_the_cli_would():
    editor = sheetform.BendEditor(REPO / "examples/bent-rectangle.json")
    start = curve_length(editor.control_points(0))
    info = editor.drag_preserving_length(0, 2, [150.0, 20.0, 70.0])
    assert info["applied"], info["rejected_because"]
    assert abs(info["curve_length_after"] - info["curve_length_before"]) < 1e-9
    assert np.isclose(curve_length(editor.control_points(0)), start, rtol=1e-6)
    np.testing.assert_array_equal(editor.control_points(0)[2], [150.0, 20.0, 70.0])
    # The edited scene is a scene `bend` reads: bent through the editor or as a dict, the same.
    run = editor.bend()
    again = sheetform.bend(editor.scene, root=REPO / "examples", outputs="preview")
    np.testing.assert_array_equal(run.vertices, again.vertices)
    assert np.isclose(run.report["regions"][0]["curve_length_mm"], start, rtol=1e-6)
    assert run.report["isometry_error_max_relative"] < 1e-9
    # Scaled rather than trimmed: the length is kept too.
    info = editor.drag_preserving_length(0, 2, [141.0, 8.0, 61.0], method="scale")
    assert info["applied"] and abs(info["curve_length_after"] - info["curve_length_before"]) < 1e-9


def test_end_handles_turn_the_start_normal():
    editor = sheetform.BendEditor(REPO / "examples/bent-rectangle.json")
    info = editor.drag_end_handles(0, start_normal=[0.0, 0.2, 1.0])
    assert info["applied"], info["rejected_because"]
    assert info["solver"]["converged"]
    p = editor.control_points(0)
    d = p[1] - p[0]
    normal = np.cross(np.cross(d, p[2] - 2 * p[1] + p[0]), d)
    wanted = np.array([0.0, 0.2, 1.0])
    assert normal @ wanted / np.linalg.norm(normal) / np.linalg.norm(wanted) > 0.99


def test_bad_edits_raise_invalid_input():
    editor = sheetform.BendEditor(REPO / "examples/bent-rectangle.json")
    with pytest.raises(sheetform.InvalidInputError, match="no region 5"):
        editor.move_control_point(5, 0, [0.0, 0.0, 0.0])
    with pytest.raises(sheetform.InvalidInputError, match="position"):
        editor.move_control_point(0, 1, [0.0, float("nan"), 0.0])
    with pytest.raises(sheetform.InvalidInputError, match="position"):
        editor.move_control_point(0, 1, [0.0, 0.0])
    with pytest.raises(sheetform.InvalidInputError, match="method"):
        editor.drag_preserving_length(0, 1, [0.0, 0.0, 0.0], method="stretch")
    with pytest.raises(sheetform.InvalidInputError):
        sheetform.BendEditor({"outline": [[0, 0], [1, 0], [0, 1]]})


def test_negative_numbers_count_from_the_end_as_python_indexes():
    editor = sheetform.BendEditor(REPO / "examples/bent-rectangle.json")
    last = editor.control_points(-1)[-1]
    np.testing.assert_array_equal(editor.control_points(0)[3], last)
    info = editor.move_control_point(-1, -2, [141.0, 8.0, 61.0])
    assert info["applied"], info["rejected_because"]
    np.testing.assert_array_equal(editor.control_points(0)[2], [141.0, 8.0, 61.0])
    with pytest.raises(sheetform.InvalidInputError, match="no control point -5"):
        editor.move_control_point(0, -5, [0.0, 0.0, 0.0])
    with pytest.raises(sheetform.InvalidInputError, match="no region -2"):
        editor.control_points(-2)


def test_the_editor_reads_its_files_from_where_it_was_opened(tmp_path, monkeypatch):
    # A textured scene opened by a relative root keeps reading from there after a chdir.
    monkeypatch.chdir(REPO)
    editor = sheetform.BendEditor(json.loads((REPO / "examples/textured-sheet.json").read_text()), root="examples")
    monkeypatch.chdir(tmp_path)
    assert editor.bend().outcome == "ok"


def test_the_sheet_and_the_analytic_curves_are_edited_as_in_the_web_editor():
    editor = sheetform.BendEditor(REPO / "examples/bent-rectangle.json")
    length = editor.bend().report["regions"][0]["curve_length_mm"]
    # A corner dragged inward stops where the sheet's edge meets the flat segment's end:
    # the edge from (240, -60) to (X, 60) crosses y = 0 at (240 + X) / 2 = L.
    info = editor.move_outline_vertex(2, [100.0, 60.0], stop_at_boundary=True)
    assert info["applied"] and 0.0 < info["moved_fraction"] < 1.0
    x = editor.scene["outline"][2][0]
    assert 2 * length - 240 <= x < 2 * length - 240 + 140 / 256
    assert editor.undo()
    assert editor.insert_outline_vertex(-1, [0.0, 0.0])["applied"]
    assert len(editor.scene["outline"]) == 5
    assert editor.delete_outline_vertex(-1)["applied"]
    assert len(editor.scene["outline"]) == 4
    with pytest.raises(sheetform.InvalidInputError, match="no hole 0"):
        editor.move_outline_vertex(0, [0.0, 0.0], hole=0)
    with pytest.raises(sheetform.InvalidInputError, match="two finite numbers"):
        editor.move_outline_vertex(0, [0.0, 0.0, 0.0])
    info = editor.move_flat_segment(0, start=[10.0, 5.0])
    assert info["applied"] and editor.scene["regions"][0]["flat_start"] == [10.0, 5.0]
    band = sheetform.BendEditor(REPO / "examples/arc-band.json")
    info = band.set_helix(0, radius=42.0, rise_per_radian=11.0)
    assert info["applied"], info["rejected_because"]
    assert np.isclose(info["curve_length_after"], np.hypot(42.0, 11.0) * np.pi / 2, rtol=1e-9)
    assert band.set_flat_arc(0, 64.0)["applied"]
    assert band.scene["regions"][0]["flat_curve"]["radius"] == 64.0
    tube = sheetform.BendEditor(REPO / "examples/tube.json")
    info = tube.set_helix(0, radius=45.0, stop_at_boundary=True)
    assert info["applied"] is False and "leaves the sheet" in info["stopped_because"]
