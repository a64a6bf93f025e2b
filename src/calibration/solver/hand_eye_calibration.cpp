#include "vocal/calibration/solver/hand_eye_calibration.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <utility>

#include <Eigen/Cholesky>
#include <Eigen/SVD>
#include <ceres/ceres.h>
#include <ceres/manifold.h>

#include "vocal/calibration/plane.h"
#include "vocal/calibration/solver/beam_radius_prior.h"
#include "vocal/calibration/solver/beam_range_view_residual.h"
#include "vocal/calibration/solver/camera_view_residual.h"
#include "vocal/calibration/solver/free_joint_origins.h"
#include "vocal/calibration/solver/hand_eye_closed_form.h"
#include "vocal/calibration/solver/link_from_joints_cost.h"
#include "vocal/calibration/solver/outline_view_residual.h"
#include "vocal/calibration/solver/pairwise_initialization.h"
#include "vocal/calibration/solver/range_view_residual.h"
#include "vocal/calibration/solver/reading_corrections_residual.h"
#include "vocal/calibration/solver/scan_ends.h"
#include "vocal/calibration/solver/tool_pose_residual.h"
#include "vocal/calibration/solver/unmodelled_view_scatter.h"
#include "vocal/core/errors.h"
#include "vocal/core/se3.h"

