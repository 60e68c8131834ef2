#!/usr/bin/python3
"""Prints the "## The viewer" section of docs/BENCHMARKS.md (markdown) to stdout: how big `hullmap view`'s
page is and how long it takes to load and to draw a frame in headless Chromium, for builds of about
10k, 100k and 1M occupied voxels; then the frame time of each of the page's levels of detail against
the cubes it draws (from which the page's choice of level and view::kCoarsestCubes come).

usage: bench/view_scale.py BUILD_DIR [--quick]

BUILD_DIR holds cli/hullmap. Needs Debian's chromium, chromium-driver, python3-selenium, python3-pil
and libjs-three (./setup.sh bench installs them). --quick: the 10k and 100k builds only.

Load time is the page's own: from the start of navigation to its first frame drawn and read back
(window.hullmapView.load_ms), median of 3 loads (1 for pages over 50 MB). Frame time: the median of
hullmapView.measureFrames(n), each frame rendered and read back before the next, the camera turning
between frames, in a 1280 x 800 window. Chromium has no GPU here: WebGL runs in SwiftShader (software)
on the machine's cores, the slowest place the page will ever run.
"""
import os
import statistics
import subprocess
import sys
import tempfile
import time

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(here, "..", "test", "view"))
import headless_chromium  # noqa: E402

if len(sys.argv) < 2:
    sys.exit(__doc__)
hullmap = os.path.join(sys.argv[1], "cli", "hullmap")
quick = "--quick" in sys.argv[2:]
reason = headless_chromium.missing()
if reason:
    sys.exit("view_scale.py: " + reason)
root = os.path.join(here, "..")
work = tempfile.mkdtemp(prefix="hullmap-view-bench-")


def run(*args):
    start = time.time()
    out = subprocess.run([hullmap, *args], check=True, stdout=subprocess.PIPE, text=True).stdout
    return out, time.time() - start


# The builds: maps/simple as the README builds it; generated scenes of 40 obstacles in a 20 m room.
builds = [("maps/simple", [os.path.join(root, "maps/simple/map_points.txt"), "--trajectory",
                           os.path.join(root, "maps/simple/KeyFrameTrajectory.txt"), "--up", "-y", "--eps", "0.12",
                           "--min-pts", "5"], None),
          ("generated, 1M points, resolution 0.05", ["--up", "-y", "--eps", "0.12", "--min-pts", "5"], 1000000)]
if not quick:
    builds.append(("generated, 3.4M points, resolution 0.02", ["--up", "-y", "--resolution", "0.02", "--eps", "0.05",
                                                               "--min-pts", "3"], 3400000))
made = []
for name, args, points in builds:
    out = os.path.join(work, "build%d" % len(made))
    if points:
        scene = out + "_scene"
        run("generate", "-o", scene, "--points", str(points), "--obstacles", "40", "--room", "20", "--seed", "42")
        args = [os.path.join(scene, "map_points.txt")] + args
    _, seconds = run("build", *args, "-o", out)
    made.append((name, out, seconds))

browser = headless_chromium.Browser(1280, 800, script_timeout=3600)


def load(page):
    errors, summary = browser.load(page, timeout=600)
    if errors or not summary or not summary.get("ready"):
        sys.exit("view_scale.py: %s did not load: %s" % (page, errors))
    return summary


rows = []
points = []  # (build, cubes drawn, frame ms)
for name, out, build_seconds in made:
    page = out + ".html"
    _, write_seconds = run("view", out, "-o", page)
    size = os.path.getsize(page)
    loads = [load(page) for _ in range(1 if size > 50e6 else 3)]
    summary = loads[-1]
    v = summary["voxels"]
    drawn = browser.run("return hullmapView.measureFrames(5)")["median_ms"]
    rows.append({"name": name, "voxels": v["total"], "parts": len(summary["parts"]), "build_s": build_seconds,
                 "size": size, "write_s": write_seconds, "load_ms": statistics.median(s["load_ms"] for s in loads),
                 "levels": v["levels"], "level": v["level"], "frame_ms": drawn})
    for k, level in enumerate(v["levels"]):
        browser.run("hullmapView.setDetail(arguments[0])", k)
        frames = 1 if level["instances"] > 300000 else 3
        points.append((name, level["instances"], browser.run("return hullmapView.measureFrames(arguments[0])",
                                                              frames)["median_ms"]))
browser.quit()

load_average = os.getloadavg()
print("## The viewer: `hullmap view`")
print()
print("`bench/view_scale.py BUILD_DIR`: the page of a build (`hullmap view OUT`, default budget: every voxel up to")
print("1M cubes) loaded from file:// in headless Chromium (Debian's, `--headless=new --use-angle=swiftshader`: WebGL in")
print("software on the CPU, no GPU), 1280 x 800. *Load*: from navigation to the first frame drawn at the level the page")
print("chose and read back (the page's `hullmapView.load_ms`), median of 3 loads; it includes the three frames the page")
print("times to choose its level. *Frame*: median of `hullmapView.measureFrames` (each frame drawn and read back before")
print("the next). The builds: `maps/simple` as in the README; `hullmap generate --points N --obstacles 40 --room 20")
print("--seed 42`, built with `--up -y` and the eps/minPts given, convex parts at the defaults.")
print()
print("| build | voxels | convex parts | build s | page MB | write s | load s | levels of detail (cubes) | drawn | frame ms |")
print("|---|---:|---:|---:|---:|---:|---:|---|---:|---:|")
for r in rows:
    print("| %s | %s | %s | %.1f | %.1f | %.2f | %.2f | %s | %s | %.0f |" % (
        r["name"], format(r["voxels"], ","), format(r["parts"], ","), r["build_s"], r["size"] / 1e6, r["write_s"],
        r["load_ms"] / 1000, ", ".join(format(l["instances"], ",") for l in r["levels"]),
        format(r["levels"][r["level"]]["instances"], ","), r["frame_ms"]))
print()
print("Frame time of each level (`hullmapView.setDetail(k)`, median of 3 frames, 1 above 300,000 cubes):")
print()
print("| build | cubes | frame ms |")
print("|---|---:|---:|")
for p in points:
    print("| %s | %s | %.0f |" % (p[0], format(p[1], ","), p[2]))
print()
for r in rows:
    mine = [p for p in points if p[0] == r["name"]]
    if len(mine) >= 2:
        fine, coarse = max(mine, key=lambda p: p[1]), min(mine, key=lambda p: p[1])
        print("- %s: %.0f us a cube between its coarsest and finest level (%s and %s cubes)." % (
            r["name"], 1000 * (fine[2] - coarse[2]) / (fine[1] - coarse[1]), format(coarse[1], ","),
            format(fine[1], ",")))
print()
print("Load average %.2f %.2f %.2f at the end (the machine is shared; the frame times move with it)." % load_average)
