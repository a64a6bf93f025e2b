#include "vocal/calibration/joint_chain.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "vocal/core/errors.h"

namespace vocal {

JointType parseJointType(const std::string& name, const std::string& where) {
  if (name == "revolute" || name == "continuous") return JointType::kRevolute;
  if (name == "prismatic") return JointType::kPrismatic;
  if (name == "fixed") return JointType::kFixed;
  throw InputError(where + ": joint type '" + name + "' is unknown: expected revolute, continuous, prismatic or fixed");
}

std::string jointTypeName(JointType type) {
  switch (type) {
    case JointType::kRevolute: return "revolute";
    case JointType::kPrismatic: return "prismatic";
    case JointType::kFixed: return "fixed";
  }
  return "?";
}

std::vector<int> jointChain(const std::vector<JointDescription>& joints, const std::string& base, const std::string& link,
                            const std::string& where) {
  // Up from the link, each frame having one parent joint (a tree, as URDF's), until the base.
  std::vector<int> up;
  std::string frame = link;
  while (frame != base) {
    int parent_joint = -1;
    for (std::size_t j = 0; j < joints.size(); ++j)
      if (joints[j].child == frame) parent_joint = static_cast<int>(j);
    if (parent_joint < 0 || up.size() > joints.size()) {
      throw InputError(where + ": no chain of joints leads from '" + base + "' to '" + link + "' (the frame '" + frame +
                       "' is no joint's child)");
    }
    up.push_back(parent_joint);
    frame = joints[parent_joint].parent;
  }
  return {up.rbegin(), up.rend()};
}

Eigen::Isometry3d jointOriginCorrected(const JointDescription& joint, const Eigen::Matrix<double, 6, 1>& correction) {
  Eigen::Quaterniond q;
  Eigen::Vector3d t;
  jointOriginCorrected<double>(joint, correction.data(), &q, &t);
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();
  origin.linear() = q.normalized().toRotationMatrix();
  origin.translation() = t;
  return origin;
}

void describeFreeOrigin(const JointDescription& joint, const Eigen::Matrix<double, 6, 1>& correction, const Eigen::Matrix<double, 6, 1>& sigma,
                        const std::vector<int>& held_parts, const JointTolerances& tolerances, JointCalibration* out) {
  out->origin_free = true;
  out->origin = jointOriginCorrected(joint, correction);
  out->origin_correction = correction;
  out->origin_sigma = sigma;
  for (const int k : held_parts) out->origin_sigma[k] = 0.0;  // held: not solved
  const char* axes = "xyz";
  const Eigen::Vector3d along = joint.origin.rotation() * joint.axis;
  std::string solved, held;
  for (int k = 0; k < 6; ++k) {
    const bool turn = k < 3;
    const int a = k % 3;
    // The joint's own motion: its offset's part, not the origin's.
    if (turn && joint.type == JointType::kRevolute && std::abs(joint.axis[a]) > 0.99) continue;
    if (!turn && joint.type == JointType::kPrismatic && std::abs(along[a]) > 0.99) continue;
    const std::string name = std::string(turn ? "turn about " : "shift along ") + axes[a];
    const double prior = turn ? tolerances.origin_rotation_sigma : tolerances.origin_translation_sigma;
    const bool was_held = std::find(held_parts.begin(), held_parts.end(), k) != held_parts.end();
    if (!was_held && sigma[k] < tolerances.unfixed_origin_share * prior) {
      char text[96];
      std::snprintf(text, sizeof(text), "%s %+.2f +- %.2f %s", name.c_str(), 1000.0 * correction[k], 1000.0 * sigma[k], turn ? "mrad" : "mm");
      solved += (solved.empty() ? "" : ", ") + std::string(text);
    } else {
      held += (held.empty() ? "" : ", ") + name;
    }
  }
  out->origin_observability = solved.empty() ? "nothing solved" : "solved " + solved;
  if (!held.empty()) out->origin_observability += "; held at the model's (the session's motion does not fix it): " + held;
}

namespace {
// base_from_link with offsets[i] added to the chain's i-th joint.
Eigen::Isometry3d chainPoseWith(const std::vector<JointDescription>& joints, const std::vector<int>& chain, const std::vector<double>& positions,
                                const std::vector<const double*>& offsets) {
  Eigen::Quaterniond q;
  Eigen::Vector3d t;
  chainTransform<double>(joints, chain, positions.data(), offsets.data(), &q, &t);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = q.normalized().toRotationMatrix();
  pose.translation() = t;
  return pose;
}
}  // namespace

Eigen::Isometry3d chainPose(const std::vector<JointDescription>& joints, const std::vector<int>& chain, const std::vector<double>& positions,
                            const std::vector<double>& offsets) {
  std::vector<const double*> chain_offsets;
  for (const int j : chain) chain_offsets.push_back(&offsets.at(j));
  return chainPoseWith(joints, chain, positions, chain_offsets);
}

Eigen::Isometry3d chainPose(const std::vector<JointDescription>& joints, const std::vector<int>& chain, const std::vector<double>& positions) {
  std::vector<const double*> own_offsets;
  for (const int j : chain) own_offsets.push_back(&joints.at(j).offset);
  return chainPoseWith(joints, chain, positions, own_offsets);
}

std::vector<int> jointsOfChains(const std::vector<int>& chain, const std::vector<std::vector<int>>& others) {
  std::vector<int> all = chain;
  for (const std::vector<int>& other : others)
    for (const int j : other)
      if (std::find(all.begin(), all.end(), j) == all.end()) all.push_back(j);
  return all;
}

std::vector<double> chainReadings(const std::vector<int>& read, const std::vector<double>& readings, const std::vector<int>& chain) {
  std::vector<double> out;
  for (const int j : chain) {
    const auto at = std::find(read.begin(), read.end(), j);
    if (at == read.end() || static_cast<std::size_t>(at - read.begin()) >= readings.size()) {
      throw InputError("joint readings: joint " + std::to_string(j) + " of a chain is not among the joints read");
    }
    out.push_back(readings[at - read.begin()]);
  }
  return out;
}

Eigen::Isometry3d JointedMounts::boardFrameAt(int k) const {
  return board_chain.empty() ? boardToolPose(k) : chainPose(joints, board_chain, board_readings.at(k));
}

Eigen::Isometry3d JointedMounts::mountFrameAt(int sensor, int k, const std::vector<double>& joint_positions) const {
  if (jointed(sensor)) return chainPose(joints, chains[sensor], joint_positions);
  if (onReportedTool(sensor)) return tool_poses.at(k);
  return Eigen::Isometry3d::Identity();
}

const std::optional<Eigen::Isometry3d>& JointedMounts::knownMount(int sensor) const {
  static const std::optional<Eigen::Isometry3d> none;
  return moves(sensor) && sensor < static_cast<int>(known_mounts.size()) ? known_mounts[sensor] : none;
}

}  // namespace vocal
