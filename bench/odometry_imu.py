#!/usr/bin/python3
"""The odometry with a gyro: each real TUM sequence in ../shared/data/tum with a consumer MEMS IMU simulated
along its own motion capture (simulate_imu: 200 Hz, D435i noise, a bias of up to 0.5 deg/s drawn per run),
tracked with and without it, ATE and RPE per run.

  bench/odometry_imu.py [FOLDER ...] [--seeds 1,2,3] [--weights W,...] [--offsets S,...]

The simulated IMU keeps the motion capture's clock, which runs a few milliseconds off the Kinect's (a
real IMU's offset to its camera is calibrated, e.g. by Kalibr, and given as time_offset): per sequence the
offset in --offsets (seconds, IMU stamp = camera stamp + offset) whose translation RPE is lowest on seed 0
stands for that calibration; the seeds measured are others. Without ../shared the script says so and stops.
"""
import argparse
import glob
import os
import re
import statistics
import subprocess
import sys
import tempfile

from tool_metrics import metrics

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..")
TOOLS = os.path.join(ROOT, "devel", "lib", "vocal")
KEYS = ("ate_rmse_m", "rpe_trans_m_per_s", "rpe_rot_deg_per_s")


def tool(name, *arguments):
    result = subprocess.run([os.path.join(TOOLS, name), *arguments], capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"odometry_imu: {name} failed:\n{result.stdout}{result.stderr}")
    return result


def track(folder, work, imu=None, offset=0.0, weight=None):
    command = [folder, "--output", os.path.join(work, "trajectory.txt"), "--quiet"]
    if imu is None:
        command.append("--no-imu")
    else:
        extrinsics = os.path.join(imu, "extrinsics_used.yaml")
        with open(os.path.join(imu, "imu_extrinsics.yaml")) as source, open(extrinsics, "w") as out:
            out.write(re.sub(r"^time_offset: .*$", f"time_offset: {offset}", source.read(), flags=re.M))
        command += ["--imu", os.path.join(imu, "imu.txt"), "--imu-extrinsics", extrinsics]
        if weight is not None:
            command += ["--imu-weight", str(weight)]
    result = tool("tum_odometry", *command)
    values = metrics(result.stdout)
    return {key: float(values[key]) for key in KEYS}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("folders", nargs="*")
    parser.add_argument("--seeds", default="1,2,3")
    parser.add_argument("--weights", default="", help="imu_weight values (default: the config's)")
    parser.add_argument("--offsets", default="-0.015,-0.0125,-0.01,-0.0075,-0.005,-0.0025,0")
    args = parser.parse_args()
    folders = args.folders or sorted(glob.glob(os.path.join(ROOT, "..", "shared", "data", "tum", "rgbd_dataset_*")))
    if not folders:
        sys.exit("odometry_imu: NO REAL DATA: ../shared/data/tum is missing; nothing measured")
    weights = [float(w) for w in args.weights.split(",")] if args.weights else [None]
    seeds = [int(s) for s in args.seeds.split(",")]
    offsets = [float(o) for o in args.offsets.split(",")]
    print("| sequence | weight | offset (s) | ATE m without / with | RPE m/s without / with | RPE deg/s without / with (lower by) |")
    print("|---|---|---|---|---|---|")
    for folder in folders:
        name = os.path.basename(folder.rstrip("/"))
        with tempfile.TemporaryDirectory() as work:
            without = track(folder, work)
            imus = {}
            for seed in [0] + seeds:
                imus[seed] = os.path.join(work, f"imu_{seed}")
                tool("simulate_imu", os.path.join(folder, "groundtruth.txt"), imus[seed], "--seed", str(seed))
            for weight in weights:
                offset = min(offsets, key=lambda o: track(folder, work, imus[0], o, weight)["rpe_trans_m_per_s"])
                runs = [track(folder, work, imus[seed], offset, weight) for seed in seeds]
                cell = {key: [run[key] for run in runs] for key in KEYS}
                span = lambda key, f: f"{min(cell[key]):{f}}-{max(cell[key]):{f}}"
                lower = 100.0 * (1.0 - statistics.mean(cell["rpe_rot_deg_per_s"]) / without["rpe_rot_deg_per_s"])
                print(f"| {name} | {'config' if weight is None else weight} | {offset:+.4f} | {without['ate_rmse_m']:.4f} / {span('ate_rmse_m', '.4f')} | "
                      f"{without['rpe_trans_m_per_s']:.4f} / {span('rpe_trans_m_per_s', '.4f')} | "
                      f"{without['rpe_rot_deg_per_s']:.3f} / {span('rpe_rot_deg_per_s', '.3f')} ({lower:.0f} %) |", flush=True)


if __name__ == "__main__":
    main()
