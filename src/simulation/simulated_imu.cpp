#include "vocal/simulation/simulated_imu.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <Eigen/Dense>

#include "vocal/core/errors.h"
#include "vocal/core/gravity.h"
#include "vocal/core/se3.h"

namespace vocal {

namespace {
struct PathDerivatives {
  Eigen::Matrix3d rotation;       // world <- imu at t
  Eigen::Vector3d rate;           // rad/s, imu frame
  Eigen::Vector3d acceleration;   // m/s^2, world frame
};

// Quadratic fits in time of the rotation (as rotation vectors about the pose at t, body frame) and the
// position over the poses around t.
PathDerivatives derivativesAt(const Trajectory& poses, double t, double half_window) {
  const auto after = std::lower_bound(poses.begin(), poses.end(), t, [](const StampedPose& p, double s) { return p.stamp < s; });
  const std::size_t j = static_cast<std::size_t>(after - poses.begin());
  std::size_t lo = j, hi = j;  // [lo, hi)
  while (lo > 0 && t - poses[lo - 1].stamp <= half_window) --lo;
  while (hi < poses.size() && poses[hi].stamp - t <= half_window) ++hi;
  while (hi - lo < 5 && (lo > 0 || hi < poses.size())) {  // too few in the window: the nearest five
    if (lo > 0 && (hi == poses.size() || t - poses[lo - 1].stamp < poses[hi].stamp - t)) --lo; else ++hi;
  }
  // The pose at t between its neighbours: what the rotation vectors are measured from.
  const std::size_t b = std::min(std::max<std::size_t>(j, 1), poses.size() - 1);
  const double span = poses[b].stamp - poses[b - 1].stamp;
  const double alpha = span > 0.0 ? std::clamp((t - poses[b - 1].stamp) / span, 0.0, 1.0) : 0.0;
  const Eigen::Matrix3d centre = interpolatePose(poses[b - 1].pose, poses[b].pose, alpha).linear();
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d rhs_rotation = Eigen::Matrix3d::Zero(), rhs_position = Eigen::Matrix3d::Zero();  // columns: 1, tau, tau^2
  for (std::size_t i = lo; i < hi; ++i) {
    const double tau = poses[i].stamp - t;
    const Eigen::Vector3d basis(1.0, tau, tau * tau);
    normal += basis * basis.transpose();
    rhs_rotation += so3Log(centre.transpose() * poses[i].pose.linear()) * basis.transpose();
    rhs_position += poses[i].pose.translation() * basis.transpose();
  }
  const Eigen::Matrix3d inverse = normal.ldlt().solve(Eigen::Matrix3d::Identity());
  const Eigen::Matrix3d rotation_fit = rhs_rotation * inverse, position_fit = rhs_position * inverse;
  PathDerivatives d;
  // Inside a gap of the path (a motion capture losing its markers for a moment) the turn across it at
  // a constant rate: a fit over the poses either side would lose what turned in between.
  if (span > half_window && t > poses[b - 1].stamp && t < poses[b].stamp) {
    d.rotation = centre;
    d.rate = so3Log(poses[b - 1].pose.linear().transpose() * poses[b].pose.linear()) / span;
    d.rate = centre.transpose() * poses[b - 1].pose.linear() * d.rate;  // in the frame at t (about the same axis)
    d.acceleration = 2.0 * (rhs_position * inverse).col(2);
    return d;
  }
  d.rotation = centre * so3Exp(rotation_fit.col(0));
  d.rate = rotation_fit.col(1);
  d.acceleration = 2.0 * position_fit.col(2);
  return d;
}
}  // namespace

ImuExtrinsics simulatedImuExtrinsics() {
  ImuExtrinsics e;
  e.imu_frame = "camera_imu_frame";
  e.camera_frame = "camera_color_optical_frame";
  e.camera_in_imu.linear() = bodyFromOpticalRotation();
  e.camera_in_imu.translation() = Eigen::Vector3d(-0.005, 0.015, 0.0);
  return e;
}

std::vector<ImuSample> simulateImu(const Trajectory& camera_poses, const SimulatedImuOptions& options, Eigen::Vector3d* true_gyro_bias) {
  if (camera_poses.size() < 3) throw InputError("IMU simulation: the path has " + std::to_string(camera_poses.size()) + " poses, at least 3 are needed");
  if (!(options.rate > 0.0)) throw InputError("IMU simulation: the rate must be positive");
  // The IMU's own path: its rates and its acceleration (with the lever arm's) come from it.
  Trajectory imu_poses;
  const Eigen::Isometry3d imu_from_camera = options.extrinsics.camera_in_imu;
  for (const StampedPose& p : camera_poses) imu_poses.push_back({p.stamp, p.pose * imu_from_camera.inverse()});
  std::mt19937 random(options.seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const ImuNoise& noise = options.extrinsics.noise;
  Eigen::Vector3d gyro_bias(uniform(random), uniform(random), uniform(random));
  gyro_bias *= options.bias_limit;
  Eigen::Vector3d accel_bias(uniform(random), uniform(random), uniform(random));
  accel_bias *= options.accel_bias_limit;
  if (true_gyro_bias) *true_gyro_bias = gyro_bias;
  const double dt = 1.0 / options.rate;
  const double gyro_sigma = noise.gyro_noise_density / std::sqrt(dt), accel_sigma = noise.accel_noise_density / std::sqrt(dt);
  const auto draw = [&]() { return Eigen::Vector3d(normal(random), normal(random), normal(random)); };
  std::vector<ImuSample> samples;
  // Up to a sample at or past the last pose, so that the span to the last frame is covered.
  const int count = static_cast<int>(std::ceil((camera_poses.back().stamp - camera_poses.front().stamp) * options.rate)) + 1;
  for (int i = 0; i < count; ++i) {
    const double t = camera_poses.front().stamp + i * dt;
    const PathDerivatives d = derivativesAt(imu_poses, t, options.fit_half_window);
    ImuSample s;
    s.stamp = t + options.extrinsics.time_offset;
    s.angular_velocity = d.rate + gyro_bias + gyro_sigma * draw();
    s.linear_acceleration = d.rotation.transpose() * (d.acceleration + Eigen::Vector3d(0.0, 0.0, kStandardGravity)) + accel_bias +
                            accel_sigma * draw();
    samples.push_back(s);
    gyro_bias += noise.gyro_bias_random_walk * std::sqrt(dt) * draw();
    accel_bias += noise.accel_bias_random_walk * std::sqrt(dt) * draw();
  }
  return samples;
}

}  // namespace vocal
