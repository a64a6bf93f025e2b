#include "vocal/simulation/simulated_joint_arm.h"

#include <cmath>
#include <random>
#include <string>

#include <Eigen/Dense>

#include "vocal/core/errors.h"
#include "vocal/core/se3.h"
#include "vocal/simulation/still_pose_timeline.h"

namespace vocal {

namespace {
constexpr int kElbow = 2;  // in sixJointArm()

std::vector<JointDescription> sixJointArm() {
  // name, parent, child, origin (translation), axis
  const struct {
    const char* name;
    const char* parent;
    const char* child;
    Eigen::Vector3d origin, axis;
  } links[] = {{"shoulder_pan_joint", "arm_base", "shoulder_link", {0, 0, 0.15}, {0, 0, 1}},
               {"shoulder_lift_joint", "shoulder_link", "upper_arm_link", {0, 0.08, 0.1}, {0, 1, 0}},
               {"elbow_joint", "upper_arm_link", "forearm_link", {0, -0.06, 0.5}, {0, 1, 0}},
               {"wrist_1_joint", "forearm_link", "wrist_1_link", {0, 0, 0.45}, {0, 1, 0}},
               {"wrist_2_joint", "wrist_1_link", "wrist_2_link", {0, 0.09, 0}, {0, 0, 1}},
               {"wrist_3_joint", "wrist_2_link", "arm_tool", {0, 0, 0.1}, {0, 1, 0}}};
  std::vector<JointDescription> joints;
  for (const auto& l : links) {
    JointDescription j;
    j.name = l.name, j.parent = l.parent, j.child = l.child;
    j.origin.translation() = l.origin;
    j.axis = l.axis;
    joints.push_back(j);
  }
  return joints;
}

Vector6d poseError(const Eigen::Isometry3d& target, const Eigen::Isometry3d& at) { return se3Log(target.inverse() * at); }

// Damped Gauss-Newton on the joint angles from `start`; false when it does not reach the pose.
bool reach(const std::vector<JointDescription>& joints, const std::vector<int>& chain, const Eigen::Isometry3d& target,
           std::vector<double>* angles) {
  const std::vector<double> zero(joints.size(), 0.0);
  for (int iteration = 0; iteration < 200; ++iteration) {
    const Vector6d error = poseError(target, chainPose(joints, chain, *angles, zero));
    if (error.norm() < 1e-12) return true;
    Eigen::Matrix<double, 6, 6> jacobian;
    for (int i = 0; i < 6; ++i) {
      std::vector<double> moved = *angles;
      moved[i] += 1e-7;
      jacobian.col(i) = (poseError(target, chainPose(joints, chain, moved, zero)) - error) / 1e-7;
    }
    const Eigen::Matrix<double, 6, 6> normal = jacobian.transpose() * jacobian + 1e-9 * Eigen::Matrix<double, 6, 6>::Identity();
    const Vector6d step = normal.ldlt().solve(jacobian.transpose() * error);
    for (int i = 0; i < 6; ++i) (*angles)[i] -= std::max(-0.3, std::min(0.3, step[i]));
  }
  return poseError(target, chainPose(joints, chain, *angles, zero)).norm() < 1e-9;
}
// The head: a pan joint 0.9 m up at the arm's side (a metre from its first joint's axis, so that the two
// first joints' offsets turn the arm and the head apart), a tilt joint 12 cm above it, the camera 6 cm ahead
// of the tilt axis looking along the tilt link's x. At each still pose it turns towards the board's centre,
// up to 0.25 rad off in pan and 0.18 in tilt (the board still in view): the board in a different part of
// its image each time, as a calibration's head poses are chosen.
void addHead(SimulatedJointArm* out, const SimulatedJointArmOptions& options, std::mt19937* rng) {
  JointDescription pan, tilt;
  pan.name = "head_pan_joint", pan.parent = "arm_base", pan.child = "head_pan_link";
  pan.origin.translation() = Eigen::Vector3d(0.2, 0.8, 0.9);
  pan.axis = Eigen::Vector3d::UnitZ();
  tilt.name = "head_tilt_joint", tilt.parent = "head_pan_link", tilt.child = SimulatedJointArm::kHeadLink;
  tilt.origin.translation() = Eigen::Vector3d(0.0, 0.0, 0.12);
  tilt.axis = Eigen::Vector3d::UnitY();
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::normal_distribution<double> noise(0.0, options.reading_noise);
  for (JointDescription* joint : {&pan, &tilt}) joint->offset = options.offset_range * unit(*rng);
  out->head_chain = {static_cast<int>(out->joints.size()), static_cast<int>(out->joints.size()) + 1};
  out->joints.push_back(pan);
  out->joints.push_back(tilt);
  // Optical z along the link's x, x along its -y, y along its -z.
  Eigen::Isometry3d& camera = out->arm.head_camera;
  camera = Eigen::Isometry3d::Identity();
  camera.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  camera.translation() = Eigen::Vector3d(0.06, 0.0, 0.04);
  const double step = 2.0 * M_PI / options.encoder_counts;
  const bool in_hand = out->arm.setup == HandEyeSetup::kEyeInHand;
  for (std::size_t k = 0; k < out->angles.size(); ++k) {
    const Eigen::Vector3d board = in_hand ? out->arm.board.translation() : out->arm.true_tool[k] * out->arm.board.translation();
    const Eigen::Vector3d from_tilt = board - (pan.origin.translation() + tilt.origin.translation());
    const std::vector<double> angles = {std::atan2(from_tilt.y(), from_tilt.x()) + 0.25 * unit(*rng),
                                        std::atan2(-from_tilt.z(), from_tilt.head<2>().norm()) + 0.18 * unit(*rng)};
    std::vector<double> readings;
    for (std::size_t j = 0; j < angles.size(); ++j)
      readings.push_back(std::round((angles[j] - out->joints[out->head_chain[j]].offset + noise(*rng)) / step) * step);
    out->head_angles.push_back(angles);
    out->head_readings.push_back(readings);
  }
}
}  // namespace

std::vector<double> SimulatedJointArm::readingsAt(double time, double still, double moving) const {
  return valuesAtTime(readings, time, still, moving);
}

std::vector<double> SimulatedJointArm::anglesAt(double time, double still, double moving) const {
  return valuesAtTime(angles, time, still, moving);
}

Eigen::Isometry3d SimulatedJointArm::headAt(const std::vector<double>& at) const {
  return chainPose(joints, head_chain, at, std::vector<double>(joints.size(), 0.0));
}

std::vector<double> SimulatedJointArm::allReadings(std::size_t pose) const {
  std::vector<double> all = readings[pose];
  if (!head_chain.empty()) all.insert(all.end(), head_readings[pose].begin(), head_readings[pose].end());
  return all;
}

std::vector<double> SimulatedJointArm::allReadingsAt(double time, double still, double moving) const {
  std::vector<double> all = readingsAt(time, still, moving);
  if (head_chain.empty()) return all;
  const std::vector<double> head = valuesAtTime(head_readings, time, still, moving);
  all.insert(all.end(), head.begin(), head.end());
  return all;
}

Eigen::Isometry3d SimulatedJointArm::headAt(double time, double still, double moving) const {
  return headAt(valuesAtTime(head_angles, time, still, moving));
}

std::vector<int> SimulatedJointArm::allJoints() const {
  std::vector<int> all = chain;
  all.insert(all.end(), head_chain.begin(), head_chain.end());
  return all;
}

Eigen::Isometry3d SimulatedJointArm::forearmAt(const std::vector<double>& at) const {
  const std::vector<int> forearm(chain.begin(), chain.begin() + kForearmJoints);
  return chainPose(joints, forearm, std::vector<double>(at.begin(), at.begin() + kForearmJoints), std::vector<double>(joints.size(), 0.0));
}

SimulatedJointArm simulateJointArm(const SimulatedArmOptions& arm_options, const SimulatedJointArmOptions& options) {
  SimulatedJointArm out;
  out.arm = simulateArm(arm_options);
  out.joints = sixJointArm();
  out.chain = {0, 1, 2, 3, 4, 5};
  out.model_joints = out.joints;
  out.joints[kElbow].origin.translation().z() += options.elbow_length_error;
  std::mt19937 rng(options.seed * 1000003u + 7u);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::normal_distribution<double> noise(0.0, options.reading_noise);
  for (JointDescription& joint : out.joints) joint.offset = options.offset_range * unit(rng);
  const double step = 2.0 * M_PI / options.encoder_counts;
  const std::vector<double> zero(out.joints.size(), 0.0);
  std::vector<double> previous = {0.0, 0.5, 1.2, 1.0, 0.0, 0.0};  // elbow up, wrist over the table
  for (std::size_t k = 0; k < out.arm.true_tool.size(); ++k) {
    std::vector<double> angles = previous;
    bool reached = reach(out.joints, out.chain, out.arm.true_tool[k], &angles);
    for (int restart = 0; !reached && restart < 60; ++restart) {
      angles = previous;
      for (double& a : angles) a += (restart < 20 ? 0.8 : 2.0) * unit(rng);
      reached = reach(out.joints, out.chain, out.arm.true_tool[k], &angles);
    }
    if (!reached) throw InputError("simulated joint arm: still pose " + std::to_string(k + 1) + " is out of the arm's reach");
    previous = angles;
    out.angles.push_back(angles);
    std::vector<double> readings;
    for (std::size_t j = 0; j < angles.size(); ++j) {
      readings.push_back(std::round((angles[j] - out.joints[out.chain[j]].offset + noise(rng)) / step) * step);
    }
    out.readings.push_back(readings);
    out.arm.true_tool[k] = chainPose(out.joints, out.chain, angles, zero);
    out.arm.reported_tool[k] = chainPose(out.model_joints, out.chain, readings, zero);  // robot_state_publisher's, uncalibrated
  }
  // The forearm camera: where the main camera was at one still pose, 10 cm behind the wrist camera
  // (eye-in-hand) or 30 cm ahead of the post camera (eye-to-hand), that pose chosen so the board's centre
  // lies within 8 degrees of its optical axis at the most still poses.
  const bool in_hand = out.arm.setup == HandEyeSetup::kEyeInHand;
  int most = -1;
  for (std::size_t candidate = 0; candidate < out.angles.size(); ++candidate) {
    const Eigen::Isometry3d camera = (in_hand ? out.arm.true_tool[candidate] * out.arm.camera * Eigen::Translation3d(0.0, 0.0, -0.1)
                                              : out.arm.camera * Eigen::Translation3d(0.0, 0.0, 0.3));
    const Eigen::Isometry3d mount = out.forearmAt(out.angles[candidate]).inverse() * camera;
    int seen = 0;
    for (std::size_t k = 0; k < out.angles.size(); ++k) {
      const Eigen::Vector3d board = in_hand ? out.arm.board.translation() : out.arm.true_tool[k] * out.arm.board.translation();
      const Eigen::Vector3d centre = (out.forearmAt(out.angles[k]) * mount).inverse() * board;
      seen += centre.z() > 0.2 && centre.normalized().z() > std::cos(8.0 * M_PI / 180.0);
    }
    if (seen > most) most = seen, out.arm.forearm_camera = mount;
  }
  if (options.head) addHead(&out, options, &rng);
  for (std::size_t j = out.model_joints.size(); j < out.joints.size(); ++j) out.model_joints.push_back(out.joints[j]);  // the head's
  for (JointDescription& joint : out.model_joints) joint.offset = 0.0;  // unknown
  return out;
}

}  // namespace vocal
