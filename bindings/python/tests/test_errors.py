"""Bad input raises the exception of its kind with a message naming the field or place,
as the CLI's tests check for its exit codes; nothing crashes the interpreter."""

import copy
import json

import numpy as np
import pytest

import sheetform
from conftest import REPO


def example(path):
    return json.loads((REPO / path).read_text())


RECT = [[0, -20], [100, -20], [100, 20], [0, 20]]
CURVE = {"type": "bezier", "control_points": [[0, 0, 0], [40, 0, 10], [80, 0, 0]]}


def bend_scene(outline=RECT, **region):
    return {"outline": outline, "regions": [{"flat_start": [0, 0], "curve": CURVE, **region}]}


def test_every_error_class_is_a_sheetform_error():
    for error in (
        sheetform.InvalidInputError,
        sheetform.InadmissibleError,
        sheetform.NotConvergedError,
        sheetform.OutputError,
        sheetform.CancelledError,
    ):
        assert issubclass(error, sheetform.SheetformError)
        assert issubclass(error, Exception)
        assert error.__doc__


@pytest.mark.parametrize(
    "scene,expected",
    [
        ({"outline": RECT}, "missing field `regions`"),
        ({"outline": RECT, "regions": [], "colour": 1}, "unknown field `colour`"),
        (bend_scene(outline=[[0, 0], [100, 40], [100, 0], [0, 40]], flat_direction=[1, 0]), "crosses"),
        (bend_scene(flat_end=[90, 0]), "bending cannot stretch the sheet"),
        (bend_scene(outline=[[0, -20], [60, -20], [60, 20], [0, 20]], flat_direction=[1, 0]), "leaves the sheet"),
        ({**bend_scene(flat_direction=[1, 0]), "tessellation": {"rulings": 100_000_000}}, "tessellation.rulings"),
        ({**bend_scene(flat_direction=[1, 0]), "texture": "../../../etc/passwd"}, "texture"),
        ({**bend_scene(flat_direction=[1, 0]), "texture": "/etc/passwd"}, "an absolute path"),
        ("no-such-scene.json", "no-such-scene.json"),
        (42, "scene"),
    ],
    ids=["missing", "unknown", "crossing", "stretch", "leaves", "size", "escaping", "absolute", "no file", "not a scene"],
)
def test_a_bad_bend_scene_raises_invalid_input_naming_the_field(scene, expected, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(sheetform.InvalidInputError) as error:
        sheetform.bend(scene)
    assert expected in str(error.value)


def test_a_non_finite_number_in_a_scene_dict_is_refused():
    scene = bend_scene(flat_direction=[1, 0])
    scene["regions"][0]["curve"] = {"type": "bezier", "control_points": [[0, 0, 0], [float("nan"), 0, 0], [1, 1, 0]]}
    with pytest.raises(sheetform.InvalidInputError, match="scene"):
        sheetform.bend(scene)
    scene["regions"][0]["curve"]["control_points"][1][0] = float("inf")
    with pytest.raises(sheetform.InvalidInputError, match="scene"):
        sheetform.bend(scene)


def test_sizes_over_their_maxima_are_refused_in_every_system():
    ffd = example("examples/ffd/duct.json")
    ffd["lattice"]["counts"] = [1000, 1000, 1000]
    with pytest.raises(sheetform.InvalidInputError, match=r"lattice\.counts\[0\]"):
        sheetform.ffd(ffd)
    slit = example("examples/slit/bench.json")
    slit["sheet"]["quads_per_strip"] = 4096
    with pytest.raises(sheetform.InvalidInputError, match=r"sheet\.quads_per_strip"):
        sheetform.slit(slit)
    photo = example("examples/photo/coffee-cup.json")
    photo["image"]["width"] = photo["image"]["height"] = 40_000
    with pytest.raises(sheetform.InvalidInputError, match="image"):
        sheetform.photo(photo, root=REPO / "examples/photo")


def test_a_photo_that_is_missing_is_named():
    photo = example("examples/photo/coffee-cup.json")
    photo["image"]["path"] = "missing.png"
    with pytest.raises(sheetform.InvalidInputError, match="missing.png"):
        sheetform.photo(photo, root=REPO / "examples/photo")


def test_an_inadmissible_shape_raises_with_the_report_saying_where():
    scene = {
        "outline": [[0, -60], [240, -60], [240, 60], [0, 60]],
        "regions": [
            {
                "flat_start": [0, 0],
                "flat_direction": [1, 0],
                "curve": {"type": "bezier", "control_points": [[0, 0, 0], [80, 10, 0], [150, -20, 60], [170, 10, 120]]},
            }
        ],
    }
    with pytest.raises(sheetform.InadmissibleError) as error:
        sheetform.bend(scene)
    report = error.value.report
    assert report["status"] == "inadmissible" and report["admissible"] is False
    assert "regression" in report["regression_entry"]["message"]
    assert report["outputs"] == ["report.json"]


@pytest.mark.parametrize(
    "vertices,faces,argument,expected",
    [
        (np.zeros((3, 2)), [[0, 1, 2]], "vertices", "(n, 3)"),
        ([[0, 0, 0], [1, 0, 0], [0, float("nan"), 0]], [[0, 1, 2]], "vertices", "row 2 has a non-finite"),
        ([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 3]], "faces", "row 0 names vertex 3"),
        ([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, -1, 2]], "faces", "vertex -1"),
        ([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0.0, 1.0, 2.0]], "faces", "integer indices expected"),
        ([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2, 0]], "faces", "(n, 3)"),
        ([["a", "b", "c"]], [[0, 0, 0]], "vertices", "not an array of numbers"),
        ([], [], "faces", "the mesh has no faces"),
        (np.eye(3), np.zeros((0, 3), dtype=np.int64), "faces", "the mesh has no faces"),
        (np.eye(3), np.array([[0, 1, 2**63 + 5]], dtype=np.uint64), "faces", "an index over"),
        (np.eye(3), np.array([[True, False, True]]), "faces", "integer indices expected"),
        (np.zeros((2, 3, 3)), [[0, 1, 2]], "vertices", "(n, 3)"),
    ],
)
def test_bad_arrays_raise_invalid_input_naming_the_array(vertices, faces, argument, expected):
    for function in (sheetform.check, sheetform.flatten):
        with pytest.raises(sheetform.InvalidInputError) as error:
            function(vertices, faces)
        assert argument in str(error.value) and expected in str(error.value), str(error.value)


