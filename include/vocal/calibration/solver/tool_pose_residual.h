#pragma once
// The arm's reported tool pose (tf) in the arm's graph (hand_eye_calibration.h): the tool's block held
// near it within the arm's repeatability; in the still-pose graph (graph_calibration.h), the board it holds
// less the board's mount.

#include <Eigen/Geometry>

#include "vocal/calibration/solver/rotation_error.h"

namespace vocal {

// The tool block where the arm reported it: rotation in the tool frame, translation in the base frame,
// each in its sigmas (radians, metres).
struct ToolPoseResidual {
  ToolPoseResidual(const Eigen::Isometry3d& reported, double rotation_sigma, double translation_sigma)
      : rotation(reported.linear()), translation(reported.translation()), rotation_sigma(rotation_sigma), translation_sigma(translation_sigma) {}

  template <typename T>
  bool operator()(const T* tq, const T* tt, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q(tq);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t(tt);
    Eigen::Map<Eigen::Matrix<T, 6, 1>> out(residual);
    out.template head<3>() = rotationBetween(Eigen::Quaternion<T>(rotation.cast<T>()), Eigen::Quaternion<T>(q)) / T(rotation_sigma);
    out.template tail<3>() = (t - translation.cast<T>()) / T(translation_sigma);
    return true;
  }

  Eigen::Matrix3d rotation;
  Eigen::Vector3d translation;
  double rotation_sigma, translation_sigma;
};

// The same where the graph holds what the tool carries instead of the tool (the still-pose graph's board
// on an arm's tool from tf): the tool is that frame's block (blocks 0, 1) less its mount on the tool (2, 3).
struct MountedToolPoseResidual {
  ToolPoseResidual reported;

  template <typename T>
  bool operator()(const T* frame_q, const T* frame_t, const T* mount_q, const T* mount_t, T* residual) const {
    const Eigen::Quaternion<T> frame(Eigen::Map<const Eigen::Quaternion<T>>{frame_q});
    const Eigen::Quaternion<T> mount(Eigen::Map<const Eigen::Quaternion<T>>{mount_q});
    const Eigen::Quaternion<T> tool_q = frame * mount.conjugate();
    const Eigen::Matrix<T, 3, 1> tool_t = Eigen::Map<const Eigen::Matrix<T, 3, 1>>(frame_t) - tool_q * Eigen::Map<const Eigen::Matrix<T, 3, 1>>(mount_t);
    return reported(tool_q.coeffs().data(), tool_t.data(), residual);
  }
};

}  // namespace vocal
