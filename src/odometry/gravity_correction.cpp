#include "vocal/odometry/gravity_correction.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "vocal/core/errors.h"
#include "vocal/core/se3.h"

namespace vocal {

namespace {
// The window up is measured over, ending this long before the frame (a backward difference's half
// span: velocities from positions kVelocitySpan apart).
constexpr double kWindow = 0.5;
constexpr double kVelocitySpan = 0.1;
constexpr double kHeldSeconds = 1.0;
}  // namespace

GravityCorrection::GravityCorrection(double time_constant) : time_constant_(time_constant) {
  if (!(time_constant > 0.0 && std::isfinite(time_constant)))
    throw InputError("gravity correction: the time constant must be positive, got " + std::to_string(time_constant));
}

void GravityCorrection::reset() {
  poses_.clear();
  up_.reset();
  last_error_ = 0.0;
}

std::optional<Eigen::Isometry3d> GravityCorrection::poseAt(double stamp) const {
  if (poses_.empty() || stamp < poses_.front().stamp || stamp > poses_.back().stamp) return std::nullopt;
  const auto after = std::lower_bound(poses_.begin(), poses_.end(), stamp,
                                      [](const StampedPose& p, double t) { return p.stamp < t; });
  if (after == poses_.begin()) return after->pose;
  const auto before = std::prev(after);
  const double span = after->stamp - before->stamp;
  return interpolatePose(before->pose, after->pose, span > 0.0 ? (stamp - before->stamp) / span : 0.0);
}

Eigen::Isometry3d GravityCorrection::correct(double stamp, const Eigen::Isometry3d& pose,
                                             const std::vector<AccelerometerSample>& accelerometer, double dt, std::string* why) {
  auto none = [&](const std::string& reason) {
    if (why) *why = reason;
    return Eigen::Isometry3d::Identity();
  };
  if (!poses_.empty() && !(stamp > poses_.back().stamp)) poses_.clear();  // time went back: start again
  poses_.push_back({stamp, pose});
  while (poses_.size() > 2 && poses_[1].stamp < stamp - kHeldSeconds) poses_.pop_front();
  const double end = stamp - 0.5 * kVelocitySpan, start = end - kWindow;
  const auto p0a = poseAt(start - 0.5 * kVelocitySpan), p0b = poseAt(start + 0.5 * kVelocitySpan);
  const auto p1a = poseAt(end - 0.5 * kVelocitySpan), p1b = poseAt(end + 0.5 * kVelocitySpan);
  if (!p0a || !p0b || !p1a || !p1b) return none("fewer than 0.6 s of tracked poses");
  const Eigen::Vector3d acceleration = ((p1b->translation() - p1a->translation()) - (p0b->translation() - p0a->translation())) /
                                       (kVelocitySpan * kWindow);
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  int count = 0;
  const auto first = std::lower_bound(accelerometer.begin(), accelerometer.end(), start,
                                      [](const AccelerometerSample& s, double t) { return s.stamp < t; });
  for (auto s = first; s != accelerometer.end() && s->stamp <= end; ++s) {
    const auto at = poseAt(s->stamp);
    if (!at || !s->specific_force.allFinite()) continue;
    force += at->linear() * s->specific_force;
    ++count;
  }
  if (count < 3) return none("fewer than 3 accelerometer samples in the last 0.5 s");
  const Eigen::Vector3d up = force / count - acceleration;  // odometry frame: gravity's reaction alone
  if (std::fabs(up.norm() - kStandardGravity) > 0.1 * kStandardGravity) {
    std::ostringstream text;
    text << "the accelerometer less the camera's acceleration read " << up.norm() << " m/s^2, not gravity's " << kStandardGravity
         << " within 10 %";
    return none(text.str());
  }
  if (why) why->clear();
  if (!up_) {
    up_ = up.normalized();
    last_error_ = 0.0;
    return Eigen::Isometry3d::Identity();
  }
  // The turn that takes the measured up onto the reference: about their cross product, a share of it.
  const Eigen::Vector3d axis = up.normalized().cross(*up_);
  last_error_ = std::atan2(axis.norm(), up.normalized().dot(*up_));
  if (axis.norm() < 1e-12) return Eigen::Isometry3d::Identity();
  const double share = std::clamp(std::max(dt, 0.0) / time_constant_, 0.0, 1.0);
  Eigen::Isometry3d correction = Eigen::Isometry3d::Identity();
  correction.linear() = so3Exp(axis.normalized() * (share * last_error_));
  // About the camera's position: the position stays.
  correction.translation() = pose.translation() - correction.linear() * pose.translation();
  for (StampedPose& held : poses_) held.pose = correction * held.pose;
  return correction;
}

}  // namespace vocal
