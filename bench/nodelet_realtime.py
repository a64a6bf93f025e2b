#!/usr/bin/python3
"""Plays a recording in real time into the IcpDvoOdometry nodelet, as a robot's camera would feed it, and
compares what it published with bag_odometry's offline run of the same recording.

  bench/nodelet_realtime.py TUM_FOLDER [--rate R] [--workdir DIR] [--no-clouds] [--port P] [--config FILE] [--busy N]
                               [--imu DIR [--imu-time-offset S]]

1. tum_to_bag --layout openni2: the frames as openni2_launch records them (bgr8 on
   /camera/rgb/image_rect_color, 16UC1 millimetres on /camera/depth_registered/image_raw, camera_info).
2. bag_odometry on that bag (every frame, as fast as it goes): the offline trajectory.
3. roslaunch vocal odometry.launch (its own master on --port), rosbag record of /odom, /diagnostics and,
   unless --no-clouds, the current and fused clouds (subscribers make the nodelet build them), then
   rosbag play at --rate (1 = real time); with --busy N, N CPU-bound processes run beside the live part (a
   robot's other work: the CPU is shared with them, the player and the recorder).
   With --imu DIR (simulate_imu's imu.txt and imu_extrinsics.yaml), the bag also carries the IMU on
   /camera/imu (gyro and accelerometer, its frame on tf) and both the nodelet (imu:=/camera/imu) and
   bag_odometry (--imu-topic /camera/imu) take it.
4. Prints the share of frames with odometry, RPE / ATE of both trajectories against the ground truth and
   the nodelet's last diagnostics (skipped frames, per-stage means).
"""
import argparse
import os
import signal
import subprocess
import sys
import time

from cpu_burners import busy_processes
from tool_metrics import metrics

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..")
TOOLS = os.path.join(ROOT, "devel", "lib", "vocal")

try:
    import rosbag
except ImportError:
    sys.exit("nodelet_realtime: python3-rosbag is not installed (scripts/install_dependencies)")


def run(command, what, **kwargs):
    result = subprocess.run(command, capture_output=True, text=True, **kwargs)
    if result.returncode != 0:
        sys.exit(f"nodelet_realtime: {what} failed:\n{result.stdout}{result.stderr}")
    return result


def ros_environment(port):
    env = dict(os.environ)
    env["ROS_MASTER_URI"] = f"http://localhost:{port}"
    env["PATH"] = "/usr/bin:/bin:" + env.get("PATH", "")
    setup = subprocess.run(["bash", "-c", f"source {ROOT}/devel/setup.bash && env"], capture_output=True, text=True,
                           env=env, check=True)
    for line in setup.stdout.splitlines():
        key, _, value = line.partition("=")
        if key in ("ROS_PACKAGE_PATH", "CMAKE_PREFIX_PATH", "LD_LIBRARY_PATH", "PYTHONPATH", "ROSLISP_PACKAGE_PATH",
                   "PKG_CONFIG_PATH", "ROS_ROOT", "ROS_ETC_DIR", "ROS_DISTRO", "ROS_VERSION", "ROS_PYTHON_VERSION"):
            env[key] = value
    return env


def wait_until_listed(env, lister, name, seconds):
    """Whether `name` shows in `lister list` (rostopic, rosservice) within `seconds`."""
    deadline = time.time() + seconds
    while time.time() < deadline:
        listed = subprocess.run([lister, "list"], capture_output=True, text=True, env=env)
        if name in listed.stdout.split():
            return True
        time.sleep(0.5)
    return False


def wait_for_topic(env, topic, seconds):
    return wait_until_listed(env, "rostopic", topic, seconds)


def stop(process):
    if process.poll() is None:
        process.send_signal(signal.SIGINT)
        try:
            process.wait(timeout=20)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()


