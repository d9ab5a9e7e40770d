"""The four systems from Python give what the CLI gives on the same scenes: positions,
flat pattern and faces of the model, every report figure to 1e-12, and the same files."""

import json
from pathlib import Path

import numpy as np
import pytest

import sheetform
from conftest import REPO, assert_close, read_obj, read_report, without_timings, y_up

# (function, CLI command, scene path relative to the repository, up axis of its OBJ)
SCENES = [
    (sheetform.bend, "bend", "examples/desk.json", "z"),
    (sheetform.bend, "bend", "examples/textured-sheet.json", "z"),
    (sheetform.slit, "slit", "examples/slit/chair.json", "y"),
    (sheetform.ffd, "ffd", "examples/ffd/two-panels.json", "z"),
    (sheetform.photo, "photo", "examples/photo/tube.json", "y"),
]


@pytest.fixture(scope="module")
def cli_outputs(cli, tmp_path_factory):
    """Each scene run once by the CLI, into its own directory."""
    outputs = {}
    for _, command, scene, _ in SCENES:
        out = tmp_path_factory.mktemp(command)
        done = cli(command, scene, "-o", out)
        assert done.returncode == 0, done.stderr
        outputs[scene] = out
    return outputs


@pytest.mark.parametrize("function,command,scene,up_axis", SCENES, ids=[s[2] for s in SCENES])
def test_a_system_from_python_equals_the_cli(function, command, scene, up_axis, cli_outputs, monkeypatch):
    monkeypatch.chdir(REPO)
    run = function(scene)
    out = cli_outputs[scene]
    # The report: every figure, the same status and outputs.
    assert_close(without_timings(run.report), without_timings(read_report(out)))
    assert run.outcome == "ok"
    assert run.report["status"] == "ok"
    # The model: positions, faces and the flat pattern at 1:1, as in the CLI's OBJ.
    v, vt, f = read_obj(out / "model.obj")
    np.testing.assert_allclose(y_up(run.vertices, up_axis), v, rtol=0, atol=1e-12 * max(1.0, np.abs(v).max()))
    np.testing.assert_allclose(run.uv, vt, rtol=0, atol=1e-12 * max(1.0, np.abs(vt).max()))
    # (The OBJ lists the faces piece by piece, each piece's in their order.)
    np.testing.assert_array_equal(run.faces[np.argsort(run.face_pieces, kind="stable")], f)
    assert run.vertices.shape == (len(v), 3) and run.uv.shape == (len(v), 2)
    assert run.faces.dtype == np.int64 and run.vertices.dtype == np.float64
    assert run.face_pieces.shape == (len(f),)
    assert run.face_pieces.max() == len(run.pieces) - 1
    # The files the CLI wrote, byte for byte (the PDF carries no date either).
    for name, data in run.files.items():
        assert data == (out / name).read_bytes(), name
    assert sorted([*run.files, "report.json"]) == sorted(run.report["outputs"])


def test_a_scene_as_a_dict_gives_the_same_model_as_its_file(monkeypatch):
    monkeypatch.chdir(REPO)
    scene = json.loads((REPO / "examples/desk.json").read_text())
    from_dict = sheetform.bend(scene)
    from_file = sheetform.bend(REPO / "examples/desk.json")
    np.testing.assert_array_equal(from_dict.vertices, from_file.vertices)
    np.testing.assert_array_equal(from_dict.uv, from_file.uv)
    assert from_dict.report["input"] is None
    assert from_file.report["input"].endswith("desk.json")


def test_the_flat_pattern_is_an_isometry_of_the_bent_sheet():
    run = sheetform.bend(REPO / "examples/bent-rectangle.json", outputs="preview")
    edges = np.concatenate([run.faces[:, [0, 1]], run.faces[:, [1, 2]], run.faces[:, [2, 0]]])
    length_3d = np.linalg.norm(run.vertices[edges[:, 0]] - run.vertices[edges[:, 1]], axis=1)
    length_flat = np.linalg.norm(run.uv[edges[:, 0]] - run.uv[edges[:, 1]], axis=1)
    assert np.abs(length_3d - length_flat).max() < 1e-9 * length_3d.max()
    assert np.abs(run.angle_defects_rad).max() < 1e-9
    assert sorted(run.files) == ["model.glb", "pattern.svg"]


