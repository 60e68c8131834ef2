"""Every bad input raises hullmap.Error (a ValueError) with the library's message, and the interpreter
goes on: wrong shape or dtype, NaN or infinity, no rows, a non-contiguous view, bad parameters."""
import math
import subprocess
import sys

import numpy as np
import pytest

import hullmap

SIMPLE = "maps/simple/map_points.txt"


@pytest.fixture(scope="module")
def simple():
    return hullmap.build(SIMPLE, up="-y", eps=0.12, min_pts=5)


@pytest.fixture(scope="module")
def points():
    return hullmap.read_points(SIMPLE, up="-y")


def bad_arrays(columns):
    """(array, words its error must hold) for an argument taking (N, columns) float64 rows."""
    good = np.ones((4, columns))
    with_nan, with_inf = good.copy(), good.copy()
    with_nan[2, 1] = math.nan
    with_inf[3, 0] = -math.inf
    wide = np.ones((4, 2 * columns))
    return [
        (np.ones((4, columns + 1)), f"got shape (4, {columns + 1})"),
        (np.ones(columns), f"got shape ({columns},)"),
        (np.ones((2, 2, columns)), f"got shape (2, 2, {columns})"),
        (good.astype(np.float32), "got dtype float32"),
        (good.astype(np.int64), "got dtype int64"),
        (good.astype(object), "got dtype object"),
        (np.empty((0, columns)), "empty"),
        (wide[:, ::2], "non-contiguous"),
        (np.asfortranarray(np.ones((4, columns))), "non-contiguous"),
        ([[1.0, 2.0]] * 3, "got shape (3, 2)"),
        (with_nan, "not finite"),
        (with_inf, "not finite"),
    ]


def raises(words, call, *args, **kwargs):
    with pytest.raises(hullmap.Error) as caught:
        call(*args, **kwargs)
    assert isinstance(caught.value, ValueError)
    assert words in str(caught.value), str(caught.value)
    return caught.value


@pytest.mark.parametrize("array,words", bad_arrays(3))
def test_dbscan_refuses_bad_points(array, words):
    # NaN and infinity are refused by the library's DBSCAN ("dbscan: point 2 is not finite").
    raises(words, hullmap.dbscan, array, 0.1, 10)


@pytest.mark.parametrize("array,words", bad_arrays(3))
def test_build_refuses_bad_points(array, words):
    raises(words.replace("not finite", "NaN or an infinity"), hullmap.build, array)


@pytest.mark.parametrize("array,words", bad_arrays(6))
def test_check_refuses_bad_segments(simple, array, words):
    raises(words.replace("not finite", "non-finite"), simple.check, array, 0.2)


@pytest.mark.parametrize("array,words", bad_arrays(3))
def test_check_path_refuses_bad_waypoints(simple, array, words):
    raises(words.replace("not finite", "non-finite"), simple.check_path, array, 0.2)


@pytest.mark.parametrize("array,words", bad_arrays(8))
def test_build_refuses_a_bad_trajectory_array(points, array, words):
    raises(words.replace("not finite", "trajectory:"), hullmap.build, points, trajectory=array)


@pytest.mark.parametrize("array,words", bad_arrays(4))
def test_build_refuses_a_bad_align_array(points, array, words):
    trajectory = np.loadtxt("maps/simple/KeyFrameTrajectory.txt", ndmin=2)
    raises(words.replace("not finite", "align:"), hullmap.build, points, trajectory=trajectory, align=array)


def test_what_is_not_an_array_is_refused(simple):
    raises("got a str numpy cannot make one of", hullmap.dbscan, "not an array", 0.1, 5)
    raises("got a str numpy cannot make one of", simple.check, "not an array", 0.2)
    raises("got a dict numpy cannot make one of", simple.check_path, {"a": 1}, 0.2)
    # A string is a path where a path may stand.
    raises("not a file: cannot open", hullmap.build, "not a file")
    raises("not a file: cannot open", hullmap.build, np.ones((3, 3)), trajectory="not a file")


def test_the_names_in_messages_are_the_librarys(points, simple):
    assert raises("eps: must be a positive finite number", hullmap.dbscan, points, 0.0, 10).parameter == "eps"
    assert raises("min_pts: must be >= 1", hullmap.dbscan, points, 0.1, 0).parameter == "min_pts"
    assert raises("metric: expected xyz or xy", hullmap.dbscan, points, 0.1, 5, metric="xz").parameter == "metric"
    assert raises("radius: must be a finite number >= 0", simple.check, np.zeros((1, 6)), -1.0).parameter == "radius"
    raises("radius", simple.check, np.zeros((1, 6)), math.nan)
    raises("contact_tolerance", simple.check, np.zeros((1, 6)), 0.1, contact_tolerance=0.0)
    raises("against: expected 'hulls' or 'octree'", simple.check, np.zeros((1, 6)), 0.1, against="voxels")
    raises("up: expected one of x, -x", hullmap.read_points, SIMPLE, up="w")
    raises("scale: must be a finite number > 0", hullmap.read_points, SIMPLE, scale=-1.0)


