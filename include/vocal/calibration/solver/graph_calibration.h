#pragma once
// ---- MSG-Cal stage 3, solver (calibration/solver/): still poses -> the rig's extrinsics ---------------
// In:  TargetObservations of every sensor (association/), the rig's reference sensor and options.
//      consensus_filter.h drops observations whose pairwise geometry disagrees with the majority;
//      pairwise_initialization.h gives closed-form sensor-to-sensor estimates (planes; 2D laser lines);
//      this file chains them and solves one Ceres graph; observability.h says which directions the
//      session's board poses leave unconstrained; pose_jackknife.h re-solves without each pose for the
//      spread across poses and held-out predictions.
// Out: CalibrationResult (each sensor's pose in the rig frame, covariance, trusted or not and why) and
//      PoseJackknife (each sensor's spread): what output/ writes.
// ------------------------------------------------------------------------------------------------------
//
// The global calibration: closed-form pairwise estimates chained along the best-connected paths of the
// sensor graph initialise one Ceres problem over every sensor pose and every target plane, with the
// point-to-plane residuals of each range observation and the plane measurement of each camera view
// (whitened by its PnP covariance) under a robust loss; the reference sensor stays fixed. With board
// edges, each target pose is the board's full pose and the points where range sensors saw its edges,
// and each camera view's board outline, are held on the board's outline (point-to-line, as Zhou et al.
// 2018 and velo2cam): the board's position within its plane is then fixed even when the normals span
// too little to fix the sensors' translation.

#include <vector>

#include "vocal/calibration/calibration_types.h"
#include "vocal/calibration/solver/consensus_filter.h"
#include "vocal/calibration/solver/observability.h"
#include "vocal/core/se3.h"

namespace vocal {

// The board's outline as constraints as well as its plane (the plane-only graph is the default).
struct BoardEdgeOptions {
  bool enabled = false;
  // The board along the camera pattern's x and y axes, metres (CalibrationSession sets them from the rig).
  double width = 0.0, height = 0.0;
  double range_sigma = 0.01;   // metres: a range sensor's edge point (its step along the line, the beam's width)
  double camera_sigma = 0.002; // metres: a camera view's board outline (PnP, the print's place on the board)
  double loss_sigmas = 2.0;    // Cauchy scale: a hand over an edge ends a line early
};

struct CalibrationOptions {
  int reference_sensor = 0;
  Eigen::Isometry3d reference_pose = Eigen::Isometry3d::Identity();  // the reference sensor in the rig frame
  // Huber threshold on an observation's residuals, in standard deviations of its points: an observation
  // whose points sit farther from the plane than this on average is down-weighted.
  double huber_sigmas = 3.0;
  int max_iterations = 100;
  // The global solution is not trusted when it moves a sensor farther than this from its closed-form
  // estimate: with few poses and outliers the graph can run away while still "converging".
  double max_departure_translation = 0.1;  // metres
  double max_departure_rotation = 0.1;     // radians
  // Reject observations inconsistent with the consensus of their sensor pairs before initialising.
  bool consensus_filter = true;
  ConsensusOptions consensus;
  BoardEdgeOptions board_edges;
};

struct SensorCalibration {
  Eigen::Isometry3d reference_from_sensor = Eigen::Isometry3d::Identity();  // in the rig frame
  Eigen::Isometry3d pairwise_estimate = Eigen::Isometry3d::Identity();      // chained closed form
  // From the solver's covariance: translation (m) along and rotation (rad) about the rig frame's axes.
  Vector6d standard_deviation = Vector6d::Zero();
  double rms = 0.0;                                // point-to-plane, metres
  int observations = 0;
  int rejected_observations = 0;  // by the consensus filter
};

// How well one observation fits the solution, so bad ones can be found.
struct ObservationResidual {
  int sensor = 0;
  int target_pose = 0;
  double rms = 0.0;       // metres, its points' distance to the solved target plane; NaN when every
                          // observation of its pose was rejected (no plane was solved)
  bool rejected = false;  // by the consensus filter (rms then measured against the solution anyway)
};

struct CalibrationResult {
  std::vector<SensorCalibration> sensors;
  std::vector<ObservationResidual> observations;  // in the order of the input
  double rms = 0.0;  // over every point
  std::vector<ObservabilityWarning> warnings;  // weakly constrained DoF, checked before solving
  bool trusted = true;   // false: the solver failed or ran away from the closed form (see failure)
  std::string failure;   // names the sensor and how far it moved
};

// Throws InputError naming the sensor when one never sees the target, shares no target pose with the
// rest (the sensor graph is not connected), or its planes cannot fix its pose (with board edges: its
// planes and the board's centres), or board edges are enabled without the board's size.
CalibrationResult calibrateRig(const std::vector<SensorSpec>& sensors, const std::vector<TargetObservation>& observations,
                               const CalibrationOptions& options = {});

}  // namespace vocal
