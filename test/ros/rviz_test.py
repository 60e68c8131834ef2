#!/usr/bin/env python3
"""ros/rviz/hullmap.rviz against hullmap_node itself: the node runs against a real ROS master (rosmaster
--core on a free port, started and stopped here) as __name:=hullmap, and the master says what it
publishes, with which types. Every topic the config names must be one of them, drawn by the RViz display
made for its type; every topic the node publishes that RViz can draw must be in the config; the markers
the node sends for a map must be in the config's fixed frame and namespaces.

Environment: HULLMAP_NODE, HULLMAP_SOURCE_DIR, HULLMAP_TEST_TMP. Nothing asserts on wall-clock time
(waits only time out).
"""
import os
import shutil
import socket
import struct
import subprocess
import time
import unittest
import xmlrpc.client

import yaml

NODE = os.environ["HULLMAP_NODE"]
SOURCE = os.environ["HULLMAP_SOURCE_DIR"]
TMP = os.path.join(os.environ["HULLMAP_TEST_TMP"], "ros_rviz")
CONFIG = os.path.join(SOURCE, "ros", "rviz", "hullmap.rviz")
TIMEOUT = 20.0

# RViz's display classes and the message type each draws (the ones the config may use).
DISPLAY_TYPES = {"rviz/MarkerArray": "visualization_msgs/MarkerArray", "rviz/Marker": "visualization_msgs/Marker",
                 "rviz/Map": "nav_msgs/OccupancyGrid", "rviz/Path": "nav_msgs/Path",
                 "rviz/PointCloud2": "sensor_msgs/PointCloud2", "rviz/Pose": "geometry_msgs/PoseStamped"}
# Types RViz has no display for: text, and the log every node publishes.
NOT_DRAWN = {"std_msgs/String", "rosgraph_msgs/Log"}

master = None
node = None
master_uri = None


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def wait_for(what, condition):
    deadline = time.time() + TIMEOUT
    while time.time() < deadline:
        value = condition()
        if value:
            return value
        time.sleep(0.05)
    raise AssertionError("timed out waiting for " + what)


def setUpModule():
    global master, node, master_uri
    shutil.rmtree(TMP, ignore_errors=True)
    os.makedirs(TMP)
    port = free_port()
    master_uri = "http://127.0.0.1:%d" % port
    os.environ["ROS_MASTER_URI"] = master_uri
    os.environ["ROS_IP"] = "127.0.0.1"
    os.environ["ROS_HOME"] = os.path.join(TMP, "ros_home")
    os.environ.pop("ROS_HOSTNAME", None)
    master = subprocess.Popen(["rosmaster", "--core", "-p", str(port)], stdout=subprocess.DEVNULL,
                              stderr=subprocess.DEVNULL)
    api = xmlrpc.client.ServerProxy(master_uri)
    wait_for("rosmaster on port %d" % port, lambda: master.poll() is None and _online(api))
    log = open(os.path.join(TMP, "node.log"), "w")
    node = subprocess.Popen([NODE, "__name:=hullmap", "_floor:=none", "_eps:=0.15", "_min_pts:=2"], stdout=log,
                            stderr=subprocess.STDOUT)


def _online(api):
    try:
        return api.getPid("/test")[0] == 1
    except OSError:
        return False


def tearDownModule():
    if node is not None:
        node.terminate()
        node.wait(10)
    if master is not None:
        master.terminate()
        master.wait(10)


def published():
    """topic -> type of every topic /hullmap publishes, as the master knows it."""
    api = xmlrpc.client.ServerProxy(master_uri)
    _, _, (publishers, _, _) = api.getSystemState("/test")
    _, _, types = api.getTopicTypes("/test")
    types = dict(types)
    return {topic: types.get(topic) for topic, nodes in publishers if "/hullmap" in nodes}


def config_displays():
    with open(CONFIG) as f:
        config = yaml.safe_load(f)
    out = []

    def walk(displays):
        for d in displays:
            if d.get("Class") == "rviz/Group":
                walk(d.get("Displays", []))
                continue
            topic = d.get("Topic", d.get("Marker Topic"))
            if topic:
                out.append(d)
    walk(config["Visualization Manager"]["Displays"])
    return config, out


class RvizConfig(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        # The node advertises everything when it starts; wait until the master lists its six outputs
        # and its log, then take the list as it stands.
        wait_for("hullmap_node's publications", lambda: len(published()) >= 7)
        cls.published = published()
        cls.config, cls.displays = config_displays()

    def test_every_topic_the_config_names_is_published_by_the_node_with_the_type_its_display_draws(self):
        self.assertTrue(self.displays)
        for d in self.displays:
            topic = d.get("Topic", d.get("Marker Topic"))
            self.assertIn(topic, self.published, "%s (%s) is not published by hullmap_node" % (topic, d["Name"]))
            self.assertEqual(DISPLAY_TYPES.get(d["Class"]), self.published[topic], (topic, d["Class"]))
            self.assertTrue(d.get("Value", True), "%s is shown" % topic)

    def test_every_topic_the_node_publishes_that_rviz_draws_is_in_the_config(self):
        named = {d.get("Topic", d.get("Marker Topic")) for d in self.displays}
        drawable = {t for t, kind in self.published.items() if kind not in NOT_DRAWN}
        self.assertEqual(drawable - named, set())
        # What is left is text: ~stats and ~path_check (docs/ROS.md), and /rosout.
        self.assertEqual({t for t, kind in self.published.items() if kind in NOT_DRAWN},
                         {"/hullmap/stats", "/hullmap/path_check", "/rosout"})

    def test_the_markers_are_in_the_configs_frame_and_namespaces(self):
        import rospy
        from sensor_msgs.msg import PointCloud2, PointField
        from visualization_msgs.msg import MarkerArray
        rospy.init_node("rviz_test", anonymous=True, disable_signals=True)
        got = {}
        sub = rospy.Subscriber("/hullmap/obstacles", MarkerArray, lambda m: got.setdefault("obstacles", m))
        pub = rospy.Publisher("/hullmap/cloud_in", PointCloud2, queue_size=2, latch=True)
        # Two small cubes of points: two obstacles.
        points = [(cx + 0.04 * i, 0.04 * j, 0.5 + 0.04 * k) for cx in (0.0, 1.0) for i in range(5) for j in range(5)
                  for k in range(5)]
        msg = PointCloud2()
        msg.header.frame_id = "slam"
        msg.fields = [PointField(name=n, offset=8 * i, datatype=PointField.FLOAT64, count=1) for i, n in enumerate("xyz")]
        msg.height, msg.width, msg.point_step = 1, len(points), 24
        msg.row_step = 24 * len(points)
        msg.is_dense = True
        msg.data = b"".join(struct.pack("<3d", *p) for p in points)
        pub.publish(msg)
        markers = wait_for("~obstacles with hulls", lambda: got.get("obstacles") if got.get("obstacles") and any(
            m.ns == "hulls" for m in got["obstacles"].markers) else None)
        frame = self.config["Visualization Manager"]["Global Options"]["Fixed Frame"]
        self.assertEqual({m.header.frame_id for m in markers.markers}, {frame})
        obstacles = [d for d in self.displays if d.get("Marker Topic") == "/hullmap/obstacles"][0]
        self.assertEqual({m.ns for m in markers.markers}, set(obstacles["Namespaces"]))
        sub.unregister()
        rospy.signal_shutdown("done")


if __name__ == "__main__":
    unittest.main(verbosity=2)
