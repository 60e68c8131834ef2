#!/usr/bin/env python3
"""hullmap_ros2's launch file and parameters YAML, run for real: `ros2 launch hullmap_ros2
hullmap.launch.py params_file:=YAML ...` and `ros2 run ... --ros-args --params-file YAML` start the
node with the YAML's parameters (its obstacles are `hullmap build`'s with the same options, and
`ros2 param get` reads them back), a launch argument wins over the YAML, `map` and `cloud` remap the
inputs, and the packaged YAML holds the ROS 1 launch file's defaults.
"""
import os
import subprocess
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ros2_support  # noqa: E402
from ros2_support import (TIMEOUT, Client, HullmapNode, Process, boxes, claim_domain, cloud, echo_markers,  # noqa: E402
                          expected_triangles, fresh_tmp, hullmap_build, same_triangles, stop_daemon, wait_for,
                          write_xyz, ECHO_DUMP)

TMP = None
client = None
YAML = """/**:
  ros__parameters:
    resolution: 0.05
    eps: 0.1
    min_pts: 5
    floor: none
    concavity: none
    extension: off
    up: z
    frame_id: launched_map
    radius: 0.3
    output_dir: {output_dir}
    qos_overrides:
      /ORB_SLAM/Map:
        subscription:
          reliability: reliable
          depth: 20
"""
BUILD_ARGS = ["--resolution", "0.05", "--eps", "0.1", "--min-pts", "5", "--floor", "none", "--concavity", "none",
              "--extension", "off"]


def setUpModule():
    global TMP, client
    claim_domain()
    TMP = fresh_tmp("ros2_launch")
    client = Client()


def tearDownModule():
    client.close()
    stop_daemon()


def param_get(name):
    return ros2_support.param_get("hullmap", name)


class LaunchAndParameters(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.yaml = os.path.join(TMP, "hullmap.yaml")
        with open(cls.yaml, "w") as f:
            f.write(YAML.format(output_dir=os.path.join(TMP, "saved")))
        cls.points = boxes([(0, 0, 1), (0.35, 0, 1), (2, 0, 1)])
        cls.xyz = os.path.join(TMP, "boxes.xyz")
        write_xyz(cls.xyz, cls.points)

    def run_node(self, args, log):
        return HullmapNode(client, TMP, name="hullmap", process=Process(args, os.path.join(TMP, log)))

    def send_cloud(self, node, topic):
        from sensor_msgs.msg import PointCloud2
        pub = client.publisher(topic, PointCloud2)
        node.send_until_taken(pub, cloud(self.points), "the cloud on " + topic)
        node.wait_idle(1)

    def test_the_launch_file_starts_the_node_with_the_yamls_parameters(self):
        expected = expected_triangles(hullmap_build([self.xyz], os.path.join(TMP, "yaml_build"), BUILD_ARGS))
        node = self.run_node(["ros2", "launch", "hullmap_ros2", "hullmap.launch.py", "params_file:=" + self.yaml,
                              "cloud:=/test/cloud"], "launch_yaml.log")
        try:
            self.send_cloud(node, "/test/cloud")
            wait_for("~/obstacles equal to hullmap build's with the YAML's options",
                     lambda: same_triangles(node.hull_triangles(), expected))
            self.assertEqual({m.header.frame_id for m in node.obstacles.markers}, {"launched_map"})
            self.assertIn("0.3", param_get("radius"))
            # YAML reads off as false; the node takes false for extension off.
            self.assertIn(param_get("extension"), ("String value is: off", "Boolean value is: False"))
            self.assertIn("reliable", param_get("qos_overrides./ORB_SLAM/Map.subscription.reliability"))
        finally:
            node.stop()

    def test_launch_arguments_win_over_the_yaml_and_map_remaps_the_marker_topic(self):
        from visualization_msgs.msg import Marker
        # The echo dump needs eps 0.15 and min_pts 2: given as arguments, over the YAML's 0.1 and 5.
        args = ["--resolution", "0.05", "--eps", "0.15", "--min-pts", "2", "--floor", "none", "--concavity", "none"]
        expected = expected_triangles(hullmap_build([ECHO_DUMP], os.path.join(TMP, "args_build"), args))
        node = self.run_node(["ros2", "launch", "hullmap_ros2", "hullmap.launch.py", "params_file:=" + self.yaml,
                              "map:=/test/orbslam", "eps:=0.15", "min_pts:=2"], "launch_args.log")
        try:
            pub = client.publisher("/test/orbslam", Marker)
            markers = echo_markers()
            for m in markers:
                pub.publish(m)
            node.wait_idle(sum(m.ns == "MapPoints" for m in markers))
            wait_for("~/obstacles equal to hullmap build's with the arguments' eps and min_pts",
                     lambda: same_triangles(node.hull_triangles(), expected))
            self.assertIn("0.15", param_get("eps"))
            self.assertIn("2", param_get("min_pts"))
        finally:
            node.stop()

    def test_ros2_run_with_params_file_reads_the_same_yaml(self):
        expected = expected_triangles(hullmap_build([self.xyz], os.path.join(TMP, "run_build"), BUILD_ARGS))
        node = self.run_node(["ros2", "run", "hullmap_ros2", "hullmap_node", "--ros-args", "--params-file", self.yaml],
                             "run_params_file.log")
        try:
            self.send_cloud(node, "/hullmap/cloud_in")
            wait_for("~/obstacles equal to hullmap build's with the YAML's options",
                     lambda: same_triangles(node.hull_triangles(), expected))
        finally:
            node.stop()

    def test_the_packaged_yaml_holds_the_ros1_launch_files_defaults(self):
        node = self.run_node(["ros2", "launch", "hullmap_ros2", "hullmap.launch.py"], "launch_defaults.log")
        try:
            for name, value in (("up", "-y"), ("eps", "auto"), ("min_pts", "auto"), ("floor", "auto"),
                                ("concavity", "default"), ("flat_gap", "auto"), ("resolution", "0.05"),
                                ("frame_id", "map"), ("min_interval", "0.0"), ("radius", "0.25")):
                self.assertIn(value, param_get(name), name)
        finally:
            node.stop()


if __name__ == "__main__":
    unittest.main(verbosity=2)
