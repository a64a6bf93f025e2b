#pragma once
// A robot arm moving a camera over a fixed board (eye-in-hand) or a board in front of a fixed camera
// (eye-to-hand), with the truth: the still poses a hand-eye session takes, the tool's pose as the arm
// reports it (its repeatability, and optionally one pose millimetres off, as a worn joint or a
// re-grip gives), and the camera's views of the board at each.

#include <cstdint>
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "vocal/calibration/extraction/pattern_observation.h"
#include "vocal/calibration/solver/hand_eye_calibration.h"
#include "vocal/core/pinhole_camera.h"

namespace vocal {

struct SimulatedArmOptions {
  HandEyeSetup setup = HandEyeSetup::kEyeInHand;
  int poses = 12;
  double tilt = 0.5;  // radians the view turns away from straight at most, about each axis across it
  double roll = 0.8;  // ... and about the viewing axis
  // Eye-to-hand: the board's centre this far from the camera (metres), and, where `across_laser`, at the
  // 2D laser's height (within a tenth of a metre) so that its scan line crosses the board at every pose.
  double near_depth = 0.6;
  double far_depth = 0.9;
  bool across_laser = false;
  double tool_translation_noise = 1e-4;  // metres: the arm's repeatability
  double tool_rotation_noise = 1e-4;     // radians
  int poor_pose = -1;              // this pose's reported tool is `poor_pose_offset` off (-1: none)
  double poor_pose_offset = 0.005;  // metres, in a random direction
  std::uint32_t seed = 1;
};

struct SimulatedArm {
  HandEyeSetup setup = HandEyeSetup::kEyeInHand;
  // Eye-in-hand: tool <- camera and base <- board. Eye-to-hand: base <- camera and tool <- board.
  Eigen::Isometry3d camera = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d board = Eigen::Isometry3d::Identity();
  std::vector<Eigen::Isometry3d> true_tool;      // base <- tool at each still pose
  std::vector<Eigen::Isometry3d> reported_tool;  // ... as the arm reports it
  // Eye-to-hand: where a 3D lidar (x ahead, z up), an RGB-D camera (optical frame) and a 2D laser (its
  // scan plane z = 0) fixed in the base frame would watch the board in the gripper too (base <- sensor),
  // for a rig that has them. Eye-in-hand: a 2D laser on the tool beside the camera (tool <- laser), its
  // scan line crossing the fixed board at a slant.
  Eigen::Isometry3d lidar = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d rgbd = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d laser = Eigen::Isometry3d::Identity();
  // With joints (simulated_joint_arm.h): a second camera on the arm's forearm link (forearm_link <-
  // camera) that sees the board, fixed or in the gripper, at most still poses.
  Eigen::Isometry3d forearm_camera = Eigen::Isometry3d::Identity();
  // ... and with a head beside the arm (SimulatedJointArmOptions::head), its camera (head_tilt_link <- camera).
  Eigen::Isometry3d head_camera = Eigen::Isometry3d::Identity();

  // Camera <- board at pose k (the truth).
  Eigen::Isometry3d cameraFromBoard(int k) const;
};

// The board 0.5 m ahead of the robot's base on the table (eye-in-hand, the camera 0.5-0.7 m from it)
// or in the gripper 0.6-0.9 m in front of a camera on a post (eye-to-hand), seen straight or tilted.
SimulatedArm simulateArm(const SimulatedArmOptions& options);

// The stations of a session of `arm`: at each pose, `views` images' corners of `pattern` projected
// through `camera` with `pixel_noise` (pixels) and observed as calibrate_rig does (observePattern) with
// the intrinsics `camera_info` gives (null: `camera`'s; a camera_info whose focal length is off).
std::vector<HandEyeStation> simulateHandEyeStations(const SimulatedArm& arm, const TargetPattern& pattern, const PinholeCamera& camera,
                                                    int views, double pixel_noise, std::mt19937* rng, const PinholeCamera* camera_info = nullptr);

// A range sensor's board points at pose k: the board's `width` x `height` rectangle sampled on a grid
// `spacing` apart, seen from `base_from_sensor` (where the sensor is at pose k: fixed, or on the tool
// then), with `noise` metres along each ray; in the sensor's frame.
std::vector<Eigen::Vector3d> simulateRangeView(const SimulatedArm& arm, int k, const Eigen::Isometry3d& base_from_sensor, double width,
                                               double height, double spacing, double noise, std::mt19937* rng);

}  // namespace vocal
