#include "vocal/calibration/graph_calibration.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <ceres/ceres.h>
#include <ceres/manifold.h>
#include <ceres/sphere_manifold.h>

#include "vocal/calibration/pairwise_initialization.h"
#include "vocal/calibration/plane.h"
#include "vocal/core/errors.h"

namespace vocal {

namespace {
// All points of one observation on the target's plane (rig frame). The sum over the points of
// (n . (q p + t) + d)^2 equals |F^T v|^2 with v = (q^-1 n, n . t + d) and F F^T the 4x4 moment matrix
// of the homogeneous points, so one block with 4 residuals carries exactly the information of every
// point at the cost of one.
struct ObservationOnPlaneResidual {
  // Residuals are divided by `point_sigma`, so every observation counts by its own noise.
  ObservationOnPlaneResidual(const std::vector<Eigen::Vector3d>& points, double point_sigma) {
    Eigen::Matrix4d moments = Eigen::Matrix4d::Zero();
    for (const Eigen::Vector3d& p : points) {
      const Eigen::Vector4d h(p.x(), p.y(), p.z(), 1.0);
      moments += h * h.transpose();
    }
    // Positive semi-definite (a 2D laser's points span only 3 dimensions): factor by eigenvalues.
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eigen(moments);
    factor_transpose =
        (eigen.eigenvalues().cwiseMax(0.0).cwiseSqrt() / point_sigma).asDiagonal() * eigen.eigenvectors().transpose();
  }

  template <typename T>
  bool operator()(const T* rotation, const T* translation, const T* normal, const T* offset, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q(rotation);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t(translation);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> n(normal);
    Eigen::Matrix<T, 4, 1> v;
    v.template head<3>() = q.conjugate() * n;
    v[3] = n.dot(t) + offset[0];
    Eigen::Map<Eigen::Matrix<T, 4, 1>> out(residual);
    out = factor_transpose.cast<T>() * v;
    return true;
  }

  Eigen::Matrix4d factor_transpose;
};

// A camera's plane measurement against the target's plane (rig frame): the predicted plane in the
// camera frame, n_c = q^-1 n and d_c = n . t + d, read as the pattern's tilt (n_c along the measured
// pattern x and y axes, zero when they agree) and the measured centre's distance to it, whitened by the
// measurement's covariance.
struct PlaneMeasurementResidual {
  explicit PlaneMeasurementResidual(const PlaneMeasurement& measurement)
      : x_axis(measurement.sensor_from_pattern.linear().col(0)),
        y_axis(measurement.sensor_from_pattern.linear().col(1)),
        centre(measurement.sensor_from_pattern.translation()) {
    // |L^-1 r|^2 = r^T covariance^-1 r for covariance = L L^T.
    whitening = measurement.covariance.llt().matrixL().solve(Eigen::Matrix3d::Identity());
  }

  template <typename T>
  bool operator()(const T* rotation, const T* translation, const T* normal, const T* offset, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q(rotation);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t(translation);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> n(normal);
    const Eigen::Matrix<T, 3, 1> n_camera = q.conjugate() * n;
    const Eigen::Matrix<T, 3, 1> r(n_camera.dot(x_axis.cast<T>()), n_camera.dot(y_axis.cast<T>()),
                                   n_camera.dot(centre.cast<T>()) + n.dot(t) + offset[0]);
    Eigen::Map<Eigen::Matrix<T, 3, 1>> out(residual);
    out = whitening.cast<T>() * r;
    return true;
  }