def test_animate_writes_the_cli_frames_from_flat_to_bent(cli, tmp_path, monkeypatch):
    """`animate=N` is `--animate N`: the same N frame files, the first flat (its points on
    one plane, the sheet before bending), the last the bent model; `animate_frames`, its
    old name, is refused naming the new one."""
    monkeypatch.chdir(REPO)
    scene = "examples/bent-rectangle.json"
    run = sheetform.bend(scene, animate=3)
    frames = sorted(name for name in run.files if name.startswith("frames/"))
    assert frames == ["frames/frame-0000.obj", "frames/frame-0001.obj", "frames/frame-0002.obj"]
    done = cli("bend", scene, "-o", tmp_path, "--animate", "3")
    assert done.returncode == 0, done.stderr
    for name in frames:
        assert run.files[name] == (tmp_path / name).read_bytes(), name
    first, _, _ = read_obj(tmp_path / frames[0])
    last, _, _ = read_obj(tmp_path / frames[-1])
    bent, _, _ = read_obj(tmp_path / "model.obj")
    # The first frame is the sheet flat: its points on one plane (however it is placed).
    assert np.linalg.svd(first - first.mean(0), compute_uv=False)[2] < 1e-9 * np.ptp(first), "the first frame is flat"
    np.testing.assert_allclose(last, bent, rtol=0, atol=1e-9 * np.abs(bent).max())
    with pytest.raises(sheetform.InvalidInputError, match="^animate_frames: is now `animate`, the name of the CLI's --animate"):
        sheetform.bend(scene, animate_frames=3)


def test_write_puts_the_cli_files_into_a_directory(tmp_path):
    run = sheetform.slit(REPO / "examples/slit/chair.json", outputs="preview")
    run.write(tmp_path / "chair")
    written = sorted(p.name for p in (tmp_path / "chair").iterdir())
    assert written == sorted(run.report["outputs"])
    assert json.loads((tmp_path / "chair" / "report.json").read_text()) == run.report


def test_arrays_are_made_once_and_owned_by_numpy():
    run = sheetform.bend(REPO / "examples/bent-rectangle.json", outputs="preview")
    assert run.vertices is run.vertices, "the same array on every access"
    assert run.files is run.files
    for array in (run.vertices, run.faces, run.uv, run.face_pieces, run.angle_defects_rad):
        assert array.flags["C_CONTIGUOUS"]


def test_an_ffd_run_has_its_welded_panels_before_and_after_the_restoration():
    run = sheetform.ffd(REPO / "examples/ffd/skirt.json", outputs="preview")
    plain, restored = run.meshes["plain"], run.meshes["restored"]
    assert plain.vertices.shape == restored.vertices.shape
    np.testing.assert_array_equal(plain.faces, restored.faces)
    after = run.report["ffd"]["angle_defects_after"]["angle_defect_max_rad"]
    before = run.report["ffd"]["angle_defects_before"]["angle_defect_max_rad"]
    assert np.isclose(np.abs(restored.angle_defects_rad).max(), after, rtol=1e-12, atol=1e-15)
    assert np.isclose(np.abs(plain.angle_defects_rad).max(), before, rtol=1e-12)
    assert after < 1e-8 < before
    assert sheetform.bend(REPO / "examples/bent-rectangle.json", outputs="preview").meshes == {}


def test_a_warm_started_ffd_run_restores_only_the_new_deformation_with_the_same_result():
    two = json.loads((REPO / "examples/ffd/skirt-drag.json").read_text())
    one = {**two, "deformations": two["deformations"][:1]}
    first = sheetform.ffd(one, root=REPO / "examples/ffd", outputs="preview")
    warm = sheetform.ffd(two, root=REPO / "examples/ffd", outputs="preview", warm_start=first)
    cold = sheetform.ffd(two, root=REPO / "examples/ffd", outputs="preview")
    assert warm.report["ffd"]["resumed_deformations"] == 1
    assert cold.report["ffd"]["resumed_deformations"] == 0
    np.testing.assert_array_equal(warm.vertices, cold.vertices)
    np.testing.assert_array_equal(warm.uv, cold.uv)
    with pytest.raises(sheetform.InvalidInputError, match="warm_start"):
        sheetform.ffd(two, root=REPO / "examples/ffd", warm_start=sheetform.bend(REPO / "examples/bent-rectangle.json"))


