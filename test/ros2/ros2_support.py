"""What the ROS 2 tests share (test/ros2/run_test.sh runs them with ROS 2 and the package sourced).

- claim_domain(): a ROS_DOMAIN_ID no other test on this machine holds (a lock file per id), so tests
  running at once, in this checkout or another, never see each other's nodes;
- Process: `ros2 run` / `ros2 launch` / `ros2 bag` in a session of their own, stopped with their whole
  process group (ros2 run starts the node as a child of a Python process);
- Client: an rclpy node spinning in a thread, with helpers to publish and to keep the latest message
  of a topic;
- messages from points (PointCloud2 of FLOAT64 fields: the exact doubles `hullmap build` reads as text)
  and from the ORB-SLAM echo dump (Markers);
- hullmap_build(): `hullmap build` of the same points, the oracle of every comparison.

Environment: HULLMAP_BINARY (the CLI), HULLMAP_SOURCE_DIR, HULLMAP_TEST_TMP. Nothing asserts on
wall-clock time: waits only time out.
"""
import fcntl
import json
import os
import shutil
import signal
import struct
import subprocess
import tempfile
import threading
import time

HULLMAP = os.environ["HULLMAP_BINARY"]
SOURCE = os.environ["HULLMAP_SOURCE_DIR"]
ECHO_DUMP = os.path.join(SOURCE, "test", "data", "orbslam_echo_map.txt")
TIMEOUT = 30.0  # seconds any single wait may take before the test fails

_held_locks = []


def claim_domain():
    """Sets ROS_DOMAIN_ID to the first id in 1..101 whose lock file this process can lock (held until
    it exits), so no two tests on the machine share a domain. Returns it."""
    lock_dir = os.path.join(tempfile.gettempdir(), "hullmap-ros2-domains")
    os.makedirs(lock_dir, exist_ok=True)
    for domain in range(1, 102):
        f = open(os.path.join(lock_dir, "%d.lock" % domain), "w")
        try:
            fcntl.flock(f, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            f.close()
            continue
        _held_locks.append(f)
        os.environ["ROS_DOMAIN_ID"] = str(domain)
        return domain
    raise RuntimeError("no free ROS_DOMAIN_ID in 1..101")


def fresh_tmp(name):
    path = os.path.join(os.environ["HULLMAP_TEST_TMP"], name)
    shutil.rmtree(path, ignore_errors=True)
    os.makedirs(path)
    return path


def wait_for(what, condition, timeout=TIMEOUT):
    deadline = time.time() + timeout
    while time.time() < deadline:
        value = condition()
        if value:
            return value
        time.sleep(0.02)
    raise AssertionError("timed out waiting for " + what)


class Process:
    """A command in its own session (setsid), its output in TMP/<name>.log; stop() ends its group."""

    def __init__(self, args, log_path):
        self.log_path = log_path
        self.log = open(log_path, "w")
        self.process = subprocess.Popen(args, stdout=self.log, stderr=subprocess.STDOUT, start_new_session=True)

    def alive(self):
        return self.process.poll() is None

    def stop(self, sig=signal.SIGINT):
        """Signals the process group, waits, then kills what is left of it. Returns the exit status."""
        if self.process.poll() is None:
            try:
                os.killpg(self.process.pid, sig)
            except ProcessLookupError:
                pass
            try:
                self.process.wait(20)
            except subprocess.TimeoutExpired:
                pass
        try:
            os.killpg(self.process.pid, signal.SIGKILL)  # children that outlived the leader
        except ProcessLookupError:
            pass
        if self.process.poll() is None:
            self.process.wait(10)
        self.log.close()
        return self.process.returncode

    def output(self):
        with open(self.log_path) as f:
            return f.read()


def stop_daemon():
    subprocess.run(["ros2", "daemon", "stop"], capture_output=True, timeout=TIMEOUT)


class Client:
    """An rclpy node spinning in a background thread."""

    def __init__(self, name="hullmap_test"):
        import rclpy
        from rclpy.executors import MultiThreadedExecutor
        self.rclpy = rclpy
        rclpy.init()
        self.node = rclpy.create_node("%s_%d" % (name, os.getpid()))
        self.executor = MultiThreadedExecutor()
        self.executor.add_node(self.node)
        self.thread = threading.Thread(target=self.executor.spin, daemon=True)
        self.thread.start()

    def close(self):
        self.executor.shutdown()
        self.node.destroy_node()
        self.rclpy.shutdown()

    def latched_qos(self):
        from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
        return QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL)

    def latest(self, topic, cls, qos=None):
        """A Latest holding the newest message on `topic` (outputs: reliable, transient_local)."""
        return Latest(self, topic, cls, qos or self.latched_qos())

    def publisher(self, topic, cls, depth=100, transient_local=False, best_effort=False):
        """A publisher (reliable unless `best_effort`), returned once some subscription matched it and
        the subscription had time to match it back: DDS discovery runs both ways, and a best-effort
        reader drops what a writer it does not know yet sends."""
        from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
        qos = QoSProfile(depth=depth,
                         reliability=ReliabilityPolicy.BEST_EFFORT if best_effort else ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.TRANSIENT_LOCAL if transient_local else DurabilityPolicy.VOLATILE)
        pub = self.node.create_publisher(cls, topic, qos)
        wait_for("a subscriber on " + topic, lambda: pub.get_subscription_count() > 0)
        time.sleep(0.5)
        return pub

    def wait_reader(self, topic, reliable, transient_local=False):
        """Until the subscriptions on `topic` are all of that reliability and durability (the node's
        map inputs follow their publishers' QoS: a publisher waits for the reader it will keep)."""
        from rclpy.qos import DurabilityPolicy, ReliabilityPolicy
        want = (ReliabilityPolicy.RELIABLE if reliable else ReliabilityPolicy.BEST_EFFORT,
                DurabilityPolicy.TRANSIENT_LOCAL if transient_local else DurabilityPolicy.VOLATILE)

        def settled():
            infos = self.node.get_subscriptions_info_by_topic(topic)
            return infos and all((i.qos_profile.reliability, i.qos_profile.durability) == want for i in infos)
        wait_for("the readers on %s to be %s" % (topic, want), settled)
        time.sleep(0.5)  # the writer matches the new reader back

    def set_parameters(self, node_name, **values):
        """Sets parameters through /NODE/set_parameters_atomically: its SetParametersResult."""
        from rcl_interfaces.msg import Parameter, ParameterType, ParameterValue
        from rcl_interfaces.srv import SetParametersAtomically
        request = SetParametersAtomically.Request()
        for name, value in values.items():
            v = ParameterValue()
            if isinstance(value, bool):
                v.type, v.bool_value = ParameterType.PARAMETER_BOOL, value
            elif isinstance(value, int):
                v.type, v.integer_value = ParameterType.PARAMETER_INTEGER, value
            elif isinstance(value, float):
                v.type, v.double_value = ParameterType.PARAMETER_DOUBLE, value
            else:
                v.type, v.string_value = ParameterType.PARAMETER_STRING, str(value)
            request.parameters.append(Parameter(name=name, value=v))
        return self.call("/%s/set_parameters_atomically" % node_name, SetParametersAtomically, request).result

    def call(self, service, cls, request):
        client = self.node.create_client(cls, service)
        if not client.wait_for_service(timeout_sec=TIMEOUT):
            raise AssertionError("service %s did not appear" % service)
        future = client.call_async(request)
        wait_for("an answer from " + service, future.done)
        self.node.destroy_client(client)
        return future.result()


