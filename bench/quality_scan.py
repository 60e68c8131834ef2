#!/usr/bin/python3
"""Fast quality scan for development: hullmap only (no Open3D grid, no real maps, no document) over
the generated scenes of bench/quality.py at one monocular scale (0.37; hullmap's rows for the two
scales of a scene agree up to rounding), scored by the same `hullmap evaluate` and targets. Prints one
line per scene and a summary line; about a second per scene.

usage: bench/quality_scan.py HULLMAP_BINARY [--seeds 1,2,3] [--furniture 8,0] [--density 30,120]
                             [--extra "build args"] [--work DIR]

Scenes are generated once into --work (default /tmp/hullmap-quality-scan) and reused; outputs go to
a fresh directory under /tmp (printed per scene). `bench/quality_misses.py OUT SCENE` then lists the
observed points a scene's hulls miss and the voxel each lies in."""
import argparse
import importlib.util
import json
import os
import shlex
import statistics
import sys
import time

ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
ap.add_argument("hullmap")
ap.add_argument("--seeds", default="1,2,3")
ap.add_argument("--furniture", default="8,0")
ap.add_argument("--density", default="30,120")
ap.add_argument("--extra", default="", help="more hullmap build arguments")
ap.add_argument("--work", default="/tmp/hullmap-quality-scan", help="generated scenes, reused")
ap.add_argument("--segments", type=int, default=2000)
ap.add_argument("--repo", default=os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
a = ap.parse_args()
spec = importlib.util.spec_from_file_location("quality", os.path.join(a.repo, "bench", "quality.py"))
q = importlib.util.module_from_spec(spec)
sys.argv = [sys.argv[0]]
spec.loader.exec_module(q)
os.makedirs(a.work, exist_ok=True)
out_root = f"/tmp/hullmap-quality-scan-out-{os.getpid()}"
os.makedirs(out_root, exist_ok=True)
rows = []
for seed in [int(s) for s in a.seeds.split(",")]:
    for d in [int(x) for x in a.density.split(",")]:
        for f in [int(x) for x in a.furniture.split(",")]:
            name = f"s{seed}-d{d}-f{f}"
            scene = f"{a.work}/{name}"
            if not os.path.exists(f"{scene}/aligned_points.txt"):
                q.run([a.hullmap, "generate", "--layout", "room", "-o", scene, "--seed", str(seed),
                       "--density", str(d), "--scale", "0.37", "--obstacles", str(f)])
                q.align_scene(scene)
            truth = f"{scene}/ground_truth.json"
            kinds = [o.get("kind", o["shape"]) for o in json.load(open(truth))["obstacles"]]
            out = f"{out_root}/{name}"
            start = time.perf_counter()
            q.run([a.hullmap, "build", f"{scene}/map_points.txt", "--trajectory", f"{scene}/KeyFrameTrajectory.txt",
                   "--align", f"{scene}/reference_trajectory.txt", *shlex.split(a.extra), "-o", out])
            seconds = time.perf_counter() - start
            m = q.evaluate(a.hullmap, f"{out}/obstacles.json", f"{scene}/aligned_points.txt", truth, kinds, a.segments)
            ok = q.passes(m)
            rows.append((name, m, ok))
            verdict = "ALL" if all(ok.values()) else "fail: " + ",".join(k for k, v in ok.items() if not v)
            print(f"{name:14s} missed {m['missed']}/{m['deep']}  fa {m['false_alarms']:.1f}%  share {m['min_share']:.1f}  "
                  f"swallowed {m['swallowed']:.1f}  parts {m['parts']:.2f} (max {m['parts_max']})  hulls {m['hulls']}  "
                  f"{seconds:.2f}s  {verdict}  out {out}", flush=True)
ms = [m for _, m, _ in rows]
print(f"scenes meeting all: {sum(all(ok.values()) for _, _, ok in rows)} of {len(rows)}; "
      f"min share median {statistics.median(m['min_share'] for m in ms):.1f} worst {min(m['min_share'] for m in ms):.1f}; "
      f"parts median {statistics.median(m['parts'] for m in ms):.2f} worst {max(m['parts'] for m in ms):.2f}; "
      f"fa worst {max(m['false_alarms'] for m in ms):.1f}; swallowed worst {max(m['swallowed'] for m in ms):.1f}; "
      f"missed worst {max(m['missed'] for m in ms)}")
