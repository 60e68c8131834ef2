#!/usr/bin/env python3
"""hullmap's ROS 2 node against the real ROS 2 core (test/ros2/run_test.sh sources it), on a
ROS_DOMAIN_ID of its own: every check compares what the node publishes or answers with `hullmap build`
and `hullmap check --json` on the same points and parameters, or with counters it publishes on ~/stats.
"""
import json
import math
import os
import subprocess
import sys
import time
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ros2_support import (HULLMAP, TIMEOUT, Client, HullmapNode, Process, boxes, claim_domain, cloud,  # noqa: E402
                          echo_markers, expected_triangles, fresh_tmp, hull_triangles, hullmap_build,
                          param_get, param_set, reliable_input, same_triangles, stop_daemon, wait_for, write_xyz,
                          ECHO_DUMP)

TMP = None
client = None


def setUpModule():
    global TMP, client
    claim_domain()
    TMP = fresh_tmp("ros2_node")
    client = Client()


def tearDownModule():
    client.close()
    stop_daemon()


def small_room(name):
    """A generated 5 m room (metric, z up, 3 pieces of furniture): its points file and points."""
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


def path_msg(waypoints, frame_id="map"):
    from geometry_msgs.msg import PoseStamped
    from nav_msgs.msg import Path
    path = Path()
    path.header.frame_id = frame_id
    for x, y, z in waypoints:
        pose = PoseStamped()
        pose.pose.position.x, pose.pose.position.y, pose.pose.position.z = float(x), float(y), float(z)
        path.poses.append(pose)
    return path


class EchoDumpAsMarkers(unittest.TestCase):
    params = {"resolution": 0.05, "eps": 0.15, "min_pts": 2, "floor": "none", "concavity": "none"}
    build_args = ["--resolution", "0.05", "--eps", "0.15", "--min-pts", "2", "--floor", "none", "--concavity", "none"]

    def test_obstacles_equal_hullmap_build_of_the_dump(self):
        expected = expected_triangles(hullmap_build([ECHO_DUMP], os.path.join(TMP, "echo_build"), self.build_args))
        self.assertGreater(len(expected), 0, "the fixture must give at least one obstacle")
        node = HullmapNode(client, TMP, dict(self.params, **reliable_input("echo_markers", "/ORB_SLAM/Map", 20)),
                           name="echo_markers")
        try:
            from visualization_msgs.msg import Marker
            pub = client.publisher("/ORB_SLAM/Map", Marker)
            markers = echo_markers()
            for m in markers:
                pub.publish(m)
            node.wait_idle(sum(m.ns == "MapPoints" for m in markers))
            wait_for("~/obstacles equal to hullmap build's", lambda: same_triangles(node.hull_triangles(), expected))
            self.assertEqual(node.stats["skipped"], 0)
            self.assertEqual(node.stats["points"], 7)  # the last publication: 5 + 2 points
            self.assertEqual({m.header.frame_id for m in node.obstacles.markers}, {"map"})
        finally:
            node.stop()

    def test_keyframes_give_the_tree_of_hullmap_build_with_their_trajectory(self):
        from builtin_interfaces.msg import Time
        from geometry_msgs.msg import PoseStamped
        from nav_msgs.msg import Path
        from visualization_msgs.msg import Marker
        keyframes = [((1403636580, 250000000), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0)),
                     ((1403636580, 500000000), (1.5, -0.5, 0.5), (0.0, 0.0, 0.38268343236508984, 0.9238795325112867))]
        tum = os.path.join(TMP, "node_keyframes.txt")
        path = Path()
        path.header.frame_id = "world"
        with open(tum, "w") as f:
            for (sec, nanosec), p, q in keyframes:
                pose = PoseStamped()
                pose.header.stamp = Time(sec=sec, nanosec=nanosec)
                pose.pose.position.x, pose.pose.position.y, pose.pose.position.z = p
                o = pose.pose.orientation
                o.x, o.y, o.z, o.w = q
                path.poses.append(pose)
                f.write("%r %r %r %r %r %r %r %r\n" % ((sec + 1e-9 * nanosec,) + p + q))
        cli_out = os.path.join(TMP, "echo_trajectory_build")
        expected = expected_triangles(hullmap_build([ECHO_DUMP], cli_out, self.build_args + ["--trajectory", tum]))
        saved = os.path.join(TMP, "echo_trajectory_saved")
        params = dict(self.params, output_dir=saved)
        params.update(reliable_input("echo_keyframes", "/ORB_SLAM/Map", 20))
        params.update(reliable_input("echo_keyframes", "~/keyframes", 2))
        node = HullmapNode(client, TMP, params, name="echo_keyframes")
        try:
            keyframe_pub = client.publisher("/%s/keyframes" % node.name, Path)
            pub = client.publisher("/ORB_SLAM/Map", Marker)
            markers = echo_markers()
            sent = 0
            # The keyframes and the map come on two topics, in no guaranteed order: both are re-sent
            # (as SLAM re-sends them) until a rebuild used the keyframes.
            deadline = time.time() + TIMEOUT
            while True:
                keyframe_pub.publish(path)
                for m in markers:
                    pub.publish(m)
                    sent += m.ns == "MapPoints"
                if node.wait_idle(sent)["keyframes"] == 2 or time.time() > deadline:
                    break
            self.assertEqual(node.stats["keyframes"], 2)
            wait_for("~/obstacles equal to hullmap build's", lambda: same_triangles(node.hull_triangles(), expected))
            from std_srvs.srv import Trigger
            answer = client.call("/%s/save" % node.name, Trigger, Trigger.Request())
            self.assertTrue(answer.success, answer.message)
            with open(os.path.join(saved, "map.bt"), "rb") as a, open(os.path.join(cli_out, "map.bt"), "rb") as b:
                self.assertEqual(a.read(), b.read())  # the same free space was cast from the keyframes
        finally:
            node.stop()


