#include "vocal/calibration/urdf_joints.h"

#include <fstream>
#include <sstream>

#include <urdf/model.h>

#include "vocal/core/errors.h"

namespace vocal {

std::vector<JointDescription> urdfJointsFromString(const std::string& xml, const std::string& what) {
  urdf::Model model;
  if (!model.initString(xml)) throw InputError(what + ": not a URDF robot description (urdf::Model could not parse it)");
  std::vector<JointDescription> joints;
  for (const auto& [name, joint] : model.joints_) {
    JointDescription d;
    d.name = name;
    switch (joint->type) {
      case urdf::Joint::REVOLUTE:
      case urdf::Joint::CONTINUOUS: d.type = JointType::kRevolute; break;
      case urdf::Joint::PRISMATIC: d.type = JointType::kPrismatic; break;
      case urdf::Joint::FIXED: d.type = JointType::kFixed; break;
      default: continue;  // floating, planar
    }
    d.parent = joint->parent_link_name;
    d.child = joint->child_link_name;
    const urdf::Pose& origin = joint->parent_to_joint_origin_transform;
    d.origin = Eigen::Isometry3d::Identity();
    d.origin.linear() = Eigen::Quaterniond(origin.rotation.w, origin.rotation.x, origin.rotation.y, origin.rotation.z).normalized().toRotationMatrix();
    d.origin.translation() = Eigen::Vector3d(origin.position.x, origin.position.y, origin.position.z);
    const Eigen::Vector3d axis(joint->axis.x, joint->axis.y, joint->axis.z);
    if (d.type != JointType::kFixed) {
      if (!(axis.norm() > 1e-9)) throw InputError(what + ": joint '" + name + "' has a zero axis");
      d.axis = axis.normalized();
    }
    // robot_calibration's calibrated offsets: the reading at the true zero, as a rising edge.
    if (joint->calibration && joint->calibration->rising) d.offset = *joint->calibration->rising;
    joints.push_back(d);
  }
  return joints;
}

std::vector<JointDescription> readUrdfJoints(const std::string& path) {
  std::ifstream file(path);
  if (!file) throw InputError(path + ": cannot read the URDF");
  std::stringstream text;
  text << file.rdbuf();
  return urdfJointsFromString(text.str(), path);
}

}  // namespace vocal
