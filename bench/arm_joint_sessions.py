#!/usr/bin/env python3
"""A camera on a 6-joint arm, the tool from the arm's joint states (simulate_calibration_session --arm):
calibrate_rig with its defaults (the joints' zero offsets in the graph) beside OpenCV's calibrateHandEye on
the tool poses the uncalibrated readings give (what /tf says), as one markdown table.

Each camera is compared with where the truth puts it in the frames the calibration can fix: the first
and the last joints' offsets are not separable from the poses on either side (held), so a camera on the
tool (or the board in the gripper) is expected at R(axis6, d6) * its mount, a camera fixed in the base at
Rz(-d1) * its pose (d: the true offsets). Offsets: the mean |solved - true| over the solved joints, with their mean sigma.

usage: /usr/bin/python3 bench/arm_joint_sessions.py [--work DIR] [--seeds N]
"""
import argparse
import os
import subprocess
import time

import numpy as np
import yaml

from pose_math import matrix, turn, error

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
TOOLS = os.path.join(ROOT, "devel", "lib", "vocal")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--work", default="/tmp/vocal_arm_joint_sessions")
    parser.add_argument("--seeds", type=int, default=3)
    args = parser.parse_args()
    print("| setup | reading noise, mrad | seed | vocal camera, mm / mrad | Tsai | Park | Daniilidis | vocal board on the tool | offsets: mean error (mean sigma), mrad | s |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for setup in ("eye-in-hand", "eye-to-hand"):
        for noise in (0.0002, 0.001):
            for seed in range(1, args.seeds + 1):
                folder = os.path.join(args.work, "%s_%g_%d" % (setup, noise, seed))
                if not os.path.exists(os.path.join(folder, "session.bag")):
                    subprocess.run([os.path.join(TOOLS, "simulate_calibration_session"), folder, "--" + setup, "--arm", "--joint-noise",
                                    str(noise), "--seed", str(seed)], check=True, stdout=subprocess.DEVNULL)
                start = time.time()
                subprocess.run([os.path.join(TOOLS, "calibrate_rig"), os.path.join(folder, "rig.yaml"), os.path.join(folder, "session.bag"),
                                "--quiet", "--output-dir", folder], stdout=subprocess.DEVNULL, stderr=subprocess.STDOUT)
                seconds = time.time() - start
                truth = yaml.safe_load(open(os.path.join(folder, "ground_truth.yaml")))
                result = yaml.safe_load(open(os.path.join(folder, "calibration.yaml")))
                rig = yaml.safe_load(open(os.path.join(folder, "rig.yaml")))
                offsets = [j["offset"] for j in truth["joints"]]
                camera = truth["camera"]["pose"]
                true_camera = matrix(camera["translation"], camera["rotation"])
                if setup == "eye-in-hand":
                    expected = turn(rig["joints"][-1]["axis"], offsets[-1]) @ true_camera
                else:
                    expected = turn(rig["joints"][0]["axis"], -offsets[0]) @ true_camera
                found = result["sensors"][0]
                cells = ["%.2f / %.2f" % error(matrix(found["translation"], found["rotation"]), expected)]
                closed = {c["method"]: c for c in result["closed_forms"]}
                for method in ("Tsai", "Park", "Daniilidis"):
                    c = closed[method]
                    cells.append("%.2f / %.2f" % error(matrix(c["translation"], c["rotation"]), expected))
                board = "-"
                if setup == "eye-to-hand":
                    b = truth["board"]["pose"]
                    expected_board = turn(rig["joints"][-1]["axis"], offsets[-1]) @ matrix(b["translation"], b["rotation"])
                    board = "%.2f / %.2f" % error(matrix(result["target"]["translation"], result["target"]["rotation"]), expected_board)
                solved = [(j, t) for j, t in zip(result["joints"], offsets) if j["solved"]]
                mean_error = np.mean([abs(j["offset"] - t) for j, t in solved]) * 1000
                mean_sigma = np.mean([j["offset_stddev"] for j, _ in solved]) * 1000
                print("| %s | %.1f | %d | **%s** | %s | %s | %s | %s | %.2f (%.2f) | %.1f |" % (
                    setup, 1000 * noise, seed, cells[0], cells[1], cells[2], cells[3], board, mean_error, mean_sigma, seconds))


if __name__ == "__main__":
    main()
