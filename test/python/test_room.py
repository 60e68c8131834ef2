"""maps/room, the README's demo map: hullmap.build gives the CLI's outputs, Map.check and Map.plan
answer as `hullmap check` and `hullmap plan` do, hullmap.load reads the directory back."""
import gc
import json
import threading

import numpy as np
import pytest

import hullmap
from conftest import ROOM, check_json, fresh_dir, run_cli
from test_build_keywords import assert_same_outputs

POINTS, TRAJECTORY, REFERENCE = ROOM[0], ROOM[2], ROOM[4]
SEGMENTS = "maps/room/segments.txt"


@pytest.fixture(scope="module")
def built():
    return hullmap.build(POINTS, trajectory=TRAJECTORY, align=REFERENCE)


@pytest.fixture(scope="module")
def segments():
    return np.loadtxt(SEGMENTS, ndmin=2)


def test_build_writes_the_clis_directory(built, room_cli):
    out = fresh_dir("room_py")
    built.save(out)
    assert_same_outputs(room_cli, out)
    assert json.loads((out / "report.json").read_text())["obstacles"] == len(built.obstacles) == 9


def test_arrays_give_the_same_obstacles_as_the_files(built, room_cli):
    # Points, keyframes and the reference trajectory as arrays (input frame): the same map.
    from_arrays = hullmap.build(hullmap.read_points(POINTS), trajectory=np.loadtxt(TRAJECTORY, ndmin=2),
                                align=np.loadtxt(REFERENCE, ndmin=2))
    out = fresh_dir("room_arrays")
    from_arrays.save(out)
    for name in ("map.bt", "voxels.csv", "obstacles.obj"):
        assert (out / name).read_bytes() == (room_cli / name).read_bytes(), name
    cli = json.loads((room_cli / "obstacles.json").read_text())
    got = json.loads((out / "obstacles.json").read_text())
    assert got["obstacles"] == cli["obstacles"]
    assert got["parameters"]["align"] == "align" and got["parameters"]["trajectory"] == "trajectory"
    assert from_arrays.report["alignment"] == built.report["alignment"]


def test_a_gps_array_is_read_as_its_file(tmp_path):
    # The reference trajectory as GPS fixes near Zurich (east/north metres to degrees on a sphere,
    # near enough for a fit); the array and the file of the same rows give the same build.
    reference = np.loadtxt(REFERENCE, ndmin=2)
    lat0, lon0, radius = 47.37, 8.54, 6371000.0
    gps = np.column_stack([reference[:, 0], lat0 + np.degrees(reference[:, 2] / radius),
                           lon0 + np.degrees(reference[:, 1] / (radius * np.cos(np.radians(lat0)))),
                           400.0 + reference[:, 3]])
    np.savetxt(tmp_path / "gps.txt", gps, fmt="%.17g")
    from_file = hullmap.build(POINTS, trajectory=TRAJECTORY, align=str(tmp_path / "gps.txt"), align_format="gps")
    from_array = hullmap.build(POINTS, trajectory=TRAJECTORY, align=gps, align_format="gps")
    assert from_file.report["alignment"] == from_array.report["alignment"]
    assert from_file.report["alignment"]["rmse"] < 0.05
    np.testing.assert_array_equal(from_file.voxels.centers, from_array.voxels.centers)
    assert [o.voxel_count for o in from_file.obstacles] == [o.voxel_count for o in from_array.obstacles]


def test_load_reads_what_build_made(built, room_cli):
    loaded = hullmap.load(room_cli)
    assert loaded.resolution == built.resolution == 0.05
    assert loaded.report == json.loads((room_cli / "report.json").read_text())
    assert len(loaded.obstacles) == len(built.obstacles)
    for a, b in zip(loaded.obstacles, built.obstacles):
        assert a.id == b.id and a.voxel_count == b.voxel_count and a.point_weight == b.point_weight
        np.testing.assert_array_equal(a.hull.vertices, b.hull.vertices)
        np.testing.assert_array_equal(a.hull.triangles, b.hull.triangles)
        np.testing.assert_array_equal(a.footprint.polygon, b.footprint.polygon)
        np.testing.assert_array_equal(a.centroid, b.centroid)
        assert len(a.parts) == len(b.parts)
        for p, q in zip(a.parts, b.parts):
            np.testing.assert_array_equal(p.hull.vertices, q.hull.vertices)
            np.testing.assert_array_equal(p.hull.triangles, q.hull.triangles)
            np.testing.assert_array_equal(p.footprint.polygon, q.footprint.polygon)
            assert (p.flat, p.filled, p.faces, p.concavity_bound) == (q.flat, q.filled, q.faces, q.concavity_bound)
    csv = np.loadtxt(room_cli / "voxels.csv", delimiter=",", skiprows=1)
    for voxels in (loaded.voxels, built.voxels):
        np.testing.assert_allclose(voxels.centers, csv[:, :3], rtol=0, atol=1e-9)
        np.testing.assert_array_equal(voxels.weights, csv[:, 3])
        np.testing.assert_array_equal(voxels.labels, csv[:, 4])
        np.testing.assert_array_equal(voxels.core, csv[:, 5] == 1)


