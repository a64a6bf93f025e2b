#pragma once
// Hand-eye calibration (calibration/solver/): a camera and the board where a robot arm moves one of them.
// In:  still poses of the arm, each with the tool's pose in the robot's base frame as the arm reports it
//      (tf) and each sensor's views of the board at that pose (a camera's PnP poses with their
//      covariance, a range sensor's board points).
// Out: the camera's pose on the tool and the board's in the base frame (eye-in-hand), or the camera's
//      in the base frame and the board's on the tool (eye-to-hand), and every other sensor's in its
//      parent (the tool, the base frame, or with the arm's joints a link before the tool: a forearm
//      camera), with standard deviations; how far
//      each arm pose had to move to fit (a poor pose is named, not followed); OpenCV's closed forms on
//      the same poses, side by side.
//
// One Ceres graph: each sensor's pose in its parent and the board's in its parent, and the tool's pose at
// every still pose as an unknown measured by the arm with its repeatability under a Cauchy loss (one arm
// pose millimetres off then moves itself instead of the result); each camera view a 6-DoF residual
// whitened by its PnP covariance, each range view its points on the board's plane (a 2D laser's as
// range errors along its beams, and its scan ends on the board's outline). A sensor whose pose the rig
// gives is held there. Started from OpenCV's calibrateHandEye (Park and Martin) for the main camera (or
// its given pose), after the board's 180-degree symmetry is resolved (a chessboard's corners may be
// found in either order).

#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "vocal/calibration/solver/hand_eye_closed_form.h"
#include "vocal/calibration/calibration_types.h"
#include "vocal/calibration/joint_chain.h"
#include "vocal/calibration/solver/intrinsics_refinement.h"
#include "vocal/calibration/solver/misdetected_view.h"

