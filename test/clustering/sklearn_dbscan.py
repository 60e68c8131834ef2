"""Reference DBSCAN for test/clustering/dbscan.cpp: scikit-learn on a points file.

usage: clustering_sklearn_dbscan.py POINTS EPS MIN_PTS xyz|xy
POINTS holds one point a line, `x y z` (whitespace separated). Prints one line per point, in order:
`label core` (label -1 for noise, core 0/1). Exit status 3 when scikit-learn is not installed.
scikit-learn's min_samples counts the point itself, like hullmap's min_pts.
"""
import sys

try:
    import numpy as np
    from sklearn.cluster import DBSCAN
except ImportError as e:  # the C++ test skips with this reason
    print(f"scikit-learn not available: {e}", file=sys.stderr)
    sys.exit(3)


def main():
    path, eps, min_pts, metric = sys.argv[1], float(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
    points = np.loadtxt(path, dtype=np.float64, ndmin=2)
    if metric == "xy":
        points = points[:, :2]
    model = DBSCAN(eps=eps, min_samples=min_pts, algorithm="kd_tree").fit(points)
    core = np.zeros(len(points), dtype=np.int64)
    core[model.core_sample_indices_] = 1
    out = sys.stdout
    for label, c in zip(model.labels_, core):
        out.write(f"{label} {c}\n")


if __name__ == "__main__":
    main()
