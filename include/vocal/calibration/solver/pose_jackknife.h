#pragma once
// How far each sensor's solution moves when one target pose is left out: the jackknife over target
// poses. The solver's covariance takes every point's error as independent; a lidar's ring biases, a
// hand on the board or a lens's residual distortion make a pose's points wrong together, differently
// from pose to pose, and only the spread between poses shows it.

#include <string>
#include <vector>

#include "vocal/calibration/solver/graph_calibration.h"

namespace vocal {

struct PoseJackknife {
  // Per sensor: translation (m) along and rotation (rad) about the rig frame's axes, as
  // SensorCalibration::standard_deviation; zero for the reference. A sensor behind joints: of its pose in
  // the rig frame at the still pose where a re-solve moved it most (its mount and the joints' offsets
  // trade off; where the sensor is is what tf gets).
  std::vector<Vector6d> standard_deviation;
  int poses = 0;   // target poses, each left out once
  int solved = 0;  // of those, the re-solves that were trusted and counted (a pose that a sensor cannot
                   // do without leaves it unconstrained: that re-solve is skipped)
};

// Re-solves `observations` without each target pose in turn (calibrateRig with `options`) and returns
// the jackknife standard deviation of every sensor's pose around `full`, the solution from all poses.
// Throws InputError when fewer than 3 re-solves succeed.
PoseJackknife jackknifeOverPoses(const std::vector<SensorSpec>& sensors, const std::vector<TargetObservation>& observations,
                                 const CalibrationOptions& options, const CalibrationResult& full);

// How well a rig solved without a target pose predicts one range sensor's view of the board at that
// pose: cross-validation over poses, which tells two ways of treating a sensor's data apart (its ring
// offsets applied or not) by what they predict rather than by how well they fit themselves.
struct HeldOutFit {
  double rms = 0.0;     // metres: the sensor's held-out board points from the board's plane as predicted
  double median = 0.0;  // metres: the median of those points' distances (a few stray points weigh less)
  int poses = 0;        // poses it was measured at
};

// For each target pose that `sensor` and another sensor saw: the rig re-solved without the pose, the
// board's plane fitted to the other sensors' points there (placed by their re-solved poses), and the
// sensor's points (placed by its own) measured against it. A re-solve that fails is skipped.
HeldOutFit heldOutBoardFit(const std::vector<SensorSpec>& sensors, const std::vector<TargetObservation>& observations,
                           const CalibrationOptions& options, int sensor);

// How far a sensor may move between the jackknife's re-solves before its result is called uncertain.
struct SpreadTolerance {
  double translation = 0.01;  // metres, the norm over the rig frame's axes
  double rotation = 0.01;     // radians
};

// Whether a sensor's spread (PoseJackknife::standard_deviation) is over `tolerance`.
bool spreadIsOver(const Vector6d& spread, const SpreadTolerance& tolerance);

// One line per sensor whose spread is over `tolerance`: its name, the spread, the rig axis it moves most
// along and about, and (by sensor type) the likely cause or the poses that would pin it down. Empty when
// every sensor is within.
std::vector<std::string> spreadOverTolerance(const PoseJackknife& jackknife, const std::vector<SensorSpec>& sensors,
                                             const SpreadTolerance& tolerance);

}  // namespace vocal
