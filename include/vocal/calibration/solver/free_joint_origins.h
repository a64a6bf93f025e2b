#pragma once
// Free joint origins (JointDescription::free_origin) in either calibration graph (graph_calibration.h,
// hand_eye_calibration.h): each a block of 6 (joint_origin_prior.h) under the model's prior; after a first
// solve, the parts the session does not fix (a standard deviation over JointTolerances::unfixed_origin_share
// of the prior's: a link's shift that turns the joints on either side alike, a revolute joint's turn about
// its own axis) are set back to the model's and held, and the graph solved again; then each origin as
// solved, with what fixed it (describeFreeOrigin). The blocks are indexed as the caller's joints are.

#include <vector>

#include "vocal/calibration/joint_chain.h"
#include "vocal/core/se3.h"

namespace ceres {
class Problem;
}

namespace vocal {

// The prior on each origin block `problem` holds.
void addJointOriginPriors(ceres::Problem* problem, std::vector<Vector6d>& origins, const JointTolerances& tolerances);

// Each origin's parts in `held` (indices of (w, dt)) set to zero and held in `problem`.
void holdOriginParts(ceres::Problem* problem, std::vector<Vector6d>* origins, const std::vector<std::vector<int>>& held);

// From `problem` as solved: the parts its covariance leaves to their prior, added to `held` and held
// (holdOriginParts). False when the problem holds no origin block (nothing to solve again).
bool holdUnfixedOriginParts(ceres::Problem* problem, std::vector<Vector6d>* origins, const JointTolerances& tolerances,
                            std::vector<std::vector<int>>* held);

// Each origin in `problem` as solved into results[i] (describeFreeOrigin), its joint joints[i]: the
// standard deviations from the problem's covariance (zero where it cannot be computed).
void setFreeOriginResults(ceres::Problem* problem, std::vector<Vector6d>& origins, const std::vector<std::vector<int>>& held,
                          const std::vector<JointDescription>& joints, const JointTolerances& tolerances, std::vector<JointCalibration>* results);

}  // namespace vocal
