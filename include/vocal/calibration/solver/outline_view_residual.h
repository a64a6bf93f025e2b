#pragma once
// A range sensor's points on the board's edge (a 2D laser's scan ends) in the arm's graph
// (hand_eye_calibration.h): against the board's outline where the unknowns put it, reached by the beam's
// footprint (its radius an unknown of the sensor's, beam_radius_prior.h).

#include <Eigen/Geometry>

#include "vocal/calibration/solver/frame_mounting.h"
#include "vocal/calibration/solver/outline_points_residual.h"

namespace vocal {

// OutlinePointsResidual (a view's edge points in one block, Cauchy's loss within, as the still-pose graph
// holds them) with the board in the sensor's parent frame (FrameMounting). Blocks as CameraViewResidual's
// and the sensor's beam radius (metres, radians: OutlinePointsResidual::withBeam); one residual per point.
struct OutlineViewResidual {
  OutlinePointsResidual on_outline;
  FrameMounting mounting;

  template <typename T>
  bool operator()(const T* xq, const T* xt, const T* yq, const T* yt, const T* sq, const T* st, const T* bq, const T* bt, const T* beam,
                  T* residual) const {
    const T* board[] = {yq, yt, sq, st, bq, bt};
    const auto [q, t] = mounting.boardInSensorParent(board);
    return on_outline.withBeam(xq, xt, q.coeffs().data(), t.data(), beam, residual);
  }
};

}  // namespace vocal
