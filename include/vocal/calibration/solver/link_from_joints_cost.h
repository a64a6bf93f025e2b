#pragma once
// LinkFromJointsResidual (link_from_joints_residual.h) as the cost both calibration graphs tie a link's
// block with: its blocks the link's rotation and translation, one offset and one reading correction per
// chain joint, and a free origin's correction (6) per chain joint that has one; `mounted`: a sensor's mount
// (rotation, translation) after the frame's blocks, the frame the sensor's on the chain's last link.

#include <vector>

#include "vocal/calibration/joint_chain.h"

namespace ceres {
class CostFunction;
}

namespace vocal {

// `joints` must outlive the cost.
ceres::CostFunction* linkFromJointsCost(const std::vector<JointDescription>* joints, const std::vector<int>& chain,
                                        const std::vector<double>& readings, bool mounted = false);

}  // namespace vocal
