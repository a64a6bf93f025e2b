#pragma once
// A camera's view of the board in the still-pose graph (graph_calibration.h) as its whole PnP pose: the
// pattern in the camera against the board's block (rig frame) and where the print lies on the board,
// whitened by the view's covariance - the arm graph's CameraViewResidual with the camera and the board
// each in the rig frame. The print's place is an unknown of the graph (one for the board): a print glued
// a few millimetres off the board's centre must not pull the range sensors' edges, which see the board's
// outline, not its print.

#include <cmath>

#include <Eigen/Geometry>

#include "vocal/calibration/solver/camera_view_residual.h"

namespace vocal {

// The pattern's pose (rig frame) from the board's (q, t) and the print's place on it: (dx, dy) metres along
// the board's x and y and a turn (rad) about its normal.
template <typename T>
void patternOnBoard(const T* board_q, const T* board_t, const T* print, Eigen::Quaternion<T>* q, Eigen::Matrix<T, 3, 1>* t) {
  using std::cos;
  using std::sin;
  const Eigen::Map<const Eigen::Quaternion<T>> board_rotation(board_q);
  const Eigen::Map<const Eigen::Matrix<T, 3, 1>> board_translation(board_t);
  *q = board_rotation * Eigen::Quaternion<T>(cos(print[2] * T(0.5)), T(0), T(0), sin(print[2] * T(0.5)));
  *t = board_translation + board_rotation * Eigen::Matrix<T, 3, 1>(print[0], print[1], T(0));
}

// Blocks: the camera's rotation and translation (rig frame), the board's, the print's place (3).
struct CameraPoseOnBoardResidual {
  explicit CameraPoseOnBoardResidual(const PlaneMeasurement& view) : view(view, FrameMounting{false, false}) {}

  template <typename T>
  bool operator()(const T* xq, const T* xt, const T* bq, const T* bt, const T* print, T* residual) const {
    Eigen::Quaternion<T> q;
    Eigen::Matrix<T, 3, 1> t;
    patternOnBoard(bq, bt, print, &q, &t);
    // Both frames fixed (FrameMounting{false, false}): their blocks are not read.
    const T unused[4] = {T(0), T(0), T(0), T(1)};
    return view.evaluate<T>(xq, xt, q.coeffs().data(), t.data(), unused, unused, unused, unused, nullptr, residual);
  }

  CameraViewResidual view;
};

// The print's place held near the board's centre, square to its edges (a prior as wide as a hand-glued print).
struct PrintPlacePrior {
  double translation_sigma = 0.01, rotation_sigma = 0.02;
  template <typename T>
  bool operator()(const T* print, T* residual) const {
    residual[0] = print[0] / T(translation_sigma);
    residual[1] = print[1] / T(translation_sigma);
    residual[2] = print[2] / T(rotation_sigma);
    return true;
  }
};

}  // namespace vocal
