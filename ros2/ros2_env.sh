# Sourced (bash) by ros2/build.sh and test/ros2/run_test.sh, never by setup.sh or .ci/run themselves:
# finds ROS 2 for the process that sources it. A ROS 2 already sourced (AMENT_PREFIX_PATH holding
# rclcpp_components and rosidl_default_generators, as /opt/ros/<distro>/setup.bash leaves it) is used
# as it is; else ../shared/ros2/activate beside the checkout (the test core, see its README) is
# sourced. Returns 1 with the reason in HULLMAP_ROS2_MISSING when neither is there.
hullmap_ros2_found() {
  local prefix
  local IFS=:
  for prefix in ${AMENT_PREFIX_PATH:-}; do
    [ -f "$prefix/share/rclcpp_components/package.xml" ] || continue
    local p
    for p in ${AMENT_PREFIX_PATH:-}; do
      [ -f "$p/share/rosidl_default_generators/package.xml" ] && return 0
    done
  done
  return 1
}

hullmap_ros2_env() {
  local root
  root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
  HULLMAP_ROS2_MISSING=""
  hullmap_ros2_found && return 0
  local activate="$root/../shared/ros2/activate"
  if [ ! -f "$activate" ]; then
    HULLMAP_ROS2_MISSING="no ROS 2 sourced (rclcpp_components, rosidl_default_generators in AMENT_PREFIX_PATH) and no $activate"
    return 1
  fi
  # shellcheck disable=SC1090
  if ! source "$activate" >/dev/null; then
    HULLMAP_ROS2_MISSING="$activate failed (its Debian packages missing? see ../shared/ros2/README.md)"
    return 1
  fi
  hullmap_ros2_found && return 0
  HULLMAP_ROS2_MISSING="$activate sourced, but rclcpp_components or rosidl_default_generators is not in it"
  return 1
}
