#include "vocal/simulation/synthetic_trajectory.h"

#include <cmath>
#include <random>

#include "vocal/core/errors.h"
#include "vocal/core/se3.h"

namespace vocal {

namespace {
struct PathShape {
  const CameraWorkspace& workspace;
  double phase[6];

  // Position and roll/pitch/yaw at path parameter s.
  Eigen::Vector3d position(double s) const {
    const Eigen::Vector3d& a = workspace.amplitude;
    return workspace.center + Eigen::Vector3d(a.x() * std::sin(1.00 * s + phase[0]), a.y() * std::sin(0.71 * s + phase[1]),
                                              a.z() * std::sin(1.37 * s + phase[2]));
  }
  Eigen::Isometry3d pose(double s) const {
    const double yaw = workspace.yaw + workspace.yaw_amplitude * std::sin(0.53 * s + phase[3]);
    const double pitch = workspace.pitch + workspace.pitch_amplitude * std::sin(0.91 * s + phase[4]);
    const double roll = workspace.roll_amplitude * std::sin(1.19 * s + phase[5]);
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = rotationFromRollPitchYaw(roll, pitch, yaw) * bodyFromOpticalRotation();
    pose.translation() = position(s);
    return pose;
  }
};
}  // namespace

Trajectory generateSyntheticTrajectory(const CameraWorkspace& workspace, const SyntheticTrajectoryOptions& options) {
  if (options.frames <= 0) throw InputError("trajectory: frames must be positive, got " + std::to_string(options.frames));
  if (!(options.frame_rate > 0.0))
    throw InputError("trajectory: frame_rate must be positive, got " + std::to_string(options.frame_rate));
  if (!(options.speed >= 0.0)) throw InputError("trajectory: speed must be >= 0, got " + std::to_string(options.speed));

  PathShape shape{workspace, {}};
  std::mt19937 rng(options.seed);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * M_PI);
  for (double& p : shape.phase) p = angle(rng);

  // Mean |dp/ds| over a long stretch of the path sets how fast s must advance for the requested speed.
  const int samples = 20000;
  const double span = 200.0;
  double length = 0.0;
  for (int i = 0; i < samples; ++i) {
    length += (shape.position(span * (i + 1) / samples) - shape.position(span * i / samples)).norm();
  }
  const double s_per_second = length > 0.0 ? options.speed / (length / span) : 0.0;

  Trajectory trajectory;
  trajectory.reserve(options.frames);
  for (int i = 0; i < options.frames; ++i) {
    const double seconds = i / options.frame_rate;
    const double stamp = std::round((options.start_stamp + seconds) * 1e6) / 1e6;
    trajectory.push_back({stamp, shape.pose(s_per_second * seconds)});
  }
  return trajectory;
}

}  // namespace vocal
