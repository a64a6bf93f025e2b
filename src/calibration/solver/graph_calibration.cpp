#include "vocal/calibration/solver/graph_calibration.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <memory>
#include <set>
#include <array>
#include <type_traits>
#include <utility>
#include <sstream>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <ceres/ceres.h>
#include <ceres/manifold.h>
#include <ceres/sphere_manifold.h>

#include "vocal/calibration/extraction/board_outline.h"
#include "vocal/calibration/plane.h"
#include "vocal/calibration/point_statistics.h"
#include "vocal/calibration/solver/arm_pose_fit.h"
#include "vocal/calibration/solver/beam_range_residual.h"
#include "vocal/calibration/solver/camera_outline_residual.h"
#include "vocal/calibration/solver/camera_pose_on_board_residual.h"
#include "vocal/calibration/solver/free_joint_origins.h"
#include "vocal/calibration/solver/hand_eye_closed_form.h"
#include "vocal/calibration/solver/link_from_joints_cost.h"
#include "vocal/calibration/solver/misdetected_view.h"
#include "vocal/calibration/solver/on_board_plane.h"
#include "vocal/calibration/solver/beam_radius_prior.h"
#include "vocal/calibration/solver/outline_points_residual.h"
#include "vocal/calibration/solver/scan_ends.h"
#include "vocal/calibration/solver/tool_pose_residual.h"
#include "vocal/calibration/solver/unmodelled_view_scatter.h"
#include "vocal/calibration/solver/pairwise_initialization.h"
#include "vocal/calibration/solver/plane_measurement_residual.h"
#include "vocal/calibration/solver/point_plane_residual.h"
#include "vocal/calibration/solver/reading_corrections_residual.h"
#include "vocal/calibration/solver/weak_board_prior.h"
#include "vocal/core/errors.h"
#include "vocal/core/se3.h"

