"""Fixtures of the mspline Python tests: the meshes, the mspline executable, a fitted model.

MSPLINE_DATA_DIR (the folder of the .off meshes) and MSPLINE_CLI (the mspline executable) are set
by ctest; run by hand, they default to the repository's data/meshes and build/cli/mspline.
"""

import os
import pathlib
import subprocess

import pytest

import mspline

REPOSITORY = pathlib.Path(__file__).resolve().parents[2]
# A small budget and one refinement keep a fit of eight.off to about a second.
FIT_ARGUMENTS = {"max_control": 800, "max_refinements": 1}
# eight's cones are a few cells apart at 800 control points: the T-spline's cells split around
# them for caps need more.
TSPLINE_FIT_ARGUMENTS = {**FIT_ARGUMENTS, "max_control": 1200}


def cli_options(options):
    """The mspline fit options of Python keyword arguments."""
    return [f"--{name.replace('_', '-')}={value}" for name, value in options.items()]


@pytest.fixture(scope="session")
def data_dir():
    return pathlib.Path(os.environ.get("MSPLINE_DATA_DIR", REPOSITORY / "data" / "meshes"))


@pytest.fixture(scope="session")
def eight(data_dir):
    """eight.off (a closed surface of genus 2) as arrays."""
    return mspline.read_mesh(data_dir / "eight.off")


@pytest.fixture(scope="session")
def cli():
    path = pathlib.Path(os.environ.get("MSPLINE_CLI", REPOSITORY / "build" / "cli" / "mspline"))
    if not path.exists():
        pytest.fail(f"the mspline executable is not at {path} (set MSPLINE_CLI)")
    return path


@pytest.fixture(scope="session")
def cli_fit(cli, data_dir, tmp_path_factory):
    """`mspline fit` of eight.off with (TSPLINE_)FIT_ARGUMENTS and a kind: the model file's path
    (its --json report next to it, .json)."""
    paths = {}

    def fit(kind):
        if kind not in paths:
            path = tmp_path_factory.mktemp("cli") / f"eight-{kind}.msp"
            run = subprocess.run([str(cli), "fit", str(data_dir / "eight.off"), "-o", str(path),
                                  "--quiet", "--json", f"--kind={kind}",
                                  *cli_options(TSPLINE_FIT_ARGUMENTS if kind == "tspline"
                                               else FIT_ARGUMENTS)],
                                 check=True, capture_output=True, text=True)
            path.with_suffix(".json").write_text(run.stdout)
            paths[kind] = path
        return paths[kind]

    return fit


@pytest.fixture(scope="session")
def eight_msp(cli_fit):
    """eight.off fitted by `mspline fit` (a T-spline with TSPLINE_FIT_ARGUMENTS)."""
    return cli_fit("tspline")