def test_bad_options_raise_invalid_input_naming_the_option():
    v = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
    f = [[0, 1, 2]]
    cases = [
        (lambda: sheetform.flatten(v, f, method="magic"), "method"),
        (lambda: sheetform.flatten(v, f, charts="some"), "charts"),
        (lambda: sheetform.flatten(v, f, units="furlong"), "units"),
        (lambda: sheetform.flatten(v, f, outputs="everything"), "outputs"),
        (lambda: sheetform.flatten(v, f, crease_angle=400.0), "crease_angle: must be an angle"),
        (lambda: sheetform.flatten(v, f, max_distortion=float("nan")), "max_distortion: must be"),
        (lambda: sheetform.flatten(v, f, pattern={"scale": -1.0}), "scale"),
        (lambda: sheetform.flatten(v, f, pattern={"page": "a0"}), "page"),
        (lambda: sheetform.PatternOptions(sheet="huge"), "sheet"),
        (lambda: sheetform.PatternOptions(sheet=(100, float("nan"))), "sheet"),
        (lambda: sheetform.flatten(v, f, pattern={"colour": "red"}), "colour"),
        (lambda: sheetform.flatten(v, f, pattern=3), "pattern"),
        (lambda: sheetform.flatten(v, f, pattern={"thickness": 1.0, "k_factor": 3.0}), "k_factor"),
        (lambda: sheetform.flatten(v, f, pattern={"kerf": -0.2}), "kerf"),
        (lambda: sheetform.flatten(v, f, pattern={"tabs": "one", "tab_width": -1.0}), "tab_width"),
        (lambda: sheetform.flatten(v, f, pattern={"tabs": "one", "tab_angle": 200.0}), "tab_angle"),
        (lambda: sheetform.flatten(v, f, pattern={"sheet": "a4", "sheet_gap": 1e308}), "sheet_gap"),
        (lambda: sheetform.flatten(v, f, pattern={"smooth_folds": -5.0}), "smooth_folds"),
        (lambda: sheetform.flatten(v, f, pattern={"thickness": 1.0, "bend_radius": -1.0}), "bend_radius"),
        (lambda: sheetform.PatternOptions(k_factor=0.3), "k_factor: goes with thickness"),
        (lambda: sheetform.PatternOptions(max_pages=-1), "max_pages"),
        (lambda: sheetform.PatternOptions(tabs="many"), "tabs"),
        (lambda: sheetform.bend({"outline": {1, 2}}), "a set is not a JSON value"),
        (lambda: sheetform.check(v, f, weld=-1.0), "weld: must be a non-negative distance"),
        (lambda: sheetform.check(v, f, tolerance=float("inf")), "tolerance: must be"),
        (lambda: sheetform.flatten(v, f, pattern=sheetform.PatternOptions(seam_allowance=-1.0)), "seam_allowance"),
        (lambda: sheetform.flatten(v, f, pattern={"scale": 0.0}), "scale"),
        (lambda: sheetform.flatten(v, f, drawn_seams=[[0, 1, 2]]), "drawn_seams"),
        (lambda: sheetform.flatten(v, f, drawn_seams=[[0, -1]]), "drawn_seams: row 0 names vertex -1"),
        (lambda: sheetform.pattern(v, f, [[0, 0], [1, 0], [0, 1]], face_pieces=[4_000_000_000]), "face_pieces: row 0 is 4000000000"),
        (lambda: sheetform.pattern(v, f, [[0, 0], [1, 0], [0, 1]], face_pieces=[0], piece_names=["a", "b"]), "piece_names: 2 names"),
        (lambda: sheetform.pattern(v, f, [[0, 0], [1, 0], [0, 1]], face_pieces=np.array([2**64 - 1], dtype=np.uint64)), "face_pieces: an index over"),
        (lambda: sheetform.pattern(v, f, [[0, 0], [1, 0]]), "uv"),
        (lambda: sheetform.pattern(v, f, [[0, 0], [1, 0], [0, 1]], face_pieces=[-1]), "face_pieces"),
        (lambda: sheetform.ffd(REPO / "examples/ffd/two-panels.json", solver="fastest"), "solver"),
    ]
    for call, name in cases:
        with pytest.raises(sheetform.InvalidInputError) as error:
            call()
        assert name in str(error.value), str(error.value)
        assert "--" not in str(error.value), f"a CLI flag rather than the keyword: {error.value}"


