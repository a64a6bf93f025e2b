#pragma once
// Sampling-consensus rejection of observations that disagree with the rigid transform most target
// poses agree on, sensor pair by sensor pair (MSG-Cal's outlier filter).

#include <cstdint>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "vocal/calibration/plane.h"

namespace vocal {

struct ConsensusOptions {
  int iterations = 200;          // random 3-pose samples per sensor pair
  double max_angle = 0.035;      // radians between a plane and its transformed partner (2 degrees)
  double max_offset = 0.02;      // metres between their offsets
  int min_shared_poses = 5;      // pairs sharing fewer poses cast no votes
  // Metres by which two poses' board centres may be farther apart in one sensor than in the other (a
  // range sensor's centre moves with what part of the board it sees).
  double max_centre_difference = 0.15;
  std::uint32_t seed = 1;
};

// planes[s] maps target pose -> plane seen by sensor s (plane-seeing sensors only). For every pair of
// sensors, the transform with the largest consensus votes each shared pose in (+1) or out (-1) for
// both sensors; an observation (sensor, pose) whose votes sum below zero is rejected. When the planes
// are too close to parallel for any 3-pose sample to fix a transform (a board tilted only up and down),
// `centres` (pose -> board centre seen, per sensor) still vote: a pose is in when its centre's distance
// to most other poses' centres is the same in both sensors, as it is for any rigid transform.
std::set<std::pair<int, int>> rejectInconsistentObservations(const std::vector<std::map<int, Plane>>& planes,
                                                            const ConsensusOptions& options = {},
                                                            const std::vector<std::map<int, Eigen::Vector3d>>* centres = nullptr);

}  // namespace vocal
