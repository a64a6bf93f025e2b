#pragma once
// A simulated arm (simulated_arm.h) with joints: a 6-revolute-joint arm (shoulder pan and lift, elbow,
// three wrist joints; about a metre of reach) reaching each still pose's tool pose (numerical inverse
// kinematics), and its encoders as the robot reports them on /joint_states: off by a zero offset each
// (what a calibration of the joints finds), quantised, with a reading error per still pose (backlash,
// the links' flex). The arm's /tf is what robot_state_publisher makes of the readings: the tool where
// the uncalibrated model puts it.

#include <cstdint>
#include <vector>

#include "vocal/calibration/joint_chain.h"
#include "vocal/simulation/simulated_arm.h"

namespace vocal {

struct SimulatedJointArmOptions {
  double offset_range = 0.005;      // radians: each joint's true zero offset drawn from +-this (a re-zeroed arm)
  double encoder_counts = 65536.0;  // per turn
  double reading_noise = 0.0002;    // radians per reading at a still pose (standard deviation)
  std::uint32_t seed = 1;
  // A pan-tilt head beside the arm (a mobile manipulator's), its camera turned at each still pose towards
  // the board: its two joints from arm_base, read like the arm's.
  bool head = false;
  // The true upper arm this much longer than the model says (metres, along the elbow joint's origin z): a
  // link length off the maker's URDF, what a free joint origin calibrates.
  double elbow_length_error = 0.0;
};

struct SimulatedJointArm {
  std::vector<JointDescription> joints;  // base "arm_base" -> tool "arm_tool"; offset and origins: the truth
  // The same as the robot's model gives them (its URDF): offsets zero, origins the maker's.
  std::vector<JointDescription> model_joints;
  std::vector<int> chain;                // all of them, in order
  std::vector<std::vector<double>> angles;    // per still pose: the true joint angles
  std::vector<std::vector<double>> readings;  // ... as the encoders report them
  // The arm's truth (true_tool: the chain at the true angles) and, as reported_tool, the chain at the
  // readings with no offsets: what the robot's /tf says.
  SimulatedArm arm;

  // The readings at `time` into a session whose still pose k holds for `still` seconds from k * (still +
  // moving) then moves smoothly to the next (the last pose stays); at a still pose exactly `readings`.
  std::vector<double> readingsAt(double time, double still, double moving) const;
  // ... and the true angles.
  std::vector<double> anglesAt(double time, double still, double moving) const;
  // base <- forearm_link (after the chain's first kForearmJoints joints) at the true `angles`.
  static constexpr int kForearmJoints = 3;
  Eigen::Isometry3d forearmAt(const std::vector<double>& angles) const;

  // With a head (SimulatedJointArmOptions::head): its pan and tilt joints (in `joints` after the arm's)
  // from arm_base to head_tilt_link, and per still pose their true angles and readings (the head camera's
  // mount: arm.head_camera).
  static constexpr char kHeadLink[] = "head_tilt_link";
  std::vector<int> head_chain;
  std::vector<std::vector<double>> head_angles, head_readings;
  // base <- head_tilt_link at the head's true `angles`, and at `time` as readingsAt.
  Eigen::Isometry3d headAt(const std::vector<double>& angles) const;
  Eigen::Isometry3d headAt(double time, double still, double moving) const;
  // The arm's joints then the head's (every joint read, as ArmJoints::read lists them): their indices in
  // `joints`, and their readings at a still pose or, as readingsAt, at `time`.
  std::vector<int> allJoints() const;
  std::vector<double> allReadings(std::size_t pose) const;
  std::vector<double> allReadingsAt(double time, double still, double moving) const;
};

// The still poses of simulateArm(arm_options) reached by the arm's joints. Throws InputError when a
// pose is out of the arm's reach.
SimulatedJointArm simulateJointArm(const SimulatedArmOptions& arm_options, const SimulatedJointArmOptions& options = {});

}  // namespace vocal