class Defaults(unittest.TestCase):
    def test_at_its_defaults_the_node_publishes_the_convex_parts_of_hullmap_build_at_its_defaults(self):
        from sensor_msgs.msg import PointCloud2
        points_file, points = small_room("defaults_scene")
        obstacles = hullmap_build([points_file], os.path.join(TMP, "defaults_build"), [])
        self.assertTrue(any(o.get("parts") for o in obstacles), "the defaults split into convex parts")
        expected = expected_triangles(obstacles)
        node = HullmapNode(client, TMP)
        try:
            # A best-effort publisher (sensor data QoS): the node's inputs take it, as they take reliable ones.
            pub = client.publisher("/%s/cloud_in" % node.name, PointCloud2, best_effort=True)
            node.send_until_taken(pub, cloud(points), "the cloud")
            node.wait_idle(1)
            wait_for("~/obstacles equal to hullmap build's at the defaults",
                     lambda: same_triangles(node.hull_triangles(), expected))
        finally:
            node.stop()


class BadParametersAtStart(unittest.TestCase):
    def test_a_bad_value_stops_the_node_with_one_line_naming_the_parameter(self):
        cases = [({"eps": "abc"}, "eps"), ({"min_interval": -1.0}, "min_interval"), ({"radius": 0.0}, "radius"),
                 ({"up": "w"}, "up"), ({"extension": "maybe"}, "extension"), ({"resolution": 0.0}, "resolution"),
                 ({"flat_gap": 0.2, "concavity": "none"}, "flat_gap"), ({"frame_id": 3}, "frame_id"),
                 ({"min_pts": 0}, "min_pts")]
        for params, name in cases:
            args = ["ros2", "run", "hullmap_ros2", "hullmap_node", "--ros-args", "-r", "__node:=bad_start"]
            for k, v in params.items():
                args += ["-p", "%s:=%s" % (k, v)]
            run = subprocess.run(args, capture_output=True, text=True, timeout=TIMEOUT, start_new_session=True)
            # ros2 run adds its own line "[ros2run]: Process exited with failure 2".
            lines = [line for line in (run.stdout + run.stderr).splitlines()
                     if line.strip() and not line.startswith("[ros2run]")]
            self.assertEqual(run.returncode, 2, "%s: %s" % (params, lines))
            self.assertEqual(len(lines), 1, "%s: %s" % (params, lines))
            self.assertIn("hullmap: %s: " % name, lines[0], params)


