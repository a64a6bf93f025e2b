#pragma once
// Roll and pitch held to gravity: the accelerometer's mean specific force over a short window, less the
// camera's own acceleration there (from the odometry's positions), is "up"; the odometry's attitude is
// pulled toward the up of the first window with a time constant, about the camera's position, heading
// and position untouched. A complementary filter (Mahony et al. 2008): the odometry solves each frame
// against a keyframe whose attitude it holds fixed, so an absolute prior in one frame's normal
// equations would move only that frame, by the share its (relative) information leaves; the drift lives
// in the keyframes' poses, which this corrects.

#include <deque>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "vocal/core/gravity.h"

namespace vocal {

class GravityCorrection {
 public:
  // `time_constant` seconds: how long a roll / pitch error takes to shrink to 1/e. > 0.
  explicit GravityCorrection(double time_constant);

  // `pose`: the camera's tracked pose at `stamp` (odometry frame). `accelerometer`: samples in the camera
  // frame, stamps increasing (on the camera's clock), at least those of the last second. Once a second
  // of poses is held, up over [stamp - 0.55, stamp - 0.05] s: mean(R(t) f(t)) - (v(end) - v(start)) /
  // 0.5 s, R and v from the poses. The first such up fixes the level (identity returned); later ones
  // give the correction C (odometry frame) that turns the pose's roll / pitch dt / time_constant of the
  // way to it: corrected pose = C * pose (the held poses are corrected too). Identity, and `why` says
  // why, while poses or samples are too few or up's length is not gravity's within 10 %.
  Eigen::Isometry3d correct(double stamp, const Eigen::Isometry3d& pose, const std::vector<AccelerometerSample>& accelerometer,
                            double dt, std::string* why = nullptr);

  void reset();
  bool started() const { return up_.has_value(); }
  // The angle between the last window's up and the reference's, before the correction (radians); 0 before.
  double lastError() const { return last_error_; }

 private:
  struct StampedPose {
    double stamp;
    Eigen::Isometry3d pose;
  };
  std::optional<Eigen::Isometry3d> poseAt(double stamp) const;  // interpolated; none outside the held span

  double time_constant_;
  std::deque<StampedPose> poses_;
  std::optional<Eigen::Vector3d> up_;  // in the odometry frame, unit
  double last_error_ = 0.0;
};

}  // namespace vocal