namespace vocal {

std::string handEyeSetupName(HandEyeSetup setup) { return setup == HandEyeSetup::kEyeInHand ? "eye-in-hand" : "eye-to-hand"; }

namespace {
constexpr double kDegrees = 180.0 / M_PI;

// The rig an arm moves, as the solver sees it.
struct ArmRig {
  std::vector<HandEyeSensor> sensors;
  bool board_on_tool = false;
  int main_camera = -1;
  // A sensor on the tool with the board on the tool too sees it through no frame that moves.
  FrameMounting mounting(int sensor) const {
    const bool same_frame = sensors[sensor].on_tool && board_on_tool && !sensors[sensor].onLink();
    return {sensors[sensor].on_tool && !same_frame, board_on_tool && !same_frame};
  }
  // Where the frame a sensor moves with was at a station: the tool, or the link it sits on.
  const Eigen::Isometry3d& movingFrameAt(int sensor, const HandEyeStation& station) const {
    return sensors[sensor].onLink() ? station.base_from_link.at(sensors[sensor].link_chain) : station.base_from_tool;
  }
  // The board in a sensor's parent frame at a station, the board at `board` in its own parent.
  Eigen::Isometry3d boardInSensorParent(int sensor, const Eigen::Isometry3d& board, const HandEyeStation& station) const {
    return mounting(sensor).boardInSensorParent(board, movingFrameAt(sensor, station), station.base_from_tool);
  }
  std::string name(int sensor) const {
    return sensors[sensor].name.empty() ? "sensor " + std::to_string(sensor) : "'" + sensors[sensor].name + "'";
  }
  // The first sensor on the tool (or fixed) held at a given pose that sees the board at some station, or
  // -1: what ties that side's frame down.
  int heldOn(bool tool_side, const std::vector<HandEyeStation>& stations) const {
    for (std::size_t s = 0; s < sensors.size(); ++s) {
      if (sensors[s].on_tool != tool_side || !sensors[s].given_pose || sensors[s].onLink()) continue;
      if (seen(static_cast<int>(s), stations)) return static_cast<int>(s);
    }
    return -1;
  }
  static bool seen(int sensor, const std::vector<HandEyeStation>& stations) {
    for (const HandEyeStation& station : stations)
      for (const HandEyeView& view : station.views)
        if (view.sensor == sensor) return true;
    return false;
  }
  // The stations as the closed form of a main camera on a link (a head's) sees them: its link as the base
  // frame under the board on the tool, or as the tool over the fixed board. (A camera on the tool or fixed
  // sees them as they are.)
  std::vector<HandEyeStation> mainCameraMotion(const std::vector<HandEyeStation>& stations) const {
    std::vector<HandEyeStation> seen_from = stations;
    for (HandEyeStation& s : seen_from) {
      const Eigen::Isometry3d& link = movingFrameAt(main_camera, s);
      s.base_from_tool = board_on_tool ? link.inverse() * s.base_from_tool : link;
    }
    return seen_from;
  }
};

struct PoseState {
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  explicit PoseState(const Eigen::Isometry3d& pose) : rotation(pose.linear()), translation(pose.translation()) {}
  Eigen::Isometry3d pose() const {
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.linear() = rotation.normalized().toRotationMatrix();
    p.translation() = translation;
    return p;
  }
};

// The main camera's first view at a station, or null.
const PlaneMeasurement* firstView(const HandEyeStation& station, int camera) {
  for (const HandEyeView& v : station.views)
    if (v.sensor == camera) return &v.pattern;
  return nullptr;
}

// The main camera's views as its first one numbers the board's corners: a rotation between two stations
// keeps its angle from the tool's motion to the camera's (A X = X B), and a board found in the other order
// adds half a turn to the camera's.
int numberCornersAlike(std::vector<HandEyeStation>* stations, int camera) {
  const HandEyeStation* first = nullptr;
  for (const HandEyeStation& s : *stations)
    if (firstView(s, camera)) first = first ? first : &s;
  if (!first) return 0;
  const Eigen::Matrix3d first_view = firstView(*first, camera)->sensor_from_pattern.linear();
  const Eigen::Matrix3d first_tool = first->base_from_tool.linear();
  int flipped = 0;
  for (HandEyeStation& station : *stations) {
    const double tool_angle = Eigen::AngleAxisd(first_tool.transpose() * station.base_from_tool.linear()).angle();
    for (HandEyeView& view : station.views) {
      if (view.sensor != camera) continue;
      const PlaneMeasurement turned = turnedHalfway(view.pattern);
      const double as_found = Eigen::AngleAxisd(first_view * view.pattern.sensor_from_pattern.linear().transpose()).angle();
      const double as_turned = Eigen::AngleAxisd(first_view * turned.sensor_from_pattern.linear().transpose()).angle();
      if (std::abs(as_turned - tool_angle) < std::abs(as_found - tool_angle)) {
        view.pattern = turned;
        ++flipped;
      }
    }
  }
  return flipped;
}

// Another camera's views numbered as the main camera numbers the board: its pose from its first view as
// found or turned halfway, whichever predicts its other views better (each as found or turned), then
// each view turned where the prediction says it was found the other way.
int turnLikePredicted(std::vector<HandEyeStation>* stations, const ArmRig& rig, int camera, const Eigen::Isometry3d& board) {
  const HandEyeStation* first = nullptr;
  for (const HandEyeStation& s : *stations)
    if (!first && firstView(s, camera)) first = &s;
  if (!first) return 0;
  const PlaneMeasurement& first_view = *firstView(*first, camera);
  const Eigen::Isometry3d seen = rig.boardInSensorParent(camera, board, *first);
  const auto disagreement = [&](const Eigen::Isometry3d& pose, const PlaneMeasurement& view, const HandEyeStation& station, bool* turn) {
    const Eigen::Isometry3d predicted = pose.inverse() * rig.boardInSensorParent(camera, board, station);
    const double as_found = rotationAngle(view.sensor_from_pattern.inverse() * predicted);
    const double as_turned = rotationAngle(turnedHalfway(view).sensor_from_pattern.inverse() * predicted);
    if (turn) *turn = as_turned < as_found;
    return std::min(as_found, as_turned);
  };
  const Eigen::Isometry3d candidates[] = {seen * first_view.sensor_from_pattern.inverse(),
                                          seen * turnedHalfway(first_view).sensor_from_pattern.inverse()};
  double total[2] = {0.0, 0.0};
  for (int c = 0; c < 2; ++c)
    for (const HandEyeStation& s : *stations)
      for (const HandEyeView& v : s.views)
        if (v.sensor == camera) total[c] += disagreement(candidates[c], v.pattern, s, nullptr);
  const Eigen::Isometry3d& pose = candidates[total[1] < total[0] ? 1 : 0];
  int flipped = 0;
  for (HandEyeStation& station : *stations) {
    for (HandEyeView& view : station.views) {
      bool turn = false;
      if (view.sensor != camera) continue;
      disagreement(pose, view.pattern, station, &turn);
      if (turn) {
        view.pattern = turnedHalfway(view.pattern);
        ++flipped;
      }
    }
  }
  return flipped;
}

// OpenCV's closed forms for the main camera in its parent (cv::calibrateHandEye takes base <- tool for
// a camera on the tool and tool <- base for a fixed one), from each station's first view of it: all five
// methods, or Park's alone.
std::vector<HandEyeClosedForm> openCvHandEye(const std::vector<HandEyeStation>& stations, int camera, bool camera_on_tool, bool all_methods) {
  std::vector<Eigen::Isometry3d> tools, views;
  for (const HandEyeStation& s : stations) {
    const PlaneMeasurement* view = firstView(s, camera);
    if (!view) continue;
    tools.push_back(camera_on_tool ? s.base_from_tool : s.base_from_tool.inverse());
    views.push_back(view->sensor_from_pattern);
  }
  if (all_methods) return openCvHandEyeMethods(tools, views);
  return {{"Park", vocal::openCvHandEye(tools, views, kParkHandEye)}};
}

// A camera view's error against the camera's pose and the board in its parent frame where the arm
// reported the frames they move with (ArmRig::boardInSensorParent), as (w, dt) of the view's perturbation.
Eigen::Matrix<double, 6, 1> viewError(const Eigen::Isometry3d& board_in_parent, const PlaneMeasurement& view, const Eigen::Isometry3d& pose) {
  return viewPoseError(view, pose.inverse() * board_in_parent);
}

// Translation and rotation sigmas of a pose block pair from the covariance (Ceres's quaternion tangent
// is half the rotation vector).
Eigen::Matrix<double, 6, 1> sigmasOf(ceres::Covariance& covariance, PoseState& state) {
  Eigen::Matrix3d rotation_covariance, translation_covariance;
  covariance.GetCovarianceMatrixInTangentSpace({state.rotation.coeffs().data()}, rotation_covariance.data());
  covariance.GetCovarianceBlock(state.translation.data(), state.translation.data(), translation_covariance.data());
  Eigen::Matrix<double, 6, 1> sigma;
  sigma.head<3>() = translation_covariance.diagonal().cwiseSqrt();
  sigma.tail<3>() = 2.0 * rotation_covariance.diagonal().cwiseSqrt();
  return sigma;
}

// What the cameras' views disagree by beyond their PnP covariance and the arm's repeatability: a real
// arm's kinematic model, the camera's intrinsics and the print are off by millimetres, far beyond either,
// and alike for every image of one still pose. So per still pose and camera, the mean of its views'
// errors against its modelled covariance (the views' PnP covariance over their count, plus the arm's):
// ViewScatterSamples (unmodelled_view_scatter.h, the still-pose graph's too).
std::pair<double, double> unmodelledScatter(const ArmRig& rig, const std::vector<HandEyeStation>& stations,
                                            const std::vector<Eigen::Isometry3d>& poses, const Eigen::Isometry3d& board,
                                            const HandEyeOptions& options) {
  ViewScatterSamples samples;
  for (const HandEyeStation& s : stations) {
    for (std::size_t camera = 0; camera < rig.sensors.size(); ++camera) {
      if (rig.sensors[camera].type != SensorType::kCamera) continue;
      const FrameMounting mounting = rig.mounting(static_cast<int>(camera));
      Eigen::Matrix<double, 6, 1> mean = Eigen::Matrix<double, 6, 1>::Zero();
      Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
      double lever = 0.0;
      int n = 0;
      for (const HandEyeView& view : s.views) {
        if (view.sensor != static_cast<int>(camera)) continue;
        mean += viewError(rig.boardInSensorParent(static_cast<int>(camera), board, s), view.pattern, poses[camera]);
        covariance += view.pattern.pose_covariance;
        // The tool's turn moves the board seen by its lever: from the tool to the board.
        lever = mounting.board_moves ? board.translation().norm()
                                       : poses[camera].translation().norm() + view.pattern.sensor_from_pattern.translation().norm();
        ++n;
      }
      if (n == 0) continue;
      mean /= n;
      covariance /= static_cast<double>(n) * n;  // of the mean of n independent views
      samples.add(mean, covariance, options.tool_rotation_sigma, options.tool_translation_sigma, lever);
    }
  }
  const ViewScatter scatter = samples.scatter();
  return {scatter.rotation, scatter.translation};
}

// The unknowns and the problem that holds them (for the covariance).
struct ArmGraph {
  std::vector<PoseState> sensors;
  PoseState board;
  std::vector<PoseState> tools;
  std::map<std::vector<int>, std::vector<PoseState>> links;  // per link sensors sit on (HandEyeSensor::link_chain): per station
  PoseState base{Eigen::Isometry3d::Identity()};  // the base frame, constant: the frame of what is fixed
  std::vector<double> offsets;                   // arm_joints: per joint of readJoints()
  std::vector<std::vector<double>> corrections;  // ... per station and joint of readJoints()
  std::vector<Vector6d> origins;                 // ... per joint of readJoints(): a free origin's correction (zero otherwise)
  std::vector<std::vector<int>> origin_held;     // ... its parts held at the model's (the session does not fix them)
  std::vector<Eigen::Vector4d> intrinsics;       // per sensor: a refined camera's correction (intrinsics_refinement.h)
  std::vector<Eigen::Vector2d> beam_radius;      // per sensor: a 2D laser's beam radius (BeamRadiusPrior), solved where in `problem`
  std::unique_ptr<ceres::Problem> problem;
  double cost = 0.0;  // Ceres's, at the solution
  explicit ArmGraph(const Eigen::Isometry3d& board_start) : board(board_start) {}
};

// Where joint `joint` (of ArmJoints::joints) is in readJoints(): its reading's, offset's and corrections' index.
std::size_t readIndex(const ArmJoints& arm, int joint) {
  const std::vector<int>& read = arm.readJoints();
  return static_cast<std::size_t>(std::find(read.begin(), read.end(), joint) - read.begin());
}

// The arm with its free origins (JointDescription::free_origin) moved by `origins` (per joint of
// readJoints(); none: as modelled).
ArmJoints withOrigins(const ArmJoints& arm, const std::vector<Vector6d>& origins) {
  ArmJoints moved = arm;
  for (std::size_t i = 0; i < origins.size(); ++i) {
    JointDescription& joint = moved.joints[arm.readJoints()[i]];
    if (joint.free_origin) joint.origin = jointOriginCorrected(joint, origins[i]);
  }
  return moved;
}

// base <- the end of `chain` (the tool's when empty) at a station's readings plus `offsets`, both per joint
// of readJoints().
Eigen::Isometry3d armLink(const ArmJoints& arm, const std::vector<double>& readings, const std::vector<double>& offsets,
                          const std::vector<int>& chain = {}) {
  const std::vector<int>& links = chain.empty() ? arm.chain : chain;
  const std::vector<int>& read = arm.readJoints();
  std::vector<double> all(arm.joints.size(), 0.0), positions;
  for (std::size_t i = 0; i < read.size(); ++i) all[read[i]] = offsets[i];
  for (const int j : links) positions.push_back(readings[readIndex(arm, j)]);
  return chainPose(arm.joints, links, positions, all);
}

// Each station's links that sensors sit on (HandEyeStation::base_from_link) at its readings plus `offsets`.
void placeLinks(const ArmRig& rig, const ArmJoints& arm, const std::vector<double>& offsets, std::vector<HandEyeStation>* stations) {
  for (const HandEyeSensor& sensor : rig.sensors) {
    if (!sensor.onLink()) continue;
    for (HandEyeStation& s : *stations) s.base_from_link[sensor.link_chain] = armLink(arm, s.joint_positions, offsets, sensor.link_chain);
  }
}

// Per joint the stations read (ArmJoints::readJoints): the range its readings covered, and whether its
// offset can be solved and what fixes it. A joint's offset turns what lies behind it (the tool's and the
// links' branches through it) against what does not; it is taken up unless, on the base side, a joint
// before it on one of its branches moved, or a branch it is not on moved (a head's views of the board an
// arm holds: its turn would move one branch and not the other), or a fixed sensor is held at the pose the
// rig gives; and unless, on the far side, a joint after it on one of its branches moved, or a sensor at the
// end of one is held at the mount the rig gives.
std::vector<JointCalibration> armJointsSolvable(const ArmRig& rig, const ArmJoints& arm, const std::vector<HandEyeStation>& stations) {
  const std::vector<int>& read = arm.readJoints();
  const std::size_t n = read.size();
  std::vector<JointCalibration> joints(n);
  std::vector<bool> moved(arm.joints.size(), false);
  for (std::size_t i = 0; i < n; ++i) {
    const JointDescription& joint = arm.joints[read[i]];
    double low = 1e300, high = -1e300;
    for (const HandEyeStation& s : stations)
      if (i < s.joint_positions.size()) low = std::min(low, s.joint_positions[i]), high = std::max(high, s.joint_positions[i]);
    joints[i].offset = joint.offset;
    joints[i].motion = high >= low ? high - low : 0.0;
    moved[read[i]] = joint.type != JointType::kFixed && joints[i].motion >= arm.tolerances.minMotion(joint);
  }
  // The branches: the tool's chain, then each link's a sensor that saw the board sits on; with the sensor
  // held at a mount the rig gives on it (or -1).
  struct Branch {
    std::vector<int> chain;
    int held = -1;
  };
  std::vector<Branch> branches = {{arm.chain, rig.heldOn(true, stations)}};
  for (std::size_t s = 0; s < rig.sensors.size(); ++s) {
    const HandEyeSensor& sensor = rig.sensors[s];
    if (!sensor.onLink() || !ArmRig::seen(static_cast<int>(s), stations)) continue;
    auto it = std::find_if(branches.begin(), branches.end(), [&](const Branch& b) { return b.chain == sensor.link_chain; });
    if (it == branches.end()) it = branches.insert(branches.end(), Branch{sensor.link_chain, -1});
    if (sensor.given_pose && it->held < 0) it->held = static_cast<int>(s);
  }
  const int base_held = rig.heldOn(false, stations);
  for (std::size_t i = 0; i < n; ++i) {
    const int j = read[i];
    bool before = false, after = false, on_tool = false, behind = false;
    int held_after = -1, other_moved = -1;  // a mount held on one of its branches; a joint that moved on a branch it is not on
    std::string link;  // the first link branch it is on, for the message
    for (const Branch& b : branches) {
      const auto at = std::find(b.chain.begin(), b.chain.end(), j);
      if (at == b.chain.end()) {
        for (const int other : b.chain)
          if (moved[other] && other_moved < 0) other_moved = other;
        continue;
      }
      behind = true;
      before = before || std::any_of(b.chain.begin(), at, [&](int k) { return moved[k]; });
      after = after || std::any_of(at + 1, b.chain.end(), [&](int k) { return moved[k]; });
      if (held_after < 0) held_after = b.held;
      if (&b == &branches.front()) on_tool = true;
      else if (link.empty()) link = arm.joints[b.chain.back()].child;
    }
    if (arm.joints[j].type == JointType::kFixed) {
      joints[i].held = "a fixed joint";
      joints[i].reported = false;
    } else if (!behind) {
      joints[i].held = "no sensor behind it saw the board";
    } else if (!before && other_moved < 0 && base_held < 0) {
      joints[i].held = "no joint before it moved, so the poses in the base frame (the board's, or the fixed sensors') take up its offset: "
                       "give a fixed sensor's pose in the rig (the reference) to solve it";
    } else if (!after && held_after < 0) {
      joints[i].held = on_tool ? "no joint after it moved, so the poses on the tool (the camera's, or the board's) take up its offset"
                               : "no joint after it moved, so the poses of the sensors on '" + link + "' take up its offset";
    } else {
      const std::string before_text = before ? "joints that moved before it"
                                      : other_moved >= 0 ? "'" + arm.joints[other_moved].name + "' that moved on another branch"
                                                         : "the pose the rig gives " + rig.name(base_held);
      const std::string after_text = after ? "joints that moved after it" : "the mount the rig gives " + rig.name(held_after);
      joints[i].fixed_by = before && after ? std::string("joints that moved before and after it") : before_text + " and " + after_text;
    }
  }
  return joints;
}

// BeamRangeViewResidual's cost: a residual per point, over the sensor's, the board's and their frames' poses.
ceres::CostFunction* beamRangeCost(const std::vector<Eigen::Vector3d>& points, double sigma, FrameMounting mounting) {
  auto* cost = new ceres::DynamicAutoDiffCostFunction<BeamRangeViewResidual, 4>(new BeamRangeViewResidual{points, sigma, mounting});
  for (int block = 0; block < 4; ++block) cost->AddParameterBlock(4), cost->AddParameterBlock(3);
  cost->SetNumResiduals(static_cast<int>(points.size()));
  return cost;
}

// Where an arm graph's joint unknowns start (per joint of readJoints()), and the free origins' parts held.
struct JointStarts {
  std::vector<double> offsets;
  std::vector<Vector6d> origins;
  std::vector<std::vector<int>> origin_held;
};

// Per sensor: the intrinsics (fx, fy, cx, cy) its first camera view was found with where the options refine
// them (zero for the others: not refined).
std::vector<Eigen::Vector4d> givenIntrinsics(const ArmRig& rig, const std::vector<HandEyeStation>& stations, const HandEyeOptions& options) {
  std::vector<Eigen::Vector4d> given(rig.sensors.size(), Eigen::Vector4d::Zero());
  for (const HandEyeStation& s : stations)
    for (const HandEyeView& view : s.views)
      if (options.intrinsics.enabled && rig.sensors[view.sensor].type == SensorType::kCamera && given[view.sensor].isZero())
        given[view.sensor] = view.pattern.intrinsics;
  return given;
}

// The stations' camera views as refined intrinsics `dk` (per sensor) move them (what the views are judged
// by once solved); as they are where none is refined.
std::vector<HandEyeStation> viewsAsSolved(std::vector<HandEyeStation> stations, const std::vector<Eigen::Vector4d>& dk) {
  for (HandEyeStation& s : stations)
    for (HandEyeView& view : s.views)
      if (view.sensor < static_cast<int>(dk.size()) && !dk[view.sensor].isZero()) view.pattern = movedByIntrinsics(view.pattern, dk[view.sensor]);
  return stations;
}

std::unique_ptr<ArmGraph> solveGraph(const ArmRig& rig, const std::vector<HandEyeStation>& stations, const HandEyeOptions& options,
                                     const std::vector<Eigen::Isometry3d>& sensor_starts, const Eigen::Isometry3d& board_start,
                                     const JointStarts* joint_starts = nullptr, const std::vector<Eigen::Vector4d>* intrinsics_starts = nullptr) {
  auto graph = std::make_unique<ArmGraph>(board_start);
  graph->problem = std::make_unique<ceres::Problem>();
  ceres::Problem& problem = *graph->problem;
  // Reserved first: the residual blocks hold pointers into each state.
  graph->sensors.reserve(sensor_starts.size());
  for (const Eigen::Isometry3d& start : sensor_starts) graph->sensors.emplace_back(start);
  const std::vector<Eigen::Vector4d> given = givenIntrinsics(rig, stations, options);
  graph->intrinsics = intrinsics_starts ? *intrinsics_starts : std::vector<Eigen::Vector4d>(rig.sensors.size(), Eigen::Vector4d::Zero());
  graph->beam_radius.assign(rig.sensors.size(), Eigen::Vector2d::Zero());
  graph->tools.reserve(stations.size());
  for (const HandEyeStation& s : stations) graph->tools.emplace_back(s.base_from_tool);
  for (const HandEyeSensor& sensor : rig.sensors) {
    if (!sensor.onLink() || graph->links.count(sensor.link_chain)) continue;
    std::vector<PoseState>& links = graph->links[sensor.link_chain];
    links.reserve(stations.size());
    for (const HandEyeStation& s : stations) links.emplace_back(s.base_from_link.at(sensor.link_chain));
  }
  for (std::size_t k = 0; k < stations.size(); ++k) {
    std::vector<int> scans(rig.sensors.size(), 0);
    for (const HandEyeView& view : stations[k].views) ++scans[view.sensor];
    for (const HandEyeView& view : stations[k].views) {
      PoseState& sensor = graph->sensors[view.sensor];
      const FrameMounting mounting = rig.mounting(view.sensor);
      // The frames the sensor and the board move with at this station (the tool, the link the sensor sits
      // on), or the base frame's constant block where one is fixed.
      const HandEyeSensor& on = rig.sensors[view.sensor];
      PoseState& sensor_frame = on.onLink() ? graph->links.at(on.link_chain)[k] : mounting.sensor_moves ? graph->tools[k] : graph->base;
      PoseState& board_frame = mounting.board_moves ? graph->tools[k] : graph->base;
      const std::vector<double*> blocks = {sensor.rotation.coeffs().data(),       sensor.translation.data(),
                                           graph->board.rotation.coeffs().data(), graph->board.translation.data(),
                                           sensor_frame.rotation.coeffs().data(), sensor_frame.translation.data(),
                                           board_frame.rotation.coeffs().data(),  board_frame.translation.data()};
      const bool laser = rig.sensors[view.sensor].type == SensorType::kLaser2d;
      if (!given[view.sensor].isZero()) {  // a camera refining its intrinsics
        double* intrinsics = graph->intrinsics[view.sensor].data();
        std::vector<double*> with = blocks;
        with.push_back(intrinsics);
        problem.AddResidualBlock(new ceres::AutoDiffCostFunction<CameraViewWithIntrinsics, 6, 4, 3, 4, 3, 4, 3, 4, 3, 4>(
                                     new CameraViewWithIntrinsics{CameraViewResidual(view.pattern, mounting)}),
                                 nullptr, with);
        addIntrinsicsEvidence(&problem, view.pattern, intrinsics);
        continue;
      }
      ceres::CostFunction* cost =
          laser ? beamRangeCost(view.points, estimatedPointSigma(view.points, SensorType::kLaser2d), mounting)
          : rig.sensors[view.sensor].type == SensorType::kCamera
              ? static_cast<ceres::CostFunction*>(new ceres::AutoDiffCostFunction<CameraViewResidual, 6, 4, 3, 4, 3, 4, 3, 4, 3>(
                    new CameraViewResidual(view.pattern, mounting)))
              : new ceres::AutoDiffCostFunction<RangeViewResidual, 4, 4, 3, 4, 3, 4, 3, 4, 3>(
                    new RangeViewResidual(view.points, estimatedPointSigma(view.points, rig.sensors[view.sensor].type), mounting));
      problem.AddResidualBlock(cost, nullptr, blocks);
      if (!laser || !(options.board_width > 0.0 && options.board_height > 0.0)) continue;
      if (view.outline.empty()) continue;
      const LaserScanEnds scan_ends = scanEndsOf(view.outline, view.points, 1, scans[view.sensor]);
      if (scan_ends.points.empty()) continue;
      const OutlinePointsResidual ends = scanEndsOnOutline(scan_ends, options.board_width, options.board_height, options.edge_loss_sigmas);
      std::vector<double*> with_beam = blocks;
      with_beam.push_back(graph->beam_radius[view.sensor].data());
      problem.AddResidualBlock(new ceres::AutoDiffCostFunction<OutlineViewResidual, ceres::DYNAMIC, 4, 3, 4, 3, 4, 3, 4, 3, 2>(
                                   new OutlineViewResidual{ends, mounting}, static_cast<int>(scan_ends.points.size())),
                               nullptr, with_beam);
    }
    PoseState& tool = graph->tools[k];
    if (!options.arm_joints) {
      auto* reported = new ToolPoseResidual(stations[k].base_from_tool, options.tool_rotation_sigma, options.tool_translation_sigma);
      problem.AddResidualBlock(new ceres::AutoDiffCostFunction<ToolPoseResidual, 6, 4, 3>(reported),
                               new ceres::CauchyLoss(options.loss_sigmas), tool.rotation.coeffs().data(), tool.translation.data());
    }
    problem.SetManifold(tool.rotation.coeffs().data(), new ceres::EigenQuaternionManifold());
  }
  for (Eigen::Vector2d& beam : graph->beam_radius)
    if (problem.HasParameterBlock(beam.data())) problem.AddResidualBlock(new ceres::AutoDiffCostFunction<BeamRadiusPrior, 2, 2>(new BeamRadiusPrior), nullptr, beam.data());
  if (const std::optional<ArmJoints>& arm = options.arm_joints) {
    const std::vector<int>& read = arm->readJoints();
    const std::size_t n = read.size();
    graph->offsets.resize(n);
    for (std::size_t i = 0; i < n; ++i) graph->offsets[i] = joint_starts ? joint_starts->offsets[i] : arm->joints[read[i]].offset;
    graph->corrections.assign(stations.size(), std::vector<double>(n, 0.0));
    graph->origins = joint_starts ? joint_starts->origins : std::vector<Vector6d>(n, Vector6d::Zero());
    graph->origin_held = joint_starts ? joint_starts->origin_held : std::vector<std::vector<int>>(n);
    std::vector<double> sigmas;
    for (const int j : read) sigmas.push_back(arm->tolerances.readingSigma(arm->joints[j]));
    for (std::size_t k = 0; k < stations.size(); ++k) {
      // The tool, and each link a sensor sits on, where the joints of its chain put it.
      const auto tie = [&](PoseState& frame, const std::vector<int>& chain) {
        std::vector<double> readings;
        for (const int j : chain) readings.push_back(stations[k].joint_positions[readIndex(*arm, j)]);
        std::vector<double*> blocks = {frame.rotation.coeffs().data(), frame.translation.data()};
        for (const int j : chain) blocks.push_back(&graph->offsets[readIndex(*arm, j)]);
        for (const int j : chain) blocks.push_back(&graph->corrections[k][readIndex(*arm, j)]);
        for (const int j : chain)
          if (arm->joints[j].free_origin) blocks.push_back(graph->origins[readIndex(*arm, j)].data());
        problem.AddResidualBlock(linkFromJointsCost(&arm->joints, chain, readings), nullptr, blocks);
      };
      tie(graph->tools[k], arm->chain);
      for (auto& [chain, links] : graph->links) {
        tie(links[k], chain);
        problem.SetManifold(links[k].rotation.coeffs().data(), new ceres::EigenQuaternionManifold());
      }
      auto* prior = new ceres::DynamicAutoDiffCostFunction<ReadingCorrectionsResidual, 4>(new ReadingCorrectionsResidual{sigmas});
      std::vector<double*> corrections;
      for (double& correction : graph->corrections[k]) prior->AddParameterBlock(1), corrections.push_back(&correction);
      prior->SetNumResiduals(static_cast<int>(n));
      problem.AddResidualBlock(prior, new ceres::CauchyLoss(options.loss_sigmas), corrections);
      for (std::size_t i = 0; i < n; ++i)
        if (arm->joints[read[i]].type == JointType::kFixed) problem.SetParameterBlockConstant(&graph->corrections[k][i]);
    }
    const std::vector<JointCalibration> solvable = armJointsSolvable(rig, *arm, stations);
    for (std::size_t i = 0; i < n; ++i)
      if (!solvable[i].held.empty()) problem.SetParameterBlockConstant(&graph->offsets[i]);
    addJointOriginPriors(&problem, graph->origins, arm->tolerances);
    holdOriginParts(&problem, &graph->origins, graph->origin_held);
  }
  for (std::size_t s = 0; s < graph->sensors.size(); ++s) {
    PoseState& sensor = graph->sensors[s];
    if (!problem.HasParameterBlock(sensor.rotation.coeffs().data())) continue;
    problem.SetManifold(sensor.rotation.coeffs().data(), new ceres::EigenQuaternionManifold());
    if (rig.sensors[s].given_pose) {  // the frame the user gave stays put
      problem.SetParameterBlockConstant(sensor.rotation.coeffs().data());
      problem.SetParameterBlockConstant(sensor.translation.data());
    }
  }
  for (Eigen::Vector4d& intrinsics : graph->intrinsics)
    if (problem.HasParameterBlock(intrinsics.data())) addIntrinsicsPrior(&problem, intrinsics.data(), options.intrinsics);
  problem.SetManifold(graph->board.rotation.coeffs().data(), new ceres::EigenQuaternionManifold());
  if (problem.HasParameterBlock(graph->base.translation.data())) {
    problem.SetParameterBlockConstant(graph->base.rotation.coeffs().data());
    problem.SetParameterBlockConstant(graph->base.translation.data());
  }
  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::DENSE_SCHUR;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.function_tolerance = 1e-12;
  solver_options.parameter_tolerance = 1e-12;
  solver_options.gradient_tolerance = 1e-14;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  // Free origins, solved for the first time: the parts the session does not fix held at the model's, and
  // the graph solved again (a later solve from these starts holds the same).
  if (options.arm_joints && !joint_starts && holdUnfixedOriginParts(&problem, &graph->origins, options.arm_joints->tolerances, &graph->origin_held))
    ceres::Solve(solver_options, &problem, &summary);
  if (!summary.IsSolutionUsable()) throw InputError("hand-eye calibration: the solver failed: " + summary.message);
  graph->cost = summary.final_cost;
  return graph;
}

// Each sensor but the main camera started from the board's poses the main camera's solution gives: a
// camera from its views (numbered alike first: turnLikePredicted), a range sensor from its board planes (alignPlanes; its fitted normals face it, so the board's normal is taken facing
// it too, from whichever side fits).
Eigen::Isometry3d startOf(const ArmRig& rig, int sensor, const std::vector<HandEyeStation>& stations, const Eigen::Isometry3d& board) {
  const bool laser = rig.sensors[sensor].type == SensorType::kLaser2d;
  std::vector<Eigen::Isometry3d> poses;
  std::vector<Plane> in_parent, in_sensor;
  std::vector<std::vector<Eigen::Vector3d>> scans;
  for (const HandEyeStation& s : stations) {
    const Eigen::Isometry3d seen = rig.boardInSensorParent(sensor, board, s);
    for (const HandEyeView& view : s.views) {
      if (view.sensor != sensor) continue;
      if (rig.sensors[sensor].type == SensorType::kCamera) {
        poses.push_back(seen * view.pattern.sensor_from_pattern.inverse());
      } else {
        Plane plane;
        plane.normal = seen.linear().col(2);
        plane.offset = -plane.normal.dot(seen.translation());
        in_parent.push_back(plane);
        if (laser) scans.push_back(view.points);  // a line: no plane of its own
        else in_sensor.push_back(fitPlane(view.points, "hand-eye range view").plane);
      }
    }
  }
  if (!poses.empty()) return chordalMean(poses);
  const std::string what = "hand-eye sensor " + rig.name(sensor);
  if (laser) return alignLaserLines(in_parent, scans, what);  // each scan point on its board's plane, either side
  const Eigen::Isometry3d front = alignPlanes(in_parent, in_sensor, what);
  std::vector<Plane> flipped = in_parent;
  for (Plane& p : flipped) p.normal = -p.normal, p.offset = -p.offset;
  const Eigen::Isometry3d back = alignPlanes(flipped, in_sensor, what);
  const auto misfit = [&](const Eigen::Isometry3d& pose, const std::vector<Plane>& planes) {
    double sum = 0.0;
    for (std::size_t i = 0; i < planes.size(); ++i) sum += (pose.linear() * in_sensor[i].normal - planes[i].normal).norm();
    return sum;
  };
  return misfit(front, in_parent) <= misfit(back, flipped) ? front : back;
}

// Drops the camera views over kMisdetectedViewDistance / kMisdetectedViewAngle from the started rig
// (every sensor's start and the board's) from `stations`; how many. The started rig is within millimetres
// (the closed form, the chordal means, the uncalibrated joints); a view held at its PnP covariance (tens
// of micrometres) that far off would pull every unknown towards it.
int dropMisdetectedViews(const ArmRig& rig, const std::vector<Eigen::Isometry3d>& starts, const Eigen::Isometry3d& board,
                         std::vector<HandEyeStation>* stations) {
  int dropped = 0;
  for (HandEyeStation& s : *stations) {
    const auto misdetected = [&](const HandEyeView& view) {
      if (rig.sensors[view.sensor].type != SensorType::kCamera) return false;
      const Eigen::Matrix<double, 6, 1> e = viewError(rig.boardInSensorParent(view.sensor, board, s), view.pattern, starts[view.sensor]);
      return e.tail<3>().norm() > kMisdetectedViewDistance || e.head<3>().norm() > kMisdetectedViewAngle;
    };
    const auto end = std::remove_if(s.views.begin(), s.views.end(), misdetected);
    dropped += static_cast<int>(s.views.end() - end);
    s.views.erase(end, s.views.end());
  }
  return dropped;
}

// `all_closed_forms`: every OpenCV method for the user to compare (the answer), or only Park and Martin's,
// which starts the graph (a jackknife re-solve).
HandEyeResult solveArmRig(const ArmRig& rig, std::vector<HandEyeStation> stations, const HandEyeOptions& options, bool all_closed_forms) {
  HandEyeResult result;
  result.setup = rig.board_on_tool ? HandEyeSetup::kEyeToHand : HandEyeSetup::kEyeInHand;
  result.main_camera = rig.main_camera;
  // The main camera's closed forms over the tool's motion as its own frame sees it (a head camera's: the
  // tool in its link).
  std::vector<HandEyeStation> motion = rig.sensors[rig.main_camera].onLink() ? rig.mainCameraMotion(stations) : std::vector<HandEyeStation>();
  std::vector<HandEyeStation>& main_stations = motion.empty() ? stations : motion;
  result.flipped_views = numberCornersAlike(&main_stations, rig.main_camera);
  for (std::size_t k = 0; k < motion.size(); ++k) stations[k].views = motion[k].views;
  result.closed_forms = openCvHandEye(main_stations, rig.main_camera, !rig.board_on_tool, all_closed_forms);
  std::vector<Eigen::Isometry3d> starts(rig.sensors.size(), Eigen::Isometry3d::Identity());
  starts[rig.main_camera] = rig.sensors[rig.main_camera].given_pose.value_or(
      std::find_if(result.closed_forms.begin(), result.closed_forms.end(), [](const HandEyeClosedForm& c) { return c.method == "Park"; })->camera);
  const FrameMounting main_mounting = rig.mounting(rig.main_camera);
  std::vector<Eigen::Isometry3d> boards;
  for (const HandEyeStation& s : stations) {
    for (const HandEyeView& view : s.views) {
      if (view.sensor != rig.main_camera) continue;
      // board in its parent = (its parent <- the camera's parent) X C
      Eigen::Isometry3d seen = starts[rig.main_camera] * view.pattern.sensor_from_pattern;
      if (main_mounting.sensor_moves) seen = rig.movingFrameAt(rig.main_camera, s) * seen;
      if (main_mounting.board_moves) seen = s.base_from_tool.inverse() * seen;
      boards.push_back(seen);
    }
  }
  const Eigen::Isometry3d board_start = chordalMean(boards);
  for (std::size_t sensor = 0; sensor < rig.sensors.size(); ++sensor) {
    const int s = static_cast<int>(sensor);
    if (s == rig.main_camera) continue;
    if (rig.sensors[sensor].type == SensorType::kCamera) result.flipped_views += turnLikePredicted(&stations, rig, s, board_start);
    starts[sensor] = rig.sensors[sensor].given_pose.value_or(startOf(rig, s, stations, board_start));
  }

  // Solved with the views' and the arm's own noise; when the cameras' views then disagree far beyond it
  // (a real arm's kinematics, a real camera's intrinsics), solved again with that scatter added.
  result.misdetected_views = dropMisdetectedViews(rig, starts, board_start, &stations);
  std::unique_ptr<ArmGraph> graph = solveGraph(rig, stations, options, starts, board_start);
  // An arm from its joints: from here on each station's tool is where its readings put it with the offsets
  // as solved (what the scatter and the views are judged against; the closed forms above had the readings alone).
  const auto calibratedTools = [&] {
    if (!options.arm_joints) return;
    const ArmJoints arm = withOrigins(*options.arm_joints, graph->origins);
    for (HandEyeStation& s : stations) s.base_from_tool = armLink(arm, s.joint_positions, graph->offsets);
    placeLinks(rig, arm, graph->offsets, &stations);
  };
  calibratedTools();
  std::vector<Eigen::Isometry3d> solved;
  for (const PoseState& p : graph->sensors) solved.push_back(p.pose());
  const auto [rotation_scatter, translation_scatter] =
      unmodelledScatter(rig, viewsAsSolved(stations, graph->intrinsics), solved, graph->board.pose(), options);
  if (translation_scatter > 0.0) {
    result.unmodelled_rotation = rotation_scatter;
    result.unmodelled_translation = translation_scatter;
    // The views of one still pose share that error (the same arm pose, the same image of the board): each
    // takes it times their count, so together they weigh as one view would.
    for (HandEyeStation& s : stations) {
      for (HandEyeView& view : s.views) {
        if (rig.sensors[view.sensor].type != SensorType::kCamera) continue;
        const double shared = static_cast<double>(std::count_if(s.views.begin(), s.views.end(), [&](const HandEyeView& v) { return v.sensor == view.sensor; }));
        view.pattern.pose_covariance.topLeftCorner<3, 3>() += shared * rotation_scatter * rotation_scatter * Eigen::Matrix3d::Identity();
        view.pattern.pose_covariance.bottomRightCorner<3, 3>() += shared * translation_scatter * translation_scatter * Eigen::Matrix3d::Identity();
      }
    }
    const JointStarts joints{graph->offsets, graph->origins, graph->origin_held};
    const std::vector<Eigen::Vector4d> intrinsics = graph->intrinsics;
    graph = solveGraph(rig, stations, options, solved, graph->board.pose(), options.arm_joints ? &joints : nullptr, &intrinsics);
    calibratedTools();
  }
  for (const PoseState& p : graph->sensors) result.sensors.push_back(p.pose());
  result.cost = graph->cost;
  for (const HandEyeSensor& sensor : rig.sensors) result.held.push_back(sensor.given_pose.has_value());
  result.board = graph->board.pose();
  result.beam_radius = graph->beam_radius;
  for (Eigen::Vector2d& beam : graph->beam_radius) result.beam_solved.push_back(graph->problem->HasParameterBlock(beam.data()));
  result.given_intrinsics = givenIntrinsics(rig, stations, options);
  result.refined_intrinsics = result.intrinsics_sigma = std::vector<Eigen::Vector4d>(rig.sensors.size(), Eigen::Vector4d::Zero());
  for (std::size_t s = 0; s < rig.sensors.size(); ++s) {
    if (result.given_intrinsics[s].isZero()) continue;
    result.refined_intrinsics[s] = refinedIntrinsics(result.given_intrinsics[s], graph->intrinsics[s]);
    result.intrinsics_sigma[s] = intrinsicsSigma(graph->problem.get(), graph->intrinsics[s].data(), result.given_intrinsics[s]);
  }
  // From here on the cameras' views are judged as the refined intrinsics put them.
  stations = viewsAsSolved(std::move(stations), graph->intrinsics);

  ceres::Covariance covariance(ceres::Covariance::Options{});
  std::vector<std::pair<const double*, const double*>> blocks;
  const auto add = [&](PoseState& state) {
    blocks.emplace_back(state.rotation.coeffs().data(), state.rotation.coeffs().data());
    blocks.emplace_back(state.translation.data(), state.translation.data());
  };
  for (std::size_t s = 0; s < rig.sensors.size(); ++s)
    if (!result.held[s]) add(graph->sensors[s]);  // a held pose has no uncertainty to give
  add(graph->board);
  result.sensor_sigmas.assign(rig.sensors.size(), Eigen::Matrix<double, 6, 1>::Zero());
  if (covariance.Compute(blocks, graph->problem.get())) {
    for (std::size_t s = 0; s < rig.sensors.size(); ++s)
      if (!result.held[s]) result.sensor_sigmas[s] = sigmasOf(covariance, graph->sensors[s]);
    result.board_sigma = sigmasOf(covariance, graph->board);
  }

  double squared_distance = 0.0, squared_angle = 0.0;
  int views = 0;
  if (const std::optional<ArmJoints>& arm = options.arm_joints) {
    result.joints = armJointsSolvable(rig, *arm, stations);
    std::vector<std::pair<const double*, const double*>> offset_blocks;
    for (std::size_t i = 0; i < graph->offsets.size(); ++i) {
      result.joints[i].offset = graph->offsets[i];
      if (result.joints[i].held.empty()) offset_blocks.emplace_back(&graph->offsets[i], &graph->offsets[i]);
    }
    std::vector<JointDescription> read_joints;
    for (const int j : arm->readJoints()) read_joints.push_back(arm->joints[j]);
    setFreeOriginResults(graph->problem.get(), graph->origins, graph->origin_held, read_joints, arm->tolerances, &result.joints);
    ceres::Covariance offset_covariance(ceres::Covariance::Options{});
    if (!offset_blocks.empty() && offset_covariance.Compute(offset_blocks, graph->problem.get())) {
      for (std::size_t i = 0; i < graph->offsets.size(); ++i) {
        if (!result.joints[i].held.empty()) continue;
        double variance = 0.0;
        offset_covariance.GetCovarianceBlock(&graph->offsets[i], &graph->offsets[i], &variance);
        result.joints[i].standard_deviation = std::sqrt(std::max(variance, 0.0));
        const JointDescription& joint = arm->joints[arm->readJoints()[i]];
        if (result.joints[i].standard_deviation > arm->tolerances.maxOffsetSigma(joint)) {
          char line[200];
          std::snprintf(line, sizeof(line), "weakly fixed (standard deviation %.1f %s): move the joints through more of this joint's and its "
                        "neighbours' range between still poses", 1000.0 * result.joints[i].standard_deviation,
                        JointTolerances::prismatic(joint) ? "mm" : "mrad");
          result.joints[i].weak = line;
        }
      }
    }
  }
  const std::optional<ArmJoints> calibrated_arm =
      options.arm_joints ? std::optional<ArmJoints>(withOrigins(*options.arm_joints, graph->origins)) : std::nullopt;
  for (std::size_t k = 0; k < stations.size(); ++k) {
    // Where the arm put the tool: its readings with the offsets (and origins) as solved (the arm's own report: tf).
    const Eigen::Isometry3d reported =
        calibrated_arm ? armLink(*calibrated_arm, stations[k].joint_positions, graph->offsets) : stations[k].base_from_tool;
    const Eigen::Isometry3d solved_tool = graph->tools[k].pose();
    result.tool_shift.push_back((solved_tool.translation() - reported.translation()).norm());
    result.tool_turn.push_back(rotationAngle(reported.inverse() * solved_tool));
    double departure = std::max(result.tool_shift.back() / options.tool_translation_sigma, result.tool_turn.back() / options.tool_rotation_sigma);
    if (const std::optional<ArmJoints>& arm = options.arm_joints) {
      // From the joints: how far its readings had to move, in their sigmas.
      departure = 0.0;
      for (std::size_t i = 0; i < arm->readJoints().size(); ++i) {
        departure = std::max(departure, std::abs(graph->corrections[k][i]) / arm->tolerances.readingSigma(arm->joints[arm->readJoints()[i]]));
      }
    }
    if (departure > options.loss_sigmas) result.poor_stations.push_back(static_cast<int>(k));
    // The cameras' views against the arm's reported pose: what a poor pose leaves unexplained.
    double distance = 0.0, angle = 0.0;
    int seen = 0;
    for (const HandEyeView& view : stations[k].views) {
      if (rig.sensors[view.sensor].type != SensorType::kCamera) continue;
      const Eigen::Matrix<double, 6, 1> e =
          viewError(rig.boardInSensorParent(view.sensor, result.board, stations[k]), view.pattern, result.sensors[view.sensor]);
      distance += e.tail<3>().norm();
      angle += e.head<3>().norm();
      squared_distance += e.tail<3>().squaredNorm();
      squared_angle += e.head<3>().squaredNorm();
      ++seen, ++views;
    }
    result.view_distance.push_back(seen ? distance / seen : 0.0);
    result.view_angle.push_back(seen ? angle / seen : 0.0);
  }
  result.rms_distance = std::sqrt(squared_distance / std::max(views, 1));
  result.rms_angle = std::sqrt(squared_angle / std::max(views, 1));
  return result;
}

// Why `chain` is not a link's chain among the arm's joints (each joint read, each the child of the one
// before, the first from the tool chain's base), or "".
std::string linkChainProblem(const ArmJoints& arm, const std::vector<int>& chain) {
  const std::vector<int>& read = arm.readJoints();
  for (std::size_t i = 0; i < chain.size(); ++i) {
    if (chain[i] < 0 || chain[i] >= static_cast<int>(arm.joints.size())) return "joint " + std::to_string(chain[i]) + " is not one of the arm's";
    const JointDescription& joint = arm.joints[chain[i]];
    if (std::find(read.begin(), read.end(), chain[i]) == read.end()) return "joint '" + joint.name + "' is not among the joints read";
    const std::string& parent = i > 0 ? arm.joints[chain[i - 1]].child : arm.chain.empty() ? joint.parent : arm.joints[arm.chain.front()].parent;
    if (joint.parent != parent) return "joint '" + joint.name + "' hangs from '" + joint.parent + "', not '" + parent + "'";
  }
  if (chain == arm.chain) return "its chain is the tool's: it is on the tool";
  return "";
}

// handEyeMotionProblem over the motion the main camera's closed form sees (ArmRig::mainCameraMotion).
std::string mainCameraMotionProblem(const ArmRig& rig, const std::vector<HandEyeStation>& stations, const HandEyeOptions& options) {
  return rig.sensors[rig.main_camera].onLink() ? handEyeMotionProblem(rig.mainCameraMotion(stations), options)
                                               : handEyeMotionProblem(stations, options);
}

// Every sensor re-solved without each station in turn (those that leave a motion that can fix it): the
// jackknife standard deviation per axis, translation in the sensor's parent frame and rotation about its
// axes. Returns the re-solves; the spreads stay zero with fewer than 2.
int spreadWithoutEachStation(const ArmRig& rig, const std::vector<HandEyeStation>& stations, const HandEyeOptions& options,
                             const std::vector<Eigen::Isometry3d>& poses, std::vector<Eigen::Matrix<double, 6, 1>>* spreads) {
  std::vector<std::vector<Eigen::Matrix<double, 6, 1>>> moves;
  for (std::size_t left_out = 0; left_out < stations.size(); ++left_out) {
    std::vector<HandEyeStation> rest = stations;
    rest.erase(rest.begin() + static_cast<std::ptrdiff_t>(left_out));
    if (!mainCameraMotionProblem(rig, rest, options).empty()) continue;
    std::vector<Eigen::Isometry3d> again;
    try {
      again = solveArmRig(rig, rest, options, false).sensors;
    } catch (const InputError&) {
      continue;  // a sensor's planes no longer fix it without that pose
    }
    std::vector<Eigen::Matrix<double, 6, 1>> move(poses.size());
    for (std::size_t s = 0; s < poses.size(); ++s) {
      move[s].head<3>() = again[s].translation() - poses[s].translation();
      const Eigen::AngleAxisd turn(again[s].linear() * poses[s].linear().transpose());
      move[s].tail<3>() = turn.angle() * turn.axis();
    }
    moves.push_back(move);
  }
  spreads->assign(poses.size(), Eigen::Matrix<double, 6, 1>::Zero());
  const double m = static_cast<double>(moves.size());
  if (moves.size() < 2) return static_cast<int>(moves.size());
  for (std::size_t s = 0; s < poses.size(); ++s) {
    Eigen::Matrix<double, 6, 1> mean = Eigen::Matrix<double, 6, 1>::Zero();
    for (const auto& move : moves) mean += move[s] / m;
    Eigen::Matrix<double, 6, 1> variance = Eigen::Matrix<double, 6, 1>::Zero();
    for (const auto& move : moves) variance += (move[s] - mean).cwiseAbs2();
    (*spreads)[s] = ((m - 1.0) / m * variance).cwiseSqrt();
  }
  return static_cast<int>(moves.size());
}

// A difference of `translation` and `rotation` in `sigma`'s (its translation's and rotation's norms): the
// larger of the two.
double inSigmas(double translation, double rotation, const Eigen::Matrix<double, 6, 1>& sigma) {
  return std::max(translation / std::max(sigma.head<3>().norm(), 1e-9), rotation / std::max(sigma.tail<3>().norm(), 1e-9));
}

// A sensor's move at `station` as `solved` puts it: between its placement `before` and its double `after`,
// in their combined sigmas.
HandEyePlacementChange placementChangeIn(const HandEyeResult& solved, int before, int after, int station) {
  const Eigen::Isometry3d apart = solved.sensors[before].inverse() * solved.sensors[after];
  const Eigen::Matrix<double, 6, 1> sigma = (solved.sensor_sigmas[before].cwiseAbs2() + solved.sensor_sigmas[after].cwiseAbs2()).cwiseSqrt();
  const double translation = apart.translation().norm(), rotation = rotationAngle(apart);
  return {station, translation, rotation, inSigmas(translation, rotation, sigma)};
}

// `stations` with each sensor that moved (`changes`) doubled in `rig`: its views from the change on are
// of the double (appended to rig's sensors in sensor order, named "... (later)"; `doubles[s]` its index,
// -1 for a sensor that did not move).
std::vector<HandEyeStation> withMovedSensorsDoubled(ArmRig* rig, std::vector<HandEyeStation> stations,
                                                    const std::vector<HandEyePlacementChange>& changes, std::vector<int>* doubles) {
  const std::size_t sensors = rig->sensors.size();
  doubles->assign(sensors, -1);
  for (std::size_t s = 0; s < sensors; ++s) {
    if (s >= changes.size() || changes[s].station < 0) continue;
    rig->sensors.push_back(rig->sensors[s]);
    rig->sensors.back().name = rig->sensors[s].name + " (later)";
    (*doubles)[s] = static_cast<int>(rig->sensors.size()) - 1;
    for (std::size_t k = static_cast<std::size_t>(changes[s].station); k < stations.size(); ++k)
      for (HandEyeView& view : stations[k].views)
        if (view.sensor == static_cast<int>(s)) view.sensor = (*doubles)[s];
  }
  return stations;
}

// Sensor s's placement before and after each split of its stations in time (at least kLeast stations a
// part), the sensor doubled for the second part (and those in `found` at theirs) and the rig solved
// again; the split whose solve fits best (least cost: where the sensor moved, each part fits its own
// views), kept when its two placements lie kMovedSigmas apart. Only for a sensor whose views disagree
// (its spread far over its sigma): the search costs a solve per split.
HandEyePlacementChange placementChange(const ArmRig& rig, const std::vector<HandEyeStation>& stations, const HandEyeOptions& options,
                                       const std::vector<HandEyePlacementChange>& found, int s) {
  constexpr std::size_t kLeast = 4;
  std::vector<std::size_t> its;  // the stations where it saw the board
  for (std::size_t k = 0; k < stations.size(); ++k)
    if (std::any_of(stations[k].views.begin(), stations[k].views.end(), [&](const HandEyeView& v) { return v.sensor == s; })) its.push_back(k);
  HandEyePlacementChange best;
  if (its.size() < 2 * kLeast) return best;
  double least = std::numeric_limits<double>::infinity();
  for (std::size_t split = kLeast; split + kLeast <= its.size(); ++split) {
    std::vector<HandEyePlacementChange> changes = found;
    changes[s].station = static_cast<int>(its[split]);
    ArmRig doubled = rig;
    std::vector<int> doubles;
    const std::vector<HandEyeStation> relabelled = withMovedSensorsDoubled(&doubled, stations, changes, &doubles);
    HandEyeResult parts;
    try {
      parts = solveArmRig(doubled, relabelled, options, false);
    } catch (const InputError&) {
      continue;  // a part alone does not fix it
    }
    if (parts.cost < least) {
      least = parts.cost;
      best = placementChangeIn(parts, s, doubles[s], changes[s].station);
    }
  }
  if (best.sigmas < HandEyeResult::kMovedSigmas) best.station = -1;
  return best;
}

// The rig solved with each sensor that moved (`changes`) as two, before and after, so that its two
// placements pull on nothing else (the board, the tool, the joints, the other sensors); each reported as
// it sits after, its spread across the stations computed again.
HandEyeResult solvedWithMovedSensorsApart(const ArmRig& rig, const std::vector<HandEyeStation>& stations, const HandEyeOptions& options,
                                          const std::vector<HandEyePlacementChange>& changes) {
  ArmRig doubled = rig;
  std::vector<int> doubles;
  const std::vector<HandEyeStation> relabelled = withMovedSensorsDoubled(&doubled, stations, changes, &doubles);
  HandEyeResult result = solveArmRig(doubled, relabelled, options, true);
  result.spread_solves = spreadWithoutEachStation(doubled, relabelled, options, result.sensors, &result.sensor_spreads);
  const std::size_t n = rig.sensors.size();
  result.placement_changes = changes;
  // Each per-sensor figure as its double (after the move) has it, the doubles then dropped.
  const auto asAfter = [&](auto* per_sensor) {
    for (std::size_t s = 0; s < n; ++s)
      if (doubles[s] >= 0) (*per_sensor)[s] = (*per_sensor)[doubles[s]];
    per_sensor->resize(n);
  };
  for (std::size_t s = 0; s < n; ++s) {
    // The move as this solve, every move apart, puts it (the search's was with the later ones' unmodelled).
    if (doubles[s] >= 0) result.placement_changes[s] = placementChangeIn(result, static_cast<int>(s), doubles[s], changes[s].station);
  }
  asAfter(&result.sensors);
  asAfter(&result.sensor_sigmas);
  asAfter(&result.sensor_spreads);
  asAfter(&result.beam_radius);
  asAfter(&result.beam_solved);
  result.held.resize(n);
  result.given_intrinsics.resize(n);
  result.refined_intrinsics.resize(n);
  result.intrinsics_sigma.resize(n);
  return result;
}
}  // namespace

std::string handEyeMotionProblem(const std::vector<HandEyeStation>& stations, const HandEyeOptions& options) {
  char line[512];
  if (stations.size() < 3) {
    std::snprintf(line, sizeof(line),
                  "%zu still pose%s of the arm with the board in view: a hand-eye calibration needs 3 or more, the tool turned "
                  "between them about two different axes",
                  stations.size(), stations.size() == 1 ? "" : "s");
    return line;
  }
  // Every turn between two stations, its axis in the tool frame (A X = X B holds in the tool frame).
  std::vector<Eigen::Vector3d> axes;
  double largest = 0.0;
  for (std::size_t i = 0; i < stations.size(); ++i) {
    for (std::size_t j = i + 1; j < stations.size(); ++j) {
      const Eigen::AngleAxisd turn(stations[i].base_from_tool.linear().transpose() * stations[j].base_from_tool.linear());
      largest = std::max(largest, turn.angle());
      if (turn.angle() >= options.min_rotation) axes.push_back(turn.axis());
    }
  }
  if (axes.empty()) {
    std::snprintf(line, sizeof(line),
                  "the tool turns by at most %.1f degrees between the arm's still poses: the camera's place on the tool cannot be "
                  "told from the arm's motion; turn the tool by %.0f degrees or more between poses, about two different axes",
                  largest * kDegrees, options.min_rotation * kDegrees);
    return line;
  }
  for (const Eigen::Vector3d& a : axes)
    for (const Eigen::Vector3d& b : axes)
      if (std::acos(std::min(1.0, std::abs(a.dot(b)))) >= options.min_axis_angle) return "";
  const Eigen::Vector3d& axis = axes.front();
  std::snprintf(line, sizeof(line),
                "every turn of the tool between the arm's still poses is about one axis (%.2f %.2f %.2f in the tool frame, within "
                "%.0f degrees): the camera's place along it cannot be found; add poses with the tool turned about another axis, by "
                "%.0f degrees or more",
                axis.x(), axis.y(), axis.z(), options.min_axis_angle * kDegrees, options.min_rotation * kDegrees);
  return line;
}

HandEyeResult calibrateArmRig(const std::vector<HandEyeSensor>& sensors, bool board_on_tool, const std::vector<HandEyeStation>& given,
                              const HandEyeOptions& options) {
  ArmRig rig{sensors, board_on_tool, -1};
  for (std::size_t s = 0; s < sensors.size(); ++s) {
    if (sensors[s].onLink()) {
      if (!options.arm_joints) {
        throw InputError("hand-eye calibration: " + rig.name(static_cast<int>(s)) +
                         " sits on a link of the arm before the tool, which needs the arm's joints (their readings and chain)");
      }
      const std::string problem = linkChainProblem(*options.arm_joints, sensors[s].link_chain);
      if (!problem.empty()) throw InputError("hand-eye calibration: " + rig.name(static_cast<int>(s)) + "'s link: " + problem);
      rig.sensors[s].on_tool = true;  // it moves with the joints
    }
    const bool other_side = rig.sensors[s].on_tool != board_on_tool;
    if (sensors[s].type == SensorType::kCamera && other_side && rig.main_camera < 0 && !sensors[s].onLink()) rig.main_camera = static_cast<int>(s);
    // (A sensor on a link sees a board on the tool move with the joints that are not on its link's chain.)
    if (sensors[s].type != SensorType::kCamera && !other_side && !sensors[s].onLink()) {
      throw InputError("hand-eye calibration: sensor " + std::to_string(s) + " (a " + sensorTypeName(sensors[s].type) + ") is " +
                       (board_on_tool ? "on the tool with the board" : "fixed like the board") +
                       ": it sees the board in one place only, which fixes no range sensor");
    }
  }
  // Else the first camera on a link (a head's, watching the board in the gripper).
  for (std::size_t s = 0; s < sensors.size() && rig.main_camera < 0; ++s)
    if (sensors[s].type == SensorType::kCamera && sensors[s].onLink()) rig.main_camera = static_cast<int>(s);
  if (rig.main_camera < 0) {
    throw InputError(std::string("hand-eye calibration: no camera ") + (board_on_tool ? "fixed in the base frame watches the board on the tool"
                                                                                      : "on the tool watches the fixed board"));
  }
  std::vector<HandEyeStation> stations;
  for (const HandEyeStation& s : given) {
    bool main_seen = false;
    for (const HandEyeView& view : s.views) {
      if (view.sensor < 0 || view.sensor >= static_cast<int>(sensors.size())) {
        throw InputError("hand-eye calibration: a view of sensor " + std::to_string(view.sensor) + ", which the rig does not have");
      }
      if (sensors[view.sensor].type == SensorType::kCamera &&
          (!view.pattern.pose_covariance.allFinite() || view.pattern.pose_covariance.llt().info() != Eigen::Success)) {
        throw InputError("hand-eye calibration: a camera view has no usable pose covariance (not positive definite)");
      }
      main_seen |= view.sensor == rig.main_camera;
    }
    if (main_seen) stations.push_back(s);  // the main camera pins every station's board
  }
  if (options.arm_joints) {
    std::vector<double> initial;
    for (const int j : options.arm_joints->readJoints()) initial.push_back(options.arm_joints->joints[j].offset);
    for (std::size_t k = 0; k < stations.size(); ++k) {
      if (stations[k].joint_positions.size() != initial.size()) {
        throw InputError("hand-eye calibration: arm pose " + std::to_string(k + 1) + " has " + std::to_string(stations[k].joint_positions.size()) +
                         " joint readings, the " + (options.arm_joints->read.empty() ? "arm's chain " : "joints read ") +
                         std::to_string(initial.size()) + " joints");
      }
    }
    placeLinks(rig, *options.arm_joints, initial, &stations);
  }
  const std::string problem = mainCameraMotionProblem(rig, stations, options);
  if (!problem.empty()) {
    throw InputError("hand-eye calibration (" + handEyeSetupName(board_on_tool ? HandEyeSetup::kEyeToHand : HandEyeSetup::kEyeInHand) +
                     "): " + problem);
  }
  HandEyeResult result = solveArmRig(rig, stations, options, true);
  result.spread_solves = spreadWithoutEachStation(rig, stations, options, result.sensors, &result.sensor_spreads);
  // A sensor whose views disagree far beyond their noise: did it move part-way? Each found is isolated
  // (solvedWithMovedSensorsApart) before the next is looked for, so that one sensor's move is not taken
  // for another's.
  result.placement_changes.assign(sensors.size(), HandEyePlacementChange());
  for (bool found = true; found && result.spread_solves >= 2;) {
    found = false;
    std::vector<HandEyePlacementChange> changes = result.placement_changes;
    for (std::size_t s = 0; s < sensors.size(); ++s) {
      // The main camera pins every station's board: it is not split.
      if (result.held[s] || static_cast<int>(s) == rig.main_camera || changes[s].station >= 0) continue;
      const Eigen::Matrix<double, 6, 1>& spread = result.sensor_spreads[s];
      if (inSigmas(spread.head<3>().norm(), spread.tail<3>().norm(), result.sensor_sigmas[s]) < HandEyeResult::kInconsistentSpread) continue;
      changes[s] = placementChange(rig, stations, options, result.placement_changes, static_cast<int>(s));
      found = found || changes[s].station >= 0;
    }
    if (!found) break;
    try {
      result = solvedWithMovedSensorsApart(rig, stations, options, changes);
    } catch (const InputError&) {
      result.placement_changes = changes;  // named all the same, the rig as solved whole
      break;
    }
  }
  return result;
}

HandEyeResult calibrateHandEye(const std::vector<HandEyeStation>& stations, HandEyeSetup setup, const HandEyeOptions& options) {
  return calibrateArmRig({{SensorType::kCamera, setup == HandEyeSetup::kEyeInHand}}, setup == HandEyeSetup::kEyeToHand, stations, options);
}

}  // namespace vocal
