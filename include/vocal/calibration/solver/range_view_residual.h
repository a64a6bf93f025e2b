#pragma once
// A range sensor's (RGB-D, 3D lidar) view of the board in the arm's graph (hand_eye_calibration.h): its
// board points on the board's plane where the unknowns put it.

#include <vector>

#include <Eigen/Geometry>

#include "vocal/calibration/solver/frame_mounting.h"
#include "vocal/calibration/solver/point_plane_residual.h"

namespace vocal {

// The points against the board's z = 0 plane in the sensor's parent frame (FrameMounting), through their
// moment matrix (point_plane_residual.h). Blocks as CameraViewResidual's.
struct RangeViewResidual {
  RangeViewResidual(const std::vector<Eigen::Vector3d>& points, double point_sigma, FrameMounting mounting)
      : on_plane(points, point_sigma), mounting(mounting) {}

  template <typename T>
  bool operator()(const T* xq, const T* xt, const T* yq, const T* yt, const T* sq, const T* st, const T* bq, const T* bt, T* residual) const {
    const T* board[] = {yq, yt, sq, st, bq, bt};
    const auto [q, t] = mounting.boardInSensorParent(board);
    const Eigen::Matrix<T, 3, 1> normal = q * Eigen::Matrix<T, 3, 1>::UnitZ();
    const T offset = -normal.dot(t);
    return on_plane(xq, xt, normal.data(), &offset, residual);
  }

  ObservationOnPlaneResidual on_plane;
  FrameMounting mounting;
};

}  // namespace vocal
