#pragma once
// A hand-eye session of a simulated arm (simulated_arm.h) recorded as a robot records it: the camera's
// images and camera_info at its rate, and the arm on /tf at its own (base -> flange, moving) with the
// flange -> tool offset on /tf_static, as robot_state_publisher gives them; the arm still at each pose
// for a while, then moving to the next while the camera keeps publishing.

#include <string>

#include "vocal/calibration/rig_description.h"
#include "vocal/tools/calibration_bag.h"
#include "vocal/simulation/simulated_arm.h"
#include "vocal/simulation/simulated_joint_arm.h"

namespace vocal {

struct HandEyeBagOptions {
  double still_seconds = 1.0;   // the arm still at each pose
  double moving_seconds = 2.0;  // ... then moving to the next
  double camera_rate = 10.0;    // Hz
  double tf_rate = 200.0;       // Hz
  double image_noise = 2.0;     // grey levels
  double lidar_noise = 0.01;    // metres along each ray (a VLP-16's is 1-3 cm)
  double depth_noise = 0.003;   // metres (an RGB-D camera's at a metre)
  double laser_noise = 0.01;    // metres along each beam (a Hokuyo UTM-30LX's is about 1 cm)
  double laser_beam_aperture = 0.0, laser_beam_divergence = 0.0;  // its beam across (SimulatedRoomView)
  // Images as image_transport's compressed transport records them (JPEG, quality 95) on the rig's image
  // topic, which then ends in "/compressed" (simulatedHandEyeRig).
  bool compressed_images = false;
  // An arm with joints (simulated_joint_arm.h): its readings on /joint_states at tf_rate too, and /tf as
  // robot_state_publisher makes it of them (uncalibrated).
  const SimulatedJointArm* joint_arm = nullptr;
  // Faults of one sensor each (calibration_bag.h), the still poses being the arm's: moved in its parent
  // frame (kMoves, kBumped), its stamps late (kTimeOffset), a camera's camera_info focal length scaled
  // (kFocalScale); ground_truth.yaml keeps the sensor as built.
  std::vector<SimulatedSensorFault> faults;
  std::uint32_t seed = 1;
};

// The rig a user would write for it: reference frame "arm_base", the tool frame "arm_tool", the camera
// on the tool (eye-in-hand, the board fixed in arm_base) or fixed in arm_base (eye-to-hand, the board on
// the tool); `target` as given.
// `beside`: eye-to-hand, a 3D lidar (VLP-16-like), an RGB-D camera and a 2D laser fixed beside the camera,
// watching the board in the gripper too (SimulatedArm::lidar, rgbd, laser); eye-in-hand, a 2D laser on the
// tool beside the camera (SimulatedArm::laser, parent the tool frame).
RigDescription simulatedHandEyeRig(HandEyeSetup setup, const TargetDescription& target, bool compressed_images = false, bool beside = false);

// `joint_arm`: the rig names the arm's joints (offsets unknown: 0) down to the tool, the tool's pose then
// comes from /joint_states rather than tf. `forearm`: a second camera on the arm's forearm_link
// (SimulatedArm::forearm_camera). With a head (SimulatedJointArm::head_chain): its camera on
// head_tilt_link (SimulatedArm::head_camera), the head's joints named beside the arm's.
RigDescription simulatedJointArmRig(HandEyeSetup setup, const TargetDescription& target, const SimulatedJointArm& joint_arm, bool beside = false,
                                    bool forearm = false);

// Throws InputError naming the bag when it cannot be written, and for rates or times that are not positive.
void writeSimulatedHandEyeBag(const SimulatedArm& arm, const RigDescription& rig, const HandEyeBagOptions& options, const std::string& bag_path);

// The truth as YAML: the camera and the board each in its parent, every still pose's tool (true and as
// reported), and which pose was reported off.
void writeHandEyeGroundTruth(const std::string& path, const SimulatedArm& arm, const RigDescription& rig, int poor_pose,
                             const SimulatedJointArm* joint_arm = nullptr);  // adds the joints' true offsets

}  // namespace vocal
