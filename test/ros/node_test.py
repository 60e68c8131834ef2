#!/usr/bin/env python3
"""hullmap_node against a real ROS master (rosmaster --core on a free port, started and stopped here).

Environment: HULLMAP_NODE, HULLMAP_BINARY (the CLI), HULLMAP_SOURCE_DIR, HULLMAP_TEST_TMP. Every check
compares the node's published obstacles with `hullmap build` of the same points and parameters, or
with counters the node publishes on ~stats; nothing asserts on wall-clock time (waits only time out).
"""
import json
import math
import os
import shutil
import socket
import struct
import subprocess
import sys
import time
import unittest

import yaml

NODE = os.environ["HULLMAP_NODE"]
HULLMAP = os.environ["HULLMAP_BINARY"]
SOURCE = os.environ["HULLMAP_SOURCE_DIR"]
TMP = os.path.join(os.environ["HULLMAP_TEST_TMP"], "ros_node")
ECHO_DUMP = os.path.join(SOURCE, "test", "data", "orbslam_echo_map.txt")
TIMEOUT = 20.0  # seconds any single wait may take before the test fails

master = None


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def setUpModule():
    global master, rospy, genpy, Marker, MarkerArray, PointCloud2, PointField, String, Path, PoseStamped, Trigger, Empty
    shutil.rmtree(TMP, ignore_errors=True)
    os.makedirs(TMP)
    port = free_port()
    os.environ["ROS_MASTER_URI"] = "http://127.0.0.1:%d" % port
    os.environ["ROS_IP"] = "127.0.0.1"
    os.environ["ROS_HOME"] = os.path.join(TMP, "ros_home")
    os.environ.pop("ROS_HOSTNAME", None)
    master = subprocess.Popen(["rosmaster", "--core", "-p", str(port)], stdout=subprocess.DEVNULL,
                              stderr=subprocess.DEVNULL)
    import rosgraph
    deadline = time.time() + TIMEOUT
    while not rosgraph.Master("/hullmap_test").is_online():
        if time.time() > deadline or master.poll() is not None:
            raise RuntimeError("rosmaster did not come up on port %d" % port)
        time.sleep(0.05)
    import genpy as _genpy
    import rospy as _rospy
    from nav_msgs.msg import Path as _Path
    from geometry_msgs.msg import PoseStamped as _PoseStamped
    from sensor_msgs.msg import PointCloud2 as _PointCloud2, PointField as _PointField
    from std_msgs.msg import String as _String
    from std_srvs.srv import Empty as _Empty, Trigger as _Trigger
    from visualization_msgs.msg import Marker as _Marker, MarkerArray as _MarkerArray
    rospy, genpy = _rospy, _genpy
    Marker, MarkerArray, PointCloud2, PointField = _Marker, _MarkerArray, _PointCloud2, _PointField
    String, Path, PoseStamped, Trigger, Empty = _String, _Path, _PoseStamped, _Trigger, _Empty
    rospy.init_node("hullmap_test", anonymous=True, disable_signals=True)


def tearDownModule():
    if rospy is not None and not rospy.is_shutdown():
        rospy.signal_shutdown("tests done")
    if master is not None:
        master.terminate()
        master.wait(10)


rospy = None


def wait_for(what, condition):
    deadline = time.time() + TIMEOUT
    while time.time() < deadline:
        value = condition()
        if value:
            return value
        time.sleep(0.02)
    raise AssertionError("timed out waiting for " + what)


def cloud(points, with_z=True):
    """A PointCloud2 of FLOAT64 x, y (and z) fields: the exact doubles `hullmap build` reads as text."""
    names = ["x", "y", "z"] if with_z else ["x", "y"]
    msg = PointCloud2()
    msg.header.frame_id = "world"
    msg.header.stamp = rospy.Time.now()
    msg.fields = [PointField(name=n, offset=8 * i, datatype=PointField.FLOAT64, count=1) for i, n in enumerate(names)]
    msg.height = 1
    msg.width = len(points)
    msg.point_step = 8 * len(names)
    msg.row_step = msg.point_step * msg.width
    msg.is_dense = True
    msg.data = b"".join(struct.pack("<%dd" % len(names), *p[:len(names)]) for p in points)
    return msg


