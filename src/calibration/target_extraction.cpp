#include "vocal/calibration/target_extraction.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <tuple>

#include <Eigen/Eigenvalues>

#include "vocal/calibration/plane.h"

namespace vocal {

namespace {
using Cell = std::tuple<long, long, long>;

Cell cellOf(const Eigen::Vector3d& p, double size) {
  return {static_cast<long>(std::floor(p.x() / size)), static_cast<long>(std::floor(p.y() / size)),
          static_cast<long>(std::floor(p.z() / size))};
}

// Connected patches of the given points: cells of `size` touching in any of 26 directions.
std::vector<std::vector<Eigen::Vector3d>> patchesOf(const std::vector<Eigen::Vector3d>& points, double size) {
  std::map<Cell, std::vector<std::size_t>> cells;
  for (std::size_t i = 0; i < points.size(); ++i) cells[cellOf(points[i], size)].push_back(i);
  std::map<Cell, bool> visited;
  std::vector<std::vector<Eigen::Vector3d>> patches;
  for (const auto& start : cells) {
    if (visited[start.first]) continue;
    std::vector<Eigen::Vector3d> patch;
    std::vector<Cell> queue = {start.first};
    visited[start.first] = true;
    while (!queue.empty()) {
      const Cell cell = queue.back();
      queue.pop_back();
      for (std::size_t i : cells.at(cell)) patch.push_back(points[i]);
      for (long dx = -1; dx <= 1; ++dx)
        for (long dy = -1; dy <= 1; ++dy)
          for (long dz = -1; dz <= 1; ++dz) {
            const Cell next{std::get<0>(cell) + dx, std::get<1>(cell) + dy, std::get<2>(cell) + dz};
            if (cells.count(next) && !visited[next]) {
              visited[next] = true;
              queue.push_back(next);
            }
          }
    }
    patches.push_back(std::move(patch));
  }
  std::sort(patches.begin(), patches.end(), [](const auto& a, const auto& b) { return a.size() > b.size(); });
  return patches;
}

// Extent of a planar patch along its two principal in-plane directions, longest first.
Eigen::Vector2d extentOf(const std::vector<Eigen::Vector3d>& patch) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : patch) mean += p;
  mean /= patch.size();
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& p : patch) scatter += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter);
  Eigen::Vector2d low(1e300, 1e300), high(-1e300, -1e300);
  for (const Eigen::Vector3d& p : patch) {
    const Eigen::Vector2d q((p - mean).dot(eigen.eigenvectors().col(2)), (p - mean).dot(eigen.eigenvectors().col(1)));
    low = low.cwiseMin(q);
    high = high.cwiseMax(q);
  }
  return high - low;
}
}  // namespace

