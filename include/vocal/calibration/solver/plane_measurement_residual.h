#pragma once
// A camera's view of the board in the still-pose graph (graph_calibration.h): its pattern's plane against
// the board's plane the unknowns put there, whitened by the view's covariance. Eigen only, so it stays out
// of Ceres's headers.

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include "vocal/calibration/calibration_types.h"
#include "vocal/calibration/solver/intrinsics_refinement.h"

namespace vocal {

// The predicted plane in the camera frame, n_c = q^-1 n and d_c = n . t + d, read as the pattern's tilt
// (n_c along the measured pattern x and y axes, zero when they agree) and the measured centre's distance
// to it, whitened by the measurement's covariance. Blocks: the camera's rotation (Eigen quaternion) and
// translation in the rig frame, the plane's normal and offset there.
struct PlaneMeasurementResidual {
  explicit PlaneMeasurementResidual(const PlaneMeasurement& measurement)
      : sensor_from_pattern(measurement.sensor_from_pattern), pose_per_intrinsics(measurement.pose_per_intrinsics) {
    // |L^-1 r|^2 = r^T covariance^-1 r for covariance = L L^T.
    whitening = measurement.covariance.llt().matrixL().solve(Eigen::Matrix3d::Identity());
  }

  template <typename T>
  bool operator()(const T* rotation, const T* translation, const T* normal, const T* offset, T* residual) const {
    return evaluate<T>(rotation, translation, normal, offset, nullptr, residual);
  }

  // With the camera's intrinsics changed by `intrinsics` (null: as given), the pattern's pose as the
  // corners would then put it (PatternPoseCorrected).
  template <typename T>
  bool evaluate(const T* sensor_rotation, const T* sensor_translation, const T* normal_block, const T* offset, const T* intrinsics,
                T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q(sensor_rotation);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t(sensor_translation);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> n(normal_block);
    Eigen::Matrix<T, 3, 1> x_axis = sensor_from_pattern.linear().col(0).cast<T>(), y_axis = sensor_from_pattern.linear().col(1).cast<T>();
    Eigen::Matrix<T, 3, 1> centre = sensor_from_pattern.translation().cast<T>();
    if (intrinsics) {
      const PatternPoseCorrected<T> corrected(sensor_from_pattern, pose_per_intrinsics, intrinsics);
      x_axis = corrected.direction(Eigen::Vector3d::UnitX());
      y_axis = corrected.direction(Eigen::Vector3d::UnitY());
      centre = corrected.point(Eigen::Vector3d::Zero());
    }
    const Eigen::Matrix<T, 3, 1> n_camera = q.conjugate() * n;
    const Eigen::Matrix<T, 3, 1> r(n_camera.dot(x_axis), n_camera.dot(y_axis), n_camera.dot(centre) + n.dot(t) + offset[0]);
    Eigen::Map<Eigen::Matrix<T, 3, 1>> out(residual);
    out = whitening.cast<T>() * r;
    return true;
  }

  Eigen::Isometry3d sensor_from_pattern;
  Eigen::Matrix<double, 6, 4> pose_per_intrinsics;
  Eigen::Matrix3d whitening;
};

// The same measurement with the camera's intrinsics correction (IntrinsicsRefinementOptions) as a fifth block.
struct PlaneMeasurementWithIntrinsics {
  PlaneMeasurementResidual measurement;
  template <typename T>
  bool operator()(const T* rotation, const T* translation, const T* normal, const T* offset, const T* intrinsics, T* residual) const {
    return measurement.evaluate<T>(rotation, translation, normal, offset, intrinsics, residual);
  }
};

}  // namespace vocal
