#include "vocal/simulation/simulated_accelerometer.h"

#include <random>

namespace vocal {

std::vector<AccelerometerSample> simulateKinectAccelerometer(const Trajectory& optical_poses, double noise, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> white(0.0, noise);
  std::vector<AccelerometerSample> samples;
  const std::size_t n = optical_poses.size();
  for (std::size_t i = 0; i < n; ++i) {
    Eigen::Vector3d acceleration = Eigen::Vector3d::Zero();
    if (i > 0 && i + 1 < n) {
      const StampedPose &before = optical_poses[i - 1], &now = optical_poses[i], &after = optical_poses[i + 1];
      const double h0 = now.stamp - before.stamp, h1 = after.stamp - now.stamp;
      if (h0 > 0.0 && h1 > 0.0) {
        const Eigen::Vector3d v0 = (now.pose.translation() - before.pose.translation()) / h0;
        const Eigen::Vector3d v1 = (after.pose.translation() - now.pose.translation()) / h1;
        acceleration = (v1 - v0) / (0.5 * (h0 + h1));
      }
    }
    const Eigen::Matrix3d world_from_accelerometer = optical_poses[i].pose.linear() * opticalFromKinectAccelerometer();
    AccelerometerSample s;
    s.stamp = optical_poses[i].stamp;
    s.specific_force = world_from_accelerometer.transpose() * (acceleration + kStandardGravity * Eigen::Vector3d::UnitZ()) +
                       Eigen::Vector3d(white(rng), white(rng), white(rng));
    samples.push_back(s);
  }
  return samples;
}

}  // namespace vocal