def test_a_closed_mesh_flattened_without_charts_is_refused_with_the_reason():
    import trimesh

    box = trimesh.creation.box()
    with pytest.raises(sheetform.InvalidInputError, match="disk"):
        sheetform.flatten(box.vertices, box.faces, charts="never")


def test_writing_over_a_file_raises_an_output_error(tmp_path):
    run = sheetform.bend(REPO / "examples/bent-rectangle.json", outputs="preview")
    blocker = tmp_path / "out"
    blocker.write_text("a file, not a directory")
    with pytest.raises(sheetform.OutputError, match="not a directory"):
        run.write(blocker)
    assert blocker.read_text() == "a file, not a directory"


def test_a_restoration_that_does_not_converge_says_so_in_its_outcome():
    # (Not an exception, as for the CLI, which writes the result and exits with 5: the
    # report says how far the restoration came.)
    scene = example("examples/ffd/two-panels.json")
    scene.setdefault("solver", {})["max_iterations"] = 1
    run = sheetform.ffd(scene, outputs="preview")
    assert run.report["status"] == "not converged"
    assert run.outcome == "out_of_tolerance"


def test_progress_is_reported_and_an_exception_in_it_stops_the_run():
    seen = []
    run = sheetform.ffd(REPO / "examples/ffd/two-panels.json", outputs="preview", progress=lambda s, f: seen.append((s, f)))
    assert run.outcome == "ok"
    fractions = [f for _, f in seen]
    assert fractions == sorted(fractions) and fractions[0] == 0.0 and fractions[-1] == 1.0
    assert any("iteration" in stage for stage, _ in seen), seen

    class Stop(Exception):
        pass

    def stop(stage, fraction):
        raise Stop(stage)

    with pytest.raises(Stop):
        sheetform.ffd(REPO / "examples/ffd/two-panels.json", progress=stop)


def test_ctrl_c_cancels_a_run_and_the_interpreter_goes_on():
    import os
    import signal

    calls = []

    def interrupt_once(stage, fraction):
        calls.append(stage)
        if len(calls) == 1:
            os.kill(os.getpid(), signal.SIGINT)

    with pytest.raises(KeyboardInterrupt):
        sheetform.ffd(REPO / "examples/ffd/two-panels.json", progress=interrupt_once)
    # It stopped at the next report, not at the end.
    assert len(calls) == 1, calls
    assert sheetform.ffd(REPO / "examples/ffd/two-panels.json", outputs="preview").outcome == "ok"