namespace vocal {

namespace {
// The least turn (radians) between the board's frames in a camera's mount frame over its views for the
// hand-eye closed form to start it: the closed form's rotation comes from the turns between poses.
constexpr double kLeastHandEyeTurn = 0.1;

// A camera view's board outline (patternOutline) in the camera's frame, placed by its PnP pose.
std::vector<Eigen::Vector3d> cameraOutline(const PlaneMeasurement& view, const BoardEdgeOptions& edges) {
  std::vector<Eigen::Vector3d> outline = patternOutline(edges.width, edges.height);
  for (Eigen::Vector3d& p : outline) p = view.sensor_from_pattern * p;
  return outline;
}

// Where a sensor saw the board's centre: a camera's pattern, a range sensor's edge points (both ends of
// every line) or, with too few of them, its points.
Eigen::Vector3d boardCentreSeen(const TargetObservation& o) {
  if (!o.plane_measurements.empty()) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (const PlaneMeasurement& m : o.plane_measurements) sum += m.sensor_from_pattern.translation();
    return sum / o.plane_measurements.size();
  }
  return centroidOf(o.outline.size() >= 4 ? o.outline : o.points);
}

// The board's pose (rig frame) from one observation of a placed sensor: a camera's PnP pose, or a range
// sensor's plane, centre and longest in-plane direction (along the board's longer side).
Eigen::Isometry3d boardPoseSeen(const TargetObservation& o, const Eigen::Isometry3d& rig_from_sensor, const Plane& plane_in_rig,
                                bool width_is_longer) {
  if (!o.plane_measurements.empty()) return rig_from_sensor * o.plane_measurements.front().sensor_from_pattern;
  const Eigen::Vector3d centre = rig_from_sensor * boardCentreSeen(o);
  const Eigen::Vector3d normal = plane_in_rig.normal;
  const Eigen::Vector3d longest = rig_from_sensor.linear() * principalAxesOf(o.points).axes.col(0);
  Eigen::Vector3d x_axis = width_is_longer ? longest : normal.cross(longest);
  x_axis = (x_axis - normal.dot(x_axis) * normal).normalized();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() << x_axis, normal.cross(x_axis), normal;
  pose.translation() = centre - normal.dot(centre - (-plane_in_rig.offset * normal)) * normal;  // onto the plane
  return pose;
}

// A 2D laser's two ends on the board from the end points of its pooled scans (each scan gives up to
// two): the mean of those on either side of their middle along the line, in beam order; none when one
// side was never seen.
std::vector<Eigen::Vector3d> lineEnds(const std::vector<Eigen::Vector3d>& outline) {
  if (outline.size() < 2) return {};
  const PrincipalAxes line = principalAxesOf(outline);
  const Eigen::Vector3d& mean = line.centroid;
  Eigen::Vector3d along = line.axes.col(0);
  if (along.head<2>().dot(Eigen::Vector2d(-mean.y(), mean.x())) < 0.0) along = -along;  // beam order: counter-clockwise
  std::vector<Eigen::Vector3d> low, high;
  for (const Eigen::Vector3d& p : outline) (along.dot(p - mean) < 0.0 ? low : high).push_back(p);
  if (low.empty() || high.empty() || (centroidOf(high) - centroidOf(low)).norm() < 0.1) return {};
  return {centroidOf(low), centroidOf(high)};
}

struct SensorState {
  Eigen::Quaterniond rotation;  // Ceres block, Eigen's (x, y, z, w) memory order
  Eigen::Vector3d translation;
};

struct PlaneState {
  Eigen::Vector3d normal;
  double offset;
};

// A residual on (sensor rotation, sensor translation, the blocks `blocks` of sizes kSizes); kSize residuals,
// or `residuals` where kSize is ceres::DYNAMIC.
template <typename Residual, int kSize, int... kSizes>
void addSensorResidual(ceres::Problem* problem, const Residual& residual, ceres::LossFunction* loss, SensorState* sensor,
                       std::array<double*, sizeof...(kSizes)> blocks, int residuals = kSize) {
  std::vector<double*> all = {sensor->rotation.coeffs().data(), sensor->translation.data()};
  all.insert(all.end(), blocks.begin(), blocks.end());
  if constexpr (kSize == ceres::DYNAMIC) {
    problem->AddResidualBlock(new ceres::AutoDiffCostFunction<Residual, kSize, 4, 3, kSizes...>(new Residual(residual), residuals), loss, all);
  } else {
    problem->AddResidualBlock(new ceres::AutoDiffCostFunction<Residual, kSize, 4, 3, kSizes...>(new Residual(residual)), loss, all);
  }
}

// A plane residual on the target pose's plane, or (with board edges) on its board's pose; a camera's
// with its intrinsics correction where `intrinsics` is set (then Residual is PlaneMeasurementResidual).
// `residuals` where kSize is ceres::DYNAMIC.
template <typename Residual, int kSize>
void addPlaneResidual(ceres::Problem* problem, const Residual& residual, ceres::LossFunction* loss, SensorState* sensor,
                      PlaneState* plane, SensorState* board, double* intrinsics = nullptr, int residuals = kSize) {
  if constexpr (std::is_same_v<Residual, PlaneMeasurementResidual>) {
    if (intrinsics) {
      const PlaneMeasurementWithIntrinsics with{residual};
      if (plane) {
        addSensorResidual<PlaneMeasurementWithIntrinsics, kSize, 3, 1, 4>(problem, with, loss, sensor,
                                                                          {plane->normal.data(), &plane->offset, intrinsics});
      } else {
        addSensorResidual<OnBoardPlane<PlaneMeasurementWithIntrinsics>, kSize, 4, 3, 4>(
            problem, OnBoardPlane<PlaneMeasurementWithIntrinsics>{with}, loss, sensor,
            {board->rotation.coeffs().data(), board->translation.data(), intrinsics});
      }
      return;
    }
  }
  if (plane) {
    addSensorResidual<Residual, kSize, 3, 1>(problem, residual, loss, sensor, {plane->normal.data(), &plane->offset}, residuals);
    return;
  }
  addSensorResidual<OnBoardPlane<Residual>, kSize, 4, 3>(problem, OnBoardPlane<Residual>{residual}, loss, sensor,
                                                         {board->rotation.coeffs().data(), board->translation.data()}, residuals);
}

void addOutlineResiduals(ceres::Problem* problem, const std::vector<Eigen::Vector3d>& outline, double sigma,
                         const BoardEdgeOptions& edges, SensorState* sensor, SensorState* board) {
  if (outline.empty()) return;
  addSensorResidual<OutlinePointsResidual, ceres::DYNAMIC, 4, 3>(
      problem, OutlinePointsResidual{outline, sigma, 0.5 * edges.width, 0.5 * edges.height, edges.loss_sigmas}, nullptr, sensor,
      {board->rotation.coeffs().data(), board->translation.data()}, static_cast<int>(outline.size()));
}

// OutlinePointsResidual with the sensor's beam radius as a block (a 2D laser's scan ends).
struct OutlinePointsWithBeam {
  OutlinePointsResidual on_outline;
  template <typename T>
  bool operator()(const T* q, const T* t, const T* board_q, const T* board_t, const T* beam, T* residual) const {
    return on_outline.withBeam(q, t, board_q, board_t, beam, residual);
  }
};

void addBeamRadiusPrior(ceres::Problem* problem, double* beam) {
  problem->AddResidualBlock(new ceres::AutoDiffCostFunction<BeamRadiusPrior, 2, 2>(new BeamRadiusPrior), nullptr, beam);
}

// A 2D laser's scan ends at one still pose (the ends of `o`'s scans, two a scan) on the board's outline
// reached by its beam (`beam`, the laser's radius block), as the arm's graph holds them.
void addScanEndResiduals(ceres::Problem* problem, const TargetObservation& o, const BoardEdgeOptions& edges, SensorState* sensor,
                         SensorState* board, double* beam) {
  const int scans = scansOfPooledEnds(o.outline);
  const LaserScanEnds ends = scanEndsOf(o.outline, o.points, scans, scans);
  if (ends.points.empty()) return;
  addSensorResidual<OutlinePointsWithBeam, ceres::DYNAMIC, 4, 3, 2>(
      problem,
      OutlinePointsWithBeam{scanEndsOnOutline(ends, edges.width, edges.height, edges.loss_sigmas)},
      nullptr, sensor, {board->rotation.coeffs().data(), board->translation.data(), beam}, static_cast<int>(ends.points.size()));
}

// The joints' offsets as Ceres blocks (one per joint of `mounts`), each still pose's reading corrections
// (target pose, joint), and where each sensor behind joints was at each (sensor, target pose): what a sensor
// behind joints needs.
struct JointOffsets {
  const JointedMounts* mounts = nullptr;
  std::vector<double>* offsets = nullptr;
  std::map<std::pair<int, int>, double>* corrections = nullptr;
  std::vector<Vector6d>* origins = nullptr;  // per joint: a free origin's correction
  std::map<std::pair<int, int>, SensorState>* placed = nullptr;
};

// The correction of joint j's reading at still pose k, with its prior the first time.
double* readingCorrection(ceres::Problem* problem, const JointOffsets& joints, int k, int j) {
  const auto [entry, added] = joints.corrections->emplace(std::make_pair(k, j), 0.0);
  if (added || !problem->HasParameterBlock(&entry->second)) {
    const JointDescription& joint = joints.mounts->joints[j];
    const double sigma = joints.mounts->tolerances.readingSigma(joint);
    auto* prior = new ceres::DynamicAutoDiffCostFunction<ReadingCorrectionsResidual>(new ReadingCorrectionsResidual{{sigma}});
    prior->AddParameterBlock(1);
    prior->SetNumResiduals(1);
    problem->AddResidualBlock(prior, nullptr, &entry->second);
    if (joint.type == JointType::kFixed) problem->SetParameterBlockConstant(&entry->second);
  }
  return &entry->second;
}

// A frame's block at still pose k (`frame`: where a sensor behind joints was, or the board an arm holds)
// tied to `chain` at that pose's `readings` times `mount` in the chain's last link, as the arm's graph ties
// its links to theirs.
void tieToChain(ceres::Problem* problem, const JointOffsets& joints, const std::vector<int>& chain, const std::vector<double>& readings, int k,
                SensorState* frame, SensorState* mount) {
  const std::vector<JointDescription>& described = joints.mounts->joints;
  std::vector<double*> blocks = {frame->rotation.coeffs().data(), frame->translation.data(), mount->rotation.coeffs().data(),
                                 mount->translation.data()};
  for (const int j : chain) blocks.push_back(&(*joints.offsets)[j]);
  for (const int j : chain) blocks.push_back(readingCorrection(problem, joints, k, j));
  for (const int j : chain)
    if (described[j].free_origin) blocks.push_back((*joints.origins)[j].data());
  problem->AddResidualBlock(linkFromJointsCost(&described, chain, readings, true), nullptr, blocks);
}

// A frame's block at a still pose (`frame`: the board on the arm's tool, or a sensor on it) held, less its
// mount, where the arm reported the tool (`tool`), within its repeatability under Cauchy: a pose millimetres
// off moves itself, not the result.
void holdToReportedTool(ceres::Problem* problem, const JointedMounts& mounts, const Eigen::Isometry3d& tool, SensorState* frame,
                        SensorState* mount) {
  const ToolPoseResidual reported(tool, mounts.tool_rotation_sigma, mounts.tool_translation_sigma);
  problem->AddResidualBlock(new ceres::AutoDiffCostFunction<MountedToolPoseResidual, 6, 4, 3, 4, 3>(new MountedToolPoseResidual{reported}),
                            new ceres::CauchyLoss(mounts.tool_loss_sigmas), frame->rotation.coeffs().data(), frame->translation.data(),
                            mount->rotation.coeffs().data(), mount->translation.data());
}

// Where a sensor behind joints was (rig frame) when it made `o`: a block of its own (started where the
// joints' readings put its mount `sensor`), tied to its chain at o's readings times its mount, as the arm's
// graph ties its links to theirs (on the reported tool: held to that tool times its mount); the views'
// residuals see it as a rigid sensor's pose. Null for a rigid sensor.
SensorState* placedOf(ceres::Problem* problem, const TargetObservation& o, const JointOffsets& joints, SensorState* sensor) {
  if (!joints.mounts || !joints.mounts->moves(o.sensor)) return nullptr;
  const JointedMounts& mounts = *joints.mounts;
  const auto [entry, added] = joints.placed->try_emplace({o.sensor, o.target_pose});
  SensorState& placed = entry->second;
  if (added) {
    const Eigen::Isometry3d mount = poseFromTranslationQuaternion(sensor->translation, sensor->rotation.normalized());
    const Eigen::Isometry3d frame = mounts.jointed(o.sensor) ? chainPose(mounts.joints, mounts.chains[o.sensor], o.joint_positions, *joints.offsets)
                                                             : mounts.tool_poses.at(o.target_pose);
    const Eigen::Isometry3d start = frame * mount;
    placed = {Eigen::Quaterniond(start.rotation()), start.translation()};
  }
  if (problem->HasParameterBlock(placed.translation.data())) return &placed;
  if (mounts.jointed(o.sensor)) {
    tieToChain(problem, joints, mounts.chains[o.sensor], o.joint_positions, o.target_pose, &placed, sensor);
  } else {  // on the reported tool, as the board on it
    holdToReportedTool(problem, mounts, mounts.tool_poses.at(o.target_pose), &placed, sensor);
  }
  problem->SetManifold(placed.rotation.coeffs().data(), new ceres::EigenQuaternionManifold());
  return &placed;
}

// Whether camera views are held by their whole poses (BoardEdgeOptions::camera_pose; the board a pose needs its edges).
bool wholeCameraPoses(const CalibrationOptions& options) { return options.board_edges.enabled && options.board_edges.camera_pose; }

// A camera's views as whole poses (BoardEdgeOptions::camera_pose): the print's place on the board (a block)
// and, where given, a count of the views too far from the start to be held so.
struct CameraPoses {
  double* print = nullptr;
  int* misdetected = nullptr;
};

// A camera view's whole pose (the pattern in the camera) against the board's block and the print's place on
// it, numbered as the board's block has its corners: found the other way round, turned half-way (the
// board's start came from another view, or turned to agree with the first pose's on a moving frame). False,
// adding nothing, where the view lies over kMisdetectedView* from where the started camera and board put it.
bool addCameraPoseResidual(ceres::Problem* problem, const PlaneMeasurement& found, const CalibrationOptions& options, SensorState* sensor,
                           SensorState* board, double* print) {
  const Eigen::Isometry3d sensor_start = poseFromTranslationQuaternion(sensor->translation, sensor->rotation.normalized());
  Eigen::Quaterniond pattern_q;
  Eigen::Vector3d pattern_t;
  patternOnBoard(board->rotation.coeffs().data(), board->translation.data(), print, &pattern_q, &pattern_t);
  const Eigen::Isometry3d predicted = sensor_start.inverse() * poseFromTranslationQuaternion(pattern_t, pattern_q);
  const PlaneMeasurement measurement = rotationAngle(found.sensor_from_pattern.inverse() * predicted) > 0.5 * M_PI ? turnedHalfway(found) : found;
  const Eigen::Isometry3d error = measurement.sensor_from_pattern.inverse() * predicted;
  if (error.translation().norm() > kMisdetectedViewDistance || rotationAngle(error) > kMisdetectedViewAngle) return false;
  addSensorResidual<CameraPoseOnBoardResidual, 6, 4, 3, 3>(problem, CameraPoseOnBoardResidual(measurement),
                                                          new ceres::HuberLoss(options.huber_sigmas * std::sqrt(6.0)), sensor,
                                                          {board->rotation.coeffs().data(), board->translation.data(), print});
  return true;
}

// An observation's residuals on its pose's plane (or, with board edges, its board), for a sensor whose
// state is `sensor`. Huber on each whitened block: down-weighted once its residuals pass huber_sigmas
// standard deviations on average. A camera's view, with `poses.print`, as its whole pose where it agrees
// with the start, else by its plane alone; without (or with its intrinsics refined) by its plane and outline.
void addObservationResiduals(ceres::Problem* problem, const TargetObservation& o, SensorType type, const CalibrationOptions& options,
                             SensorState* sensor, std::map<int, PlaneState>* planes, std::map<int, SensorState>* boards,
                             const JointOffsets& joints, double* intrinsics, double* beam, const CameraPoses& poses) {
  const BoardEdgeOptions& edges = options.board_edges;
  PlaneState* plane = edges.enabled ? nullptr : &planes->at(o.target_pose);
  SensorState* board = edges.enabled ? &boards->at(o.target_pose) : nullptr;
  if (SensorState* placed = placedOf(problem, o, joints, sensor)) sensor = placed;
  if (!o.plane_measurements.empty()) {
    for (const PlaneMeasurement& measurement : o.plane_measurements) {
      const bool whole_pose = board && poses.print && !intrinsics;
      if (whole_pose && addCameraPoseResidual(problem, measurement, options, sensor, board, poses.print)) continue;
      addPlaneResidual<PlaneMeasurementResidual, 3>(problem, PlaneMeasurementResidual(measurement),
                                                    new ceres::HuberLoss(options.huber_sigmas * std::sqrt(3.0)), sensor, plane, board,
                                                    intrinsics);
      if (whole_pose) {  // misdetected: a pattern found shifted by a square still lies in the board's plane, not on its outline
        if (poses.misdetected) ++*poses.misdetected;
        continue;
      }
      if (intrinsics) addIntrinsicsEvidence(problem, measurement, intrinsics);
      if (board && intrinsics) {
        for (const Eigen::Vector3d& q : patternOutline(edges.width, edges.height)) {
          addSensorResidual<CameraOutlineWithIntrinsics, 1, 4, 3, 4>(
              problem,
              CameraOutlineWithIntrinsics{q, measurement.sensor_from_pattern, measurement.pose_per_intrinsics, edges.camera_sigma,
                                          0.5 * edges.width, 0.5 * edges.height},
              new ceres::CauchyLoss(edges.loss_sigmas), sensor, {board->rotation.coeffs().data(), board->translation.data(), intrinsics});
        }
      } else if (board) {
        addOutlineResiduals(problem, cameraOutline(measurement, edges), edges.camera_sigma, edges, sensor, board);
      }
    }
    return;
  }
  const double threshold = options.huber_sigmas * std::sqrt(static_cast<double>(o.points.size()));
  if (type == SensorType::kLaser2d) {
    // Range errors along its beams, as in the arm's graph (beam_range_residual.h): a line's distances to
    // the board would bias the laser's height and pitch towards grazing beams.
    addPlaneResidual<BeamRangePlaneResidual, ceres::DYNAMIC>(problem, BeamRangePlaneResidual{o.points, estimatedPointSigma(o.points, type)},
                                                             new ceres::HuberLoss(threshold), sensor, plane, board, nullptr,
                                                             static_cast<int>(o.points.size()));
  } else {
    addPlaneResidual<ObservationOnPlaneResidual, 4>(problem, ObservationOnPlaneResidual(o.points, estimatedPointSigma(o.points, type)),
                                                    new ceres::HuberLoss(threshold), sensor, plane, board);
  }
  if (board && type == SensorType::kLaser2d && beam) {
    addScanEndResiduals(problem, o, edges, sensor, board, beam);
  } else if (board) {
    addOutlineResiduals(problem, o.outline, edges.range_sigma, edges, sensor, board);
  }
}

ceres::Solver::Options solverOptions(const CalibrationOptions& options) {
  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::SPARSE_SCHUR;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.function_tolerance = 1e-12;
  solver_options.parameter_tolerance = 1e-12;
  solver_options.gradient_tolerance = 1e-14;
  solver_options.num_threads = 2;
  return solver_options;
}

// One sensor fitted alone to solved boards held constant: its observations at poses with a board, from
// `sensor`'s current state. The problem, for its covariance; none when no observation has a board.
// `intrinsics`: a camera's intrinsics correction, `beam` a 2D laser's beam radius (with board edges), each
// refined with it where `free_extras`, else held.
std::unique_ptr<ceres::Problem> fitAlone(const std::vector<const TargetObservation*>& its, SensorType type, const CalibrationOptions& options,
                                         SensorState* sensor, std::map<int, PlaneState>* planes, std::map<int, SensorState>* boards,
                                         const JointOffsets& joints, double* intrinsics, bool free_extras, double* beam, double* print) {
  const CameraPoses poses{print, nullptr};
  auto alone = std::make_unique<ceres::Problem>();
  for (const TargetObservation* o : its) {
    if (!planes->count(o->target_pose)) continue;
    addObservationResiduals(alone.get(), *o, type, options, sensor, planes, boards, joints, intrinsics, beam, poses);
  }
  if (alone->NumResidualBlocks() == 0) return nullptr;
  if (intrinsics && free_extras) addIntrinsicsPrior(alone.get(), intrinsics, options.intrinsics);
  if (beam && free_extras && alone->HasParameterBlock(beam)) addBeamRadiusPrior(alone.get(), beam);
  alone->SetManifold(sensor->rotation.coeffs().data(), new ceres::EigenQuaternionManifold());
  std::vector<double*> blocks;
  alone->GetParameterBlocks(&blocks);
  // Its own: its pose (and, behind joints, where it was at each still pose), and its extras where freed.
  std::set<const double*> own_blocks = {sensor->rotation.coeffs().data(), sensor->translation.data()};
  for (const double* extra : {intrinsics, beam})
    if (free_extras && extra) own_blocks.insert(extra);
  for (const TargetObservation* o : its) {
    const auto placed = joints.placed->find({o->sensor, o->target_pose});
    if (placed != joints.placed->end()) own_blocks.insert({placed->second.rotation.coeffs().data(), placed->second.translation.data()});
  }
  for (double* block : blocks) {
    const bool own = own_blocks.count(block) > 0;
    if (!own) alone->SetParameterBlockConstant(block);
  }
  ceres::Solver::Options solver_options = solverOptions(options);
  solver_options.linear_solver_type = ceres::DENSE_QR;  // one sensor: 6 unknowns
  solver_options.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, alone.get(), &summary);
  return alone;
}

