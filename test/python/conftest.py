"""Shared fixtures of the Python module's tests (test/python), run by CTest (test/python/CMakeLists.txt).

CTest passes the paths in the environment: PYTHONPATH (the build's python/ directory),
HULLMAP_SOURCE_DIR, HULLMAP_BINARY (the CLI), HULLMAP_REAL_DATA_DIR (shared/data/real),
HULLMAP_TEST_TMP (scratch space in the build tree), HULLMAP_BUILD_DIR and HULLMAP_CMAKE (for the
install test). Run by hand: `PYTHONPATH=build/python python3 -m pytest test/python` from the checkout
takes the same defaults.
"""
import json
import os
import shutil
import subprocess
from pathlib import Path

import pytest

SOURCE = Path(os.environ.get("HULLMAP_SOURCE_DIR", Path(__file__).resolve().parents[2]))
BUILD = Path(os.environ.get("HULLMAP_BUILD_DIR", SOURCE / "build"))
BINARY = Path(os.environ.get("HULLMAP_BINARY", BUILD / "cli" / "hullmap"))
REAL = Path(os.environ.get("HULLMAP_REAL_DATA_DIR", SOURCE.parent / "shared" / "data" / "real"))
TMP = Path(os.environ.get("HULLMAP_TEST_TMP", BUILD / "test" / "tmp"))

# The CLI's build of maps/room at its defaults, as the README's demo runs it.
ROOM = ["maps/room/map_points.txt", "--trajectory", "maps/room/KeyFrameTrajectory.txt", "--align",
        "maps/room/reference_trajectory.txt"]


def run_cli(*args, check=True):
    """Runs the hullmap CLI from the source directory (so that paths in its outputs are relative, as
    the Python calls give them); returns the CompletedProcess."""
    done = subprocess.run([str(BINARY), *map(str, args)], cwd=SOURCE, capture_output=True, text=True)
    if check and done.returncode not in (0, 1):
        raise AssertionError(f"hullmap {' '.join(map(str, args))} exited {done.returncode}: {done.stderr}")
    return done


def fresh_dir(name):
    """An empty scratch directory (its parent made), named after the test."""
    path = TMP / "python" / name
    shutil.rmtree(path, ignore_errors=True)
    path.parent.mkdir(parents=True, exist_ok=True)
    return path


def check_json(directory, radius, *args):
    """`hullmap check DIR --radius R ARGS --json`, one dict a segment."""
    out = run_cli("check", directory, "--radius", radius, *args, "--json").stdout
    return [json.loads(line) for line in out.splitlines() if '"index"' in line]


@pytest.fixture(autouse=True, scope="session")
def in_source_dir():
    """Relative paths (maps/room/...) name the same files for the module and the CLI, in every
    fixture too."""
    before = os.getcwd()
    os.chdir(SOURCE)
    yield
    os.chdir(before)


@pytest.fixture(scope="session")
def room_cli():
    """The CLI's output directory for maps/room at its defaults, made once per run."""
    out = fresh_dir("room_cli")
    done = run_cli("build", *ROOM, "-o", out)
    assert done.returncode == 0, done.stderr
    return out


def real_file(name):
    """A file of shared/data/real, or a skip saying it is missing."""
    path = REAL / name
    if not path.is_file():
        pytest.skip(f"real data missing: {path} (set HULLMAP_REAL_DATA_DIR; see shared/data/real/SOURCES.md)")
    return path
