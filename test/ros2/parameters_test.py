#!/usr/bin/env python3
"""No value set through the parameter service leaves hullmap's ROS 2 node unable to rebuild a valid map:
a value outside its documented range is refused, naming the parameter, for every parameter; a
resolution at which the octree reaches no point of the current map is refused; a value accepted
that fails to build gives way to the last values that built, said in ~/stats. Against the real ROS 2
core, on a ROS_DOMAIN_ID of its own; every map is compared with `hullmap build`'s.
"""
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ros2_support import (Client, HullmapNode, boxes, claim_domain, cloud, expected_triangles,  # noqa: E402
                          fresh_tmp, hullmap_build, same_triangles, stop_daemon, wait_for, write_xyz)

TMP = None
client = None

PARAMS = {"resolution": 0.05, "eps": 0.1, "min_pts": 5, "floor": "none", "concavity": "none"}
BUILD_ARGS = ["--resolution", "0.05", "--eps", "0.1", "--min-pts", "5", "--floor", "none", "--concavity", "none"]

# One value outside its documented range (docs/ROS.md, Parameters) for every parameter of the node.
BAD = [("resolution", 1e-09), ("resolution", 2000.0), ("eps", 1.5), ("eps", "abc"), ("min_pts", 0),
       ("floor", "sideways"), ("level", "maybe"), ("ceiling", "up"), ("concavity", -1.0), ("concavity", 5.0), ("flat_gap", 0.2),
       ("extension", "maybe"), ("stray_parts", -1), ("sparse_edges", "sometimes"), ("metric", "manhattan"),
       ("up", "w"), ("scale", 0.0), ("scale", 1e7), ("z_min", float("inf")), ("z_max", float("nan")),
       ("hit", 1.0), ("miss", 0.0), ("clamp_min", 0.99), ("clamp_max", 0.1), ("occupancy_threshold", 1.5),
       ("max_range", float("inf")), ("frame_id", "world"), ("min_interval", 7200.0), ("output_dir", ""),
       ("radius", 0.0), ("occupancy_min_z", float("nan")), ("occupancy_max_z", float("nan"))]


def setUpModule():
    global TMP, client
    claim_domain()
    TMP = fresh_tmp("ros2_parameters")
    client = Client()


def tearDownModule():
    client.close()
    stop_daemon()


def build_of(points, name, args=BUILD_ARGS):
    path = os.path.join(TMP, name + ".xyz")
    write_xyz(path, points)
    return expected_triangles(hullmap_build([path], os.path.join(TMP, name + "_build"), args))


class ParametersThatCannotPoison(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        from sensor_msgs.msg import PointCloud2
        cls.node = HullmapNode(client, TMP, PARAMS, name="hullmap_parameters")
        cls.pub = client.publisher("/%s/cloud_in" % cls.node.name, PointCloud2, depth=10)
        client.wait_reader("/%s/cloud_in" % cls.node.name, reliable=True)
        cls.sent = 0

    @classmethod
    def tearDownClass(cls):
        cls.node.stop()

    def show(self, points, expected):
        self.pub.publish(cloud(points))
        ParametersThatCannotPoison.sent += 1
        stats = self.node.wait_idle(self.sent)
        wait_for("~/obstacles equal to hullmap build's", lambda: same_triangles(self.node.hull_triangles(), expected))
        return stats

    def test_1_every_parameter_refuses_a_value_outside_its_range_naming_it(self):
        # The map 10 m from the origin: the octree at resolution 0.0002 reaches +-6.6 m, none of it.
        points = boxes([(10, 0, 1), (10, 2, 1)])
        expected = build_of(points, "far_boxes")
        self.show(points, expected)
        covered = set()
        for name, value in BAD + [("resolution", 0.0002)]:
            result = client.set_parameters(self.node.name, **{name: value})
            self.assertFalse(result.successful, "%s = %r was accepted" % (name, value))
            self.assertIn(name, result.reason, (name, value))
            covered.add(name)
        # With eps auto (eps 0.1 is more than 20 voxels of 0.0002), the octree's reach is what refuses it.
        reason = client.set_parameters(self.node.name, resolution=0.0002, eps="auto").reason
        self.assertIn("resolution: the octree could address no point of the current map", reason)
        from rcl_interfaces.srv import ListParameters
        listed = client.call("/%s/list_parameters" % self.node.name, ListParameters, ListParameters.Request())
        ours = {n for n in listed.result.names if not n.startswith("qos_overrides.") and n != "use_sim_time"}
        self.assertEqual(ours - covered, set(), "parameters without a bad value tried")
        # Nothing changed: the same map still rebuilds as before, and a valid value still applies.
        self.assertTrue(self.node.alive())
        stats = self.show(points, expected)
        self.assertEqual(stats["failed"], 0)
        self.assertTrue(client.set_parameters(self.node.name, resolution=0.01).successful)  # reaches +-328 m
        self.assertTrue(client.set_parameters(self.node.name, resolution=0.05).successful)

    def test_2_an_accepted_value_that_fails_to_build_gives_way_to_the_last_that_built(self):
        first, second = boxes([(0, 0, 1), (2, 0, 1)]), boxes([(0, 3, 1)])
        self.show(first, build_of(first, "kept_first"))
        # z_min 100 is in range, but leaves no point of these maps: their build fails with it.
        self.assertTrue(client.set_parameters(self.node.name, z_min=100.0).successful)
        stats = self.show(second, build_of(second, "kept_second"))  # built with the values before
        self.assertEqual(stats["failed"], 0)
        self.assertIn("z_min", stats["refused_settings"])
        self.assertEqual(stats["points"], len(second))
        self.show(first, build_of(first, "kept_first"))  # and goes on with them
        wait_for("the log to say why", lambda: "failed with the parameters as set" in self.node.process.output())
        # A value set again is tried again.
        self.assertTrue(client.set_parameters(self.node.name, z_min="none").successful)
        stats = self.show(second, build_of(second, "kept_second"))
        self.assertEqual(stats["refused_settings"], "")


if __name__ == "__main__":
    unittest.main(verbosity=2)
