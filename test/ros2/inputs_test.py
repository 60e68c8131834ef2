#!/usr/bin/env python3
"""hullmap's ROS 2 map inputs at their defaults, against the real ROS 2 core on a ROS_DOMAIN_ID of its
own: each follows the reliability and durability of the publishers on its topic, as they come and go
(seen in the graph and in ~/stats' inputs); a map published latched before the node started arrives; a
64 MB cloud followed by a small map ends on the small map, rebuilt as `hullmap build` builds it.
"""
import os
import struct
import subprocess
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ros2_support import (Client, HullmapNode, boxes, claim_domain, cloud, expected_triangles,  # noqa: E402
                          fresh_tmp, hullmap_build, same_triangles, stop_daemon, wait_for, write_xyz)

TMP = None
client = None

PARAMS = {"resolution": 0.05, "eps": 0.1, "min_pts": 5, "floor": "none", "concavity": "none"}
BUILD_ARGS = ["--resolution", "0.05", "--eps", "0.1", "--min-pts", "5", "--floor", "none", "--concavity", "none"]


def setUpModule():
    global TMP, client
    claim_domain()
    TMP = fresh_tmp("ros2_inputs")
    client = Client()


def tearDownModule():
    client.close()
    stop_daemon()


def build_of(points, name):
    path = os.path.join(TMP, name + ".xyz")
    write_xyz(path, points)
    return expected_triangles(hullmap_build([path], os.path.join(TMP, name + "_build"), BUILD_ARGS))


class FollowingPublishers(unittest.TestCase):
    def test_each_map_input_follows_its_publishers_as_they_come_and_go(self):
        from nav_msgs.msg import Path
        from sensor_msgs.msg import PointCloud2
        from visualization_msgs.msg import Marker
        node = HullmapNode(client, TMP, PARAMS, name="hullmap_following")
        try:
            for topic, cls in (("/%s/cloud_in" % node.name, PointCloud2), ("/ORB_SLAM/Map", Marker),
                               ("/%s/keyframes" % node.name, Path)):
                client.wait_reader(topic, reliable=False)  # none yet: best effort takes any that comes
                self.assertEqual(node.stats["inputs"][topic], "best effort, volatile")
                reliable = client.publisher(topic, cls, transient_local=True)
                client.wait_reader(topic, reliable=True, transient_local=True)
                wait_for("~/stats to say so", lambda: node.stats["inputs"][topic] == "reliable, transient_local")
                best_effort = client.publisher(topic, cls, best_effort=True)  # one best effort: best effort
                client.wait_reader(topic, reliable=False)
                client.node.destroy_publisher(best_effort)
                client.wait_reader(topic, reliable=True, transient_local=True)
                client.node.destroy_publisher(reliable)
                client.wait_reader(topic, reliable=False)
            self.assertIn("has a best-effort publisher", node.process.output())
        finally:
            node.stop()

    def test_a_map_latched_before_the_node_started_arrives(self):
        from sensor_msgs.msg import PointCloud2
        from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
        points = boxes([(0, 0, 1), (2, 0, 1)])
        expected = build_of(points, "latched")
        name = "hullmap_latched"
        qos = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL)
        pub = client.node.create_publisher(PointCloud2, "/%s/cloud_in" % name, qos)
        pub.publish(cloud(points))
        node = HullmapNode(client, TMP, PARAMS, name=name)
        try:
            node.wait_idle(1)
            wait_for("~/obstacles equal to hullmap build's", lambda: same_triangles(node.hull_triangles(), expected))
        finally:
            node.stop()
            client.node.destroy_publisher(pub)


class BigMapsConfig(unittest.TestCase):
    def test_the_packages_cyclonedds_config_keeps_dds_on_loopback_and_a_node_runs_with_it(self):
        import xml.etree.ElementTree as ET
        from sensor_msgs.msg import PointCloud2
        prefix = subprocess.run(["ros2", "pkg", "prefix", "hullmap_ros2"], capture_output=True, text=True,
                                check=True).stdout.strip()
        config = os.path.join(prefix, "share", "hullmap_ros2", "config", "cyclonedds_big_maps.xml")
        domain = ET.parse(config).getroot().find("Domain")
        self.assertEqual(domain.find("General/AllowMulticast").text, "false")
        self.assertEqual([p.get("address") for p in domain.findall("Discovery/Peers/Peer")], ["127.0.0.1"])
        # A min the kernel refuses would stop the node from starting: only a max.
        self.assertIn(domain.find("Internal/SocketReceiveBufferSize").get("min"), (None, "default"))
        points = boxes([(0, 0, 1), (2, 0, 1)])
        expected = build_of(points, "big_maps_config")
        given = os.environ["CYCLONEDDS_URI"]
        os.environ["CYCLONEDDS_URI"] = "file://" + config  # the node's only: this client keeps the tests'
        try:
            node = HullmapNode(client, TMP, PARAMS, name="hullmap_big_maps_config")
        finally:
            os.environ["CYCLONEDDS_URI"] = given
        try:
            pub = client.publisher("/%s/cloud_in" % node.name, PointCloud2, best_effort=True)
            node.send_until_taken(pub, cloud(points), "the cloud")
            node.wait_idle(1)
            wait_for("~/obstacles equal to hullmap build's", lambda: same_triangles(node.hull_triangles(), expected))
        finally:
            node.stop()


class BigThenSmall(unittest.TestCase):
    def test_a_64_mb_cloud_followed_by_a_small_map_ends_on_the_small_map(self):
        from sensor_msgs.msg import PointCloud2, PointField
        node = HullmapNode(client, TMP, PARAMS, name="hullmap_big_small")
        try:
            big = PointCloud2()
            n = 64 * 2**20 // 12  # 5.6M FLOAT32 points, one point repeated: the size of a 5M-point map
            big.fields = [PointField(name=c, offset=4 * i, datatype=PointField.FLOAT32, count=1)
                          for i, c in enumerate("xyz")]
            big.height, big.width, big.point_step, big.row_step, big.is_dense = 1, n, 12, 12 * n, True
            big.data = struct.pack("<3f", 5.0, 5.0, 1.0) * n
            small = boxes([(0, 0, 1), (2, 0, 1), (0, 3, 0.5)])
            expected = build_of(small, "small_after_big")
            topic = "/%s/cloud_in" % node.name
            pub = client.publisher(topic, PointCloud2, depth=10)
            client.wait_reader(topic, reliable=True)
            pub.publish(big)
            pub.publish(cloud(small))
            stats = node.wait_idle(2)
            wait_for("~/obstacles equal to hullmap build's of the small map",
                     lambda: same_triangles(node.hull_triangles(), expected))
            stats = node.stats
            print("64 MB then small: %s" % stats, file=sys.stderr)
            self.assertEqual(stats["messages"], 2)
            self.assertEqual(stats["rebuilds"] + stats["folded"], 2)
            self.assertEqual(stats["points"], len(small))
            self.assertEqual(stats["failed"], 0)
        finally:
            node.stop()


if __name__ == "__main__":
    unittest.main(verbosity=2)