std::vector<Eigen::Vector3d> extractTargetPoints(const std::vector<Eigen::Vector3d>& cloud, double target_width,
                                                 double target_height, const TargetExtractionOptions& options) {
  std::mt19937 rng(options.seed);
  std::vector<Eigen::Vector3d> remaining = cloud;
  const double longest = std::max(target_width, target_height), shortest = std::min(target_width, target_height);
  for (int plane_index = 0; plane_index < options.max_planes && static_cast<int>(remaining.size()) >= options.min_points;
       ++plane_index) {
    // RANSAC: the plane through three random points with the most inliers.
    std::uniform_int_distribution<std::size_t> pick(0, remaining.size() - 1);
    Plane best;
    std::size_t best_count = 0;
    for (int iteration = 0; iteration < options.iterations; ++iteration) {
      const Eigen::Vector3d& a = remaining[pick(rng)];
      const Eigen::Vector3d& b = remaining[pick(rng)];
      const Eigen::Vector3d& c = remaining[pick(rng)];
      const Eigen::Vector3d normal = (b - a).cross(c - a);
      if (normal.norm() < 1e-9) continue;
      Plane plane{normal.normalized(), 0.0};
      plane.offset = -plane.normal.dot(a);
      std::size_t count = 0;
      for (const Eigen::Vector3d& p : remaining) count += std::abs(plane.signedDistance(p)) < options.distance_threshold;
      if (count > best_count) best_count = count, best = plane;
    }
    if (static_cast<int>(best_count) < options.min_points) break;
    std::vector<Eigen::Vector3d> inliers, outliers;
    for (const Eigen::Vector3d& p : remaining) {
      (std::abs(best.signedDistance(p)) < options.distance_threshold ? inliers : outliers).push_back(p);
    }
    // Only the plane's largest patch is a candidate: smaller pieces of a floor or wall cut up by
    // shadows would otherwise pass for the target.
    std::vector<std::vector<Eigen::Vector3d>> patches = patchesOf(inliers, options.cell_size);
    if (static_cast<int>(patches.front().size()) >= options.min_points) {
      const Eigen::Vector2d extent = extentOf(patches.front());
      const bool not_larger = extent[0] <= std::hypot(target_width, target_height) + options.size_slack &&
                              extent[1] <= longest + options.size_slack;
      const bool not_scrap = extent[0] >= options.min_size_fraction * shortest;
      if (not_larger && not_scrap) return patches.front();
    }
    remaining = std::move(outliers);
  }
  return {};
}

std::vector<Eigen::Vector3d> extractTargetSegment(const std::vector<Eigen::Vector3d>& scan, double target_width,
                                                  double target_height, const TargetExtractionOptions& options) {
  std::mt19937 rng(options.seed);
  std::vector<Eigen::Vector3d> remaining = scan;
  const double diagonal = std::hypot(target_width, target_height);
  const double shortest = std::min(target_width, target_height);
  for (int line_index = 0; line_index < options.max_planes && static_cast<int>(remaining.size()) >= 10; ++line_index) {
    std::uniform_int_distribution<std::size_t> pick(0, remaining.size() - 1);
    Eigen::Vector2d best_point = Eigen::Vector2d::Zero(), best_normal = Eigen::Vector2d::UnitX();
    std::size_t best_count = 0;
    for (int iteration = 0; iteration < options.iterations; ++iteration) {
      const Eigen::Vector2d a = remaining[pick(rng)].head<2>(), b = remaining[pick(rng)].head<2>();
      if ((b - a).norm() < 1e-6) continue;
      const Eigen::Vector2d normal = Eigen::Vector2d(-(b - a).y(), (b - a).x()).normalized();
      std::size_t count = 0;
      for (const Eigen::Vector3d& p : remaining) count += std::abs(normal.dot(p.head<2>() - a)) < options.distance_threshold;
      if (count > best_count) best_count = count, best_point = a, best_normal = normal;
    }
    if (best_count < 10) break;
    // Runs of consecutive inliers (scan order) without gaps wider than cell_size.
    std::vector<std::vector<Eigen::Vector3d>> runs(1);
    std::vector<Eigen::Vector3d> outliers;
    for (const Eigen::Vector3d& p : remaining) {
      if (std::abs(best_normal.dot(p.head<2>() - best_point)) >= options.distance_threshold) {
        outliers.push_back(p);
        if (!runs.back().empty()) runs.emplace_back();
        continue;
      }
      if (!runs.back().empty() && (p - runs.back().back()).norm() > options.cell_size) runs.emplace_back();
      runs.back().push_back(p);
    }
    // Only the line's longest run is a candidate (a wall seen at a grazing angle breaks into short runs).
    const auto run = std::max_element(runs.begin(), runs.end(), [](const auto& a, const auto& b) { return a.size() < b.size(); });
    if (run->size() >= 10) {
      const double length = (run->back() - run->front()).norm();
      if (length <= diagonal + options.size_slack && length >= options.min_size_fraction * shortest) return *run;
    }
    remaining = std::move(outliers);
  }
  return {};
}

}  // namespace vocal
