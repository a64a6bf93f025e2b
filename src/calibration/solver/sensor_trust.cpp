#include "vocal/calibration/solver/sensor_trust.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <set>

#include "vocal/calibration/point_statistics.h"
#include "vocal/calibration/solver/hand_eye_calibration.h"
#include "vocal/core/errors.h"
#include "vocal/core/se3.h"

namespace vocal {

namespace {
bool scaleIsSignificant(const SensorCalibration& sensor, const SensorTrustOptions& trust) {
  return std::abs(sensor.disagreement_scale) > std::max(trust.max_scale, 3.0 * sensor.disagreement_scale_sigma);
}

// One compared view of a sensor: its pose and disagreement.
struct ComparedView {
  int pose = 0;
  double distance = 0.0;  // signed, m
  double angle = 0.0;     // rad (NaN for a view whose orientation was not measured)
  double range = 0.0;     // m
  bool off = false;       // over either threshold
};

std::vector<ComparedView> comparedViews(const CalibrationResult& result, int sensor, const SensorTrustOptions& trust) {
  std::vector<ComparedView> views;
  for (const ObservationResidual& o : result.observations) {
    if (o.sensor != sensor || std::isnan(o.plane_distance)) continue;
    ComparedView v{o.target_pose, o.plane_distance, o.plane_angle, o.range};
    v.off = std::abs(v.distance) > trust.max_distance || (!std::isnan(v.angle) && v.angle > trust.max_angle);
    views.push_back(v);
  }
  std::sort(views.begin(), views.end(), [](const ComparedView& a, const ComparedView& b) { return a.pose < b.pose; });
  return views;
}

// The likely cause of a disagreement, in words a user acts on (a change at one pose is found apart:
// placementChange).
std::string disagreementCause(const SensorSpec& spec, const SensorCalibration& sensor, const std::vector<ComparedView>& views,
                              const SensorTrustOptions& trust, int other_sources) {
  int off = 0;
  std::vector<double> angles;
  for (const ComparedView& v : views) {
    off += v.off;
    if (!std::isnan(v.angle)) angles.push_back(v.angle);
  }
  char text[520];
  const bool angles_agree = angles.empty() || median(angles) <= trust.max_angle;
  if (scaleIsSignificant(sensor, trust) && angles_agree) {  // a scale leaves each view's angle right
    std::snprintf(text, sizeof(text),
                  "the board's distance from it reads %.1f %% too %s (+-%.1f %%) against the others': a scale error - %s",
                  100.0 * std::abs(sensor.disagreement_scale), sensor.disagreement_scale > 0.0 ? "long" : "short",
                  100.0 * sensor.disagreement_scale_sigma,
                  spec.type == SensorType::kCamera ? "check its camera_info (focal length) and the target's square size in the rig YAML"
                                                   : "check the sensor's range calibration (depth units, range scale)");
    return text;
  }
  if (spec.type == SensorType::kLidar3d && !angles_agree && sensor.disagreement_distance <= trust.max_distance) {
    return "its board views stand where the others put the board but tilted against it: range biases that differ from ring to ring "
           "tilt each view (calibrate with its ring offsets, where it sees walls and floor all round, or check its ring offset verdict)";
  }
  if (spec.type != SensorType::kCamera && angles_agree && off * 10 >= static_cast<int>(views.size()) * 8) {
    std::vector<double> distances;
    int positive = 0;
    for (const ComparedView& v : views) distances.push_back(v.distance), positive += v.distance > 0.0;
    const int n = static_cast<int>(views.size());
    if (positive * 10 >= n * 9 || positive * 10 <= n) {
      const double offset = median(distances);
      std::snprintf(text, sizeof(text),
                    "its board is at the right angle but %.0f mm %s than the others put it at every pose: a range offset (the "
                    "sensor's own range calibration, dark squares reading long) or a wrong target size in the rig YAML",
                    1000.0 * std::abs(offset), offset > 0.0 ? "farther" : "nearer");
      return text;
    }
  }
  std::snprintf(text, sizeof(text),
                "%d of %zu still poses disagree, in no pattern: it moves between poses (is it on a joint - a pan-tilt head, an arm - "
                "or loosely mounted? a sensor on joints: name them in the rig, 'joints:' or 'urdf:', and its 'parent' link) or the segment taken for the board is not the board (set a crop_box, check the target size)%s",
                off, views.size(), other_sources <= 1 ? "; with only one other sensor to compare with, either of the two may be at fault" : "");
  return text;
}

// Plane-seeing sensors in the graph other than `sensor`.
int otherPlaneSources(const std::vector<SensorSpec>& sensors, const CalibrationResult& result, int sensor) {
  int count = 0;
  for (std::size_t s = 0; s < sensors.size(); ++s)
    count += static_cast<int>(s) != sensor && !result.sensors[s].isolated && sensors[s].type != SensorType::kLaser2d;
  return count;
}

// Where a sensor's placement changed once during the session (a bump): its pose fitted alone to the solved
// boards from the poses before and from those after each split. Found when the two parts place it beyond
// the thresholds apart and each part alone fits its views far better than one placement fits them all
// (their squared disagreements, in thresholds, at least four times smaller together): noise and poses
// that constrain a part poorly move the placements, not the fit. On an arm's session the boards are where
// the arm put them, within its repeatability, so "apart" is in the sensor's own sigmas (kMovedSigmas of the
// two parts' difference, HandEyeResult::kMovedSigmas, as the arm's graph judges a move) where those are
// under the thresholds.
struct PlacementChange {
  int pose = -1;  // the first pose after the change; -1: none
  double translation = 0.0, rotation = 0.0;  // between the two parts' placements
  double improvement = 0.0;                  // one placement's misfit over the two parts'
};

// The views' squared disagreement with their boards, in thresholds, with the sensor at `pose`.
double misfit(const std::vector<ViewInSensor>& views, const std::vector<const Plane*>& boards, std::size_t begin, std::size_t end,
              const Eigen::Isometry3d& pose, const SensorTrustOptions& trust) {
  double sum = 0.0;
  for (std::size_t i = begin; i < end; ++i) {
    const ViewDisagreement v = viewDisagreement(views[i], pose, *boards[i]);
    sum += std::pow(v.distance / trust.max_distance, 2) + (std::isnan(v.angle) ? 0.0 : std::pow(v.angle / trust.max_angle, 2));
  }
  return sum;
}

PlacementChange placementChange(const std::vector<SensorSpec>& sensors, const std::vector<TargetObservation>& observations,
                                const CalibrationResult& result, const CalibrationOptions& options, int sensor) {
  std::vector<const TargetObservation*> its;
  for (const TargetObservation& o : observations)
    if (o.sensor == sensor && result.board_planes.count(o.target_pose)) its.push_back(&o);
  std::sort(its.begin(), its.end(), [](const TargetObservation* a, const TargetObservation* b) { return a->target_pose < b->target_pose; });
  PlacementChange change;
  constexpr std::size_t kLeast = 4;  // poses in each part
  // Behind joints the sensor is somewhere else at every pose: no one placement to split.
  if (its.size() < 2 * kLeast || options.mounts.moves(sensor)) return change;
  const SensorTrustOptions& trust = options.trust;
  // Each view's centre and normal once, not once per split.
  std::vector<ViewInSensor> views;
  std::vector<const Plane*> boards;
  for (const TargetObservation* o : its) {
    TargetObservation moved;
    views.push_back(viewInSensor(result.viewAsSolved(*o, &moved), sensors[sensor].type));
    boards.push_back(&result.board_planes.at(o->target_pose));
  }
  const std::size_t n = its.size();
  const double whole = misfit(views, boards, 0, n, result.sensors[sensor].reference_from_sensor, trust);
  // The sensor's sigmas where an arm placed the boards (zero: judged by the thresholds alone).
  const Vector6d& sigma = result.sensors[sensor].standard_deviation;
  const bool by_sigmas = options.mounts.boardMoves() && sigma.head<3>().norm() > 0.0 && sigma.tail<3>().norm() > 0.0;
  double best = 0.0;
  for (std::size_t split = kLeast; split + kLeast <= n; ++split) {
    const std::optional<Eigen::Isometry3d> a = fitSensorToSolvedBoards(sensors, {its.begin(), its.begin() + split}, result, options);
    const std::optional<Eigen::Isometry3d> b = fitSensorToSolvedBoards(sensors, {its.begin() + split, its.end()}, result, options);
    if (!a || !b) continue;
    const double parts = misfit(views, boards, 0, split, *a, trust) + misfit(views, boards, split, n, *b, trust);
    const double improvement = whole / std::max(parts, 1e-12);
    const Eigen::Isometry3d apart = a->inverse() * *b;
    // Each part's sigma is the whole's times the root of its share; their difference's, both together.
    const double parts_sigma = std::sqrt(static_cast<double>(n) / split + static_cast<double>(n) / (n - split));
    const double limit_t = by_sigmas ? std::min(trust.max_distance, HandEyeResult::kMovedSigmas * parts_sigma * sigma.head<3>().norm()) : trust.max_distance;
    const double limit_r = by_sigmas ? std::min(trust.max_angle, HandEyeResult::kMovedSigmas * parts_sigma * sigma.tail<3>().norm()) : trust.max_angle;
    const double moved = std::max(apart.translation().norm() / limit_t, rotationAngle(apart) / limit_r);
    if (moved > 1.0 && improvement > 4.0 && improvement > best) {
      best = improvement;
      change.pose = its[split]->target_pose, change.translation = apart.translation().norm(), change.rotation = rotationAngle(apart);
      change.improvement = improvement;
    }
  }
  return change;
}
}  // namespace

double disagreementRatio(const SensorCalibration& sensor, const SensorTrustOptions& trust) {
  if (sensor.compared_poses == 0) return 0.0;
  const double ratio = std::max(sensor.disagreement_distance / trust.max_distance, sensor.disagreement_angle / trust.max_angle);
  return std::max(ratio, scaleIsSignificant(sensor, trust) ? std::abs(sensor.disagreement_scale) / trust.max_scale : 0.0);
}

CalibrationOptions withIsolatedSensors(CalibrationOptions options, const CalibrationResult& result) {
  if (result.view_scatter) options.view_scatter = result.view_scatter;
  options.isolated_sensors.clear();
  for (std::size_t s = 0; s < result.sensors.size(); ++s)
    if (result.sensors[s].isolated) options.isolated_sensors.push_back(static_cast<int>(s));
  return options;
}

CalibrationResult calibrateRigWithTrust(const std::vector<SensorSpec>& sensors, const std::vector<TargetObservation>& observations,
                                        const CalibrationOptions& options) {
  const SensorTrustOptions& trust = options.trust;
  const int sensor_count = static_cast<int>(sensors.size());
  // A sensor that never saw the target in a still pose is left out, the rest calibrated without it (the
  // reference cannot be: calibrateRig says so).
  std::vector<bool> unseen(sensor_count, true);
  for (const TargetObservation& o : observations)
    if (o.sensor >= 0 && o.sensor < sensor_count) unseen[o.sensor] = false;
  // So is a plane-seeing sensor that shares fewer still poses than place it with every other (a clock
  // off the others', a sensor that saw the board rarely): named, never the whole rig refused.
  std::vector<std::set<int>> poses(sensor_count);
  for (const TargetObservation& o : observations)
    if (o.sensor >= 0 && o.sensor < sensor_count) poses[o.sensor].insert(o.target_pose);
  std::vector<int> most_shared(sensor_count, 0);
  for (int s = 0; s < sensor_count; ++s) {
    // With the arm's base the rig frame the board is where the arm's poses put it: shared with every pose.
    if (options.baseIsRigFrame()) most_shared[s] = static_cast<int>(poses[s].size());
    for (int other = 0; other < sensor_count; ++other) {
      if (other == s || sensors[other].type == SensorType::kLaser2d) continue;
      int shared = 0;
      for (const int k : poses[s]) shared += poses[other].count(k);
      most_shared[s] = std::max(most_shared[s], shared);
    }
  }
  std::vector<bool> too_few(sensor_count, false);
  for (int s = 0; s < sensor_count; ++s)
    too_few[s] = !unseen[s] && s != options.reference_sensor && sensors[s].type != SensorType::kLaser2d && most_shared[s] < kLeastSharedPoses;
  CalibrationOptions seen_options = options;
  for (int s = 0; s < sensor_count; ++s)
    if ((unseen[s] || too_few[s]) && s != options.reference_sensor) seen_options.isolated_sensors.push_back(s);
  // And so is one whose views cannot place it (its boards' planes too close to parallel): named, the rest
  // calibrated without it.
  std::vector<std::string> unplaceable(sensor_count);
  CalibrationResult full;
  for (;;) {
    try {
      full = calibrateRig(sensors, observations, seen_options);
      break;
    } catch (const UnplaceableSensorError& e) {
      if (e.sensor == options.reference_sensor || e.sensor < 0 || e.sensor >= sensor_count || !unplaceable[e.sensor].empty()) throw;
      unplaceable[e.sensor] = e.what();
      seen_options.isolated_sensors.push_back(e.sensor);
    }
  }
  CalibrationResult result = full;
  std::vector<std::string> kept_in(sensor_count);  // per sensor: why it could not be taken out
  std::vector<PlacementChange> changes(sensor_count);
  bool taken_out = false;  // by a round below
  // Each round solves the rig once without each sensor still in it: a sensor is at fault when it
  // disagrees with the others solved without it (or moved part-way), and of those, the one whose
  // removal leaves the rest agreeing best is taken out. Judging each against the rest solved without it
  // matters: a sensor with many points (a lidar) pulls the boards to itself, and then the sensors that
  // are right seem to disagree.
  for (int round = 0; round < sensor_count; ++round) {
    int pick = -1;
    double pick_rest = 0.0, pick_own = 0.0;
    CalibrationResult pick_result;
    PlacementChange pick_change;
    for (int s = 0; s < sensor_count; ++s) {
      if (s == options.reference_sensor || result.sensors[s].isolated || !kept_in[s].empty()) continue;
      CalibrationOptions trial_options = withIsolatedSensors(seen_options, result);
      trial_options.isolated_sensors.push_back(s);
      CalibrationResult trial;
      try {
        trial = calibrateRig(sensors, observations, trial_options);
      } catch (const InputError& e) {
        kept_in[s] = std::string("it cannot be taken out of the graph (") + e.what() + ")";
        continue;
      }
      if (!trial.trusted) continue;
      const double own = disagreementRatio(trial.sensors[s], trust);
      const PlacementChange change = placementChange(sensors, observations, trial, options, s);
      if (own <= 1.0 && change.pose < 0) continue;
      double rest = 0.0;
      for (int other = 0; other < sensor_count; ++other) {
        if (other != s && other != options.reference_sensor && !trial.sensors[other].isolated)
          rest = std::max(rest, disagreementRatio(trial.sensors[other], trust));
      }
      // Where taking out either leaves the rest agreeing and both moved part-way, the one whose split fits
      // far better moved: the other's change can be the boards the moved one drags (a board tied to an arm's
      // tool follows a sensor with many points).
      const bool both_moved = pick >= 0 && rest <= 1.0 && pick_rest <= 1.0 && change.pose >= 0 && pick_change.pose >= 0;
      const bool better = both_moved ? change.improvement > pick_change.improvement : rest < pick_rest || (rest == pick_rest && own > pick_own);
      if (pick < 0 || better) {
        pick = s, pick_rest = rest, pick_own = own, pick_result = std::move(trial), pick_change = change;
      }
    }
    if (pick < 0) break;
    result = std::move(pick_result);
    changes[pick] = pick_change;
    taken_out = true;
  }
  // An arm's camera views were weighted by their scatter as the solve with every sensor measured it: a
  // sensor taken out (bumped, say) dragged the boards and widened it. Measured again without it (those
  // left out from the start, unseen or unplaceable, were out of that solve already).
  if (taken_out && result.view_scatter && result.view_scatter->translation > 0.0) {
    CalibrationOptions again = withIsolatedSensors(seen_options, result);
    again.view_scatter.reset();
    try {
      CalibrationResult measured = calibrateRig(sensors, observations, again);
      if (measured.trusted) result = std::move(measured);
    } catch (const InputError&) {
      // kept as the trials solved it
    }
  }
  for (int s = 0; s < sensor_count; ++s) {
    SensorCalibration& sensor = result.sensors[s];
    if (s == options.reference_sensor) continue;
    if (unseen[s]) {
      sensor.distrust = "it never saw the target in a still pose, so it is not calibrated (its pose in the result is a placeholder); "
                        "the others were solved without it";
      continue;
    }
    if (!unplaceable[s].empty()) {
      sensor.distrust = "its views of the board cannot place it (" + unplaceable[s] +
                        "), so it is not calibrated (its pose in the result is a placeholder); the others were solved without it";
      continue;
    }
    if (too_few[s]) {
      sensor.distrust = "it shares " + std::to_string(most_shared[s]) + " still pose" + (most_shared[s] == 1 ? "" : "s") +
                        " at most with another sensor, and " + std::to_string(kLeastSharedPoses) +
                        " are needed to place it, so it is not calibrated (its pose in the result is a placeholder); the others were "
                        "solved without it (is its clock off the others'? calibrate_rig --report prints each sensor's; or it saw the "
                        "board rarely: hold it in its view at more poses)";
      continue;
    }
    const std::string placement = !trust.isolate     ? std::string("; kept in the graph (isolation is off)")
                                  : sensor.isolated   ? std::string("; taken out of the graph, the others solved without it")
                                  : !kept_in[s].empty() ? "; " + kept_in[s]
                                                        : std::string("; kept in the graph (the rest agree no better without it)");
    if (changes[s].pose >= 0) {
      char line[400];
      std::snprintf(line, sizeof(line),
                    "its placement from the still poses before pose %d and from those after differ by %.0f mm / %.0f mrad, and each "
                    "part fits its own views %.0fx better than one placement fits all: it moved part-way through the session (bumped, or "
                    "a loose mount); fix it and record again",
                    changes[s].pose, 1000.0 * changes[s].translation, 1000.0 * changes[s].rotation, changes[s].improvement);
      sensor.distrust = line + placement;
      continue;
    }
    if (disagreementRatio(sensor, trust) <= 1.0) continue;  // never isolated: a full solve's ratio is not over
    char head[200];
    std::snprintf(head, sizeof(head), "its board views lie %.0f mm / %.0f mrad from where the other sensors put the board (median of %d poses)",
                  1000.0 * sensor.disagreement_distance, 1000.0 * sensor.disagreement_angle, sensor.compared_poses);
    sensor.distrust = std::string(head) + "; " +
                      disagreementCause(sensors[s], sensor, comparedViews(result, s, trust), trust, otherPlaneSources(sensors, result, s)) +
                      placement;
  }
  if (trust.isolate) return result;
  // Only named: the verdicts found with each sensor judged against the rest, on the solve with every sensor.
  CalibrationResult named = full;
  for (int s = 0; s < sensor_count; ++s) named.sensors[s].distrust = result.sensors[s].distrust;
  return named;
}

}  // namespace vocal
