#!/usr/bin/env python3
"""`hullmap build run.bag --topic T`: bags written here with python3-rosbag (no ROS master needed).

Environment: HULLMAP_BINARY (the CLI), HULLMAP_SOURCE_DIR, HULLMAP_TEST_TMP. A bag of the echo dump's
messages must give what `hullmap build` gives on the dump itself; a PointCloud2 topic its last
cloud; a missing topic, a truncated and a corrupt bag exit 2 with one line naming the topic or bag.
"""
import json
import os
import shutil
import struct
import subprocess
import unittest

import genpy
import rosbag
import rospy
import yaml
from geometry_msgs.msg import PoseStamped
from nav_msgs.msg import Path
from sensor_msgs.msg import PointCloud2, PointField
from visualization_msgs.msg import Marker

HULLMAP = os.environ["HULLMAP_BINARY"]
SOURCE = os.environ["HULLMAP_SOURCE_DIR"]
TMP = os.path.join(os.environ["HULLMAP_TEST_TMP"], "ros_bag")
ECHO_DUMP = os.path.join(SOURCE, "test", "data", "orbslam_echo_map.txt")
ARGS = ["--resolution", "0.05", "--eps", "0.15", "--min-pts", "2"]


def setUpModule():
    shutil.rmtree(TMP, ignore_errors=True)
    os.makedirs(TMP)


def build(inputs, name, extra=()):
    out = os.path.join(TMP, name)
    run = subprocess.run([HULLMAP, "build", *inputs, "-o", out, *ARGS, *extra], capture_output=True, text=True)
    return run, out


def obstacles(out):
    with open(os.path.join(out, "obstacles.json")) as f:
        return json.load(f)["obstacles"]


def cloud(points, stamp):
    msg = PointCloud2()
    msg.header.frame_id = "world"
    msg.header.stamp = stamp
    msg.fields = [PointField(name=n, offset=8 * i, datatype=PointField.FLOAT64, count=1) for i, n in enumerate("xyz")]
    msg.height, msg.width = 1, len(points)
    msg.point_step = 24
    msg.row_step = 24 * len(points)
    msg.is_dense = True
    msg.data = b"".join(struct.pack("<3d", *p) for p in points)
    return msg


def box(cx, cy, cz, spacing=0.04, n=5):
    return [(cx + i * spacing, cy + j * spacing, cz + k * spacing)
            for i in range(n + 1) for j in range(n + 1) for k in range(n + 1)]