class CloudInput(unittest.TestCase):
    """~/cloud_in: equality with hullmap build, save, the check topic and service against hullmap check,
    late subscribers, parameters at run time, malformed messages, a burst of maps, reset."""

    params = {"resolution": 0.05, "eps": 0.1, "min_pts": 5, "floor": "none", "concavity": "none"}
    build_args = ["--resolution", "0.05", "--eps", "0.1", "--min-pts", "5", "--floor", "none", "--concavity", "none"]

    @classmethod
    def setUpClass(cls):
        from sensor_msgs.msg import PointCloud2
        cls.output_dir = os.path.join(TMP, "saved")
        # min_interval 0.1 s: at most about 10 rebuilds start during the 1 s burst below, so most of its
        # maps must be folded (the counts are printed, not asserted: they depend on the machine). The
        # inputs are made reliable with room for the burst (their QoS overrides): every message sent
        # reaches the node, so its counts can be checked exactly.
        name = "hullmap_cloud_input"
        params = dict(cls.params, output_dir=cls.output_dir, min_interval=0.1)
        params.update(reliable_input(name, "~/cloud_in", 60))
        params.update(reliable_input(name, "/ORB_SLAM/Map", 20))
        cls.node = HullmapNode(client, TMP, params, name=name)
        cls.pub = client.publisher("/%s/cloud_in" % cls.node.name, PointCloud2, depth=10)
        cls.sent = 0

    @classmethod
    def tearDownClass(cls):
        cls.node.stop()

    def send(self, msg):
        self.pub.publish(msg)
        CloudInput.sent += 1

    def build_of(self, points, name, args=None):
        path = os.path.join(TMP, name + ".xyz")
        write_xyz(path, points)
        return expected_triangles(hullmap_build([path], os.path.join(TMP, name + "_build"), args or self.build_args))

    def show(self, points, expected):
        self.send(cloud(points))
        self.node.wait_idle(self.sent)
        wait_for("~/obstacles equal to hullmap build's", lambda: same_triangles(self.node.hull_triangles(), expected))

    def test_a_cloud_gives_hullmap_builds_obstacles_and_the_checks_agree_with_hullmap_check(self):
        from hullmap_interfaces.srv import CheckPath
        from nav_msgs.msg import Path
        from std_srvs.srv import Trigger
        points = boxes([(0, 0, 1), (2, 0, 1), (0, 3, 0.5)])
        expected = self.build_of(points, "three_boxes")
        self.assertEqual(len(expected), 3)
        self.show(points, expected)

        answer = client.call("/%s/save" % self.node.name, Trigger, Trigger.Request())
        self.assertTrue(answer.success, answer.message)
        self.assertEqual(answer.message, os.path.abspath(self.output_dir))
        check = subprocess.run([HULLMAP, "check", self.output_dir, "--radius", "0.05", "--json",
                                "--segment", "-1,0,1,1,0,1"], capture_output=True, text=True)
        self.assertEqual(check.returncode, 1, check.stderr)  # collides

        # The topic: ~/path_check holds hullmap check --json's lines for the node's radius (0.25).
        waypoints = [(-1, 0, 1), (1, 0, 1), (1, -2, 1), (2, -2, 1), (2, 1, 1)]
        waypoints_file = os.path.join(TMP, "path.txt")
        with open(waypoints_file, "w") as f:
            f.writelines("%r %r %r\n" % p for p in waypoints)
        path_pub = client.publisher("/%s/check_path" % self.node.name, Path, depth=10)
        before = self.node.path_check_topic.count
        path_pub.publish(path_msg(waypoints))
        wait_for("~/path_check", lambda: self.node.path_check_topic.count > before)
        cli = subprocess.run([HULLMAP, "check", self.output_dir, "--radius", "0.25", "--json", "--path", waypoints_file],
                             capture_output=True, text=True)
        self.assertEqual(self.node.path_check_topic.value.data, cli.stdout)

        # The service, for radii of its own: per segment hullmap check --json's fields, and the contact.
        for radius in (0.0, 0.25, 0.6):
            cli = subprocess.run([HULLMAP, "check", self.output_dir, "--radius", repr(radius), "--json", "--path",
                                  waypoints_file], capture_output=True, text=True)
            lines = [json.loads(line) for line in cli.stdout.splitlines()]
            request = CheckPath.Request()
            request.path = path_msg(waypoints)
            request.radius = radius
            response = client.call("/%s/check_path" % self.node.name, CheckPath, request)
            self.assertTrue(response.success, response.message)
            self.assertEqual(len(response.segments), len(lines))
            first = None
            for i, (got, want) in enumerate(zip(response.segments, lines)):
                self.assertEqual(got.collides, want["collides"], (radius, i))
                self.assertEqual(got.obstacle, -1 if want["obstacle"] is None else want["obstacle"], (radius, i))
                self.assertEqual(got.part, want.get("part", -1), (radius, i))
                self.assertAlmostEqual(got.clearance, want["clearance"], places=9)
                if want["collides"]:
                    self.assertAlmostEqual(got.t, want["t"], places=9)
                    first = i if first is None else first
                a, b = waypoints[i], waypoints[i + 1]
                for k, c in enumerate((got.contact.x, got.contact.y, got.contact.z)):
                    self.assertAlmostEqual(c, a[k] + got.t * (b[k] - a[k]), places=9)
            self.assertEqual(response.first_colliding_segment, -1 if first is None else first, radius)
        self.assertTrue(any(line["collides"] for line in lines))  # the last radius's answer was not all clear
        bad = CheckPath.Request()
        bad.path = path_msg([(0, 0, 0), (1, 1, 1)])
        bad.radius = -1.0
        refused = client.call("/%s/check_path" % self.node.name, CheckPath, bad)
        self.assertFalse(refused.success)
        self.assertIn("radius", refused.message)

    def test_a_subscriber_that_joins_later_gets_the_last_map(self):
        from visualization_msgs.msg import MarkerArray
        from nav_msgs.msg import OccupancyGrid
        points = boxes([(5, 5, 1), (7, 5, 1)])
        expected = self.build_of(points, "late_boxes")
        self.show(points, expected)
        late = client.latest("/%s/obstacles" % self.node.name, MarkerArray)
        grid = client.latest("/%s/projected_map" % self.node.name, OccupancyGrid)
        try:
            wait_for("the late subscriber's ~/obstacles", lambda: same_triangles(hull_triangles(late.value), expected))
            wait_for("the late subscriber's ~/projected_map", lambda: grid.value is not None)
            self.assertIn(100, list(grid.value.data))
        finally:
            late.close()
            grid.close()

    def test_parameters_set_at_run_time_apply_at_the_next_rebuild_and_bad_ones_are_refused(self):
        name = self.node.name
        for param, value, reason in (("eps", "abc", "eps: expected a number, got 'abc'"),
                                     ("eps", "-1.0", "eps"),
                                     ("min_pts", "0", "min_pts"),
                                     ("radius", "-1.0", "radius"),
                                     ("flat_gap", "0.2", "flat_gap"),  # concavity is none here
                                     ("frame_id", "world", "read-only")):
            before = param_get(name, param)
            out = param_set(name, param, value)
            self.assertIn("Setting parameter failed", out, (param, value))
            self.assertIn(reason, out, (param, value))
            self.assertEqual(param_get(name, param), before)
        self.assertTrue(self.node.alive())
        # eps 0.2 joins two boxes 15 cm apart that eps 0.1 keeps apart.
        points = boxes([(0, -4, 1), (0.35, -4, 1)])
        apart = self.build_of(points, "eps_apart")
        joined = self.build_of(points, "eps_joined", [("0.2" if a == "0.1" else a) for a in self.build_args])
        self.assertNotEqual(len(apart), len(joined))
        self.show(points, apart)
        try:
            out = param_set(name, "eps", "0.2")
            self.assertIn("Set parameter successful", out)
            self.assertTrue(same_triangles(self.node.hull_triangles(), apart))  # nothing rebuilt by the change
            self.show(points, joined)
        finally:
            self.assertIn("Set parameter successful", param_set(name, "eps", "0.1"))

    def test_malformed_messages_are_skipped_and_the_node_keeps_serving(self):
        from geometry_msgs.msg import Point
        from visualization_msgs.msg import Marker
        skipped = self.node.stats["skipped"]
        self.send(cloud(boxes([(5, 5, 1)]), with_z=False))
        wait_for("the cloud without z to be skipped", lambda: self.node.stats["skipped"] == skipped + 1)
        marker_pub = client.publisher("/ORB_SLAM/Map", Marker)
        bad = Marker()
        bad.ns, bad.id, bad.type = "MapPoints", 0, Marker.POINTS
        bad.points = [Point(x=0.0, y=0.0, z=0.0), Point(x=float("nan"), y=1.0, z=1.0)]
        marker_pub.publish(bad)
        CloudInput.sent += 1
        wait_for("the marker with a NaN to be skipped", lambda: self.node.stats["skipped"] == skipped + 2)
        short = cloud(boxes([(5, 5, 1)]))
        short.data = short.data[:-10]
        self.send(short)
        wait_for("the short cloud to be skipped", lambda: self.node.stats["skipped"] == skipped + 3)
        self.assertTrue(self.node.alive())
        points = boxes([(-3, -3, 1)])
        self.show(points, self.build_of(points, "one_box"))

    def test_a_burst_of_50_maps_ends_on_the_last_and_never_queues_more_than_one(self):
        # Up to 18,522 points a map, one each 20 ms: rebuilds take about as long, so maps arrive while
        # one runs (how many fold depends on the machine; none may be lost or queued).
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
        rebuilds, folded = stats["rebuilds"] - before["rebuilds"], stats["folded"] - before["folded"]
        print("burst: %d rebuilds, %d folded" % (rebuilds, folded), file=sys.stderr)
        self.assertEqual(stats["messages"] - before["messages"], 50)
        self.assertEqual(rebuilds + folded, 50)
        self.assertLessEqual(stats["max_waiting"], 1)
        ids = [m.id for m in self.node.obstacles.markers if m.ns == "hulls" and m.action == 0]
        self.assertEqual(sorted(ids), sorted(expected))

    def test_reset_forgets_the_map_and_deletes_its_markers(self):
        from std_srvs.srv import Empty, Trigger
        points = boxes([(0, 0, 1), (2, 0, 1)])
        expected = self.build_of(points, "reset_boxes")
        self.show(points, expected)
        client.call("/%s/reset" % self.node.name, Empty, Empty.Request())
        wait_for("empty ~/obstacles", lambda: self.node.hull_triangles() == {})
        deleted = {(m.ns, m.id) for m in self.node.obstacles.markers if m.action == 2}
        self.assertEqual(deleted, {(ns, i) for ns in ("hulls", "footprints", "labels") for i in expected})
        wait_for("~/stats after the reset", lambda: self.node.stats["obstacles"] == 0)
        self.assertFalse(client.call("/%s/save" % self.node.name, Trigger, Trigger.Request()).success)


