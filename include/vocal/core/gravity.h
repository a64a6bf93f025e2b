#pragma once
// Gravity from an accelerometer, to start the odometry frame level (REP-105: odom's z up). A hand-held
// camera starts tilted (TUM's freiburg1 sequences: 31-46 deg down); without this its first pose is odom,
// and the room stands tilted in rviz.

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace vocal {

constexpr double kStandardGravity = 9.80665;  // m/s^2

// The accelerometer's specific force (m/s^2, in its own frame): at rest it points up, |g| long.
struct AccelerometerSample {
  double stamp = 0.0;
  Eigen::Vector3d specific_force = Eigen::Vector3d::Zero();
};

// TUM's accelerometer.txt (`timestamp ax ay az`, `#` comments). Throws InputError naming the file and
// line for a malformed line, a value that is not finite or a stamp not after the one before.
std::vector<AccelerometerSample> readAccelerometerFile(const std::string& path);
void writeAccelerometerFile(const std::string& path, const std::vector<AccelerometerSample>& samples);

// The Kinect's accelerometer axes (x left, y up, z forward: how TUM's accelerometer.txt reads, checked
// against its motion capture) in the camera's optical frame (x right, y down, z forward).
Eigen::Matrix3d opticalFromKinectAccelerometer();

// The shortest turn that takes `up` (the specific force at rest, in a body frame) to +z: the body's
// roll and pitch undone, its heading kept. Rotates a body frame into a level one with the same yaw.
Eigen::Matrix3d levelFromUp(const Eigen::Vector3d& up);

// The mean specific force of the samples within `window` seconds of `stamp` (either side): gravity, where
// its length is within 10 % of g (a hand's accelerations average out: a real Kinect's samples scatter
// by up to 2.7 m/s^2 on TUM's hand-held freiburg1_xyz and 5.2 on freiburg1_rpy within 0.5 s of the first
// frame, yet the mean of 0.2 s lies 3.7-4.2 deg from the motion capture's up, the sensor's own error).
// Otherwise nothing, and `why` says what was wrong.
std::optional<Eigen::Vector3d> stillSpecificForce(const std::vector<AccelerometerSample>& samples, double stamp, double window,
                                                  std::string* why = nullptr);

}  // namespace vocal
