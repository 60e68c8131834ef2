#!/usr/bin/env python3
"""ROS 2 bags, recorded here with `ros2 bag record` in both storage formats (sqlite3 and MCAP) from
messages published with rclpy: `hullmap build BAG --topic T` (rosbag2's own reader, through
hullmap_ros2's hullmap_bag_reader) gives what `hullmap build` gives on the same points from a file;
--trajectory-topic what --trajectory gives with a TUM file of the same poses; a missing topic, a
topic of another type and damaged bags exit 2 with one line naming the bag; and `ros2 bag play` of a
bag into the node gives the obstacles that `hullmap build` gives on the bag.
"""
import glob
import json
import os
import shutil
import signal
import subprocess
import sys
import time
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ros2_support import (HULLMAP, TIMEOUT, Client, HullmapNode, Process, boxes, claim_domain, cloud,  # noqa: E402
                          echo_markers, expected_triangles, fresh_tmp, reliable_input, same_triangles, stop_daemon,
                          wait_for, write_xyz, ECHO_DUMP)

TMP = None
client = None
ARGS = ["--resolution", "0.05", "--eps", "0.15", "--min-pts", "2"]
STORAGES = ("sqlite3", "mcap")
# Keyframes: (sec, nanosec), position, quaternion (x y z w), in the map topic's frame.
KEYFRAMES = [((1403636580, 250000000), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0)),
             ((1403636580, 500000000), (1.5, -0.5, 0.5), (0.0, 0.0, 0.38268343236508984, 0.9238795325112867)),
             ((1403636581, 0), (3.0, 0.5, 1.0), (0.0, 0.0, 0.0, 1.0))]
CLOUD_POINTS = [(0 + 0.04 * i, 0.04 * j, 1 + 0.04 * k) for i in range(6) for j in range(6) for k in range(6)] + \
               [(1 + 0.04 * i, 0.04 * j, 1 + 0.04 * k) for i in range(6) for j in range(6) for k in range(6)]


def setUpModule():
    global TMP, client
    claim_domain()
    TMP = fresh_tmp("ros2_bag")
    client = Client()


def tearDownModule():
    client.close()
    stop_daemon()


def pose_stamped(stamp, position, quaternion):
    from geometry_msgs.msg import PoseStamped
    msg = PoseStamped()
    msg.header.frame_id = "world"
    msg.header.stamp.sec, msg.header.stamp.nanosec = stamp
    msg.pose.position.x, msg.pose.position.y, msg.pose.position.z = position
    o = msg.pose.orientation
    o.x, o.y, o.z, o.w = quaternion
    return msg


def messages():
    """(topic, message) in publishing order: the echo dump's markers, three clouds (the last one
    malformed: no z), the keyframes one a PoseStamped and as a growing Path."""
    from nav_msgs.msg import Path
    out = [("/ORB_SLAM/Map", m) for m in echo_markers()]
    no_z = cloud(boxes([(7, 7, 7)]), with_z=False)
    out += [("/orb_slam3/all_points", cloud(boxes([(5, 5, 5)]))), ("/orb_slam3/all_points", cloud(CLOUD_POINTS)),
            ("/orb_slam3/all_points", no_z)]
    path = Path()
    path.header.frame_id = "world"
    for kf in KEYFRAMES:
        out.append(("/keyframe", pose_stamped(*kf)))
        path.poses.append(pose_stamped(*kf))
        grown = Path()
        grown.header = path.header
        grown.poses = list(path.poses)
        out.append(("/trajectory", grown))
    return out


def count_messages(bag, storage):
    import rosbag2_py
    reader = rosbag2_py.SequentialReader()
    reader.open(rosbag2_py.StorageOptions(uri=bag, storage_id=storage),
                rosbag2_py.ConverterOptions(input_serialization_format="cdr", output_serialization_format="cdr"))
    counts = {}
    while reader.has_next():
        topic, _, _ = reader.read_next()
        counts[topic] = counts.get(topic, 0) + 1
    return counts


def record(storage, name):
    """A bag of messages() recorded by `ros2 bag record -s STORAGE`: its directory."""
    from rclpy.duration import Duration
    sent = messages()
    expected = {}
    for topic, _ in sent:
        expected[topic] = expected.get(topic, 0) + 1
    # The recorder's subscriptions hold every message (its default depth, 10, would drop some of a
    # quick burst before it writes them).
    qos = os.path.join(TMP, "record_qos.yaml")
    with open(qos, "w") as f:
        for topic in expected:
            f.write("%s:\n  history: keep_last\n  depth: 100\n  reliability: reliable\n  durability: volatile\n" % topic)
    for attempt in range(3):
        bag = os.path.join(TMP, "%s_%d" % (name, attempt))
        recorder = Process(["ros2", "bag", "record", "-s", storage, "-o", bag, "--qos-profile-overrides-path", qos,
                            *sorted(expected)], os.path.join(TMP, "%s_%d_record.log" % (name, attempt)))
        try:
            publishers = {}
            for topic, msg in sent:
                if topic not in publishers:
                    publishers[topic] = client.publisher(topic, type(msg), depth=len(sent))
            for topic, msg in sent:
                publishers[topic].publish(msg)
            for pub in publishers.values():
                pub.wait_for_all_acked(Duration(seconds=TIMEOUT))  # in the recorder's reader
            time.sleep(1.0)  # and written by it
        finally:
            recorder.stop()
            for pub in publishers.values():
                client.node.destroy_publisher(pub)
        if count_messages(bag, storage) == expected:
            return bag
        print("recording %s: %s of %s, again" % (bag, count_messages(bag, storage), expected), file=sys.stderr)
    raise AssertionError("ros2 bag record did not record every message in 3 attempts")