// Each listed sensor's standard deviations from `problem`'s covariance; left at zero when it cannot be
// computed (a rank-deficient problem).
// ... and the board's mount on the joints that move it where `board_mount` is given (and solved).
void setStandardDeviations(ceres::Problem* problem, const std::vector<int>& listed, std::vector<SensorState>& sensor_state,
                           CalibrationResult* result, SensorState* board_mount = nullptr) {
  std::vector<SensorState*> states;
  for (const int s : listed) states.push_back(&sensor_state[s]);
  const bool with_board = board_mount && problem->HasParameterBlock(board_mount->translation.data()) &&
                          !problem->IsParameterBlockConstant(board_mount->translation.data());
  if (with_board) states.push_back(board_mount);
  ceres::Covariance::Options covariance_options;
  ceres::Covariance covariance(covariance_options);
  std::vector<std::pair<const double*, const double*>> blocks;
  for (SensorState* state : states) {
    blocks.emplace_back(state->rotation.coeffs().data(), state->rotation.coeffs().data());
    blocks.emplace_back(state->translation.data(), state->translation.data());
  }
  if (blocks.empty() || !covariance.Compute(blocks, problem)) return;
  for (std::size_t i = 0; i < states.size(); ++i) {
    Eigen::Matrix3d rotation_covariance, translation_covariance;
    // The joint covariance of the listed blocks: one block, its 3x3 tangent-space covariance.
    covariance.GetCovarianceMatrixInTangentSpace({states[i]->rotation.coeffs().data()}, rotation_covariance.data());
    covariance.GetCovarianceBlock(states[i]->translation.data(), states[i]->translation.data(), translation_covariance.data());
    Vector6d& sigma = i < listed.size() ? result->sensors[listed[i]].standard_deviation : result->board_mount_sigma;
    sigma.head<3>() = translation_covariance.diagonal().cwiseSqrt();
    // Ceres's quaternion tangent is half the rotation vector (q = [cos|d|, sin|d| d/|d|] q0), so
    // rotation sigmas in radians of angle are twice the tangent's.
    sigma.tail<3>() = 2.0 * rotation_covariance.diagonal().cwiseSqrt();
  }
}

// Each joint's range over the still poses of the sensors behind it (in the graph), and whether its offset
// can be solved: a joint's offset turns (shifts) everything after it in the chain, which the mount at
// the chain's end takes up exactly unless a joint after it moved over the session.
std::vector<JointCalibration> jointOffsetsSolvable(const JointedMounts& mounts, const std::vector<TargetObservation>& observations,
                                                   const std::vector<bool>& isolated, bool base_is_rig_frame) {
  const std::size_t joint_count = mounts.joints.size();
  std::vector<double> low(joint_count, std::numeric_limits<double>::infinity()), high(joint_count, -std::numeric_limits<double>::infinity());
  const auto cover = [&](const std::vector<int>& chain, const std::vector<double>& positions) {
    for (std::size_t i = 0; i < chain.size() && i < positions.size(); ++i) {
      low[chain[i]] = std::min(low[chain[i]], positions[i]);
      high[chain[i]] = std::max(high[chain[i]], positions[i]);
    }
  };
  std::set<int> board_poses;  // the still poses a sensor in the graph saw the board at
  for (const TargetObservation& o : observations) {
    if (isolated[o.sensor]) continue;
    if (mounts.jointed(o.sensor)) cover(mounts.chains[o.sensor], o.joint_positions);
    board_poses.insert(o.target_pose);
  }
  for (const int k : board_poses) {
    const auto board = mounts.board_readings.find(k);
    if (board != mounts.board_readings.end()) cover(mounts.board_chain, board->second);
  }
  std::vector<JointCalibration> joints(joint_count);
  const auto moved = [&](int j) {
    const JointDescription& joint = mounts.joints[j];
    if (joint.type == JointType::kFixed || !(high[j] >= low[j])) return false;
    return high[j] - low[j] >= mounts.tolerances.minMotion(joint);
  };
  std::vector<bool> solvable(joint_count, false), in_a_chain(joint_count, false), before_board(joint_count, false), first(joint_count, false);
  std::vector<std::string> fixed_after(joint_count);  // what ties a solvable joint down on the far side
  // A chain in the graph: a sensor's, or the board's; `known`: what ends it has a known mount.
  const auto judge = [&](const std::vector<int>& chain, bool known, const std::string& known_mount) {
    const auto first_moving = std::find_if(chain.begin(), chain.end(), [&](int j) { return mounts.joints[j].type != JointType::kFixed; });
    if (first_moving != chain.end()) first[*first_moving] = true;
    bool later_moved = false;
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
      in_a_chain[*it] = true;
      if (fixed_after[*it].empty() && (later_moved || known)) fixed_after[*it] = later_moved ? "joints that moved after it" : known_mount;
      solvable[*it] = solvable[*it] || later_moved || known;
      later_moved = later_moved || moved(*it);
    }
  };
  for (std::size_t s = 0; s < mounts.chains.size(); ++s) {
    if (!mounts.jointed(static_cast<int>(s)) || isolated[s]) continue;
    judge(mounts.chains[s], mounts.knownMount(static_cast<int>(s)).has_value(), "the known mount of the sensor behind it");
  }
  if (!mounts.board_chain.empty()) {
    judge(mounts.board_chain, mounts.known_board_mount.has_value(), "the board's known mount");
    for (const int j : mounts.board_chain) before_board[j] = true;
  }
  // The arm's base the rig frame with the board on its chain: the first moving joint of that chain turns the
  // board at every pose about its axis, and the sensors fixed in the base with it, unless a sensor on a
  // chain without that joint (a head's) sees the board too.
  int board_first = -1;
  if (base_is_rig_frame && !mounts.board_chain.empty()) {
    for (const int j : mounts.board_chain)
      if (board_first < 0 && mounts.joints[j].type != JointType::kFixed) board_first = j;
    for (std::size_t s = 0; s < mounts.chains.size() && board_first >= 0; ++s) {
      const std::vector<int>& chain = mounts.chains[s];
      if (mounts.jointed(static_cast<int>(s)) && !isolated[s] && std::find(chain.begin(), chain.end(), board_first) == chain.end()) board_first = -1;
    }
  }
  for (std::size_t j = 0; j < joint_count; ++j) {
    const JointDescription& joint = mounts.joints[j];
    joints[j].offset = joint.offset;
    joints[j].motion = high[j] >= low[j] ? high[j] - low[j] : 0.0;
    joints[j].reported = joint.type != JointType::kFixed && in_a_chain[j];
    if (joint.type == JointType::kFixed) {
      joints[j].held = "a fixed joint";
    } else if (!in_a_chain[j]) {
      joints[j].held = "no calibrated sensor is behind it";
    } else if (first[j] && mounts.board_fixed) {
      joints[j].held = "the first joint from the base, whose frame is the rig's: the board lying still in it takes up its offset";
    } else if (static_cast<int>(j) == board_first) {
      joints[j].held = "the first joint from the base, whose frame is the rig's: the sensors fixed in it take up its offset (give one "
                       "sensor's pose, the reference, to solve it)";
    } else if (!solvable[j] && before_board[j]) {
      joints[j].held = "no joint after it moved over the session, so the board's mount takes up its offset: move the joints after it "
                       "between still poses, or give the board's mount";
    } else if (!solvable[j]) {
      joints[j].held = "no joint after it moved over the session, so the mount of the sensor behind it takes up its offset: move the "
                       "joints after it between still poses, or give the sensor's mount";
    } else {
      joints[j].fixed_by = std::string(mounts.board_fixed        ? "the board lying still in the base frame"
                                       : base_is_rig_frame        ? "the base frame (the rig's)"
                                                                  : "the reference's given pose (the rig frame)") +
                           " and " + fixed_after[j];
    }
  }
  return joints;
}

