"""hullmap.dbscan and hullmap.read_points against brute-force oracles on small inputs, and what the
arrays they return hold (their own memory, no copy)."""
import numpy as np
import pytest

import hullmap


def oracle(points, eps, min_pts, weights=None, metric="xyz"):
    """DBSCAN as dbscan.hpp states it, by brute force: neighbours at squared distance
    dx*dx + dy*dy (+ dz*dz) <= eps*eps, core when their weight reaches min_pts, clusters the
    connected core points, a border point in the cluster of its nearest core neighbour (the first
    in the input among equally near ones), clusters numbered by their first point."""
    n = len(points)
    w = np.ones(n, dtype=np.int64) if weights is None else np.asarray(weights, dtype=np.int64)
    d = points[:, None, :] - points[None, :, :]
    squared = d[..., 0] * d[..., 0] + d[..., 1] * d[..., 1]
    if metric == "xyz":
        squared = squared + d[..., 2] * d[..., 2]
    near = squared <= eps * eps
    core = (near * w[None, :]).sum(axis=1) >= min_pts
    component = np.full(n, -1)
    for start in np.flatnonzero(core):
        if component[start] >= 0:
            continue
        component[start] = start
        stack = [start]
        while stack:
            i = stack.pop()
            for j in np.flatnonzero(near[i] & core & (component < 0)):
                component[j] = start
                stack.append(j)
    owner = np.full(n, -1)
    owner[core] = component[core]
    for i in np.flatnonzero(~core):
        candidates = np.flatnonzero(near[i] & core)
        if len(candidates):
            owner[i] = component[candidates[np.argmin(squared[i, candidates])]]
    labels = np.full(n, -1, dtype=np.int32)
    numbers = {}
    for i in range(n):
        if owner[i] >= 0:
            labels[i] = numbers.setdefault(owner[i], len(numbers))
    return labels


def scene(seed, n):
    rng = np.random.default_rng(seed)
    centres = rng.uniform(0, 2, size=(4, 3))
    points = centres[rng.integers(0, 4, n)] + rng.normal(0, 0.08, size=(n, 3))
    points[::7] = rng.uniform(0, 2, size=(len(points[::7]), 3))
    return points


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("metric", ["xyz", "xy"])
def test_dbscan_is_the_brute_force_oracle(seed, metric):
    points = scene(seed, 300)
    for eps, min_pts in [(0.05, 3), (0.1, 6), (0.2, 25)]:
        got = hullmap.dbscan(points, eps, min_pts, metric=metric)
        np.testing.assert_array_equal(got, oracle(points, eps, min_pts, metric=metric))


@pytest.mark.parametrize("seed", range(4))
def test_weights_count_as_points(seed):
    points = scene(seed, 250)
    weights = np.random.default_rng(seed).integers(1, 5, len(points)).astype(np.uint32)
    for dtype in (np.uint32, np.int64, np.uint8):
        got = hullmap.dbscan(points, 0.1, 8, weights=weights.astype(dtype))
        np.testing.assert_array_equal(got, oracle(points, 0.1, 8, weights))
    # A list of ints is an array too.
    np.testing.assert_array_equal(hullmap.dbscan(points, 0.1, 8, weights=weights.tolist()),
                                  oracle(points, 0.1, 8, weights))


def test_labels_are_the_librarys_own_memory():
    points = scene(1, 500)
    labels = hullmap.dbscan(points, 0.1, 6)
    assert labels.dtype == np.int32 and labels.shape == (500,)
    # Moved out of the library's result, not copied: numpy does not own it, a capsule does.
    assert not labels.flags.owndata and type(labels.base).__name__ == "PyCapsule"
    assert labels.flags.writeable and labels.flags.c_contiguous
    assert labels.min() >= -1 and set(np.unique(labels[labels >= 0])) == set(range(labels.max() + 1))


def test_a_list_of_rows_is_taken():
    points = scene(2, 120)
    np.testing.assert_array_equal(hullmap.dbscan(points.tolist(), 0.1, 5), hullmap.dbscan(points, 0.1, 5))


def test_read_points_keeps_the_readers_sniffing_and_turns_the_frame(tmp_path):
    # The same three points as text (a header line and commas), PLY and PCD; formats found from the bytes.
    rows = np.array([[1.5, -2.0, 0.25], [0.0, 3.0, 4.0], [-1.0, -1.0, -1.0]])
    text = tmp_path / "points.anything"
    text.write_text("pos_x, pos_y, pos_z\n" + "".join(f"{x}, {y}, {z}\n" for x, y, z in rows))
    ply = tmp_path / "points.dat"
    ply.write_text("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                   "property float z\nend_header\n" + "".join(f"{x} {y} {z}\n" for x, y, z in rows))
    pcd = tmp_path / "points.txt"
    pcd.write_text("VERSION 0.7\nFIELDS x y z\nSIZE 8 8 8\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 3\nHEIGHT 1\n"
                   "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA ascii\n" + "".join(f"{x} {y} {z}\n" for x, y, z in rows))
    for path in (text, ply, pcd):
        got = hullmap.read_points(path)
        np.testing.assert_array_equal(got, rows)
        assert not got.flags.owndata and type(got.base).__name__ == "PyCapsule"
    # ORB-SLAM's frame (y down) to z up: (x, y, z) -> (x, z, -y); scale first.
    np.testing.assert_array_equal(hullmap.read_points(text, up="-y", scale=2.0),
                                  2.0 * np.stack([rows[:, 0], rows[:, 2], -rows[:, 1]], axis=1))
    # Several files are one union, in order.
    np.testing.assert_array_equal(hullmap.read_points([text, ply]), np.concatenate([rows, rows]))
    # A row with a NaN is dropped, as every reader drops it.
    nan = tmp_path / "nan.xyz"
    nan.write_text("1 2 3\nnan 0 0\n4 5 6\n")
    np.testing.assert_array_equal(hullmap.read_points(nan), [[1, 2, 3], [4, 5, 6]])
