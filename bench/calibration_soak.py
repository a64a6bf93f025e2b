#!/usr/bin/python3
"""Soak: the MsgCalibration nodelet on a long live session, its memory sampled as it runs.

  bench/calibration_soak.py [--poses 150] [--still 3] [--moving 1] [--seed 3] [--max-held-mb MB]
                            [--sample-every 20] [--port P] [--workdir DIR]

A simulated session (simulate_calibration_session: an RGB-D reference, a VLP-16-like lidar, a 2D laser
and a camera at 10 Hz, unsynchronised; the board held still --still s at each of --poses poses and
carried --moving s between them) is played in real time (rosbag play) into `roslaunch vocal
calibration.launch` (its own master on --port). Every --sample-every seconds it prints the manager's
resident memory (VmRSS from /proc) and what the nodelet's diagnostics say it holds; at the end it
calls ~calibrate and prints each sensor's error against the simulator's ground truth.
--max-held-mb is the nodelet's ~max_held_mb (its default otherwise; 0: no budget, as before it had one).
"""
import argparse
import os
import subprocess
import sys
import threading
import time

import numpy as np
import yaml

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..")
TOOLS = os.path.join(ROOT, "devel", "lib", "vocal")
sys.path.insert(0, HERE)
from calibration_sessions import angle, rotation  # noqa: E402
from nodelet_realtime import ros_environment, stop, wait_until_listed  # noqa: E402
from odometry_soak import manager_pid, resident_mib  # noqa: E402

try:
    import rospy
    from diagnostic_msgs.msg import DiagnosticArray
except ImportError as e:
    sys.exit(f"calibration_soak: {e} (scripts/install_dependencies installs the message modules)")


class Diagnostics:
    """The calibration nodelet's latest diagnostics, by key."""

    def __init__(self):
        self.lock = threading.Lock()
        self.values = {}
        self.summary = ""

    def on_diagnostics(self, msg):
        for status in msg.status:
            if "msg_calibration" in status.name:
                with self.lock:
                    self.values = {kv.key: kv.value for kv in status.values}
                    self.summary = status.message


def simulate(folder, args):
    if os.path.exists(f"{folder}/session.bag"):
        return
    command = [f"{TOOLS}/simulate_calibration_session", folder, "--poses", str(args.poses), "--still", str(args.still),
               "--moving", str(args.moving), "--seed", str(args.seed)]
    print("simulating: " + " ".join(command), flush=True)
    done = subprocess.run(command, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"calibration_soak: simulation failed:\n{done.stdout}{done.stderr}")


def errors(result_path, truth_path):
    result = yaml.safe_load(open(result_path))
    truth = yaml.safe_load(open(truth_path))
    cells = []
    for s, t in zip(result["sensors"][1:], truth["sensors"][1:]):
        p = t["pose"]
        cells.append(f"{s['name']} {1000 * np.linalg.norm(np.array(s['translation']) - p[:3]):.1f} mm / "
                     f"{1000 * angle(rotation(p[3:]), rotation(s['rotation'])):.1f} mrad"
                     f"{'' if s.get('published', True) else ' (withheld)'}")
    return ", ".join(cells)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--poses", type=int, default=150)
    parser.add_argument("--still", type=float, default=3.0)
    parser.add_argument("--moving", type=float, default=1.0)
    parser.add_argument("--seed", type=int, default=3)
    parser.add_argument("--max-held-mb", type=float, default=None)
    parser.add_argument("--sample-every", type=float, default=20.0, help="seconds")
    parser.add_argument("--port", type=int, default=11419)
    parser.add_argument("--workdir", default="/tmp/vocal_calibration_soak")
    args = parser.parse_args()
    session = os.path.join(args.workdir, f"poses{args.poses}_still{args.still}_moving{args.moving}_seed{args.seed}")
    simulate(session, args)
    budget = "default" if args.max_held_mb is None else f"{args.max_held_mb:g}"
    output = os.path.join(args.workdir, f"result_budget_{budget}")
    os.makedirs(output, exist_ok=True)
    seconds = args.poses * (args.still + args.moving)
    print(f"session: {args.poses} poses, {args.still} s still + {args.moving} s moving ({seconds:.0f} s), "
          f"~max_held_mb {budget}", flush=True)

    env = ros_environment(args.port)
    os.environ.update(env)
    log = open(os.path.join(args.workdir, "roslaunch.log"), "w")
    launch_args = [f"rig:={session}/rig.yaml", f"output_dir:={output}"]
    if args.max_held_mb is not None:
        launch_args.append(f"max_held_mb:={args.max_held_mb}")
    launch = subprocess.Popen(["roslaunch", "-p", str(args.port), "vocal", "calibration.launch"] + launch_args, env=env,
                              stdout=log, stderr=subprocess.STDOUT)
    play = None
    try:
        if not wait_until_listed(env, "rosservice", "/msg_calibration/calibrate", 60):
            sys.exit(f"calibration_soak: no /msg_calibration/calibrate within 60 s (see {args.workdir}/roslaunch.log)")
        pid = manager_pid("vocal_calibration_manager")
        if pid is None:
            sys.exit("calibration_soak: no process of the nodelet manager found")
        rospy.init_node("calibration_soak", anonymous=True, disable_signals=True)
        diagnostics = Diagnostics()
        rospy.Subscriber("/diagnostics", DiagnosticArray, diagnostics.on_diagnostics, queue_size=10)
        time.sleep(2.0)
        print(f"{'s':>5} {'RSS MiB':>8}  nodelet's memory diagnostics", flush=True)
        started = time.time()
        play = subprocess.Popen(["rosbag", "play", "-q", f"{session}/session.bag"], env=env, stdout=subprocess.DEVNULL,
                                stderr=subprocess.STDOUT)
        samples = []
        next_sample = started
        while True:
            done = play.poll() is not None
            now = time.time()
            if now >= next_sample or done:
                rss = resident_mib(pid)
                with diagnostics.lock:
                    memory = diagnostics.values.get("memory", "-")
                samples.append((now - started, rss))
                print(f"{now - started:5.0f} {rss:8.1f}  {memory}", flush=True)
                next_sample += args.sample_every
            if done:
                break
            time.sleep(0.5)
        time.sleep(3.0)  # the last messages taken, a diagnostics update
        with diagnostics.lock:
            counts = {k: v for k, v in diagnostics.values.items() if k != "memory"}
        for name, value in counts.items():
            print(f"  {name}: {value}")
        called = time.time()
        reply = subprocess.run(["rosservice", "call", "/msg_calibration/calibrate"], capture_output=True, text=True, env=env,
                               timeout=600)
        print(f"~calibrate ({time.time() - called:.0f} s): {reply.stdout.strip()[:400]}")
        print(f"RSS after ~calibrate: {resident_mib(pid):.1f} MiB")
        if os.path.exists(f"{output}/calibration.yaml"):
            print("errors against the ground truth: " + errors(f"{output}/calibration.yaml", f"{session}/ground_truth.yaml"))
        # The growth after the first sample that holds a minute of session.
        minute = next((rss for t, rss in samples if t >= 60), samples[0][1])
        last = samples[-1][1]
        print(f"RSS at 60 s {minute:.1f} MiB, at the end {last:.1f} MiB ({100 * (last - minute) / minute:+.1f} %)")
    finally:
        if play is not None:
            stop(play)
        stop(launch)


if __name__ == "__main__":
    main()
