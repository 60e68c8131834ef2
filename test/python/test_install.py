"""The module installed as a user installs it: `cmake --install` puts the package into the
interpreter's package directory under the prefix; `pip install --no-build-isolation .` builds and
installs it offline (no package index) into a virtual environment. Each then imports and builds,
from another directory, without the build tree on its path."""
import os
import subprocess
import sys
import sysconfig
from pathlib import Path

import pytest

from conftest import BUILD, SOURCE, fresh_dir

CMAKE = os.environ.get("HULLMAP_CMAKE", "cmake")

USE = """
import sys, hullmap
print(hullmap.__file__)
m = hullmap.build(sys.argv[1], up="-y", eps=0.12, min_pts=5)
print(len(m.obstacles))
"""


def run_python(python, env, cwd):
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"} | env
    done = subprocess.run([str(python), "-c", USE, str(SOURCE / "maps/simple/map_points.txt")], cwd=cwd, env=env,
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    file, obstacles = done.stdout.split()
    return Path(file), int(obstacles)


def expected_obstacles():
    import hullmap
    return len(hullmap.build("maps/simple/map_points.txt", up="-y", eps=0.12, min_pts=5).obstacles)


def test_cmake_install_puts_the_package_in_the_interpreters_directory():
    prefix = fresh_dir("install_prefix")
    done = subprocess.run([CMAKE, "--install", str(BUILD), "--prefix", str(prefix), "--component", "python"],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    paths = sysconfig.get_paths()
    site = prefix / os.path.relpath(paths["platlib"], paths["data"])
    assert sorted(p.name.split(".")[0] for p in (site / "hullmap").iterdir()) == ["__init__", "_hullmap"]
    file, obstacles = run_python(sys.executable, {"PYTHONPATH": str(site)}, prefix)
    assert file == site / "hullmap" / "__init__.py"
    assert obstacles == expected_obstacles() > 0


def test_pip_installs_offline_into_a_virtual_environment():
    for module in ("venv", "pip"):
        if subprocess.run([sys.executable, "-c", f"import {module}"], capture_output=True).returncode != 0:
            pytest.skip(f"{module} is not importable (Debian's python3-{module})")
    venv = fresh_dir("pip_venv")
    # The system's pip, setuptools and numpy seen from the environment; nothing is downloaded.
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", "--without-pip", str(venv)], check=True)
    python = venv / "bin" / "python"
    done = subprocess.run([str(python), "-m", "pip", "install", "--no-build-isolation", "--no-index", "--quiet",
                           str(SOURCE)], capture_output=True, text=True, env=os.environ | {"JOBS": "2"})
    assert done.returncode == 0, done.stdout + done.stderr
    file, obstacles = run_python(python, {}, venv)
    assert file.is_relative_to(venv) and file.name == "__init__.py"
    assert obstacles == expected_obstacles() > 0
