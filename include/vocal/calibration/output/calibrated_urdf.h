#pragma once
// The robot's URDF with the calibration in it: each calibrated joint's zero offset as its
// <calibration rising="..."/> (what robot_calibration writes), each solved free origin as its <origin>,
// the rest of the file as it was.

#include <map>
#include <string>

#include <Eigen/Geometry>

namespace vocal {

// `urdf`: the robot's URDF text; `offsets`: joint name -> offset (radians; metres). Each named joint's
// <calibration> element is replaced (or added before its </joint>). Throws InputError naming `what` for a
// joint the URDF does not have.
std::string withJointOffsets(const std::string& urdf, const std::map<std::string, double>& offsets, const std::string& what);

// `urdf` with each named joint's <origin .../> replaced by `origins`' (joint name -> its origin in its
// parent; added where the joint has none). Throws InputError naming `what` for a joint the URDF does not have.
std::string withJointOrigins(const std::string& urdf, const std::map<std::string, Eigen::Isometry3d>& origins, const std::string& what);

// Both from the file at `from` to the file at `to`; throws InputError naming either when it cannot be read or written.
void writeCalibratedUrdf(const std::string& from, const std::string& to, const std::map<std::string, double>& offsets,
                         const std::map<std::string, Eigen::Isometry3d>& origins = {});

}  // namespace vocal
