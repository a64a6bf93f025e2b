#pragma once
// Helpers of the calibration graphs' residual tests (test_arm_graph_residuals.cpp,
// test_rig_graph_residuals.cpp): poses as the graphs' blocks hold them.

#include <vector>

#include <Eigen/Geometry>

#include "vocal/calibration/joint_chain.h"
#include "vocal/core/se3.h"

namespace vocal_test {

// A pose's rotation (Eigen's x y z w) and translation, as the graph's blocks hold them.
struct Blocks {
  explicit Blocks(const Eigen::Isometry3d& pose) : q(pose.linear()), t(pose.translation()) {}
  Eigen::Quaterniond q;
  Eigen::Vector3d t;
};

// A translation and a turn of `angle` about `axis` (normalised here).
inline Eigen::Isometry3d pose(const Eigen::Vector3d& translation, double angle, const Eigen::Vector3d& axis) {
  return vocal::poseFromTranslationQuaternion(translation, Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized())));
}

// A pan joint (about z, 0.2 m up) and a tilt joint after it (about y, 0.1 m ahead and up): a head's chain.
inline std::vector<vocal::JointDescription> panTiltJoints() {
  std::vector<vocal::JointDescription> joints(2);
  joints[0].name = "pan", joints[0].parent = "base", joints[0].child = "pan_link", joints[0].axis = Eigen::Vector3d::UnitZ();
  joints[0].origin.translation() = Eigen::Vector3d(0.0, 0.0, 0.2);
  joints[1].name = "tilt", joints[1].parent = "pan_link", joints[1].child = "tilt_link", joints[1].axis = Eigen::Vector3d::UnitY();
  joints[1].origin.translation() = Eigen::Vector3d(0.1, 0.0, 0.1);
  return joints;
}

}  // namespace vocal_test
