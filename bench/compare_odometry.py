#!/usr/bin/python3
"""Runs vocal, OpenCV's RgbdICPOdometry (rgbd module) and Open3D's RGB-D odometry (hybrid term) on the same
TUM-layout frames and prints accuracy and speed side by side.

  bench/compare_odometry.py TUM_FOLDER [--frames N] [--vocal-args "..."]

OpenCV and Open3D run frame to frame with a 3-level pyramid and the reference iterations (10/5/4 from
fine to coarse), vocal with its defaults (3 levels, keyframes, the same iterations); all with the same
intrinsics, depth range and depth-difference threshold, everything else at each library's defaults.
Frames per second count the estimator only (image loading excluded), on whatever this machine offers
(each uses the cores it uses by default). Accuracy comes from vocal's evaluate_trajectory for every
trajectory. A library that is not installed is said so and left out.
"""
import argparse
import os
import re
import subprocess
import sys
import time

import numpy as np

from tool_metrics import metrics

try:
    import open3d as o3d
except ImportError:
    o3d = None
try:
    import cv2
except ImportError:
    cv2 = None

HERE = os.path.dirname(os.path.abspath(__file__))
TOOLS = os.path.join(HERE, "..", "devel", "lib", "vocal")
# vocal's reference values (OdometryConfig lists 10, 5, 4 from the finest level); Open3D lists its
# iterations from the coarsest level to the original size.
ITERATIONS_COARSE_TO_FINE = [4, 5, 10]
PUBLISHED = {"freiburg1": (517.3, 516.5, 318.6, 255.3), "freiburg2": (520.9, 521.0, 325.1, 249.7),
             "freiburg3": (535.4, 539.2, 320.1, 247.6)}


def read_list(path):
    entries = []
    for line in open(path):
        if line.strip() and not line.startswith("#"):
            stamp, name = line.split()[:2]
            entries.append((float(stamp), name))
    return entries


def associate(first, second, max_difference=0.02):
    """TUM associate.py: closest pairs first, each stamp used once."""
    candidates = sorted((abs(a - b), i, j) for i, (a, _) in enumerate(first) for j, (b, _) in enumerate(second)
                        if abs(a - b) < max_difference)
    used_first, used_second, matches = set(), set(), []
    for _, i, j in candidates:
        if i not in used_first and j not in used_second:
            used_first.add(i)
            used_second.add(j)
            matches.append((i, j))
    return sorted(matches)


def intrinsics(folder):
    camera_yaml = os.path.join(folder, "camera.yaml")
    if os.path.exists(camera_yaml):
        text = open(camera_yaml).read()
        width = int(re.search(r"image_width:\s*(\d+)", text).group(1))
        height = int(re.search(r"image_height:\s*(\d+)", text).group(1))
        k = [float(v) for v in re.search(r"camera_matrix:.*?data:\s*\[([^\]]*)\]", text, re.S).group(1).split(",")]
        return width, height, k[0], k[4], k[2], k[5]
    for name, (fx, fy, cx, cy) in PUBLISHED.items():
        if name in folder:
            return 640, 480, fx, fy, cx, cy
    return 640, 480, 525.0, 525.0, 319.5, 239.5


def frame_pairs(folder, frames):
    rgb = read_list(os.path.join(folder, "rgb.txt"))
    depth = read_list(os.path.join(folder, "depth.txt"))
    return rgb, depth, associate(rgb, depth)[:frames]


def write_trajectory(output, stamps, poses):
    lines = ["%.6f %.9f %.9f %.9f %.9f %.9f %.9f %.9f" % (stamp, *pose[:3, 3], *quaternion(pose[:3, :3]))
             for stamp, pose in zip(stamps, poses)]
    with open(output, "w") as f:
        f.write("# timestamp tx ty tz qx qy qz qw\n" + "\n".join(lines) + "\n")


def run_frame_to_frame(folder, frames, output, load, align):
    """Chains align(current, previous) -> (success, previous_from_current 4x4) over the folder's frames;
    load(rgb_path, depth_path) reads one frame. Returns frames, frames per second of align, failures."""
    rgb, depth, pairs = frame_pairs(folder, frames)
    pose = np.eye(4)
    previous = None
    seconds = 0.0
    failures = 0
    stamps, poses = [], []
    for i, j in pairs:
        current = load(os.path.join(folder, rgb[i][1]), os.path.join(folder, depth[j][1]))
        if previous is not None:
            start = time.perf_counter()
            success, transform = align(current, previous)
            seconds += time.perf_counter() - start
            if success:
                pose = pose @ transform
            else:
                failures += 1
        previous = current
        stamps.append(rgb[i][0])
        poses.append(pose.copy())
    write_trajectory(output, stamps, poses)
    return len(pairs), (len(pairs) - 1) / max(seconds, 1e-9), failures


