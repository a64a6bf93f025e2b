#pragma once
// Every outline point of one view against the board's outline in one residual block, for both graphs: the
// still-pose graph's with board edges (graph_calibration.h: a range sensor's edge points, the outline a
// camera's pattern pose predicts) and the arm's (a 2D laser's scan ends, outline_view_residual.h). Eigen
// only.

#include <cmath>
#include <vector>

#include <Eigen/Geometry>

#include "vocal/calibration/extraction/board_outline.h"

namespace vocal {

// r times sqrt(log(1 + x) / x), x = (r / c)^2: its square is Cauchy's c^2 log(1 + (r / c)^2), the loss Ceres
// applies to a block of one residual, for residuals that share a block.
template <typename T>
T cauchyResidual(const T& r, double c) {
  using std::log1p;
  using std::sqrt;
  const T x = r * r / T(c * c);
  const T factor = x < T(1e-8) ? T(1.0) - x / T(2.0) : log1p(x) / x;
  return r * sqrt(factor);
}

// Each point (sensor frame) against a width x height board (centred on the board frame, x along the
// width): its distance within the board's plane to the outline (distanceToOutline), in `sigma`s, under
// Cauchy's loss of `loss_sigmas`. The sensor-to-board turn is composed once per view rather than once per
// point (behind joints the chain too: a head's depth camera brings hundreds of edge points a view; per
// point, the outline took 8x the whole solve; a pan-tilt head described as rigid took 95 s with its rigid
// sensors' points one block each, 22 s per view). Blocks: the sensor's and the board's rotation and
// translation in one frame; one residual per point.
struct OutlinePointsResidual {
  std::vector<Eigen::Vector3d> points;
  double sigma, half_width, half_height, loss_sigmas;

  template <typename T>
  bool operator()(const T* rotation, const T* translation, const T* board_rotation, const T* board_translation, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q(rotation), q_board(board_rotation);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t(translation), t_board(board_translation);
    // The board's x and y rows of board <- sensor, once: per point a 2x3 product.
    const Eigen::Matrix<T, 3, 3> turn = (q_board.conjugate() * q).toRotationMatrix();
    const Eigen::Matrix<T, 3, 1> offset = q_board.conjugate() * (t - t_board);
    for (std::size_t i = 0; i < points.size(); ++i) {
      const Eigen::Vector3d& p = points[i];
      const T x = turn(0, 0) * p.x() + turn(0, 1) * p.y() + turn(0, 2) * p.z() + offset.x();
      const T y = turn(1, 0) * p.x() + turn(1, 1) * p.y() + turn(1, 2) * p.z() + offset.y();
      residual[i] = cauchyResidual(distanceToOutline(x, y, half_width, half_height) / T(sigma), loss_sigmas);
    }
    return true;
  }
};

}  // namespace vocal
