#include "vocal/calibration/extraction/board_outline.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace vocal {

namespace {
// A return's direction as (along its scan line, across the lines): a lidar's azimuth (relative to the
// points' mean, so a board behind the sensor does not wrap at +-pi) and elevation (a scattered
// pattern's too); a depth camera's x / z and y / z (constant along a pixel row and column).
struct Directions {
  ScanPattern pattern;
  double reference_azimuth = 0.0;

  Eigen::Vector2d of(const Eigen::Vector3d& p) const {
    if (pattern == ScanPattern::kPinhole) return {p.x() / p.z(), p.y() / p.z()};
    return {std::remainder(std::atan2(p.y(), p.x()) - reference_azimuth, 2.0 * M_PI), std::atan2(p.z(), p.head<2>().norm())};
  }
  Eigen::Vector3d ray(const Eigen::Vector2d& d) const {
    if (pattern == ScanPattern::kPinhole) return {d.x(), d.y(), 1.0};
    const double azimuth = d.x() + reference_azimuth;
    return {std::cos(d.y()) * std::cos(azimuth), std::cos(d.y()) * std::sin(azimuth), std::sin(d.y())};
  }
};

// A line's end moved `outward` along coordinate `along`, onto the plane along its ray.
void addEnd(Eigen::Vector2d end, int along, double outward, const Directions& frame, const Plane& plane,
            std::vector<Eigen::Vector3d>* outline) {
  end[along] += outward;
  const Eigen::Vector3d ray = frame.ray(end);
  const double facing = plane.normal.dot(ray);
  if (std::abs(facing) < 1e-9) return;
  const double scale = -plane.offset / facing;
  if (scale > 0.0) outline->push_back(scale * ray);
}

// Lines along coordinate `along` (0 or 1), grouped by the other coordinate: a new line where it jumps
// by more than half the spacing between lines. Each line's ends go out by half a step along it.
void addLineEnds(const std::vector<Eigen::Vector2d>& directions, int along, double step_along, double step_across,
                 const Directions& frame, const Plane& plane, std::vector<Eigen::Vector3d>* outline) {
  const int across = 1 - along;
  std::vector<Eigen::Vector2d> sorted = directions;
  std::sort(sorted.begin(), sorted.end(), [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a[across] < b[across]; });
  std::size_t first = 0;
  for (std::size_t i = 1; i <= sorted.size(); ++i) {
    if (i < sorted.size() && sorted[i][across] - sorted[i - 1][across] <= 0.5 * step_across) continue;
    if (i - first >= 2) {
      const auto [low, high] = std::minmax_element(sorted.begin() + first, sorted.begin() + i,
                                                   [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a[along] < b[along]; });
      addEnd(*low, along, -0.5 * step_along, frame, plane, outline);
      addEnd(*high, along, 0.5 * step_along, frame, plane, outline);
    }
    first = i;
  }
}

// A pattern without scan lines (a Livox's rosette): rows (or columns) `bin` wide stand in for lines;
// each one's extreme returns go out by half the mean spacing.
void addBinnedEnds(const std::vector<Eigen::Vector2d>& directions, int along, double bin, double step_along, const Directions& frame,
                   const Plane& plane, std::vector<Eigen::Vector3d>* outline) {
  struct Ends {
    Eigen::Vector2d low, high;  // the returns lowest and highest along
    int count = 0;
  };
  std::map<long, Ends> bins;
  for (const Eigen::Vector2d& d : directions) {
    Ends& ends = bins.try_emplace(static_cast<long>(std::floor(d[1 - along] / bin)), Ends{d, d}).first->second;
    if (d[along] < ends.low[along]) ends.low = d;
    if (d[along] > ends.high[along]) ends.high = d;
    ++ends.count;
  }
  for (const auto& [key, ends] : bins) {
    if (ends.count < 2) continue;
    addEnd(ends.low, along, -0.5 * step_along, frame, plane, outline);
    addEnd(ends.high, along, 0.5 * step_along, frame, plane, outline);
  }
}
}  // namespace

std::vector<Eigen::Vector3d> boardOutlinePoints(const std::vector<Eigen::Vector3d>& points, const Plane& plane,
                                                const ScanSpacing& spacing) {
  std::vector<Eigen::Vector3d> outline;
  if (points.size() < 2) return outline;
  Directions frame{spacing.pattern};
  if (spacing.pattern != ScanPattern::kPinhole) {
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const Eigen::Vector3d& p : points) mean += p.head<2>().normalized();
    frame.reference_azimuth = std::atan2(mean.y(), mean.x());
  }
  std::vector<Eigen::Vector2d> directions;
  directions.reserve(points.size());
  for (const Eigen::Vector3d& p : points) directions.push_back(frame.of(p));
  // No scan lines: rows and columns two mean spacings wide.
  if (spacing.pattern == ScanPattern::kScattered) {
    addBinnedEnds(directions, 0, 2.0 * spacing.vertical, spacing.horizontal, frame, plane, &outline);
    addBinnedEnds(directions, 1, 2.0 * spacing.horizontal, spacing.vertical, frame, plane, &outline);
    return outline;
  }
  // A 2D laser's one line has no spacing across: any positive step keeps it whole.
  const double across = spacing.vertical > 0.0 ? spacing.vertical : 1.0;
  addLineEnds(directions, 0, spacing.horizontal, across, frame, plane, &outline);
  // A depth camera's columns give the top and bottom edges that its rows only end on at the corners.
  if (spacing.pattern == ScanPattern::kPinhole) addLineEnds(directions, 1, spacing.vertical, spacing.horizontal, frame, plane, &outline);
  return outline;
}

}  // namespace vocal
