#include "vocal/calibration/calibration_session.h"

#include <algorithm>
#include <limits>
#include <cmath>
#include <cstdio>
#include <map>

#include "vocal/calibration/extraction/pattern_observation.h"
#include "vocal/calibration/point_statistics.h"
#include "vocal/calibration/solver/pose_jackknife.h"
#include "vocal/calibration/solver/sensor_trust.h"
#include "vocal/core/errors.h"

namespace vocal {

namespace {
// A segment is background when it recurs in this share of the session's tenths: the board held at one
// pose stays in the one or two its pose lasted (four with three poses, the fewest that calibrate).
// (Seen again after a tenth without it is not enough: a board tilted only up and down comes back to
// within a few centimetres and degrees of an earlier pose's plane now and then.)
constexpr double kBackgroundRecurrence = 0.5;

std::vector<Eigen::Vector3f> toFloats(const std::vector<Eigen::Vector3d>& points) {
  std::vector<Eigen::Vector3f> out;
  out.reserve(points.size());
  for (const Eigen::Vector3d& p : points) out.push_back(p.cast<float>());
  return out;
}

// `sample` > 0: every k-th point, at most `sample` of them.
std::vector<Eigen::Vector3d> toDoubles(const std::vector<Eigen::Vector3f>& points, std::size_t sample = 0) {
  const std::size_t step = sample > 0 ? (points.size() + sample - 1) / sample : 1;
  std::vector<Eigen::Vector3d> out;
  out.reserve(points.size() / std::max<std::size_t>(step, 1) + 1);
  for (std::size_t i = 0; i < points.size(); i += step) out.push_back(points[i].cast<double>());
  return out;
}

// Points of a view enough to tell whether it moved (its plane within a fraction of the stillness bounds):
// what deciding what to keep associates, so that it costs a fraction of what is held.
constexpr std::size_t kPointsForStillness = 256;

// What a camera's observation holds for the solve.
std::size_t heldBytesOf(const TimedObservation& o) {
  return sizeof(o) + (o.points.size() + o.outline.size()) * sizeof(Eigen::Vector3d) + o.plane_measurements.size() * sizeof(PlaneMeasurement);
}

// The median angle between neighbouring returns of a scan given in beam order.
double beamSpacingOf(const std::vector<Eigen::Vector3d>& scan) {
  std::vector<double> steps;
  for (std::size_t i = 1; i < scan.size(); ++i) {
    const double step = std::abs(std::remainder(std::atan2(scan[i].y(), scan[i].x()) - std::atan2(scan[i - 1].y(), scan[i - 1].x()), 2 * M_PI));
    if (step > 1e-6) steps.push_back(step);
  }
  return median(std::move(steps));
}
}  // namespace

CalibrationSession::CalibrationSession(RigDescription rig, TargetExtractionOptions extraction, StillnessOptions stillness,
                                       RingOffsetOptions ring_offsets, SessionMemoryOptions memory)
    : rig_(std::move(rig)),
      extraction_(extraction),
      stillness_(stillness),
      counts_(rig_.sensors.size()),
      backgrounds_(rig_.sensors.size()),
      lidar_spacing_(rig_.sensors.size()),
      ring_offset_options_(ring_offsets),
      ring_offsets_(rig_.sensors.size()),
      ring_offset_choice_(rig_.sensors.size()),
      memory_options_(memory) {
  // Not given: half the rig's board's smaller side.
  if (!(stillness_.max_centre_spread > 0.0)) stillness_.max_centre_spread = 0.5 * std::min(rig_.target.width, rig_.target.height);
  arm_ = rig_.handEye();
  if (arm_)
    for (const std::vector<int>& chain : arm_->link_chains)
      if (!chain.empty() && std::find(still_links_.begin(), still_links_.end(), chain) == still_links_.end()) still_links_.push_back(chain);
  mounts_ = rig_.jointedMounts();
  joint_readings_.resize(rig_.joints.size());
  for (std::size_t j = 0; j < rig_.joints.size(); ++j) joint_index_[rig_.joints[j].name] = static_cast<int>(j);
}

int CalibrationSession::sensorIndex(const std::string& name) const {
  for (std::size_t i = 0; i < rig_.sensors.size(); ++i)
    if (rig_.sensors[i].spec.name == name) return static_cast<int>(i);
  return -1;
}

const RigSensorDescription& CalibrationSession::checkSensor(int sensor, SensorType expected, const char* data) const {
  if (sensor < 0 || sensor >= static_cast<int>(rig_.sensors.size())) {
    throw InputError("calibration session: sensor index " + std::to_string(sensor) + " is not one of the " +
                     std::to_string(rig_.sensors.size()) + " sensors of the rig");
  }
  const RigSensorDescription& description = rig_.sensors[sensor];
  if (description.spec.type != expected) {
    throw InputError("sensor '" + description.spec.name + "' is a " + sensorTypeName(description.spec.type) + " sensor: it takes no " +
                     data);
  }
  return description;
}

bool CalibrationSession::record(int sensor, double stamp, std::vector<Eigen::Vector3d> points, std::vector<PlaneMeasurement> planes) {
  ++counts_[sensor].received;
  if (points.empty()) return false;
  TimedObservation observation;
  observation.sensor = sensor;
  observation.stamp = stamp;
  observation.points = std::move(points);
  observation.plane_measurements = std::move(planes);
  const std::size_t bytes = heldBytesOf(observation);
  if (!roomFor(bytes)) {
    ++counts_[sensor].not_kept;
    return true;
  }
  ++counts_[sensor].target_found;
  held_bytes_ += bytes;
  observations_.push_back(std::move(observation));
  return true;
}

TargetExtractionOptions CalibrationSession::extractionFor(int sensor) const {
  TargetExtractionOptions options = extraction_;
  if (rig_.sensors[sensor].crop_box) options.crop_box = rig_.sensors[sensor].crop_box;
  return options;
}

bool CalibrationSession::recordRange(int sensor, double stamp, TargetSearch search) {
  ++counts_[sensor].received;
  const bool found = !search.candidates.empty();
  StoredRangeMessage message;
  message.sensor = sensor;
  message.stamp = stamp;
  for (const TargetCandidate& c : search.candidates) message.candidates.push_back({toFloats(c.points), toFloats(c.outline), c.mismatch});
  message.rejection = std::move(search.rejection);
  message.check = std::move(search.check);
  const std::size_t bytes = heldBytes(message);
  if (!roomFor(bytes)) {
    ++counts_[sensor].not_kept;
    return found;
  }
  std::vector<StaticBackground::Summary> summaries;
  for (const TargetCandidate& c : search.candidates) summaries.push_back(StaticBackground::summarise(c.points));
  backgrounds_[sensor].addMessage(summaries, search.surfaces);
  candidate_summaries_.push_back(std::move(summaries));
  chosen_.clear();
  held_bytes_ += bytes;
  range_messages_.push_back(std::move(message));
  return found;
}

std::size_t CalibrationSession::heldBytes(const StoredRangeMessage& message) {
  std::size_t bytes = sizeof(message) + message.rejection.capacity() + message.check.capacity();
  for (const StoredCandidate& c : message.candidates) bytes += sizeof(c) + (c.points.size() + c.outline.size()) * sizeof(Eigen::Vector3f);
  return bytes;
}

SessionMemory CalibrationSession::memory() const {
  SessionMemory memory;
  memory.held_mb = held_bytes_ / 1e6;
  memory.held_messages = observations_.size() + range_messages_.size();
  memory.let_go = let_go_;
  memory.full = full_;
  return memory;
}

std::string CalibrationSession::memorySummary() const {
  const SessionMemory m = memory();
  char line[400];
  int n = std::snprintf(line, sizeof(line), "%.1f MB of target data held in %zu messages", m.held_mb, m.held_messages);
  if (memory_options_.max_held_mb > 0.0) n += std::snprintf(line + n, sizeof(line) - n, " (budget %g MB)", memory_options_.max_held_mb);
  if (m.let_go > 0) {
    n += std::snprintf(line + n, sizeof(line) - n, ", %zu let go (settled and in no still pose, or past a pose's first %.1f s thinned to about %d)",
                       m.let_go, memory_options_.max_pose_seconds, memory_options_.max_pose_messages);
  }
  if (m.full) std::snprintf(line + n, sizeof(line) - n, "; FULL: later messages are counted, not kept");
  return line;
}

void CalibrationSession::addToolPose(double stamp, const Eigen::Isometry3d& reference_from_tool) {
  if (!arm_) throw InputError("tool pose: the rig has no sensor or target on a moving frame (no 'parent' other than " + rig_.reference_frame + ")");
  if (!std::isfinite(stamp) || !reference_from_tool.matrix().allFinite()) {
    throw InputError("tool pose of '" + arm_->tool_frame + "': not finite");
  }
  tool_poses_.push_back({stamp, reference_from_tool, {}});
}

void CalibrationSession::addJointState(double stamp, const std::vector<std::string>& names, const std::vector<double>& positions) {
  if (names.size() != positions.size()) {
    throw InputError("joint state: " + std::to_string(names.size()) + " names but " + std::to_string(positions.size()) + " positions");
  }
  if (!std::isfinite(stamp)) throw InputError("joint state: its stamp is not finite");
  // This message's reading of each of the rig's joints (NaN: not in it), kept in time order (a
  // recording's joint states may arrive slightly out of order).
  std::vector<double> read(rig_.joints.size(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t i = 0; i < names.size(); ++i) {
    const auto joint = joint_index_.find(names[i]);
    if (joint == joint_index_.end() || !std::isfinite(positions[i])) continue;
    read[joint->second] = positions[i];
    std::vector<JointReading>& own = joint_readings_[joint->second];
    const JointReading reading{stamp, positions[i]};
    if (own.empty() || own.back().stamp <= stamp) {
      own.push_back(reading);
    } else {
      own.insert(std::upper_bound(own.begin(), own.end(), stamp, [](double t, const JointReading& r) { return t < r.stamp; }), reading);
    }
  }
  // An arm's tool from its joints: its pose at this stamp when the message reads every joint of its chain.
  if (!arm_ || !arm_->from_joints || arm_->chain.empty()) return;
  std::vector<double> readings;
  for (const int j : arm_->chain) {
    const double position = rig_.joints[j].type == JointType::kFixed ? 0.0 : read[j];
    if (!std::isfinite(position)) return;
    readings.push_back(position);
  }
  FramePoseSample sample{stamp, chainPose(rig_.joints, arm_->chain, readings), {}};
  // Each other link a sensor sits on, from its joints' latest readings (a head's may come in messages of
  // their own): still spans are where those stand still too.
  for (const std::vector<int>& chain : still_links_) {
    std::vector<double> positions;
    for (const int j : chain) {
      const std::vector<JointReading>& own = joint_readings_[j];
      positions.push_back(rig_.joints[j].type == JointType::kFixed ? 0.0 : std::isfinite(read[j]) ? read[j] : own.empty() ? 0.0 : own.back().position);
    }
    sample.links.push_back(chainPose(rig_.joints, chain, positions));
  }
  tool_poses_.push_back(std::move(sample));
}

std::size_t CalibrationSession::jointReadings() const {
  std::size_t n = 0;
  for (const std::vector<JointReading>& own : joint_readings_) n += own.size();
  return n;
}

JointPositionCounts CalibrationSession::jointPositionCounts() const {
  JointPositionCounts counts;
  associate(timedObservations(), &counts);
  return counts;
}

std::vector<TargetObservation> CalibrationSession::associate(std::vector<TimedObservation> timed, JointPositionCounts* counts) const {
  applyClockOffsets(estimateClockOffsets(rig_.specs(), timed, rig_.reference_sensor, stillness_, clock_offset_options_), &timed);
  std::vector<TargetObservation> associated = associateStillTarget(rig_.specs(), std::move(timed), stillness_);
  if (mounts_.chains.empty()) return associated;
  return attachJointPositions(std::move(associated), mounts_, joint_readings_, rig_.specs(), joint_stillness_, counts);
}

HandEyeAssociation CalibrationSession::handEyeAssociation(const ToolStillnessOptions& options) const {
  if (!arm_) throw InputError("hand-eye association: the rig has no sensor or target on a moving frame");
  HandEyeAssociation association = associateToolStillness(tool_poses_, timedObservations(), options);
  if (!arm_->from_joints) return association;
  // Each still pose's joint readings: their median over its views' span (the nearest within 0.05 s of it).
  JointedMounts arm;
  arm.joints = rig_.joints;
  arm.chains = {arm_->readJoints()};  // not a chain: every joint read, as ArmJoints::read lists them
  std::vector<TargetObservation> spans(association.stations.size());
  for (std::size_t k = 0; k < spans.size(); ++k) {
    spans[k].target_pose = static_cast<int>(k);
    spans[k].first_stamp = association.stations[k].first_stamp, spans[k].last_stamp = association.stations[k].last_stamp;
  }
  // Not dropped for motion: the arm's still spans are the tool's own stillness already. A span no reading
  // covers keeps none (calibrateArmRig names it).
  JointStillnessOptions any_motion = joint_stillness_;
  any_motion.max_motion = any_motion.max_prismatic_motion = std::numeric_limits<double>::infinity();
  const SensorSpec tool{arm_->tool_frame, SensorType::kCamera, arm_->tool_frame};
  for (TargetObservation& read : attachJointPositions(std::move(spans), arm, joint_readings_, {tool}, any_motion, nullptr)) {
    association.stations[read.target_pose].joint_positions = std::move(read.joint_positions);
  }
  return association;
}

std::optional<ArmJoints> CalibrationSession::armJoints() const {
  if (!arm_ || !arm_->from_joints) return std::nullopt;
  ArmJoints arm;
  arm.joints = rig_.joints;
  arm.chain = arm_->chain;
  arm.read = arm_->readJoints();
  arm.tolerances = mounts_.tolerances;
  return arm;
}

HandEyeOptions CalibrationSession::handEyeOptions() const {
  HandEyeOptions options;
  options.arm_joints = armJoints();
  options.board_width = rig_.target.width;
  options.board_height = rig_.target.height;
  return options;
}

bool CalibrationSession::roomFor(std::size_t bytes) {
  const double budget = memory_options_.max_held_mb * 1e6;
  if (full_) return false;
  if (!(budget > 0.0) || held_bytes_ + bytes <= budget) return true;
  // An arm's still poses are the tool's (handEyeAssociation), not the target's: nothing to let go by.
  if (arm_) return !(full_ = true);
  letGoOfWhatNoStillPoseUses();
  // What the still poses keep fills the budget: compacting again would free next to nothing.
  full_ = held_bytes_ + bytes > 0.75 * budget;
  return !full_;
}

void CalibrationSession::letGoOfWhatNoStillPoseUses() {
  // The still pose of each message as calibrate() would associate them now (chosen_ holds until the end).
  const std::vector<int>& chosen = chosenCandidates();
  const std::vector<int> pose_of =
      stillPoseOfEachObservation(rig_.specs(), timedObservations(ringOffsets(), kPointsForStillness), stillness_);
  // Each held message's sensor, stamp and still pose, as timedObservations lists them: the cameras'
  // observations, then the range messages with a chosen candidate.
  struct Held {
    int sensor;
    double stamp;
    int pose;
  };
  std::vector<Held> held;
  std::size_t next = 0;  // into pose_of
  for (const TimedObservation& o : observations_) held.push_back({o.sensor, o.stamp, pose_of[next++]});
  for (std::size_t i = 0; i < range_messages_.size(); ++i)
    held.push_back({range_messages_[i].sensor, range_messages_[i].stamp, chosen[i] >= 0 ? pose_of[next++] : -1});

  // Kept: what is not settled yet, every message of a still pose not over yet, and of a pose that is
  // over, per sensor, its first max_pose_seconds thinned to about max_pose_messages spread over them:
  // its first and last kept (the span the association matches across sensors stays) and no two kept
  // ones further apart than a still run may bridge (the run stays one run).
  const double settled = newest_stamp_ - memory_options_.settle_seconds;
  std::map<int, double> pose_end;  // its last member's stamp
  for (const Held& h : held)
    if (h.pose >= 0) pose_end[h.pose] = std::max(pose_end[h.pose], h.stamp);
  std::vector<bool> keep(held.size(), false);
  std::map<std::pair<int, int>, std::vector<std::size_t>> members;  // per (pose, sensor), of poses that are over
  for (std::size_t h = 0; h < held.size(); ++h) {
    if (held[h].stamp >= settled || (held[h].pose >= 0 && pose_end[held[h].pose] >= settled)) keep[h] = true;
    else if (held[h].pose >= 0) members[{held[h].pose, held[h].sensor}].push_back(h);
  }
  const double spacing = std::min(stillness_.max_gap, memory_options_.max_pose_seconds / std::max(1, memory_options_.max_pose_messages));
  for (auto& [pose_and_sensor, group] : members) {
    std::sort(group.begin(), group.end(), [&](std::size_t a, std::size_t b) { return held[a].stamp < held[b].stamp; });
    const double until = held[group.front()].stamp + memory_options_.max_pose_seconds;
    while (held[group.back()].stamp > until) group.pop_back();
    double last_kept = held[group.front()].stamp;
    keep[group.front()] = keep[group.back()] = true;
    for (std::size_t k = 1; k + 1 < group.size(); ++k) {
      if (held[group[k + 1]].stamp - last_kept <= spacing) continue;  // the next one is still near enough
      keep[group[k]] = true;
      last_kept = held[group[k]].stamp;
    }
  }

  std::size_t h = 0;
  std::vector<TimedObservation> cameras;
  for (TimedObservation& o : observations_) {
    if (keep[h++]) cameras.push_back(std::move(o));
  }
  let_go_ += observations_.size() - cameras.size();
  observations_ = std::move(cameras);
  std::vector<StoredRangeMessage> messages;
  std::vector<std::vector<StaticBackground::Summary>> summaries;
  for (std::size_t i = 0; i < range_messages_.size(); ++i) {
    StoredRangeMessage& m = range_messages_[i];
    if (keep[h++]) {
      messages.push_back(std::move(m));
      summaries.push_back(std::move(candidate_summaries_[i]));
      continue;
    }
    // Its counts stay: counts() resolves only the messages still held.
    if (chosen[i] >= 0) ++counts_[m.sensor].target_found;
    else if (!m.candidates.empty()) ++counts_[m.sensor].only_background;
    ++let_go_;
  }
  range_messages_ = std::move(messages);
  candidate_summaries_ = std::move(summaries);
  chosen_.clear();
  held_bytes_ = 0;
  for (const TimedObservation& o : observations_) held_bytes_ += heldBytesOf(o);
  for (const StoredRangeMessage& m : range_messages_) held_bytes_ += heldBytes(m);
}

namespace {
// Each ring's elevation as its driver numbers them: the median of its returns' (rings of 20 or more).
std::vector<double> elevationsOfDriverRings(const std::vector<Eigen::Vector3d>& cloud, const std::vector<int>& rings) {
  std::map<int, std::vector<double>> by_ring;
  for (std::size_t i = 0; i < cloud.size() && i < rings.size(); ++i)
    by_ring[rings[i]].push_back(std::atan2(cloud[i].z(), cloud[i].head<2>().norm()));
  std::vector<double> elevations;
  for (auto& [ring, values] : by_ring)
    if (values.size() >= 20) elevations.push_back(median(std::move(values)));
  std::sort(elevations.begin(), elevations.end());
  return elevations;
}

// Rings found by clustering elevations (no ring field) beyond this are bands of a scanning lidar, not
// lasers: a multi-beam lidar without a ring field has at most 64 (128-beam ones publish the field).
constexpr std::size_t kMostRingsFound = 64;
// Returns a lidar's first cloud needs for its spacing: without a ring field, and with one.
constexpr std::size_t kLeastReturns = 1000, kLeastCroppedReturns = 200;

// Whether a lidar's rings are its lasers': the driver's, or few enough found by elevation.
bool ringsAreALidars(const ScanSpacing& spacing) { return spacing.rings_from_driver || spacing.rings.size() <= kMostRingsFound; }
}  // namespace

void CalibrationSession::prepareCloud(int sensor, const std::vector<Eigen::Vector3d>& cloud, const std::vector<int>& rings) {
  checkSensor(sensor, SensorType::kLidar3d, "point cloud");
  ScanSpacing& spacing = lidar_spacing_[sensor];
  // Enough returns to see the spacing: a whole scan, or a scan cropped around the board when the
  // driver's ring field says which ring each return is on.
  const bool ring_field = rings.size() == cloud.size();
  if (spacing.horizontal > 0.0 || cloud.size() < kLeastCroppedReturns) return;
  if (!ring_field && cloud.size() < kLeastReturns) {
    // Without a ring field, a scan cropped round the board shows its spacing only where its returns fall
    // into bands (a scanning laser's sweeps); else wait for a fuller cloud.
    spacing = estimateCroppedScanSpacing(cloud);
    return;
  }
  spacing = estimateScanSpacing(cloud);
  if (!ring_field && spacing.rings.empty()) {
    // A scan cropped round the board can hold a thousand returns and more, on too few per band for the
    // rings of a whole scan: its bands, where its returns fall into them.
    if (ScanSpacing banded = estimateCroppedScanSpacing(cloud); banded.horizontal > 0.0) spacing = std::move(banded);
  }
  // What the driver knows beats clustering elevations (a laser's own vertical offset spreads its
  // elevation at close range; a scanner without rings has none to cluster).
  if (rings.size() == cloud.size()) {
    std::vector<double> driver = elevationsOfDriverRings(cloud, rings);
    if (driver.size() >= 2) spacing.rings = std::move(driver), spacing.rings_from_driver = true;
  }
}

CalibrationSession::Extraction CalibrationSession::extractCloud(int sensor, const std::vector<Eigen::Vector3d>& cloud) const {
  const RigSensorDescription& description = checkSensor(sensor, SensorType::kLidar3d, "point cloud");
  const ScanSpacing& spacing = lidar_spacing_[sensor];
  if (!(spacing.horizontal > 0.0 && spacing.vertical > 0.0)) {
    throw InputError("sensor '" + description.spec.name + "': a cloud of " + std::to_string(cloud.size()) +
                     " points shows no ring or row spacing (a lidar's first cloud needs " + std::to_string(kLeastReturns) +
                     " points or more, " + std::to_string(kLeastCroppedReturns) + " with a ring field or its returns in elevation bands)");
  }
  // The bands a cropped scan shows move with the board: this cloud's own.
  ScanSpacing own = spacing;
  if (spacing.rings_per_cloud) own.rings = elevationBandsOf(cloud);
  Extraction extraction;
  extraction.search = findTargetInCloud(cloud, rig_.target.width, rig_.target.height, own, extractionFor(sensor));
  return extraction;
}

bool CalibrationSession::addCloud(int sensor, double stamp, const std::vector<Eigen::Vector3d>& cloud, const std::vector<int>& rings) {
  prepareCloud(sensor, cloud, rings);
  return take(sensor, stamp, extractCloud(sensor, cloud));
}

bool CalibrationSession::take(int sensor, double stamp, Extraction extraction) {
  // An index out of range: checkSensor throws, naming it.
  if (sensor < 0 || sensor >= static_cast<int>(rig_.sensors.size())) checkSensor(sensor, SensorType::kCamera, "data");
  newest_stamp_ = std::max(newest_stamp_, stamp);
  const SensorType type = rig_.sensors[sensor].spec.type;
  if (type == SensorType::kCamera) {
    counts_[sensor].views_with_corners_left_out += extraction.corners_left_out > 0;
    return record(sensor, stamp, std::move(extraction.points), std::move(extraction.planes));
  }
  TargetSearch& search = extraction.search;
  if (type == SensorType::kLidar3d) {
    std::optional<RingOffsetEstimator>& offsets = ring_offsets_[sensor];
    const ScanSpacing& spacing = lidar_spacing_[sensor];
    if (ring_offset_options_.enabled && !offsets && spacing.rings.size() >= 2 && ringsAreALidars(spacing) && !spacing.rings_per_cloud)
      offsets.emplace(spacing.rings, ring_offset_options_);
    if (offsets) {
      offsets->addPlanes(search.room_points);
      ring_offset_choice_[sensor].reset();  // decided on the clouds before this one
    }
    search.room_points.clear();  // tens of thousands of returns per cloud: not kept
  }
  return recordRange(sensor, stamp, std::move(search));
}

std::vector<std::optional<RingOffsets>> CalibrationSession::estimatedRingOffsets() const {
  std::vector<std::optional<RingOffsets>> offsets(ring_offsets_.size());
  for (std::size_t s = 0; s < offsets.size(); ++s) {
    if (ring_offsets_[s]) {
      offsets[s] = ring_offsets_[s]->solve();
    } else if (ring_offset_options_.enabled && lidar_spacing_[s].horizontal > 0.0 && lidar_spacing_[s].rings.size() < 2) {
      // A lidar whose clouds came without rings: say so rather than nothing.
      offsets[s].emplace();
      offsets[s]->verdict = "not estimated: its clouds show no rings (a solid-state or non-repeating scan pattern, and no ring field)";
    } else if (ring_offset_options_.enabled && lidar_spacing_[s].rings_per_cloud) {
      offsets[s].emplace();
      offsets[s]->verdict = "not estimated: its clouds are cropped round the board and carry no ring field, so no room's planes say"
                            " which return came from which laser";
    } else if (ring_offset_options_.enabled && lidar_spacing_[s].horizontal > 0.0 && !ringsAreALidars(lidar_spacing_[s])) {
      offsets[s].emplace();
      offsets[s]->verdict = "not estimated: its clouds carry no ring field and show " + std::to_string(lidar_spacing_[s].rings.size()) +
                            " elevation bands, more than a multi-beam lidar's " + std::to_string(kMostRingsFound) +
                            ": a scanning or rotating-head lidar, whose returns no laser's offset describes";
    }
  }
  return offsets;
}

std::vector<std::optional<RingOffsets>> CalibrationSession::ringOffsets() const {
  std::vector<std::optional<RingOffsets>> offsets = estimatedRingOffsets();
  for (std::size_t s = 0; s < offsets.size(); ++s) {
    if (!offsets[s] || !ring_offset_choice_[s]) continue;
    offsets[s]->applied = ring_offset_choice_[s]->applied;
    offsets[s]->verdict = ring_offset_choice_[s]->verdict;
    offsets[s]->warning = ring_offset_choice_[s]->warning;
  }
  return offsets;
}

std::vector<CalibrationSession::RingOffsetTrial> CalibrationSession::ringOffsetTrials() const {
  const std::vector<std::optional<RingOffsets>> estimated = estimatedRingOffsets();
  // Every lidar's estimated offsets applied, those beyond specification too: the same for each trial.
  std::vector<std::optional<RingOffsets>> offsets = estimated;
  for (std::optional<RingOffsets>& rings : offsets)
    if (rings && rings->estimated) rings->applied = true;
  std::vector<RingOffsetTrial> trials;
  std::optional<std::vector<TargetObservation>> with;
  for (std::size_t s = 0; s < offsets.size(); ++s) {
    if (!offsets[s] || !offsets[s]->estimated) continue;
    if (!with) with = associate(timedObservations(offsets));
    std::vector<std::optional<RingOffsets>> without = offsets;
    without[s]->applied = false;
    RingOffsetTrial trial;
    trial.sensor = static_cast<int>(s);
    trial.offsets = *estimated[s];
    trial.without = associate(timedObservations(without));
    trial.with = *with;
    trials.push_back(std::move(trial));
  }
  return trials;
}

void CalibrationSession::recordRingOffsetChoice(int sensor, RingOffsetChoice choice) {
  checkSensor(sensor, SensorType::kLidar3d, "ring offsets");
  ring_offset_choice_[sensor] = std::move(choice);
}

std::vector<std::optional<RingOffsets>> CalibrationSession::chooseRingOffsets(const CalibrationOptions& options) {
  for (RingOffsetTrial& trial : ringOffsetTrials())
    recordRingOffsetChoice(trial.sensor, judgeRingOffsets(rig_.specs(), trial, calibrationOptions(options)));
  return ringOffsets();
}

RingOffsetChoice judgeRingOffsets(const std::vector<SensorSpec>& sensors, const CalibrationSession::RingOffsetTrial& trial,
                                  const CalibrationOptions& options) {
  HeldOutFit without, with;
  try {
    without = heldOutBoardFit(sensors, trial.without, options, trial.sensor);
    with = heldOutBoardFit(sensors, trial.with, options, trial.sensor);
  } catch (const InputError&) {
    without.poses = with.poses = 0;  // the rig does not solve yet: nothing to predict with
  }
  const RingOffsets& offsets = trial.offsets;
  char line[640];
  if (without.poses == 0 || with.poses == 0) {
    if (!offsets.beyond_specification)
      return {true, "applied, unchecked: no still pose where another sensor saw the board to check them against", ""};
    std::snprintf(line, sizeof(line),
                  "refused, unchecked: the room's planes ask %s, beyond the +-%.0f mm a lidar's ranges are specified to, and no "
                  "still pose where another sensor saw the board can confirm it: the board's returns are taken as measured",
                  offsets.range().c_str(), 1000 * offsets.specification);
    return {false, line, ""};
  }
  const bool better = with.rms <= without.rms;
  // Beyond the specification the room must speak with one voice as well: a lidar whose ranges all read
  // long bends every flat surface alike, bent or cluttered walls each ask for their own (the real
  // office's VLP-16: 15 % of the planes' information within 15 mm of their median; a simulated lidar 5 cm
  // long, 97 %; the real OS1-64 lab, 99 % at +45 mm).
  constexpr double kLeastAgreement = 0.5;
  const bool room_agrees = offsets.planes_agreeing >= kLeastAgreement;
  const bool applied = better && (!offsets.beyond_specification || room_agrees);
  std::snprintf(line, sizeof(line),
                "%s: the board's held-out poses are predicted %s with them (%.1f mm rms, median %.1f mm, off the plane the "
                "other sensors put it in; %.1f mm rms, median %.1f mm, without; %d poses, each left out once)",
                applied ? "applied" : "refused", better ? "better" : "worse", 1000 * with.rms, 1000 * with.median, 1000 * without.rms,
                1000 * without.median, with.poses);
  RingOffsetChoice choice{applied, line, ""};
  if (!offsets.beyond_specification) return choice;
  char room[240];
  std::snprintf(room, sizeof(room), "%.0f %% of the room planes' say within +-%.0f mm of %+.0f mm", 100 * offsets.planes_agreeing,
                1000 * offsets.agreement, 1000 * offsets.common_offset);
  if (applied) {
    std::snprintf(line, sizeof(line),
                  "the room's planes (%s) and the board agree its ranges read %s too long, beyond the +-%.0f mm a lidar's ranges are "
                  "specified to: applied, but check the driver's calibration (its range offsets or calibration file, the "
                  "per-laser corrections of a Velodyne's calibration YAML, an Ouster's beam intrinsics)",
                  room, offsets.range().c_str(), 1000 * offsets.specification);
    choice.warning = line;
  } else {
    choice.verdict += "; the room's planes asked " + offsets.range() + ", beyond the lidar's specification, " +
                      (room_agrees ? std::string("with one voice (") + room + ")"
                                   : std::string("each their own (") + room + "): bent or cluttered walls, not the lidar");
  }
  return choice;
}

CalibrationSession::Extraction CalibrationSession::extractScan(int sensor, const std::vector<Eigen::Vector3d>& scan) const {
  checkSensor(sensor, SensorType::kLaser2d, "2D scan");
  const double beam_spacing = beamSpacingOf(scan);
  Extraction extraction;
  if (beam_spacing > 0.0) {
    extraction.search = findTargetInScan(scan, rig_.target.width, rig_.target.height, beam_spacing, extractionFor(sensor));
  } else {
    extraction.search.rejection = "the scan has fewer than 2 returns";
    extraction.search.check = "no segment";
  }
  return extraction;
}

bool CalibrationSession::addScan(int sensor, double stamp, const std::vector<Eigen::Vector3d>& scan) {
  return take(sensor, stamp, extractScan(sensor, scan));
}

CalibrationSession::Extraction CalibrationSession::extractDepth(int sensor, const DepthImage& depth, const PinholeCamera& camera) const {
  const RigSensorDescription& description = checkSensor(sensor, SensorType::kRgbd, "depth image");
  if (!depth.sameSize(camera.width, camera.height)) {
    throw InputError("sensor '" + description.spec.name + "': depth image is " + std::to_string(depth.width()) + "x" +
                     std::to_string(depth.height()) + " but its camera_info is " + std::to_string(camera.width) + "x" +
                     std::to_string(camera.height));
  }
  // Every second pixel: the plane fit gains nothing from more, extraction runs four times faster.
  constexpr int kStep = 2;
  std::vector<Eigen::Vector3d> cloud;
  for (int v = 0; v < depth.height(); v += kStep)
    for (int u = 0; u < depth.width(); u += kStep)
      if (isValidDepth(depth(u, v))) cloud.push_back(camera.backProject(u, v, depth(u, v)));
  const ScanSpacing spacing{kStep / camera.fx, kStep / camera.fy, ScanPattern::kPinhole};
  Extraction extraction;
  extraction.search = findTargetInCloud(cloud, rig_.target.width, rig_.target.height, spacing, extractionFor(sensor));
  return extraction;
}

bool CalibrationSession::addDepth(int sensor, double stamp, const DepthImage& depth, const PinholeCamera& camera) {
  return take(sensor, stamp, extractDepth(sensor, depth, camera));
}

CalibrationSession::Extraction CalibrationSession::extractImage(int sensor, const ColorImage& image, const PinholeCamera& camera,
                                                                const LensDistortion& distortion) const {
  const RigSensorDescription& description = checkSensor(sensor, SensorType::kCamera, "image");
  const char* name = description.spec.name.c_str();
  Extraction extraction;
  std::vector<Eigen::Vector2d> corners;
  try {
    corners = detectPattern(image, rig_.target.pattern, name);
  } catch (const InputError&) {
    return extraction;  // no board in view: normal while the target moves
  }
  PatternObservation seen = observePattern(corners, rig_.target.pattern, camera, name, distortion);
  extraction.points = std::move(seen.points);
  extraction.planes = {seen.plane};
  extraction.corners_left_out = static_cast<int>(seen.corners_left_out.size());
  return extraction;
}

bool CalibrationSession::addImage(int sensor, double stamp, const ColorImage& image, const PinholeCamera& camera,
                                  const LensDistortion& distortion) {
  return take(sensor, stamp, extractImage(sensor, image, camera, distortion));
}

const std::vector<int>& CalibrationSession::chosenCandidates() const {
  if (chosen_.size() == range_messages_.size()) return chosen_;
  chosen_.assign(range_messages_.size(), -1);
  for (std::size_t i = 0; i < range_messages_.size(); ++i) {
    const std::vector<StaticBackground::Summary>& candidates = candidate_summaries_[i];
    for (std::size_t c = 0; c < candidates.size() && chosen_[i] < 0; ++c) {
      if (backgrounds_[range_messages_[i].sensor].recurrence(candidates[c]) < kBackgroundRecurrence) chosen_[i] = static_cast<int>(c);
    }
  }
  return chosen_;
}

std::vector<RangeMessage> CalibrationSession::rangeMessages() const {
  const std::vector<int>& chosen = chosenCandidates();
  std::vector<RangeMessage> messages(range_messages_.size());
  for (std::size_t i = 0; i < messages.size(); ++i) {
    const StoredRangeMessage& stored = range_messages_[i];
    RangeMessage& m = messages[i];
    m.sensor = stored.sensor;
    m.stamp = stored.stamp;
    m.search.rejection = stored.rejection;
    m.search.check = stored.check;
    for (const StoredCandidate& c : stored.candidates) m.search.candidates.push_back({toDoubles(c.points), toDoubles(c.outline), c.mismatch});
    m.chosen = chosen[i];
    if (m.chosen >= 0) continue;
    const std::size_t found = m.search.candidates.size();
    m.rejection = found == 0 ? m.search.rejection
                             : std::to_string(found) + " board-shaped segment" + (found > 1 ? "s" : "") +
                                   ", all static background (in the same place in most of the sensor's messages)";
    m.check = found == 0 ? m.search.check : "static background";
  }
  return messages;
}

std::vector<TimedObservation> CalibrationSession::timedObservations() const { return timedObservations(ringOffsets()); }

std::vector<TimedObservation> CalibrationSession::timedObservations(const std::vector<std::optional<RingOffsets>>& offsets,
                                                                  std::size_t sample) const {
  const std::vector<int>& chosen = chosenCandidates();
  std::vector<TimedObservation> observations = observations_;
  for (std::size_t i = 0; i < range_messages_.size(); ++i) {
    if (chosen[i] < 0) continue;
    TimedObservation observation;
    observation.sensor = range_messages_[i].sensor;
    observation.stamp = range_messages_[i].stamp;
    observation.points = toDoubles(range_messages_[i].candidates[chosen[i]].points, sample);
    observation.outline = toDoubles(range_messages_[i].candidates[chosen[i]].outline);
    if (sample > 0) observation.point_count = range_messages_[i].candidates[chosen[i]].points.size();
    if (const std::optional<RingOffsets>& rings = offsets[observation.sensor]; rings && rings->applied) {
      for (Eigen::Vector3d& p : observation.points) p = rings->corrected(p);
      for (Eigen::Vector3d& p : observation.outline) p = rings->corrected(p);
    }
    observations.push_back(std::move(observation));
  }
  return observations;
}

std::vector<SensorDataCounts> CalibrationSession::counts() const {
  const std::vector<int>& chosen = chosenCandidates();
  std::vector<SensorDataCounts> counts = counts_;
  for (std::size_t i = 0; i < range_messages_.size(); ++i) {
    if (chosen[i] >= 0) ++counts[range_messages_[i].sensor].target_found;
    else if (!range_messages_[i].candidates.empty()) ++counts[range_messages_[i].sensor].only_background;
  }
  return counts;
}

std::vector<TargetObservation> CalibrationSession::associatedObservations() const { return associate(timedObservations()); }

std::vector<ClockOffset> CalibrationSession::clockOffsets() const {
  return estimateClockOffsets(rig_.specs(), timedObservations(), rig_.reference_sensor, stillness_, clock_offset_options_);
}

CalibrationResult CalibrationSession::calibrate(CalibrationOptions options) const {
  return calibrate(associatedObservations(), options);
}

CalibrationOptions CalibrationSession::calibrationOptions(CalibrationOptions options) const {
  options.reference_sensor = rig_.reference_sensor;
  options.reference_pose = *rig_.sensors[rig_.reference_sensor].pose;
  if (options.mounts.chains.empty()) {
    const JointTolerances tolerances = options.mounts.tolerances;  // the caller's, with the rig's joints and chains
    options.mounts = mounts_;
    options.mounts.tolerances = tolerances;
  }
  if (options.board_edges.enabled && !(options.board_edges.width > 0.0)) {
    // The rig's board: its pattern's columns run along its width (checkTargetDescription).
    options.board_edges.width = rig_.target.width;
    options.board_edges.height = rig_.target.height;
  }
  return options;
}

CalibrationResult CalibrationSession::calibrate(const std::vector<TargetObservation>& associated,
                                                CalibrationOptions options) const {
  // A sensor that saw the target but was never still with it: say why, rather than "never saw the target"
  // (the explanation re-reads every message: only when there is such a sensor).
  std::vector<bool> in_a_pose(rig_.sensors.size(), false);
  for (const TargetObservation& o : associated)
    if (o.sensor >= 0 && o.sensor < static_cast<int>(in_a_pose.size())) in_a_pose[o.sensor] = true;
  const std::vector<SensorDataCounts> seen = counts();
  bool never_still = false;
  for (std::size_t s = 0; s < seen.size(); ++s) never_still = never_still || (seen[s].target_found > 0 && !in_a_pose[s]);
  const std::string unassociated =
      never_still ? missingStillnessExplanation(rig_.specs(), timedObservations(), associated, stillness_) : std::string();
  const int reference = rig_.reference_sensor;
  const std::string& reference_name = rig_.sensors[reference].spec.name;
  if (!unassociated.empty() && unassociated.rfind("sensor '" + reference_name + "' ", 0) == 0) throw InputError("calibration: " + unassociated);
  CalibrationResult result = calibrateRigWithTrust(rig_.specs(), associated, calibrationOptions(options));
  // A sensor behind joints whose every view was dropped for its joints (moving, or never read): why.
  std::optional<JointPositionCounts> joints;  // counted once, when a sensor needs it (it associates every view again)
  for (std::size_t s = 0; s < rig_.sensors.size(); ++s) {
    if (!mounts_.jointed(static_cast<int>(s)) || in_a_pose[s] || seen[s].target_found == 0) continue;
    if (!joints) joints = jointPositionCounts();
    if (joints->kept + joints->moving + joints->unread == 0) continue;
    result.sensors[s].distrust = "its views were all dropped for its joints (" + std::to_string(joints->moving) + " while they moved, " +
                                 std::to_string(joints->unread) + " without a reading on " + rig_.joint_states_topic + "; first: " +
                                 joints->first + "); not calibrated, the others were solved without it";
  }
  for (std::size_t s = 0; s < rig_.sensors.size() && !unassociated.empty(); ++s) {
    if (unassociated.rfind("sensor '" + rig_.sensors[s].spec.name + "' ", 0) == 0 && result.sensors[s].distrust.find("for its joints") == std::string::npos) {
      result.sensors[s].distrust = "it " + unassociated.substr(unassociated.find("' ") + 2) + "; not calibrated, the others were solved without it";
    }
  }
  return result;
}

}  // namespace vocal