// The solved joint offsets' standard deviations from `problem`'s covariance.
void setJointStandardDeviations(ceres::Problem* problem, std::vector<double>& offsets, CalibrationResult* result) {
  std::vector<std::pair<const double*, const double*>> blocks;
  for (double& offset : offsets)
    if (problem->HasParameterBlock(&offset) && !problem->IsParameterBlockConstant(&offset)) blocks.emplace_back(&offset, &offset);
  ceres::Covariance::Options covariance_options;
  ceres::Covariance covariance(covariance_options);
  if (blocks.empty() || !covariance.Compute(blocks, problem)) return;
  for (std::size_t j = 0; j < offsets.size(); ++j) {
    if (!problem->HasParameterBlock(&offsets[j]) || problem->IsParameterBlockConstant(&offsets[j])) continue;
    double variance = 0.0;
    covariance.GetCovarianceBlock(&offsets[j], &offsets[j], &variance);
    result->joints[j].standard_deviation = std::sqrt(std::max(variance, 0.0));
  }
  const JointedMounts& mounts = result->mounts;
  for (std::size_t j = 0; j < offsets.size(); ++j) {
    JointCalibration& joint = result->joints[j];
    if (!joint.held.empty() || joint.standard_deviation <= mounts.tolerances.maxOffsetSigma(mounts.joints[j])) continue;
    // The joints after it in the chains it is in: their motion is what separates its offset from the mounts.
    std::string after;
    double motion = 0.0;
    const char* motion_unit = "rad";
    std::vector<std::vector<int>> chains = mounts.chains;
    chains.push_back(mounts.board_chain);
    for (const std::vector<int>& chain : chains) {
      const auto at = std::find(chain.begin(), chain.end(), static_cast<int>(j));
      for (auto it = at == chain.end() ? chain.end() : at + 1; it != chain.end(); ++it) {
        if (mounts.joints[*it].type == JointType::kFixed || after.find("'" + mounts.joints[*it].name + "'") != std::string::npos) continue;
        after += (after.empty() ? "'" : " and '") + mounts.joints[*it].name + "'";
        if (result->joints[*it].motion > motion) {
          motion = result->joints[*it].motion;
          motion_unit = JointTolerances::prismatic(mounts.joints[*it]) ? "m" : "rad";
        }
      }
    }
    const bool before_board = std::find(mounts.board_chain.begin(), mounts.board_chain.end(), static_cast<int>(j)) != mounts.board_chain.end();
    char line[400];
    std::snprintf(line, sizeof(line), "weakly fixed (standard deviation %.1f %s): move %s over more than its %.2f %s between still poses, or "
                  "give %s",
                  1000.0 * joint.standard_deviation, JointTolerances::prismatic(mounts.joints[j]) ? "mm" : "mrad", after.c_str(), motion,
                  motion_unit, before_board ? "the board's mount" : "the mount of the sensor behind it");
    joint.weak = line;
  }
}

// The slope of a line through (range, distance) pairs and its standard error; both 0 for fewer than 4
// pairs or ranges that hardly differ.
void fitScale(const std::vector<std::pair<double, double>>& pairs, double* slope, double* sigma) {
  *slope = *sigma = 0.0;
  const double n = static_cast<double>(pairs.size());
  if (pairs.size() < 4) return;
  double mean_r = 0.0, mean_d = 0.0;
  for (const auto& [r, d] : pairs) mean_r += r / n, mean_d += d / n;
  double srr = 0.0, srd = 0.0;
  for (const auto& [r, d] : pairs) srr += (r - mean_r) * (r - mean_r), srd += (r - mean_r) * (d - mean_d);
  if (srr < 1e-4 * n) return;  // ranges within a centimetre of each other: no slope to see
  *slope = srd / srr;
  double left = 0.0;
  for (const auto& [r, d] : pairs) left += std::pow(d - mean_d - *slope * (r - mean_r), 2);
  *sigma = std::sqrt(left / (n - 2.0) / srr);
}
}  // namespace

