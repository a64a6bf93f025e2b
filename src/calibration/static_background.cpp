#include "vocal/calibration/static_background.h"

#include <algorithm>
#include <cmath>
#include <unordered_set>

#include <Eigen/Geometry>

#include "vocal/calibration/point_statistics.h"

namespace vocal {

StaticBackground::Summary StaticBackground::summarise(const std::vector<Eigen::Vector3d>& points) {
  const PrincipalAxes principal = principalAxesOf(points);
  // A 2D scan's segment is a line in the scan plane (z = 0): its normal is the in-plane perpendicular.
  const bool line = std::all_of(points.begin(), points.end(), [](const Eigen::Vector3d& p) { return p.z() == 0.0; });
  const Eigen::Vector3d normal =
      line ? principal.axes.col(0).cross(Eigen::Vector3d::UnitZ()).normalized() : Eigen::Vector3d(principal.axes.col(2));
  return {normal, principal.centroid};
}

std::uint64_t StaticBackground::cellOf(const Eigen::Vector3d& centre) const {
  std::uint64_t key = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const auto cell = static_cast<std::int64_t>(std::floor(centre[axis] / options_.centre)) + (1 << 20);
    key = (key << 21) | (static_cast<std::uint64_t>(cell) & ((1u << 21) - 1));
  }
  return key;
}

void StaticBackground::addMessage(const std::vector<Summary>& segments) {
  for (const Summary& segment : segments) cells_[cellOf(segment.centre)].push_back({segment, messages_});
  ++messages_;
}

double StaticBackground::recurrence(const Summary& query) const {
  if (messages_ == 0) return 0.0;
  const double cos_angle = std::cos(options_.angle);
  constexpr int kParts = 10;
  std::unordered_set<int> parts;
  const Eigen::Vector3d cell = (query.centre / options_.centre).array().floor();
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dz = -1; dz <= 1; ++dz) {
        const auto found = cells_.find(cellOf((cell + Eigen::Vector3d(dx + 0.5, dy + 0.5, dz + 0.5)) * options_.centre));
        if (found == cells_.end()) continue;
        for (const Seen& seen : found->second) {
          const Summary& s = seen.segment;
          if (std::abs(s.normal.dot(query.normal)) >= cos_angle && std::abs(query.normal.dot(s.centre - query.centre)) <= options_.offset &&
              (s.centre - query.centre).norm() <= options_.centre) {
            parts.insert(seen.message * kParts / messages_);
          }
        }
      }
  return static_cast<double>(parts.size()) / std::min(kParts, messages_);
}

}  // namespace vocal
