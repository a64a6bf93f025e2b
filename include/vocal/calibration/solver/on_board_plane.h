#pragma once
// A plane residual (PlaneMeasurementResidual, ObservationOnPlaneResidual) on a board pose instead of a
// plane, for the still-pose graph with board edges (graph_calibration.h): the board's plane is its z = 0.

#include <Eigen/Geometry>

namespace vocal {

// Blocks: the sensor's rotation and translation, the board's (rig <- board) rotation and translation, then
// the plane residual's blocks after its plane (an intrinsics correction), and the residual.
template <typename PlaneResidual>
struct OnBoardPlane {
  PlaneResidual plane;

  template <typename T, typename... Rest>
  bool operator()(const T* rotation, const T* translation, const T* board_rotation, const T* board_translation, Rest... rest) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q(board_rotation);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t(board_translation);
    const Eigen::Matrix<T, 3, 1> normal = q * Eigen::Matrix<T, 3, 1>::UnitZ();
    const T offset = -normal.dot(t);
    return plane(rotation, translation, normal.data(), &offset, rest...);
  }
};

}  // namespace vocal