namespace {
CalibrationResult solveRig(const std::vector<SensorSpec>& sensors, const std::vector<TargetObservation>& observations,
                           const CalibrationOptions& options) {
  const int sensor_count = static_cast<int>(sensors.size());
  const JointedMounts& mounts = options.mounts;
  // No sensor's pose given and the board on the arm or lying still in its base: the base is the rig frame.
  const bool base_is_reference = options.baseIsRigFrame();
  if (mounts.board_fixed && options.reference_sensor != -1) {
    throw InputError("calibration: the board lies still in the arm's base frame, which is then the rig frame: no sensor is the reference "
                     "(reference_sensor -1), but sensor index " + std::to_string(options.reference_sensor) + " was given");
  }
  if (!base_is_reference && (options.reference_sensor < 0 || options.reference_sensor >= sensor_count)) {
    throw InputError("calibration: reference sensor index " + std::to_string(options.reference_sensor) + " is not one of the " +
                     std::to_string(sensor_count) + " sensors");
  }
  const BoardEdgeOptions& edges = options.board_edges;
  if (edges.enabled && !(edges.width > 0.0 && edges.height > 0.0)) {
    throw InputError("calibration: board edges need the board's width and height (got " + std::to_string(edges.width) + " x " +
                     std::to_string(edges.height) + " m)");
  }
  std::vector<bool> isolated(sensor_count, false);
  for (const int s : options.isolated_sensors) {
    if (s < 0 || s >= sensor_count) {
      throw InputError("calibration: isolated sensor index " + std::to_string(s) + " is not one of the " + std::to_string(sensor_count) +
                       " sensors");
    }
    if (s == options.reference_sensor) {
      throw InputError("calibration: the reference sensor '" + sensors[s].name + "' cannot be kept out of the graph");
    }
    isolated[s] = true;
  }
  // Sensors behind joints or on the reported tool: their mounts are the unknowns, each observation's pose
  // composed through the chain or the tool.
  if (!mounts.chains.empty() && static_cast<int>(mounts.chains.size()) != sensor_count) {
    throw InputError("calibration: the joints name chains for " + std::to_string(mounts.chains.size()) + " sensors of " +
                     std::to_string(sensor_count));
  }
  if (!mounts.on_reported_tool.empty() && static_cast<int>(mounts.on_reported_tool.size()) != sensor_count) {
    throw InputError("calibration: the reported tool names " + std::to_string(mounts.on_reported_tool.size()) + " sensors of " +
                     std::to_string(sensor_count));
  }
  // Whether a sensor is somewhere else at each still pose (behind joints, or on the reported tool).
  const auto moves = [&](int s) { return mounts.moves(s); };
  for (int s = 0; s < sensor_count; ++s) {
    if (mounts.jointed(s) && mounts.onReportedTool(s)) {
      throw InputError("calibration: sensor '" + sensors[s].name + "' is both behind joints and on the reported tool");
    }
    if (!moves(s)) continue;
    if (s == options.reference_sensor) {
      throw InputError("calibration: the reference sensor '" + sensors[s].name + "' is behind joints; give the pose of a sensor mounted rigidly");
    }
    if (!mounts.jointed(s)) continue;
    for (const int j : mounts.chains[s]) {
      if (j < 0 || j >= static_cast<int>(mounts.joints.size())) throw InputError("calibration: sensor '" + sensors[s].name + "''s chain names no joint");
    }
  }
  if (mounts.boardMoves()) {
    if (!edges.enabled) {
      throw InputError("calibration: the board is on a frame that moves (an arm's tool), which needs its full pose at each still pose: "
                       "give the board's size and keep its edges (board_edges)");
    }
    for (const int j : mounts.board_chain) {
      if (j < 0 || j >= static_cast<int>(mounts.joints.size())) throw InputError("calibration: the board's chain names no joint");
    }
    if (!mounts.board_chain.empty() + !mounts.board_tool_poses.empty() + mounts.board_fixed > 1) {
      throw InputError("calibration: the board's frame comes from the arm's joints, from its reported tool poses or is the base frame: "
                       "one of them, not several");
    }
  }
  std::vector<double> joint_offsets;
  for (const JointDescription& joint : mounts.joints) joint_offsets.push_back(joint.offset);
  std::map<std::pair<int, int>, double> reading_corrections;  // a std::map: its values stay where they are (Ceres blocks)
  std::vector<Vector6d> origin_corrections(mounts.joints.size(), Vector6d::Zero());
  std::map<std::pair<int, int>, SensorState> placed_at_poses;  // a std::map too
  const JointOffsets joint_state{&mounts, &joint_offsets, &reading_corrections, &origin_corrections, &placed_at_poses};
  // The chain's pose (rig frame) when o was made, the offsets at their initial values: the identity for a rigid mount.
  const auto chainAt = [&](const TargetObservation& o) { return mounts.mountFrameAt(o.sensor, o.target_pose, o.joint_positions); };
  // Planes fitted per (sensor, target pose).
  std::vector<std::map<int, Plane>> planes(sensor_count);
  std::vector<std::map<int, Eigen::Vector3d>> centres(sensor_count);  // the board's centre as each saw it
  std::vector<int> observation_count(sensor_count, 0);
  for (const TargetObservation& o : observations) {
    if (o.sensor < 0 || o.sensor >= sensor_count) {
      throw InputError("calibration: an observation names sensor index " + std::to_string(o.sensor) + " of " +
                       std::to_string(sensor_count));
    }
    // A 2D laser sees a line of the target, not a plane: its points join the graph directly.
    if (sensors[o.sensor].type != SensorType::kLaser2d) {
      planes[o.sensor][o.target_pose] = fitPlane(o.points, sensors[o.sensor].name.c_str()).plane;
      centres[o.sensor][o.target_pose] = boardCentreSeen(o);
    }
    ++observation_count[o.sensor];
    if (mounts.onReportedTool(o.sensor) && !mounts.tool_poses.count(o.target_pose)) {
      throw InputError("calibration: sensor '" + sensors[o.sensor].name + "' is on the arm's tool, but still pose " + std::to_string(o.target_pose) +
                       " has no tool pose the arm reported");
    }
    if (mounts.jointed(o.sensor)) {
      bool finite = o.joint_positions.size() == mounts.chains[o.sensor].size();
      for (const double q : o.joint_positions) finite = finite && std::isfinite(q);
      if (!finite) {
        throw InputError("calibration: sensor '" + sensors[o.sensor].name + "' is behind " + std::to_string(mounts.chains[o.sensor].size()) +
                         " joints, but its view at still pose " + std::to_string(o.target_pose) + " has " +
                         std::to_string(o.joint_positions.size()) + " finite joint positions");
      }
    }
    if (mounts.boardMoves() && mounts.board_chain.empty() && !mounts.board_fixed && !mounts.board_tool_poses.count(o.target_pose)) {
      throw InputError("calibration: the board is on the arm's tool, but still pose " + std::to_string(o.target_pose) +
                       " has no tool pose the arm reported");
    }
    if (!mounts.board_chain.empty()) {
      const auto readings = mounts.board_readings.find(o.target_pose);
      bool finite = readings != mounts.board_readings.end() && readings->second.size() == mounts.board_chain.size();
      for (std::size_t i = 0; finite && i < readings->second.size(); ++i) finite = std::isfinite(readings->second[i]);
      if (!finite) {
        throw InputError("calibration: the board is behind " + std::to_string(mounts.board_chain.size()) + " joints, but still pose " +
                         std::to_string(o.target_pose) + " has " +
                         std::to_string(readings == mounts.board_readings.end() ? 0 : readings->second.size()) + " readings of them, or one not finite");
      }
    }
  }
  std::map<std::pair<int, int>, const TargetObservation*> observation_of;  // (sensor, target pose)
  for (const TargetObservation& o : observations) observation_of[{o.sensor, o.target_pose}] = &o;
  std::set<std::pair<int, int>> rejected;
  if (options.consensus_filter) {
    // Isolated sensors cast no votes: they are out because they disagree with the rest.
    std::vector<std::map<int, Plane>> voting = planes;
    // Nor do sensors behind joints: their planes move with the joints, not only with the board.
    for (int s = 0; s < sensor_count; ++s)
      if (isolated[s] || moves(s)) voting[s].clear();
    rejected = rejectInconsistentObservations(voting, options.consensus, &centres);
    for (const auto& r : rejected) planes[r.first].erase(r.second);
  }
  for (int s = 0; s < sensor_count; ++s) {
    if (observation_count[s] == 0 && !isolated[s]) {  // an isolated one is absent: left at the identity
      throw InputError("calibration: sensor '" + sensors[s].name + "' never sees the target: its pose is unconstrained in all 6 DoF");
    }
  }

  const std::vector<ObservabilityWarning> warnings = checkObservability(sensors, planes);

  // Chain closed-form estimates along a maximum spanning tree (edges weighted by shared poses).
  auto sharedPoses = [&](int a, int b) {
    std::vector<int> shared;
    for (const auto& entry : planes[a])
      if (planes[b].count(entry.first)) shared.push_back(entry.first);
    return shared;
  };
  auto isLaser = [&](int s) { return sensors[s].type == SensorType::kLaser2d; };
  if (!base_is_reference && isLaser(options.reference_sensor)) {
    throw InputError("calibration: the reference sensor '" + sensors[options.reference_sensor].name +
                     "' is a 2D laser; choose a sensor that sees the target's plane");
  }
  std::vector<Eigen::Isometry3d> initial(sensor_count, Eigen::Isometry3d::Identity());
  std::vector<bool> placed(sensor_count, false);
  std::vector<bool> unplaced(sensor_count, false);  // isolated, and its views cannot place it
  int placed_count = 0;
  if (!base_is_reference) {
    placed[options.reference_sensor] = true;
    initial[options.reference_sensor] = options.reference_pose;
    placed_count = 1;
  } else {
    // The base the rig frame: each camera on the arm over the board lying still (eye-in-hand), or fixed in
    // the base before the board on the arm (eye-to-hand), started from the hand-eye closed form over its
    // views; one that moves while the board does too (a head's before the arm's board) is placed from those
    // by the spanning tree below.
    for (int s = 0; s < sensor_count; ++s) {
      if (isolated[s] || sensors[s].type != SensorType::kCamera || !handEyeClosedFormApplies(mounts, s)) continue;
      std::set<int> kept;
      for (const auto& entry : planes[s]) kept.insert(entry.first);
      const HandEyeViews seen = handEyeViews(mounts, observations, s, &kept);
      if (static_cast<int>(seen.frames.size()) < kLeastSharedPoses || seen.turned < kLeastHandEyeTurn) continue;
      initial[s] = mounts.knownMount(s) ? *mounts.knownMount(s) : openCvHandEye(seen.frames, seen.views, kParkHandEye);
      placed[s] = true;
      ++placed_count;
    }
    if (placed_count == 0 && mounts.board_fixed) {
      throw InputError("calibration: the board lies still in the arm's base frame, but no camera on the arm saw it at " +
                       std::to_string(kLeastSharedPoses) + " still poses or more: a camera's views of the board start the sensors on "
                       "the arm (a range sensor's planes alone leave the board's place in its plane open)");
    }
    if (placed_count == 0) {
      throw InputError("calibration: no sensor's pose is given, so the arm's base is the rig frame, but no camera saw the board on the "
                       "arm at " + std::to_string(kLeastSharedPoses) + " still poses or more, turned between them: a camera's views "
                       "start the others (give one sensor's pose, the reference, to start from it)");
    }
  }
  int plane_sensors = 0;
  const auto absent = [&](int s) { return observation_count[s] == 0; };  // isolated (else thrown above), never seen
  for (int s = 0; s < sensor_count; ++s) plane_sensors += !isLaser(s) && !absent(s);
  for (int added = placed_count; added < plane_sensors; ++added) {
    int best_parent = -1, best_child = -1;
    std::size_t best_shared = 0;
    // An isolated sensor is placed from the others but places none of them, after every other; so is
    // one behind joints (its pose differs per still pose), unless the base is the rig frame and only
    // sensors on the arm place others.
    for (int a = 0; a < sensor_count; ++a) {
      if (!placed[a] || isolated[a] || (moves(a) && !base_is_reference)) continue;
      for (int b = 0; b < sensor_count; ++b) {
        if (placed[b] || isLaser(b)) continue;
        const std::size_t shared = sharedPoses(a, b).size();
        if (shared == 0) continue;
        const bool first = best_child < 0 || (isolated[best_child] && !isolated[b]);
        if (first || (isolated[best_child] == isolated[b] && shared > best_shared)) best_shared = shared, best_parent = a, best_child = b;
      }
    }
    if (best_child < 0) {
      // Left: isolated sensors sharing no pose with the placed ones (too few to place: they stay unplaced).
      bool only_isolated = true;
      for (int s = 0; s < sensor_count; ++s) only_isolated = only_isolated && (placed[s] || isLaser(s) || isolated[s]);
      if (only_isolated) break;
      std::string unplaced;
      for (int s = 0; s < sensor_count; ++s)
        if (!placed[s] && !isLaser(s)) unplaced += (unplaced.empty() ? "'" : ", '") + sensors[s].name + "'";
      throw InputError("calibration: the sensor graph is not connected: " + unplaced +
                       " share no target pose with the reference's group");
    }
    std::vector<Plane> in_parent, in_child;
    BoardCentres centres;
    // A child behind joints: the parent's views carried into the chain's last link at each pose (joint
    // offsets at their initial values), where its mount is fixed; a parent on the arm's: carried into the rig frame.
    const bool child_moves = moves(best_child), moving = child_moves || moves(best_parent);
    for (int k : sharedPoses(best_parent, best_child)) {
      Eigen::Isometry3d link_from_parent = Eigen::Isometry3d::Identity();
      if (moving) {
        link_from_parent = chainAt(*observation_of.at({best_parent, k})) * initial[best_parent];
        if (child_moves) link_from_parent = chainAt(*observation_of.at({best_child, k})).inverse() * link_from_parent;
      }
      in_parent.push_back(transformPlane(link_from_parent, planes[best_parent][k]));
      in_child.push_back(planes[best_child][k]);
      if (edges.enabled) {
        centres.in_a.push_back(link_from_parent * boardCentreSeen(*observation_of.at({best_parent, k})));
        centres.in_b.push_back(boardCentreSeen(*observation_of.at({best_child, k})));
      }
    }
    // An isolated sensor with too few poses to place (calibrateRigWithTrust leaves such a one out): it
    // stays where it is, named by its distrust, and places nothing.
    if (isolated[best_child] && best_shared < kLeastSharedPoses) {
      placed[best_child] = true;
      continue;
    }
    if (const std::optional<Eigen::Isometry3d>& known = mounts.knownMount(best_child)) {
      initial[best_child] = *known;
      placed[best_child] = true;
      continue;
    }
    try {
      initial[best_child] = (moving ? Eigen::Isometry3d::Identity() : initial[best_parent]) *
                            alignPlanes(in_parent, in_child,
                                        "calibration of '" + sensors[best_child].name + "' against '" + sensors[best_parent].name + "'",
                                        edges.enabled ? &centres : nullptr);
    } catch (const InputError& e) {
      // An isolated one stays where it is, named by its distrust (calibrateRigWithTrust), and places nothing.
      if (!isolated[best_child]) throw UnplaceableSensorError(best_child, e.what());
      unplaced[best_child] = true;
    }
    placed[best_child] = true;
  }

  // Where sensor s was (rig frame) at still pose k, as initialised.
  const auto initialAt = [&](int s, int k) { return chainAt(*observation_of.at({s, k})) * initial[s]; };
  // Target planes in the rig frame, from the placed plane-seeing sensors in the graph (rigid ones first).
  std::map<int, Plane> rig_planes;
  for (const bool behind_joints : {false, true}) {
    for (int s = 0; s < sensor_count; ++s) {
      if (isolated[s] || moves(s) != behind_joints) continue;
      for (const auto& entry : planes[s]) {
        if (!rig_planes.count(entry.first)) rig_planes[entry.first] = transformPlane(initialAt(s, entry.first), entry.second);
      }
    }
  }
  // With edges, the board's pose per target pose: from a camera that saw it where one did (cameras
  // first), else from the first range sensor (2D lasers fit no plane).
  std::map<int, Eigen::Isometry3d> rig_boards;
  std::vector<int> board_sources;
  for (int s = 0; s < sensor_count && edges.enabled; ++s)
    if (!isLaser(s) && !isolated[s]) board_sources.push_back(s);
  std::stable_partition(board_sources.begin(), board_sources.end(), [&](int s) { return sensors[s].type == SensorType::kCamera; });
  std::stable_partition(board_sources.begin(), board_sources.end(), [&](int s) { return !moves(s); });
  for (int s : board_sources) {
    for (const auto& entry : planes[s]) {
      if (rig_boards.count(entry.first)) continue;
      rig_boards[entry.first] = boardPoseSeen(*observation_of.at({s, entry.first}), initialAt(s, entry.first), rig_planes[entry.first],
                                              edges.width >= edges.height);
    }
  }
  // The board on a moving frame: its mount there, the mean of where each pose's board puts it. A board seen
  // by range sensors alone is placed in its plane only up to a half turn: each pose's turned to agree with
  // the first (the outline is the same either way).
  std::optional<Eigen::Isometry3d> board_mount_start;
  if (mounts.boardMoves() && !rig_boards.empty()) {
    std::vector<Eigen::Isometry3d> mounted;
    for (auto& [k, board] : rig_boards) {
      Eigen::Isometry3d mount = mounts.boardFrameAt(k).inverse() * board;
      if (!mounted.empty() && rotationAngle(mounted.front().inverse() * mount) > 0.5 * M_PI) {
        board = board * Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ());
        mount = mounts.boardFrameAt(k).inverse() * board;
      }
      mounted.push_back(mount);
    }
    board_mount_start = mounts.known_board_mount ? *mounts.known_board_mount : chordalMean(mounted);
  }
  // 2D lasers: their scan points on those planes (behind joints: carried into its chain's last link at
  // each pose, where its mount is fixed).
  for (int s = 0; s < sensor_count; ++s) {
    if (!isLaser(s) || absent(s)) continue;
    std::vector<Plane> seen_planes;
    std::vector<std::vector<Eigen::Vector3d>> scans;
    ScanEnds scan_ends;
    scan_ends.board_width = edges.width;
    scan_ends.board_height = edges.height;
    for (const TargetObservation& o : observations) {
      if (o.sensor != s || !rig_planes.count(o.target_pose)) continue;
      const Eigen::Isometry3d link_from_rig = chainAt(o).inverse();
      seen_planes.push_back(transformPlane(link_from_rig, rig_planes[o.target_pose]));
      scans.push_back(o.points);
      if (edges.enabled) {
        scan_ends.rig_from_board.push_back(link_from_rig * rig_boards.at(o.target_pose));
        scan_ends.ends.push_back(lineEnds(o.outline));
      }
    }
    try {
      initial[s] = alignLaserLines(seen_planes, scans, "calibration of 2D laser '" + sensors[s].name + "'",
                                   edges.enabled ? &scan_ends : nullptr);
    } catch (const InputError& e) {
      if (!isolated[s]) throw UnplaceableSensorError(s, e.what());
      unplaced[s] = true;
    }
    placed[s] = true;
  }

