#pragma once
// A robot's joints from its URDF (urdf::Model, ROS's own parser), as the calibration models them
// (joint_chain.h): what a rig YAML's `urdf:` names instead of listing the joints itself.

#include <string>
#include <vector>

#include "vocal/calibration/joint_chain.h"

namespace vocal {

// Every revolute, continuous, prismatic and fixed joint of the URDF file, with its calibration offset
// where the URDF has one (<calibration rising=...>, what robot_calibration writes). Floating and planar
// joints are left out (no chain to a sensor runs through them). Throws InputError naming the file when it
// cannot be read or parsed.
std::vector<JointDescription> readUrdfJoints(const std::string& path);
// The same from the URDF's text (robot_description on the parameter server); `what` names it.
std::vector<JointDescription> urdfJointsFromString(const std::string& xml, const std::string& what);

}  // namespace vocal
