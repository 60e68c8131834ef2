"""hullmap.build's keywords are `hullmap build`'s options by their library names: the same run writes
the same directory (every file byte for byte; report.json but for its timings and peak memory)."""
import json
import os
import warnings

import numpy as np
import pytest

import hullmap
from conftest import fresh_dir, run_cli

POINTS = "maps/simple/map_points.txt"
TRAJECTORY = "maps/simple/KeyFrameTrajectory.txt"


def report_without_times(path):
    # Warnings are the same codes in each front end's words (the CLI's flags, the module's keywords):
    # compared by number here, in words in test_warnings_are_the_clis_in_keywords_and_go_into_the_report.
    report = json.loads(path.read_text())
    del report["timings_ms"], report["peak_rss_mb"]
    report["warnings"] = len(report["warnings"])
    return report


def assert_same_outputs(cli_dir, py_dir):
    names = sorted(os.listdir(cli_dir))
    assert names == sorted(os.listdir(py_dir))
    for name in names:
        if name == "report.json":
            assert report_without_times(cli_dir / name) == report_without_times(py_dir / name)
        else:
            assert (cli_dir / name).read_bytes() == (py_dir / name).read_bytes(), name


CASES = {
    "tour": (["--up", "-y", "--eps", "0.12", "--min-pts", "5"], dict(up="-y", eps=0.12, min_pts=5)),
    "trajectory_words": (
        ["--trajectory", TRAJECTORY, "--up", "-y", "--resolution", "0.1", "--floor", "none", "--concavity", "none",
         "--metric", "xy", "--extension", "off"],
        dict(trajectory=TRAJECTORY, up="-y", resolution=0.1, floor="none", concavity="none", metric="xy",
             extension=False)),
    "sensor_model": (
        ["--trajectory", TRAJECTORY, "--up", "-y", "--max-range", "6", "--miss", "0.35", "--hit", "0.8",
         "--clamp-min", "0.2", "--clamp-max", "0.95", "--occupancy-threshold", "0.6", "--extension", "on",
         "--concavity", "0.2", "--flat-gap", "0.25", "--eps", "0.15"],
        dict(trajectory=TRAJECTORY, up="-y", max_range=6, miss=0.35, hit=0.8, clamp_min=0.2, clamp_max=0.95,
             occupancy_threshold=0.6, extension="on", concavity=0.2, flat_gap=0.25, eps=0.15)),
    "filters": (
        ["--up", "-y", "--scale", "1.5", "--crop", "-5,-5,-1,5,5,3", "--z-min", "0.1", "--z-max", "2.5",
         "--ceiling", "2.4", "--floor", "0.05", "--min-pts", "8", "--ot"],
        dict(up="-y", scale=1.5, crop=(-5, -5, -1, 5, 5, 3), z_min=0.1, z_max=2.5, ceiling=2.4, floor=0.05,
             min_pts=np.int64(8), write_ot=True)),
    "stray_parts": (["--trajectory", TRAJECTORY, "--up", "-y", "--stray-parts", "0"],
                    dict(trajectory=TRAJECTORY, up="-y", stray_parts=0)),
    "sparse_edges": (["--trajectory", TRAJECTORY, "--up", "-y", "--sparse-edges", "off"],
                     dict(trajectory=TRAJECTORY, up="-y", sparse_edges=False)),
    "level": (["--up", "-y", "--level", "off", "--eps", "0.12", "--min-pts", "5"],
              dict(up="-y", level=False, eps=0.12, min_pts=5)),
    "origin": (["--origin", "0,1,0", "--up", "-y", "--eps", "auto", "--min-pts", "auto"],
               dict(origin=(0, 1, 0), up="-y", eps="auto", min_pts="auto")),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_build_writes_what_the_cli_writes(case):
    cli_args, keywords = CASES[case]
    cli_dir, py_dir = fresh_dir(f"keywords_{case}_cli"), fresh_dir(f"keywords_{case}_py")
    done = run_cli("build", POINTS, *cli_args, "-o", cli_dir)
    assert done.returncode == 0, done.stderr
    hullmap.build(POINTS, **keywords).save(py_dir)
    assert_same_outputs(cli_dir, py_dir)


def test_warnings_are_the_clis_in_keywords_and_go_into_the_report():
    # No up on files named as ORB-SLAM names its own: the CLI's frame hint, as a BuildWarning that
    # names the keyword (up='-y') where the CLI names its flag (--up -y).
    cli_dir, py_dir = fresh_dir("warnings_cli"), fresh_dir("warnings_py")
    done = run_cli("build", POINTS, "--trajectory", TRAJECTORY, "-o", cli_dir)
    assert done.returncode == 0, done.stderr
    cli_warnings = [line.removeprefix("hullmap: warning: ") for line in done.stderr.splitlines()]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        built = hullmap.build(POINTS, trajectory=TRAJECTORY)
    got = [str(w.message) for w in caught if issubclass(w.category, hullmap.BuildWarning)]
    assert "it likely needs --up -y (--up was left at z)" in cli_warnings[0]
    assert got == [w.replace("--up -y", "up='-y'").replace("--up was", "up was") for w in cli_warnings[:1]] + \
        cli_warnings[1:], (got, cli_warnings)
    assert not any("--" in w for w in got)
    assert built.report["warnings"] == got
    built.save(py_dir)
    assert_same_outputs(cli_dir, py_dir)
    assert json.loads((py_dir / "report.json").read_text())["warnings"] == got
    # Warnings as errors stop the build there, with the warning as the exception.
    with warnings.catch_warnings():
        warnings.simplefilter("error", hullmap.BuildWarning)
        with pytest.raises(hullmap.BuildWarning):
            hullmap.build(POINTS, trajectory=TRAJECTORY)


def test_an_octree_file_builds_as_the_cli_builds_it():
    source = fresh_dir("octree_source")
    hullmap.build(POINTS, up="-y", eps=0.12, min_pts=5).save(source)
    cli_dir, py_dir = fresh_dir("octree_cli"), fresh_dir("octree_py")
    done = run_cli("build", source / "map.bt", "--eps", "0.12", "--min-pts", "5", "-o", cli_dir)
    assert done.returncode == 0, done.stderr
    built = hullmap.build(str(source / "map.bt"), eps=0.12, min_pts=5)
    built.save(py_dir)
    assert_same_outputs(cli_dir, py_dir)
    assert built.resolution == 0.05


def test_points_in_memory_make_the_same_obstacles_as_their_file():
    # The input frame's points (read_points with the default up) and a trajectory array: the same
    # octree and obstacles; report.json then names the arrays by their keywords.
    points = hullmap.read_points(POINTS)
    trajectory = np.loadtxt(TRAJECTORY, ndmin=2)
    from_file = hullmap.build(POINTS, trajectory=TRAJECTORY, up="-y", eps=0.12, min_pts=5)
    from_arrays = hullmap.build(points, trajectory=trajectory, up="-y", eps=0.12, min_pts=5)
    a, b = fresh_dir("memory_file"), fresh_dir("memory_arrays")
    from_file.save(a)
    from_arrays.save(b)
    assert (a / "map.bt").read_bytes() == (b / "map.bt").read_bytes()
    assert (a / "voxels.csv").read_bytes() == (b / "voxels.csv").read_bytes()
    assert json.loads((a / "obstacles.json").read_text())["obstacles"] == \
        json.loads((b / "obstacles.json").read_text())["obstacles"]
    report = from_arrays.report
    assert report["inputs"] == [{"path": "points", "format": "memory", "points_read": len(points),
                                 "points_dropped": {}}]
    assert report["parameters"]["trajectory"] == "trajectory"
    # A list of files is their union, as several inputs on the command line.
    half = fresh_dir("memory_union")
    half.mkdir()
    rows = np.loadtxt(POINTS, ndmin=2)
    np.savetxt(half / "a.txt", rows[: len(rows) // 2])
    np.savetxt(half / "b.txt", rows[len(rows) // 2:])
    union = hullmap.build([str(half / "a.txt"), half / "b.txt"], up="-y", eps=0.12, min_pts=5)
    whole = hullmap.build(POINTS, up="-y", eps=0.12, min_pts=5)
    assert [o.voxel_count for o in union.obstacles] == [o.voxel_count for o in whole.obstacles]
    assert union.report["parameters"]["inputs"] == [str(half / "a.txt"), str(half / "b.txt")]