def boxes(centres, spacing=0.04, half=0.1):
    """Points on a grid filling an axis-aligned cube of half-width `half` around each centre."""
    n = int(round(2 * half / spacing))
    points = []
    for cx, cy, cz in centres:
        for i in range(n + 1):
            for j in range(n + 1):
                for k in range(n + 1):
                    points.append((cx - half + i * spacing, cy - half + j * spacing, cz - half + k * spacing))
    return points


def write_xyz(path, points):
    with open(path, "w") as f:
        for p in points:
            f.write("%r %r %r\n" % p)


def hullmap_build(inputs, out, args):
    subprocess.run([HULLMAP, "build", *inputs, "-o", out, *args], check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(out, "obstacles.json")) as f:
        return json.load(f)["obstacles"]


def expected_triangles(obstacles):
    """id -> the hull's triangles (its convex parts' hulls' when it has parts) as the TRIANGLE_LIST points
    the node must publish, in order."""
    def triangles(hull):
        return [tuple(hull["vertices"][k]) for t in hull["triangles"] for k in t]
    return {o["id"]: ([p for part in o["parts"] for p in triangles(part["hull"])] if o.get("parts") else
                      triangles(o["hull"])) for o in obstacles}


class Node:
    """One hullmap_node process with its private parameters, and the latest of each output it publishes."""

    count = 0

    def __init__(self, params):
        Node.count += 1
        self.name = "hullmap%d" % Node.count
        args = [NODE, "__name:=" + self.name] + ["_%s:=%s" % kv for kv in params.items()]
        self.log = open(os.path.join(TMP, self.name + ".log"), "w")
        self.process = subprocess.Popen(args, stdout=self.log, stderr=subprocess.STDOUT)
        self.stats = None
        self.obstacles = None
        self.path_check = None
        self.subs = [
            rospy.Subscriber("/%s/stats" % self.name, String, self._on_stats),
            rospy.Subscriber("/%s/obstacles" % self.name, MarkerArray, self._on_obstacles),
            rospy.Subscriber("/%s/path_check" % self.name, String, self._on_path_check),
        ]
        wait_for(self.name + "'s ~stats", lambda: self.stats is not None)

    def _on_stats(self, msg):
        self.stats = json.loads(msg.data)

    def _on_obstacles(self, msg):
        self.obstacles = msg

    def _on_path_check(self, msg):
        self.path_check = msg.data

    def publisher(self, topic, cls):
        pub = rospy.Publisher(topic, cls, queue_size=100)
        wait_for("the node to subscribe to " + topic, lambda: pub.get_num_connections() > 0)
        return pub

    def hull_triangles(self):
        """id -> TRIANGLE_LIST points of the latest ~obstacles (ns hulls)."""
        if self.obstacles is None:
            return None
        return {m.id: [(p.x, p.y, p.z) for p in m.points] for m in self.obstacles.markers
                if m.ns == "hulls" and m.action == Marker.ADD}

    def wait_idle(self, messages):
        """Until the node took `messages` map messages and nothing is waiting or running."""
        return wait_for("%s to take %d messages and go idle (stats %s)" % (self.name, messages, self.stats),
                        lambda: self.stats and self.stats["messages"] + self.stats["skipped"] >= messages and
                        not self.stats["pending"] and not self.stats["busy"] and self.stats)

    def alive(self):
        return self.process.poll() is None

    def stop(self):
        for s in self.subs:
            s.unregister()
        self.process.terminate()
        self.process.wait(10)
        self.log.close()


def same_triangles(a, b, tol=1e-9):
    if a is None or set(a) != set(b):
        return False
    for key in a:
        if len(a[key]) != len(b[key]):
            return False
        for p, q in zip(a[key], b[key]):
            if any(abs(u - v) > tol for u, v in zip(p, q)):
                return False
    return True


