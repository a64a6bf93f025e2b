#include "vocal/calibration/pose_jackknife.h"

#include <set>
#include <string>

#include "vocal/core/errors.h"

namespace vocal {

PoseJackknife jackknifeOverPoses(const std::vector<SensorSpec>& sensors, const std::vector<TargetObservation>& observations,
                                 const CalibrationOptions& options, const CalibrationResult& full) {
  std::set<int> poses;
  for (const TargetObservation& o : observations) poses.insert(o.target_pose);
  PoseJackknife jackknife;
  jackknife.poses = static_cast<int>(poses.size());
  // Per re-solve and sensor: how far it moved from the full solution (translation, rotation vector in the rig frame).
  std::vector<std::vector<Vector6d>> moves;
  for (const int left_out : poses) {
    std::vector<TargetObservation> rest;
    for (const TargetObservation& o : observations)
      if (o.target_pose != left_out) rest.push_back(o);
    CalibrationResult result;
    try {
      result = calibrateRig(sensors, rest, options);
    } catch (const InputError&) {
      continue;  // a sensor seen only at this pose, or its remaining planes cannot fix it
    }
    if (!result.trusted) continue;
    std::vector<Vector6d> move(sensors.size());
    for (std::size_t s = 0; s < sensors.size(); ++s) {
      const Eigen::Isometry3d& all = full.sensors[s].reference_from_sensor;
      const Eigen::Isometry3d& without = result.sensors[s].reference_from_sensor;
      move[s].head<3>() = without.translation() - all.translation();
      const Eigen::AngleAxisd turn(without.rotation() * all.rotation().transpose());
      move[s].tail<3>() = turn.angle() * turn.axis();
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

}  // namespace vocal
