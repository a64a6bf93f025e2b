#pragma once
// A range sensor's point on the board's edge against the board's outline, for the Ceres graphs (hand-eye
// for a 2D laser's scan ends; the still-pose graph holds a view's points in one block,
// outline_points_residual.h): Eigen only, so it stays out of Ceres's headers.

#include <Eigen/Geometry>

#include "vocal/calibration/extraction/board_outline.h"

namespace vocal {

// The point (sensor frame) against a width x height board (centred on the board frame, x along the
// width): its distance within the board's plane to the outline, in standard deviations. Blocks: the
// sensor's and the board's rotation (Eigen quaternion) and translation in one frame.
struct OutlinePointResidual {
  Eigen::Vector3d point;
  double sigma, half_width, half_height;

  template <typename T>
  bool operator()(const T* rotation, const T* translation, const T* board_rotation, const T* board_translation, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q(rotation), q_board(board_rotation);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t(translation), t_board(board_translation);
    const Eigen::Matrix<T, 3, 1> on_board = q_board.conjugate() * (q * point.cast<T>() + t - t_board);
    residual[0] = distanceToOutline(on_board.x(), on_board.y(), half_width, half_height) / T(sigma);
    return true;
  }
};

}  // namespace vocal
