#pragma once
// A sensor on a pan-tilt head (a Kinect on a PR2's or Fetch's head): two revolute joints, pan about the
// base's z and tilt about the pan link's y, the sensor mounted on the tilt link, turned towards the
// board at each still pose (with a little of its own wander), and the joints' encoders as a robot
// reports them on /joint_states: off by a zero offset each (the calibration's unknowns), quantised to
// the encoder's counts, and late by half the gear's backlash in the direction of the last motion.

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "vocal/calibration/joint_chain.h"

namespace vocal {

struct SimulatedPanTiltOptions {
  std::string base_frame = "base_link";
  Eigen::Vector3d base_from_pan = Eigen::Vector3d(0.05, -0.1, 1.1);  // the pan joint in the base frame
  double wander = 0.12;             // radians each joint turns away from aiming at the board, at most
  double offset_range = 0.03;       // radians: each joint's true zero offset drawn from +-this
  double encoder_counts = 4096.0;   // per turn (a 12-bit absolute encoder: 1.5 mrad steps)
  double backlash = 0.001;          // radians of play in each joint's gears
  // The tilt joint's true origin this far from the model's (metres, in the pan link): a head built off its
  // drawing, what a free joint origin calibrates. `joints` hold the truth; the model is them less this.
  Eigen::Vector3d tilt_origin_error = Eigen::Vector3d::Zero();
  std::uint32_t seed = 1;
};

struct SimulatedPanTilt {
  std::vector<JointDescription> joints;  // pan then tilt; offset: the truth
  std::vector<int> chain;                // {0, 1}: base -> pan link -> tilt link
  Eigen::Isometry3d mount = Eigen::Isometry3d::Identity();  // tilt link <- sensor (optical frame)
  std::vector<std::vector<double>> angles;  // per still pose: each joint's true angle
  SimulatedPanTiltOptions options;

  // The joints' true angles at `time` seconds into a session whose still pose k holds for `still` seconds
  // from k * (still + moving), then moves (smoothly) to pose k + 1 (the last pose stays).
  std::vector<double> anglesAt(double time, double still, double moving) const;
  // What the encoders report for those angles, moving in `direction` (+1 / -1 per joint, the sign of the
  // last motion; 0: at rest after none): angle - offset, late by half the backlash, quantised.
  std::vector<double> reported(const std::vector<double>& angles, const std::vector<int>& direction) const;
  // base <- sensor at the joints' true angles: the aimed sensor, or another mounted `on_tilt` on the tilt link.
  Eigen::Isometry3d baseFromSensor(const std::vector<double>& angles) const;
  Eigen::Isometry3d baseFromSensor(const std::vector<double>& angles, const Eigen::Isometry3d& on_tilt) const;
};

// A head that aims a sensor mounted `mount` on its tilt link at each board centre of `boards` (base frame).
SimulatedPanTilt simulatePanTilt(const std::vector<Eigen::Isometry3d>& boards, const Eigen::Isometry3d& mount,
                                 const SimulatedPanTiltOptions& options = {});

}  // namespace vocal