  // Parameter blocks.
  std::vector<SensorState> sensor_state(sensor_count);
  for (int s = 0; s < sensor_count; ++s) {
    sensor_state[s].rotation = Eigen::Quaterniond(initial[s].rotation());
    sensor_state[s].translation = initial[s].translation();
  }
  std::map<int, PlaneState> plane_state;
  for (const auto& entry : rig_planes) plane_state[entry.first] = {entry.second.normal, entry.second.offset};
  std::map<int, SensorState> board_state;  // with edges: rig_from_board per target pose, instead of its plane
  for (const auto& entry : rig_boards) board_state[entry.first] = {Eigen::Quaterniond(entry.second.rotation()), entry.second.translation()};

  // Cameras' intrinsics corrections (relative, PlaneMeasurement::pose_per_intrinsics), where refined: a
  // camera whose views came from corners.
  std::vector<Eigen::Vector4d> intrinsics_state(sensor_count, Eigen::Vector4d::Zero());
  std::vector<Eigen::Vector4d> given_intrinsics(sensor_count, Eigen::Vector4d::Zero());
  for (const TargetObservation& o : observations)
    for (const PlaneMeasurement& m : o.plane_measurements)
      if (options.intrinsics.enabled && given_intrinsics[o.sensor].isZero()) given_intrinsics[o.sensor] = m.intrinsics;
  const auto intrinsicsOf = [&](int s) { return given_intrinsics[s].isZero() ? nullptr : intrinsics_state[s].data(); };
  // 2D lasers' beam radii, with board edges.
  std::vector<Eigen::Vector2d> beam_state(sensor_count, Eigen::Vector2d::Zero());
  const auto beamOf = [&](int s) { return edges.enabled && sensors[s].type == SensorType::kLaser2d ? beam_state[s].data() : nullptr; };

  // With cameras' whole poses (BoardEdgeOptions::camera_pose): the print's place on the board.
  Eigen::Vector3d print_state = Eigen::Vector3d::Zero();
  double* const print = wholeCameraPoses(options) ? print_state.data() : nullptr;
  int misdetected_views = 0;

