#!/usr/bin/python3
"""Prints the "## The viewer" section of docs/BENCHMARKS.md (markdown) to stdout: how big `hullmap view`'s
page is and how long it takes to load and to draw a frame in headless Chromium, for builds of about
10k, 100k and 1M occupied voxels, at the default budget (voxels merged into coarser cells past
view::kDefaultMaxInstances cubes) and with every voxel drawn; then the frame time against the cubes
drawn, from which the budget is chosen.

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
sys.path.insert(0, os.path.join(here, "..", "test"))
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
    builds.append(("generated, 4M points, resolution 0.02", ["--up", "-y", "--resolution", "0.02", "--eps", "0.05",
                                                             "--min-pts", "3"], 4000000))
made = []
for name, args, points in builds:
    out = os.path.join(work, "build%d" % len(made))
    if points:
        scene = out + "_scene"
        run("generate", "-o", scene, "--points", str(points), "--obstacles", "40", "--room", "20", "--seed", "42")
        args = [os.path.join(scene, "map_points.txt")] + args
    _, seconds = run("build", *args, "-o", out)
    made.append((name, out, seconds))

browser = headless_chromium.Browser(1280, 800, script_timeout=1800)


def measure(page, frames):
    size = os.path.getsize(page)
    loads = []
    summary = None
    for _ in range(1 if size > 50e6 else 3):
        errors, summary = browser.load(page, timeout=600)
        if errors or not summary or not summary.get("ready"):
            sys.exit("view_scale.py: %s did not load: %s" % (page, errors))
        loads.append(summary["load_ms"])
    frame = browser.run("return hullmapView.measureFrames(arguments[0])", frames)
    return {"size": size, "load_ms": statistics.median(loads), "frame_ms": frame["median_ms"],
            "instances": summary["voxels"]["instances"], "voxels": summary["voxels"]["total"],
            "factor": summary["voxels"]["factor"], "cell": summary["voxels"]["cell"], "parts": len(summary["parts"])}


rows = []
points = []  # (cubes drawn, frame ms)
for name, out, build_seconds in made:
    for budget in (None, "100000000"):
        page = out + ("_all" if budget else "") + ".html"
        args = ["view", out, "-o", page] + (["--max-instances", budget] if budget else [])
        _, write_seconds = run(*args)
        m = measure(page, 3 if budget else 5)
        m.update(name=name, budget=budget, write_s=write_seconds)
        rows.append(m)
        points.append((m["instances"], m["frame_ms"]))
    # Coarser cells of the same build, for the frame time against the cubes drawn.
    for budget in ("50000", "20000"):
        page = out + "_" + budget + ".html"
        run("view", out, "-o", page, "--max-instances", budget)
        m = measure(page, 5)
        if m["instances"] not in [p[0] for p in points]:
            points.append((m["instances"], m["frame_ms"]))
browser.quit()

load = os.getloadavg()
print("## The viewer: `hullmap view`")
print()
print("`bench/view_scale.py BUILD_DIR`: the page of a build (`hullmap view OUT`) loaded from file:// in headless")
print("Chromium (Debian's, `--headless=new --use-angle=swiftshader`: WebGL in software on the CPU, no GPU), 1280 x 800.")
print("*Load*: from navigation to the first frame drawn and read back (the page's `hullmapView.load_ms`), median of")
print("3 loads. *Frame*: median of `hullmapView.measureFrames`, each frame drawn and read back before the next. The")
print("builds: `maps/simple` as in the README; `hullmap generate --points N --obstacles 40 --room 20 --seed 42`, built")
print("with `--up -y` and the eps/minPts given (convex parts at the defaults).")
print()
print("| build | voxels | convex parts | build s | page | cubes drawn | page MB | write s | load s | frame ms |")
print("|---|---:|---:|---:|---|---:|---:|---:|---:|---:|")
for r in rows:
    build_s = [b[2] for b in made if b[0] == r["name"]][0]
    page = "every voxel (`--max-instances 100000000`)" if r["budget"] else \
        ("default budget" + (": merged into cells of %g (%d voxels a side)" % (r["cell"], r["factor"]) if r["factor"] > 1 else ""))
    print("| %s | %s | %s | %.1f | %s | %s | %.1f | %.2f | %.2f | %.0f |" % (
        r["name"], format(r["voxels"], ","), format(r["parts"], ","), build_s, page, format(r["instances"], ","),
        r["size"] / 1e6, r["write_s"], r["load_ms"] / 1000, r["frame_ms"]))
print()
points.sort()
print("Frame time against the cubes drawn (every page above, and the same builds at `--max-instances` 50,000 and")
print("20,000):")
print()
print("| cubes drawn | " + " | ".join(format(p[0], ",") for p in points) + " |")
print("|---|" + "---:|" * len(points))
print("| frame ms | " + " | ".join("%.0f" % p[1] for p in points) + " |")
print()
if len(points) >= 2:
    n = len(points)
    mx = sum(p[0] for p in points) / n
    my = sum(p[1] for p in points) / n
    slope = sum((p[0] - mx) * (p[1] - my) for p in points) / max(1e-9, sum((p[0] - mx) ** 2 for p in points))
    print("Least squares: %.1f ms + %.2f ms per 1,000 cubes. Load average %.2f %.2f %.2f at the end." % (
        my - slope * mx, 1000 * slope, *load))