@pytest.mark.parametrize(
    "command,source,flags,options",
    [
        ("bend", "examples/desk.json", ["--scale", "0.5", "--page", "letter", "--pattern-units", "in"], {"scale": 0.5, "page": "letter", "pattern_units": "in"}),
        # tube.json has a seam (tabs, seam allowance) and folds (thickness).
        ("bend", "examples/tube.json", ["--tabs", "alternate", "--tab-width", "7", "--tab-angle", "60", "--sheet", "900x1200", "--kerf", "0.2"], {"tabs": "alternate", "tab_width": 7.0, "tab_angle": 60.0, "sheet": (900, 1200), "kerf": 0.2}),
        ("bend", "examples/tube.json", ["--seam-allowance", "10", "--no-notches", "--grain-lines"], {"seam_allowance": 10.0, "notches": False, "grain_lines": True}),
        ("flatten", "examples/meshes/gift-box.obj", ["--thickness", "1.5", "--k-factor", "0.33", "--bend-radius", "2", "--tabs", "none"], {"thickness": 1.5, "k_factor": 0.33, "bend_radius": 2.0, "tabs": "none"}),
        ("flatten", "examples/meshes/gift-box.obj", ["--tab-width", "8", "--tab-angle", "80"], {"tab_width": 8.0, "tab_angle": 80.0}),
        ("flatten", "examples/meshes/gift-box.obj", ["--tabs", "none"], {"tabs": "none"}),
    ],
    ids=["scale-page-units", "tabs-sheet-kerf", "allowance-grain", "thickness", "net-tab-size", "net-without-tabs"],
)
def test_pattern_options_give_the_cli_flags_files(command, source, flags, options, cli, tmp_path, monkeypatch):
    # One vocabulary (issue 39): each keyword is its flag's name (`--no-notches` is
    # `notches=False`).
    named = {f[2:].removeprefix("no-").replace("-", "_") for f in flags if f.startswith("--")}
    assert named == set(options), (named, set(options))
    monkeypatch.chdir(REPO)
    out = tmp_path / "out"
    done = cli(command, source, "-o", out, *flags)
    assert done.returncode == 0, done.stderr
    expected = read_report(out)
    written = sorted(name for name in expected["outputs"] if name != "report.json")
    for pattern in (options, sheetform.PatternOptions(**options)):
        if command == "bend":
            run = sheetform.bend(source, pattern=pattern)
        else:
            vertices, _, faces = read_obj(REPO / source)
            run = sheetform.flatten(vertices, faces, name=Path(source).stem, pattern=pattern)
            run.report.pop("input"), expected.pop("input", None)
        assert_close(without_timings(run.report), without_timings({k: v for k, v in expected.items()}))
        assert sorted(run.files) == written
        for name, data in run.files.items():
            assert data == (out / name).read_bytes(), name
    # The options change the pattern: the same scene without them gives other files.
    plain = sheetform.bend(source) if command == "bend" else sheetform.flatten(vertices, faces, name=Path(source).stem)
    assert plain.files["pattern.svg"] != run.files["pattern.svg"]


def test_a_photo_closed_round_its_axis_equals_the_cli(cli, tmp_path, monkeypatch):
    monkeypatch.chdir(REPO)
    scene = "examples/photo/coffee-cup.json"
    done = cli("photo", scene, "-o", tmp_path, "--back-side", "revolve")
    assert done.returncode == 0, done.stderr
    run = sheetform.photo(scene, back_side="revolve")
    assert_close(without_timings(run.report), without_timings(read_report(tmp_path)))
    assert len(run.report["photo"]["revolution"]["bands"]) == 1
    assert run.report["pattern"]["seam_count"] == 1 and run.report["pattern"]["tabs"]["placed"] == 1
    v, vt, f = read_obj(tmp_path / "model.obj")
    np.testing.assert_allclose(y_up(run.vertices, "y"), v, rtol=0, atol=1e-12 * max(1.0, np.abs(v).max()))
    # The visible half by default; a side that is neither is refused by name.
    assert "revolution" not in sheetform.photo(scene, outputs="preview").report["photo"]
    with pytest.raises(sheetform.InvalidInputError, match="back_side"):
        sheetform.photo(scene, back_side="mirror")
