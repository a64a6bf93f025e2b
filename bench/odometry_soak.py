#!/usr/bin/python3
"""Soak: the IcpDvoOdometry nodelet on a long live stream, its memory and rate sampled as it runs.

  bench/odometry_soak.py [TUM_FOLDER] [--frames 10000] [--rate 30] [--sample-every 500] [--port P]
                         [--fused-cloud-max-voxels N]

The real frames of TUM_FOLDER (default ../shared/data/tum/rgbd_dataset_freiburg1_xyz_first300) are
published as openni2_launch does (bgr8, 16UC1 millimetres, camera_info) at --rate, played forward
then backward and again (0..N-1, N-2..1, ...) with stamps that keep increasing, so the camera's motion
stays continuous for all --frames frames and the odometry never restarts. roslaunch vocal
odometry.launch runs the nodelet in its own manager (its own master on --port); this script
subscribes to /odom and /fused_cloud (so the nodelet publishes the map) and /diagnostics; the path's
length comes from the diagnostics (a Python subscriber to /path would spend more CPU deserialising
4,000 poses 30 times a second than the nodelet spends tracking).

Every --sample-every frames it prints the manager's resident memory (VmRSS from /proc), the
odometry rate and latency over the last window, the fused cloud's and the path's sizes and the
nodelet's keyframe count. At the end: RSS at frame 1,000 against the last sample (the issue's
bound: within 5 %), and the rate of the first and last windows.
"""
import argparse
import os
import signal
import subprocess
import sys
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..")
DEFAULT_FOLDER = os.path.join(ROOT, "..", "shared", "data", "tum", "rgbd_dataset_freiburg1_xyz_first300")
sys.path.insert(0, HERE)
from nodelet_realtime import ros_environment, stop, wait_for_topic  # noqa: E402

try:
    import cv2
    import rospy
    from diagnostic_msgs.msg import DiagnosticArray
    from nav_msgs.msg import Odometry
    from sensor_msgs.msg import CameraInfo, Image, PointCloud2
except ImportError as e:
    sys.exit(f"odometry_soak: {e} (scripts/install_dependencies installs python3-opencv and the message modules)")


def read_list(path):
    entries = []
    with open(path) as f:
        for line in f:
            if line.strip() and not line.startswith("#"):
                stamp, name = line.split()[:2]
                entries.append((float(stamp), name))
    return entries


def load_frames(folder):
    """The folder's RGB frames with the nearest depth frame (TUM's association), as message payloads."""
    rgb = read_list(os.path.join(folder, "rgb.txt"))
    depth = read_list(os.path.join(folder, "depth.txt"))
    frames = []
    for stamp, name in rgb:
        depth_stamp, depth_name = min(depth, key=lambda d: abs(d[0] - stamp))
        if abs(depth_stamp - stamp) > 0.02:
            continue
        colour = cv2.imread(os.path.join(folder, name), cv2.IMREAD_COLOR)  # BGR, as openni2_camera's bgr8
        raw = cv2.imread(os.path.join(folder, depth_name), cv2.IMREAD_UNCHANGED)  # TUM: 5000 per metre
        millimetres = (raw.astype("float64") / 5.0).round().astype("uint16")
        frames.append((colour.tobytes(), millimetres.tobytes(), colour.shape[1], colour.shape[0]))
    return frames


def image_message(data, width, height, encoding, bytes_per_pixel, frame_id):
    msg = Image()
    msg.header.frame_id = frame_id
    msg.width, msg.height, msg.encoding, msg.step = width, height, encoding, width * bytes_per_pixel
    msg.data = data
    return msg


def camera_info(width, height, frame_id):
    msg = CameraInfo()
    msg.header.frame_id = frame_id
    msg.width, msg.height = width, height
    fx, fy, cx, cy = 517.3, 516.5, 318.6, 255.3  # freiburg1
    msg.distortion_model = "plumb_bob"
    msg.D = [0.0] * 5
    msg.K = [fx, 0, cx, 0, fy, cy, 0, 0, 1]
    msg.R = [1, 0, 0, 0, 1, 0, 0, 0, 1]
    msg.P = [fx, 0, cx, 0, 0, fy, cy, 0, 0, 0, 1, 0]
    return msg