class BagInput(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.bag = os.path.join(TMP, "run.bag")
        with open(ECHO_DUMP) as f:
            docs = [d for d in yaml.safe_load_all(f) if d]
        cls.cloud_points = box(0, 0, 1) + box(1, 0, 1)
        with rosbag.Bag(cls.bag, "w") as bag:
            for i, doc in enumerate(docs):
                msg = Marker()
                genpy.message.fill_message_args(msg, [doc])
                bag.write("/ORB_SLAM/Map", msg, rospy.Time(100 + i))
            bag.write("/orb_slam3/all_points", cloud(box(5, 5, 5), rospy.Time(100)), rospy.Time(100))
            no_z = cloud(box(7, 7, 7), rospy.Time(103))
            no_z.fields = no_z.fields[:2]
            bag.write("/orb_slam3/all_points", cloud(cls.cloud_points, rospy.Time(102)), rospy.Time(102))
            bag.write("/orb_slam3/all_points", no_z, rospy.Time(103))  # malformed: skipped, as the node does

    def test_marker_topic_gives_the_echo_dumps_obstacles(self):
        run, out = build([self.bag], "from_bag", ["--topic", "/ORB_SLAM/Map"])
        self.assertEqual(run.returncode, 0, run.stderr)
        dump_run, dump_out = build([ECHO_DUMP], "from_dump")
        self.assertEqual(dump_run.returncode, 0, dump_run.stderr)
        expected = obstacles(dump_out)
        self.assertGreater(len(expected), 0)
        self.assertEqual(obstacles(out), expected)
        self.assertIn("points: 7 read", run.stdout)

    def test_cloud_topic_gives_its_last_well_formed_cloud(self):
        xyz = os.path.join(TMP, "last_cloud.xyz")
        with open(xyz, "w") as f:
            f.writelines("%r %r %r\n" % p for p in self.cloud_points)
        run, out = build([self.bag], "cloud_bag", ["--topic", "/orb_slam3/all_points"])
        self.assertEqual(run.returncode, 0, run.stderr)
        self.assertIn("1 malformed message", run.stderr)
        xyz_run, xyz_out = build([xyz], "cloud_xyz")
        self.assertEqual(xyz_run.returncode, 0, xyz_run.stderr)
        self.assertEqual(len(obstacles(xyz_out)), 2)
        self.assertEqual(obstacles(out), obstacles(xyz_out))

    def assert_one_line_exit_2(self, run, *needles):
        self.assertEqual(run.returncode, 2, run.stdout + run.stderr)
        lines = run.stderr.strip().splitlines()
        self.assertEqual(len(lines), 1, run.stderr)
        for needle in needles:
            self.assertIn(needle, lines[0])

    def test_a_missing_topic_is_named(self):
        run, _ = build([self.bag], "missing", ["--topic", "/no/such/topic"])
        self.assert_one_line_exit_2(run, "/no/such/topic", "run.bag")

    def test_a_bag_without_topic_option_is_refused(self):
        run, _ = build([self.bag], "no_option")
        self.assert_one_line_exit_2(run, "--topic")

    def test_truncated_bag(self):
        with open(self.bag, "rb") as f:
            data = f.read()
        for cut in (len(data) // 2, 100, 13):
            truncated = os.path.join(TMP, "truncated_%d.bag" % cut)
            with open(truncated, "wb") as f:
                f.write(data[:cut])
            run, out = build([truncated], "truncated_%d" % cut, ["--topic", "/ORB_SLAM/Map"])
            self.assert_one_line_exit_2(run, "truncated_%d.bag" % cut, "the file holds %d bytes" % cut)
            self.assertFalse(os.path.exists(out))

    def test_corrupt_bag(self):
        with open(self.bag, "rb") as f:
            data = bytearray(f.read())
        # The structure rosbag reads: version line, file header record, first chunk record (after the
        # 13-byte version line and the 4096-byte file header), the chunk infos at the end. ROS1 bags
        # carry no checksum: damage inside a message's bytes cannot be seen and is not tested.
        for name, offset in (("magic", 0), ("header", 20), ("chunk", 13 + 4096), ("index", len(data) - 64)):
            corrupt = bytearray(data)
            corrupt[offset:offset + 16] = b"\xff" * 16
            path = os.path.join(TMP, "corrupt_%s.bag" % name)
            with open(path, "wb") as f:
                f.write(corrupt)
            run, out = build([path], "corrupt_" + name, ["--topic", "/ORB_SLAM/Map"])
            self.assert_one_line_exit_2(run, "corrupt_%s.bag" % name, "not a readable ROS1 bag", "bytes")
            self.assertFalse(os.path.exists(out))


# Keyframes: stamp, position, quaternion (x y z w), in the map topic's frame.
KEYFRAMES = [(1403636580.25, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0)),
             (1403636580.5, (1.5, -0.5, 0.5), (0.0, 0.0, 0.38268343236508984, 0.9238795325112867)),
             (1403636581.0, (3.0, 0.5, 1.0), (0.0, 0.0, 0.0, 1.0))]


def pose_stamped(stamp, position, quaternion):
    msg = PoseStamped()
    msg.header.frame_id = "world"
    msg.header.stamp = rospy.Time.from_sec(stamp)
    msg.pose.position.x, msg.pose.position.y, msg.pose.position.z = position
    o = msg.pose.orientation
    o.x, o.y, o.z, o.w = quaternion
    return msg


class BagKeyframes(unittest.TestCase):
    """--trajectory-topic gives what --trajectory gives with a TUM file of the same poses."""

    @classmethod
    def setUpClass(cls):
        cls.tum = os.path.join(TMP, "keyframes.txt")
        with open(cls.tum, "w") as f:
            for stamp, p, q in KEYFRAMES:
                # the stamps as the bag holds them (nanoseconds)
                f.write("%r %r %r %r %r %r %r %r\n" % ((rospy.Time.from_sec(stamp).to_sec(),) + p + q))
        cls.bag = os.path.join(TMP, "keyframes.bag")
        with open(ECHO_DUMP) as f:
            docs = [d for d in yaml.safe_load_all(f) if d]
        with rosbag.Bag(cls.bag, "w") as bag:
            for i, doc in enumerate(docs):
                msg = Marker()
                genpy.message.fill_message_args(msg, [doc])
                bag.write("/ORB_SLAM/Map", msg, rospy.Time(100 + i))
            path = Path()
            path.header.frame_id = "world"
            for i, kf in enumerate(KEYFRAMES):
                bag.write("/keyframe", pose_stamped(*kf), rospy.Time(100 + i))
                path.poses.append(pose_stamped(*kf))
                bag.write("/trajectory", path, rospy.Time(100 + i))  # grows; the last holds all

    def check(self, topic, name):
        run, out = build([self.bag], name, ["--topic", "/ORB_SLAM/Map", "--trajectory-topic", topic, "--max-range", "5"])
        self.assertEqual(run.returncode, 0, run.stderr)
        tum_run, tum_out = build([ECHO_DUMP], name + "_tum", ["--trajectory", self.tum, "--max-range", "5"])
        self.assertEqual(tum_run.returncode, 0, tum_run.stderr)
        self.assertEqual(obstacles(out), obstacles(tum_out))
        with open(os.path.join(out, "report.json")) as f:
            report = json.load(f)
        with open(os.path.join(tum_out, "report.json")) as f:
            tum_report = json.load(f)
        self.assertEqual(report["keyframes"], 3)
        self.assertEqual(tum_report["keyframes"], 3)
        self.assertEqual(report["parameters"]["trajectory"], self.bag + ":" + topic)
        with open(os.path.join(out, "voxels.csv")) as a, open(os.path.join(tum_out, "voxels.csv")) as b:
            self.assertEqual(a.read(), b.read())
        with open(os.path.join(out, "map.bt"), "rb") as a, open(os.path.join(tum_out, "map.bt"), "rb") as b:
            self.assertEqual(a.read(), b.read())  # the same free space was cast

    def test_pose_stamped_keyframes(self):
        self.check("/keyframe", "kf_pose")

    def test_path_keyframes(self):
        self.check("/trajectory", "kf_path")

    def test_a_trajectory_topic_of_another_type_is_named(self):
        run, _ = build([self.bag], "kf_wrong", ["--topic", "/ORB_SLAM/Map", "--trajectory-topic", "/ORB_SLAM/Map"])
        self.assertEqual(run.returncode, 2)
        self.assertIn("expected geometry_msgs/PoseStamped or nav_msgs/Path", run.stderr)


if __name__ == "__main__":
    unittest.main(verbosity=2, warnings="ignore")
