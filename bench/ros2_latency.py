#!/usr/bin/env python3
"""Latency of the ROS 2 node (hullmap_ros2's hullmap_node) from a map message to its published
obstacles, at 10k, 20k, 100k and 1M map points, against octomap's insertPointCloud of the same points
from one keyframe, in the same run: the method of bench/ros_latency.py (the ROS 1 row), over ROS 2.
Prints the markdown rows of docs/BENCHMARKS.md.

usage: bench/ros2_latency.py BENCH_OCTOMAP_CLOUD [repeats] [--defaults [SIZE...]]
  with ROS 2 and the hullmap_ros2 package sourced (bench/section_ros.sh does it);
  BENCH_OCTOMAP_CLOUD: a bench build's hullmap_bench_octomap_cloud.

The map (ros_latency.room): a 10 x 8 x 3 m room holding 8 boxes whose surfaces carry 90% of the
points, 10% scattered, sent as a FLOAT32 PointCloud2 on ~/cloud_in by a reliable publisher. The
node's cloud input is made reliable (its QoS override), as ROS 1's TCP is: a lost message would
stall the measurement. With --defaults the node runs at its defaults, no override: its input
follows the reliable publisher (docs/ROS.md, QoS), measured at SIZE points (default 1000000). end-to-end:
publish() to the ~/obstacles message with the same stamp received here (serialisation and DDS
transport both ways included); node: the node's own latency_ms; rebuild_ms: the build alone.
Parameters are hullmap build's defaults. Medians of `repeats` messages per size. The node and this
client run on a ROS_DOMAIN_ID of their own (test/ros2/ros2_support.claim_domain).
"""
import json
import os
import shutil
import signal
import struct
import subprocess
import sys
import tempfile
import threading
import time

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, here)
sys.path.insert(0, os.path.join(here, "..", "test", "ros2"))
os.environ.setdefault("HULLMAP_BINARY", "hullmap")
os.environ.setdefault("HULLMAP_SOURCE_DIR", os.path.join(here, ".."))
os.environ.setdefault("HULLMAP_TEST_TMP", tempfile.gettempdir())
from ros2_support import claim_domain  # noqa: E402
from ros_latency import ORIGIN, SIZES, median, room  # noqa: E402  (the ROS 1 row's maps)


def main():
    args = sys.argv[1:]
    defaults = "--defaults" in args
    sizes = SIZES
    if defaults:
        sizes = [int(a) for a in args[args.index("--defaults") + 1:]] or [1_000_000]
        args = args[:args.index("--defaults")]
    octomap_binary = args[0]
    repeats = int(args[1]) if len(args) > 1 else 3
    claim_domain()
    import rclpy
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
    from builtin_interfaces.msg import Time
    from sensor_msgs.msg import PointCloud2, PointField
    from std_msgs.msg import String
    from visualization_msgs.msg import MarkerArray

    tmp = tempfile.mkdtemp(prefix="hullmap_ros2_latency_")
    prefix = "qos_overrides./hullmap/cloud_in.subscription."
    override = [] if defaults else ["-p", prefix + "reliability:=reliable", "-p", prefix + "depth:=2"]
    node = subprocess.Popen(["ros2", "run", "hullmap_ros2", "hullmap_node", "--ros-args", *override],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    rclpy.init()
    client = rclpy.create_node("hullmap_bench_%d" % os.getpid())
    executor = SingleThreadedExecutor()
    executor.add_node(client)
    spinner = threading.Thread(target=executor.spin, daemon=True)
    spinner.start()
    try:
        state = {"stats": None, "obstacles": {}}
        latched = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                             durability=DurabilityPolicy.TRANSIENT_LOCAL)
        client.create_subscription(String, "/hullmap/stats",
                                   lambda m: state.__setitem__("stats", json.loads(m.data)), latched)

        def on_obstacles(msg):
            if msg.markers:
                s = msg.markers[0].header.stamp
                state["obstacles"][s.sec * 10**9 + s.nanosec] = time.perf_counter()
        client.create_subscription(MarkerArray, "/hullmap/obstacles", on_obstacles,
                                   QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE,
                                              durability=DurabilityPolicy.TRANSIENT_LOCAL))
        pub = client.create_publisher(PointCloud2, "/hullmap/cloud_in",
                                      QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE))
        while pub.get_subscription_count() == 0 or state["stats"] is None:
            time.sleep(0.05)
        # At the defaults the node re-creates its reader as reliable once it has seen this writer.
        while any(i.qos_profile.reliability != ReliabilityPolicy.RELIABLE
                  for i in client.get_subscriptions_info_by_topic("/hullmap/cloud_in")):
            time.sleep(0.05)
        time.sleep(1.0)  # the node's reader matches this writer too

        print("| map points | voxels | obstacles | ROS 2 node end-to-end (ms) | node latency_ms | rebuild_ms | "
              "octomap insertPointCloud (ms) | octomap / hullmap end-to-end |")
        print("|---|---|---|---|---|---|---|---|")
        for n in sizes:
            points = room(n)
            xyz = os.path.join(tmp, "room_%d.xyz" % n)
            with open(xyz, "w") as f:
                f.writelines("%.6f %.6f %.6f\n" % p for p in points)
            data = b"".join(struct.pack("<3f", *p) for p in points)
            e2e, node_ms, rebuild = [], [], []
            for r in range(repeats):
                msg = PointCloud2()
                msg.header.frame_id = "world"
                msg.header.stamp = Time(sec=1000 + n // 1000, nanosec=r + 1)
                msg.fields = [PointField(name=c, offset=4 * i, datatype=PointField.FLOAT32, count=1)
                              for i, c in enumerate("xyz")]
                msg.height, msg.width, msg.point_step = 1, n, 12
                msg.row_step, msg.is_dense, msg.data = 12 * n, True, data
                stamp = msg.header.stamp.sec * 10**9 + msg.header.stamp.nanosec
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
        shutil.rmtree(tmp, ignore_errors=True)
        executor.shutdown()
        client.destroy_node()
        rclpy.shutdown()
        try:
            os.killpg(node.pid, signal.SIGINT)
            node.wait(20)
        except (ProcessLookupError, subprocess.TimeoutExpired):
            os.killpg(node.pid, signal.SIGKILL)
            node.wait(10)


if __name__ == "__main__":
    main()
