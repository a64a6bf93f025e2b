#pragma once
// An IMU riding along a camera path: what a RealSense D435i or an Azure Kinect would have measured
// where the camera went (a synthetic path, or a real one: TUM's motion capture), with a consumer MEMS
// noise model. The path is differentiated through local quadratic fits (a smoothing spline's job: the
// motion capture's own jitter is not read as rotation).

#include <cstdint>
#include <vector>

#include "vocal/core/imu_samples.h"
#include "vocal/core/tum_trajectory.h"

namespace vocal {

struct SimulatedImuOptions {
  double rate = 200.0;             // Hz
  double bias_limit = 0.5 * 3.14159265358979 / 180.0;  // rad/s: each axis's constant gyro bias drawn uniformly within +-this
  double accel_bias_limit = 0.05;  // m/s^2, likewise
  double fit_half_window = 0.05;   // seconds either side of a sample the path is fitted over
  ImuExtrinsics extrinsics;        // its pose in the camera, time offset and noise figures
  std::uint32_t seed = 1;
};

// Samples from the path's start to its end (camera clock), stamped on the IMU's clock (+ time_offset):
// angular velocity and specific force (world z up, g = 9.80665) in the IMU frame, plus white noise at
// the noise densities, a bias drawn per run and the densities' random walks. `camera_poses`: the
// camera's optical frame in the world, stamps increasing. Throws InputError for fewer than 3 poses.
// `true_gyro_bias` (optional) gets the bias at the first sample (rad/s).
std::vector<ImuSample> simulateImu(const Trajectory& camera_poses, const SimulatedImuOptions& options,
                                   Eigen::Vector3d* true_gyro_bias = nullptr);

// The IMU pose the simulator writes unless told otherwise: a D435i's, x forward, y left, z up, 15 mm
// beside the colour camera's optical centre.
ImuExtrinsics simulatedImuExtrinsics();

}  // namespace vocal