class EchoDumpAsMarkers(unittest.TestCase):
    def test_obstacles_equal_hullmap_build_of_the_dump(self):
        params = {"resolution": 0.05, "eps": 0.15, "min_pts": 2, "floor": "none", "concavity": "none"}
        expected = expected_triangles(hullmap_build([ECHO_DUMP], os.path.join(TMP, "echo_build"),
                                                    ["--resolution", "0.05", "--eps", "0.15", "--min-pts", "2", "--floor", "none", "--concavity", "none"]))
        self.assertGreater(len(expected), 0, "the fixture must give at least one obstacle")
        node = Node(params)
        try:
            pub = node.publisher("/ORB_SLAM/Map", Marker)
            with open(ECHO_DUMP) as f:
                docs = [d for d in yaml.safe_load_all(f) if d]
            map_messages = 0
            for doc in docs:
                msg = Marker()
                genpy.message.fill_message_args(msg, [doc])
                pub.publish(msg)
                map_messages += doc["ns"] == "MapPoints"
            node.wait_idle(map_messages)
            wait_for("~obstacles equal to hullmap build's",
                     lambda: same_triangles(node.hull_triangles(), expected))
            self.assertEqual(node.stats["skipped"], 0)
            self.assertEqual(node.stats["points"], 7)  # the last publication: 5 + 2 points
        finally:
            node.stop()


    def test_keyframes_give_the_tree_of_hullmap_build_with_their_trajectory(self):
        keyframes = [(1403636580.25, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0)),
                     (1403636580.5, (1.5, -0.5, 0.5), (0.0, 0.0, 0.38268343236508984, 0.9238795325112867))]
        tum = os.path.join(TMP, "node_keyframes.txt")
        path = Path()
        path.header.frame_id = "world"
        with open(tum, "w") as f:
            for stamp, p, q in keyframes:
                pose = PoseStamped()
                pose.header.stamp = rospy.Time.from_sec(stamp)
                pose.pose.position.x, pose.pose.position.y, pose.pose.position.z = p
                o = pose.pose.orientation
                o.x, o.y, o.z, o.w = q
                path.poses.append(pose)
                f.write("%r %r %r %r %r %r %r %r\n" % ((pose.header.stamp.to_sec(),) + p + q))
        args = ["--resolution", "0.05", "--eps", "0.15", "--min-pts", "2", "--floor", "none", "--concavity", "none",
                "--trajectory", tum]
        cli_out = os.path.join(TMP, "echo_trajectory_build")
        expected = expected_triangles(hullmap_build([ECHO_DUMP], cli_out, args))
        saved = os.path.join(TMP, "echo_trajectory_saved")
        node = Node({"resolution": 0.05, "eps": 0.15, "min_pts": 2, "floor": "none", "concavity": "none",
                     "output_dir": saved})
        try:
            keyframe_pub = node.publisher("/%s/keyframes" % node.name, Path)
            keyframe_pub.publish(path)
            pub = node.publisher("/ORB_SLAM/Map", Marker)
            with open(ECHO_DUMP) as f:
                docs = [d for d in yaml.safe_load_all(f) if d]
            sent = 0
            # The keyframes and the map come on two topics, in no guaranteed order: the map is re-sent
            # (as SLAM re-sends it) until a rebuild used the keyframes.
            deadline = time.time() + TIMEOUT
            while True:
                for doc in docs:
                    msg = Marker()
                    genpy.message.fill_message_args(msg, [doc])
                    pub.publish(msg)
                    sent += doc["ns"] == "MapPoints"
                if node.wait_idle(sent)["keyframes"] == 2 or time.time() > deadline:
                    break
            self.assertEqual(node.stats["keyframes"], 2)
            wait_for("~obstacles equal to hullmap build's", lambda: same_triangles(node.hull_triangles(), expected))
            answer = rospy.ServiceProxy("/%s/save" % node.name, Trigger)()
            self.assertTrue(answer.success, answer.message)
            with open(os.path.join(saved, "map.bt"), "rb") as a, open(os.path.join(cli_out, "map.bt"), "rb") as b:
                self.assertEqual(a.read(), b.read())  # the same free space was cast from the keyframes
        finally:
            node.stop()


