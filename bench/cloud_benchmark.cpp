// vocal's own point-cloud code against PCL's, on what the odometry nodelet does with clouds: fusing
// frames into a voxel map (VoxelCloudMap against pcl::VoxelGrid re-filtering the growing map) and
// packing a cloud into a PointCloud2 (toPointCloud2 against pcl::PointCloud + pcl::toROSMsg).
// The issue asks for PCL where it does as well; these numbers decide.

#include <cmath>
#include <vector>

#include <benchmark/benchmark.h>
#include <pcl/common/transforms.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl_conversions/pcl_conversions.h>

#include "vocal/core/voxel_cloud_map.h"
#include "vocal/nodelets/message_conversions.h"

namespace {
constexpr double kVoxel = 0.02;

// A 320x240 depth camera's view of a room corner 2-3 m away, coloured by position.
std::vector<vocal::ColoredPoint> frameView() {
  std::vector<vocal::ColoredPoint> points;
  for (int v = 0; v < 240; ++v) {
    for (int u = 0; u < 320; ++u) {
      const double x = (u - 160) / 262.5, y = (v - 120) / 262.5;
      const double z = 2.0 + 0.5 * std::abs(x) + 0.2 * y;
      points.push_back({Eigen::Vector3f(x * z, y * z, z), vocal::Rgb8{static_cast<std::uint8_t>(u % 256), static_cast<std::uint8_t>(v), 90}});
    }
  }
  return points;
}

Eigen::Isometry3d poseOf(int frame) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(0.01 * frame, 0.0, 0.005 * frame);
  pose.linear() = Eigen::AngleAxisd(0.005 * frame, Eigen::Vector3d::UnitY()).toRotationMatrix();
  return pose;
}

pcl::PointCloud<pcl::PointXYZRGB> toPcl(const std::vector<vocal::ColoredPoint>& points) {
  pcl::PointCloud<pcl::PointXYZRGB> cloud;
  cloud.reserve(points.size());
  for (const vocal::ColoredPoint& p : points) {
    pcl::PointXYZRGB q(p.color.r, p.color.g, p.color.b);
    q.x = p.position.x(), q.y = p.position.y(), q.z = p.position.z();
    cloud.push_back(q);
  }
  return cloud;
}

// 30 frames fused, then the map read out (what the nodelet publishes).
void BM_FuseFrames_VoxelCloudMap(benchmark::State& state) {
  const std::vector<vocal::ColoredPoint> view = frameView();
  std::size_t voxels = 0;
  for (auto _ : state) {
    vocal::VoxelCloudMap map(kVoxel, 2000000);
    for (int frame = 0; frame < 30; ++frame) map.add(view, poseOf(frame));
    voxels = map.points().size();
    benchmark::DoNotOptimize(voxels);
  }
  state.counters["voxels"] = static_cast<double>(voxels);
}
BENCHMARK(BM_FuseFrames_VoxelCloudMap)->Unit(benchmark::kMillisecond);

void BM_FuseFrames_PclVoxelGrid(benchmark::State& state) {
  const pcl::PointCloud<pcl::PointXYZRGB> view = toPcl(frameView());
  std::size_t voxels = 0;
  for (auto _ : state) {
    pcl::PointCloud<pcl::PointXYZRGB>::Ptr map(new pcl::PointCloud<pcl::PointXYZRGB>);
    for (int frame = 0; frame < 30; ++frame) {
      pcl::PointCloud<pcl::PointXYZRGB> moved;
      pcl::transformPointCloud(view, moved, poseOf(frame).matrix().cast<float>());
      *map += moved;
      pcl::VoxelGrid<pcl::PointXYZRGB> grid;
      grid.setLeafSize(kVoxel, kVoxel, kVoxel);
      grid.setInputCloud(map);
      pcl::PointCloud<pcl::PointXYZRGB>::Ptr filtered(new pcl::PointCloud<pcl::PointXYZRGB>);
      grid.filter(*filtered);
      map = filtered;
    }
    voxels = map->size();
    benchmark::DoNotOptimize(voxels);
  }
  state.counters["voxels"] = static_cast<double>(voxels);
}
BENCHMARK(BM_FuseFrames_PclVoxelGrid)->Unit(benchmark::kMillisecond);

void BM_PackCloud_ToPointCloud2(benchmark::State& state) {
  const std::vector<vocal::ColoredPoint> view = frameView();
  for (auto _ : state) {
    const sensor_msgs::PointCloud2 msg = vocal::toPointCloud2(view, "odom", ros::Time(1));
    benchmark::DoNotOptimize(msg.data.data());
  }
}
BENCHMARK(BM_PackCloud_ToPointCloud2)->Unit(benchmark::kMicrosecond);

// From the same points: build the pcl::PointCloud, then pcl::toROSMsg.
void BM_PackCloud_PclToRosMsg(benchmark::State& state) {
  const std::vector<vocal::ColoredPoint> view = frameView();
  for (auto _ : state) {
    const pcl::PointCloud<pcl::PointXYZRGB> cloud = toPcl(view);
    sensor_msgs::PointCloud2 msg;
    pcl::toROSMsg(cloud, msg);
    benchmark::DoNotOptimize(msg.data.data());
  }
}
BENCHMARK(BM_PackCloud_PclToRosMsg)->Unit(benchmark::kMicrosecond);
}  // namespace

BENCHMARK_MAIN();
