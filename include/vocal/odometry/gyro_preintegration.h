#pragma once
// A gyro's rates between two instants integrated into one rotation (preintegration, Forster et al. 2017,
// rotation part) with its covariance: what the odometry takes as a prior on a frame's rotation.

#include <vector>

#include <Eigen/Core>

#include "vocal/core/imu_samples.h"

namespace vocal {

struct GyroDelta {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // imu(t0) <- imu(t1)
  // Of a right perturbation rotation * Exp(d) (rad^2), from the rates' white noise alone.
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  double seconds = 0.0;
  int samples = 0;        // samples inside [t0, t1]
  bool complete = false;  // samples at or before t0 and at or after t1, none more than max_gap apart
};

// The rotation from t0 to t1 (IMU stamps, t0 < t1) of `samples` (stamps increasing): the rate at any
// instant interpolated linearly between its neighbours, `bias` taken off, integrated piece by piece
// between the samples (trapezoid). Where the samples do not reach t0 or t1, or two are more than
// `max_gap` seconds apart, the delta is integrated over what there is and marked incomplete.
GyroDelta preintegrateGyro(const std::vector<ImuSample>& samples, double t0, double t1, const Eigen::Vector3d& bias,
                           double gyro_noise_density, double max_gap = 0.05);

}  // namespace vocal
