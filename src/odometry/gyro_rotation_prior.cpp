#include "vocal/odometry/gyro_rotation_prior.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "vocal/core/se3.h"
#include "vocal/odometry/gyro_preintegration.h"

namespace vocal {

GyroRotationPrior::GyroRotationPrior(const ImuExtrinsics& extrinsics, const GyroBiasOptions& options)
    : extrinsics_(extrinsics), options_(options) {
  bias_covariance_ = options_.initial_sigma * options_.initial_sigma * Eigen::Matrix3d::Identity();
}

bool GyroRotationPrior::add(const ImuSample& sample, std::string* why) {
  std::ostringstream reason;
  if (!std::isfinite(sample.stamp) || !sample.angular_velocity.allFinite() || !sample.linear_acceleration.allFinite()) {
    reason << "IMU sample at " << sample.stamp << " s: a value is not finite (NaN or inf)";
  } else if (!samples_.empty() && !(sample.stamp > samples_.back().stamp)) {
    reason.precision(6);
    reason << std::fixed << "IMU sample at " << sample.stamp << " s: not after the last one (" << samples_.back().stamp
           << " s): stamps out of order";
  } else {
    samples_.push_back(sample);
    return true;
  }
  if (why) *why = reason.str();
  return false;
}

void GyroRotationPrior::add(const std::vector<ImuSample>& samples) {
  for (const ImuSample& s : samples) add(s);
}

void GyroRotationPrior::forgetBefore(double camera_stamp) {
  const double keep_from = camera_stamp + extrinsics_.time_offset - 1.0 - options_.max_span;
  const auto end = std::lower_bound(samples_.begin(), samples_.end(), keep_from,
                                    [](const ImuSample& s, double stamp) { return s.stamp < stamp; });
  if (end - samples_.begin() > 1) samples_.erase(samples_.begin(), end - 1);
}

std::optional<RotationPrior> GyroRotationPrior::between(double t0, double t1, std::string* why) const {
  const double offset = extrinsics_.time_offset;
  const GyroDelta delta = preintegrateGyro(samples_, t0 + offset, t1 + offset, bias_, extrinsics_.noise.gyro_noise_density);
  if (!delta.complete) {
    if (why) {
      std::ostringstream reason;
      reason.precision(3);
      reason << std::fixed << "the IMU samples do not cover " << t0 + offset << "-" << t1 + offset << " s (IMU clock)";
      if (!samples_.empty()) reason << ": they span " << samples_.front().stamp << "-" << samples_.back().stamp << " s";
      reason << ", or leave a gap over 0.05 s";
      *why = reason.str();
    }
    return std::nullopt;
  }
  const Eigen::Matrix3d imu_from_camera = extrinsics_.camera_in_imu.rotation();
  RotationPrior prior;
  prior.rotation = imu_from_camera.transpose() * delta.rotation * imu_from_camera;
  // The bias left unknown turns the rotation by about its integral over the span.
  const Eigen::Matrix3d covariance = delta.covariance + delta.seconds * delta.seconds * bias_covariance_;
  prior.covariance = imu_from_camera.transpose() * covariance * imu_from_camera;
  return prior;
}

void GyroRotationPrior::observe(double keyframe_stamp, double camera_stamp, const Eigen::Matrix3d& keyframe_from_camera) {
  if (pending_ && keyframe_stamp != pending_keyframe_) {
    if (pending_stamp_ - pending_keyframe_ >= options_.min_span) updateBias(pending_keyframe_, pending_stamp_, pending_rotation_);
    pending_ = false;
  }
  if (keyframe_stamp == measured_keyframe_ || !(camera_stamp > keyframe_stamp)) return;
  pending_ = true;
  pending_keyframe_ = keyframe_stamp, pending_stamp_ = camera_stamp, pending_rotation_ = keyframe_from_camera;
  if (camera_stamp - keyframe_stamp >= options_.max_span) {
    updateBias(keyframe_stamp, camera_stamp, keyframe_from_camera);
    measured_keyframe_ = keyframe_stamp;
    pending_ = false;
  }
}

void GyroRotationPrior::updateBias(double camera_t0, double camera_t1, const Eigen::Matrix3d& camera_rotation) {
  const double offset = extrinsics_.time_offset;
  const double t0 = camera_t0 + offset, t1 = camera_t1 + offset;
  const GyroDelta gyro = preintegrateGyro(samples_, t0, t1, bias_, extrinsics_.noise.gyro_noise_density);
  if (!gyro.complete) return;
  const Eigen::Matrix3d imu_from_camera = extrinsics_.camera_in_imu.rotation();
  const Eigen::Matrix3d vision = imu_from_camera * camera_rotation * imu_from_camera.transpose();
  // vision = gyro(b) ~ gyro(bias) Exp(J (b - bias)): J by differences, as a fast turn bends it away from -span * I.
  Eigen::Matrix3d J;
  constexpr double kStep = 1e-4;
  for (int i = 0; i < 3; ++i) {
    const GyroDelta nudged = preintegrateGyro(samples_, t0, t1, bias_ + kStep * Eigen::Vector3d::Unit(i), 0.0);
    J.col(i) = so3Log(gyro.rotation.transpose() * nudged.rotation) / kStep;
  }
  const Eigen::Vector3d innovation = so3Log(gyro.rotation.transpose() * vision);
  const double walk = extrinsics_.noise.gyro_bias_random_walk;
  bias_covariance_ += walk * walk * (t1 - t0) * Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d measurement = options_.vision_sigma * options_.vision_sigma * Eigen::Matrix3d::Identity() + gyro.covariance;
  const Eigen::Matrix3d S = J * bias_covariance_ * J.transpose() + measurement;
  const Eigen::Matrix3d K = bias_covariance_ * J.transpose() * S.inverse();
  bias_ += K * innovation;
  bias_covariance_ = (Eigen::Matrix3d::Identity() - K * J) * bias_covariance_;
  bias_covariance_ = (0.5 * (bias_covariance_ + bias_covariance_.transpose())).eval();
  ++bias_updates_;
}

}  // namespace vocal
