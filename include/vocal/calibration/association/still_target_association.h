#pragma once
// ---- MSG-Cal stage 2, association (calibration/association/): time -> still target poses -------------
// In:  every sensor's TimedObservations (extraction's results with their stamps), in any order.
// Out: one TargetObservation per sensor and still pose, target_pose numbered by time: what solver/
//      calibrates from. Messages taken in motion or outside the sensors' common still span are dropped.
// ------------------------------------------------------------------------------------------------------
//
// Association by time: observations of different sensors taken while the target was held still are
// of one plane. Each sensor's stream is cut into still runs (consecutive observations whose plane, or
// a 2D laser's line, does not move; a message or two unlike the run between ones like it are passed
// over); runs of two or more sensors that overlap in time form one target pose. The gap a run may
// bridge follows each sensor's own message period, so slow (triggered, 3 Hz) and fast sensors
// associate alike.

#include <string>
#include <vector>

#include "vocal/calibration/calibration_types.h"

namespace vocal {

struct TimedObservation {
  int sensor = 0;
  double stamp = 0.0;  // seconds
  std::vector<Eigen::Vector3d> points;  // in the sensor frame
  std::vector<PlaneMeasurement> plane_measurements;  // a camera's, as in TargetObservation
  std::vector<Eigen::Vector3d> outline;              // a range sensor's, as in TargetObservation
  // The points of the whole view when `points` is a sample of them (what a session deciding what to keep
  // associates: stillness needs each view's plane, not every return); 0: points.size().
  std::size_t point_count = 0;
};

struct StillnessOptions {
  double max_angle = 0.01;     // radians between consecutive planes (or laser lines) of a still run
  double max_offset = 0.005;   // metres between their offsets (or line centroids)
  double jitter_multiple = 3.0;  // ... or this many times the sensor's median consecutive difference, if larger
  double max_gap = 0.3;        // seconds between consecutive observations of a run, at least ...
  double gap_periods = 2.5;    // ... and up to this many of the sensor's median message periods
  double min_duration = 0.4;   // seconds a run must last to count as still
  // Metres: a still run's messages whose board centre lies farther than this from the centre of its
  // fullest view (most points) saw something else (a range sensor that missed the board and took the
  // person's torso) and are left out. 0: none left out (CalibrationSession, given 0, takes half its
  // rig's board's smaller side).
  double max_centre_spread = 0.0;
};

// One TargetObservation per sensor and still period (the points of its longest still run pooled),
// target_pose numbered by time. Observations in motion are dropped, and so are a run's messages more
// than half the sensor's period outside the span the other sensors' runs agree on, and those whose
// centre is farther than max_centre_spread from the run's fullest view. Throws InputError naming the
// sensor for an observation with a sensor index out of range.
std::vector<TargetObservation> associateStillTarget(const std::vector<SensorSpec>& sensors,
                                                    std::vector<TimedObservation> observations,
                                                    const StillnessOptions& options = {});

// The same association, told per input observation (in input order): the target_pose whose observation
// it went into, -1 for none. What a session decides what to keep by, without pooling any points.
std::vector<int> stillPoseOfEachObservation(const std::vector<SensorSpec>& sensors, std::vector<TimedObservation> observations,
                                            const StillnessOptions& options = {});

// One sensor's still run that lasted (StillnessOptions::min_duration): the stamps of its first and last message.
struct StillSpan {
  int sensor = 0;
  double begin = 0.0, end = 0.0;
};
// Every sensor's still runs, by sensor then time, each message's stamp as given (clock_offsets.h reads
// them before any stamp is corrected). Throws InputError for a sensor index out of range.
std::vector<StillSpan> stillSpans(const std::vector<SensorSpec>& sensors, std::vector<TimedObservation> observations,
                                  const StillnessOptions& options = {});

// Why a sensor that saw the target has no associated observation, for the first such sensor: its
// observations' spacing, the gap and duration a still run needs, the longest run it had, or that its
// runs overlap no other sensor's still period. Empty when every sensor with observations is associated.
std::string missingStillnessExplanation(const std::vector<SensorSpec>& sensors,
                                        const std::vector<TimedObservation>& observations,
                                        const std::vector<TargetObservation>& associated,
                                        const StillnessOptions& options = {});

}  // namespace vocal
