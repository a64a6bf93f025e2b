#include "vocal/core/voxel_cloud_map.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "vocal/core/errors.h"

namespace vocal {

namespace {
// 21 bits per axis (+-1e6 voxels) packed into one key.
std::uint64_t voxelKey(const Eigen::Vector3d& p, double voxel_size) {
  constexpr std::int64_t kOffset = 1 << 20;
  constexpr std::uint64_t kMask = (1u << 21) - 1;
  std::uint64_t key = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const auto cell = static_cast<std::int64_t>(std::floor(p[axis] / voxel_size)) + kOffset;
    key = (key << 21) | (static_cast<std::uint64_t>(cell) & kMask);
  }
  return key;
}
}  // namespace

VoxelCloudMap::VoxelCloudMap(double voxel_size, std::size_t max_voxels) : voxel_size_(voxel_size), max_voxels_(max_voxels) {
  if (!(voxel_size > 0.0) || !std::isfinite(voxel_size)) {
    throw InputError("voxel cloud map: voxel size " + std::to_string(voxel_size) + " m must be positive");
  }
  if (max_voxels == 0) throw InputError("voxel cloud map: the voxel budget must be at least 1");
}

void VoxelCloudMap::add(const std::vector<ColoredPoint>& points, const Eigen::Isometry3d& map_from_points) {
  ++adds_;
  for (const ColoredPoint& point : points) {
    const Eigen::Vector3d p = map_from_points * point.position.cast<double>();
    const std::uint64_t key = voxelKey(p, voxel_size_);
    auto voxel = voxels_.find(key);
    if (voxel == voxels_.end()) {
      if (voxels_.size() >= max_voxels_) evictOldest();
      if (voxels_.size() >= max_voxels_) {
        ++dropped_;
        continue;
      }
      voxel = voxels_.emplace(key, Voxel{}).first;
    }
    voxel->second.position_sum += p;
    voxel->second.color_sum += Eigen::Vector3d(point.color.r, point.color.g, point.color.b);
    ++voxel->second.count;
    voxel->second.last_add = adds_;
  }
}

void VoxelCloudMap::evictOldest() {
  std::vector<std::uint32_t> ages;
  ages.reserve(voxels_.size());
  for (const auto& entry : voxels_)
    if (entry.second.last_add != adds_) ages.push_back(entry.second.last_add);
  if (ages.empty()) return;
  // The add() at which the oldest tenth of the budget ends; all voxels last touched up to it go.
  const std::size_t wanted = std::min(ages.size(), std::max<std::size_t>(1, max_voxels_ / 10));
  std::nth_element(ages.begin(), ages.begin() + (wanted - 1), ages.end());
  const std::uint32_t cutoff = ages[wanted - 1];
  for (auto it = voxels_.begin(); it != voxels_.end();) {
    if (it->second.last_add <= cutoff && it->second.last_add != adds_) {
      it = voxels_.erase(it);
      ++evicted_;
    } else {
      ++it;
    }
  }
}

std::vector<ColoredPoint> VoxelCloudMap::points() const {
  std::vector<ColoredPoint> out;
  out.reserve(voxels_.size());
  for (const auto& entry : voxels_) {
    const Voxel& v = entry.second;
    const Eigen::Vector3d color = v.color_sum / v.count;
    out.push_back({(v.position_sum / v.count).cast<float>(),
                   Rgb8{static_cast<std::uint8_t>(std::lround(color.x())), static_cast<std::uint8_t>(std::lround(color.y())),
                        static_cast<std::uint8_t>(std::lround(color.z()))}});
  }
  return out;
}

void VoxelCloudMap::clear() {
  voxels_.clear();
  dropped_ = evicted_ = 0;
}

}  // namespace vocal
