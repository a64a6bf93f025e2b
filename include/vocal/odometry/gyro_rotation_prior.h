#pragma once
// The camera's rotation between two frames as the IMU's gyro measured it: the rates preintegrated
// between the frames' stamps (on the IMU's clock), turned into the camera frame through the IMU's
// extrinsics, the gyro's bias taken off. The bias is estimated online (a Kalman filter) from the
// rotations vision measured on its own against each keyframe: over a keyframe's span vision's error does
// not grow, the bias's integral does; and with the prior's pull taken out, a wrong bias is not
// confirmed by the rotation it bent. The prior's covariance holds the rates' noise and what is left
// unknown of the bias.

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "vocal/core/imu_samples.h"

namespace vocal {

// camera(t0) <- camera(t1), a right perturbation's covariance (rad^2) in camera(t1).
struct RotationPrior {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();
};

struct GyroBiasOptions {
  double initial_sigma = 0.01;  // rad/s (0.57 deg/s): a consumer MEMS gyro's bias when switched on
  double vision_sigma = 0.002;  // rad: vision's rotation error against its keyframe
  double min_span = 0.1;        // seconds: shorter keyframe spans say too little of the bias
  double max_span = 1.0;        // seconds: a keyframe held longer is measured once, at this span
};

class GyroRotationPrior {
 public:
  explicit GyroRotationPrior(const ImuExtrinsics& extrinsics, const GyroBiasOptions& options = {});

  // Appends a sample. False (and `why` says which and why) for a rate or acceleration that is not
  // finite or a stamp not after the last one's: the sample is dropped.
  bool add(const ImuSample& sample, std::string* why = nullptr);
  void add(const std::vector<ImuSample>& samples);  // a file's (already checked) samples
  // Forgets samples older than `camera_stamp` less a second and max_span (a live stream's memory stays bounded).
  void forgetBefore(double camera_stamp);

  // The camera's rotation from camera stamp t0 to t1 (each moved onto the IMU's clock by the time
  // offset); none when the samples do not cover the span (`why` says so).
  std::optional<RotationPrior> between(double t0, double t1, std::string* why = nullptr) const;

  // A frame vision tracked: its keyframe's stamp, its own, and the rotation keyframe <- camera vision
  // alone measured (OdometryResult::vision_rotation). Each keyframe's longest span (up to max_span)
  // becomes one measurement of the bias when the keyframe changes.
  void observe(double keyframe_stamp, double camera_stamp, const Eigen::Matrix3d& keyframe_from_camera);
  // A frame vision did not track: its keyframe's pending measurement is dropped.
  void breakWindow() { pending_ = false; }

  const Eigen::Vector3d& bias() const { return bias_; }  // rad/s, IMU frame
  Eigen::Vector3d biasSigma() const { return bias_covariance_.diagonal().cwiseSqrt(); }
  int biasUpdates() const { return bias_updates_; }
  const std::vector<ImuSample>& samples() const { return samples_; }
  const ImuExtrinsics& extrinsics() const { return extrinsics_; }

 private:
  ImuExtrinsics extrinsics_;
  GyroBiasOptions options_;
  std::vector<ImuSample> samples_;
  Eigen::Vector3d bias_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d bias_covariance_;
  int bias_updates_ = 0;
  // The latest span of the current keyframe, not yet measured.
  bool pending_ = false;
  double pending_keyframe_ = 0.0, pending_stamp_ = 0.0, measured_keyframe_ = -1.0;
  Eigen::Matrix3d pending_rotation_ = Eigen::Matrix3d::Identity();
  void updateBias(double t0, double t1, const Eigen::Matrix3d& camera_rotation);
};

}  // namespace vocal