namespace vocal {

enum class HandEyeSetup {
  kEyeInHand,  // the camera on the tool, the board fixed in the base frame
  kEyeToHand,  // the camera fixed in the base frame, the board on the tool
};
std::string handEyeSetupName(HandEyeSetup setup);  // "eye-in-hand", "eye-to-hand"

// One sensor of an arm's rig: a camera or a range sensor (RGB-D, 3D lidar), on the tool or fixed in the
// base frame.
struct HandEyeSensor {
  HandEyeSensor(SensorType type = SensorType::kCamera, bool on_tool = true, std::optional<Eigen::Isometry3d> given_pose = std::nullopt,
                std::string name = "")
      : type(type), on_tool(on_tool), given_pose(std::move(given_pose)), name(std::move(name)) {}
  SensorType type = SensorType::kCamera;
  bool on_tool = true;
  // The pose the rig gives it in its parent, held there: the frame the user gave stays put. A fixed
  // sensor's (the reference) ties the base frame down, so with an arm from its joints the first joint's
  // offset is solved instead of taken up by the base side's poses; a tool sensor's known mount does the
  // same for the last joint's.
  std::optional<Eigen::Isometry3d> given_pose;
  std::string name;  // for messages; empty: "sensor N"
  // On a link that moves with joints other than the tool (a camera on the arm's forearm, or on a head's
  // pan-tilt joints beside the arm; needs HandEyeOptions::arm_joints): the joints from the base to that
  // link (jointChain; indices into ArmJoints::joints, each one of ArmJoints::readJoints()). Empty: on the
  // tool or fixed (`on_tool`). Its pose is then in that link, which moves with those joints only.
  std::vector<int> link_chain;
  bool onLink() const { return !link_chain.empty(); }
};

// One sensor's view of the board at one still pose of the arm.
struct HandEyeView {
  int sensor = 0;
  PlaneMeasurement pattern;             // a camera's: the pattern's pose and covariance
  std::vector<Eigen::Vector3d> points;  // a range sensor's board points, in its frame
  std::vector<Eigen::Vector3d> outline;  // ... its points on the board's edges (a 2D laser's scan ends)
};

// One still pose of the arm.
struct HandEyeStation {
  Eigen::Isometry3d base_from_tool = Eigen::Isometry3d::Identity();  // as the arm reports it
  // With HandEyeOptions::arm_joints: the reading there of each joint of ArmJoints::readJoints()
  // (base_from_tool is then the tool's chain at them plus the initial offsets).
  std::vector<double> joint_positions;
  // ... and where they put the links sensors sit on (by HandEyeSensor::link_chain): filled in by the solver.
  std::map<std::vector<int>, Eigen::Isometry3d> base_from_link;
  std::vector<HandEyeView> views;  // every sensor's views of the board while the arm stood there
  double first_stamp = 0.0, last_stamp = 0.0;  // seconds, to find it again in the recording
};

struct HandEyeOptions {
  // The arm's repeatability: how far a reported tool pose may lie from where the tool is (a typical
  // industrial or collaborative arm: 0.1 mm, and about as many milliradians as that over its reach).
  double tool_translation_sigma = 1e-4;  // metres
  double tool_rotation_sigma = 1e-4;     // radians
  // Cauchy scale on a tool pose's departure, in those sigmas: beyond it an arm pose counts as poor.
  double loss_sigmas = 5.0;
  // The motion a hand-eye calibration needs (Tsai and Lenz): rotations between poses about at least
  // two axes at least `min_axis_angle` apart, each turn by at least `min_rotation`.
  double min_rotation = 0.17;    // radians (10 degrees)
  double min_axis_angle = 0.35;  // radians (20 degrees)
  int max_iterations = 100;
  // The board's plate (pattern centred on it, x along the width), metres; zero: not known. A 2D laser's
  // line on the board's plane leaves it free to slide along the line: its scan ends, held on the plate's
  // outline where the laser's beam reaches it (its radius an unknown per laser, BeamRadiusPrior), within
  // their beams' step and at least a millimetre (scan_ends.h), under a Cauchy loss of `edge_loss_sigmas` (a
  // finger over the edge ends a line early), fix it.
  double board_width = 0.0, board_height = 0.0;
  double edge_loss_sigmas = 2.0;
  // The tool's pose from the arm's joints: each still pose's tool is the chain's at its readings plus the
  // joints' zero offsets (unknowns of the graph; the first and last joints' are held, as the board's and
  // the sensors' poses take them up) plus the readings' own errors (a prior of reading_sigma, under the
  // Cauchy loss: a pose whose readings do not fit is poor), instead of the reported pose within the
  // repeatability above.
  std::optional<ArmJoints> arm_joints;
  // Each camera's focal lengths refined with the poses (intrinsics_refinement.h), its views moved with them.
  IntrinsicsRefinementOptions intrinsics;
};

// A sensor that moved part-way through an arm's session (bumped, a loose mount): its placement from the
// stations before `station` and from those after it, each part solved on its own.
struct HandEyePlacementChange {
  int station = -1;  // the first station (index) of the second placement; -1: none found
  double translation = 0.0, rotation = 0.0;  // between the two placements (m, rad)
  double sigmas = 0.0;  // that difference in the two placements' combined sigmas (the larger of the two)
};

struct HandEyeResult {
  HandEyeSetup setup = HandEyeSetup::kEyeInHand;
  // Every sensor in its parent (tool <- sensor on the tool, base <- sensor fixed); standard deviations,
  // translation (m) along and rotation (rad) about the axes of the frame each is expressed in; and each
  // re-solved without each station in turn (those that leave a motion that can fix it): the jackknife
  // standard deviation per axis, zero with fewer than 2 re-solves.
  std::vector<Eigen::Isometry3d> sensors;
  std::vector<Eigen::Matrix<double, 6, 1>> sensor_sigmas, sensor_spreads;
  int spread_solves = 0;
  double cost = 0.0;  // the final solve's (Ceres's: half the sum of squared residuals, robust losses applied)
  // Per sensor whose spread is kInconsistentSpread times its sigma or more (its views disagree beyond their
  // noise): the split of its stations in time that, the sensor placed apart before and after it, fits
  // best, kept when the two placements differ by kMovedSigmas or more; station -1 otherwise.
  std::vector<HandEyePlacementChange> placement_changes;
  static constexpr double kInconsistentSpread = 5.0;
  // A 6 mm / 6 mrad bump of a lidar beside an arm (24 poses, its halves' sigmas 1.0 mm / 1.5 mrad) came
  // out at 5.2 sigmas, an untouched 2D laser beside it at 3.0.
  static constexpr double kMovedSigmas = 5.0;
  int main_camera = 0;  // the camera the closed forms are for
  // Eye-in-hand: tool <- camera and base <- board. Eye-to-hand: base <- camera and tool <- board.
  const Eigen::Isometry3d& camera() const { return sensors[main_camera]; }
  const Eigen::Matrix<double, 6, 1>& cameraSigma() const { return sensor_sigmas[main_camera]; }
  Eigen::Isometry3d board = Eigen::Isometry3d::Identity();
  Eigen::Matrix<double, 6, 1> board_sigma = Eigen::Matrix<double, 6, 1>::Zero();
  // Per station: how far the solve moved the tool from where the arm reported it (m, rad), and whether
  // that is beyond HandEyeOptions::loss_sigmas (a poor arm pose, or a view of something else).
  std::vector<double> tool_shift, tool_turn;
  std::vector<int> poor_stations;
  // Per station: the board as the cameras saw it against the board as the solution puts it, at the
  // board's centre (m) and in angle (rad), the mean over its camera views; and the RMS over every one.
  std::vector<double> view_distance, view_angle;
  double rms_distance = 0.0, rms_angle = 0.0;
  // What the still poses' camera views disagreed by beyond their PnP covariance and the arm's
  // repeatability, per axis (rad, m), added to each view's covariance times its pose's view count before
  // the final solve (zero when the model explained them).
  double unmodelled_rotation = 0.0, unmodelled_translation = 0.0;
  int flipped_views = 0;  // views whose corners were found in the other order (board turned 180 degrees)
  // Camera views left out: their board over kMisdetectedView* from where the started rig put it (a pattern
  // found shifted by a square, a view of something else).
  int misdetected_views = 0;
  std::vector<HandEyeClosedForm> closed_forms;
  // With HandEyeOptions::arm_joints: per joint of ArmJoints::readJoints(), the offset as solved (and what
  // fixed it) or held and why.
  std::vector<JointCalibration> joints;
  std::vector<bool> held;  // per sensor: at its given pose (HandEyeSensor::given_pose; sigma and spread zero)
  // Per sensor, with HandEyeOptions::intrinsics: a camera's (fx, fy, cx, cy) in pixels as its camera_info gave
  // them and as solved, and the solved ones' standard deviations; zero for the others.
  std::vector<Eigen::Vector4d> given_intrinsics, refined_intrinsics, intrinsics_sigma;
  // Per sensor: a 2D laser's beam radius as its scan ends put it (metres at its exit, radians of spread:
  // radius = [0] + [1] x range; OutlinePointsResidual::withBeam), and whether its ends were held (false for
  // every other sensor, and a laser without ends or the board's size).
  std::vector<Eigen::Vector2d> beam_radius;
  std::vector<bool> beam_solved;
};

// Why the arm's motion between the stations cannot fix the camera (the classic degeneracy: fewer than 3
// poses, every turn about one axis, or every turn too small), in words with the motion that would fix
// it; empty when it can.
std::string handEyeMotionProblem(const std::vector<HandEyeStation>& stations, const HandEyeOptions& options = {});

// One camera (sensor 0): on the tool over a fixed board (eye-in-hand) or fixed, the board on the tool.
// Throws InputError for fewer than 3 stations with a view, a view without a usable covariance, or a
// degenerate motion (handEyeMotionProblem's message).
HandEyeResult calibrateHandEye(const std::vector<HandEyeStation>& stations, HandEyeSetup setup, const HandEyeOptions& options = {});

// Several sensors in one graph: `board_on_tool` (eye-to-hand) or the board fixed in the base frame; the
// first camera on the other side from the board (on the tool when the board is fixed, fixed when it is
// on the tool) is the main camera, started from OpenCV's closed form; every other sensor is started
// from the board's poses that solution gives (a camera's views; a range sensor's planes, which must turn
// about two axes at least; a 2D laser's lines on them, from five poses) or from its given pose. Without
// such a camera, the first camera on a link (HandEyeSensor::link_chain: a head's camera watching the board
// in the gripper) is the main camera, its closed form over the tool's motion as that link sees it.
// Throws InputError as calibrateHandEye, for no camera, for a sensor on the board's side that is not a
// camera (it would see the board in one place only), and for a sensor on a link without the arm's joints,
// or whose chain is not one of them.
HandEyeResult calibrateArmRig(const std::vector<HandEyeSensor>& sensors, bool board_on_tool, const std::vector<HandEyeStation>& stations,
                              const HandEyeOptions& options = {});

}  // namespace vocal