class Latest:
    def __init__(self, client, topic, cls, qos):
        self.value = None
        self.count = 0
        self.lock = threading.Lock()
        self.sub = client.node.create_subscription(cls, topic, self._take, qos)
        self.client = client

    def _take(self, msg):
        with self.lock:
            self.value = msg
            self.count += 1

    def close(self):
        self.client.node.destroy_subscription(self.sub)


def cloud(points, stamp=None, with_z=True, frame_id="world"):
    """A PointCloud2 of FLOAT64 x, y (and z) fields."""
    from sensor_msgs.msg import PointCloud2, PointField
    names = ["x", "y", "z"] if with_z else ["x", "y"]
    msg = PointCloud2()
    msg.header.frame_id = frame_id
    if stamp is not None:
        msg.header.stamp = stamp
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
    return [(cx - half + i * spacing, cy - half + j * spacing, cz - half + k * spacing)
            for cx, cy, cz in centres for i in range(n + 1) for j in range(n + 1) for k in range(n + 1)]


def write_xyz(path, points):
    with open(path, "w") as f:
        for p in points:
            f.write("%r %r %r\n" % tuple(p))


def echo_markers():
    """The echo dump's messages as visualization_msgs/Marker, in order."""
    import yaml
    from geometry_msgs.msg import Point
    from std_msgs.msg import ColorRGBA
    from visualization_msgs.msg import Marker
    with open(ECHO_DUMP) as f:
        docs = [d for d in yaml.safe_load_all(f) if d]
    markers = []
    for doc in docs:
        m = Marker()
        m.header.frame_id = doc["header"]["frame_id"]
        m.header.stamp.sec = doc["header"]["stamp"]["secs"]
        m.header.stamp.nanosec = doc["header"]["stamp"]["nsecs"]
        m.ns, m.id, m.type, m.action = doc["ns"], doc["id"], doc["type"], doc["action"]
        m.pose.orientation.w = float(doc["pose"]["orientation"]["w"])
        m.scale.x, m.scale.y, m.scale.z = (float(doc["scale"][k]) for k in "xyz")
        m.points = [Point(x=float(p["x"]), y=float(p["y"]), z=float(p["z"])) for p in doc.get("points") or []]
        m.colors = [ColorRGBA(r=float(c["r"]), g=float(c["g"]), b=float(c["b"]), a=float(c["a"]))
                    for c in doc.get("colors") or []]
        markers.append(m)
    return markers


def hullmap_build(inputs, out, args):
    """`hullmap build INPUTS -o OUT ARGS`; its obstacles.json's obstacles."""
    run = subprocess.run([HULLMAP, "build", *inputs, "-o", out, *args], capture_output=True, text=True)
    if run.returncode != 0:
        raise AssertionError("hullmap build %s: %s" % (" ".join(inputs + args), run.stderr))
    with open(os.path.join(out, "obstacles.json")) as f:
        return json.load(f)["obstacles"]


