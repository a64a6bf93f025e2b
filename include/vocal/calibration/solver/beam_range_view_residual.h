#pragma once
// A 2D laser's view of the board in the arm's graph (hand_eye_calibration.h): its board points as range
// errors along its beams against the board's plane where the unknowns put it.

#include <vector>

#include <Eigen/Geometry>

#include "vocal/calibration/solver/beam_range_residual.h"
#include "vocal/calibration/solver/frame_mounting.h"

namespace vocal {

// One residual per point (beam_range_residual.h): a line's plane alone fixes the laser's height and pitch
// weakly, so the bias a fit of point-to-plane distances has there would be taken up in full. Blocks (a
// dynamic cost): the laser's rotation and translation, the board's, the frame the laser moves with, the
// frame the board moves with.
struct BeamRangeViewResidual {
  std::vector<Eigen::Vector3d> points;
  double sigma;
  FrameMounting mounting;

  template <typename T>
  bool operator()(T const* const* blocks, T* residuals) const {
    const auto [q, t] = mounting.boardInSensorParent(blocks + 2);
    const Eigen::Matrix<T, 3, 1> normal = q * Eigen::Matrix<T, 3, 1>::UnitZ();
    beamRangeResiduals(points, sigma, Eigen::Quaternion<T>(blocks[0]), Eigen::Matrix<T, 3, 1>(blocks[1]), normal, T(-normal.dot(t)), residuals);
    return true;
  }
};

}  // namespace vocal
