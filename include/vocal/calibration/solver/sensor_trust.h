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


// calibrateRig, then while a sensor (not the reference) disagrees by options.trust: the one that disagrees most is
// isolated (CalibrationOptions::isolated_sensors) and the rig re-solved, kept when the sensor still
// disagrees with the rest solved without it. Every sensor that disagrees in the end gets
// SensorCalibration::distrust: what it disagrees by, whether it was taken out of the graph, and its most
// likely cause in words a user acts on. Throws as calibrateRig does for the first solve.
CalibrationResult calibrateRigWithTrust(const std::vector<SensorSpec>& sensors, const std::vector<TargetObservation>& observations,
                                        const CalibrationOptions& options);

// The options that reproduce `result`'s graph (its isolated sensors), for re-solves of the same session
// (the pose jackknife).
CalibrationOptions withIsolatedSensors(CalibrationOptions options, const CalibrationResult& result);

}  // namespace vocal