def run_opencv(folder, frames, output):
    _, _, fx, fy, cx, cy = intrinsics(folder)
    camera = np.array([[fx, 0, cx], [0, fy, cy], [0, 0, 1]], dtype=np.float64)
    odometry = cv2.rgbd.RgbdICPOdometry_create(
        cameraMatrix=camera, minDepth=0.3, maxDepth=6.0, maxDepthDiff=0.07,
        iterCounts=np.array(ITERATIONS_COARSE_TO_FINE[::-1], dtype=np.int32),
        transformType=cv2.rgbd.Odometry_RIGID_BODY_MOTION)

    def load(rgb_path, depth_path):
        grey = cv2.imread(rgb_path, cv2.IMREAD_GRAYSCALE)
        return grey, cv2.imread(depth_path, cv2.IMREAD_UNCHANGED).astype(np.float32) / 5000.0

    def align(current, previous):
        # source = current, destination = previous: Rt maps current points into the previous frame.
        return odometry.compute(current[0], current[1], None, previous[0], previous[1], None)

    return run_frame_to_frame(folder, frames, output, load, align)


def run_open3d(folder, frames, output):
    width, height, fx, fy, cx, cy = intrinsics(folder)
    camera = o3d.camera.PinholeCameraIntrinsic(width, height, fx, fy, cx, cy)
    option = o3d.pipelines.odometry.OdometryOption(
        iteration_number_per_pyramid_level=o3d.utility.IntVector(ITERATIONS_COARSE_TO_FINE),
        depth_diff_max=0.07, depth_min=0.3, depth_max=6.0)
    jacobian = o3d.pipelines.odometry.RGBDOdometryJacobianFromHybridTerm()

    def load(rgb_path, depth_path):
        return o3d.geometry.RGBDImage.create_from_color_and_depth(
            o3d.io.read_image(rgb_path), o3d.io.read_image(depth_path), depth_scale=5000.0, depth_trunc=6.0,
            convert_rgb_to_intensity=True)

    def align(current, previous):
        # source = current, target = previous: the result maps current points into the previous frame.
        success, transform, _ = o3d.pipelines.odometry.compute_rgbd_odometry(
            current, previous, camera, np.eye(4), jacobian, option)
        return success, transform

    return run_frame_to_frame(folder, frames, output, load, align)


def quaternion(R):
    w = np.sqrt(max(0.0, 1.0 + R[0, 0] + R[1, 1] + R[2, 2])) / 2
    x = np.sqrt(max(0.0, 1.0 + R[0, 0] - R[1, 1] - R[2, 2])) / 2
    y = np.sqrt(max(0.0, 1.0 - R[0, 0] + R[1, 1] - R[2, 2])) / 2
    z = np.sqrt(max(0.0, 1.0 - R[0, 0] - R[1, 1] + R[2, 2])) / 2
    x = np.copysign(x, R[2, 1] - R[1, 2])
    y = np.copysign(y, R[0, 2] - R[2, 0])
    z = np.copysign(z, R[1, 0] - R[0, 1])
    return x, y, z, w


def evaluate(ground_truth, trajectory, fps, failures):
    evaluation = subprocess.run([os.path.join(TOOLS, "evaluate_trajectory"), ground_truth, trajectory],
                                capture_output=True, text=True, check=True)
    values = metrics(evaluation.stdout)
    values["frames_per_second"] = fps
    values["tracking_failures"] = failures
    return values


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("folder")
    parser.add_argument("--frames", type=int, default=100000)
    parser.add_argument("--vocal-args", default="", help="extra arguments for tum_odometry")
    parser.add_argument("--workdir", default="/tmp")
    args = parser.parse_args()
    ground_truth = os.path.join(args.folder, "groundtruth.txt")
    if not os.path.exists(ground_truth):
        sys.exit(f"compare_odometry: {ground_truth} is missing: accuracy needs ground truth")

    vocal_trajectory = os.path.join(args.workdir, "vocal_trajectory.txt")
    command = [os.path.join(TOOLS, "tum_odometry"), args.folder, "--output", vocal_trajectory, "--quiet",
               "--frames", str(args.frames)] + args.vocal_args.split()
    vocal_run = subprocess.run(command, capture_output=True, text=True)
    if vocal_run.returncode != 0:
        sys.exit("compare_odometry: tum_odometry failed:\n" + vocal_run.stderr)
    columns = {"vocal": metrics(vocal_run.stdout)}
    backend = re.search(r"backend (.*)", vocal_run.stderr)
    frames = int(columns["vocal"].get("frames", 0))
    described = [f"vocal: {backend.group(1) if backend else '?'}"]

    others = [("opencv", cv2, "python3-opencv", run_opencv, "rgbd.RgbdICPOdometry"),
              ("open3d", o3d, "python3-open3d", run_open3d, "hybrid term")]
    for name, module, package, runner, method in others:
        if module is None:
            print(f"*** {package} is not installed (apt-get install {package}): {name} left out ***")
            continue
        trajectory = os.path.join(args.workdir, f"{name}_trajectory.txt")
        frames, fps, failures = runner(args.folder, args.frames, trajectory)
        columns[name] = evaluate(ground_truth, trajectory, fps, failures)
        described.append(f"{name}: {module.__version__} {method}")

    print(f"sequence: {args.folder} ({frames} frames)")
    print("; ".join(described))
    print(f"{'metric':<22}" + "".join(f"{name:>12}" for name in columns))
    for key in ["frames_per_second", "ate_rmse_m", "rpe_trans_m_per_s", "rpe_rot_deg_per_s", "tracking_failures"]:
        print(f"{key:<22}" + "".join(f"{values.get(key, float('nan')):>12.4f}" for values in columns.values()))


if __name__ == "__main__":
    main()
