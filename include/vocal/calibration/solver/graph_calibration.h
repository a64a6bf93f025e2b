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

#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "vocal/calibration/calibration_types.h"
#include "vocal/calibration/joint_chain.h"
#include "vocal/calibration/plane.h"
#include "vocal/calibration/solver/consensus_filter.h"
#include "vocal/calibration/solver/intrinsics_refinement.h"
#include "vocal/calibration/solver/observability.h"
#include "vocal/core/errors.h"
#include "vocal/core/se3.h"

namespace vocal {

// The board's outline as constraints as well as its plane (the plane-only graph is the default).
struct BoardEdgeOptions {
  bool enabled = false;
  // The board along the camera pattern's x and y axes, metres (CalibrationSession sets them from the rig).
  double width = 0.0, height = 0.0;
  // Metres: a range sensor's edge point (its step along the line, the beam's width); a 2D laser's scan ends
  // are held instead on the outline reached by its beam's footprint (its radius an unknown, as in the arm's
  // graph: beam_radius_prior.h), each within its beams' step and at least a millimetre (scan_ends.h).
  double range_sigma = 0.01;
  double camera_sigma = 0.002; // metres: a camera view's board outline (PnP, the print's place on the board)
  double loss_sigmas = 2.0;    // Cauchy scale: a hand over an edge ends a line early
  // A camera's view as its whole PnP pose of the pattern on the board, the print's place on the board an
  // unknown (camera_pose_on_board_residual.h), instead of its plane and outline (not with its intrinsics refined).
  bool camera_pose = false;
};

// When a sensor's result is trusted (sensor_trust.h, calibrateRigWithTrust; calibrateRig itself only measures).
struct SensorTrustOptions {
  bool isolate = true;  // take the sensors that disagree out of the graph (false: only name them)
  // A sensor disagrees when the median over its poses of its board view's distance from (m) or angle to
  // (rad) the board the others solved is over these. Sensors 2 cm / 0.02 rad off put their views of a
  // board 1.5-3 m away 2-6 cm and 0.02 rad from the others'; noise and a real lidar's ring biases a few mm
  // and up to 10 mrad (the real office's VLP-16: 1 mm / 9 mrad).
  double max_distance = 0.015;
  double max_angle = 0.02;
  // ... or its views' distance grows with range by more than this share (and three standard errors): 1 %
  // at 1.6 m is as far off as 1.6 cm.
  double max_scale = 0.01;
};

// What an arm's whole-pose camera views disagree by beyond their PnP covariance and the arm's
// repeatability, per axis (unmodelled_view_scatter.h).
struct ViewScatter {
  double rotation = 0.0;     // radians
  double translation = 0.0;  // metres
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
  // Sensors kept out of the graph (sensor_trust.h isolates those that disagree with the rest): the rig is
  // solved without them, then each is fitted alone to the boards the others solved, so it moves none of
  // them. Never the reference sensor.
  std::vector<int> isolated_sensors;
  SensorTrustOptions trust;
  JointedMounts mounts;
  IntrinsicsRefinementOptions intrinsics;
  // An arm's session with whole camera poses: the views' scatter as a solve of all of them measured it
  // (CalibrationResult::view_scatter), taken as it is by the re-solves of trust and the jackknife rather
  // than measured again (a second solve each). Unset: measured.
  std::optional<ViewScatter> view_scatter;

