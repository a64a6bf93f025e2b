#!/usr/bin/env python3
"""A head and an arm in one session (simulate_calibration_session --arm --head): calibrate_rig with its
defaults, the head's and the arm's joint offsets in one graph, as one markdown table.

The head camera is judged where it matters, in the base frame at each still pose's true head angles read
by noise-free encoders (the chain with the solved offsets times the solved mount, against the true chain
times the true mount): what the held tilt offset and the solved mount trade between them cancels there.
A camera on the post is judged in the base frame; a wrist camera by its mount against R(axis6, d6) * the
true mount (the last joint's offset d6 is taken up by it). Offsets: each branch's first joint, solved
(truth) +- sigma.

usage: /usr/bin/python3 bench/head_arm_sessions.py [--work DIR] [--seeds N] [--poses N]
"""
import argparse
import os
import subprocess
import time

import yaml

from pose_math import chain_pose, matrix, turn, error

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
TOOLS = os.path.join(ROOT, "devel", "lib", "vocal")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--work", default="/tmp/vocal_head_arm_sessions")
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--poses", type=int, default=12)
    args = parser.parse_args()
    print("| setup | seed | head camera in the base frame, worst over the still poses, mm / mrad | main camera, mm / mrad "
          "| shoulder pan offset, mrad | head pan offset, mrad | s |")
    print("|---|---|---|---|---|---|---|")
    for setup in ("eye-in-hand", "eye-to-hand"):
        for seed in range(1, args.seeds + 1):
            folder = os.path.join(args.work, "%s_%d" % (setup, seed))
            if not os.path.exists(os.path.join(folder, "session.bag")):
                subprocess.run([os.path.join(TOOLS, "simulate_calibration_session"), folder, "--" + setup, "--arm", "--head", "--poses",
                                str(args.poses), "--seed", str(seed)], check=True, stdout=subprocess.DEVNULL)
            start = time.time()
            run = subprocess.run([os.path.join(TOOLS, "calibrate_rig"), os.path.join(folder, "rig.yaml"), os.path.join(folder, "session.bag"),
                                  "--quiet", "--output-dir", folder], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
            seconds = time.time() - start
            if run.returncode != 0:
                print("| %s | %d | calibrate_rig failed (%d): %s |" % (setup, seed, run.returncode, run.stdout.strip().splitlines()[-1]))
                continue
            truth = yaml.safe_load(open(os.path.join(folder, "ground_truth.yaml")))
            result = yaml.safe_load(open(os.path.join(folder, "calibration.yaml")))
            rig = yaml.safe_load(open(os.path.join(folder, "rig.yaml")))
            true_offsets = {j["name"]: j["offset"] for j in truth["joints"]}
            solved = {j["name"]: j for j in result["joints"]}
            head = [j for j in rig["joints"] if j["name"].startswith("head_")]
            sensors = {s["name"]: s for s in result["sensors"]}
            mount = sensors["head_camera"]
            true_mount = truth["sensors"]["head_camera"]["pose"]
            worst = (0.0, 0.0)
            for angles in truth["head_angles"]:
                readings = [a - true_offsets[j["name"]] for a, j in zip(angles, head)]
                found = chain_pose(head, [r + solved[j["name"]]["offset"] for r, j in zip(readings, head)]) @ matrix(
                    mount["translation"], mount["rotation"])
                expected = chain_pose(head, angles) @ matrix(true_mount["translation"], true_mount["rotation"])
                e = error(found, expected)
                worst = (max(worst[0], e[0]), max(worst[1], e[1]))
            main_camera = sensors["arm_camera"]
            true_main = truth["sensors"]["arm_camera"]["pose"]
            expected_main = matrix(true_main["translation"], true_main["rotation"])
            if setup == "eye-in-hand":
                last = [j for j in rig["joints"] if j["name"] == "wrist_3_joint"][0]
                expected_main = turn(last["axis"], true_offsets["wrist_3_joint"] - solved["wrist_3_joint"]["offset"]) @ expected_main
            main_error = error(matrix(main_camera["translation"], main_camera["rotation"]), expected_main)

            def offset(name):
                j = solved[name]
                return "%+.2f (%+.2f) +- %.2f" % (1000 * j["offset"], 1000 * true_offsets[name], 1000 * j["offset_stddev"])

            print("| %s | %d | **%.2f / %.2f** | %.2f / %.2f | %s | %s | %.1f |" % (
                setup, seed, worst[0], worst[1], main_error[0], main_error[1], offset("shoulder_pan_joint"), offset("head_pan_joint"), seconds))


if __name__ == "__main__":
    main()
