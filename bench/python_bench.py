"""The Python section of docs/BENCHMARKS.md: hullmap's module timed from Python, in one process.

usage: PYTHONPATH=BUILD/python /usr/bin/python3 bench/python_bench.py HULLMAP WORK_DIR [--points 100000]
           [--segments 200000] [--repeat 5] [--threads 2]

HULLMAP is the CLI (it writes the generated scenes: `hullmap generate`), WORK_DIR a scratch directory.
Prints the section's markdown table, two rows:
- hullmap.dbscan (eps 0.1, minPts 10, 3D) on a generated scene of --points points (`hullmap generate
  --points N --z-up`, generateScene's defaults as the DBSCAN section's scenes), median of --repeat
  calls, the array going in and the labels coming out included; sklearn.cluster.DBSCAN(kd_tree,
  n_jobs=threads) and Open3D's cluster_dbscan on the same array, one timed call each; agreement as
  bench/dbscan_peers.py checks it (noise set and core partition).
- Map.check on the Path checks section's generated_100 scene (`hullmap generate --obstacles 100
  --room 30 --points 500000 --seed 42`, built by hullmap.build with its trajectory and up="-y", the
  CLI's defaults otherwise): --segments random segments drawn as bench_collision draws them (start
  uniform in the room, z 0.2 to 2.8, direction uniform, length 0.5-3 m, end inside), radius 0.1 and
  0.3, median of --repeat calls: segments per second from the call's start to its structured array.
"""
import argparse
import os
import subprocess
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from dbscan_peers import agreement, run_open3d, run_sklearn  # noqa: E402

import hullmap  # noqa: E402


def median_seconds(call, repeat):
    """(wall seconds, CPU seconds of all threads) of the median run by wall time, and its result."""
    times = []
    result = None
    for _ in range(repeat):
        start, cpu = time.perf_counter(), time.process_time()
        result = call()
        times.append((time.perf_counter() - start, time.process_time() - cpu))
    times.sort()
    return times[len(times) // 2], result


def random_segments(n, room, height, seed=7):
    rng = np.random.default_rng(seed)
    lo, hi = np.array([-room / 2, -room / 2, 0.2]), np.array([room / 2, room / 2, height - 0.2])
    out = []
    count = 0
    while count < n:
        a = lo + (hi - lo) * rng.random((n, 3))
        d = 2 * rng.random((n, 3)) - 1
        norm = np.linalg.norm(d, axis=1)
        keep = (norm <= 1) & (norm > 1e-3)
        a, d, norm = a[keep], d[keep], norm[keep]
        b = a + d / norm[:, None] * (0.5 + 2.5 * rng.random(len(a)))[:, None]
        inside = np.all((b >= lo) & (b <= hi), axis=1)
        out.append(np.hstack([a[inside], b[inside]]))
        count += int(inside.sum())
    return np.ascontiguousarray(np.vstack(out)[:n])


def generate(hullmap_cli, directory, *args):
    subprocess.run([hullmap_cli, "generate", "-o", directory, *args], check=True, stdout=subprocess.DEVNULL)


def rate(x):
    return f"{x / 1e6:.2f} M/s" if x >= 1e6 else f"{x / 1e3:.1f} k/s"


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("hullmap")
    parser.add_argument("work")
    parser.add_argument("--points", type=int, default=100000)
    parser.add_argument("--segments", type=int, default=200000)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--threads", type=int, default=2)
    args = parser.parse_args()

    # DBSCAN: the same array for the three.
    scene = os.path.join(args.work, "dbscan_scene")
    generate(args.hullmap, scene, "--points", str(args.points), "--z-up")
    points = hullmap.read_points(os.path.join(scene, "map_points.txt"))
    hullmap.dbscan(points, 0.1, 10)  # warm-up: TBB's threads, first touch of the allocator
    (h_s, h_cpu), labels = median_seconds(lambda: hullmap.dbscan(points, 0.1, 10), args.repeat)
    # Agreement as dbscan_peers.py checks it, on scikit-learn's core points (hullmap.dbscan returns
    # labels only; the core definition is the same, which the C++ tests check point for point).
    problems = []
    sk_s, sk_labels, sk_core, why = run_sklearn(points, 0.1, 10, args.threads)
    if why:
        problems.append(why)
    o3d_s, o3d_labels, why_o3d = run_open3d(points, 0.1, 10, args.threads)
    if why_o3d:
        problems.append(why_o3d)
    if sk_core is not None:
        problems += agreement("sklearn", sk_labels, sk_core, labels.astype(np.int64), sk_core)
        if o3d_labels is not None:
            problems += agreement("Open3D", o3d_labels, None, labels.astype(np.int64), sk_core)
    verdict = "identical noise and core partition" if not problems else "; ".join(problems)
    clusters = int(labels.max()) + 1

    # Map.check on generated_100.
    scene100 = os.path.join(args.work, "generated_100")
    generate(args.hullmap, scene100, "--obstacles", "100", "--room", "30", "--points", "500000", "--seed", "42")
    built = hullmap.build(os.path.join(scene100, "map_points.txt"),
                          trajectory=os.path.join(scene100, "KeyFrameTrajectory.txt"), up="-y")
    segments = random_segments(args.segments, 30.0, 3.0)
    checks = {}
    for radius in (0.1, 0.3):
        built.check(segments[:1000], radius)  # warm-up
        (seconds, cpu), result = median_seconds(lambda: built.check(segments, radius), args.repeat)
        checks[radius] = (len(segments) / seconds, float(result["collides"].mean()), cpu / seconds)

    fmt = lambda v, p: "-" if v is None else p.format(v)  # noqa: E731
    print("| call, from Python | input | hullmap | scikit-learn | Open3D | scikit-learn / hullmap "
          "| Open3D / hullmap | result |")
    print("|---|---|---:|---:|---:|---:|---:|---|")
    print(f"| `hullmap.dbscan(points, 0.1, 10)` | {len(points):,} points, generated scene | {h_s:.4f} s "
          f"(CPU {h_cpu:.4f} s) "
          f"| {fmt(sk_s, '{:.2f} s')} | {fmt(o3d_s, '{:.2f} s')} | {fmt(None if sk_s is None else sk_s / h_s, '{:.0f}x')} "
          f"| {fmt(None if o3d_s is None else o3d_s / h_s, '{:.0f}x')} | {clusters} clusters; {verdict} |")
    r1, r3 = checks[0.1], checks[0.3]
    print(f"| `Map.check(segments, r)` | {len(segments):,} segments, generated_100 ({len(built.obstacles)} "
          f"obstacles) | r 0.1: {rate(r1[0])} ({rate(r1[0] / r1[2])} a CPU second), r 0.3: {rate(r3[0])} "
          f"({rate(r3[0] / r3[2])} a CPU second) | - | - | - | - | colliding: "
          f"{100 * r1[1]:.1f}% (r 0.1), {100 * r3[1]:.1f}% (r 0.3); CPU time over wall time {r1[2]:.2f}, "
          f"{r3[2]:.2f} (2.00: both cores the whole time) |")
    print()
    worst = min(r1[0], r3[0])
    print(f"Target (Map.check: at least 1,000,000 segments a second on 2 cores, as the C++ figure): "
          f"{'met' if worst >= 1e6 else 'MISSED'} in this run (slowest radius {rate(worst)}).")
    return 0 if not problems else 1


if __name__ == "__main__":
    sys.exit(main())
