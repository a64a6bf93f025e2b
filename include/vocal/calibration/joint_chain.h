#pragma once
// A robot's joints between the rig's reference frame and a sensor's link (a camera on a pan-tilt head):
// URDF's model of them, each joint's child frame at `origin` in its parent, moved about (revolute) or
// along (prismatic) its axis, in the child frame, by the joint's position plus its zero offset. Kept
// free of ROS (the rig YAML's `joints:` list and a URDF, urdf_joints.h, both give these); the forward
// kinematics is templated so that Ceres differentiates the calibration graph through it.

#include <map>
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
  // Its origin an unknown too (robot_calibration's free frames: a link whose length or angle is off the
  // model), corrected by jointOriginCorrected under JointTolerances' origin prior.
  bool free_origin = false;
};

// A rotation vector as a quaternion, written out so that Ceres's jets pass through it (first order at zero).
template <typename T>
Eigen::Quaternion<T> quaternionFromRotationVector(const Eigen::Matrix<T, 3, 1>& w) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  const T squared = w.squaredNorm();
  if (squared > T(1e-20)) {
    const T angle = sqrt(squared);
    const T scale = sin(angle * T(0.5)) / angle;
    return Eigen::Quaternion<T>(cos(angle * T(0.5)), scale * w.x(), scale * w.y(), scale * w.z());
  }
  return Eigen::Quaternion<T>(T(1), T(0.5) * w.x(), T(0.5) * w.y(), T(0.5) * w.z());
}

// A joint's origin moved by `correction` (w, dt): turned by exp([w]x) in its child frame and shifted by dt in
// its parent, less what the joint's own motion makes of it - a revolute joint's turn about its axis and a
// prismatic joint's shift along it are its offset's, so those parts of the correction are dropped.
template <typename T>
void jointOriginCorrected(const JointDescription& joint, const T* correction, Eigen::Quaternion<T>* rotation, Eigen::Matrix<T, 3, 1>* translation) {
  const Eigen::Quaternion<T> origin_rotation(joint.origin.rotation().cast<T>());
  const Eigen::Matrix<T, 3, 1> axis = joint.axis.cast<T>();
  Eigen::Matrix<T, 3, 1> w(correction[0], correction[1], correction[2]), dt(correction[3], correction[4], correction[5]);
  if (joint.type == JointType::kRevolute) w -= axis * axis.dot(w);
  if (joint.type == JointType::kPrismatic) {
    const Eigen::Matrix<T, 3, 1> along = origin_rotation * axis;
    dt -= along * along.dot(dt);
  }
  *rotation = origin_rotation * quaternionFromRotationVector<T>(w);
  *translation = joint.origin.translation().cast<T>() + dt;
}
Eigen::Isometry3d jointOriginCorrected(const JointDescription& joint, const Eigen::Matrix<double, 6, 1>& correction);

// The joints from `base` down to `link`, in order (empty when link is base). Throws InputError naming
// `where`, the link and the base when no chain of joints leads from one to the other.
std::vector<int> jointChain(const std::vector<JointDescription>& joints, const std::string& base, const std::string& link,
                            const std::string& where);