  // No sensor's pose given and the board on the arm (its tool, its chain) or lying still in its base: the
  // base the arm's poses are in is the rig frame (reference_sensor -1).
  bool baseIsRigFrame() const { return reference_sensor < 0 && mounts.boardMoves(); }
};

// Still poses a plane-seeing sensor must share with the others to be placed (three planes fix a pose).
constexpr int kLeastSharedPoses = 3;

// calibrateRig's InputError where one sensor's views cannot place it (its boards' planes too close to
// parallel, a 2D laser's lines too few or alike): calibrateRigWithTrust leaves that sensor out and
// calibrates the rest.
class UnplaceableSensorError : public InputError {
 public:
  UnplaceableSensorError(int sensor, const std::string& message) : InputError(message), sensor(sensor) {}
  int sensor;
};

struct SensorCalibration {
  // In the rig frame; a sensor behind joints (JointedMounts): its mount in its chain's last link.
  Eigen::Isometry3d reference_from_sensor = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d pairwise_estimate = Eigen::Isometry3d::Identity();      // chained closed form
  // From the solver's covariance: translation (m) along and rotation (rad) about the rig frame's axes.
  Vector6d standard_deviation = Vector6d::Zero();
  double rms = 0.0;                                // point-to-plane, metres
  int observations = 0;
  int rejected_observations = 0;  // by the consensus filter
  // How far the sensor's board views lie from where the other sensors' views put the board (the solved
  // board; for an isolated sensor, solved without it): medians over the poses it shares with another
  // plane-seeing sensor, of the distance at the centre of its view (m) and the angle between its board
  // normal (a 2D laser: its line) and the board's (rad). Zero with no shared pose (`compared_poses` 0).
  double disagreement_distance = 0.0;
  double disagreement_angle = 0.0;
  int compared_poses = 0;
  // Its views' distance from the others' board as a share of their range (a line through the views, the
  // slope): a scale error - wrong focal length or square size - that the sensor's translation along its
  // view cannot take up once the board stands at several distances; and the slope's standard error.
  double disagreement_scale = 0.0, disagreement_scale_sigma = 0.0;
  // A camera with its intrinsics refined (CalibrationOptions::intrinsics): (fx, fy, cx, cy) in pixels as its
  // camera_info gave them and as solved, and the solved ones' standard deviations; all zero otherwise.
  Eigen::Vector4d given_intrinsics = Eigen::Vector4d::Zero(), refined_intrinsics = Eigen::Vector4d::Zero();
  Eigen::Vector4d intrinsics_sigma = Eigen::Vector4d::Zero();
  bool intrinsicsRefined() const { return given_intrinsics[0] > 0.0; }
  // The refinement as the graph holds it: the relative change (dfx / fx, dfy / fy, dcx / fx, dcy / fy)
  // of PlaneMeasurement::pose_per_intrinsics; zero when not refined.
  Eigen::Vector4d intrinsicsCorrection() const;
  // A 2D laser with board edges: its beam's radius as its scan ends put it (metres at its exit, radians
  // times the range; OutlinePointsResidual::withBeam), solved or not.
  Eigen::Vector2d beam_radius = Eigen::Vector2d::Zero();
  bool beam_solved = false;
  bool isolated = false;  // kept out of the graph (CalibrationOptions::isolated_sensors)
  std::string distrust;   // why this sensor's result is not trusted, for the user (empty: trusted); sensor_trust.h
};

// How well one observation fits the solution, so bad ones can be found.
struct ObservationResidual {
  int sensor = 0;
  int target_pose = 0;
  double rms = 0.0;       // metres, its points' distance to the solved target plane; NaN when every
                          // observation of its pose was rejected (no plane was solved)
  bool rejected = false;  // by the consensus filter (rms then measured against the solution anyway)
  // Its view against the board the other sensors solved (SensorCalibration::disagreement_*): distance
  // at its view's centre along the board's normal (m; positive: its view lies beyond the others' board,
  // seen from the sensor) and angle (rad); NaN when no other sensor fixed that pose's board.
  double plane_distance = 0.0, plane_angle = 0.0;
  double range = 0.0;  // metres from the sensor to its view's centre
};


struct CalibrationResult {
  std::vector<SensorCalibration> sensors;
  JointedMounts mounts;                 // the options', each joint's offset as solved
  std::vector<JointCalibration> joints;  // per joint of mounts.joints
  std::vector<ObservationResidual> observations;  // in the order of the input
  double rms = 0.0;  // over every point
  std::vector<ObservabilityWarning> warnings;  // weakly constrained DoF, checked before solving
  // The target as solved, rig frame, per target pose: its plane, and with board edges its full pose.
  std::map<int, Plane> board_planes;
  std::map<int, Eigen::Isometry3d> boards;
  // The board behind joints (JointedMounts::board_chain): its mount in the chain's last link, and its standard
  // deviations (translation along and rotation about the link's axes; zero where the mount is known).
  std::optional<Eigen::Isometry3d> board_mount;
  Vector6d board_mount_sigma = Vector6d::Zero();
  // With BoardEdgeOptions::camera_pose: the print's place on the board (dx, dy metres along its axes, a turn
  // about its normal in radians; camera_pose_on_board_residual.h) as solved; zero otherwise.
  Eigen::Vector3d print_on_board = Eigen::Vector3d::Zero();
  // ... and the camera views held by their plane only: their whole pose over kMisdetectedView*
  // (misdetected_view.h) from where the started rig put it.
  int misdetected_views = 0;
  // An arm's session with whole camera poses: what the views disagreed by beyond their PnP covariance and
  // the arm's repeatability (unmodelled_view_scatter.h), each view weighted by it in a second solve; zero
  // where the model explained them. Unset for other rigs.
  std::optional<ViewScatter> view_scatter;
  // An arm's session, as solved: where each sensor the arm carries was (rig frame) per (sensor, still pose),
  // and each still pose's reading corrections per (still pose, joint) (arm_pose_fit.h reads them).
  std::map<std::pair<int, int>, Eigen::Isometry3d> placed_at_poses;
  std::map<std::pair<int, int>, double> reading_corrections;
  // ... and the still poses the arm had to move beyond its repeatability to fit the others (arm_pose_fit.h).
  std::vector<int> poor_arm_poses;
  bool trusted = true;   // false: the solver failed or a sensor in the graph ran away from the closed form (see failure)
  std::string failure;   // names the sensor and how far it moved

