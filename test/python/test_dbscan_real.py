"""hullmap.dbscan gives scikit-learn's labels, up to renumbering, on the real ORB-SLAM maps of
shared/data/real (SOURCES.md): the same noise, the same core points in the same clusters, and
every other point in the same cluster too, except a border point within eps of core points of two
clusters, which DBSCAN's definition leaves to either (scikit-learn takes the cluster that reached
it first, hullmap the nearest core point's, dbscan.hpp)."""
import numpy as np
import pytest

import hullmap
from conftest import real_file

sklearn = pytest.importorskip("sklearn.cluster", reason="scikit-learn (Debian's python3-sklearn) is not installed")
from sklearn.neighbors import NearestNeighbors  # noqa: E402


def compare(points, eps, min_pts, metric):
    labels = hullmap.dbscan(points, eps, min_pts, metric=metric)
    space = points[:, :2] if metric == "xy" else points
    model = sklearn.DBSCAN(eps=eps, min_samples=min_pts, algorithm="kd_tree").fit(space)
    theirs = model.labels_
    core = np.zeros(len(points), dtype=bool)
    core[model.core_sample_indices_] = True
    assert labels.max() == theirs.max(), "cluster counts differ"
    np.testing.assert_array_equal(labels == -1, theirs == -1)
    # Renumbering: scikit-learn's cluster of each core point is one hullmap cluster, and back.
    pairs = np.unique(np.stack([labels[core], theirs[core]], axis=1), axis=0)
    assert len(np.unique(pairs[:, 0])) == len(pairs) == len(np.unique(pairs[:, 1])), "core partitions differ"
    renumber = dict(zip(pairs[:, 1].tolist(), pairs[:, 0].tolist()))
    renumbered = np.array([renumber.get(label, -1) for label in theirs.tolist()])
    differ = np.flatnonzero(renumbered != labels)
    # Only border points reachable from two clusters may differ, and hullmap's is the cluster of the
    # nearest core point among them.
    assert not core[differ].any()
    if len(differ) == 0:
        return 0
    distances, neighbours = NearestNeighbors(radius=eps).fit(space).radius_neighbors(space[differ])
    for i, d, n in zip(differ, distances, neighbours):
        cores = core[n]
        assert len(set(labels[n[cores]].tolist())) > 1, f"point {i} differs but only one cluster reaches it"
        assert labels[i] == labels[n[cores][np.argmin(d[cores])]]
    return len(differ)


def test_orbslam2_v1_01():
    points = np.loadtxt(real_file("orbslam2_euroc_V1_01_MapPoints.txt"), ndmin=2)
    assert points.shape == (8704, 3)
    differ = [compare(points, eps, min_pts, metric)
              for eps, min_pts, metric in [(0.1, 10, "xyz"), (0.05, 5, "xyz"), (0.3, 35, "xyz"), (0.13, 15, "xy")]]
    # The border points reachable from two clusters are a handful of 8704 (10 at eps 0.1).
    assert sum(differ) < 0.01 * len(points)


def test_orbslam3_mh_01_union():
    # The active map of an ORB-SLAM3 run is the union of its two files; read as the CLI reads them.
    points = hullmap.read_points([real_file("orbslam3_euroc_MH_01_mono_pointcloud.txt"),
                                  real_file("orbslam3_euroc_MH_01_mono_ref_pointcloud.txt")])
    assert points.shape == (12292, 3)
    differ = [compare(points, eps, min_pts, metric)
              for eps, min_pts, metric in [(0.1, 10, "xyz"), (0.2, 5, "xyz"), (0.1, 10, "xy")]]
    assert sum(differ) < 0.01 * len(points)
