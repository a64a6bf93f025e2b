#!/usr/bin/env python3
"""Hand-eye sessions, calibrate_rig with its defaults beside OpenCV's calibrateHandEye on the same poses,
as one markdown table: the camera's error (mm / mrad) against the truth (simulated) or the authors' own
result (real), the arm poses named poor, and the run time.

usage: /usr/bin/python3 bench/hand_eye_sessions.py [--work DIR] [--seeds N]

The real Franka recording comes from ../shared/data/real_rigs (a loud note when it is not there);
simulated sessions (eye-in-hand, eye-to-hand, and eye-to-hand with a lidar and an RGB-D camera beside; with
and without one arm pose reported 5 mm off; seeds 1..N) are generated into --work (default /tmp/vocal_hand_eye_sessions) once and reused.
"""
import argparse
import os
import subprocess
import sys
import time

import yaml

from pose_math import matrix, error

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
TOOLS = os.path.join(ROOT, "devel", "lib", "vocal")
REAL = os.path.join(ROOT, "..", "shared", "data", "real_rigs", "franka_eye_in_hand")
# The recording's README: the authors' result, the camera optical frame in panda_EE.
FRANKA_REFERENCE = ([0.0577, -0.0339, -0.0423], [0.00076, 0.00411, 0.71098, 0.70320])


def calibrate(rig, bag, out):
    os.makedirs(out, exist_ok=True)
    start = time.time()
    run = subprocess.run([os.path.join(TOOLS, "calibrate_rig"), rig, bag, "--quiet", "--output-dir", out],
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    seconds = time.time() - start
    path = os.path.join(out, "calibration.yaml")
    if not os.path.exists(path):
        sys.exit("calibrate_rig failed on %s:\n%s" % (bag, run.stdout))
    return yaml.safe_load(open(path)), seconds


def row(name, result, truth, seconds, others=None):
    """`others`: the truth of the rig's other sensors by name, printed after the camera's cell."""
    camera = result["sensors"][0]
    ours = error(matrix(camera["translation"], camera["rotation"]), truth)
    closed = {c["method"]: error(matrix(c["translation"], c["rotation"]), truth) for c in result["closed_forms"]}
    cells = " | ".join("%.2f / %.2f" % closed[m] for m in ("Tsai", "Park", "Horaud", "Andreff", "Daniilidis"))
    poor = ",".join(str(p) for p in result["poor_arm_poses"]) or "-"
    beside = ""
    for sensor in result["sensors"][1:]:
        pose = others[sensor["name"]]["pose"]
        e = error(matrix(sensor["translation"], sensor["rotation"]), matrix(pose["translation"], pose["rotation"]))
        beside += "; %s %.2f / %.2f" % (sensor["name"], e[0], e[1])
    published = all(s["published"] for s in result["sensors"])
    print("| %s | **%.2f / %.2f**%s | %s | %s | %s | %.1f |" % (
        name, ours[0], ours[1], beside, cells, poor, "yes" if published else "no", seconds), flush=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--work", default="/tmp/vocal_hand_eye_sessions")
    parser.add_argument("--seeds", type=int, default=3)
    args = parser.parse_args()
    print("| session | vocal mm / mrad (the sensors beside) | Tsai | Park | Horaud | Andreff | Daniilidis | poor arm poses | published | s |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    if os.path.exists(os.path.join(REAL, "session.bag")):
        result, seconds = calibrate(os.path.join(ROOT, "config", "franka_eye_in_hand_rig.yaml"), os.path.join(REAL, "session.bag"),
                                    os.path.join(args.work, "franka"))
        row("real Franka wrist camera (vs the authors' result)", result, matrix(*FRANKA_REFERENCE), seconds)
    else:
        print("*** real Franka recording not found at %s: its row is SKIPPED ***" % os.path.abspath(REAL))
    for setup, beside in (("eye-in-hand", False), ("eye-to-hand", False), ("eye-to-hand", True)):
        for poor in (0, 5):
            for seed in range(1, args.seeds + 1):
                folder = os.path.join(args.work, "%s%s_poor%d_seed%d" % (setup, "_beside" if beside else "", poor, seed))
                if not os.path.exists(os.path.join(folder, "session.bag")):
                    command = [os.path.join(TOOLS, "simulate_calibration_session"), folder, "--" + setup, "--seed", str(seed)]
                    if poor:
                        command += ["--poor-pose", str(poor)]
                    if beside:
                        command += ["--beside"]
                    subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
                truth = yaml.safe_load(open(os.path.join(folder, "ground_truth.yaml")))
                result, seconds = calibrate(os.path.join(folder, "rig.yaml"), os.path.join(folder, "session.bag"), folder)
                name = "simulated %s%s, seed %d%s" % (setup, " + lidar + RGB-D + 2D laser" if beside else "", seed,
                                                      ", pose %d reported 5 mm off" % poor if poor else "")
                camera = truth["camera"]["pose"]
                row(name, result, matrix(camera["translation"], camera["rotation"]), seconds, truth.get("sensors"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