class SimTime(unittest.TestCase):
    def test_with_use_sim_time_outputs_without_a_stamp_get_the_clock_topics_time(self):
        from rosgraph_msgs.msg import Clock
        from sensor_msgs.msg import PointCloud2
        from std_srvs.srv import Empty
        node = HullmapNode(client, TMP, dict(CloudInput.params, use_sim_time="true"))
        try:
            clock = client.publisher("/clock", Clock, depth=1)
            tick = Clock()
            tick.clock.sec, tick.clock.nanosec = 1234, 5678
            clock.publish(tick)
            # A cloud without a stamp: its outputs are stamped with the node's (simulated) time.
            stamps = set()
            pub = client.publisher("/%s/cloud_in" % node.name, PointCloud2)
            deadline = time.time() + TIMEOUT
            while (1234, 5678) not in stamps and time.time() < deadline:
                clock.publish(tick)  # until the node has taken the clock
                before = node.stats["rebuilds"]
                node.send_until_taken(pub, cloud(boxes([(0, 0, 1)])), "a cloud")
                wait_for("a rebuild", lambda: node.stats["rebuilds"] > before)
                wait_for("its obstacles", lambda: node.obstacles is not None)
                m = node.obstacles.markers[0]
                stamps.add((m.header.stamp.sec, m.header.stamp.nanosec))
            self.assertIn((1234, 5678), stamps)
            tick.clock.sec = 2000
            clock.publish(tick)
            time.sleep(0.5)
            client.call("/%s/reset" % node.name, Empty, Empty.Request())
            wait_for("the reset's outputs at the clock's time",
                     lambda: node.obstacles.markers and node.obstacles.markers[0].header.stamp.sec == 2000)
        finally:
            node.stop()