def build(inputs, name, extra=()):
    out = os.path.join(TMP, name)
    run = subprocess.run([HULLMAP, "build", *inputs, "-o", out, *ARGS, *extra], capture_output=True, text=True)
    return run, out


def obstacles(out):
    with open(os.path.join(out, "obstacles.json")) as f:
        return json.load(f)["obstacles"]


def storage_file(bag):
    files = glob.glob(os.path.join(bag, "*.db3")) + glob.glob(os.path.join(bag, "*.mcap"))
    assert len(files) == 1, files
    return files[0]


class RecordedBags(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.bags = {storage: record(storage, "run_" + storage) for storage in STORAGES}
        cls.tum = os.path.join(TMP, "keyframes.txt")
        with open(cls.tum, "w") as f:
            for (sec, nanosec), p, q in KEYFRAMES:
                f.write("%r %r %r %r %r %r %r %r\n" % ((sec + 1e-9 * nanosec,) + p + q))

    def inputs(self):
        """Each bag as its directory and as its storage file."""
        for storage, bag in self.bags.items():
            yield storage, bag
            yield storage, storage_file(bag)

    def test_the_marker_topic_gives_the_echo_dumps_obstacles(self):
        dump_run, dump_out = build([ECHO_DUMP], "from_dump")
        self.assertEqual(dump_run.returncode, 0, dump_run.stderr)
        expected = obstacles(dump_out)
        self.assertGreater(len(expected), 0)
        for storage, bag in self.inputs():
            run, out = build([bag], "markers_" + os.path.basename(bag), ["--topic", "/ORB_SLAM/Map"])
            self.assertEqual(run.returncode, 0, run.stderr)
            self.assertEqual(obstacles(out), expected, bag)
            self.assertIn("points: 7 read", run.stdout)

    def test_the_cloud_topic_gives_its_last_well_formed_cloud_as_the_same_points_from_a_file(self):
        xyz = os.path.join(TMP, "last_cloud.xyz")
        write_xyz(xyz, CLOUD_POINTS)
        xyz_run, xyz_out = build([xyz], "cloud_xyz")
        self.assertEqual(xyz_run.returncode, 0, xyz_run.stderr)
        self.assertEqual(len(obstacles(xyz_out)), 2)
        for storage, bag in self.inputs():
            run, out = build([bag], "cloud_" + os.path.basename(bag), ["--topic", "/orb_slam3/all_points"])
            self.assertEqual(run.returncode, 0, run.stderr)
            self.assertIn("1 malformed message", run.stderr)
            self.assertEqual(obstacles(out), obstacles(xyz_out), bag)
            with open(os.path.join(out, "map.bt"), "rb") as a, open(os.path.join(xyz_out, "map.bt"), "rb") as b:
                self.assertEqual(a.read(), b.read(), bag)

    def test_trajectory_topics_give_what_the_tum_file_gives(self):
        tum_run, tum_out = build([ECHO_DUMP], "kf_tum", ["--trajectory", self.tum, "--max-range", "5"])
        self.assertEqual(tum_run.returncode, 0, tum_run.stderr)
        for storage, bag in self.bags.items():
            for topic in ("/keyframe", "/trajectory"):
                run, out = build([bag], "kf_%s_%s" % (storage, topic.strip("/")),
                                 ["--topic", "/ORB_SLAM/Map", "--trajectory-topic", topic, "--max-range", "5"])
                self.assertEqual(run.returncode, 0, run.stderr)
                with open(os.path.join(out, "report.json")) as f:
                    report = json.load(f)
                self.assertEqual(report["keyframes"], 3)
                self.assertEqual(report["parameters"]["trajectory"], bag + ":" + topic)
                self.assertEqual(obstacles(out), obstacles(tum_out))
                with open(os.path.join(out, "map.bt"), "rb") as a, open(os.path.join(tum_out, "map.bt"), "rb") as b:
                    self.assertEqual(a.read(), b.read(), (bag, topic))  # the same free space was cast

    def assert_one_line_exit_2(self, run, *needles):
        self.assertEqual(run.returncode, 2, run.stdout + run.stderr)
        lines = run.stderr.strip().splitlines()
        self.assertEqual(len(lines), 1, run.stderr)
        for needle in needles:
            self.assertIn(needle, lines[0])

    def test_a_missing_topic_a_topic_of_another_type_and_no_topic_option_are_named(self):
        for storage, bag in self.bags.items():
            run, _ = build([bag], "missing_" + storage, ["--topic", "/no/such/topic"])
            self.assert_one_line_exit_2(run, bag, "/no/such/topic", "/ORB_SLAM/Map")
            run, _ = build([bag], "wrong_" + storage, ["--topic", "/keyframe"])
            self.assert_one_line_exit_2(run, bag, "/keyframe", "geometry_msgs/msg/PoseStamped")
            run, _ = build([bag], "wrong_kf_" + storage, ["--topic", "/ORB_SLAM/Map", "--trajectory-topic", "/ORB_SLAM/Map"])
            self.assert_one_line_exit_2(run, "expected geometry_msgs/msg/PoseStamped or nav_msgs/msg/Path")
            run, _ = build([bag], "no_option_" + storage)
            self.assert_one_line_exit_2(run, bag, "a ROS 2 bag: give --topic")

    def test_damaged_bags_exit_2_naming_the_bag_and_write_nothing(self):
        for storage, bag in self.bags.items():
            with open(storage_file(bag), "rb") as f:
                data = f.read()
            extension = os.path.splitext(storage_file(bag))[1]
            # Damage to the structure rosbag2 reads: the file's start, an MCAP chunk's record header (the
            # chunk after the 8-byte magic, a 25-byte header and a 33-byte metadata record), an SQLite
            # b-tree page; and truncations. Neither format checks the bytes inside a message (the MCAP
            # writer stores no chunk CRC): damage there is not seen, and not tested.
            damaged = {"truncated_half": data[:len(data) // 2], "truncated_100": data[:100],
                       "header": b"\xff" * 64 + data[64:], "empty": b""}
            structure = 84 if storage == "mcap" else 4096
            damaged["structure"] = data[:structure] + b"\xff" * 64 + data[structure + 64:]
            for name, content in damaged.items():
                path = os.path.join(TMP, "%s_%s%s" % (storage, name, extension))
                with open(path, "wb") as f:
                    f.write(content)
                run, out = build([path], "damaged_%s_%s" % (storage, name), ["--topic", "/ORB_SLAM/Map"])
                self.assert_one_line_exit_2(run, path)
                self.assertFalse(os.path.exists(out), path)

    def test_without_the_reader_hullmap_build_says_what_it_needs(self):
        env = dict(os.environ, AMENT_PREFIX_PATH="/nonexistent")
        run = subprocess.run([HULLMAP, "build", self.bags["sqlite3"], "--topic", "/ORB_SLAM/Map", "-o",
                              os.path.join(TMP, "no_reader")], capture_output=True, text=True, env=env)
        self.assert_one_line_exit_2(run, "hullmap_ros2", "AMENT_PREFIX_PATH")

    def test_ros2_bag_play_into_the_node_gives_hullmap_builds_obstacles_on_the_bag(self):
        from sensor_msgs.msg import PointCloud2  # noqa: F401 (the node's input type)
        for storage, bag in self.bags.items():
            run, out = build([bag], "play_build_" + storage, ["--topic", "/orb_slam3/all_points", "--floor", "none",
                                                              "--concavity", "none"])
            self.assertEqual(run.returncode, 0, run.stderr)
            expected = expected_triangles(obstacles(out))
            name = "played_" + storage
            params = {"resolution": 0.05, "eps": 0.15, "min_pts": 2, "floor": "none", "concavity": "none"}
            # QoS overrides go by the resolved topic: ~/cloud_in is remapped onto the bag's topic.
            params.update(reliable_input(name, "/orb_slam3/all_points", 10))
            node = HullmapNode(client, TMP, params, name=name,
                               extra_args=["-r", "/%s/cloud_in:=/orb_slam3/all_points" % name])
            try:
                # --delay: time for the node and the player to discover each other before the first
                # message; --wait-for-all-acked: the player ends once the node has every message.
                play = Process(["ros2", "bag", "play", bag, "--topics", "/orb_slam3/all_points", "--delay", "2",
                                "--wait-for-all-acked", str(int(TIMEOUT * 1000)), "--disable-keyboard-controls"],
                               os.path.join(TMP, name + "_play.log"))
                try:
                    self.assertEqual(play.process.wait(TIMEOUT), 0, play.output())
                finally:
                    play.stop()
                # The three clouds: two taken, the one without z skipped (as the bag reader skips it).
                stats = node.wait_idle(3)
                self.assertEqual((stats["messages"], stats["skipped"]), (2, 1))
                wait_for("~/obstacles equal to hullmap build's on the bag",
                         lambda: same_triangles(node.hull_triangles(), expected))
            finally:
                node.stop()


if __name__ == "__main__":
    unittest.main(verbosity=2)