def expected_triangles(obstacles):
    """id -> the hull's triangles (its convex parts' hulls' when it has parts) as the TRIANGLE_LIST
    points the node must publish, in order."""
    def triangles(hull):
        return [tuple(hull["vertices"][k]) for t in hull["triangles"] for k in t]
    return {o["id"]: ([p for part in o["parts"] for p in triangles(part["hull"])] if o.get("parts") else
                      triangles(o["hull"])) for o in obstacles}


def hull_triangles(marker_array):
    """id -> TRIANGLE_LIST points of a ~/obstacles message (ns hulls), or None."""
    if marker_array is None:
        return None
    return {m.id: [(p.x, p.y, p.z) for p in m.points] for m in marker_array.markers
            if m.ns == "hulls" and m.action == 0}


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


def ros_args(params):
    """--ros-args -p name:=value for each parameter (values as ROS 2 reads them from YAML)."""
    args = []
    for name, value in params.items():
        args += ["-p", "%s:=%s" % (name, value)]
    return args


def param_get(node_name, name):
    """`ros2 param get /NODE NAME`'s answer, asked again while the node is not yet discovered."""
    def answer():
        run = subprocess.run(["ros2", "param", "get", "--no-daemon", "/" + node_name, name], capture_output=True,
                             text=True, timeout=TIMEOUT)
        return run.stdout.strip() if run.returncode == 0 and run.stdout.strip() else None
    return wait_for("ros2 param get /%s %s" % (node_name, name), answer)


def param_set(node_name, name, value):
    """`ros2 param set /NODE NAME VALUE` (asked again while the node is not yet discovered): its output."""
    def answer():
        run = subprocess.run(["ros2", "param", "set", "--no-daemon", "/" + node_name, name, str(value)],
                             capture_output=True, text=True, timeout=TIMEOUT)
        out = run.stdout + run.stderr
        return out if "Node not found" not in out else None
    return wait_for("ros2 param set /%s %s" % (node_name, name), answer)


def reliable_input(node_name, topic, depth):
    """Parameters that make the node's input `topic` (~/cloud_in: "/NAME/cloud_in") reliable with
    room for `depth` messages (its QoS overrides), so that a test's burst reaches it whole."""
    prefix = "qos_overrides.%s.subscription." % topic.replace("~", "/" + node_name)
    return {prefix + "reliability": "reliable", prefix + "depth": depth}


class HullmapNode:
    """hullmap_node started with `ros2 run` (or `ros2 launch`, or loaded in a container: give `process`),
    with the latest ~/stats, ~/obstacles and ~/path_check it published."""

    count = 0

    def __init__(self, client, tmp, params=None, extra_args=(), name=None, process=None, wait=True):
        from std_msgs.msg import String
        from visualization_msgs.msg import MarkerArray
        HullmapNode.count += 1
        self.client = client
        self.name = name or "hullmap%d" % HullmapNode.count
        if process is None:
            args = ["ros2", "run", "hullmap_ros2", "hullmap_node", "--ros-args", "-r", "__node:=" + self.name]
            args += ros_args(params or {}) + list(extra_args)
            process = Process(args, os.path.join(tmp, self.name + ".log"))
        self.process = process
        self.stats_topic = client.latest("/%s/stats" % self.name, String)
        self.obstacles_topic = client.latest("/%s/obstacles" % self.name, MarkerArray)
        self.path_check_topic = client.latest("/%s/path_check" % self.name, String)
        if wait:
            wait_for(self.name + "'s ~/stats (log: %s)" % process.log_path, lambda: self.stats is not None)

    @property
    def stats(self):
        msg = self.stats_topic.value
        return json.loads(msg.data) if msg is not None else None

    @property
    def obstacles(self):
        return self.obstacles_topic.value

    def hull_triangles(self):
        return hull_triangles(self.obstacles)

    def send_until_taken(self, publisher, msg, what):
        """Publishes `msg` until the node took one more map message than before (a best-effort input
        may lose one). Returns the stats."""
        before = self.stats["messages"] + self.stats["skipped"]
        deadline = time.time() + TIMEOUT
        while time.time() < deadline:
            publisher.publish(msg)
            try:
                return wait_for(what, lambda: self.stats["messages"] + self.stats["skipped"] > before, timeout=2.0)
            except AssertionError:
                continue
        raise AssertionError("timed out waiting for " + what)

    def wait_idle(self, messages):
        """Until the node took `messages` map messages (or skipped them) and nothing waits or runs."""
        def idle():
            s = self.stats
            return s and s["messages"] + s["skipped"] >= messages and not s["pending"] and not s["busy"] and s
        return wait_for("%s to take %d messages and go idle (stats %s)" % (self.name, messages, self.stats), idle)

    def alive(self):
        return self.process.alive()

    def stop(self):
        for t in (self.stats_topic, self.obstacles_topic, self.path_check_topic):
            t.close()
        return self.process.stop()