class Component(unittest.TestCase):
    def test_the_component_loads_into_a_container_and_builds_as_the_executable(self):
        from sensor_msgs.msg import PointCloud2
        container = Process(["ros2", "run", "rclcpp_components", "component_container", "--ros-args", "-r",
                             "__node:=hullmap_container"], os.path.join(TMP, "container.log"))
        try:
            load = subprocess.run(["ros2", "component", "load", "--no-daemon", "/hullmap_container", "hullmap_ros2",
                                   "hullmap::ros2::HullmapNode", "-r", "__node:=hullmap_component",
                                   *sum((["-p", "%s:=%s" % kv] for kv in CloudInput.params.items()), [])],
                                  capture_output=True, text=True, timeout=TIMEOUT)
            self.assertEqual(load.returncode, 0, load.stdout + load.stderr)
            node = HullmapNode(client, TMP, name="hullmap_component", process=container)
            points = boxes([(0, 0, 1), (2, 0, 1)])
            path = os.path.join(TMP, "component.xyz")
            write_xyz(path, points)
            expected = expected_triangles(hullmap_build([path], os.path.join(TMP, "component_build"),
                                                        CloudInput.build_args))
            pub = client.publisher("/hullmap_component/cloud_in", PointCloud2)
            node.send_until_taken(pub, cloud(points), "the component to take the cloud")
            node.wait_idle(1)
            wait_for("the component's obstacles", lambda: same_triangles(node.hull_triangles(), expected))
            for t in (node.stats_topic, node.obstacles_topic, node.path_check_topic):
                t.close()
        finally:
            container.stop()


if __name__ == "__main__":
    unittest.main(verbosity=2)