  ceres::Problem problem;
  for (const TargetObservation& o : observations) {
    if (!plane_state.count(o.target_pose)) continue;  // only 2D lasers (or isolated sensors) saw it: no plane
    if (rejected.count({o.sensor, o.target_pose}) || isolated[o.sensor]) continue;
    addObservationResiduals(&problem, o, sensors[o.sensor].type, options, &sensor_state[o.sensor], &plane_state, &board_state, joint_state,
                            intrinsicsOf(o.sensor), beamOf(o.sensor), CameraPoses{print, &misdetected_views});
  }
  if (print && problem.HasParameterBlock(print)) {
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<PrintPlacePrior, 3, 3>(new PrintPlacePrior), nullptr, print);
    // Only cameras in the graph: nothing sees the board's edges, the print's place is the board's own.
    bool edges_seen = false;
    for (int s = 0; s < sensor_count; ++s) edges_seen = edges_seen || (!isolated[s] && !absent(s) && sensors[s].type != SensorType::kCamera);
    if (!edges_seen) problem.SetParameterBlockConstant(print);
  }
  for (int s = 0; s < sensor_count; ++s) {
    if (intrinsicsOf(s) && problem.HasParameterBlock(intrinsicsOf(s))) addIntrinsicsPrior(&problem, intrinsicsOf(s), options.intrinsics);
    if (beamOf(s) && problem.HasParameterBlock(beamOf(s))) addBeamRadiusPrior(&problem, beamOf(s));
  }
  // The board on a moving frame: behind joints each pose's board tied to its chain times its mount (the
  // tie of a sensor behind joints); on a tool from tf, the board less its mount where the arm reported the tool.
  SensorState board_mount{Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero()};
  if (board_mount_start) {
    board_mount = {Eigen::Quaterniond(board_mount_start->rotation()), board_mount_start->translation()};
    for (auto& [k, board] : board_state) {
      if (!problem.HasParameterBlock(board.rotation.coeffs().data())) continue;
      if (!mounts.board_chain.empty()) {
        tieToChain(&problem, joint_state, mounts.board_chain, mounts.board_readings.at(k), k, &board, &board_mount);
        continue;
      }
      holdToReportedTool(&problem, mounts, mounts.boardToolPose(k), &board, &board_mount);
    }
    if (problem.HasParameterBlock(board_mount.rotation.coeffs().data())) {
      problem.SetManifold(board_mount.rotation.coeffs().data(), new ceres::EigenQuaternionManifold());
      if (mounts.known_board_mount) {
        problem.SetParameterBlockConstant(board_mount.rotation.coeffs().data());
        problem.SetParameterBlockConstant(board_mount.translation.data());
      }
    }
  }
  // Joint offsets: each solved where a joint after it in some sensor's chain moved over the session, else
  // held (the mount takes it up).
  std::vector<JointCalibration> joint_results = jointOffsetsSolvable(mounts, observations, isolated, base_is_reference);
  for (std::size_t j = 0; j < joint_offsets.size(); ++j) {
    if (problem.HasParameterBlock(&joint_offsets[j]) && !joint_results[j].held.empty()) problem.SetParameterBlockConstant(&joint_offsets[j]);
  }
  addJointOriginPriors(&problem, origin_corrections, mounts.tolerances);
  for (int s = 0; s < sensor_count; ++s) {
    if (problem.HasParameterBlock(sensor_state[s].rotation.coeffs().data()))  // not an isolated sensor's
      problem.SetManifold(sensor_state[s].rotation.coeffs().data(), new ceres::EigenQuaternionManifold());
  }
  if (!edges.enabled) {
    for (auto& entry : plane_state) problem.SetManifold(entry.second.normal.data(), new ceres::SphereManifold<3>());
  }
  for (auto& entry : board_state) {
    if (!problem.HasParameterBlock(entry.second.rotation.coeffs().data())) continue;
    problem.SetManifold(entry.second.rotation.coeffs().data(), new ceres::EigenQuaternionManifold());
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<WeakBoardPrior, 6, 4, 3>(new WeakBoardPrior{entry.second.rotation, entry.second.translation}),
                             nullptr, entry.second.rotation.coeffs().data(), entry.second.translation.data());
  }
  if (!base_is_reference) {
    problem.SetParameterBlockConstant(sensor_state[options.reference_sensor].rotation.coeffs().data());
    problem.SetParameterBlockConstant(sensor_state[options.reference_sensor].translation.data());
  }
  for (int s = 0; s < sensor_count; ++s) {
    if (!mounts.knownMount(s) || !problem.HasParameterBlock(sensor_state[s].translation.data())) continue;
    problem.SetParameterBlockConstant(sensor_state[s].rotation.coeffs().data());
    problem.SetParameterBlockConstant(sensor_state[s].translation.data());
  }

  const ceres::Solver::Options solver_options = solverOptions(options);
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  // Free origins: the parts the session does not fix held at the model's, and the graph solved again.
  std::vector<std::vector<int>> origin_held;
  if (holdUnfixedOriginParts(&problem, &origin_corrections, mounts.tolerances, &origin_held)) ceres::Solve(solver_options, &problem, &summary);
  // Each isolated sensor alone against the boards the others solved (held constant).
  std::vector<std::unique_ptr<ceres::Problem>> isolated_problems(sensor_count);
  for (int s = 0; s < sensor_count; ++s) {
    if (!isolated[s]) continue;
    std::vector<const TargetObservation*> its;
    for (const TargetObservation& o : observations)
      if (o.sensor == s && !rejected.count({o.sensor, o.target_pose})) its.push_back(&o);
    // None: it shares no pose the others fixed, and its closed form stays. Too few: it stays unplaced.
    if ((static_cast<int>(its.size()) < kLeastSharedPoses && !isLaser(s)) || unplaced[s]) continue;
    isolated_problems[s] =
        fitAlone(its, sensors[s].type, options, &sensor_state[s], &plane_state, &board_state, joint_state, intrinsicsOf(s), true, beamOf(s), print);
  }
  for (const auto& entry : board_state) {  // with edges: the solved boards' planes
    const Eigen::Vector3d normal = entry.second.rotation.normalized() * Eigen::Vector3d::UnitZ();
    plane_state[entry.first] = {normal, -normal.dot(entry.second.translation)};
  }

  CalibrationResult result;
  result.warnings = warnings;
  result.mounts = mounts;
  for (std::size_t j = 0; j < joint_offsets.size(); ++j) result.mounts.joints[j].offset = joint_results[j].offset = joint_offsets[j];
  // The joints as solved: a free origin is the one found (and no longer an unknown of what uses them).
  for (std::size_t j = 0; j < origin_corrections.size(); ++j) {
    JointDescription& joint = result.mounts.joints[j];
    if (!joint.free_origin) continue;
    joint.origin = jointOriginCorrected(joint, origin_corrections[j]);
    joint.free_origin = false;
  }
  result.joints = joint_results;
  if (board_mount_start) result.board_mount = poseFromTranslationQuaternion(board_mount.translation, board_mount.rotation.normalized());
  result.print_on_board = print_state;
  result.misdetected_views = misdetected_views;
  for (const auto& [key, placed] : placed_at_poses)
    if (problem.HasParameterBlock(placed.translation.data()))
      result.placed_at_poses[key] = poseFromTranslationQuaternion(placed.translation, placed.rotation.normalized());
  for (const auto& [key, correction] : reading_corrections)
    if (problem.HasParameterBlock(&correction)) result.reading_corrections[key] = correction;
  for (const auto& entry : plane_state) result.board_planes[entry.first] = {entry.second.normal, entry.second.offset};
  for (const auto& entry : board_state) {
    Eigen::Isometry3d board = Eigen::Isometry3d::Identity();
    board.linear() = entry.second.rotation.normalized().toRotationMatrix();
    board.translation() = entry.second.translation;
    result.boards[entry.first] = board;
  }
  result.sensors.resize(sensor_count);
  for (int s = 0; s < sensor_count; ++s) {
    SensorCalibration& out = result.sensors[s];
    out.reference_from_sensor = Eigen::Isometry3d::Identity();
    out.reference_from_sensor.linear() = sensor_state[s].rotation.normalized().toRotationMatrix();
    out.reference_from_sensor.translation() = sensor_state[s].translation;
    out.pairwise_estimate = initial[s];
    out.observations = observation_count[s];
    if (intrinsicsOf(s)) {
      const Eigen::Vector4d& given = given_intrinsics[s];
      const Eigen::Vector4d& dk = intrinsics_state[s];
      out.given_intrinsics = given;
      out.refined_intrinsics = refinedIntrinsics(given, dk);
    }
    const bool solved_beam = beamOf(s) && (problem.HasParameterBlock(beamOf(s)) || (isolated_problems[s] && isolated_problems[s]->HasParameterBlock(beamOf(s))));
    if (solved_beam) out.beam_radius = beam_state[s], out.beam_solved = true;
  }
  // Per pose, how many sensors in the graph fixed its plane: an observation is compared with the board
  // the others put there only where another did.
  std::map<int, int> plane_sources;
  for (int s = 0; s < sensor_count; ++s)
    if (!isolated[s])
      for (const auto& entry : planes[s]) ++plane_sources[entry.first];
  // Each observation's distance to its solved plane, once; sensor and overall RMS over the kept ones.
  std::vector<double> sensor_squared(sensor_count, 0.0);
  std::vector<std::size_t> sensor_points(sensor_count, 0);
  std::vector<std::vector<double>> distances(sensor_count), angles(sensor_count);
  std::vector<std::vector<std::pair<double, double>>> ranged(sensor_count);  // (range, signed distance) per compared view
  for (const TargetObservation& given : observations) {
    TargetObservation moved;
    const TargetObservation& o = result.viewAsSolved(given, &moved);
    ObservationResidual residual;
    residual.sensor = o.sensor;
    residual.target_pose = o.target_pose;
    residual.rejected = rejected.count({o.sensor, o.target_pose}) > 0;
    residual.rms = std::numeric_limits<double>::quiet_NaN();  // no plane was solved for this pose
    residual.plane_distance = residual.plane_angle = std::numeric_limits<double>::quiet_NaN();
    const auto plane = plane_state.find(o.target_pose);
    if (plane != plane_state.end() && !o.points.empty()) {
      const Eigen::Isometry3d pose = result.rigFromSensorAt(o);
      double squared = 0.0;
      for (const Eigen::Vector3d& p : o.points) squared += std::pow(plane->second.normal.dot(pose * p) + plane->second.offset, 2);
      residual.rms = std::sqrt(squared / o.points.size());
      if (!residual.rejected) {
        sensor_squared[o.sensor] += squared;
        sensor_points[o.sensor] += o.points.size();
      }
      // Against the board the others fixed: its own count among the sources when it is in the graph
      // (a 2D laser fixes none).
      const bool own_source = !isolated[o.sensor] && !isLaser(o.sensor) && planes[o.sensor].count(o.target_pose);
      if (plane_sources[o.target_pose] - (own_source ? 1 : 0) > 0) {
        const ViewDisagreement view =
            viewDisagreement(viewInSensor(o, sensors[o.sensor].type), pose, Plane{plane->second.normal, plane->second.offset});
        residual.range = view.range, residual.plane_distance = view.distance, residual.plane_angle = view.angle;
        distances[o.sensor].push_back(std::abs(residual.plane_distance));
        if (!isLaser(o.sensor)) ranged[o.sensor].emplace_back(residual.range, residual.plane_distance);
        if (!std::isnan(residual.plane_angle)) angles[o.sensor].push_back(residual.plane_angle);
      }
    }
    if (residual.rejected) ++result.sensors[o.sensor].rejected_observations;
    result.observations.push_back(residual);
  }
  double total_squared = 0.0;
  std::size_t total_points = 0;
  for (int s = 0; s < sensor_count; ++s) {
    SensorCalibration& out = result.sensors[s];
    out.rms = sensor_points[s] ? std::sqrt(sensor_squared[s] / sensor_points[s]) : 0.0;
    out.isolated = isolated[s];
    out.compared_poses = static_cast<int>(distances[s].size());
    if (!distances[s].empty()) out.disagreement_distance = median(distances[s]);
    if (!angles[s].empty()) out.disagreement_angle = median(angles[s]);
    fitScale(ranged[s], &out.disagreement_scale, &out.disagreement_scale_sigma);
    if (isolated[s]) continue;  // the graph's rms is over the sensors in it
    total_squared += sensor_squared[s];
    total_points += sensor_points[s];
  }
  result.rms = total_points ? std::sqrt(total_squared / total_points) : 0.0;
  if (!summary.IsSolutionUsable()) {
    result.trusted = false;
    result.failure = "the solver did not reach a usable solution: " + summary.message;
  }
  // An isolated sensor's run-away moves none of the others: it is judged on its own (sensor_trust.h).
  for (int s = 0; s < sensor_count && result.trusted; ++s) {
    if (isolated[s]) continue;
    const Eigen::Isometry3d departure = result.sensors[s].pairwise_estimate.inverse() * result.sensors[s].reference_from_sensor;
    const double moved = departure.translation().norm(), turned = rotationAngle(departure);
    if (moved > options.max_departure_translation || turned > options.max_departure_rotation) {
      std::ostringstream message;
      message << "sensor '" << sensors[s].name << "' moved " << moved << " m and " << turned
              << " rad away from its closed-form estimate: the data does not pin it down (too few poses or too many outliers)";
      result.trusted = false;
      result.failure = message.str();
    }
  }

  // Standard deviations from the solver's covariance (residuals are already whitened): the graph's sensors
  // from the graph, each isolated one from its own fit.
  std::vector<int> in_graph;
  for (int s = 0; s < sensor_count; ++s)
    if (s != options.reference_sensor && !isolated[s] && !mounts.knownMount(s)) in_graph.push_back(s);
  setStandardDeviations(&problem, in_graph, sensor_state, &result, board_mount_start ? &board_mount : nullptr);
  for (int s = 0; s < sensor_count; ++s) {
    ceres::Problem* own = isolated[s] ? isolated_problems[s].get() : &problem;
    if (intrinsicsOf(s) && own) result.sensors[s].intrinsics_sigma = intrinsicsSigma(own, intrinsicsOf(s), given_intrinsics[s]);
  }
  setJointStandardDeviations(&problem, joint_offsets, &result);
  setFreeOriginResults(&problem, origin_corrections, origin_held, mounts.joints, mounts.tolerances, &result.joints);
  for (int s = 0; s < sensor_count; ++s)
    if (isolated_problems[s]) setStandardDeviations(isolated_problems[s].get(), {s}, sensor_state, &result);
  return result;
}

