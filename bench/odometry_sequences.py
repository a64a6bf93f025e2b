#!/usr/bin/env python3
"""Every real TUM sequence in ../shared/data/tum, tum_odometry with its defaults and the alternatives that
matter, as one markdown table: RPE (m/s, deg/s over 1 s), ATE RMSE (m), frames per second of the
estimator, keyframes; then whether the default holds against frame-to-frame tracking on every sequence.

usage: /usr/bin/python3 bench/odometry_sequences.py [--data DIR] [--only NAME[,NAME...]] [--frames N]
                                                   [--starts K] [--configs LABEL[,LABEL...]] [--no-synthetic]

A default changes only when this table says so on every sequence (docs/benchmarks.md). Beside the real
ones it runs a synthetic untextured room through a Kinect's noise (generate_synthetic_sequence --scene
bare_room --kinect-noise --rolling-shutter 0.02, 90 frames at 320x240, written to /tmp once): the three
real sequences are all textured, and a setting that only textured frames like must show what it does
where the creases are all the photometric term has (unless --no-synthetic). With --starts K
every figure is the mean over K runs started 10 frames apart (frame 0, 10, ...): on sequences of a few
seconds one run's keyframe choices alone move RPE by several per cent, more than most settings do.
Frames per second count the estimator only (image loading excluded) on whatever this machine offers:
run it on an otherwise idle machine.
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
    ("--brightness fixed", ["--brightness", "fixed"], {}),
    ("rolling_shutter_readout 0", [], {"rolling_shutter_readout": "0.0"}),
    ("rolling_shutter_readout 0.01", [], {"rolling_shutter_readout": "0.01"}),
    ("rolling_shutter_readout 0.03", [], {"rolling_shutter_readout": "0.03"}),
    ("undistort_lens false", [], {"undistort_lens": "false"}),
    ("depth_time_offset 0", [], {"depth_time_offset": "0.0"}),
    ("depth_time_offset -0.0075", [], {"depth_time_offset": "-0.0075"}),
    ("depth_time_offset -0.01", [], {"depth_time_offset": "-0.01"}),
    ("none of the camera models (before)", ["--brightness", "fixed"],
     {"rolling_shutter_readout": "0.0", "undistort_lens": "false", "depth_time_offset": "0.0"}),
    ("keyframe_max_rotation_deg 8", [], {"keyframe_max_rotation_deg": "8.0"}),
    ("keyframe_max_rotation_deg 5", [], {"keyframe_max_rotation_deg": "5.0"}),
    ("keyframe_max_residual_growth 10 (overlap and distance alone)", [], {"keyframe_max_residual_growth": "10.0"}),
    ("keyframe_max_residual_growth 1.2", [], {"keyframe_max_residual_growth": "1.2"}),
    ("keyframe_min_overlap 0.8", [], {"keyframe_min_overlap": "0.8"}),
    ("--features always", ["--features", "always"], {}),
    ("--features off", ["--features", "off"], {}),
    ("--reference frame --features always", ["--reference", "frame", "--features", "always"], {}),
    ("convergence 1e-4", [], {"convergence_translation": "1.0e-4", "convergence_rotation": "1.0e-4"}),
    ("finest_convergence_factor 1 (the default before 2026-11-26)", [], {"finest_convergence_factor": "1.0"}),
    ("finest_convergence_factor 2", [], {"finest_convergence_factor": "2.0"}),
    ("finest_convergence_factor 5", [], {"finest_convergence_factor": "5.0"}),
    # The local window: each new keyframe solved against 1 or 2 earlier ones, 4 refined together.
    ("local window 4 keyframes 1 link", [], {"local_window_keyframes": "4", "local_window_links": "1"}),
    ("local window 4 keyframes 2 links", [], {"local_window_keyframes": "4", "local_window_links": "2"}),
    ("local window 6 keyframes 2 links", [], {"local_window_keyframes": "6", "local_window_links": "2"}),
    # Fewer steps at full size: the coarse levels converge; one or two steps refine.
    ("iterations 2 5 4", [], {"iterations": "[2, 5, 4]"}),
    ("iterations 1 5 4", [], {"iterations": "[1, 5, 4]"}),
    ("iterations 1 5 4 --reference frame", ["--reference", "frame"], {"iterations": "[1, 5, 4]"}),
    ("iterations 1 8 4", [], {"iterations": "[1, 8, 4]"}),
    ("--rgb-weight 3 (the default before 2026-11-26)", ["--rgb-weight", "3"], {}),
    ("--rgb-weight 10", ["--rgb-weight", "10"], {}),
    ("--rgb-weight 15", ["--rgb-weight", "15"], {}),
    ("--rgb-weight 25", ["--rgb-weight", "25"], {}),
    ("--rgb-weight 30", ["--rgb-weight", "30"], {}),
    ("keyframe_after_unconverged", [], {"keyframe_after_unconverged": "true"}),
    # ICP pairs weighted by a Kinect's depth noise as measured (bench/depth_noise.py).
    ("depth_noise_quadratic 0.001", [], {"depth_noise_quadratic": "0.001"}),
    ("depth_noise_quadratic 0.001 floor 0.002", [], {"depth_noise_quadratic": "0.001", "depth_noise_floor": "0.002"}),
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


def run(folder, arguments, settings, frames, starts):
    """The metrics of one configuration on one sequence, averaged over `starts` start frames."""
    config = config_with(settings)
    if config:
        arguments = ["--config", config] + arguments
    output = os.path.join("/tmp", "vocal_odometry_sequences_" + os.path.basename(folder) + ".txt")
    runs = []
    for start in range(starts):
        command = [os.path.join(TOOLS, "tum_odometry"), folder, "--output", output, "--quiet",
                   "--skip", str(10 * start)] + arguments
        if frames:
            command += ["--frames", str(frames)]
        result = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        if result.returncode != 0:
            sys.exit("tum_odometry failed on %s %s:\n%s" % (folder, " ".join(arguments), result.stdout))
        runs.append(metrics(result.stdout))
    return {key: sum(m.get(key, 0) for m in runs) / len(runs) for key in runs[0]}


def synthetic_untextured_room():
    """A TUM-layout folder of the untextured room through a Kinect's noise, generated once."""
    folder = os.path.join("/tmp", "vocal_odometry_sequences_synthetic_bare_room")
    if not os.path.exists(os.path.join(folder, "groundtruth.txt")):
        subprocess.run([os.path.join(TOOLS, "generate_synthetic_sequence"), folder, "--scene", "bare_room", "--frames", "90",
                        "--width", "320", "--height", "240", "--kinect-noise", "--rolling-shutter", "0.02", "--quiet"],
                       check=True)
    return folder


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--data", default=DATA, help="folder of TUM sequences (default ../shared/data/tum)")
    parser.add_argument("--only", default="", help="comma-separated substrings of the sequences' names")
    parser.add_argument("--frames", type=int, default=0, help="only the first N frames of each")
    parser.add_argument("--starts", type=int, default=1, help="mean over K runs started 10 frames apart")
    parser.add_argument("--configs", default="", help="comma-separated labels to run (default: all)")
    parser.add_argument("--no-synthetic", action="store_true", help="without the synthetic untextured room")
    args = parser.parse_args()
    configurations = CONFIGURATIONS
    if args.configs:
        wanted = args.configs.split(",")
        unknown = [label for label in wanted if label not in [c[0] for c in CONFIGURATIONS]]
        if unknown:
            sys.exit("bench/odometry_sequences.py: unknown configuration %s; the labels are:\n  %s" %
                     (", ".join("'%s'" % label for label in unknown), "\n  ".join(c[0] for c in CONFIGURATIONS)))
        configurations = [c for c in CONFIGURATIONS if c[0] in wanted or c[0] in ("default", "--reference frame")]
    folders = sorted(f for f in glob.glob(os.path.join(args.data, "rgbd_dataset_*")) if os.path.isdir(f))
    if not folders:
        print("*** no TUM sequences found in %s: only the synthetic room is measured ***" % os.path.abspath(args.data))
    if args.only:
        folders = [f for f in folders if any(name in os.path.basename(f) for name in args.only.split(","))]
    if not args.no_synthetic and (not args.only or any(name in "synthetic_bare_room" for name in args.only.split(","))):
        folders.append(synthetic_untextured_room())
    if not folders:
        print("*** no sequence left to measure ***")
        return 1
    print("| sequence | configuration | RPE m/s | RPE deg/s | ATE m | fps | keyframes |")
    print("|---|---|---|---|---|---|---|")
    verdicts = []
    for folder in folders:
        name = os.path.basename(folder).replace("rgbd_dataset_", "").replace("vocal_odometry_sequences_", "")
        results = {}
        for label, arguments, settings in configurations:
            m = run(folder, arguments, settings, args.frames, args.starts)
            results[label] = m
            print("| %s | %s | %.4f | %.3f | %.4f | %.1f | %.0f |" % (
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
