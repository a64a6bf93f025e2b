#pragma once
// Per-sensor trust and isolation: a sensor whose board views do not agree with where the other sensors
// put the board (far beyond what noise explains) is named with its likely cause, taken out of the graph,
// and the rest re-solved without it, so that one bad sensor (moved during the session, on a joint the rig
// does not describe, wrong intrinsics, a post taken for the board) never moves the others.

#include <string>
#include <vector>

#include "vocal/calibration/solver/graph_calibration.h"

namespace vocal {

// How far over the thresholds a sensor's disagreement is (> 1: it disagrees), from its SensorCalibration.
double disagreementRatio(const SensorCalibration& sensor, const SensorTrustOptions& trust);

// calibrateRig with every sensor judged against the rest solved without it. A sensor that never saw the
// target in a still pose is left out (not the reference). Then, round by round: the rig solved once
// without each sensor still in the graph; a sensor is at fault when it disagrees (options.trust) with the
// rest solved without it, or when its placement from the poses before some pose and from those after
// differ (a bump); of those, the one whose removal leaves the rest agreeing best is taken out
// (CalibrationOptions::isolated_sensors). Every sensor at fault gets SensorCalibration::distrust: what it
// disagrees by, its most likely cause in words a user acts on, and whether it was taken out. With
// options.trust.isolate false the verdicts are the same and the result is the solve with every sensor.
// Throws as calibrateRig does for the first solve.
CalibrationResult calibrateRigWithTrust(const std::vector<SensorSpec>& sensors, const std::vector<TargetObservation>& observations,
                                        const CalibrationOptions& options);

// The options that reproduce `result`'s graph (its isolated sensors, and an arm's views' scatter as it
// measured it), for re-solves of the same session (the pose jackknife, trust's trials).
CalibrationOptions withIsolatedSensors(CalibrationOptions options, const CalibrationResult& result);

}  // namespace vocal
