#pragma once
// Frame-to-frame RGB-D odometry: point-to-plane ICP and dense photometric odometry (DVO) fused in one
// weighted 6x6 system per iteration, solved coarse to fine (Whelan et al. 2013).

#include <memory>
#include <string>

#include <Eigen/Geometry>

#include "vocal/core/pinhole_camera.h"
#include "vocal/core/rgbd_frame.h"
#include "vocal/core/se3.h"
#include "vocal/odometry/feature_alignment.h"
#include "vocal/odometry/odometry_backend.h"
#include "vocal/odometry/odometry_config.h"

namespace vocal {

struct OdometryQuality {
  int icp_inliers = 0;        // at the finest level, last iteration
  int rgb_inliers = 0;
  double icp_rmse = 0.0;      // metres
  double rgb_rmse = 0.0;      // intensity units
  int iterations = 0;         // solver steps over all levels
  double condition = 0.0;     // of the final system (largest / smallest eigenvalue)
  double weakest_information = 0.0;  // smallest eigenvalue of the final system per inlier
  bool trusted = false;       // the increment passed every check and was applied
  int feature_inliers = 0;    // features agreeing on the starting motion (0: started from none)
  bool feature_fallback = false;  // fallback mode: the first solve was suspicious, features were asked
};

// Wall-clock milliseconds of one track() call per stage.
struct OdometryTimings {
  double preprocess_ms = 0.0;  // pyramids, maps, gradients (the backend's pushFrame)
  double features_ms = 0.0;    // ORB extraction, matching and PnP (feature initialisation)
  double solve_ms = 0.0;       // the coarse-to-fine dense solve(s) and the result checks
};

struct OdometryResult {
  bool first_frame = false;  // the first frame (or the first after a reset) only sets the reference
  Eigen::Isometry3d increment = Eigen::Isometry3d::Identity();  // previous camera <- current camera
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();       // odometry frame <- current camera
  // Of the increment's twist [v; w] (a left perturbation, in the previous camera frame).
  Matrix6d covariance = Matrix6d::Identity();
  // Of the pose's twist in the odometry frame (left perturbation): grows with every increment, zero
  // after a reset (the start pose is given).
  Matrix6d pose_covariance = Matrix6d::Zero();
  OdometryQuality quality;
  OdometryTimings timings;
  std::string failure;  // why tracking was not trusted; empty when it was
};

class IcpDvoOdometry {
 public:
  // Throws InputError for an invalid camera or config, or when the backend cannot be made.
  IcpDvoOdometry(const PinholeCamera& camera, const OdometryConfig& config,
                 std::unique_ptr<OdometryBackend> backend = nullptr);

  // Estimates the motion since the previous frame. Throws InputError when the frame does not fit the
  // camera (size, colour vs depth); bad content (no valid depth, no texture or structure, a jump)
  // is reported in the result, the increment then is not applied.
  OdometryResult track(const RgbdFrame& frame);

  // Forgets the reference frame; the next frame starts again at `pose`.
  void reset(const Eigen::Isometry3d& pose = Eigen::Isometry3d::Identity());

  const Eigen::Isometry3d& pose() const { return pose_; }
  const Matrix6d& poseCovariance() const { return pose_covariance_; }
  const OdometryBackend& backend() const { return *backend_; }
  const PinholeCamera& camera() const { return camera_; }
  const OdometryConfig& config() const { return config_; }

 private:
  struct DenseSolve {
    Eigen::Isometry3d increment = Eigen::Isometry3d::Identity();
    Matrix6d information = Matrix6d::Zero();  // the final fused system's A
    OdometryQuality quality;
    std::string failure;  // empty when every check passed
  };
  // The coarse-to-fine ICP + DVO solve from `start`, and its checks.
  DenseSolve solveFrom(const Eigen::Isometry3d& start);
  // The residual a wrong minimum shows in: photometric RMSE (ICP's in ICP mode).
  double residualLevelOf(const OdometryQuality& quality) const;
  // Failed, or a residual far above the running level: worth a second start from the features.
  bool suspicious(const DenseSolve& solve) const;

  PinholeCamera camera_;
  OdometryConfig config_;
  std::unique_ptr<OdometryBackend> backend_;
  bool has_reference_ = false;
  Eigen::Isometry3d pose_ = Eigen::Isometry3d::Identity();
  Matrix6d pose_covariance_ = Matrix6d::Zero();
  std::shared_ptr<const FrameFeatures> reference_features_;  // for feature initialisation (null: not extracted)
  RgbdFrame reference_frame_;  // fallback mode: to extract the reference's features when needed
  Eigen::Isometry3d velocity_ = Eigen::Isometry3d::Identity();  // the last trusted increment
  double residual_level_ = 0.0;  // running average of trusted frames' residualLevelOf (0: none yet)
};

}  // namespace vocal
