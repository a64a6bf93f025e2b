#include "vocal/simulation/simulated_pan_tilt.h"

#include "vocal/simulation/still_pose_timeline.h"

#include <cmath>
#include <random>

namespace vocal {

std::vector<double> SimulatedPanTilt::anglesAt(double time, double still, double moving) const {
  return valuesAtTime(angles, time, still, moving);
}

std::vector<double> SimulatedPanTilt::reported(const std::vector<double>& true_angles, const std::vector<int>& direction) const {
  const double step = 2.0 * M_PI / options.encoder_counts;
  std::vector<double> readings(true_angles.size());
  for (std::size_t j = 0; j < readings.size(); ++j) {
    // The encoder sits on the motor's side of the gears: it leads the output by half the play.
    const double lead = 0.5 * options.backlash * (j < direction.size() ? direction[j] : 0);
    readings[j] = std::round((true_angles[j] - joints[j].offset + lead) / step) * step;
  }
  return readings;
}

Eigen::Isometry3d SimulatedPanTilt::baseFromSensor(const std::vector<double>& true_angles) const { return baseFromSensor(true_angles, mount); }

Eigen::Isometry3d SimulatedPanTilt::baseFromSensor(const std::vector<double>& true_angles, const Eigen::Isometry3d& on_tilt) const {
  return chainPose(joints, chain, true_angles, std::vector<double>(joints.size(), 0.0)) * on_tilt;
}

SimulatedPanTilt simulatePanTilt(const std::vector<Eigen::Isometry3d>& boards, const Eigen::Isometry3d& mount,
                                 const SimulatedPanTiltOptions& options) {
  std::mt19937 rng(options.seed * 2654435761u + 17u);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  SimulatedPanTilt head;
  head.options = options;
  head.mount = mount;
  JointDescription pan;
  pan.name = "head_pan_joint";
  pan.parent = options.base_frame;
  pan.child = "head_pan_link";
  pan.origin.translation() = options.base_from_pan;
  pan.axis = Eigen::Vector3d::UnitZ();
  pan.offset = options.offset_range * unit(rng);
  JointDescription tilt;
  tilt.name = "head_tilt_joint";
  tilt.parent = pan.child;
  tilt.child = "head_tilt_link";
  tilt.origin.translation() = Eigen::Vector3d(0.02, 0.0, 0.09) + options.tilt_origin_error;
  tilt.axis = Eigen::Vector3d::UnitY();
  tilt.offset = options.offset_range * unit(rng);
  head.joints = {pan, tilt};
  head.chain = {0, 1};
  for (const Eigen::Isometry3d& board : boards) {
    // Aim the sensor's line of sight (its z, mounted looking along the tilt link's x) at the board's centre.
    const Eigen::Vector3d to_board = board.translation() - (options.base_from_pan + tilt.origin.translation());
    const double pan_angle = std::atan2(to_board.y(), to_board.x()) + options.wander * unit(rng);
    const double tilt_angle = std::atan2(-to_board.z(), to_board.head<2>().norm()) + options.wander * unit(rng);
    head.angles.push_back({pan_angle, tilt_angle});
  }
  return head;
}

}  // namespace vocal
