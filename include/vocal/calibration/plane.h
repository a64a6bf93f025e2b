#pragma once
// A plane n . x + d = 0 with unit normal n, and the operations calibration needs on it.

#include <vector>

#include <Eigen/Geometry>

namespace vocal {

struct Plane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // unit
  double offset = 0.0;                                // d: n . x + d = 0

  double signedDistance(const Eigen::Vector3d& point) const { return normal.dot(point) + offset; }
};

// The plane expressed in frame a, given a_from_b and the plane in frame b.
Plane transformPlane(const Eigen::Isometry3d& a_from_b, const Plane& plane_in_b);

struct PlaneFit {
  Plane plane;
  double rms = 0.0;  // of the point-to-plane distances
};

// Least-squares plane through the points (smallest singular vector of the centred points), normal
// oriented towards the origin of the points' frame (the sensor). Throws InputError naming `what`
// for fewer than 3 points or collinear points.
PlaneFit fitPlane(const std::vector<Eigen::Vector3d>& points, const char* what);

}  // namespace vocal
