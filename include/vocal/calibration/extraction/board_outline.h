#pragma once
// Where a range sensor saw the board's edges: each scan line (a lidar ring, a 2D laser's scan, a depth
// camera's pixel row and column) crosses the board between two returns at its ends. The graph holds
// these points on the board's outline (graph_calibration.h), which fixes the board's position within
// its plane when the planes' normals span too little to.

#include <vector>

#include <Eigen/Core>

#include "vocal/calibration/extraction/target_extraction.h"
#include "vocal/calibration/plane.h"

namespace vocal {

// The two end points of every scan line among `points` (the board's returns, sensor frame), each
// moved half a step outward along its line (the edge lies between the last return on the board and
// the first off it) and onto `plane` along its ray (range noise and mixed pixels then do not move it).
// Lines with fewer than 2 returns give none.
std::vector<Eigen::Vector3d> boardOutlinePoints(const std::vector<Eigen::Vector3d>& points, const Plane& plane,
                                                const ScanSpacing& spacing);

// The signed distance of a point in the board's plane (board frame: centred, x along the width) to the
// outline of a width x height rectangle: negative inside, zero on an edge. Templated for Ceres.
template <typename T>
T distanceToOutline(const T& x, const T& y, double half_width, double half_height) {
  using std::abs;
  using std::sqrt;
  const T dx = abs(x) - half_width, dy = abs(y) - half_height;
  if (dx > T(0.0) && dy > T(0.0)) return sqrt(dx * dx + dy * dy);
  return dx > dy ? dx : dy;
}

}  // namespace vocal
