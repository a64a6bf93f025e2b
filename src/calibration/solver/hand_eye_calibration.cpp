#include "vocal/calibration/solver/hand_eye_calibration.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include <Eigen/Cholesky>
#include <Eigen/SVD>
#include <ceres/ceres.h>
#include <ceres/manifold.h>
#include <ceres/rotation.h>
#include <opencv2/calib3d.hpp>

#include "vocal/core/errors.h"
#include "vocal/core/se3.h"

namespace vocal {

std::string handEyeSetupName(HandEyeSetup setup) { return setup == HandEyeSetup::kEyeInHand ? "eye-in-hand" : "eye-to-hand"; }

namespace {
constexpr double kDegrees = 180.0 / M_PI;

// R_meas^T R_pred as a rotation vector (the perturbation R_pred = R_meas exp([w]x)).
template <typename T>
Eigen::Matrix<T, 3, 1> rotationBetween(const Eigen::Quaternion<T>& measured, const Eigen::Quaternion<T>& predicted) {
  const Eigen::Quaternion<T> error = measured.conjugate() * predicted;
  const T wxyz[4] = {error.w(), error.x(), error.y(), error.z()};
  Eigen::Matrix<T, 3, 1> w;
  ceres::QuaternionToAngleAxis(wxyz, w.data());
  return w;
}

// One camera view of the board against the pose the unknowns predict for it: eye-in-hand
// camera <- board = X^-1 T^-1 Y, eye-to-hand X^-1 T Y (X the camera in its parent, Y the board in its
// parent, T base <- tool), as (w, dt) whitened by the view's PnP covariance.
struct ViewResidual {
  ViewResidual(const PlaneMeasurement& view, HandEyeSetup setup)
      : rotation(view.sensor_from_pattern.linear()), translation(view.sensor_from_pattern.translation()), eye_in_hand(setup == HandEyeSetup::kEyeInHand) {
    whitening = view.pose_covariance.llt().matrixL().solve(Eigen::Matrix<double, 6, 6>::Identity());
  }

  template <typename T>
  bool operator()(const T* xq, const T* xt, const T* yq, const T* yt, const T* tq, const T* tt, T* residual) const {
    using Quaternion = Eigen::Quaternion<T>;
    using Vector = Eigen::Matrix<T, 3, 1>;
    const Eigen::Map<const Quaternion> camera_q(xq), board_q(yq), tool_q(tq);
    const Eigen::Map<const Vector> camera_t(xt), board_t(yt), tool_t(tt);
    Quaternion q;
    Vector t;
    if (eye_in_hand) {
      q = camera_q.conjugate() * tool_q.conjugate() * board_q;
      t = camera_q.conjugate() * (tool_q.conjugate() * (board_t - tool_t) - camera_t);
    } else {
      q = camera_q.conjugate() * tool_q * board_q;
      t = camera_q.conjugate() * (tool_q * board_t + tool_t - camera_t);
    }
    Eigen::Matrix<T, 6, 1> r;
    r.template head<3>() = rotationBetween(Quaternion(rotation.cast<T>()), q);
    r.template tail<3>() = t - translation.cast<T>();
    Eigen::Map<Eigen::Matrix<T, 6, 1>> out(residual);
    out = whitening.cast<T>() * r;
    return true;
  }

  Eigen::Matrix3d rotation;
  Eigen::Vector3d translation;
  bool eye_in_hand;
  Eigen::Matrix<double, 6, 6> whitening;
};

// The tool where the arm reported it, within its repeatability: rotation in the tool frame, translation
// in the base frame, each in its sigmas.
struct ToolPoseResidual {
  ToolPoseResidual(const Eigen::Isometry3d& reported, const HandEyeOptions& options)
      : rotation(reported.linear()), translation(reported.translation()),
        rotation_sigma(options.tool_rotation_sigma), translation_sigma(options.tool_translation_sigma) {}

  template <typename T>
  bool operator()(const T* tq, const T* tt, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q(tq);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t(tt);
    Eigen::Map<Eigen::Matrix<T, 6, 1>> out(residual);
    out.template head<3>() = rotationBetween(Eigen::Quaternion<T>(rotation.cast<T>()), Eigen::Quaternion<T>(q)) / T(rotation_sigma);
    out.template tail<3>() = (t - translation.cast<T>()) / T(translation_sigma);
    return true;
  }