@pytest.mark.parametrize("keywords,words", [
    ({"eps": -0.1}, "eps: must be a positive finite number"),
    ({"eps": "big"}, "eps: expected a number or 'auto'"),
    ({"eps": math.inf}, "eps: must be a positive finite number"),
    ({"min_pts": 0}, "min_pts: must be at least 1"),
    ({"min_pts": 2.5}, "min_pts: expected a whole number"),
    ({"min_pts": True}, "min_pts: expected a whole number"),
    ({"resolution": 0}, "resolution: must be a positive number"),
    ({"hit": 1.5}, "hit: must be a probability"),
    ({"clamp_min": 0.9, "clamp_max": 0.8}, "clamp_min/clamp_max"),
    ({"scale": 0}, "scale: must be a positive finite number"),
    ({"up": "q"}, "up: expected one of"),
    ({"up": 3}, "up: expected one of"),
    ({"metric": "manhattan"}, "metric: expected xyz or xy"),
    ({"floor": "sometimes"}, "floor: expected auto, none or a height"),
    ({"floor": math.nan}, "floor: height must be finite"),
    ({"ceiling": [1]}, "ceiling: expected 'auto', 'none' or a height"),
    ({"crop": (0, 0, 0, 1, 1)}, "crop: expected six numbers"),
    ({"crop": (1, 0, 0, 0, 1, 1)}, "crop: min corner exceeds max corner"),
    ({"concavity": -1}, "concavity: must be a finite number >= 0"),
    ({"concavity": "some"}, "concavity: expected a number, 'default' or 'none'"),
    ({"flat_gap": -1}, "flat_gap: must be a finite number >= 0"),
    ({"concavity": "none", "flat_gap": 0.1}, "flat_gap: applies only to convex parts"),
    ({"extension": "maybe"}, "extension: expected 'auto', True or False"),
    ({"stray_parts": -1}, "stray_parts: expected a whole number >= 0"),
    ({"stray_parts": 1.5}, "stray_parts: expected a whole number >= 0"),
    ({"stray_parts": True}, "stray_parts: expected a whole number >= 0"),
    ({"write_ot": 1}, "write_ot: expected True or False"),
    ({"level": "sometimes"}, "level: expected 'auto', True or False"),
    ({"camera_frame": "yes"}, "camera_frame: expected True, False or None"),
    ({"max_range": 3.0}, "max_range: applies only to free space cast along rays"),
    ({"miss": 0.3, "max_range": 2.0}, "max_range/miss: applies only"),
    ({"align_format": "gps"}, "align_format: applies only with align"),
    ({"align_model": "drift"}, "align_model: applies only with align"),
    ({"origin": (0, 0)}, "origin: expected three numbers"),
    ({"origin": (0, 0, math.nan)}, "origin: must be finite"),
    ({"origin": (0, 0, 0), "trajectory": "maps/simple/KeyFrameTrajectory.txt"}, "trajectory/origin: give one or the other"),
    ({"align": "maps/room/reference_trajectory.txt"}, "align: needs the keyframe trajectory"),
    ({"trajectory": "maps/simple/KeyFrameTrajectory.txt", "align": "maps/room/reference_trajectory.txt",
      "align_format": "kml"}, "align_format: expected 'tum' or 'gps'"),
    ({"trajectory": "no/such/trajectory.txt"}, "no/such/trajectory.txt"),
])
def test_build_refuses_bad_parameters(points, keywords, words):
    raises(words, hullmap.build, points, **keywords)


def test_build_names_a_bad_file_and_its_line(tmp_path):
    bad = tmp_path / "bad.txt"
    bad.write_text("1 2 3\n4 5\n")
    raises(f"{bad}:2:", hullmap.build, str(bad))
    raises(f"{bad}:2:", hullmap.read_points, bad)
    raises("no/such/file.txt", hullmap.read_points, "no/such/file.txt")
    raises("path: expected a path or a list of paths", hullmap.read_points, 42)


def test_an_octree_input_refuses_what_makes_an_octree(simple, tmp_path):
    out = tmp_path / "out"
    simple.save(out)
    raises("resolution/floor: cannot apply to", hullmap.build, str(out / "map.bt"), resolution=0.1, floor="none")


