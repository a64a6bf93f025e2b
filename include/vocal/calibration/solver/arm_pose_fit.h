#pragma once
// How far the still-pose graph moved each of an arm's still poses from where the arm put it: the board on
// its tool, or a sensor it carries, against its readings (offsets as solved) or its reported tool pose. A
// pose the others cannot be fitted with unless it moves beyond the arm's repeatability is poor: its robust
// loss keeps it from pulling the result, and the user is told which pose to look at, as the arm's own
// graph tells (HandEyeResult::poor_stations).

#include <map>
#include <vector>

#include "vocal/calibration/calibration_types.h"
#include "vocal/calibration/solver/graph_calibration.h"

namespace vocal {

struct ArmPoseFit {
  // The carried frame that moved most (in the arm's sigmas): metres and radians from where the arm put it.
  double shift = 0.0, turn = 0.0;
  // That move in the arm's sigmas: the readings' (JointTolerances::readingSigma) for a pose from the joints,
  // the reported tool's (JointedMounts::tool_*_sigma) for one from tf.
  double departure = 0.0;
  bool poor = false;  // departure over JointedMounts::tool_loss_sigmas
  // Its camera views (whole poses) against where the arm put camera and board as solved: mean distance (m)
  // and angle (rad), over `views`.
  double view_distance = 0.0, view_angle = 0.0;
  int views = 0;
};

// Per still pose of `solved` (an arm's session: the board or some sensor moves with the arm), its fit; empty
// for a rig with nothing on an arm.
std::map<int, ArmPoseFit> armPoseFits(const std::vector<SensorSpec>& sensors, const std::vector<TargetObservation>& observations,
                                      const CalibrationResult& solved);

}  // namespace vocal
