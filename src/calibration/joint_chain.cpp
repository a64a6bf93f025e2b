#include "vocal/calibration/joint_chain.h"

#include <algorithm>

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

const std::optional<Eigen::Isometry3d>& JointedMounts::knownMount(int sensor) const {
  static const std::optional<Eigen::Isometry3d> none;
  return jointed(sensor) && sensor < static_cast<int>(known_mounts.size()) ? known_mounts[sensor] : none;
}

}  // namespace vocal
