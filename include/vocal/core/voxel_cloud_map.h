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

  // Adds points given in a frame placed at `map_from_points`. At the budget the voxels no add() has
  // touched for longest go first (a tenth of the budget at a time), so a long run keeps the most
  // recently seen surfaces in bounded memory; points that would open a voxel beyond the budget when
  // every voxel was touched by this same add() are dropped and counted.
  void add(const std::vector<ColoredPoint>& points, const Eigen::Isometry3d& map_from_points);
  std::vector<ColoredPoint> points() const;
  std::size_t voxels() const { return voxels_.size(); }
  std::size_t droppedPoints() const { return dropped_; }
  std::size_t evictedVoxels() const { return evicted_; }
  void clear();

 private:
  struct Voxel {
    Eigen::Vector3d position_sum = Eigen::Vector3d::Zero();
    Eigen::Vector3d color_sum = Eigen::Vector3d::Zero();
    std::uint32_t count = 0;
    std::uint32_t last_add = 0;  // the add() that last touched it
  };
  // Removes the least recently touched voxels (not those of the add() under way) down to 90 % of the budget.
  void evictOldest();
  double voxel_size_;
  std::size_t max_voxels_;
  std::unordered_map<std::uint64_t, Voxel> voxels_;
  std::size_t dropped_ = 0, evicted_ = 0;
  std::uint32_t adds_ = 0;
};

}  // namespace vocal
