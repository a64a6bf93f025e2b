#include "vocal/calibration/solver/scan_ends.h"

#include <algorithm>
#include <cmath>

#include "vocal/calibration/point_statistics.h"

namespace vocal {

namespace {
// How far along its line a step between beams moves an end, at most (1 / cos of the angle between the
// beam and the line's normal in the scan plane: a board turned away stretches the steps along it).
constexpr double kMaxScanEndStretch = 5.0;
}  // namespace

double beamStep(const std::vector<Eigen::Vector3d>& points) {
  std::vector<double> bearings, steps;
  for (const Eigen::Vector3d& p : points) bearings.push_back(std::atan2(p.y(), p.x()));
  std::sort(bearings.begin(), bearings.end());
  // Several scans' points on the same beams share their bearings: those are no step.
  for (std::size_t i = 1; i < bearings.size(); ++i)
    if (bearings[i] - bearings[i - 1] > 1e-5) steps.push_back(bearings[i] - bearings[i - 1]);
  return median(steps);
}

int scansOfPooledEnds(const std::vector<Eigen::Vector3d>& ends) {
  std::vector<double> bearings;
  for (const Eigen::Vector3d& p : ends) bearings.push_back(std::atan2(p.y(), p.x()));
  std::sort(bearings.begin(), bearings.end());
  int distinct = bearings.empty() ? 0 : 1;
  for (std::size_t i = 1; i < bearings.size(); ++i) distinct += bearings[i] - bearings[i - 1] > 1e-5;
  return distinct == 0 ? 1 : std::max(1, static_cast<int>(std::lround(static_cast<double>(ends.size()) / distinct)));
}

LaserScanEnds scanEndsOf(const std::vector<Eigen::Vector3d>& ends, const std::vector<Eigen::Vector3d>& line_points, int pooled, int scans) {
  constexpr double floor = kLeastScanEndSigma;
  LaserScanEnds out;
  if (line_points.size() < 3) return out;
  pooled = std::max(pooled, 1), scans = std::max(scans, 1);
  const double step = beamStep(line_points);
  // The scan's line (in its plane) and the points' scatter across it: where one scan's fit puts the line
  // at a distance d along it from the middle is off by sigma sqrt(1 / m + d^2 / S) across it (m points a
  // scan, S the sum of their squared distances along it), which moves an end that far times tan of its
  // beam's angle to the line's normal along the line.
  const PrincipalAxes line = principalAxesOf(line_points);
  const Eigen::Vector3d along = Eigen::Vector3d(line.axes(0, 0), line.axes(1, 0), 0.0).normalized();
  const Eigen::Vector3d across(-along.y(), along.x(), 0.0);  // the line's normal in the scan plane
  double squares = 0.0, spread_along = 0.0;
  for (const Eigen::Vector3d& p : line_points) {
    squares += std::pow(across.dot(p - line.centroid), 2);
    spread_along += std::pow(along.dot(p - line.centroid), 2);
  }
  const double m = static_cast<double>(line_points.size()) / pooled;
  const double scatter = std::sqrt(squares / (line_points.size() - 2));
  for (const Eigen::Vector3d& end : ends) {
    const double cosine = std::max(std::abs(across.dot(end.normalized())), 1.0 / kMaxScanEndStretch);
    const double stretch = 1.0 / cosine, tangent = std::sqrt(stretch * stretch - 1.0);
    const double d = along.dot(end - line.centroid);
    const double fit = scatter * std::sqrt(1.0 / m + d * d * pooled / spread_along) * tangent;
    const double quantum = step * end.norm() * stretch / std::sqrt(12.0);
    out.points.push_back(end);
    // The beams' step is the same for every scan of a still board: shared, counted once over the scans;
    // the fit is each scan's own.
    out.sigmas.push_back(std::sqrt(scans * (quantum * quantum + floor * floor) + fit * fit));
  }
  return out;
}

OutlinePointsResidual scanEndsOnOutline(const LaserScanEnds& ends, double width, double height, double loss_sigmas) {
  return {ends.points, kLeastScanEndSigma, 0.5 * width, 0.5 * height, loss_sigmas, ends.sigmas};
}

}  // namespace vocal