def test_arrays_of_a_map_are_read_only_views_that_keep_it(room_cli):
    centers = hullmap.load(room_cli).voxels.centers
    vertices = hullmap.load(room_cli).obstacles[3].parts[0].hull.vertices
    gc.collect()
    # The Map is gone from Python's names; the views hold it.
    assert centers.shape[1] == 3 and np.isfinite(centers).all() and vertices.shape[1] == 3
    assert not centers.flags.writeable and not centers.flags.owndata
    assert isinstance(centers.base, hullmap.Map) and isinstance(vertices.base, hullmap.ConvexHull)
    with pytest.raises(ValueError):
        centers[0, 0] = 1.0


def expect_same_checks(got, cli):
    assert len(got) == len(cli)
    for row, line in zip(got, cli):
        assert bool(row["collides"]) == line["collides"]
        assert row["obstacle"] == (line["obstacle"] if line["obstacle"] is not None else -1)
        assert row["part"] == line.get("part", -1)
        assert row["surface"] == (line.get("surface") or "")
        assert row["clearance"] == line["clearance"]
        if line["collides"]:
            assert row["t"] == line["t"]


@pytest.mark.parametrize("radius", [0.0, 0.3, 0.5])
def test_check_agrees_with_the_cli(built, room_cli, segments, radius):
    cli = check_json(room_cli, radius, "--segments", SEGMENTS)
    expect_same_checks(hullmap.load(room_cli).check(segments, radius), cli)
    expect_same_checks(built.check(segments, radius), cli)
    result = built.check(segments, radius)
    assert result.dtype.names == ("collides", "obstacle", "part", "surface", "t", "clearance")


def test_the_floor_is_an_obstacle_and_input_frame_queries_agree_with_the_cli(built, room_cli):
    # A segment below the floor collides with it, naming it; the same places asked in the input
    # frame (--frame input) answer as the CLI answers.
    low = np.array([[-1.0, 0.5, 0.1, 1.0, 0.5, 0.1]])
    row = built.check(low, 0.3)[0]
    assert row["collides"] and (row["surface"] == "floor" or row["obstacle"] >= 0)
    assert [s.name for s in built.surfaces] == [s.name for s in hullmap.load(room_cli).surfaces]
    path = fresh_dir("room_input_frame")
    path.mkdir()
    input_segments = np.hstack([hullmap.read_points(POINTS)[:40:2], hullmap.read_points(POINTS)[1:41:2]])
    np.savetxt(path / "segments.txt", input_segments, fmt="%.17g")
    cli = check_json(room_cli, 0.3, "--segments", path / "segments.txt", "--frame", "input")
    expect_same_checks(hullmap.load(room_cli).check(input_segments, 0.3, frame="input"), cli)


def test_octree_checks_agree_with_the_cli(built, room_cli, segments):
    cli = check_json(room_cli, 0.3, "--segments", SEGMENTS, "--against", "octree")
    expect_same_checks(hullmap.load(room_cli).check(segments, 0.3, against="octree"), cli)
    expect_same_checks(built.check(segments, 0.3, against="octree"), cli)


def test_a_path_is_checked_as_the_cli_checks_it(built, room_cli, segments):
    waypoints = np.ascontiguousarray(segments[:, :3])
    path_file = fresh_dir("room_path")
    path_file.mkdir()
    np.savetxt(path_file / "path.txt", waypoints, fmt="%.17g")
    cli = check_json(room_cli, 0.3, "--path", path_file / "path.txt")
    text = run_cli("check", room_cli, "--radius", "0.3", "--path", path_file / "path.txt").stdout
    last = text.splitlines()[-1]
    result = built.check_path(waypoints, 0.3)
    expect_same_checks(result.segments, cli)
    assert last.startswith(f"path: first collision in segment {result.first_colliding_segment} at (")
    contact = [float(v) for v in last[last.index("(") + 1:-1].split()]
    assert contact == result.first_contact.tolist()


@pytest.mark.parametrize("goal", ["3,3,1", "0,0,1", "-1.2,-0.8,0.5"])
def test_plan_agrees_with_the_cli(built, room_cli, goal):
    done = run_cli("plan", room_cli, "--from", "-3,-3,1", "--to", goal, "--radius", "0.3")
    plan = built.plan((-3, -3, 1), [float(v) for v in goal.split(",")], 0.3)
    if done.returncode == 1:
        assert plan.path is None
        assert done.stdout.strip() == f"no path: {plan.blocked}"
    else:
        cli = np.array([[float(v) for v in line.split()] for line in done.stdout.splitlines()])
        np.testing.assert_array_equal(plan.path, cli)
        assert plan.blocked == ""
        assert not built.check_path(plan.path, 0.3).segments["collides"].any()


def test_concurrent_checks_give_the_same_answers(built):
    # Checks release the GIL: threads run them at once, each answer as alone.
    rng = np.random.default_rng(7)
    starts = rng.uniform([-5, -5, 0.2], [5, 5, 2.8], size=(20000, 3))
    segments = np.hstack([starts, starts + rng.normal(0, 1.5, size=(20000, 3))])
    alone = built.check(segments, 0.2)
    results = [None] * 4

    def run(i):
        results[i] = built.check(segments, 0.2)

    threads = [threading.Thread(target=run, args=(i,)) for i in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for r in results:
        np.testing.assert_array_equal(r, alone)
    assert 0 < alone["collides"].sum() < len(alone)
