#!/usr/bin/python3
"""The odometry's rate when other processes share the CPU: tum_odometry on the same frames idle, idle on one
thread, and with 1 and 2 CPU-bound processes beside it (busy loops this script starts and stops itself),
printing frames per second, the per-stage means and the RPE of each run.

  bench/odometry_contention.py [FOLDER ...] [--frames N] [--runs R] [--busy 0,1,2] [--threads T] [--config FILE]

Folders default to the real TUM sequences in ../shared/data/tum (said loudly when they are missing: then a
synthetic room rendered by generate_synthetic_sequence is used). --threads is passed to tum_odometry
(0, the default: every core the process may use). Each cell is the median of --runs runs.
"""
import argparse
import glob
import os
import re
import statistics
import subprocess
import sys
import tempfile

from cpu_burners import busy_processes
from tool_metrics import metrics

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..")
TOOLS = os.path.join(ROOT, "devel", "lib", "vocal")


def run_tum_odometry(folder, frames, threads, config, busy):
    with tempfile.TemporaryDirectory() as work, busy_processes(busy):
        command = [os.path.join(TOOLS, "tum_odometry"), folder, "--output", os.path.join(work, "trajectory.txt"),
                   "--frames", str(frames), "--quiet", "--threads", str(threads)]
        if config:
            command += ["--config", config]
        result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"odometry_contention: tum_odometry failed on {folder}:\n{result.stdout}{result.stderr}")
    backend = re.search(r"backend (.+?);", result.stderr)
    return metrics(result.stdout), backend.group(1) if backend else "backend not said"


def default_folders():
    real = sorted(glob.glob(os.path.join(ROOT, "..", "shared", "data", "tum", "rgbd_dataset_*")))
    if real:
        return real
    print("odometry_contention: NOTE ../shared/data/tum is missing: measuring a synthetic room instead of real frames",
          file=sys.stderr)
    folder = os.path.join(tempfile.gettempdir(), "vocal_contention_room")
    if not os.path.exists(os.path.join(folder, "associations.txt")):
        subprocess.run([os.path.join(TOOLS, "generate_synthetic_sequence"), folder, "--frames", "120", "--width", "640",
                        "--height", "480", "--kinect-noise"], check=True, capture_output=True)
    return [folder]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("folders", nargs="*")
    parser.add_argument("--frames", type=int, default=200)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--busy", default="0,1,2", help="numbers of busy processes beside it, comma-separated")
    parser.add_argument("--threads", type=int, default=0, help="tum_odometry --threads (0: every core)")
    parser.add_argument("--config", help="odometry settings (default: the built-in defaults)")
    args = parser.parse_args()
    folders = args.folders or default_folders()
    cells = [("idle", args.threads, 0), ("idle, 1 thread", 1, 0)]
    cells += [(f"{n} busy process" + ("es" if n > 1 else ""), args.threads, n) for n in map(int, args.busy.split(",")) if n > 0]
    print(f"machine: {os.cpu_count()} CPUs ({os.sched_getaffinity(0).__len__()} usable); {args.frames} frames, median of {args.runs} runs")
    header = f"| sequence | {' | '.join(name for name, _, _ in cells)} |"
    rows, details = [], []
    for folder in folders:
        name = os.path.basename(os.path.normpath(folder))
        fps_cells = []
        for label, threads, busy in cells:
            runs = [run_tum_odometry(folder, args.frames, threads, args.config, busy) for _ in range(args.runs)]
            fps = [m.get("frames_per_second", float("nan")) for m, _ in runs]
            median = statistics.median(fps)
            chosen = min(runs, key=lambda r: abs(r[0].get("frames_per_second", 0) - median))[0]
            fps_cells.append(f"{median:.1f}")
            details.append(f"{name}, {label}: {median:.1f} fps (runs {', '.join(f'{f:.1f}' for f in fps)}), "
                           f"preprocess {chosen.get('preprocess_ms', float('nan')):.2f} ms, solve {chosen.get('solve_ms', float('nan')):.2f} ms, "
                           f"RPE {chosen.get('rpe_trans_m_per_s', float('nan')):.4f} m/s; {runs[0][1].strip()}")
            print(details[-1], flush=True)
        rows.append(f"| {name} | {' | '.join(fps_cells)} |")
    print()
    print(header)
    print("|" + "---|" * (len(cells) + 1))
    for row in rows:
        print(row)


if __name__ == "__main__":
    main()
