#!/usr/bin/env python3
"""Camera-IMU calibration through the tools, as a user runs them: per seed, simulate_calibration_session
--waved-imu writes a waved session (rendered images, sensor_msgs/Imu), calibrate_rig calibrates it; the
camera in the IMU (Kalibr's camchain-imucam.yaml) and the time offset against ground_truth.yaml, and
calibrate_rig's wall time. Usage: camera_imu_sessions.py [--seconds S] [--seeds N] [--keep DIR]"""
import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np
import yaml

HERE = os.path.dirname(os.path.abspath(__file__))
TOOLS = os.path.join(HERE, "..", "devel", "lib", "vocal")
OFFSETS = [0.005, -0.012, 0.02, 0.015, -0.008]


def pose_matrix(values):
    x, y, z, qx, qy, qz, qw = values
    q = np.array([qw, qx, qy, qz]) / np.linalg.norm([qw, qx, qy, qz])
    w, a, b, c = q
    r = np.array([[1 - 2 * (b * b + c * c), 2 * (a * b - c * w), 2 * (a * c + b * w)],
                  [2 * (a * b + c * w), 1 - 2 * (a * a + c * c), 2 * (b * c - a * w)],
                  [2 * (a * c - b * w), 2 * (b * c + a * w), 1 - 2 * (a * a + b * b)]])
    m = np.eye(4)
    m[:3, :3], m[:3, 3] = r, [x, y, z]
    return m


def angle(r):
    return float(np.arccos(np.clip((np.trace(r) - 1) / 2, -1, 1)))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--seconds", type=float, default=60)
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--keep", help="write the sessions here (default: a temporary folder, removed)")
    args = parser.parse_args()
    root = args.keep or tempfile.mkdtemp(prefix="camera_imu_")
    print("| seed | offset ms | frames with the board | camera in IMU error mm / mrad | offset error ms | calibrate_rig s |")
    print("|---|---|---|---|---|---|")
    for seed in range(1, args.seeds + 1):
        folder = os.path.join(root, "seed%d" % seed)
        offset = OFFSETS[(seed - 1) % len(OFFSETS)]
        subprocess.run([os.path.join(TOOLS, "simulate_calibration_session"), folder, "--waved-imu", "--seconds", str(args.seconds),
                        "--seed", str(seed), "--time-offset", str(offset)], check=True, stdout=subprocess.DEVNULL)
        start = time.time()
        run = subprocess.run([os.path.join(TOOLS, "calibrate_rig"), os.path.join(folder, "rig.yaml"), os.path.join(folder, "session.bag"),
                              "--quiet", "--output-dir", folder], capture_output=True, text=True)
        seconds = time.time() - start
        if run.returncode != 0:
            print("| %d | %.1f | calibrate_rig exit %d: %s |" % (seed, offset * 1000, run.returncode, run.stdout.strip().splitlines()[-1]))
            continue
        truth = yaml.safe_load(open(os.path.join(folder, "ground_truth.yaml")))
        chain = yaml.safe_load(open(os.path.join(folder, "camchain-imucam.yaml")))["cam0"]
        error = np.array(chain["T_cam_imu"]) @ pose_matrix(truth["camera_in_imu"])
        frames = [line for line in run.stdout.splitlines() if "the board in" in line][0]
        found = frames.split("the board in ")[1].split(" frames")[0]
        print("| %d | %.1f | %s | %.3f / %.3f | %.3f | %.1f |" % (
            seed, offset * 1000, found, 1000 * np.linalg.norm(error[:3, 3]), 1000 * angle(error[:3, :3]),
            1000 * (chain["timeshift_cam_imu"] - truth["time_offset"]), seconds))
        sys.stdout.flush()
    if not args.keep:
        shutil.rmtree(root)


if __name__ == "__main__":
    main()
