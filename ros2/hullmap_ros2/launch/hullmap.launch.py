"""hullmap's ROS 2 node on ORB-SLAM's map (docs/ROS.md).

    ros2 launch hullmap_ros2 hullmap.launch.py                       # /ORB_SLAM/Map, config/hullmap.yaml
    ros2 launch hullmap_ros2 hullmap.launch.py cloud:=/orb_slam3/all_points min_pts:=5
    ros2 launch hullmap_ros2 hullmap.launch.py params_file:=my_hullmap.yaml

The arguments are the ROS 1 launch file's (ros/launch/hullmap.launch): `map` (the Marker topic, remapped
onto /ORB_SLAM/Map), `cloud` (remapped onto ~/cloud_in), and the parameters resolution, eps, min_pts,
floor, level, concavity, flat_gap, up, frame_id, min_interval, output_dir and radius, plus `params_file` (the
parameters YAML, default this package's config/hullmap.yaml, which holds the ROS 1 launch file's
defaults) and use_sim_time. A parameter argument given on the command line wins over the YAML; one
left out takes the YAML's value.
"""
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, OpaqueFunction
from launch.substitutions import LaunchConfiguration, PathJoinSubstitution
from launch_ros.actions import Node
from launch_ros.substitutions import FindPackageShare

PARAMETERS = ["resolution", "eps", "min_pts", "floor", "level", "concavity", "flat_gap", "up", "frame_id",
              "min_interval", "output_dir", "radius", "use_sim_time"]


def value(text):
    """A launch argument's text as the parameter's type: number, true/false, or the text itself."""
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return {"true": True, "false": False}.get(text, text)


def node(context):
    given = {name: value(LaunchConfiguration(name).perform(context)) for name in PARAMETERS
             if LaunchConfiguration(name).perform(context) != ""}
    return [Node(
        package="hullmap_ros2",
        executable="hullmap_node",
        name="hullmap",
        output="screen",
        parameters=[LaunchConfiguration("params_file"), given],
        remappings=[("/ORB_SLAM/Map", LaunchConfiguration("map")),
                    ("~/cloud_in", LaunchConfiguration("cloud"))],
    )]


def generate_launch_description():
    arguments = [
        DeclareLaunchArgument("map", default_value="/ORB_SLAM/Map",
                              description="ORB-SLAM's visualization_msgs/Marker map topic"),
        DeclareLaunchArgument("cloud", default_value="~/cloud_in",
                              description="a sensor_msgs/PointCloud2 map topic (ORB-SLAM2/3 wrappers)"),
        DeclareLaunchArgument("params_file",
                              default_value=PathJoinSubstitution([FindPackageShare("hullmap_ros2"), "config",
                                                                  "hullmap.yaml"]),
                              description="the node's parameters (YAML, ros__parameters)"),
    ]
    arguments += [DeclareLaunchArgument(name, default_value="",
                                        description="the parameter " + name + " (empty: the params_file's)")
                  for name in PARAMETERS]
    return LaunchDescription(arguments + [OpaqueFunction(function=node)])