def test_an_unknown_keyword_is_a_type_error(points):
    with pytest.raises(TypeError, match="unexpected keyword argument 'epss'"):
        hullmap.build(points, epss=0.1)


def test_dbscan_refuses_bad_weights(points):
    n = len(points)
    raises("weights: 3 weights for", hullmap.dbscan, points, 0.1, 5, weights=np.ones(3, dtype=np.uint32))
    raises("weights: expected a (N,) array of positive integers", hullmap.dbscan, points, 0.1, 5, weights=np.ones(n))
    raises("weights: expected a (N,) array", hullmap.dbscan, points, 0.1, 5, weights=np.ones((n, 1), dtype=int))
    negative = np.ones(n, dtype=np.int64)
    negative[7] = -2
    raises("weight of point 7 is -2", hullmap.dbscan, points, 0.1, 5, weights=negative)
    zero = np.ones(n, dtype=np.uint16)
    zero[3] = 0
    raises("weight of point 3 is 0", hullmap.dbscan, points, 0.1, 5, weights=zero)


def test_plan_refuses_bad_requests(simple):
    raises("start: expected three numbers", simple.plan, (0, 0), (1, 1, 1), 0.2)
    raises("goal: must be finite", simple.plan, (0, 0, 1), (1, math.inf, 1), 0.2)
    raises("method: expected 'roadmap' or 'ompl'", simple.plan, (0, 0, 1), (1, 1, 1), 0.2, method="prm")
    raises("time_limit: applies only to method 'ompl'", simple.plan, (0, 0, 1), (1, 1, 1), 0.2, time_limit=1.0)
    raises("radius: must be a finite number >= 0", simple.plan, (0, 0, 1), (1, 1, 1), -0.2)
    raises("time_limit: must be > 0 and finite seconds", simple.plan, (0, 0, 1), (1, 1, 1), 0.2, method="ompl", time_limit=0.0)


def test_load_and_save_refuse_what_they_cannot_do(simple, tmp_path):
    raises("not a directory", hullmap.load, tmp_path / "absent")
    (tmp_path / "empty").mkdir()
    raises("obstacles.json", hullmap.load, tmp_path / "empty")
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "notes.txt").write_text("mine\n")
    raises(str(mine), simple.save, mine)
    assert (mine / "notes.txt").read_text() == "mine\n"
    raises(str(tmp_path / "a" / "b"), simple.save, tmp_path / "a" / "b")
    assert not (tmp_path / "a").exists()
    simple.save(tmp_path / "a" / "b", parents=True)
    loaded = hullmap.load(tmp_path / "a" / "b")
    raises("save: this Map was read from", loaded.save, tmp_path / "c")


def test_a_wrong_scalar_type_is_a_type_error(simple, points):
    # pybind11's conversion of the signature's scalars, as for any Python function.
    with pytest.raises(TypeError):
        simple.check(np.zeros((1, 6)), "wide")
    with pytest.raises(TypeError):
        hullmap.dbscan(points, 0.1, "ten")


def test_the_interpreter_lives_through_every_bad_input():
    # The same calls in a child interpreter, which then prints: a crash would show as a signal.
    script = """
import math, numpy as np, hullmap
m = hullmap.build("maps/simple/map_points.txt", up="-y", eps=0.12, min_pts=5)
calls = [
    lambda: hullmap.dbscan(np.ones((3, 3))[:, ::2], 0.1, 5),
    lambda: hullmap.dbscan(np.full((3, 3), math.nan), 0.1, 5),
    lambda: hullmap.dbscan(np.empty((0, 3)), 0.1, 5),
    lambda: hullmap.build(np.ones((5, 3), dtype=np.float32)),
    lambda: hullmap.build(np.full((3, 3), math.inf)),
    lambda: m.check(np.full((2, 6), math.nan), 0.2),
    lambda: m.check(np.ones((2, 7)), 0.2),
    lambda: m.check(np.ones((2, 6)), -1),
    lambda: m.check_path(np.ones((1, 4)), 0.2),
    lambda: m.plan((0, 0, math.nan), (1, 1, 1), 0.2),
    lambda: hullmap.load("/nonexistent"),
    lambda: hullmap.read_points("/nonexistent"),
]
for call in calls:
    try:
        call()
    except (ValueError, TypeError):
        pass
    else:
        raise SystemExit("no error")
print("alive")
"""
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "alive"


def test_a_single_waypoint_is_one_check(simple):
    # checkPath on one waypoint checks that point (a zero-length segment): not an error.
    result = simple.check_path(np.array([[100.0, 100.0, 100.0]]), 0.2)
    assert len(result.segments) == 1 and not result.segments["collides"][0]
    assert result.first_colliding_segment is None and result.first_contact is None
