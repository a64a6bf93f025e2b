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
// plane's inliers are split into connected patches; the first plane whose largest patch is neither
// larger than the target (its extent against width x height) nor a scrap gives the result. Empty when
// no plane fits.
std::vector<Eigen::Vector3d> extractTargetPoints(const std::vector<Eigen::Vector3d>& cloud, double target_width,
                                                 double target_height, const TargetExtractionOptions& options = {});

// The target's segment in a full 2D scan (points in the scan plane z = 0, in scan order): RANSAC lines,
// longest first; each line's inliers split where consecutive points are more than cell_size apart or
// something else is in between; the first line whose longest run fits the target (at most its diagonal
// + slack, at least min_size_fraction of its shorter side) gives the result. Empty when none fits.
std::vector<Eigen::Vector3d> extractTargetSegment(const std::vector<Eigen::Vector3d>& scan, double target_width,
                                                  double target_height, const TargetExtractionOptions& options = {});

}  // namespace vocal
