#include "vocal/simulation/blank_wall_visit.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "vocal/core/errors.h"
#include "vocal/core/se3.h"

namespace vocal {

namespace {
// 0 before `start`, 1 after start + span, smooth in between (zero rate and acceleration at both ends).
double smoothStep(double t, double start, double span) {
  const double x = std::clamp((t - start) / span, 0.0, 1.0);
  return x * x * x * (10.0 + x * (-15.0 + 6.0 * x));
}
}  // namespace

std::pair<double, double> blankWallDwell(const BlankWallVisitOptions& options) {
  const double first = options.start_stamp + options.room_before_seconds + options.turn_seconds;
  return {first, first + options.wall_seconds};
}

Trajectory generateBlankWallVisit(const BlankWallVisitOptions& options) {
  if (!(options.frame_rate > 0.0)) throw InputError("blank wall visit: frame_rate must be positive");
  if (!(options.room_before_seconds >= 0.0 && options.room_after_seconds >= 0.0 && options.turn_seconds > 0.0 &&
        options.wall_seconds >= 0.0))
    throw InputError("blank wall visit: room and wall seconds must be >= 0, turn seconds > 0");
  const double room = options.room_before_seconds, turn = options.turn_seconds, wall = options.wall_seconds;
  const double total = room + 2.0 * turn + wall + options.room_after_seconds;
  const int frames = static_cast<int>(std::floor(total * options.frame_rate)) + 1;
  const Eigen::Vector3d center(-1.5, 0.0, 1.4);
  Trajectory path;
  path.reserve(frames);
  for (int i = 0; i < frames; ++i) {
    const double t = i / options.frame_rate;
    const double facing_wall = smoothStep(t, room, turn) - smoothStep(t, room + turn + wall, turn);
    // Hand-held wobble at incommensurate frequencies (peaks: 0.6 rad/s yaw, 0.3 m/s travel).
    const double yaw = facing_wall * M_PI / 2 + 0.2 * std::sin(2.9 * t + 0.3);
    const double pitch = 0.15 * (1.0 - facing_wall) + 0.08 * std::sin(2.3 * t + 1.1);
    const double roll = 0.05 * std::sin(1.7 * t + 2.0);
    const Eigen::Vector3d wobble(0.15 * std::sin(1.9 * t), 0.1 * std::sin(1.3 * t + 0.7), 0.08 * std::sin(2.6 * t + 1.9));
    StampedPose pose;
    pose.stamp = std::round((options.start_stamp + t) * 1e6) / 1e6;
    pose.pose.linear() = rotationFromRollPitchYaw(roll, pitch, yaw) * bodyFromOpticalRotation();
    pose.pose.translation() = center + wobble;
    path.push_back(pose);
  }
  return path;
}

}  // namespace vocal
