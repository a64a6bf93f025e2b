#pragma once
// The cameras' intrinsics refined with their poses, in either calibration graph (graph_calibration.h,
// hand_eye_calibration.h): each camera's focal lengths (and, where freed, its principal point) as a
// relative correction dk = (dfx / fx, dfy / fy, dcx / fx, dcy / fy) of its camera_info's, under a prior,
// fixed by its corners' own perspective (PlaneMeasurement::evidence_*) and by the rest of the graph (a
// lidar's ranges are metric; an arm's motion is too). Each view moves with dk to first order
// (PlaneMeasurement::pose_per_intrinsics): PatternPoseCorrected.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "vocal/calibration/calibration_types.h"

namespace ceres {
class Problem;
}

namespace vocal {

struct IntrinsicsRefinementOptions {
  bool enabled = false;
  double focal_sigma = 0.02;  // the prior on each focal length, as a share of it
  // The principal point too (off: held at camera_info's). A shift of it is nearly a turn of the camera,
  // which its pose takes up; freed, the real OS1-64 lab's pair moved 12 mm from the factory's extrinsic
  // where the focal lengths alone left it 8 mm.
  bool principal_point = false;
  double centre_sigma = 0.03;  // its prior, as a share of the focal length (20 px at 650)
};

// The pattern's pose as a camera's intrinsics correction `intrinsics` (dk) moves it, to first order:
// R exp([w]x) ~ R (I + [w]x), t + dt, (w, dt) = pose_per_intrinsics dk.
template <typename T>
struct PatternPoseCorrected {
  PatternPoseCorrected(const Eigen::Isometry3d& measured, const Eigen::Matrix<double, 6, 4>& pose_per_intrinsics, const T* intrinsics)
      : measured(measured), moved(pose_per_intrinsics.cast<T>() * Eigen::Map<const Eigen::Matrix<T, 4, 1>>(intrinsics)) {}
  // A direction, and a point, of the pattern's frame in the camera's.
  Eigen::Matrix<T, 3, 1> direction(const Eigen::Vector3d& in_pattern) const {
    const Eigen::Matrix<T, 3, 1> e = in_pattern.cast<T>();
    return measured.linear().cast<T>() * (e + moved.template head<3>().cross(e));
  }
  Eigen::Matrix<T, 3, 1> point(const Eigen::Vector3d& in_pattern) const {
    return direction(in_pattern) + measured.translation().cast<T>() + moved.template tail<3>();
  }
  const Eigen::Isometry3d& measured;
  Eigen::Matrix<T, 6, 1> moved;
};

// What one view's corners say of the intrinsics correction beyond the pose (PlaneMeasurement::evidence_*).
struct IntrinsicsEvidenceResidual {
  Eigen::Matrix4d matrix;
  Eigen::Vector4d offset;
  template <typename T>
  bool operator()(const T* intrinsics, T* residual) const {
    Eigen::Map<Eigen::Matrix<T, 4, 1>> out(residual);
    out = matrix.cast<T>() * Eigen::Map<const Eigen::Matrix<T, 4, 1>>(intrinsics) + offset.cast<T>();
    return true;
  }
};

// The camera_info's intrinsics as a prior: each relative change in its sigma.
struct IntrinsicsPrior {
  Eigen::Vector4d sigma;
  template <typename T>
  bool operator()(const T* intrinsics, T* residual) const {
    for (int k = 0; k < 4; ++k) residual[k] = intrinsics[k] / T(sigma[k]);
    return true;
  }
};

// (fx, fy, cx, cy) in pixels from camera_info's `given` and the correction `dk`.
inline Eigen::Vector4d refinedIntrinsics(const Eigen::Vector4d& given, const Eigen::Vector4d& dk) {
  return given + Eigen::Vector4d(given[0] * dk[0], given[1] * dk[1], given[0] * dk[2], given[1] * dk[3]);
}

// `view` as the correction `dk` moves it (R exp([w]x), t + dt): where its corners would have put the
// pattern with the refined intrinsics.
PlaneMeasurement movedByIntrinsics(const PlaneMeasurement& view, const Eigen::Vector4d& dk);

// The prior on a camera's correction block `intrinsics`; its principal point held unless `options` free it.
void addIntrinsicsPrior(ceres::Problem* problem, double* intrinsics, const IntrinsicsRefinementOptions& options);
// One view's corners' own evidence on the block (nothing where the view has none).
void addIntrinsicsEvidence(ceres::Problem* problem, const PlaneMeasurement& view, double* intrinsics);
// The refined intrinsics' standard deviations in pixels (`given`: camera_info's) from `problem`'s
// covariance; zero where the block is not in it or the covariance cannot be computed.
Eigen::Vector4d intrinsicsSigma(ceres::Problem* problem, double* intrinsics, const Eigen::Vector4d& given);

}  // namespace vocal
