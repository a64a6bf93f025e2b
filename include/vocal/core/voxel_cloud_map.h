#pragma once
// A coloured point map fused from many frames: one point per occupied voxel (the mean position and
// colour of what fell into it), so a long run stays bounded in memory and cheap to draw.

#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include <Eigen/Geometry>

#include "vocal/core/colored_point.h"

namespace vocal {

class VoxelCloudMap {
 public:
  // Throws InputError for a voxel size that is not positive or a zero voxel budget.
  VoxelCloudMap(double voxel_size, std::size_t max_voxels);

  // Adds points given in a frame placed at `map_from_points`. Points that would open a voxel beyond
  // the budget are dropped and counted.
  void add(const std::vector<ColoredPoint>& points, const Eigen::Isometry3d& map_from_points);
  std::vector<ColoredPoint> points() const;
  std::size_t voxels() const { return voxels_.size(); }
  std::size_t droppedPoints() const { return dropped_; }
  void clear();

 private:
  struct Voxel {
    Eigen::Vector3d position_sum = Eigen::Vector3d::Zero();
    Eigen::Vector3d color_sum = Eigen::Vector3d::Zero();
    std::uint32_t count = 0;
  };
  double voxel_size_;
  std::size_t max_voxels_;
  std::unordered_map<std::uint64_t, Voxel> voxels_;
  std::size_t dropped_ = 0;
};

}  // namespace vocal
