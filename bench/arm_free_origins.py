#!/usr/bin/env python3
"""An arm whose upper arm is longer than its model says (simulate_calibration_session --arm --link-error M),
calibrated with the model's origins held (the defaults) and with the elbow's origin free
(`free_joint_origins: [elbow_joint]`, --free-origins), beside the same arm with a right model: one markdown table.

What is compared is gauge-free: the camera as the board sees it (eye-in-hand: board <- camera) or the board as
the camera sees it (eye-to-hand: camera <- board), through the arm's joints at 30 configurations the session
never visited (each joint uniformly within the range the session's poses covered), the true kinematics against
the calibrated ones (the model's joints, the solved offsets and origins, at the same readings); the worst of
the 30 in mm / mrad; and the elbow's origin shift along its link (z) against the truth.

usage: /usr/bin/python3 bench/arm_free_origins.py [--work DIR] [--seeds N] [--error M] [--poses N]
"""
import argparse
import math
import os
import subprocess
import time

import numpy as np
import yaml

from pose_math import matrix, turn, error

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
TOOLS = os.path.join(ROOT, "devel", "lib", "vocal")


def rpy_matrix(xyz, rpy):
    """URDF's origin: R = Rz(yaw) Ry(pitch) Rx(roll)."""
    return matrix(xyz, [0, 0, 0, 1]) @ turn([0, 0, 1], rpy[2]) @ turn([0, 1, 0], rpy[1]) @ turn([1, 0, 0], rpy[0])


def forward(origins, axes, angles):
    pose = np.eye(4)
    for origin, axis, angle in zip(origins, axes, angles):
        pose = pose @ origin @ turn(axis, angle)
    return pose


def measure(folder, rng):
    truth = yaml.safe_load(open(os.path.join(folder, "ground_truth.yaml")))
    rig = yaml.safe_load(open(os.path.join(folder, "rig.yaml")))
    result = yaml.safe_load(open(os.path.join(folder, "calibration.yaml")))
    joints = rig["joints"]
    axes = [j["axis"] for j in joints]
    model = [matrix(j["origin"][:3], j["origin"][3:]) for j in joints]
    true_origins = list(model)
    for i, t in enumerate(truth["joints"]):
        if "origin" in t:
            true_origins[i] = matrix(t["origin"]["translation"], t["origin"]["rotation"])
    true_offsets = [t["offset"] for t in truth["joints"]]
    solved_origins = list(model)
    elbow_shift = float("nan")
    for i, j in enumerate(result["joints"]):
        if "origin" in j:
            solved_origins[i] = rpy_matrix(j["origin"]["xyz"], j["origin"]["rpy"])
            if j["name"] == "elbow_joint":
                elbow_shift = 1000 * j["origin"]["correction"][5]
    solved_offsets = [j["offset"] for j in result["joints"]]
    camera = truth["camera"]["pose"]
    true_camera = matrix(camera["translation"], camera["rotation"])
    board = truth["board"]["pose"]
    true_board = matrix(board["translation"], board["rotation"])
    found_camera = matrix(result["sensors"][0]["translation"], result["sensors"][0]["rotation"])
    found_board = matrix(result["target"]["translation"], result["target"]["rotation"])
    in_hand = truth["setup"] == "eye-in-hand"
    visited = np.array(truth["arm_angles"])
    low, high = visited.min(axis=0), visited.max(axis=0)
    worst = (0.0, 0.0)
    for _ in range(30):
        angles = rng.uniform(low, high)
        reading = angles - np.array(true_offsets)
        true_tool = forward(true_origins, axes, angles)
        tool = forward(solved_origins, axes, reading + np.array(solved_offsets))
        if in_hand:  # the camera as the board sees it
            expected = np.linalg.inv(true_board) @ true_tool @ true_camera
            found = np.linalg.inv(found_board) @ tool @ found_camera
        else:  # the board as the camera sees it
            expected = np.linalg.inv(true_camera) @ true_tool @ true_board
            found = np.linalg.inv(found_camera) @ tool @ found_board
        e = error(found, expected)
        worst = (max(worst[0], e[0]), max(worst[1], e[1]))
    return worst, elbow_shift


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--work", default="/tmp/vocal_arm_free_origins")
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--error", type=float, default=0.01)
    parser.add_argument("--poses", type=int, default=12)
    args = parser.parse_args()
    print("| setup | seed | upper arm off by | model's origins held: worst at 30 unvisited configurations, mm / mrad | elbow origin free: worst, mm / mrad | its shift along z, mm | right model, held | s (free) |")
    print("|---|---|---|---|---|---|---|---|")
    rng = np.random.default_rng(7)
    for setup in ("eye-in-hand", "eye-to-hand"):
        for seed in range(1, args.seeds + 1):
            cells = {}
            seconds = 0.0
            for name, extra in (("held", ["--link-error", str(args.error)]),
                                ("free", ["--link-error", str(args.error), "--free-origins", "elbow_joint"]),
                                ("right", [])):
                folder = os.path.join(args.work, "%s_%d_%s_%g_%d" % (setup, seed, name, args.error, args.poses))
                if not os.path.exists(os.path.join(folder, "session.bag")):
                    subprocess.run([os.path.join(TOOLS, "simulate_calibration_session"), folder, "--" + setup, "--arm", "--poses",
                                    str(args.poses), "--seed", str(seed)] + extra, check=True, stdout=subprocess.DEVNULL)
                start = time.time()
                subprocess.run([os.path.join(TOOLS, "calibrate_rig"), os.path.join(folder, "rig.yaml"), os.path.join(folder, "session.bag"),
                                "--quiet", "--publish-uncertain", "--output-dir", folder], stdout=subprocess.DEVNULL, stderr=subprocess.STDOUT)
                if name == "free":
                    seconds = time.time() - start
                cells[name] = measure(folder, np.random.default_rng(rng.integers(1 << 30)))
            print("| %s | %d | %.0f mm | %.2f / %.2f | **%.2f / %.2f** | %+.2f (truth %+.2f) | %.2f / %.2f | %.1f |" % (
                setup, seed, 1000 * args.error, *cells["held"][0], *cells["free"][0], cells["free"][1], 1000 * args.error,
                *cells["right"][0], seconds))


if __name__ == "__main__":
    main()
