#!/usr/bin/python3
"""Draws docs/img/ros_markers.png from what hullmap_node publishes (no RViz on a headless machine).

Starts a ROS master on a free port and hullmap_node at its defaults, publishes the generated room
scene's map points (`hullmap generate --layout room --z-up`, metric and z-up) as one PointCloud2 on
~cloud_in, waits for the latched ~obstacles and ~occupied_cells_vis_array MarkerArrays, and renders
them as RViz would show them from above at an angle: each hull's TRIANGLE_LIST in its marker colour
(painter's order), its footprint LINE_STRIP, and the occupied cells as grey dots.

usage: docs/img/ros_picture.py BUILD_DIR [OUT.png]   (Debian's python3 with python3-rospy; rsvg-convert)
"""
import math
import os
import shutil
import socket
import struct
import subprocess
import sys
import tempfile
import time

build = sys.argv[1] if len(sys.argv) > 1 else "build"
out = sys.argv[2] if len(sys.argv) > 2 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "ros_markers.png")
node_bin = os.path.join(build, "ros", "hullmap_node")
hullmap = os.path.join(build, "cli", "hullmap")
for path in (node_bin, hullmap):
    if not os.access(path, os.X_OK):
        sys.exit("%s: not built (ROS1 packages missing?)" % path)

work = tempfile.mkdtemp(prefix="hullmap-ros-picture-")
subprocess.run([hullmap, "generate", "--layout", "room", "--z-up", "--seed", "3", "-o", os.path.join(work, "scene")],
               check=True, stdout=subprocess.DEVNULL)
points = []
with open(os.path.join(work, "scene", "map_points.txt")) as f:
    for line in f:
        fields = line.split()
        if len(fields) == 3 and not line.startswith("#"):
            points.append(tuple(float(v) for v in fields))

