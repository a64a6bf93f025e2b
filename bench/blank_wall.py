#!/usr/bin/python3
"""A blank wall crossed with and without a gyro: the synthetic room with a blank panel (scene blank_wall),
the camera looking into the room, turning to face the panel alone for WALL seconds (turning +-0.2 rad and
moving +-15 cm), turning back (generate_synthetic_sequence --blank-wall-visit), Kinect-like noise and a
20 ms rolling shutter; a consumer MEMS gyro simulated along the path per seed (simulate_imu: bias up to
0.5 deg/s per axis, learned online). Per run: frames not tracked and degraded, the rotation's error
(worst while facing the wall, and at the end), the position's at the end, ATE.

  bench/blank_wall.py [--wall 10] [--seeds 1,2,3] [--width 640 --height 480] [--folder DIR]

--folder reuses (or keeps) a rendered sequence: rendering 640x480 takes minutes.
"""
import argparse
import math
import os
import subprocess
import sys
import tempfile

from tool_metrics import metrics

HERE = os.path.dirname(os.path.abspath(__file__))
TOOLS = os.path.join(HERE, "..", "devel", "lib", "vocal")
ROOM_BEFORE, TURN = 4.0, 1.0  # BlankWallVisitOptions' defaults: the dwell starts 5 s in


def tool(name, *arguments):
    result = subprocess.run([os.path.join(TOOLS, name), *arguments], capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"blank_wall: {name} failed:\n{result.stdout}{result.stderr}")
    return result


def read_poses(path):
    poses = {}
    with open(path) as lines:
        for line in lines:
            if line.startswith("#") or not line.strip():
                continue
            v = [float(x) for x in line.split()]
            poses[round(v[0], 4)] = (v[1:4], v[4:8])
    return poses


def angle_deg(q, r):
    dot = abs(sum(a * b for a, b in zip(q, r))) / math.sqrt(sum(a * a for a in q) * sum(b * b for b in r))
    return math.degrees(2.0 * math.acos(min(1.0, dot)))


def errors(truth, estimate, dwell):
    stamps = sorted(estimate)
    worst = max(angle_deg(truth[s][1], estimate[s][1]) for s in stamps if dwell[0] <= s <= dwell[1])
    end = stamps[-1]
    position = math.dist(truth[end][0], estimate[end][0])
    return worst, angle_deg(truth[end][1], estimate[end][1]), position


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--wall", type=float, default=10.0)
    parser.add_argument("--seeds", default="1,2,3")
    parser.add_argument("--width", type=int, default=640)
    parser.add_argument("--height", type=int, default=480)
    parser.add_argument("--folder", default="")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as work:
        folder = args.folder or os.path.join(work, "sequence")
        if not os.path.exists(os.path.join(folder, "groundtruth.txt")):
            tool("generate_synthetic_sequence", folder, "--blank-wall-visit", str(args.wall), "--width", str(args.width), "--height",
                 str(args.height), "--kinect-noise", "--rolling-shutter", "0.02", "--quiet")
        truth = read_poses(os.path.join(folder, "groundtruth.txt"))
        start = min(truth)
        dwell = (start + ROOM_BEFORE + TURN, start + ROOM_BEFORE + TURN + args.wall)
        # The camera renders depth and colour at one instant: the default's 5 ms between them is a Kinect's.
        config = os.path.join(work, "synthetic.yaml")
        with open(config, "w") as out:
            out.write("depth_time_offset: 0.0\n")
        print(f"| run | frames not tracked | degraded | rotation error at the wall, worst (deg) | at the end (deg) | position at the end (m) | ATE (m) |")
        print("|---|---|---|---|---|---|---|")
        runs = [("without a gyro", None)] + [(f"gyro, seed {seed}", seed) for seed in args.seeds.split(",")]
        for name, seed in runs:
            command = [folder, "--config", config, "--output", os.path.join(work, "estimate.txt"), "--quiet", "--start-from-ground-truth"]
            if seed is None:
                command.append("--no-imu")
            else:
                imu = os.path.join(work, f"imu_{seed}")
                tool("simulate_imu", os.path.join(folder, "groundtruth.txt"), imu, "--seed", seed)
                command += ["--imu", os.path.join(imu, "imu.txt"), "--imu-extrinsics", os.path.join(imu, "imu_extrinsics.yaml")]
            values = metrics(tool("tum_odometry", *command).stdout)
            worst, end, position = errors(truth, read_poses(os.path.join(work, "estimate.txt")), dwell)
            print(f"| {name} | {values['tracking_failures']:.0f} of {values['frames']:.0f} | {values.get('degraded_frames', 0):.0f} | "
                  f"{worst:.2f} | {end:.2f} | {position:.3f} | {values['ate_rmse_m']:.3f} |", flush=True)


if __name__ == "__main__":
    main()
