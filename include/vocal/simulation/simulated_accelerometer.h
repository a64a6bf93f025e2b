#pragma once
// A Kinect's accelerometer along a simulated camera path, as TUM's accelerometer.txt gives a real one:
// what the odometry levels its frame with.

#include <cstdint>
#include <vector>

#include "vocal/core/gravity.h"
#include "vocal/core/tum_trajectory.h"

namespace vocal {

// One sample per pose of `optical_poses` (the optical frame in a world whose z is up): gravity and the
// path's acceleration (central differences) as specific force in the Kinect's accelerometer frame
// (opticalFromKinectAccelerometer), with white noise of `noise` m/s^2 per axis.
std::vector<AccelerometerSample> simulateKinectAccelerometer(const Trajectory& optical_poses, double noise, std::uint32_t seed);

}  // namespace vocal