def small_room(name):
    """A generated 5 m room (metric, z up, 3 pieces of furniture) in TMP/name: its points file and points."""
    scene = os.path.join(TMP, name)
    subprocess.run([HULLMAP, "generate", "--layout", "room", "--z-up", "--seed", "3", "--obstacles", "3",
                    "--room", "5", "-o", scene], check=True, capture_output=True)
    points_file = os.path.join(scene, "map_points.txt")
    points = []
    with open(points_file) as f:
        for line in f:
            fields = line.split()
            if len(fields) == 3 and not line.startswith("#"):
                points.append(tuple(float(v) for v in fields))
    return points_file, points


class Defaults(unittest.TestCase):
    def test_at_its_defaults_the_node_publishes_the_convex_parts_of_hullmap_build_at_its_defaults(self):
        # A generated room, metric and z-up: at the defaults the floor is found and left out, eps and
        # minPts are chosen from the map and the clusters are split into convex parts; the node's
        # parameters default to build's, and its hull markers hold the parts (what checks use).
        points_file, points = small_room("defaults_scene")
        obstacles = hullmap_build([points_file], os.path.join(TMP, "defaults_build"), [])
        self.assertTrue(any(o.get("parts") for o in obstacles), "the defaults split into convex parts")
        expected = expected_triangles(obstacles)
        node = Node({})
        try:
            node.publisher("/%s/cloud_in" % node.name, PointCloud2).publish(cloud(points))
            node.wait_idle(1)
            wait_for("~obstacles equal to hullmap build's at the defaults",
                     lambda: same_triangles(node.hull_triangles(), expected))
        finally:
            node.stop()


def expect_like_build_and_bad_values_stop(test, name, param, value, flags, bad):
    """The node with ~param: value publishes the parts `hullmap build FLAGS` writes for the small room,
    which differ from the defaults' (else the check could not fail); each of `bad` stops the node
    at start with exit 2, naming ~param."""
    points_file, points = small_room(name + "_scene")
    at_defaults = expected_triangles(hullmap_build([points_file], os.path.join(TMP, name + "_default"), []))
    given = expected_triangles(hullmap_build([points_file], os.path.join(TMP, name + "_given"), flags))
    test.assertFalse(same_triangles(given, at_defaults), "%s should change this room's parts" % " ".join(flags))
    node = Node({param: value})
    try:
        node.publisher("/%s/cloud_in" % node.name, PointCloud2).publish(cloud(points))
        node.wait_idle(1)
        wait_for("~obstacles equal to hullmap build %s's" % " ".join(flags),
                 lambda: same_triangles(node.hull_triangles(), given))
    finally:
        node.stop()
    for params in bad:
        Node.count += 1
        args = [NODE, "__name:=hullmap%d" % Node.count] + ["_%s:=%s" % kv for kv in params.items()]
        r = subprocess.run(args, capture_output=True, text=True, timeout=TIMEOUT)
        test.assertEqual(r.returncode, 2, "%s: %s" % (params, r.stdout + r.stderr))
        test.assertIn("~" + param, r.stdout + r.stderr, params)


class FlatGap(unittest.TestCase):
    def test_flat_gap_0_publishes_hullmap_build_flat_gap_0_and_bad_values_stop_the_node(self):
        # The generated room's walls are flat parts at the default (auto: the eps used); ~flat_gap 0
        # turns that off, as --flat-gap 0 does.
        expect_like_build_and_bad_values_stop(
            self, "flat_gap", "flat_gap", 0, ["--flat-gap", "0"],
            [{"flat_gap": "x"}, {"flat_gap": -1}, {"flat_gap": "nan"}, {"flat_gap": 0.2, "concavity": "none"}])


class Extension(unittest.TestCase):
    def test_extension_off_publishes_hullmap_build_extension_off_and_bad_values_stop_the_node(self):
        # At the defaults (auto minPts) the cluster extension runs, as in hullmap build; ~extension
        # off leaves DBSCAN's clusters, as --extension off does.
        expect_like_build_and_bad_values_stop(
            self, "extension", "extension", "off", ["--extension", "off"],
            [{"extension": "x"}, {"extension": 1}, {"extension": "Auto"}])


