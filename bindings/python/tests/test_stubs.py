"""The type stubs (`sheetform/_native.pyi`) describe the module as built: mypy's stubtest
compares every name, signature and default with the runtime's."""

import os
import subprocess
import sys
from pathlib import Path

from conftest import REPO


def test_the_stubs_match_the_native_module():
    # (The installed package's own stubs: the ones a user's type checker reads.)
    environment = dict(os.environ)
    done = subprocess.run(
        [sys.executable, "-m", "mypy.stubtest", "sheetform._native", "--concise"],
        capture_output=True,
        text=True,
        env=environment,
        check=False,
    )
    assert done.returncode == 0, done.stdout + done.stderr


def test_the_example_type_checks_against_the_stubs():
    environment = dict(os.environ)
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "mypy",
            "--ignore-missing-imports",
            "--follow-imports=silent",
            str(REPO / "examples/python/bend_and_flatten.py"),
        ],
        capture_output=True,
        text=True,
        env=environment,
        check=False,
    )
    assert done.returncode == 0, done.stdout + done.stderr


def test_the_package_under_test_is_an_installed_one_not_the_source_tree():
    """CI installs the wheel into a fresh environment and tests that (issue 39): the
    package imported here must not be bindings/python/python of this checkout."""
    import sheetform

    source = (REPO / "bindings/python/python").resolve()
    assert source not in Path(sheetform.__file__).resolve().parents
