#!/usr/bin/env python3
"""The depth noise of the real Kinect frames in ../shared/data/tum, against depth: the model the odometry
weights its ICP pairs by (DepthNoiseModel, config depth_noise_floor / depth_noise_quadratic) checked on
real data.

usage: /usr/bin/python3 bench/depth_noise.py [--data DIR] [--frames N] [--floor M] [--quadratic K]

In every 7x7 patch (every 7th pixel of every 10th depth frame, up to N frames a sequence) whose depths
all exist and lie within a few centimetres of the centre's (one surface), a quadratic surface is
fitted to the depth; the RMS of its residuals estimates the noise there. Per 0.25 m depth bin: the
median and lower quartile of those (most patches are smooth surfaces; the rest add their shape), the
median over z^2, and what the model sqrt(floor^2 + (quadratic z^2)^2) gives (by default the values
config/odometry.yaml documents for a Kinect: 0.5 mm, 0.001 / m); then the quadratic fitted to the
medians at 1 m and beyond.
"""
import argparse
import glob
import os
import sys

import cv2
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "..", "shared", "data", "tum")
RADIUS = 3
BINS = np.arange(0.5, 4.01, 0.25)


def patch_noise(depth):
    """(centre depth, residual RMS) of every usable patch of one depth image in metres."""
    side = 2 * RADIUS + 1
    yy, xx = np.mgrid[-RADIUS:RADIUS + 1, -RADIUS:RADIUS + 1]
    design = np.c_[xx.ravel(), yy.ravel(), np.ones(side * side), xx.ravel() ** 2, yy.ravel() ** 2, (xx * yy).ravel()]
    projector = np.eye(side * side) - design @ np.linalg.pinv(design)
    found = []
    height, width = depth.shape
    for y in range(RADIUS, height - RADIUS, side):
        for x in range(RADIUS, width - RADIUS, side):
            patch = depth[y - RADIUS:y + RADIUS + 1, x - RADIUS:x + RADIUS + 1]
            centre = patch[RADIUS, RADIUS]
            if (patch <= 0).any() or np.abs(patch - centre).max() > 0.05 * centre * centre + 0.02:
                continue
            residual = projector @ patch.ravel()
            found.append((centre, np.sqrt(residual @ residual / (side * side - design.shape[1]))))
    return found


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--data", default=DATA)
    parser.add_argument("--frames", type=int, default=12)
    parser.add_argument("--floor", type=float, default=0.0005, help="metres")
    parser.add_argument("--quadratic", type=float, default=0.001, help="per metre")
    args = parser.parse_args()
    folders = sorted(glob.glob(os.path.join(args.data, "rgbd_dataset_*")))
    if not folders:
        print("*** no TUM sequences under %s: nothing measured ***" % args.data)
        return 1
    floor, quadratic = args.floor, args.quadratic
    print("model: sigma = sqrt(%g^2 + (%g z^2)^2) m\n" % (floor, quadratic))
    fitted = []
    print("| sequence | depth m | patches | sigma p25 mm | sigma median mm | median / z^2 mm | model mm |")
    print("|---|---|---|---|---|---|---|")
    for folder in folders:
        bins = [[] for _ in range(len(BINS) - 1)]
        for path in sorted(glob.glob(os.path.join(folder, "depth", "*.png")))[::10][:args.frames]:
            depth = cv2.imread(path, cv2.IMREAD_UNCHANGED).astype(np.float64) / 5000.0
            for centre, sigma in patch_noise(depth):
                k = np.searchsorted(BINS, centre) - 1
                if 0 <= k < len(bins):
                    bins[k].append(sigma)
        name = os.path.basename(folder).replace("rgbd_dataset_", "")
        for k, values in enumerate(bins):
            if len(values) < 50:
                continue
            z = (BINS[k] + BINS[k + 1]) / 2
            p25, median = np.percentile(values, [25, 50])
            model = np.sqrt(floor ** 2 + (quadratic * z * z) ** 2)
            if z >= 1.0:
                fitted.append(np.sqrt(max(median ** 2 - floor ** 2, 0.0)) / (z * z))
            print("| %s | %.2f | %d | %.2f | %.2f | %.2f | %.2f |" % (name, z, len(values), p25 * 1e3, median * 1e3,
                                                                   median / (z * z) * 1e3, model * 1e3))
    print("\nquadratic fitted to the medians at 1 m and beyond (floor %g m): %.5f / m (bins %.5f-%.5f)" % (
        floor, np.median(fitted), min(fitted), max(fitted)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
