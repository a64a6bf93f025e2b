#pragma once
// Trajectories in the TUM format: one pose per line, `timestamp tx ty tz qx qy qz qw`, the pose of
// the camera in the world frame (T_world_camera).

#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace vocal {

struct StampedPose {
  double stamp = 0.0;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
};

using Trajectory = std::vector<StampedPose>;

// Throws InputError naming the file and line for a malformed line (field count, a number that does not
// parse, a zero or non-unit quaternion) or stamps that do not increase.
Trajectory readTumTrajectory(const std::string& path);

// Writes with enough digits that readTumTrajectory returns the same doubles; throws InputError if the
// file cannot be written.
void writeTumTrajectory(const std::string& path, const Trajectory& trajectory);

std::vector<double> trajectoryStamps(const Trajectory& trajectory);

}  // namespace vocal
