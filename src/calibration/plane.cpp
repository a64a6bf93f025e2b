#include "vocal/calibration/plane.h"

#include <cmath>
#include <algorithm>
#include <string>

#include "vocal/calibration/point_statistics.h"
#include "vocal/core/errors.h"

namespace vocal {

Plane transformPlane(const Eigen::Isometry3d& a_from_b, const Plane& plane_in_b) {
  Plane plane;
  plane.normal = a_from_b.linear() * plane_in_b.normal;
  plane.offset = plane_in_b.offset - plane.normal.dot(a_from_b.translation());
  return plane;
}

PlaneFit fitPlane(const std::vector<Eigen::Vector3d>& points, const char* what) {
  if (points.size() < 3) {
    throw InputError(std::string(what) + ": a plane needs at least 3 points, got " + std::to_string(points.size()));
  }
  const PrincipalAxes principal = principalAxesOf(points);
  if (principal.spread[1] <= 1e-12 * std::max(principal.spread[0], 1e-300)) {
    throw InputError(std::string(what) + ": the points are collinear, they do not define a plane");
  }
  PlaneFit fit;
  fit.plane.normal = principal.axes.col(2);
  fit.plane.offset = -fit.plane.normal.dot(principal.centroid);
  if (fit.plane.offset < 0.0) {  // face the sensor: the origin is on the positive side
    fit.plane.normal = -fit.plane.normal;
    fit.plane.offset = -fit.plane.offset;
  }
  double squared = 0.0;
  for (const Eigen::Vector3d& p : points) squared += std::pow(fit.plane.signedDistance(p), 2);
  fit.rms = std::sqrt(squared / points.size());
  return fit;
}

}  // namespace vocal
