#!/usr/bin/python3
"""Regenerates the README's picture, docs/img/view_room.png: `hullmap view` of maps/room built at its
defaults (with its reference trajectory), a path from `hullmap plan` and a path through the furniture,
both checked at radius 0.3, seen in headless Chromium (Debian's chromium, chromium-driver,
python3-selenium, python3-pil, libjs-three).

usage: docs/img/view_picture.py [HULLMAP_BINARY]     (default: build/cli/hullmap)
"""
import io
import os
import shutil
import subprocess
import sys
import tempfile

here = os.path.dirname(os.path.abspath(__file__))
root = os.path.join(here, "..", "..")
sys.path.insert(0, os.path.join(root, "test", "view"))
import headless_chromium  # noqa: E402

hullmap = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(root, "build", "cli", "hullmap"))
reason = headless_chromium.missing()
if reason:
    sys.exit("view_picture.py: " + reason)
# Run from the checkout with relative paths: the frame string (report.json, the legend) names them.
os.chdir(root)
room = os.path.join("maps", "room")
work = tempfile.mkdtemp(prefix="hullmap-view-picture-")
try:
    out = os.path.join(work, "room")
    subprocess.run([hullmap, "build", os.path.join(room, "map_points.txt"), "--trajectory",
                    os.path.join(room, "KeyFrameTrajectory.txt"), "--align", os.path.join(room, "reference_trajectory.txt"),
                    "-o", out], check=True, stdout=subprocess.DEVNULL)
    subprocess.run([hullmap, "plan", out, "--from", "-3,-3,1", "--to", "3,3,1.2", "--radius", "0.3",
                    "-o", os.path.join(work, "plan.txt")], check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(work, "through.txt"), "w") as f:
        f.write("# x y z: from the south-west corner through the furniture\n-3 -3 1\n0 -2.3 0.6\n3 3 1.2\n")
    page = os.path.join(work, "room.html")
    subprocess.run([hullmap, "view", out, "-o", page, "--path", os.path.join(work, "plan.txt"), "--path",
                    os.path.join(work, "through.txt"), "-r", "0.3"], check=True, stdout=subprocess.DEVNULL)
    with headless_chromium.Browser(1280, 760) as browser:
        errors, summary = browser.load(page)
        if errors or not summary or not summary.get("ready"):
            sys.exit("view_picture.py: the page failed: %s" % errors)
        browser.run("hullmapView.setDetail(0)")  # every voxel, whatever this machine's frame time
        browser.run("hullmapView.setView(arguments[0], arguments[1])", [-1.2, -8.6, 10.4], [0.4, -0.1, 0.0])
        png = browser.screenshot_png()
    from PIL import Image
    image = Image.open(io.BytesIO(png)).convert("RGB")
    # 256 colours are plenty for flat shading and keep the file small.
    image.quantize(colors=256, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE).save(
        os.path.join(here, "view_room.png"), optimize=True)
    print("wrote " + os.path.join(here, "view_room.png"))
finally:
    shutil.rmtree(work, ignore_errors=True)
