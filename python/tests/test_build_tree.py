"""The package as the build tree holds it (PYTHONPATH=build/<preset>/python, the harness
tests/python/python_test.sh): the module and the program of one build are one version, and the
module finds the source tree's data and examples from its own location, with no
LATHECTL_DATA_DIR nor LATHECTL_EXAMPLES_DIR (the installed package's case is
tests/package/package_test.sh's)."""
import os
import pathlib
import subprocess

import pytest

import lathectl
from lathectl import _lathectl

PACKAGE = pathlib.Path(lathectl.__file__).resolve().parent  # build/<preset>/python/lathectl
BUILD = PACKAGE.parent.parent
SOURCE = pathlib.Path(__file__).resolve().parents[2]


def test_package_is_the_build_trees():
    assert pathlib.Path(_lathectl.__file__).resolve().parent == PACKAGE
    assert pathlib.Path(os.environ["PYTHONPATH"]).resolve() == PACKAGE.parent
    # (the harness passes LATHECTL, the program, and the outputs to compare with; nothing that
    # would move the data)
    assert "LATHECTL_DATA_DIR" not in os.environ and "LATHECTL_EXAMPLES_DIR" not in os.environ


def test_same_version_as_the_program():
    program = BUILD / "lathectl"
    if not program.exists() or program.stat().st_mtime < os.stat(_lathectl.__file__).st_mtime:
        pytest.skip(f"{program} not built, or older than the module (only _lathectl rebuilt)")
    out = subprocess.run([program, "--version"], check=True, capture_output=True, text=True)
    assert out.stdout.strip() == f"lathectl {lathectl.__version__} (commit {_lathectl.commit})"


def test_data_and_examples_from_the_source_tree():
    assert pathlib.Path(lathectl.data_dir()).resolve() == SOURCE / "data"
    assert (pathlib.Path(lathectl.data_dir()) / "materials.toml").is_file()
    examples = pathlib.Path(lathectl.examples_dir()).resolve()
    assert examples == SOURCE / "examples" / "scenarios"
    assert (examples / "c_csv_template.toml").is_file()
