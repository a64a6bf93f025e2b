#include "vocal/calibration/solver/pose_jackknife.h"

#include <cmath>
#include <cstdio>
#include <optional>
#include <set>
#include <string>

#include "vocal/calibration/point_statistics.h"
#include "vocal/calibration/solver/sensor_trust.h"
#include "vocal/core/errors.h"

namespace vocal {

namespace {
// The rig solved from every observation but those of target pose `left_out`; none when that fails or is
// not trusted (a sensor seen only at that pose, or its remaining planes cannot fix it).
std::optional<CalibrationResult> solveWithoutPose(const std::vector<SensorSpec>& sensors,
                                                  const std::vector<TargetObservation>& observations,
                                                  const CalibrationOptions& options, int left_out) {
  std::vector<TargetObservation> rest;
  for (const TargetObservation& o : observations)
    if (o.target_pose != left_out) rest.push_back(o);
  try {
    CalibrationResult result = calibrateRig(sensors, rest, options);
    if (result.trusted) return result;
  } catch (const InputError&) {
  }
  return std::nullopt;
}
}  // namespace

PoseJackknife jackknifeOverPoses(const std::vector<SensorSpec>& sensors, const std::vector<TargetObservation>& observations,
                                 const CalibrationOptions& options, const CalibrationResult& full) {
  std::set<int> poses;
  for (const TargetObservation& o : observations) poses.insert(o.target_pose);
  PoseJackknife jackknife;
  jackknife.poses = static_cast<int>(poses.size());
  // Per re-solve and sensor: how far it moved from the full solution (translation, rotation vector in the rig frame).
  std::vector<std::vector<Vector6d>> moves;
  const CalibrationOptions same_graph = withIsolatedSensors(options, full);  // the sensors `full` kept out stay out
  for (const int left_out : poses) {
    const std::optional<CalibrationResult> result = solveWithoutPose(sensors, observations, same_graph, left_out);
    if (!result) continue;
    std::vector<Vector6d> move(sensors.size());
    const auto moved = [](const Eigen::Isometry3d& all, const Eigen::Isometry3d& without) {
      Vector6d m;
      m.head<3>() = without.translation() - all.translation();
      const Eigen::AngleAxisd turn(without.rotation() * all.rotation().transpose());
      m.tail<3>() = turn.angle() * turn.axis();
      return m;
    };
    for (std::size_t s = 0; s < sensors.size(); ++s) {
      move[s] = moved(full.sensors[s].reference_from_sensor, result->sensors[s].reference_from_sensor);
      if (!full.mounts.moves(static_cast<int>(s))) continue;
      // Behind joints the mount and the offsets trade off; what matters is where the sensor is: its move in
      // the rig frame at the still pose where it moved most.
      move[s].setZero();
      for (const TargetObservation& o : observations) {
        if (o.sensor != static_cast<int>(s)) continue;
        const Vector6d at = moved(full.rigFromSensorAt(o), result->rigFromSensorAt(o));
        if (at.head<3>().norm() + at.tail<3>().norm() > move[s].head<3>().norm() + move[s].tail<3>().norm()) move[s] = at;
      }
    }
    moves.push_back(std::move(move));
  }
  jackknife.solved = static_cast<int>(moves.size());
  if (jackknife.solved < 3) {
    throw InputError("pose jackknife: only " + std::to_string(jackknife.solved) + " of " + std::to_string(jackknife.poses) +
                     " re-solves without one target pose succeeded; at least 3 are needed");
  }
  // Jackknife variance: (m - 1) / m times the sum of squared deviations from the replicates' mean.
  const double m = jackknife.solved;
  for (std::size_t s = 0; s < sensors.size(); ++s) {
    Vector6d mean = Vector6d::Zero();
    for (const std::vector<Vector6d>& move : moves) mean += move[s] / m;
    Vector6d variance = Vector6d::Zero();
    for (const std::vector<Vector6d>& move : moves) variance += (move[s] - mean).cwiseAbs2();
    jackknife.standard_deviation.push_back(((m - 1.0) / m * variance).cwiseSqrt());
  }
  return jackknife;
}

HeldOutFit heldOutBoardFit(const std::vector<SensorSpec>& sensors, const std::vector<TargetObservation>& observations,
                           const CalibrationOptions& options, int sensor) {
  std::set<int> poses;
  for (const TargetObservation& o : observations)
    if (o.sensor == sensor) poses.insert(o.target_pose);
  HeldOutFit fit;
  double squares = 0.0;
  std::size_t points = 0;
  std::vector<double> distances;
  for (const int held_out : poses) {
    std::vector<const TargetObservation*> others;
    const TargetObservation* own = nullptr;
    for (const TargetObservation& o : observations) {
      if (o.target_pose != held_out) continue;
      if (o.sensor == sensor) own = &o;
      else others.push_back(&o);
    }
    // A 2D laser's points are a line: they fix no plane by themselves.
    bool plane_seen = false;
    for (const TargetObservation* o : others) plane_seen = plane_seen || sensors[o->sensor].type != SensorType::kLaser2d;
    if (!plane_seen) continue;
    const std::optional<CalibrationResult> result = solveWithoutPose(sensors, observations, options, held_out);
    if (!result) continue;
    std::vector<Eigen::Vector3d> board;
    for (const TargetObservation* o : others)
      for (const Eigen::Vector3d& p : o->points) board.push_back(result->rigFromSensorAt(*o) * p);
    if (board.size() < 3) continue;
    const PrincipalAxes plane = principalAxesOf(board);
    const Eigen::Isometry3d placed = result->rigFromSensorAt(*own);
    for (const Eigen::Vector3d& p : own->points) {
      const double distance = plane.axes.col(2).dot(placed * p - plane.centroid);
      squares += distance * distance;
      distances.push_back(std::abs(distance));
    }
    points += own->points.size();
    ++fit.poses;
  }
  if (points > 0) fit.rms = std::sqrt(squares / static_cast<double>(points));
  if (!distances.empty()) fit.median = median(distances);
  return fit;
}

namespace {
// Why a sensor of this type moves between re-solves, or which poses would pin it down.
const char* adviceFor(SensorType type) {
  switch (type) {
    case SensorType::kLidar3d:
      return "a 3D lidar's per-ring range biases (its intrinsic calibration, the driver's calibration file) tilt "
             "every plane it sees alike, which moves its height and pitch together and no choice of poses undoes: "
             "calibrate where it sees walls and floor around it, which its ring offsets are estimated from";
    case SensorType::kLaser2d:
      return "tilt the target further and at more heights: a 2D laser's height, pitch and roll come only from where "
             "its one line crosses tilted targets";
    default:
      return "hold the target at more poses, tilts and distances";
  }
}
}  // namespace

bool spreadIsOver(const Vector6d& spread, const SpreadTolerance& tolerance) {
  return spread.head<3>().norm() > tolerance.translation || spread.tail<3>().norm() > tolerance.rotation;
}

std::vector<std::string> spreadOverTolerance(const PoseJackknife& jackknife, const std::vector<SensorSpec>& sensors,
                                             const SpreadTolerance& tolerance) {
  static const char* const kAxis[] = {"x", "y", "z"};
  std::vector<std::string> lines;
  for (std::size_t s = 0; s < sensors.size() && s < jackknife.standard_deviation.size(); ++s) {
    const Vector6d& spread = jackknife.standard_deviation[s];
    if (!spreadIsOver(spread, tolerance)) continue;
    const double translation = spread.head<3>().norm(), rotation = spread.tail<3>().norm();
    Eigen::Index along = 0, about = 0;
    spread.head<3>().maxCoeff(&along);
    spread.tail<3>().maxCoeff(&about);
    char line[256];
    std::snprintf(line, sizeof(line),
                  "sensor '%s' moves %.1f mm / %.1f mrad between re-solves without one pose (tolerance %.1f mm / %.1f mrad), "
                  "most along the rig's %s and about its %s: its result may be off by as much; ",
                  sensors[s].name.c_str(), 1000 * translation, 1000 * rotation, 1000 * tolerance.translation,
                  1000 * tolerance.rotation, kAxis[along], kAxis[about]);
    lines.push_back(line + std::string(adviceFor(sensors[s].type)));
  }
  return lines;
}

}  // namespace vocal
