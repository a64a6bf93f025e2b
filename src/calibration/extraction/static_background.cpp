#include "vocal/calibration/extraction/static_background.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "vocal/calibration/point_statistics.h"

namespace vocal {

StaticBackground::Summary StaticBackground::summarise(const std::vector<Eigen::Vector3d>& points) {
  const PrincipalAxes principal = principalAxesOf(points);
  // A 2D scan's segment is a line in the scan plane (z = 0): its normal is the in-plane perpendicular.
  const bool line = std::all_of(points.begin(), points.end(), [](const Eigen::Vector3d& p) { return p.z() == 0.0; });
  const Eigen::Vector3d normal =
      line ? principal.axes.col(0).cross(Eigen::Vector3d::UnitZ()).normalized() : Eigen::Vector3d(principal.axes.col(2));
  Summary summary;
  summary.normal = normal;
  summary.centre = principal.centroid;
  summary.along = normal.unitOrthogonal();
  return summary;
}

std::uint64_t StaticBackground::cellOf(const Eigen::Vector3d& centre) const {
  std::uint64_t key = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const auto cell = static_cast<std::int64_t>(std::floor(centre[axis] / options_.centre)) + (1 << 20);
    key = (key << 21) | (static_cast<std::uint64_t>(cell) & ((1u << 21) - 1));
  }
  return key;
}

void StaticBackground::addMessage(const std::vector<Summary>& segments, const std::vector<SurfacePatch>& surfaces) {
  for (const Summary& segment : segments) cells_[cellOf(segment.centre)].push_back({segment, messages_});
  // The same rectangle (its longer side's direction and length, its shorter side, its centre and plane)
  // as one seen before: another message of that surface.
  const auto longer = [](const SurfacePatch& p) { return p.half_along >= p.half_across ? p.along : Eigen::Vector3d(p.normal.cross(p.along)); };
  const auto sides = [](const SurfacePatch& p) { return Eigen::Vector2d(std::max(p.half_along, p.half_across), std::min(p.half_along, p.half_across)); };
  for (const SurfacePatch& surface : surfaces) {
    const auto same = std::find_if(surfaces_.begin(), surfaces_.end(), [&](const SeenSurface& seen) {
      return covers(seen.patch, surface) && (seen.patch.centre - surface.centre).norm() <= 0.5 * options_.centre &&
             (sides(seen.patch) - sides(surface)).cwiseAbs().maxCoeff() <= 0.5 * options_.centre &&
             std::abs(longer(seen.patch).dot(longer(surface))) >= std::cos(options_.angle);
    });
    if (same == surfaces_.end()) {
      surfaces_.push_back({surface, {messages_}});
    } else if (same->messages.back() != messages_) {
      same->messages.push_back(messages_);
    }
  }
  ++messages_;
}

bool StaticBackground::covers(const SurfacePatch& seen, const Summary& query) const {
  return std::abs(seen.normal.dot(query.normal)) >= std::cos(options_.angle) &&
         std::abs(seen.normal.dot(query.centre - seen.centre)) <= options_.offset && seen.inPlaneDistanceTo(query.centre) <= options_.centre;
}

int StaticBackground::partsWith(const Summary& query) const {
  const int parts = partsOfTheSession();
  const auto part_of = [&](int message) { return message * parts / messages_; };
  // Messages m of part p: m * parts / messages_ == p, i.e. from ceil(p * messages_ / parts) on.
  const auto first_of = [&](int part) { return (part * messages_ + parts - 1) / parts; };
  std::vector<char> counted(messages_, 0);
  std::vector<int> part_matches(parts, 0);
  const auto count = [&](int message) {
    if (!counted[message]) counted[message] = 1, ++part_matches[part_of(message)];
  };
  const Eigen::Vector3d cell = (query.centre / options_.centre).array().floor();
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dz = -1; dz <= 1; ++dz) {
        const auto found = cells_.find(cellOf((cell + Eigen::Vector3d(dx + 0.5, dy + 0.5, dz + 0.5)) * options_.centre));
        if (found == cells_.end()) continue;
        for (const Seen& seen : found->second)
          if (covers(seen.segment, query)) count(seen.message);
      }
  for (const SeenSurface& surface : surfaces_)
    if (covers(surface.patch, query))
      for (int message : surface.messages) count(message);
  int seen = 0;
  for (int p = 0; p < parts; ++p) seen += part_matches[p] > 0 && part_matches[p] >= options_.part_share * (first_of(p + 1) - first_of(p));
  return seen;
}

double StaticBackground::recurrence(const Summary& query) const {
  if (messages_ == 0) return 0.0;
  return static_cast<double>(partsWith(query)) / partsOfTheSession();
}

}  // namespace vocal