// One joint's parent_from_child at `position` (offset included by the caller), its origin corrected by
// `origin_correction` where given (jointOriginCorrected).
template <typename T>
void jointTransform(const JointDescription& joint, const T& position, Eigen::Quaternion<T>* rotation, Eigen::Matrix<T, 3, 1>* translation,
                    const T* origin_correction = nullptr) {
  Eigen::Quaternion<T> origin_rotation(joint.origin.rotation().cast<T>());
  Eigen::Matrix<T, 3, 1> origin_translation = joint.origin.translation().cast<T>();
  if (origin_correction) jointOriginCorrected<T>(joint, origin_correction, &origin_rotation, &origin_translation);
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

// base_from_link through `chain` (jointChain) with each joint at positions[i] + offsets[i][0] and, where
// `origins` and origins[i] are given, its origin corrected by origins[i] (6 values).
template <typename T>
void chainTransform(const std::vector<JointDescription>& joints, const std::vector<int>& chain, const double* positions,
                    const T* const* offsets, Eigen::Quaternion<T>* rotation, Eigen::Matrix<T, 3, 1>* translation,
                    const T* const* origins = nullptr) {
  *rotation = Eigen::Quaternion<T>::Identity();
  *translation = Eigen::Matrix<T, 3, 1>::Zero();
  for (std::size_t i = 0; i < chain.size(); ++i) {
    Eigen::Quaternion<T> q;
    Eigen::Matrix<T, 3, 1> t;
    jointTransform(joints[chain[i]], T(positions[i]) + offsets[i][0], &q, &t, origins ? origins[i] : nullptr);
    *translation = *translation + *rotation * t;
    *rotation = *rotation * q;
  }
}

// The same at readings a still pose's corrections are added to as well (both per chain joint): where the
// calibration graphs put a sensor or a tool behind joints.
template <typename T>
void correctedChainTransform(const std::vector<JointDescription>& joints, const std::vector<int>& chain, const double* readings,
                             const T* const* offsets, const T* const* corrections, Eigen::Quaternion<T>* rotation,
                             Eigen::Matrix<T, 3, 1>* translation, const T* const* origins = nullptr) {
  std::vector<T> added(chain.size());
  std::vector<const T*> added_blocks(chain.size());
  for (std::size_t i = 0; i < chain.size(); ++i) added[i] = offsets[i][0] + corrections[i][0], added_blocks[i] = &added[i];
  chainTransform<T>(joints, chain, readings, added_blocks.data(), rotation, translation, origins);
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
  // A free origin's prior (JointDescription::free_origin): how far the model's link may be off, metres
  // and radians per axis (a machined link's tolerance, a mount's angle).
  double origin_translation_sigma = 0.01, origin_rotation_sigma = 0.01;
  // ... and the share of it beyond which a part of an origin counts as not fixed by the session: held at
  // the model's (a shift of a link that turns the joints on either side alike trades with their offsets).
  double unfixed_origin_share = 0.5;

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
  // A free origin (JointDescription::free_origin): the origin as solved, its correction (w, dt) from the
  // model's and standard deviations, and per component whether the session fixed it or its prior holds it.
  bool origin_free = false;
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();
  Eigen::Matrix<double, 6, 1> origin_correction = Eigen::Matrix<double, 6, 1>::Zero(), origin_sigma = Eigen::Matrix<double, 6, 1>::Zero();
  std::string origin_observability;  // for the user: which parts the data fixed, which the prior held
};

// A free origin's result in `out` (JointCalibration::origin_*): the corrected origin, its correction and
// standard deviations (w, dt), and for the user which parts the session fixed and which were held at the
// model's (`held`, indices of (w, dt), and any whose standard deviation is over unfixed_origin_share of its
// prior's; a revolute joint's turn about its axis, a prismatic joint's shift along it, are its offset's and
// not named).
void describeFreeOrigin(const JointDescription& joint, const Eigen::Matrix<double, 6, 1>& correction, const Eigen::Matrix<double, 6, 1>& sigma,
                        const std::vector<int>& held, const JointTolerances& tolerances, JointCalibration* out);

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
  // The board on a link the joints move (an arm's tool holding it before fixed sensors): at each still pose
  // it sits at board_chain's pose for that pose's readings (board_readings, per target pose) times its mount
  // in the chain's last link, an unknown unless known_board_mount gives it. Neither this nor tool poses
  // below: the board is free at each still pose (held by hand, on a stand). Needs the board's full pose
  // (board edges).
  std::vector<int> board_chain;
  std::map<int, std::vector<double>> board_readings;
  // ... or on an arm's tool whose pose the arm reports (tf): per target pose, base <- tool as reported, held
  // within the arm's repeatability (metres, radians; HandEyeOptions' alike) under a Cauchy loss of
  // `tool_loss_sigmas` (a pose millimetres off moves itself, not the result).
  std::map<int, Eigen::Isometry3d> board_tool_poses;
  double tool_translation_sigma = 1e-4, tool_rotation_sigma = 1e-4, tool_loss_sigmas = 5.0;
  std::optional<Eigen::Isometry3d> known_board_mount;
  // The board lies still in the rig frame, an arm's base, while the arm moves the sensors that see it
  // (eye-in-hand): one pose there, each still pose's board held to it within the tool sigmas above (a board
  // nudged moves itself). No sensor's pose is given (CalibrationOptions::reference_sensor -1): the base the
  // joints or the reported tool poses are in is the rig frame, and the first moving joint of each chain is
  // held, as the board takes up its offset.
  bool board_fixed = false;
  // Per sensor (or none): on the arm's tool whose pose the arm reports (tf), at tool_poses' pose for each
  // still pose (base <- tool, held within the tool sigmas as the board's), its mount in tool_frame an unknown.
  std::vector<bool> on_reported_tool;
  std::map<int, Eigen::Isometry3d> tool_poses;
  std::string tool_frame;

  bool jointed(int sensor) const { return sensor >= 0 && sensor < static_cast<int>(chains.size()) && !chains[sensor].empty(); }
  bool onReportedTool(int sensor) const {
    return sensor >= 0 && sensor < static_cast<int>(on_reported_tool.size()) && on_reported_tool[sensor];
  }
  // Whether a sensor is somewhere else at each still pose (behind joints, or on the reported tool).
  bool moves(int sensor) const { return jointed(sensor) || onReportedTool(sensor); }
  bool boardMoves() const { return !board_chain.empty() || !board_tool_poses.empty() || board_fixed; }
  // The board's frame at still pose k where it is on the reported tool or fixed in the rig frame.
  Eigen::Isometry3d boardToolPose(int k) const { return board_fixed ? Eigen::Isometry3d::Identity() : board_tool_poses.at(k); }
  // ... or on the board's chain at that pose's readings (the joints' offsets as they stand): where its mount sits.
  Eigen::Isometry3d boardFrameAt(int k) const;
  // Where a sensor's mount frame was (rig frame) at still pose k read as `joint_positions` (its chain's): its
  // chain's last link at the joints' offsets, the reported tool, or the rig frame itself (a rigid sensor).
  Eigen::Isometry3d mountFrameAt(int sensor, int k, const std::vector<double>& joint_positions) const;
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
// The readings of `chain`'s joints, in its order, from `readings` of the joints `read` lists (jointsOfChains).
// Throws InputError where one of them is not read.
std::vector<double> chainReadings(const std::vector<int>& read, const std::vector<double>& readings, const std::vector<int>& chain);

}  // namespace vocal
