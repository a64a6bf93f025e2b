#!/usr/bin/env python3
"""Every real TUM sequence in ../shared/data/tum, tum_odometry with its defaults and the alternatives that
matter, as one markdown table: RPE (m/s, deg/s over 1 s), ATE RMSE (m), frames per second of the
estimator, keyframes; then whether the default holds against frame-to-frame tracking on every sequence.

usage: /usr/bin/python3 bench/odometry_sequences.py [--data DIR] [--only NAME[,NAME...]] [--frames N]

A default changes only when this table says so on every sequence (docs/benchmarks.md). Frames per
second count the estimator only (image loading excluded) on whatever this machine offers: run it on an
otherwise idle machine.
"""
import argparse
import glob
import os
import subprocess
import sys

from tool_metrics import metrics

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
TOOLS = os.path.join(ROOT, "devel", "lib", "vocal")
DATA = os.path.join(ROOT, "..", "shared", "data", "tum")

# (label, tum_odometry arguments, settings changed in a copy of config/odometry.yaml)
CONFIGURATIONS = [
    ("default", [], {}),
    ("--reference frame", ["--reference", "frame"], {}),
    ("--features always", ["--features", "always"], {}),
    ("--features off", ["--features", "off"], {}),
    ("--reference frame --features always", ["--reference", "frame", "--features", "always"], {}),
    ("convergence 1e-4", [], {"convergence_translation": "1.0e-4", "convergence_rotation": "1.0e-4"}),
    ("--rgb-weight 1", ["--rgb-weight", "1"], {}),
    ("--rgb-weight 10", ["--rgb-weight", "10"], {}),
]


def config_with(settings):
    """A copy of config/odometry.yaml with `settings` (key: value text) replaced; None for none."""
    if not settings:
        return None
    lines = []
    for line in open(os.path.join(ROOT, "config", "odometry.yaml")):
        key = line.split(":")[0].strip()
        lines.append("%s: %s\n" % (key, settings[key]) if key in settings else line)
    path = os.path.join("/tmp", "vocal_odometry_sequences_config.yaml")
    with open(path, "w") as f:
        f.writelines(lines)
    return path


def run(folder, arguments, settings, frames):
    config = config_with(settings)
    if config:
        arguments = ["--config", config] + arguments
    output = os.path.join("/tmp", "vocal_odometry_sequences_" + os.path.basename(folder) + ".txt")
    command = [os.path.join(TOOLS, "tum_odometry"), folder, "--output", output, "--quiet"] + arguments
    if frames:
        command += ["--frames", str(frames)]
    result = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if result.returncode != 0:
        sys.exit("tum_odometry failed on %s %s:\n%s" % (folder, " ".join(arguments), result.stdout))
    return metrics(result.stdout)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--data", default=DATA, help="folder of TUM sequences (default ../shared/data/tum)")
    parser.add_argument("--only", default="", help="comma-separated substrings of the sequences' names")
    parser.add_argument("--frames", type=int, default=0, help="only the first N frames of each")
    args = parser.parse_args()
    folders = sorted(f for f in glob.glob(os.path.join(args.data, "rgbd_dataset_*")) if os.path.isdir(f))
    if args.only:
        folders = [f for f in folders if any(name in os.path.basename(f) for name in args.only.split(","))]
    if not folders:
        print("*** no TUM sequences found in %s: nothing measured ***" % os.path.abspath(args.data))
        return 1
    print("| sequence | configuration | RPE m/s | RPE deg/s | ATE m | fps | keyframes |")
    print("|---|---|---|---|---|---|---|")
    verdicts = []
    for folder in folders:
        name = os.path.basename(folder).replace("rgbd_dataset_", "")
        results = {}
        for label, arguments, settings in CONFIGURATIONS:
            m = run(folder, arguments, settings, args.frames)
            results[label] = m
            print("| %s | %s | %.4f | %.3f | %.4f | %.1f | %d |" % (
                name, label, m["rpe_trans_m_per_s"], m["rpe_rot_deg_per_s"], m["ate_rmse_m"], m["frames_per_second"],
                m.get("keyframes", 0)), flush=True)
        default, frame = results["default"]["rpe_trans_m_per_s"], results["--reference frame"]["rpe_trans_m_per_s"]
        verdicts.append("%s: default RPE %.4f vs frame to frame %.4f (%+.1f %%): %s" % (
            name, default, frame, 100.0 * (default / frame - 1.0), "holds" if default <= 1.01 * frame else "WORSE by more than 1 %"))
    print()
    for verdict in verdicts:
        print(verdict)
    return 0


if __name__ == "__main__":
    sys.exit(main())
