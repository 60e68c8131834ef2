#!/usr/bin/env python3
"""Latency of hullmap_node from a map message to its published obstacles, at 10k, 20k, 100k and 1M map
points, against octomap's insertPointCloud of the same points from one keyframe (the work
octomap_server does on every message), in the same run. Prints the markdown rows of docs/BENCHMARKS.md.

usage: bench/ros_latency.py HULLMAP_NODE BENCH_OCTOMAP_CLOUD [repeats]
  HULLMAP_NODE: build/ros/hullmap_node; BENCH_OCTOMAP_CLOUD: a bench build's hullmap_bench_octomap_cloud.

The map: a 10 x 8 x 3 m room holding 8 boxes (furniture) whose surfaces carry 90% of the points, and
10% scattered uniformly (ORB-SLAM's outliers), sent as a FLOAT32 PointCloud2 on ~cloud_in as the
ORB-SLAM2/3 wrappers send it. end-to-end: publish() to the ~obstacles message with the same stamp
received here (serialisation and transport both ways included); node: the node's own latency_ms
(message callback to obstacles published). Parameters are hullmap build's defaults (resolution 0.05,
eps and min_pts chosen from the map, floor search, convex parts). Medians of `repeats` messages per size.
"""
import json
import os
import random
import socket
import struct
import subprocess
import sys
import tempfile
import time

SIZES = [10_000, 20_000, 100_000, 1_000_000]
ORIGIN = (5.0, 4.0, 1.5)


def room(n, seed=1):
    rng = random.Random(seed)
    boxes = [((1 + 1.1 * i, 1 + 0.7 * (i % 3), 0), (0.6, 0.5, 0.4 + 0.15 * i)) for i in range(8)]
    points = []
    surface = int(0.9 * n)
    for k in range(surface):
        (x0, y0, z0), (sx, sy, sz) = boxes[k % len(boxes)]
        u, v = rng.random(), rng.random()
        face = rng.randrange(5)  # four sides and the top
        if face == 0: p = (x0 + u * sx, y0, z0 + v * sz)
        elif face == 1: p = (x0 + u * sx, y0 + sy, z0 + v * sz)
        elif face == 2: p = (x0, y0 + u * sy, z0 + v * sz)
        elif face == 3: p = (x0 + sx, y0 + u * sy, z0 + v * sz)
        else: p = (x0 + u * sx, y0 + v * sy, z0 + sz)
        points.append(p)
    for _ in range(n - surface):
        points.append((rng.uniform(0, 10), rng.uniform(0, 8), rng.uniform(0, 3)))
    return points


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def median(values):
    values = sorted(values)
    return values[len(values) // 2]


def main():
    node_binary, octomap_binary = sys.argv[1], sys.argv[2]
    repeats = int(sys.argv[3]) if len(sys.argv) > 3 else 3
    tmp = tempfile.mkdtemp(prefix="hullmap_ros_latency_")
    port = free_port()
    os.environ.update(ROS_MASTER_URI="http://127.0.0.1:%d" % port, ROS_IP="127.0.0.1",
                      ROS_HOME=os.path.join(tmp, "ros_home"))
    master = subprocess.Popen(["rosmaster", "--core", "-p", str(port)], stdout=subprocess.DEVNULL,
                              stderr=subprocess.DEVNULL)
    node = None
    try:
        import rosgraph
        while not rosgraph.Master("/bench").is_online():
            time.sleep(0.05)
        import rospy
        from sensor_msgs.msg import PointCloud2, PointField
        from std_msgs.msg import String
        from visualization_msgs.msg import MarkerArray
        rospy.init_node("hullmap_bench", anonymous=True, disable_signals=True)
        node = subprocess.Popen([node_binary, "__name:=hullmap"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        state = {"stats": None, "obstacles": {}}
        rospy.Subscriber("/hullmap/stats", String, lambda m: state.__setitem__("stats", json.loads(m.data)))

        def on_obstacles(msg):
            if msg.markers:
                state["obstacles"][msg.markers[0].header.stamp.to_nsec()] = time.perf_counter()
        rospy.Subscriber("/hullmap/obstacles", MarkerArray, on_obstacles, queue_size=10)
        pub = rospy.Publisher("/hullmap/cloud_in", PointCloud2, queue_size=1)
        while pub.get_num_connections() == 0 or state["stats"] is None:
            time.sleep(0.05)

        print("| map points | voxels | obstacles | hullmap_node end-to-end (ms) | node latency_ms | rebuild_ms | "
              "octomap insertPointCloud (ms) | octomap / hullmap end-to-end |")
        print("|---|---|---|---|---|---|---|---|")
        for n in SIZES:
            points = room(n)
            xyz = os.path.join(tmp, "room_%d.xyz" % n)
            with open(xyz, "w") as f:
                f.writelines("%.6f %.6f %.6f\n" % p for p in points)
            data = b"".join(struct.pack("<3f", *p) for p in points)
            e2e, node_ms, rebuild = [], [], []
            for r in range(repeats):
                msg = PointCloud2()
                msg.header.frame_id = "world"
                msg.header.stamp = rospy.Time(1000 + n // 1000, r + 1)
                msg.fields = [PointField(name=c, offset=4 * i, datatype=PointField.FLOAT32, count=1)
                              for i, c in enumerate("xyz")]
                msg.height, msg.width, msg.point_step = 1, n, 12
                msg.row_step, msg.is_dense, msg.data = 12 * n, True, data
                stamp = msg.header.stamp.to_nsec()
                before = state["stats"]["rebuilds"]
                start = time.perf_counter()
                pub.publish(msg)
                while stamp not in state["obstacles"] or state["stats"]["rebuilds"] <= before:
                    time.sleep(0.001)
                e2e.append(1000 * (state["obstacles"][stamp] - start))
                node_ms.append(state["stats"]["latency_ms"])
                rebuild.append(state["stats"]["rebuild_ms"])
            octo = json.loads(subprocess.run([octomap_binary, xyz, "0.05", *map(str, ORIGIN), str(repeats)],
                                             check=True, capture_output=True, text=True).stdout)
            s = state["stats"]
            print("| %d | %d | %d | %.1f | %.1f | %.1f | %.1f | %.1fx |" % (
                n, s["voxels"], s["obstacles"], median(e2e), median(node_ms), median(rebuild),
                octo["octomap_insert_ms"], octo["octomap_insert_ms"] / median(e2e)))
            sys.stdout.flush()
    finally:
        if node is not None:
            node.terminate()
            node.wait(10)
        master.terminate()
        master.wait(10)


if __name__ == "__main__":
    main()
