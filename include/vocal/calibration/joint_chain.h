#pragma once
// A robot's joints between the rig's reference frame and a sensor's link (a camera on a pan-tilt head):
// URDF's model of them, each joint's child frame at `origin` in its parent, moved about (revolute) or
// along (prismatic) its axis, in the child frame, by the joint's position plus its zero offset. Kept
// free of ROS (the rig YAML's `joints:` list and a URDF, urdf_joints.h, both give these); the forward
// kinematics is templated so that Ceres differentiates the calibration graph through it.

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace vocal {

enum class JointType { kRevolute, kPrismatic, kFixed };

JointType parseJointType(const std::string& name, const std::string& where);  // revolute, continuous, prismatic, fixed
std::string jointTypeName(JointType type);

struct JointDescription {
  std::string name;
  JointType type = JointType::kRevolute;
  std::string parent, child;  // frames
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();  // the child frame at position 0, in the parent
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();           // unit, in the child frame
  // Radians (metres): what the joint's encoder reads at its true zero, added to every reading - the
  // calibrated unknown (robot_calibration's calibration_offsets). The initial value; the truth in a
  // simulation's ground truth.
  double offset = 0.0;
};

// The joints from `base` down to `link`, in order (empty when link is base). Throws InputError naming
// `where`, the link and the base when no chain of joints leads from one to the other.
std::vector<int> jointChain(const std::vector<JointDescription>& joints, const std::string& base, const std::string& link,
                            const std::string& where);

// One joint's parent_from_child at `position` (offset included by the caller).
template <typename T>
void jointTransform(const JointDescription& joint, const T& position, Eigen::Quaternion<T>* rotation, Eigen::Matrix<T, 3, 1>* translation) {
  const Eigen::Quaternion<T> origin_rotation(joint.origin.rotation().cast<T>());
  const Eigen::Matrix<T, 3, 1> origin_translation = joint.origin.translation().cast<T>();
  const Eigen::Matrix<T, 3, 1> axis = joint.axis.cast<T>();
  if (joint.type == JointType::kRevolute) {
    // The quaternion of a turn by `position` about `axis`, written out (Eigen's AngleAxis is not autodiff-safe).
    using std::cos;
    using std::sin;
    const T half = position * T(0.5);
    const Eigen::Quaternion<T> turn(cos(half), sin(half) * axis.x(), sin(half) * axis.y(), sin(half) * axis.z());
    *rotation = origin_rotation * turn;
    *translation = origin_translation;
  } else if (joint.type == JointType::kPrismatic) {
    *rotation = origin_rotation;
    *translation = origin_translation + origin_rotation * (axis * position);
  } else {
    *rotation = origin_rotation;
    *translation = origin_translation;
  }
}

// base_from_link through `chain` (jointChain) with each joint at positions[i] + offsets[chain[i]].
template <typename T>
void chainTransform(const std::vector<JointDescription>& joints, const std::vector<int>& chain, const double* positions,
                    const T* const* offsets, Eigen::Quaternion<T>* rotation, Eigen::Matrix<T, 3, 1>* translation) {
  *rotation = Eigen::Quaternion<T>::Identity();
  *translation = Eigen::Matrix<T, 3, 1>::Zero();
  for (std::size_t i = 0; i < chain.size(); ++i) {
    Eigen::Quaternion<T> q;
    Eigen::Matrix<T, 3, 1> t;
    jointTransform(joints[chain[i]], T(positions[i]) + offsets[i][0], &q, &t);
    *translation = *translation + *rotation * t;
    *rotation = *rotation * q;
  }
}

// The same at readings a still pose's corrections are added to as well (both per chain joint): where the
// calibration graphs put a sensor or a tool behind joints.
template <typename T>
void correctedChainTransform(const std::vector<JointDescription>& joints, const std::vector<int>& chain, const double* readings,
                             const T* const* offsets, const T* const* corrections, Eigen::Quaternion<T>* rotation,
                             Eigen::Matrix<T, 3, 1>* translation) {
  std::vector<T> added(chain.size());
  std::vector<const T*> added_blocks(chain.size());
  for (std::size_t i = 0; i < chain.size(); ++i) added[i] = offsets[i][0] + corrections[i][0], added_blocks[i] = &added[i];
  chainTransform<T>(joints, chain, readings, added_blocks.data(), rotation, translation);
}

// The same in doubles: base_from_link with the chain's joints at `positions` (one per chain joint) plus
// offsets[joint] (one per joint of `joints`), or plus each joint's own offset.
Eigen::Isometry3d chainPose(const std::vector<JointDescription>& joints, const std::vector<int>& chain, const std::vector<double>& positions,
                            const std::vector<double>& offsets);
Eigen::Isometry3d chainPose(const std::vector<JointDescription>& joints, const std::vector<int>& chain, const std::vector<double>& positions);

// How a joint must move, how far its readings may be off, and how well its offset must be solved, in
// radians for a revolute joint and metres for a prismatic one: what both calibration graphs judge joints by.
struct JointTolerances {
  // A joint must move this much over the session for the offsets before it to be told from a mount.
  double min_motion = 0.05, min_prismatic_motion = 0.02;
  // How far a still pose's reading may be from the joint's true position (the encoder's counts, the
  // gears' backlash, the link's flex): each still pose's readings are corrected within it (a prior), so
  // that the views' own precision does not overstate the offsets'.
  double reading_sigma = 0.001, prismatic_reading_sigma = 0.0005;
  // An offset solved less well than this is named weak.
  double max_offset_sigma = 0.002, max_prismatic_offset_sigma = 0.002;

  double minMotion(const JointDescription& joint) const { return prismatic(joint) ? min_prismatic_motion : min_motion; }
  double readingSigma(const JointDescription& joint) const { return prismatic(joint) ? prismatic_reading_sigma : reading_sigma; }
  double maxOffsetSigma(const JointDescription& joint) const { return prismatic(joint) ? max_prismatic_offset_sigma : max_offset_sigma; }
  static bool prismatic(const JointDescription& joint) { return joint.type == JointType::kPrismatic; }
};

// A joint's zero offset as solved.
struct JointCalibration {
  double offset = 0.0;  // radians (metres), added to the encoder's reading
  double standard_deviation = 0.0;
  // The offset could not be told from a mount (no joint after it in a sensor's chain moved): held at its
  // initial value, and why, for the user. Empty: solved.
  std::string held;
  // Solved: what fixed it, for the user (the joints on either side that moved, or a pose the rig gives).
  std::string fixed_by;
  double motion = 0.0;  // the range its positions covered over the still poses
  // Solved, but its standard deviation is over max_offset_sigma: what would fix it better, for the user.
  std::string weak;
  // False for a fixed joint, and one no calibrated sensor is behind: nothing to tell the user of it.
  bool reported = true;
};

// Sensors mounted behind a robot's joints (a camera on a pan-tilt head): at each still pose the sensor
// sits at its chain's pose for that pose's joint positions (TargetObservation::joint_positions) times its
// mount in the chain's last link, the unknown in place of its pose in the rig frame. The joints' zero
// offsets are unknowns of the same graph.
struct JointedMounts {
  std::vector<JointDescription> joints;  // offset: the initial value
  std::vector<std::vector<int>> chains;  // per sensor (or none): its joints from the rig frame (jointChain); empty: rigid
  // Per sensor (or none): a mount known from the robot's model (CAD), held; its joints' offsets are then
  // all solvable. Unset: the mount is an unknown.
  std::vector<std::optional<Eigen::Isometry3d>> known_mounts;
  JointTolerances tolerances;

  bool jointed(int sensor) const { return sensor >= 0 && sensor < static_cast<int>(chains.size()) && !chains[sensor].empty(); }
  const std::optional<Eigen::Isometry3d>& knownMount(int sensor) const;
};

// An arm whose tool's pose comes from its joints (a hand-eye rig whose moving frame is a link of the rig's
// joints): the chain from the base to the tool, and how far a still pose's reading may be off.
struct ArmJoints {
  std::vector<JointDescription> joints;  // offset: the initial value
  std::vector<int> chain;                // base -> tool (jointChain)
  JointTolerances tolerances;
  // The joints each still pose reads (HandEyeStation::joint_positions), in order: the chain's, then those
  // of other links' chains sensors sit on (a head's). Empty: the chain's.
  std::vector<int> read;
  const std::vector<int>& readJoints() const { return read.empty() ? chain : read; }
};

// `chain` followed by each of `others`' joints not already listed: the joints a graph over several chains
// from one base reads (ArmJoints::read).
std::vector<int> jointsOfChains(const std::vector<int>& chain, const std::vector<std::vector<int>>& others);

}  // namespace vocal