  Eigen::Matrix3d rotation;
  Eigen::Vector3d translation;
  double rotation_sigma, translation_sigma;
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

Eigen::Isometry3d chordalMean(const std::vector<Eigen::Isometry3d>& poses) {
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  for (const Eigen::Isometry3d& p : poses) {
    sum += p.linear();
    translation += p.translation();
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(sum, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d rotation = svd.matrixU() * svd.matrixV().transpose();
  if (rotation.determinant() < 0) rotation = svd.matrixU() * Eigen::Vector3d(1, 1, -1).asDiagonal() * svd.matrixV().transpose();
  Eigen::Isometry3d mean = Eigen::Isometry3d::Identity();
  mean.linear() = rotation;
  mean.translation() = translation / static_cast<double>(std::max<std::size_t>(poses.size(), 1));
  return mean;
}

// The board's pose as seen when its corners were found in the other order: turned 180 degrees about
// its normal; the covariance's rotation part follows the pattern frame.
PlaneMeasurement turnedHalfway(const PlaneMeasurement& view) {
  PlaneMeasurement turned = view;
  const Eigen::Matrix3d half_turn = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  turned.sensor_from_pattern.linear() = view.sensor_from_pattern.linear() * half_turn;
  Eigen::Matrix<double, 6, 6> change = Eigen::Matrix<double, 6, 6>::Identity();
  change.topLeftCorner<3, 3>() = half_turn.transpose();
  turned.pose_covariance = change * view.pose_covariance * change.transpose();
  return turned;
}

// Each view's board as the first station's first view numbers its corners: a rotation between two
// stations keeps its angle from the tool's motion to the camera's (A X = X B), and a board found in the
// other order adds half a turn to the camera's.
int numberCornersAlike(std::vector<HandEyeStation>* stations) {
  const HandEyeStation& first = stations->front();
  const Eigen::Matrix3d& first_view = first.views.front().sensor_from_pattern.linear();
  int flipped = 0;
  for (HandEyeStation& station : *stations) {
    const double tool_angle = Eigen::AngleAxisd(first.base_from_tool.linear().transpose() * station.base_from_tool.linear()).angle();
    for (PlaneMeasurement& view : station.views) {
      const PlaneMeasurement turned = turnedHalfway(view);
      const double as_found = Eigen::AngleAxisd(first_view * view.sensor_from_pattern.linear().transpose()).angle();
      const double as_turned = Eigen::AngleAxisd(first_view * turned.sensor_from_pattern.linear().transpose()).angle();
      if (std::abs(as_turned - tool_angle) < std::abs(as_found - tool_angle)) {
        view = turned;
        ++flipped;
      }
    }
  }
  return flipped;
}

// OpenCV's closed form: the camera in its parent (cv::calibrateHandEye takes base <- tool for
// eye-in-hand and tool <- base for eye-to-hand), from each station's first view.
Eigen::Isometry3d openCvHandEye(const std::vector<HandEyeStation>& stations, HandEyeSetup setup, cv::HandEyeCalibrationMethod method) {
  std::vector<cv::Mat> tool_rotations, tool_translations, board_rotations, board_translations;
  auto rotationMat = [](const Eigen::Matrix3d& r) {
    cv::Mat m(3, 3, CV_64F);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) m.at<double>(i, j) = r(i, j);
    return m;
  };
  auto vectorMat = [](const Eigen::Vector3d& v) { return cv::Mat((cv::Mat_<double>(3, 1) << v.x(), v.y(), v.z())); };
  for (const HandEyeStation& s : stations) {
    const Eigen::Isometry3d tool = setup == HandEyeSetup::kEyeInHand ? s.base_from_tool : s.base_from_tool.inverse();
    tool_rotations.push_back(rotationMat(tool.linear()));
    tool_translations.push_back(vectorMat(tool.translation()));
    board_rotations.push_back(rotationMat(s.views.front().sensor_from_pattern.linear()));
    board_translations.push_back(vectorMat(s.views.front().sensor_from_pattern.translation()));
  }
  cv::Mat rotation, translation;
  cv::calibrateHandEye(tool_rotations, tool_translations, board_rotations, board_translations, rotation, translation, method);
  Eigen::Isometry3d camera = Eigen::Isometry3d::Identity();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) camera.linear()(i, j) = rotation.at<double>(i, j);
    camera.translation()[i] = translation.at<double>(i);
  }
  return camera;
}

// The board in its parent as one station's view puts it, given the camera in its parent.
Eigen::Isometry3d boardFrom(const Eigen::Isometry3d& base_from_tool, const Eigen::Isometry3d& camera, const PlaneMeasurement& view,
                            HandEyeSetup setup) {
  return setup == HandEyeSetup::kEyeInHand ? base_from_tool * camera * view.sensor_from_pattern
                                           : base_from_tool.inverse() * camera * view.sensor_from_pattern;
}

// The board each view shows against where X and Y put it with the tool where the arm reported it, as
// (w, dt) of the view's perturbation.
Eigen::Matrix<double, 6, 1> viewError(const HandEyeStation& station, const PlaneMeasurement& view, const Eigen::Isometry3d& camera,
                                      const Eigen::Isometry3d& board, HandEyeSetup setup) {
  const Eigen::Isometry3d predicted = setup == HandEyeSetup::kEyeInHand ? camera.inverse() * station.base_from_tool.inverse() * board
                                                                        : camera.inverse() * station.base_from_tool * board;
  Eigen::Matrix<double, 6, 1> error;
  const Eigen::AngleAxisd turn(view.sensor_from_pattern.linear().transpose() * predicted.linear());
  error.head<3>() = turn.angle() * turn.axis();
  error.tail<3>() = predicted.translation() - view.sensor_from_pattern.translation();
  return error;
}

// What the views disagree by beyond their PnP covariance and the arm's repeatability: a real arm's
// kinematic model, the camera's intrinsics and the print are off by millimetres, far beyond either. Per
// axis, the views' median squared error (rotation, translation) when the median view's error under the
// modelled covariance is over twice what 6 degrees of freedom give (chi-square median 5.35); zero
// otherwise. The median: one poor arm pose among several does not raise it.
std::pair<double, double> unmodelledScatter(const std::vector<HandEyeStation>& stations, const Eigen::Isometry3d& camera,
                                            const Eigen::Isometry3d& board, HandEyeSetup setup, const HandEyeOptions& options) {
  std::vector<double> chi2, rotation, translation;
  for (const HandEyeStation& s : stations) {
    for (const PlaneMeasurement& view : s.views) {
      const Eigen::Matrix<double, 6, 1> e = viewError(s, view, camera, board, setup);
      // The tool's turn moves the board seen by its lever: from the tool to the board.
      const double lever = setup == HandEyeSetup::kEyeInHand ? camera.translation().norm() + view.sensor_from_pattern.translation().norm()
                                                             : board.translation().norm();
      Eigen::Matrix<double, 6, 6> modelled = view.pose_covariance;
      modelled.topLeftCorner<3, 3>() += std::pow(options.tool_rotation_sigma, 2) * Eigen::Matrix3d::Identity();
      modelled.bottomRightCorner<3, 3>() +=
          (std::pow(options.tool_translation_sigma, 2) + std::pow(options.tool_rotation_sigma * lever, 2)) * Eigen::Matrix3d::Identity();
      chi2.push_back(e.dot(modelled.ldlt().solve(e)));
      rotation.push_back(e.head<3>().squaredNorm() / 3.0);
      translation.push_back(e.tail<3>().squaredNorm() / 3.0);
    }
  }
  const auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  };
  constexpr double kChiSquareMedian6 = 5.35;
  if (chi2.empty() || median(chi2) <= 2.0 * kChiSquareMedian6) return {0.0, 0.0};
  // A squared normal's median is 0.455 of its mean.
  return {std::sqrt(median(rotation) / 0.455), std::sqrt(median(translation) / 0.455)};
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

namespace {
HandEyeResult solveHandEye(std::vector<HandEyeStation> stations, HandEyeSetup setup, const HandEyeOptions& options);

// The camera's pose re-solved without each station in turn: its jackknife standard deviation per axis,
// translation in the camera's parent frame and rotation about its axes. None solved: zero, 0 re-solves.
int spreadWithoutEachStation(const std::vector<HandEyeStation>& stations, HandEyeSetup setup, const HandEyeOptions& options,
                             const Eigen::Isometry3d& camera, Eigen::Matrix<double, 6, 1>* spread) {
  std::vector<Eigen::Matrix<double, 6, 1>> moves;
  for (std::size_t left_out = 0; left_out < stations.size(); ++left_out) {
    std::vector<HandEyeStation> rest = stations;
    rest.erase(rest.begin() + static_cast<std::ptrdiff_t>(left_out));
    if (!handEyeMotionProblem(rest, options).empty()) continue;
    const Eigen::Isometry3d again = solveHandEye(rest, setup, options).camera;
    Eigen::Matrix<double, 6, 1> move;
    move.head<3>() = again.translation() - camera.translation();
    const Eigen::AngleAxisd turn(again.linear() * camera.linear().transpose());
    move.tail<3>() = turn.angle() * turn.axis();
    moves.push_back(move);
  }
  spread->setZero();
  const double m = static_cast<double>(moves.size());
  if (moves.size() < 2) return static_cast<int>(moves.size());
  Eigen::Matrix<double, 6, 1> mean = Eigen::Matrix<double, 6, 1>::Zero();
  for (const auto& move : moves) mean += move / m;
  for (const auto& move : moves) *spread += (move - mean).cwiseAbs2();
  *spread = ((m - 1.0) / m * *spread).cwiseSqrt();
  return static_cast<int>(moves.size());
}
}  // namespace

HandEyeResult calibrateHandEye(const std::vector<HandEyeStation>& given, HandEyeSetup setup, const HandEyeOptions& options) {
  std::vector<HandEyeStation> stations;
  for (const HandEyeStation& s : given) {
    if (s.views.empty()) continue;
    for (const PlaneMeasurement& view : s.views) {
      if (!view.pose_covariance.allFinite() || view.pose_covariance.llt().info() != Eigen::Success) {
        throw InputError("hand-eye calibration: a camera view has no usable pose covariance (not positive definite)");
      }
    }
    stations.push_back(s);
  }
  const std::string problem = handEyeMotionProblem(stations, options);
  if (!problem.empty()) throw InputError("hand-eye calibration (" + handEyeSetupName(setup) + "): " + problem);
  HandEyeResult result = solveHandEye(stations, setup, options);
  result.spread_solves = spreadWithoutEachStation(stations, setup, options, result.camera, &result.camera_spread);
  return result;
}

namespace {
// The unknowns and the problem that holds them (for the covariance).
struct HandEyeGraph {
  PoseState camera, board;
  std::vector<PoseState> tools;
  std::unique_ptr<ceres::Problem> problem;
  HandEyeGraph(const Eigen::Isometry3d& camera_start, const Eigen::Isometry3d& board_start) : camera(camera_start), board(board_start) {}
};

std::unique_ptr<HandEyeGraph> solveGraph(const std::vector<HandEyeStation>& stations, HandEyeSetup setup, const HandEyeOptions& options,
                                         const Eigen::Isometry3d& camera_start, const Eigen::Isometry3d& board_start) {
  auto graph = std::make_unique<HandEyeGraph>(camera_start, board_start);
  graph->problem = std::make_unique<ceres::Problem>();
  ceres::Problem& problem = *graph->problem;
  // Reserved first: the residual blocks hold pointers into each tool's state.
  graph->tools.reserve(stations.size());
  for (const HandEyeStation& s : stations) graph->tools.emplace_back(s.base_from_tool);
  for (std::size_t k = 0; k < stations.size(); ++k) {
    PoseState& tool = graph->tools[k];
    for (const PlaneMeasurement& view : stations[k].views) {
      problem.AddResidualBlock(new ceres::AutoDiffCostFunction<ViewResidual, 6, 4, 3, 4, 3, 4, 3>(new ViewResidual(view, setup)), nullptr,
                               graph->camera.rotation.coeffs().data(), graph->camera.translation.data(), graph->board.rotation.coeffs().data(),
                               graph->board.translation.data(), tool.rotation.coeffs().data(), tool.translation.data());
    }
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<ToolPoseResidual, 6, 4, 3>(new ToolPoseResidual(stations[k].base_from_tool, options)),
                             new ceres::CauchyLoss(options.loss_sigmas), tool.rotation.coeffs().data(), tool.translation.data());
    problem.SetManifold(tool.rotation.coeffs().data(), new ceres::EigenQuaternionManifold());
  }
  problem.SetManifold(graph->camera.rotation.coeffs().data(), new ceres::EigenQuaternionManifold());
  problem.SetManifold(graph->board.rotation.coeffs().data(), new ceres::EigenQuaternionManifold());
  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::DENSE_SCHUR;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.function_tolerance = 1e-12;
  solver_options.parameter_tolerance = 1e-12;
  solver_options.gradient_tolerance = 1e-14;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  if (!summary.IsSolutionUsable()) throw InputError("hand-eye calibration: the solver failed: " + summary.message);
  return graph;
}

HandEyeResult solveHandEye(std::vector<HandEyeStation> stations, HandEyeSetup setup, const HandEyeOptions& options) {
  HandEyeResult result;
  result.setup = setup;
  result.flipped_views = numberCornersAlike(&stations);
  const std::pair<const char*, cv::HandEyeCalibrationMethod> methods[] = {{"Tsai", cv::CALIB_HAND_EYE_TSAI},
                                                                          {"Park", cv::CALIB_HAND_EYE_PARK},
                                                                          {"Horaud", cv::CALIB_HAND_EYE_HORAUD},
                                                                          {"Andreff", cv::CALIB_HAND_EYE_ANDREFF},
                                                                          {"Daniilidis", cv::CALIB_HAND_EYE_DANIILIDIS}};
  for (const auto& [name, method] : methods) result.closed_forms.push_back({name, openCvHandEye(stations, setup, method)});
  const Eigen::Isometry3d start = result.closed_forms[1].camera;  // Park and Martin
  std::vector<Eigen::Isometry3d> boards;
  for (const HandEyeStation& s : stations)
    for (const PlaneMeasurement& view : s.views) boards.push_back(boardFrom(s.base_from_tool, start, view, setup));

  // Solved with the views' and the arm's own noise; when the views then disagree far beyond it (a real
  // arm's kinematics, a real camera's intrinsics), solved again with that scatter added to every view.
  std::unique_ptr<HandEyeGraph> graph = solveGraph(stations, setup, options, start, chordalMean(boards));
  const auto [rotation_scatter, translation_scatter] = unmodelledScatter(stations, graph->camera.pose(), graph->board.pose(), setup, options);
  if (translation_scatter > 0.0) {
    result.unmodelled_rotation = rotation_scatter;
    result.unmodelled_translation = translation_scatter;
    // The views of one still pose share that error (the same arm pose, the same image of the board): each
    // takes it times their count, so together they weigh as one view would.
    for (HandEyeStation& s : stations) {
      const double shared = static_cast<double>(s.views.size());
      for (PlaneMeasurement& view : s.views) {
        view.pose_covariance.topLeftCorner<3, 3>() += shared * rotation_scatter * rotation_scatter * Eigen::Matrix3d::Identity();
        view.pose_covariance.bottomRightCorner<3, 3>() += shared * translation_scatter * translation_scatter * Eigen::Matrix3d::Identity();
      }
    }
    graph = solveGraph(stations, setup, options, graph->camera.pose(), graph->board.pose());
  }
  PoseState& camera = graph->camera;
  PoseState& board = graph->board;
  const std::vector<PoseState>& tools = graph->tools;
  ceres::Problem& problem_graph = *graph->problem;
  result.camera = camera.pose();
  result.board = board.pose();

  ceres::Covariance covariance(ceres::Covariance::Options{});
  const std::vector<std::pair<const double*, const double*>> blocks = {
      {camera.rotation.coeffs().data(), camera.rotation.coeffs().data()},
      {camera.translation.data(), camera.translation.data()},
      {board.rotation.coeffs().data(), board.rotation.coeffs().data()},
      {board.translation.data(), board.translation.data()}};
  if (covariance.Compute(blocks, &problem_graph)) {
    result.camera_sigma = sigmasOf(covariance, camera);
    result.board_sigma = sigmasOf(covariance, board);
  }

  double squared_distance = 0.0, squared_angle = 0.0;
  int views = 0;
  for (std::size_t k = 0; k < stations.size(); ++k) {
    const Eigen::Isometry3d reported = stations[k].base_from_tool, solved = tools[k].pose();
    result.tool_shift.push_back((solved.translation() - reported.translation()).norm());
    result.tool_turn.push_back(rotationAngle(reported.inverse() * solved));
    const double shift_sigmas = result.tool_shift.back() / options.tool_translation_sigma;
    const double turn_sigmas = result.tool_turn.back() / options.tool_rotation_sigma;
    if (std::max(shift_sigmas, turn_sigmas) > options.loss_sigmas) result.poor_stations.push_back(static_cast<int>(k));
    // Against the arm's reported pose: what a poor pose leaves unexplained.
    double distance = 0.0, angle = 0.0;
    for (const PlaneMeasurement& view : stations[k].views) {
      const Eigen::Isometry3d predicted = setup == HandEyeSetup::kEyeInHand ? result.camera.inverse() * reported.inverse() * result.board
                                                                            : result.camera.inverse() * reported * result.board;
      const double d = (predicted.translation() - view.sensor_from_pattern.translation()).norm();
      const double a = rotationAngle(view.sensor_from_pattern.inverse() * predicted);
      distance += d / stations[k].views.size();
      angle += a / stations[k].views.size();
      squared_distance += d * d;
      squared_angle += a * a;
      ++views;
    }
    result.view_distance.push_back(distance);
    result.view_angle.push_back(angle);
  }
  result.rms_distance = std::sqrt(squared_distance / std::max(views, 1));
  result.rms_angle = std::sqrt(squared_angle / std::max(views, 1));
  return result;
}
}  // namespace

}  // namespace vocal
