#pragma once
// Plane extraction for depth and lidar sensors: the target's points in a cloud that also holds the
// floor, walls and clutter.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace vocal {

struct TargetExtractionOptions {
  double distance_threshold = 0.015;  // metres from a plane to count as its inlier
  int iterations = 400;               // RANSAC samples per plane
  int max_planes = 6;                 // planes tried, largest first
  double cell_size = 0.08;            // metres: inliers closer than about this form one patch
  double size_slack = 0.15;           // metres a patch may exceed the target's diagonal by
  double min_size_fraction = 0.3;     // of the target's shorter side: a patch's longest extent at least
  int min_points = 30;
  std::uint32_t seed = 1;
};

// The points of the patch that fits the target's size: planes are found by RANSAC, largest first; each
// plane's inliers are split into connected patches; the first patch neither larger than the target
// (its extent against width x height) nor a scrap is returned. Empty when no patch fits.
std::vector<Eigen::Vector3d> extractTargetPoints(const std::vector<Eigen::Vector3d>& cloud, double target_width,
                                                 double target_height, const TargetExtractionOptions& options = {});

}  // namespace vocal
