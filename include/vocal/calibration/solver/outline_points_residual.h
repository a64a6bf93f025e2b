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
  // Per point, where given: its own sigma instead of `sigma` (a 2D laser's scan end, scan_ends.h).
  std::vector<double> point_sigmas = {};

  template <typename T>
  bool operator()(const T* rotation, const T* translation, const T* board_rotation, const T* board_translation, T* residual) const {
    return withBeam(rotation, translation, board_rotation, board_translation, static_cast<const T*>(nullptr), residual);
  }

  // ... with the sensor's beam a disc of radius beam[0] metres plus beam[1] radians times the range (a ray
  // where `beam` is null). A laser's beam is as wide as its exit plus its divergence times the range (a
  // SICK LMS1xx's 8 mm + 15 mrad across) and one that falls partly on the board returns from it, so a scan
  // runs on past the board's edge until its beam's footprint on the board's plane (the disc cast along
  // the ray: wider where the board turns away) no longer touches it: the end's distance to the edge is
  // that footprint's reach across the edge.
  template <typename T>
  bool withBeam(const T* rotation, const T* translation, const T* board_rotation, const T* board_translation, const T* beam,
                T* residual) const {
    using std::abs;
    using std::sqrt;
    const Eigen::Map<const Eigen::Quaternion<T>> q(rotation), q_board(board_rotation);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t(translation), t_board(board_translation);
    // The board's x and y rows of board <- sensor, once: per point a 2x3 product.
    const Eigen::Matrix<T, 3, 3> turn = (q_board.conjugate() * q).toRotationMatrix();
    const Eigen::Matrix<T, 3, 1> offset = q_board.conjugate() * (t - t_board);
    for (std::size_t i = 0; i < points.size(); ++i) {
      const Eigen::Vector3d& p = points[i];
      const T x = turn(0, 0) * p.x() + turn(0, 1) * p.y() + turn(0, 2) * p.z() + offset.x();
      const T y = turn(1, 0) * p.x() + turn(1, 1) * p.y() + turn(1, 2) * p.z() + offset.y();
      T distance = distanceToOutline(x, y, half_width, half_height);
      if (beam) {
        // The edge's outward normal e (board frame) and the ray d: the disc of radius rho across d, cast
        // along d onto the board's plane, reaches rho |f - d (f . d)| across the edge, f = e - z (e . d) / d_z.
        const Eigen::Matrix<T, 3, 1> d = turn * p.normalized().cast<T>();
        const bool side = abs(x) - half_width > abs(y) - half_height;
        Eigen::Matrix<T, 3, 1> e(side ? (x < T(0) ? T(-1) : T(1)) : T(0), side ? T(0) : (y < T(0) ? T(-1) : T(1)), T(0));
        const T dz = abs(d.z()) < T(0.1) ? (d.z() < T(0) ? T(-0.1) : T(0.1)) : d.z();  // at most 10 times the disc
        const Eigen::Matrix<T, 3, 1> f(e.x(), e.y(), -e.dot(d) / dz);
        const Eigen::Matrix<T, 3, 1> across = f - d * f.dot(d);
        distance -= (beam[0] + beam[1] * p.norm()) * sqrt(across.squaredNorm() + T(1e-12));
      }
      residual[i] = cauchyResidual(distance / T(point_sigmas.empty() ? sigma : point_sigmas[i]), loss_sigmas);
    }
    return true;
  }
};

}  // namespace vocal
