"""Open3D and scikit-learn DBSCAN on the scenes bench_dbscan wrote; agreement with hullmap.

usage: /usr/bin/python3 bench/dbscan_peers.py DIR HULLMAP_JSONL [--sizes 10000,100000] [--eps 0.1] [--min-pts 10]
                                              [--threads 2] [--markdown]

DIR holds, per size n, scene_<n>.f64 (n x 3 float64), hullmap_<n>.i32 (labels) and hullmap_<n>.u8 (core
flags), as bench/bench_dbscan.cpp writes them; HULLMAP_JSONL is that program's stdout. For every size in
--sizes, runs open3d.geometry.PointCloud.cluster_dbscan(eps, min_points) and
sklearn.cluster.DBSCAN(eps, min_samples, algorithm='kd_tree', n_jobs=threads), times each fit, and checks
against hullmap: the same noise set and the same partition of the core points (scikit-learn reports its
core points; Open3D does not, so hullmap's core points are used, which is the same set when the noise sets
agree). Border points may legitimately go to another cluster within reach, so they are not compared.
Prints one JSON object per size, or with --markdown the table of docs/BENCHMARKS.md's DBSCAN section
(sizes without peers show "-").
"""
import argparse
import json
import os
import sys
import time

import numpy as np


def same_partition(a, b, mask):
    """True when labels a and b induce the same partition of the points where mask is set."""
    if not mask.any():
        return True
    pairs = np.unique(np.stack([a[mask], b[mask]], axis=1), axis=0)
    return len(np.unique(pairs[:, 0])) == len(pairs) and len(np.unique(pairs[:, 1])) == len(pairs)


def agreement(name, labels, core, h_labels, h_core):
    problems = []
    noise_diff = int(np.count_nonzero((labels == -1) != (h_labels == -1)))
    if noise_diff:
        problems.append(f"{name}: {noise_diff} points differ in noise")
    if core is not None:
        core_diff = int(np.count_nonzero(core != h_core))
        if core_diff:
            problems.append(f"{name}: {core_diff} core flags differ")
    mask = h_core.astype(bool) if core is None else (h_core.astype(bool) & core.astype(bool))
    if not same_partition(labels, h_labels, mask):
        problems.append(f"{name}: core partitions differ")
    return problems


def run_open3d(points, eps, min_pts, threads):
    try:
        import open3d as o3d
    except ImportError as e:
        return None, None, f"open3d not available: {e}"
    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(points))
    t0 = time.perf_counter()
    labels = np.asarray(cloud.cluster_dbscan(eps=eps, min_points=min_pts, print_progress=False))
    return time.perf_counter() - t0, labels.astype(np.int64), None


def run_sklearn(points, eps, min_pts, threads):
    try:
        from sklearn.cluster import DBSCAN
    except ImportError as e:
        return None, None, None, f"scikit-learn not available: {e}"
    t0 = time.perf_counter()
    model = DBSCAN(eps=eps, min_samples=min_pts, algorithm="kd_tree", n_jobs=threads).fit(points)
    seconds = time.perf_counter() - t0
    core = np.zeros(len(points), dtype=np.uint8)
    core[model.core_sample_indices_] = 1
    return seconds, model.labels_.astype(np.int64), core, None


def fmt(value, pattern):
    return "-" if value is None else pattern.format(value)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("dir")
    parser.add_argument("hullmap_jsonl")
    parser.add_argument("--sizes", default="10000,100000")
    parser.add_argument("--eps", type=float, default=0.1)
    parser.add_argument("--min-pts", type=int, default=10)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--markdown", action="store_true")
    args = parser.parse_args()

    hullmap = {}
    with open(args.hullmap_jsonl) as f:
        for line in f:
            line = line.strip()
            if line.startswith("{"):
                row = json.loads(line)
                hullmap[row["points"]] = row
    peer_sizes = [int(s) for s in args.sizes.split(",") if s]

    results = []
    for n in sorted(hullmap):
        row = {"points": n, "hullmap": hullmap[n]}
        if n in peer_sizes:
            stem = os.path.join(args.dir, f"{{}}_{n}.{{}}")
            points = np.fromfile(stem.format("scene", "f64"), dtype="<f8").reshape(-1, 3)
            h_labels = np.fromfile(stem.format("hullmap", "i32"), dtype="<i4").astype(np.int64)
            h_core = np.fromfile(stem.format("hullmap", "u8"), dtype=np.uint8)
            assert len(points) == n == len(h_labels) == len(h_core), f"size mismatch for {n}"
            problems = []
            o3d_s, o3d_labels, why = run_open3d(points, args.eps, args.min_pts, args.threads)
            if why:
                problems.append(why)
            else:
                row["open3d_seconds"] = o3d_s
                problems += agreement("Open3D", o3d_labels, None, h_labels, h_core)
            sk_s, sk_labels, sk_core, why = run_sklearn(points, args.eps, args.min_pts, args.threads)
            if why:
                problems.append(why)
            else:
                row["sklearn_seconds"] = sk_s
                problems += agreement("sklearn", sk_labels, sk_core, h_labels, h_core)
            row["agreement"] = "identical noise and core partition" if not problems else "; ".join(problems)
            row["agrees"] = not problems
        results.append(row)
        if not args.markdown:
            print(json.dumps(row), flush=True)

    if args.markdown:
        print("| points | hullmap s | hullmap CPU s | Open3D s | sklearn s | Open3D / hullmap | sklearn / hullmap | hullmap points/s "
              "| hullmap peak MB | bytes/point | clusters | noise | agreement |")
        print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|")
        for row in results:
            h = row["hullmap"]
            hs = h["seconds"]
            o3d_s = row.get("open3d_seconds")
            sk_s = row.get("sklearn_seconds")
            print(f"| {row['points']:,} | {hs:.4f} | {fmt(h.get('cpu_seconds'), '{:.4f}')} | {fmt(o3d_s, '{:.2f}')} | {fmt(sk_s, '{:.2f}')} "
                  f"| {fmt(None if o3d_s is None else o3d_s / hs, '{:.0f}x')} "
                  f"| {fmt(None if sk_s is None else sk_s / hs, '{:.0f}x')} "
                  f"| {h['points_per_second'] / 1e6:.1f} M | {h['peak_bytes'] / 1e6:.1f} | {h['bytes_per_point']:.1f} "
                  f"| {h['clusters']} | {h['noise']:,} | {row.get('agreement', 'not compared')} |")
    return 0 if all(r.get("agrees", True) for r in results) else 1


if __name__ == "__main__":
    sys.exit(main())
