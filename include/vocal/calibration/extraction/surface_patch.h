#pragma once
// A planar piece of what a range sensor sees: its plane and the rectangle it covers there. A board
// candidate is summarised by its centre alone (no extent); a wall, the floor or a large piece of
// furniture by its whole rectangle, so a board-sized part of it (the rest hidden by the person in
// front) can be recognised as lying on it. A 2D scan's piece is a line in its plane z = 0: the
// rectangle stands upright on the scan, its normal the line's in-plane perpendicular.

#include <algorithm>
#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace vocal {

struct SurfacePatch {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ(), centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d along = Eigen::Vector3d::UnitX();  // in the plane: the direction of the first side
  double half_along = 0.0, half_across = 0.0;        // half the rectangle's sides

  // How far `point`, projected into the plane, lies outside the rectangle (0 inside).
  double inPlaneDistanceTo(const Eigen::Vector3d& point) const {
    const Eigen::Vector3d d = point - centre;
    const double outside_along = std::max(0.0, std::abs(along.dot(d)) - half_along);
    const double outside_across = std::max(0.0, std::abs(normal.cross(along).dot(d)) - half_across);
    return std::hypot(outside_along, outside_across);
  }
};

}  // namespace vocal