def resident_mib(pid):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    return float("nan")


def manager_pid(name):
    found = subprocess.run(["pgrep", "-f", f"__name:={name}"], capture_output=True, text=True).stdout.split()
    return int(found[0]) if found else None


class Listener:
    """What the nodelet publishes, counted under one lock."""

    def __init__(self):
        self.lock = threading.Lock()
        self.odometry = 0
        self.latencies = []  # seconds from publishing a frame to its odometry arriving
        self.published_at = {}
        self.fused_points = 0
        self.diagnostics = {}

    def on_odometry(self, msg):
        now = time.time()
        with self.lock:
            self.odometry += 1
            sent = self.published_at.pop(msg.header.stamp.to_nsec(), None)
            if sent is not None:
                self.latencies.append(now - sent)

    def on_fused_cloud(self, msg):
        with self.lock:
            self.fused_points = msg.width * msg.height

    def on_diagnostics(self, msg):
        for status in msg.status:
            if "icp_dvo_odometry" in status.name:
                with self.lock:
                    self.diagnostics = {kv.key: kv.value for kv in status.values}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("folder", nargs="?", default=DEFAULT_FOLDER)
    parser.add_argument("--frames", type=int, default=10000)
    parser.add_argument("--rate", type=float, default=30.0, help="frames per second published")
    parser.add_argument("--sample-every", type=int, default=500)
    parser.add_argument("--port", type=int, default=11418)
    parser.add_argument("--workdir", default="/tmp/vocal_odometry_soak")
    parser.add_argument("--fused-cloud-max-voxels", type=int, default=None,
                        help="the fused cloud's budget (the nodelet's default otherwise): a budget reached during "
                             "warm-up separates the map's growth from any other")
    args = parser.parse_args()
    if not os.path.exists(os.path.join(args.folder, "rgb.txt")):
        sys.exit(f"odometry_soak: {args.folder} is not a TUM folder (rgb.txt missing): the soak needs real frames")
    os.makedirs(args.workdir, exist_ok=True)

    frames = load_frames(args.folder)
    order = list(range(len(frames))) + list(range(len(frames) - 2, 0, -1))
    print(f"stream: {len(frames)} frames of {args.folder} played forward and back, {args.frames} frames at {args.rate} Hz")

    env = ros_environment(args.port)
    os.environ.update(env)
    log = open(os.path.join(args.workdir, "roslaunch.log"), "w")
    launch_args = []
    if args.fused_cloud_max_voxels is not None:
        config = os.path.join(args.workdir, "odometry.yaml")
        with open(os.path.join(ROOT, "config", "odometry.yaml")) as default, open(config, "w") as f:
            f.write(default.read() + f"\nfused_cloud_max_voxels: {args.fused_cloud_max_voxels}\n")
        launch_args.append(f"config:={config}")
    launch = subprocess.Popen(["roslaunch", "-p", str(args.port), "vocal", "odometry.launch"] + launch_args, env=env,
                              stdout=log, stderr=subprocess.STDOUT)
    try:
        if not wait_for_topic(env, "/odom", 60):
            sys.exit(f"odometry_soak: the nodelet did not advertise /odom within 60 s (see {args.workdir}/roslaunch.log)")
        pid = manager_pid("vocal_nodelet_manager")
        if pid is None:
            sys.exit("odometry_soak: no process of the nodelet manager found")
        rospy.init_node("odometry_soak", anonymous=True, disable_signals=True)
        listener = Listener()
        rospy.Subscriber("/odom", Odometry, listener.on_odometry, queue_size=100)
        rospy.Subscriber("/fused_cloud", PointCloud2, listener.on_fused_cloud, queue_size=1, buff_size=2 ** 26)
        rospy.Subscriber("/diagnostics", DiagnosticArray, listener.on_diagnostics, queue_size=10)
        frame_id = "camera_rgb_optical_frame"
        rgb_pub = rospy.Publisher("/camera/rgb/image_rect_color", Image, queue_size=2)
        depth_pub = rospy.Publisher("/camera/depth_registered/image_raw", Image, queue_size=2)
        info_pub = rospy.Publisher("/camera/rgb/camera_info", CameraInfo, queue_size=2)
        time.sleep(3.0)  # subscriptions connect both ways
        width, height = frames[0][2], frames[0][3]
        info = camera_info(width, height, frame_id)
        messages = [(image_message(c, width, height, "bgr8", 3, frame_id),
                     image_message(d, width, height, "16UC1", 2, frame_id)) for c, d, _, _ in frames]

        print(f"{'frame':>7} {'RSS MiB':>9} {'odom Hz':>8} {'latency ms':>11} {'fused pts':>10} {'path':>6} "
              f"{'keyframes':>9} {'skipped':>8}")
        samples = []
        start = time.time()
        stamp0 = rospy.Time(1000.0)
        window_start, window_odometry = start, 0
        for k in range(1, args.frames + 1):
            due = start + (k - 1) / args.rate
            delay = due - time.time()
            if delay > 0:
                time.sleep(delay)
            stamp = stamp0 + rospy.Duration.from_sec((k - 1) / args.rate)
            rgb, depth = messages[order[(k - 1) % len(order)]]
            for msg in (rgb, depth, info):
                msg.header.stamp = stamp
            with listener.lock:
                listener.published_at[stamp.to_nsec()] = time.time()
            depth_pub.publish(depth)
            info_pub.publish(info)
            rgb_pub.publish(rgb)
            if k % args.sample_every == 0:
                now = time.time()
                with listener.lock:
                    rate = (listener.odometry - window_odometry) / (now - window_start)
                    window_start, window_odometry = now, listener.odometry
                    latency = 1000.0 * sum(listener.latencies) / max(len(listener.latencies), 1)
                    listener.latencies = []
                    stale = stamp.to_nsec() - int(5e9)  # frames the nodelet skipped never get odometry
                    listener.published_at = {s: t for s, t in listener.published_at.items() if s > stale}
                    fused, diag = listener.fused_points, dict(listener.diagnostics)
                path = diag.get("path poses", "?")
                rss = resident_mib(pid)
                samples.append((k, rss, rate))
                print(f"{k:>7} {rss:>9.1f} {rate:>8.1f} {latency:>11.1f} {fused:>10} {path:>6} "
                      f"{diag.get('keyframes', '?'):>9} {diag.get('frames skipped', '?'):>8}", flush=True)
        time.sleep(3.0)
        with listener.lock:
            diagnostics = dict(listener.diagnostics)
            odometry = listener.odometry
    finally:
        stop(launch)

    print(f"odometry messages: {odometry} of {args.frames} frames ({odometry / args.frames:.3f})")
    at_1000 = next((rss for k, rss, _ in samples if k >= 1000), None)
    if at_1000 is not None and samples:
        last_frame, last_rss, _ = samples[-1]
        change = 100.0 * (last_rss - at_1000) / at_1000
        verdict = "flat (within 5 %)" if abs(change) <= 5.0 else "GROWS by more than 5 %"
        print(f"rss: frame 1000 {at_1000:.1f} MiB, frame {last_frame} {last_rss:.1f} MiB ({change:+.1f} %): {verdict}")
    if len(samples) >= 2:
        print(f"rate: first window {samples[0][2]:.1f} Hz, last window {samples[-1][2]:.1f} Hz")
    if diagnostics:
        print("nodelet diagnostics at the end:")
        for key in ["frames received", "frames skipped", "frames tracked", "frames lost", "frames dropped", "keyframes",
                    "resets", "path poses", "mean processing ms"]:
            if key in diagnostics:
                print(f"  {key}: {diagnostics[key]}")


if __name__ == "__main__":
    signal.signal(signal.SIGINT, signal.default_int_handler)
    main()