  // Where the sensor of `o` was in the rig frame when it made it: its pose, or behind joints its chain
  // at o's joint positions (offsets as solved) times its mount.
  Eigen::Isometry3d rigFromSensorAt(const TargetObservation& o) const;
  // `o` as the solution sees it: a camera's views (and the corners placed by them) moved to where its
  // refined intrinsics put them (SensorCalibration::refined_intrinsics), written to `moved`; any other
  // view is `o` itself (no copy: range views are large).
  const TargetObservation& viewAsSolved(const TargetObservation& o, TargetObservation* moved) const;
};

// One view against a board (rig frame) with the sensor at `rig_from_sensor`: the distance at the view's
// centre along the board's normal (m; positive: the view lies beyond the board, seen from the sensor),
// the angle between the view's normal (a 2D laser: its line) and the board's (rad; NaN when the view
// has too few points), and the range to the view's centre (m).
struct ViewDisagreement {
  double distance = 0.0;
  double angle = std::numeric_limits<double>::quiet_NaN();
  double range = 0.0;
};
// What a view's disagreement needs of it, in the sensor frame, computed once per view (a range view's
// normal is a plane fit of its points): its centre, and its normal or, for a 2D laser, its line
// (zero when it has too few points).
struct ViewInSensor {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();
  bool direction_is_line = false;
};
ViewInSensor viewInSensor(const TargetObservation& view, SensorType type);
ViewDisagreement viewDisagreement(const ViewInSensor& view, const Eigen::Isometry3d& rig_from_sensor, const Plane& board);

// One sensor's pose fitted alone to the boards `solved` holds (constant), from its observations `its` (all
// of one sensor) at poses with a solved board, starting from its pose in `solved`: how a part of a
// session places it (sensor_trust.h: before and after a bump). None when no observation has a board.
std::optional<Eigen::Isometry3d> fitSensorToSolvedBoards(const std::vector<SensorSpec>& sensors,
                                                         const std::vector<const TargetObservation*>& its, const CalibrationResult& solved,
                                                         const CalibrationOptions& options);

// Throws InputError naming the sensor when one never sees the target, shares no target pose with the
// rest (the sensor graph is not connected), or its planes cannot fix its pose (with board edges: its
// planes and the board's centres), or board edges are enabled without the board's size; for an
// isolated sensor that is the reference or not a sensor of the rig; and for joints (options.mounts): a
// reference or 2D laser behind joints, a jointed observation without one position per joint of its chain.
CalibrationResult calibrateRig(const std::vector<SensorSpec>& sensors, const std::vector<TargetObservation>& observations,
                               const CalibrationOptions& options = {});

}  // namespace vocal