  Eigen::Vector3d x_axis, y_axis, centre;
  Eigen::Matrix3d whitening;
};

// A range sensor's point noise from its own points: the RMS distance to their best plane (or, for a
// 2D laser, to their best line in the scan plane), with a floor so noise-free data stays finite.
double estimatedPointSigma(const std::vector<Eigen::Vector3d>& points, SensorType type) {
  constexpr double kFloor = 1e-4;
  if (points.size() < 3) return kFloor;
  if (type != SensorType::kLaser2d) return std::max(kFloor, fitPlane(points, "observation").rms);
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const Eigen::Vector3d& p : points) mean += p.head<2>();
  mean /= points.size();
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (const Eigen::Vector3d& p : points) scatter += (p.head<2>() - mean) * (p.head<2>() - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> line(scatter);
  return std::max(kFloor, std::sqrt(std::max(line.eigenvalues()[0], 0.0) / points.size()));
}

struct SensorState {
  Eigen::Quaterniond rotation;  // Ceres block, Eigen's (x, y, z, w) memory order
  Eigen::Vector3d translation;
};

struct PlaneState {
  Eigen::Vector3d normal;
  double offset;
};
}  // namespace

CalibrationResult calibrateRig(const std::vector<SensorSpec>& sensors, const std::vector<TargetObservation>& observations,
                               const CalibrationOptions& options) {
  const int sensor_count = static_cast<int>(sensors.size());
  if (options.reference_sensor < 0 || options.reference_sensor >= sensor_count) {
    throw InputError("calibration: reference sensor index " + std::to_string(options.reference_sensor) + " is not one of the " +
                     std::to_string(sensor_count) + " sensors");
  }
  // Planes fitted per (sensor, target pose).
  std::vector<std::map<int, Plane>> planes(sensor_count);
  std::vector<int> observation_count(sensor_count, 0);
  for (const TargetObservation& o : observations) {
    if (o.sensor < 0 || o.sensor >= sensor_count) {
      throw InputError("calibration: an observation names sensor index " + std::to_string(o.sensor) + " of " +
                       std::to_string(sensor_count));
    }
    // A 2D laser sees a line of the target, not a plane: its points join the graph directly.
    if (sensors[o.sensor].type != SensorType::kLaser2d) {
      planes[o.sensor][o.target_pose] = fitPlane(o.points, sensors[o.sensor].name.c_str()).plane;
    }
    ++observation_count[o.sensor];
  }
  std::set<std::pair<int, int>> rejected;
  if (options.consensus_filter) {
    rejected = rejectInconsistentObservations(planes, options.consensus);
    for (const auto& r : rejected) planes[r.first].erase(r.second);
  }
  for (int s = 0; s < sensor_count; ++s) {
    if (observation_count[s] == 0) {
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
  if (isLaser(options.reference_sensor)) {
    throw InputError("calibration: the reference sensor '" + sensors[options.reference_sensor].name +
                     "' is a 2D laser; choose a sensor that sees the target's plane");
  }
  std::vector<Eigen::Isometry3d> initial(sensor_count, Eigen::Isometry3d::Identity());
  std::vector<bool> placed(sensor_count, false);
  placed[options.reference_sensor] = true;
  initial[options.reference_sensor] = options.reference_pose;
  int plane_sensors = 0;
  for (int s = 0; s < sensor_count; ++s) plane_sensors += !isLaser(s);
  for (int added = 1; added < plane_sensors; ++added) {
    int best_parent = -1, best_child = -1;
    std::size_t best_shared = 0;
    for (int a = 0; a < sensor_count; ++a) {
      if (!placed[a]) continue;
      for (int b = 0; b < sensor_count; ++b) {
        if (placed[b] || isLaser(b)) continue;
        const std::size_t shared = sharedPoses(a, b).size();
        if (shared > best_shared) best_shared = shared, best_parent = a, best_child = b;
      }
    }
    if (best_child < 0) {
      std::string unplaced;
      for (int s = 0; s < sensor_count; ++s)
        if (!placed[s] && !isLaser(s)) unplaced += (unplaced.empty() ? "'" : ", '") + sensors[s].name + "'";
      throw InputError("calibration: the sensor graph is not connected: " + unplaced +
                       " share no target pose with the reference's group");
    }
    std::vector<Plane> in_parent, in_child;
    for (int k : sharedPoses(best_parent, best_child)) {
      in_parent.push_back(planes[best_parent][k]);
      in_child.push_back(planes[best_child][k]);
    }
    initial[best_child] = initial[best_parent] * alignPlanes(in_parent, in_child, "calibration of '" + sensors[best_child].name +
                                                                                    "' against '" + sensors[best_parent].name + "'");
    placed[best_child] = true;
  }

  // Target planes in the rig frame, from the placed plane-seeing sensors.
  std::map<int, Plane> rig_planes;
  for (int s = 0; s < sensor_count; ++s) {
    for (const auto& entry : planes[s]) {
      if (!rig_planes.count(entry.first)) rig_planes[entry.first] = transformPlane(initial[s], entry.second);
    }
  }
  // 2D lasers: their scan points on those planes.
  for (int s = 0; s < sensor_count; ++s) {
    if (!isLaser(s)) continue;
    std::vector<Plane> seen_planes;
    std::vector<std::vector<Eigen::Vector3d>> scans;
    for (const TargetObservation& o : observations) {
      if (o.sensor != s || !rig_planes.count(o.target_pose)) continue;
      seen_planes.push_back(rig_planes[o.target_pose]);
      scans.push_back(o.points);
    }
    initial[s] = alignLaserLines(seen_planes, scans, "calibration of 2D laser '" + sensors[s].name + "'");
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

  ceres::Problem problem;
  for (const TargetObservation& o : observations) {
    if (!plane_state.count(o.target_pose)) continue;  // only 2D lasers saw it: one line fixes no plane
    if (rejected.count({o.sensor, o.target_pose})) continue;
    SensorState& sensor = sensor_state[o.sensor];
    PlaneState& plane = plane_state[o.target_pose];
    // Huber on each whitened block: down-weighted once its residuals pass huber_sigmas standard
    // deviations on average.
    if (!o.plane_measurements.empty()) {
      for (const PlaneMeasurement& measurement : o.plane_measurements) {
        auto* cost = new ceres::AutoDiffCostFunction<PlaneMeasurementResidual, 3, 4, 3, 3, 1>(
            new PlaneMeasurementResidual(measurement));
        problem.AddResidualBlock(cost, new ceres::HuberLoss(options.huber_sigmas * std::sqrt(3.0)),
                                 sensor.rotation.coeffs().data(), sensor.translation.data(), plane.normal.data(),
                                 &plane.offset);
      }
      continue;
    }
    auto* cost = new ceres::AutoDiffCostFunction<ObservationOnPlaneResidual, 4, 4, 3, 3, 1>(
        new ObservationOnPlaneResidual(o.points, estimatedPointSigma(o.points, sensors[o.sensor].type)));
    const double threshold = options.huber_sigmas * std::sqrt(static_cast<double>(o.points.size()));
    problem.AddResidualBlock(cost, new ceres::HuberLoss(threshold), sensor.rotation.coeffs().data(),
                             sensor.translation.data(), plane.normal.data(), &plane.offset);
  }
  for (int s = 0; s < sensor_count; ++s) {
    problem.SetManifold(sensor_state[s].rotation.coeffs().data(), new ceres::EigenQuaternionManifold());
  }
  for (auto& entry : plane_state) problem.SetManifold(entry.second.normal.data(), new ceres::SphereManifold<3>());
  problem.SetParameterBlockConstant(sensor_state[options.reference_sensor].rotation.coeffs().data());
  problem.SetParameterBlockConstant(sensor_state[options.reference_sensor].translation.data());

  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::SPARSE_SCHUR;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.function_tolerance = 1e-12;
  solver_options.parameter_tolerance = 1e-12;
  solver_options.gradient_tolerance = 1e-14;
  solver_options.num_threads = 2;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);

  CalibrationResult result;
  result.warnings = warnings;
  result.sensors.resize(sensor_count);
  for (int s = 0; s < sensor_count; ++s) {
    SensorCalibration& out = result.sensors[s];
    out.reference_from_sensor = Eigen::Isometry3d::Identity();
    out.reference_from_sensor.linear() = sensor_state[s].rotation.normalized().toRotationMatrix();
    out.reference_from_sensor.translation() = sensor_state[s].translation;
    out.pairwise_estimate = initial[s];
    out.observations = observation_count[s];
  }
  // Each observation's distance to its solved plane, once; sensor and overall RMS over the kept ones.
  std::vector<double> sensor_squared(sensor_count, 0.0);
  std::vector<std::size_t> sensor_points(sensor_count, 0);
  for (const TargetObservation& o : observations) {
    ObservationResidual residual;
    residual.sensor = o.sensor;
    residual.target_pose = o.target_pose;
    residual.rejected = rejected.count({o.sensor, o.target_pose}) > 0;
    residual.rms = std::numeric_limits<double>::quiet_NaN();  // no plane was solved for this pose
    const auto plane = plane_state.find(o.target_pose);
    if (plane != plane_state.end() && !o.points.empty()) {
      const Eigen::Isometry3d& pose = result.sensors[o.sensor].reference_from_sensor;
      double squared = 0.0;
      for (const Eigen::Vector3d& p : o.points) squared += std::pow(plane->second.normal.dot(pose * p) + plane->second.offset, 2);
      residual.rms = std::sqrt(squared / o.points.size());
      if (!residual.rejected) {
        sensor_squared[o.sensor] += squared;
        sensor_points[o.sensor] += o.points.size();
      }
    }
    if (residual.rejected) ++result.sensors[o.sensor].rejected_observations;
    result.observations.push_back(residual);
  }
  double total_squared = 0.0;
  std::size_t total_points = 0;
  for (int s = 0; s < sensor_count; ++s) {
    result.sensors[s].rms = sensor_points[s] ? std::sqrt(sensor_squared[s] / sensor_points[s]) : 0.0;
    total_squared += sensor_squared[s];
    total_points += sensor_points[s];
  }
  result.rms = total_points ? std::sqrt(total_squared / total_points) : 0.0;
  if (!summary.IsSolutionUsable()) {
    result.trusted = false;
    result.failure = "the solver did not reach a usable solution: " + summary.message;
  }
  for (int s = 0; s < sensor_count && result.trusted; ++s) {
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

  // Standard deviations from the solver's covariance (residuals are already whitened).
  ceres::Covariance::Options covariance_options;
  ceres::Covariance covariance(covariance_options);
  std::vector<std::pair<const double*, const double*>> blocks;
  for (int s = 0; s < sensor_count; ++s) {
    if (s == options.reference_sensor) continue;
    blocks.emplace_back(sensor_state[s].rotation.coeffs().data(), sensor_state[s].rotation.coeffs().data());
    blocks.emplace_back(sensor_state[s].translation.data(), sensor_state[s].translation.data());
  }
  if (!blocks.empty() && covariance.Compute(blocks, &problem)) {
    for (int s = 0; s < sensor_count; ++s) {
      if (s == options.reference_sensor) continue;
      Eigen::Matrix3d rotation_covariance, translation_covariance;
      // The joint covariance of the listed blocks: one block, its 3x3 tangent-space covariance.
      covariance.GetCovarianceMatrixInTangentSpace({sensor_state[s].rotation.coeffs().data()}, rotation_covariance.data());
      covariance.GetCovarianceBlock(sensor_state[s].translation.data(), sensor_state[s].translation.data(),
                                    translation_covariance.data());
      result.sensors[s].standard_deviation.head<3>() = translation_covariance.diagonal().cwiseSqrt();
      // Ceres's quaternion tangent is half the rotation vector (q = [cos|d|, sin|d| d/|d|] q0), so
      // rotation sigmas in radians of angle are twice the tangent's.
      result.sensors[s].standard_deviation.tail<3>() = 2.0 * rotation_covariance.diagonal().cwiseSqrt();
    }
  }
  return result;
}

}  // namespace vocal