// solveRig; an arm's session with camera views as whole poses solved again with each view weighted by what
// they disagree by beyond their noise.
CalibrationResult solveWithViewScatter(const std::vector<SensorSpec>& sensors, const std::vector<TargetObservation>& observations,
                                       const CalibrationOptions& options) {
  // An arm's session, camera views as whole poses: where they disagree beyond their noise and the arm's
  // (a real arm's kinematics, a real lens), solved again with each weighted by that, as the arm's graph does.
  if (!options.mounts.boardMoves() || !wholeCameraPoses(options)) return solveRig(sensors, observations, options);
  const auto solvedWith = [&](const ViewScatter& scatter) {
    CalibrationResult result = scatter.translation > 0.0 ? solveRig(sensors, withViewScatter(observations, sensors, scatter), options)
                                                         : solveRig(sensors, observations, options);
    result.view_scatter = scatter;
    return result;
  };
  if (options.view_scatter) return solvedWith(*options.view_scatter);  // as a solve of every view measured it
  CalibrationResult result = solveRig(sensors, observations, options);
  if (!result.trusted) return result;
  const ViewScatter scatter = unmodelledViewScatter(sensors, observations, result);
  if (scatter.translation <= 0.0) {
    result.view_scatter = scatter;
    return result;
  }
  return solvedWith(scatter);
}
}  // namespace

CalibrationResult calibrateRig(const std::vector<SensorSpec>& sensors, const std::vector<TargetObservation>& observations,
                               const CalibrationOptions& options) {
  CalibrationResult result = solveWithViewScatter(sensors, observations, options);
  for (const auto& [k, fit] : armPoseFits(sensors, observations, result))
    if (fit.poor) result.poor_arm_poses.push_back(k);
  return result;
}

double estimatedPointSigma(const std::vector<Eigen::Vector3d>& points, SensorType type) {
  constexpr double kFloor = 1e-4;
  if (points.size() < 3) return kFloor;
  if (type != SensorType::kLaser2d) return std::max(kFloor, fitPlane(points, "observation").rms);
  // The scan's points lie in z = 0: the spread across their line is the middle one.
  return std::max(kFloor, std::sqrt(std::max(principalAxesOf(points).spread[1], 0.0) / points.size()));
}

ViewInSensor viewInSensor(const TargetObservation& o, SensorType type) {
  ViewInSensor view;
  view.centre = boardCentreSeen(o);
  if (!o.plane_measurements.empty()) {
    view.direction = o.plane_measurements.front().sensor_from_pattern.linear().col(2);
  } else if (type == SensorType::kLaser2d) {
    if (o.points.size() >= 2) view.direction = principalAxesOf(o.points).axes.col(0), view.direction_is_line = true;
  } else if (o.points.size() >= 3) {
    view.direction = fitPlane(o.points, "observation").plane.normal;
  }
  return view;
}

ViewDisagreement viewDisagreement(const ViewInSensor& seen, const Eigen::Isometry3d& rig_from_sensor, const Plane& board) {
  ViewDisagreement view;
  view.range = seen.centre.norm();
  // The board's normal turned towards the sensor: a view beyond the board is then positive.
  const double side = board.signedDistance(rig_from_sensor.translation()) < 0.0 ? -1.0 : 1.0;
  view.distance = -side * board.signedDistance(rig_from_sensor * seen.centre);
  if (seen.direction.isZero()) return view;
  const double along_normal = std::min(1.0, std::abs(board.normal.dot(rig_from_sensor.linear() * seen.direction)));  // |cos|
  view.angle = seen.direction_is_line ? std::asin(along_normal) : std::acos(along_normal);
  return view;
}

Eigen::Vector4d SensorCalibration::intrinsicsCorrection() const {
  if (!intrinsicsRefined()) return Eigen::Vector4d::Zero();
  const Eigen::Vector4d change = refined_intrinsics - given_intrinsics;
  const double fx = given_intrinsics[0], fy = given_intrinsics[1];
  return Eigen::Vector4d(change[0] / fx, change[1] / fy, change[2] / fx, change[3] / fy);
}

const TargetObservation& CalibrationResult::viewAsSolved(const TargetObservation& o, TargetObservation* moved) const {
  const SensorCalibration& sensor = sensors.at(o.sensor);
  if (!sensor.intrinsicsRefined() || o.plane_measurements.empty()) return o;
  const Eigen::Vector4d dk = sensor.intrinsicsCorrection();
  *moved = o;
  for (PlaneMeasurement& m : moved->plane_measurements) m = movedByIntrinsics(m, dk);
  // The corners were placed by the first view's pose.
  const Eigen::Isometry3d shift = moved->plane_measurements.front().sensor_from_pattern * o.plane_measurements.front().sensor_from_pattern.inverse();
  for (Eigen::Vector3d& p : moved->points) p = shift * p;
  return *moved;
}

Eigen::Isometry3d CalibrationResult::rigFromSensorAt(const TargetObservation& o) const {
  const Eigen::Isometry3d& pose = sensors.at(o.sensor).reference_from_sensor;
  return mounts.mountFrameAt(o.sensor, o.target_pose, o.joint_positions) * pose;
}

std::optional<Eigen::Isometry3d> fitSensorToSolvedBoards(const std::vector<SensorSpec>& sensors,
                                                         const std::vector<const TargetObservation*>& its, const CalibrationResult& solved,
                                                         const CalibrationOptions& options) {
  if (its.empty()) return std::nullopt;
  const int s = its.front()->sensor;
  SensorState state{Eigen::Quaterniond(solved.sensors.at(s).reference_from_sensor.rotation()),
                    solved.sensors.at(s).reference_from_sensor.translation()};
  std::map<int, PlaneState> planes;
  std::map<int, SensorState> boards;
  for (const auto& [pose, plane] : solved.board_planes) planes[pose] = {plane.normal, plane.offset};
  for (const auto& [pose, board] : solved.boards) boards[pose] = {Eigen::Quaterniond(board.rotation()), board.translation()};
  std::vector<const TargetObservation*> pointers;
  for (const TargetObservation* o : its) {
    if (o->sensor != s) throw InputError("calibration: fitting one sensor alone, but the observations name two");
    if (options.board_edges.enabled ? boards.count(o->target_pose) : planes.count(o->target_pose)) pointers.push_back(o);
  }
  std::vector<double> joint_offsets;
  for (const JointDescription& joint : solved.mounts.joints) joint_offsets.push_back(joint.offset);
  std::map<std::pair<int, int>, double> reading_corrections;
  std::vector<Vector6d> origins(joint_offsets.size(), Vector6d::Zero());  // as solved: none free
  std::map<std::pair<int, int>, SensorState> placed_at_poses;
  // A refined camera's intrinsics as solved, held.
  const SensorCalibration& as_solved = solved.sensors.at(s);
  Eigen::Vector4d intrinsics = as_solved.intrinsicsCorrection();
  // A 2D laser's beam as solved (none where it was not), held.
  Eigen::Vector2d beam = as_solved.beam_radius;
  const bool laser_ends = options.board_edges.enabled && sensors.at(s).type == SensorType::kLaser2d;
  const JointOffsets joint_state{&solved.mounts, &joint_offsets, &reading_corrections, &origins, &placed_at_poses};
  Eigen::Vector3d print = solved.print_on_board;  // as solved, held
  if (!fitAlone(pointers, sensors.at(s).type, options, &state, &planes, &boards, joint_state,
                as_solved.intrinsicsRefined() ? intrinsics.data() : nullptr, false, laser_ends ? beam.data() : nullptr,
                wholeCameraPoses(options) ? print.data() : nullptr)) {
    return std::nullopt;
  }
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = state.rotation.normalized().toRotationMatrix();
  pose.translation() = state.translation;
  return pose;
}

}  // namespace vocal