def write_trajectory(path, poses):
    with open(path, "w") as f:
        f.write("# timestamp tx ty tz qx qy qz qw\n")
        for stamp, p, q in poses:
            f.write("%.6f %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n" % (stamp, p.x, p.y, p.z, q.x, q.y, q.z, q.w))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("folder")
    parser.add_argument("--rate", type=float, default=1.0, help="rosbag play rate (1 = real time)")
    parser.add_argument("--workdir", default="/tmp/vocal_nodelet_realtime")
    parser.add_argument("--no-clouds", action="store_true", help="nobody subscribes to the clouds")
    parser.add_argument("--port", type=int, default=11417, help="port of the ROS master this run starts")
    parser.add_argument("--config", help="odometry settings for both runs (default: config/odometry.yaml)")
    parser.add_argument("--busy", type=int, default=0, help="CPU-bound processes running beside the live run")
    parser.add_argument("--imu", help="a folder with imu.txt and imu_extrinsics.yaml to play on /camera/imu")
    parser.add_argument("--imu-time-offset", type=float, default=0.0, help="IMU stamp = camera stamp + this (s)")
    args = parser.parse_args()
    ground_truth = os.path.join(args.folder, "groundtruth.txt")
    if not os.path.exists(ground_truth):
        sys.exit(f"nodelet_realtime: {ground_truth} is missing: accuracy needs ground truth")
    os.makedirs(args.workdir, exist_ok=True)
    bag = os.path.join(args.workdir, "openni2.bag")
    imu = ["--imu", os.path.abspath(args.imu)] if args.imu else []
    run([os.path.join(TOOLS, "tum_to_bag"), args.folder, bag, "--layout", "openni2", "--quiet"] + imu, "tum_to_bag")
    offline_trajectory = os.path.join(args.workdir, "bag_odometry.txt")
    config = ["--config", os.path.abspath(args.config)] if args.config else []
    offline_imu = ["--imu-topic", "/camera/imu", "--imu-time-offset", str(args.imu_time_offset)] if args.imu else []
    offline = metrics(run([os.path.join(TOOLS, "bag_odometry"), bag, "--output", offline_trajectory, "--groundtruth",
                           ground_truth, "--quiet"] + config + offline_imu, "bag_odometry").stdout)

    env = ros_environment(args.port)
    record_bag = os.path.join(args.workdir, "nodelet_output.bag")
    topics = ["/odom", "/diagnostics"] + ([] if args.no_clouds else ["/cloud", "/fused_cloud"])
    launch_log = open(os.path.join(args.workdir, "roslaunch.log"), "w")
    launch_config = ["config:=" + os.path.abspath(args.config)] if args.config else []
    if args.imu:
        launch_config += ["imu:=/camera/imu", f"imu_time_offset:={args.imu_time_offset}"]
    launch = subprocess.Popen(["roslaunch", "-p", str(args.port), "vocal", "odometry.launch"] + launch_config, env=env,
                              stdout=launch_log, stderr=subprocess.STDOUT)
    recorder = None
    try:
        if not wait_for_topic(env, "/odom", 60):
            sys.exit("nodelet_realtime: the nodelet did not advertise /odom within 60 s")
        recorder = subprocess.Popen(["rosbag", "record", "-O", record_bag] + topics, env=env,
                                    stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        time.sleep(3.0)  # the recorder's subscriptions reach the nodelet
        with busy_processes(args.busy):
            run(["rosbag", "play", "--quiet", "--rate", str(args.rate), bag], "rosbag play", env=env)
            time.sleep(3.0)  # the last frame's odometry and a diagnostics update
    finally:
        if recorder:
            stop(recorder)
        stop(launch)

    poses, diagnostics, clouds = [], None, 0
    with rosbag.Bag(record_bag) as recorded:
        for topic, msg, _ in recorded.read_messages():
            if topic == "/odom":
                poses.append((msg.header.stamp.to_sec(), msg.pose.pose.position, msg.pose.pose.orientation))
            elif topic == "/cloud":
                clouds += 1
            elif topic == "/diagnostics":
                for status in msg.status:
                    if "odometry" in status.name:
                        diagnostics = {kv.key: kv.value for kv in status.values}
    nodelet_trajectory = os.path.join(args.workdir, "nodelet.txt")
    write_trajectory(nodelet_trajectory, poses)
    online = metrics(run([os.path.join(TOOLS, "evaluate_trajectory"), ground_truth, nodelet_trajectory],
                         "evaluate_trajectory").stdout)

    frames = int(offline.get("frames", 0))
    print(f"recording: {bag} ({frames} frames, openni2_launch topics, bgr8 + 16UC1), played at rate {args.rate}, "
          f"{args.busy} busy processes beside it on {os.cpu_count()} CPUs")
    print(f"odometry_published: {len(poses)}")
    print(f"odometry_share: {len(poses) / max(frames, 1):.3f}")
    print(f"clouds_published: {clouds}")
    print(f"{'metric':<22}{'nodelet':>12}{'bag_odometry':>14}")
    for key in ["ate_rmse_m", "rpe_trans_m_per_s", "rpe_rot_deg_per_s"]:
        print(f"{key:<22}{online.get(key, float('nan')):>12.4f}{offline.get(key, float('nan')):>14.4f}")
    if "rpe_trans_m_per_s" in online and "rpe_trans_m_per_s" in offline:
        print(f"rpe_ratio: {online['rpe_trans_m_per_s'] / offline['rpe_trans_m_per_s']:.3f}")
    if diagnostics:
        print("nodelet diagnostics at the end:")
        for key, value in diagnostics.items():
            print(f"  {key}: {value}")


if __name__ == "__main__":
    main()
