#pragma once
// The rotation between a measured and a predicted orientation as a rotation vector, for the Ceres
// residuals of the arm's graph (camera_view_residual.h, tool_pose_residual.h, link_from_joints_residual.h).

#include <Eigen/Geometry>
#include <ceres/rotation.h>

namespace vocal {

// R_meas^T R_pred as a rotation vector (the perturbation R_pred = R_meas exp([w]x)).
template <typename T>
Eigen::Matrix<T, 3, 1> rotationBetween(const Eigen::Quaternion<T>& measured, const Eigen::Quaternion<T>& predicted) {
  const Eigen::Quaternion<T> error = measured.conjugate() * predicted;
  const T wxyz[4] = {error.w(), error.x(), error.y(), error.z()};
  Eigen::Matrix<T, 3, 1> w;
  ceres::QuaternionToAngleAxis(wxyz, w.data());
  return w;
}

}  // namespace vocal
