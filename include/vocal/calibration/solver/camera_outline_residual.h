#pragma once
// A camera's view of the board's outline in the still-pose graph with board edges and refined intrinsics
// (graph_calibration.h): the outline its pattern's pose predicts, moved by the intrinsics correction,
// against the board's outline the unknowns put there. Eigen only.

#include <vector>

#include <Eigen/Geometry>

#include "vocal/calibration/extraction/board_outline.h"
#include "vocal/calibration/solver/intrinsics_refinement.h"

namespace vocal {

// A width x height board's outline in the pattern's frame (the pattern centred on the board, its x along
// the board's width): each edge's ends and middle (so each corner twice).
inline std::vector<Eigen::Vector3d> patternOutline(double width, double height) {
  const double half_width = 0.5 * width, half_height = 0.5 * height;
  std::vector<Eigen::Vector3d> outline;
  for (double s : {-0.5, 0.0, 0.5}) {
    for (double side : {-1.0, 1.0}) {
      outline.emplace_back(side * half_width, s * 2.0 * half_height, 0.0);
      outline.emplace_back(s * 2.0 * half_width, side * half_height, 0.0);
    }
  }
  return outline;
}

// One outline point (pattern frame) placed by the view's pose with the camera's intrinsics correction
// (PatternPoseCorrected): its distance within the board's plane to the board's outline, in standard
// deviations. Blocks: the camera's and the board's rotation and translation in the rig frame, the
// intrinsics correction.
struct CameraOutlineWithIntrinsics {
  Eigen::Vector3d on_pattern;
  Eigen::Isometry3d sensor_from_pattern;
  Eigen::Matrix<double, 6, 4> pose_per_intrinsics;
  double sigma, half_width, half_height;

  template <typename T>
  bool operator()(const T* rotation, const T* translation, const T* board_rotation, const T* board_translation, const T* intrinsics,
                  T* residual) const {
    const Eigen::Matrix<T, 3, 1> point = PatternPoseCorrected<T>(sensor_from_pattern, pose_per_intrinsics, intrinsics).point(on_pattern);
    const Eigen::Map<const Eigen::Quaternion<T>> q_sensor(rotation), q_board(board_rotation);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t_sensor(translation), t_board(board_translation);
    const Eigen::Matrix<T, 3, 1> on_board = q_board.conjugate() * (q_sensor * point + t_sensor - t_board);
    residual[0] = distanceToOutline(on_board.x(), on_board.y(), half_width, half_height) / T(sigma);
    return true;
  }
};

}  // namespace vocal