def test_the_ffd_photo_and_slit_bad_inputs_of_the_cli_tests(tmp_path):
    # A non-manifold panel in a mesh file: three faces on one edge.
    (tmp_path / "fan.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\ng fan\nf 1 2 3\nf 2 1 4\nf 1 2 5\n")
    duct = {"model": {"procedural": {"kind": "duct"}}}
    cases = [
        ({"model": {"mesh": "fan.obj"}, "deformations": [{"edits": []}]}, "non-manifold"),
        ({**duct, "lattice": {"degrees": [3, 3, 3], "counts": [3, 4, 4]}, "deformations": [{"edits": []}]}, "lattice.counts[0]"),
        (
            {**duct, "lattice": {"box_min": [-100, -100, 0], "box_max": [50, 100, 300]}, "deformations": [{"edits": []}]},
            "outside the lattice volume",
        ),
        (
            {**duct, "deformations": [{"edits": [{"move": {"points": [[9, 0, 0]], "by": [1, 0, 0]}}]}]},
            "deformations[0].edits[0].move.points[0]",
        ),
        ({**duct, "deformations": [{"edits": []}], "model": {"mesh": "../fan.obj"}}, "model"),
    ]
    for scene, expected in cases:
        with pytest.raises(sheetform.InvalidInputError) as error:
            sheetform.ffd(scene, root=tmp_path)
        assert expected in str(error.value), str(error.value)

    good = example("examples/photo/synthetic/cone-ortho.json")
    for change, expected in [
        ({"image": {**good["image"], "width": 481}}, "480 × 480"),
        ({"true_size": {**good["true_size"], "length": 0}}, "true_size.length"),
        ({"self_symmetric_curves": ["rim", "bottom", "rim"]}, "self_symmetric_curves"),
    ]:
        with pytest.raises(sheetform.InvalidInputError) as error:
            sheetform.photo({**good, **change}, root=REPO / "examples/photo/synthetic")
        assert expected in str(error.value), str(error.value)

    bench = example("examples/slit/bench.json")
    joint = copy.deepcopy(bench)
    joint["sheet"].update(strip_count=60, l4_slit_width=1)
    joint["solver"] = {"mode": "joint"}
    with pytest.raises(sheetform.InvalidInputError, match="joint mode"):
        sheetform.slit(joint)


def test_keywords_named_before_the_cli_vocabulary_are_refused_with_their_new_name():
    """One vocabulary (issue 39): the keywords are the CLI's flags (`--kerf` is `kerf`,
    `--units` is `units`); the old names are refused naming the new one, not ignored."""
    v = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
    f = [[0, 1, 2]]
    for call, old, new in [
        (lambda: sheetform.PatternOptions(kerf_mm=0.2), "kerf_mm", "kerf"),
        (lambda: sheetform.PatternOptions(units="in"), "units", "pattern_units"),
        (lambda: sheetform.flatten(v, f, pattern={"tab_width_mm": 7.0}), "tab_width_mm", "tab_width"),
        (lambda: sheetform.flatten(v, f, unit="cm"), "unit", "units"),
        (lambda: sheetform.develop(v, f, unit="cm"), "unit", "units"),
        (lambda: sheetform.check(v, f, unit="cm"), "unit", "units"),
    ]:
        with pytest.raises(sheetform.InvalidInputError, match=f"^{old}: is now `{new}`, the name of the CLI's --{new.replace('_', '-')}"):
            call()
    # Renamed to a keyword that is not a flag of the same name: what it is now.
    with pytest.raises(sheetform.InvalidInputError, match=r"^seams: is now `drawn_seams`, the seam edges an OBJ draws"):
        sheetform.flatten(v, f, seams=[[0, 1]])
    with pytest.raises(sheetform.InvalidInputError, match=r'^automatic_seams: is now `seams`, `"automatic"` or `"drawn"`'):
        sheetform.develop(v, f, automatic_seams=False)
    # A keyword that never existed is Python's own error.
    with pytest.raises(TypeError, match="unexpected keyword argument 'colour'"):
        sheetform.flatten(v, f, colour="red")
