#!/usr/bin/env python3
"""Pan-tilt sessions (simulate_calibration_session --pan-tilt): an RGB-D camera on a pan-tilt head before a
fixed lidar (the reference) and 2D laser, the head's joints on /joint_states at 200 Hz (12-bit encoders, 1
mrad of backlash, zero offsets drawn from +-0.03 rad). calibrate_rig with its defaults on three rig
descriptions of each recording, as one markdown table:

- known mount: the camera's mount on the tilt link given (pose_known: true), both joint offsets solved;
- free mount: the mount an unknown too (the tilt's offset is then the mount's to take up: held);
- rigid: the joints ignored, the camera described as if fixed in base_link.

Per row: each joint offset's error (mrad) and sigma, the camera's worst error (mm / mrad) in base_link over
a grid of head positions (pan -0.4..0.4, tilt -0.3..0.3 rad, readings as the encoders give them) against
the truth, the 2D laser's error (with --head-laser, the laser on the head's tilt link too: its worst over
the same grid), whether the camera was published, and the run time.

usage: /usr/bin/python3 bench/pan_tilt_sessions.py [--work DIR] [--seeds N] [--poses N] [--head-laser]
"""
import argparse
import os
import subprocess
import time

import yaml

from pose_math import chain_pose, matrix, error

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
TOOLS = os.path.join(ROOT, "devel", "lib", "vocal")


def head_pose(joints, offsets, readings, mount):
    """base_link <- camera with the joints (revolute, in order) at readings + offsets."""
    return chain_pose(joints, [reading + offset for offset, reading in zip(offsets, readings)]) @ mount


def worst_over_grid(grid, joints, offsets, true_offsets, found, true_mount, rigid):
    """A head sensor's worst error (mm, mrad) over the head positions of `grid`: where the result puts it
    (fixed where `rigid`) against the truth."""
    worst = (0.0, 0.0)
    for readings in grid:
        pose = found if rigid else head_pose(joints, offsets, readings, found)
        e = error(pose, head_pose(joints, true_offsets, readings, true_mount))
        worst = (max(worst[0], e[0]), max(worst[1], e[1]))
    return worst


def simulate(folder, seed, poses, head_laser):
    if not os.path.exists(os.path.join(folder, "session.bag")):
        subprocess.run([os.path.join(TOOLS, "simulate_calibration_session"), folder, "--pan-tilt", "--pose-known", "--poses", str(poses),
                        "--seed", str(seed)] + (["--head-laser"] if head_laser else []), check=True, stdout=subprocess.DEVNULL)
    rig = open(os.path.join(folder, "rig.yaml")).read()
    free = rig.replace(", pose_known: true", "")
    free = free[:free.rfind(",\n     pose:")] + "}\n"
    rigid = free.replace(", parent: head_tilt_link", "")
    for name, text in (("free.yaml", free), ("rigid.yaml", rigid)):
        open(os.path.join(folder, name), "w").write(text)


def calibrate(folder, rig, out):
    """The result YAML (None when calibrate_rig refused) and its last line, and the run time."""
    path = os.path.join(folder, out, "calibration.yaml")
    os.makedirs(os.path.dirname(path), exist_ok=True)
    if os.path.exists(path):
        os.remove(path)
    start = time.time()
    run = subprocess.run([os.path.join(TOOLS, "calibrate_rig"), os.path.join(folder, rig), os.path.join(folder, "session.bag"), "--quiet",
                          "--output-dir", os.path.join(folder, out)], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    result = yaml.safe_load(open(path)) if os.path.exists(path) else None
    return result, run.stdout.strip().splitlines()[-1], time.time() - start


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--work", default="/tmp/vocal_pan_tilt_sessions")
    parser.add_argument("--seeds", type=int, default=6)
    parser.add_argument("--poses", type=int, default=16)
    parser.add_argument("--head-laser", action="store_true", help="the 2D laser on the head's tilt link too")
    args = parser.parse_args()
    grid = [(p, t) for p in (-0.4, 0.0, 0.4) for t in (-0.3, 0.0, 0.3)]
    print("| seed | rig | pan offset error (sigma), mrad | tilt offset error (sigma), mrad | camera worst over the head's range, mm / mrad "
          "| laser%s, mm / mrad | camera published | time, s |" % (" worst over the head's range" if args.head_laser else ""))
    print("|---|---|---|---|---|---|---|---|")
    for seed in range(1, args.seeds + 1):
        folder = os.path.join(args.work, "seed%d" % seed)
        simulate(folder, seed, args.poses, args.head_laser)
        truth = yaml.safe_load(open(os.path.join(folder, "ground_truth.yaml")))
        joints = truth["joints"]
        true_offsets = [j["offset"] for j in joints]
        cam = truth["sensors"][2]["pose"]
        true_mount = matrix(cam[:3], cam[3:])
        laser_truth = matrix(truth["sensors"][1]["pose"][:3], truth["sensors"][1]["pose"][3:])
        for rig, label in (("rig.yaml", "known mount"), ("free.yaml", "free mount"), ("rigid.yaml", "rigid (joints ignored)")):
            result, last, seconds = calibrate(folder, rig, label.split()[0])
            if result is None:
                print("| %d | %s | - | - | refused: %s | - | no | %.1f |" % (seed, label, last.replace("|", "/")[:160], seconds))
                continue
            camera = result["sensors"][2]
            found = matrix(camera["translation"], camera["rotation"])
            solved = {j["name"]: j for j in result.get("joints", [])}
            cells = []
            offsets = []
            for joint, true_offset in zip(joints, true_offsets):
                j = solved.get(joint["name"])
                if j is None:
                    cells.append("-")
                    offsets.append(0.0)
                    continue
                offsets.append(j["offset"])
                cells.append(("%+.2f (%.2f)" % (1000 * (j["offset"] - true_offset), 1000 * j["offset_stddev"])) if j["solved"] else "held")
            rigid = rig == "rigid.yaml"
            worst = worst_over_grid(grid, joints, offsets, true_offsets, found, true_mount, rigid)
            laser = result["sensors"][1]
            laser_found = matrix(laser["translation"], laser["rotation"])
            laser_error = (worst_over_grid(grid, joints, offsets, true_offsets, laser_found, laser_truth, rigid) if args.head_laser
                           else error(laser_found, laser_truth))
            print("| %d | %s | %s | %s | %.2f / %.2f | %.2f / %.2f | %s | %.1f |" % (
                seed, label, cells[0], cells[1], worst[0], worst[1], laser_error[0], laser_error[1],
                "yes" if camera.get("published", True) else "no", seconds))


if __name__ == "__main__":
    main()