class CloudInput(unittest.TestCase):
    """~cloud_in: equality with hullmap build, ~save then hullmap check, malformed messages, a burst."""

    # The three boxes' bottoms would be a floor to --floor auto (and the map moved): these tests are
    # about the node against hullmap build, not about the floor, so both leave it and parts out.
    params = {"resolution": 0.05, "eps": 0.1, "min_pts": 5, "floor": "none", "concavity": "none"}
    build_args = ["--resolution", "0.05", "--eps", "0.1", "--min-pts", "5", "--floor", "none", "--concavity", "none"]

    @classmethod
    def setUpClass(cls):
        cls.output_dir = os.path.join(TMP, "saved")
        # min_interval 0.1 s: at most about 10 rebuilds start during the 1 s burst below, so most of its
        # maps must be folded (the counts are printed, not asserted: they depend on the machine).
        cls.node = Node(dict(cls.params, output_dir=cls.output_dir, min_interval=0.1))
        cls.pub = cls.node.publisher("/%s/cloud_in" % cls.node.name, PointCloud2)
        cls.sent = 0

    @classmethod
    def tearDownClass(cls):
        cls.node.stop()

    def send(self, msg):
        self.pub.publish(msg)
        CloudInput.sent += 1

    def build_of(self, points, name):
        path = os.path.join(TMP, name + ".xyz")
        write_xyz(path, points)
        return expected_triangles(hullmap_build([path], os.path.join(TMP, name + "_build"), self.build_args))

    def test_a_cloud_gives_hullmap_builds_obstacles_and_save_feeds_hullmap_check(self):
        points = boxes([(0, 0, 1), (2, 0, 1), (0, 3, 0.5)])
        expected = self.build_of(points, "three_boxes")
        self.assertEqual(len(expected), 3)
        self.send(cloud(points))
        self.node.wait_idle(self.sent)
        wait_for("~obstacles equal to hullmap build's", lambda: same_triangles(self.node.hull_triangles(), expected))

        save = rospy.ServiceProxy("/%s/save" % self.node.name, Trigger)
        save.wait_for_service(TIMEOUT)
        answer = save()
        self.assertTrue(answer.success, answer.message)
        check = subprocess.run([HULLMAP, "check", self.output_dir, "--radius", "0.05", "--json",
                                "--segment", "-1,0,1,1,0,1"], capture_output=True, text=True)
        self.assertEqual(check.returncode, 1, check.stderr)  # collides
        line = json.loads(check.stdout.splitlines()[-1])
        self.assertTrue(line["collides"])
        clear = subprocess.run([HULLMAP, "check", self.output_dir, "--radius", "0.05",
                                "--segment", "-1,-2,1,1,-2,1"], capture_output=True, text=True)
        self.assertEqual(clear.returncode, 0, clear.stdout + clear.stderr)

        # ~check_path on the same map gives hullmap check's JSON lines.
        path_pub = self.node.publisher("/%s/check_path" % self.node.name, Path)
        path = Path()
        path.header.frame_id = "map"
        for x, y, z in [(-1, 0, 1), (1, 0, 1), (1, -2, 1)]:
            pose = PoseStamped()
            pose.pose.position.x, pose.pose.position.y, pose.pose.position.z = x, y, z
            path.poses.append(pose)
        self.node.path_check = None
        path_pub.publish(path)
        got = wait_for("~path_check", lambda: self.node.path_check)
        waypoints = os.path.join(TMP, "path.txt")
        with open(waypoints, "w") as f:
            f.write("-1 0 1\n1 0 1\n1 -2 1\n")
        cli = subprocess.run([HULLMAP, "check", self.output_dir, "--radius", "0.25", "--json", "--path", waypoints],
                             capture_output=True, text=True)
        self.assertEqual(got, cli.stdout)

    def test_malformed_messages_are_skipped_and_the_node_keeps_serving(self):
        skipped = self.node.stats["skipped"]
        no_z = cloud(boxes([(5, 5, 1)]), with_z=False)
        self.send(no_z)
        wait_for("the cloud without z to be skipped", lambda: self.node.stats["skipped"] == skipped + 1)

        marker_pub = self.node.publisher("/ORB_SLAM/Map", Marker)
        bad = Marker()
        bad.ns, bad.id, bad.type = "MapPoints", 0, Marker.POINTS
        from geometry_msgs.msg import Point
        bad.points = [Point(0, 0, 0), Point(float("nan"), 1, 1)]
        marker_pub.publish(bad)
        CloudInput.sent += 1
        wait_for("the marker with a NaN to be skipped", lambda: self.node.stats["skipped"] == skipped + 2)
        self.assertTrue(self.node.alive())

        points = boxes([(-3, -3, 1)])
        expected = self.build_of(points, "one_box")
        self.send(cloud(points))
        self.node.wait_idle(self.sent)
        wait_for("the next good cloud's obstacles", lambda: same_triangles(self.node.hull_triangles(), expected))

    def test_a_burst_of_50_maps_ends_on_the_last_and_never_queues_more_than_one(self):
        # Up to 18,522 points a map: rebuilds take about as long as the 20 ms between messages, so maps
        # arrive while one runs (how many fold depends on the machine; none may be lost or queued).
        maps = [boxes([(0.5 * i, 0, 1), (0.5 * i, 2, 1)] if i % 2 == 0 else [(0.5 * i, 0, 1)], spacing=0.02, half=0.2)
                for i in range(50)]
        expected = self.build_of(maps[-1], "burst_last")
        before = dict(self.node.stats)
        messages = [cloud(points) for points in maps]  # made before, so the burst is only publish()
        start = time.time()
        for i, msg in enumerate(messages):
            self.send(msg)
            time.sleep(max(0.0, start + 0.02 * (i + 1) - time.time()))
        stats = self.node.wait_idle(self.sent)
        wait_for("the last map's obstacles", lambda: same_triangles(self.node.hull_triangles(), expected))
        taken = stats["messages"] - before["messages"]
        print("burst: %d rebuilds, %d folded" % (stats["rebuilds"] - before["rebuilds"], stats["folded"] - before["folded"]),
              file=sys.stderr)
        self.assertEqual(taken, 50)
        # Every map was either rebuilt or folded into a newer one: none is left behind, none twice.
        self.assertEqual((stats["rebuilds"] - before["rebuilds"]) + (stats["folded"] - before["folded"]), 50)
        self.assertLessEqual(stats["max_waiting"], 1)
        # The markers of the obstacles gone from the last map were deleted.
        ids = [m.id for m in self.node.obstacles.markers if m.ns == "hulls" and m.action == Marker.ADD]
        self.assertEqual(sorted(ids), sorted(expected))

    def test_reset_forgets_the_map_and_deletes_its_markers(self):
        points = boxes([(0, 0, 1), (2, 0, 1)])
        expected = self.build_of(points, "reset_boxes")
        self.send(cloud(points))
        self.node.wait_idle(self.sent)
        wait_for("the map before the reset", lambda: same_triangles(self.node.hull_triangles(), expected))
        reset = rospy.ServiceProxy("/%s/reset" % self.node.name, Empty)
        reset.wait_for_service(TIMEOUT)
        reset()
        wait_for("empty ~obstacles", lambda: self.node.hull_triangles() == {})
        deleted = {(m.ns, m.id) for m in self.node.obstacles.markers if m.action == Marker.DELETE}
        self.assertEqual(deleted, {(ns, i) for ns in ("hulls", "footprints", "labels") for i in expected})
        wait_for("~stats after the reset", lambda: self.node.stats["obstacles"] == 0)
        save = rospy.ServiceProxy("/%s/save" % self.node.name, Trigger)
        self.assertFalse(save().success)  # nothing to save


if __name__ == "__main__":
    unittest.main(verbosity=2, warnings="ignore")  # rospy leaves sockets to the GC