with socket.socket() as s:
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
os.environ.update(ROS_MASTER_URI="http://127.0.0.1:%d" % port, ROS_IP="127.0.0.1", ROS_HOME=os.path.join(work, "ros"))
master = subprocess.Popen(["rosmaster", "--core", "-p", str(port)], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
node = None
try:
    import rosgraph
    deadline = time.time() + 20
    while not rosgraph.Master("/hullmap_picture").is_online():
        if time.time() > deadline:
            sys.exit("rosmaster did not come up")
        time.sleep(0.05)
    import rospy
    from sensor_msgs.msg import PointCloud2, PointField
    from visualization_msgs.msg import Marker, MarkerArray

    node = subprocess.Popen([node_bin, "__name:=hullmap"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    rospy.init_node("hullmap_picture", anonymous=True, disable_signals=True)
    got = {}
    rospy.Subscriber("/hullmap/obstacles", MarkerArray, lambda m: got.__setitem__("obstacles", m))
    rospy.Subscriber("/hullmap/occupied_cells_vis_array", MarkerArray, lambda m: got.__setitem__("cells", m))
    pub = rospy.Publisher("/hullmap/cloud_in", PointCloud2, queue_size=1, latch=True)
    msg = PointCloud2()
    msg.header.frame_id = "map"
    msg.header.stamp = rospy.Time.now()
    msg.fields = [PointField(name=n, offset=8 * i, datatype=PointField.FLOAT64, count=1) for i, n in enumerate("xyz")]
    msg.height, msg.width, msg.point_step = 1, len(points), 24
    msg.row_step, msg.is_dense = 24 * len(points), True
    msg.data = b"".join(struct.pack("<3d", *p) for p in points)
    pub.publish(msg)
    deadline = time.time() + 60
    while time.time() < deadline and not (
            "obstacles" in got and "cells" in got and any(m.ns == "hulls" and m.action == Marker.ADD
                                                          for m in got["obstacles"].markers)):
        time.sleep(0.05)
    if "obstacles" not in got or "cells" not in got:
        sys.exit("hullmap_node published no obstacles within 60 s")
finally:
    if node is not None:
        node.terminate()
        node.wait(10)
    master.terminate()
    master.wait(10)

# An RViz-like orbit view: azimuth 35 degrees, elevation 40 degrees.
az, el = math.radians(35), math.radians(40)


def view(p):
    x, y, z = p.x, p.y, p.z
    u = x * math.cos(az) - y * math.sin(az)
    w = x * math.sin(az) + y * math.cos(az)
    v = z * math.cos(el) - w * math.sin(el)
    depth = w * math.cos(el) + z * math.sin(el)
    return u, -v, depth


PALETTE = ["#f3c300", "#875692", "#f38400", "#a1caf1", "#be0032", "#c2b280", "#008856", "#e68fac", "#0067a5",
           "#f99379", "#604e97", "#f6a600", "#b3446c", "#dcd300", "#882d17", "#8db600"]  # Kelly's colours
shapes = []  # (depth, svg element)
hulls = footprints = 0
for m in got["obstacles"].markers:
    if m.action != Marker.ADD:
        continue
    # One colour per obstacle id (the node gives every hull the same colour, as RViz would show it).
    colour = PALETTE[m.id % len(PALETTE)]
    if m.ns == "hulls" and m.type == Marker.TRIANGLE_LIST:
        hulls += 1
        for k in range(0, len(m.points) - 2, 3):
            tri = [view(p) for p in m.points[k:k + 3]]
            d = sum(t[2] for t in tri) / 3
            pts = " ".join("%.3f,%.3f" % (t[0], t[1]) for t in tri)
            shapes.append((d, '<polygon points="%s" fill="%s" fill-opacity="0.55" stroke="%s" stroke-width="0.01"/>'
                           % (pts, colour, colour)))
    elif m.ns == "footprints" and m.type in (Marker.LINE_STRIP, Marker.LINE_LIST):
        footprints += 1
        pts = [view(p) for p in m.points]
        runs = [pts] if m.type == Marker.LINE_STRIP else [pts[k:k + 2] for k in range(0, len(pts) - 1, 2)]
        for run in runs:
            shapes.append((max(t[2] for t in run) + 100,
                           '<polyline points="%s" fill="none" stroke="#222" stroke-width="0.02"/>'
                           % " ".join("%.3f,%.3f" % (t[0], t[1]) for t in run)))
cells = floor_cells = 0
for m in got["cells"].markers:
    for p in m.points:
        cells += 1
        if p.z < m.scale.z:  # the floor (levelled to z = 0): left out of the picture for clarity
            floor_cells += 1
            continue
        u, v, d = view(p)
        shapes.append((d, '<circle cx="%.3f" cy="%.3f" r="0.012" fill="#999"/>' % (u, v)))
shapes.sort(key=lambda s: -s[0])  # far first
xs, ys = [], []
for _, e in shapes:
    if e.startswith("<circle"):
        parts = e.split('"')
        xs.append(float(parts[1]))
        ys.append(float(parts[3]))
x0, x1, y0, y1 = min(xs) - 0.5, max(xs) + 0.5, min(ys) - 0.8, max(ys) + 0.5
caption = ("hullmap_node at its defaults on a generated room (%d map points, one PointCloud2): %d hulls (ns hulls), "
           "%d footprints, %d occupied cells (octomap_server's CUBE_LIST; the %d floor cells not drawn), drawn from "
           "the published markers" % (len(points), hulls, footprints, cells, floor_cells))
svg = os.path.join(work, "markers.svg")
with open(svg, "w") as f:
    f.write('<svg xmlns="http://www.w3.org/2000/svg" viewBox="%.3f %.3f %.3f %.3f" width="900" height="%d">\n'
            % (x0, y0, x1 - x0, y1 - y0, int(900 * (y1 - y0) / (x1 - x0))))
    f.write('<rect x="%.3f" y="%.3f" width="%.3f" height="%.3f" fill="#30303a"/>\n' % (x0, y0, x1 - x0, y1 - y0))
    for _, e in shapes:
        f.write(e + "\n")
    f.write('<text x="%.3f" y="%.3f" font-size="%.3f" fill="#eee" font-family="sans-serif">%s</text>\n'
            % (x0 + 0.2, y0 + 0.4, (x1 - x0) / 135, caption))
    f.write("</svg>\n")
subprocess.run(["rsvg-convert", "-w", "900", svg, "-o", out + ".tmp"], check=True)
os.replace(out + ".tmp", out)
shutil.rmtree(work, ignore_errors=True)
print("%s: %d hulls, %d footprints, %d cells" % (out, hulls, footprints, cells))
