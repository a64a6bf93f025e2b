#pragma once
// The classic sparse alternative to dense odometry (after the seed's Algorithm 1): ORB features of two
// RGB-D frames matched, the reference's lifted to 3D with its depth, and the motion most pairs agree
// on (RANSAC over EPnP samples on reprojection errors, refined on the inliers). Used as the dense solver's
// starting point: dense ICP + DVO converge only within a few centimetres and degrees of the truth,
// features find larger motions.

#include <memory>

#include <Eigen/Geometry>

#include "vocal/core/pinhole_camera.h"
#include "vocal/core/rgbd_frame.h"

namespace vocal {

struct FeatureAlignmentOptions {
  int max_features = 600;
  double max_reprojection_px = 2.0;  // an inlier's reprojection error
  int min_inliers = 25;
  double min_inlier_fraction = 0.3;  // of the matches with reference depth
  int iterations = 200;
  // Keypoints are detected on the grey image halved (2x2 means) while it is wider than this: a
  // starting point needs no full-resolution corners (measured at 640x480: extraction 2.0 instead of
  // 3.8 ms, fr1_xyz RPE 0.01929 vs 0.01928 m/s).
  int max_detection_width = 320;
};

struct FeatureAlignment {
  bool found = false;  // enough matches agree on one motion
  Eigen::Isometry3d reference_from_current = Eigen::Isometry3d::Identity();
  int matches = 0;     // cross-checked matches with valid depth in the reference frame
  int inliers = 0;
};

// A frame's ORB keypoints and descriptors, each with its 3D point where the depth is usable (OpenCV's
// types stay in the .cpp). Extracted once per frame: a frame is the current one, then the reference.
struct FrameFeatures;
std::shared_ptr<const FrameFeatures> extractFrameFeatures(const RgbdFrame& frame, const PinholeCamera& camera,
                                                          const FeatureAlignmentOptions& options = {});

FeatureAlignment alignFrameFeatures(const FrameFeatures& reference, const FrameFeatures& current, const PinholeCamera& camera,
                                    const FeatureAlignmentOptions& options = {});

// Both steps for two frames.
FeatureAlignment alignByFeatures(const RgbdFrame& reference, const RgbdFrame& current, const PinholeCamera& camera,
                                 const FeatureAlignmentOptions& options = {});

}  // namespace vocal
