#include "vocal/calibration/association/still_target_association.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "vocal/calibration/plane.h"
#include "vocal/calibration/point_statistics.h"
#include "vocal/core/errors.h"

namespace vocal {

namespace {
// What is compared between consecutive observations: a plane (n, d), or for a 2D laser its line as
// (direction in the scan plane, centroid).
struct Shape {
  Eigen::Vector3d direction;
  double offset = 0.0;
  Eigen::Vector3d centroid;
};

Shape shapeOf(const TimedObservation& o, SensorType type) {
  Shape shape;
  if (type == SensorType::kLaser2d) {
    const PrincipalAxes line = principalAxesOf(o.points);
    shape.centroid = line.centroid;
    shape.direction = line.axes.col(0);
  } else {
    shape.centroid = centroidOf(o.points);
    const Plane plane = fitPlane(o.points, "still-target association").plane;
    shape.direction = plane.normal;
    shape.offset = plane.offset;
  }
  return shape;
}

// Every observation's shape, fitted once.
std::vector<Shape> shapesOf(const std::vector<SensorSpec>& sensors, const std::vector<TimedObservation>& observations) {
  std::vector<Shape> shapes;
  shapes.reserve(observations.size());
  for (const TimedObservation& o : observations) shapes.push_back(shapeOf(o, sensors[o.sensor].type));
  return shapes;
}

// How far apart two observations' shapes are: the angle between them and their offsets' difference
// (a laser line's: its centroids' distance).
Eigen::Vector2d shapeDifference(const Shape& a, const Shape& b, SensorType type) {
  const double angle = std::acos(std::min(1.0, std::abs(a.direction.dot(b.direction))));
  return {angle, type == SensorType::kLaser2d ? (a.centroid - b.centroid).norm() : std::abs(a.offset - b.offset)};
}

// The largest difference still counted as unmoved, per sensor: the options' bounds, or a multiple of
// the sensor's own jitter (the median difference between consecutive observations, most of which are
// of a still target) where its noise, mixed pixels and hands on the board make that larger.
std::vector<Eigen::Vector2d> stillnessBounds(const std::vector<SensorSpec>& sensors, const std::vector<TimedObservation>& sorted,
                                             const std::vector<Shape>& shapes, const StillnessOptions& options) {
  std::vector<std::vector<double>> angles(sensors.size()), offsets(sensors.size());
  for (std::size_t i = 1; i < sorted.size(); ++i) {
    if (sorted[i].sensor != sorted[i - 1].sensor) continue;
    const Eigen::Vector2d d = shapeDifference(shapes[i - 1], shapes[i], sensors[sorted[i].sensor].type);
    angles[sorted[i].sensor].push_back(d[0]);
    offsets[sorted[i].sensor].push_back(d[1]);
  }
  std::vector<Eigen::Vector2d> bounds;
  for (std::size_t s = 0; s < sensors.size(); ++s) {
    bounds.emplace_back(std::max(options.max_angle, options.jitter_multiple * median(angles[s])),
                        std::max(options.max_offset, options.jitter_multiple * median(offsets[s])));
  }
  return bounds;
}

// The members (indices into sorted) whose centroid lies within `spread` of the centroid of the member
// with the most points (the fullest view of the board: a torso taken where the board was missed has fewer).
std::vector<std::size_t> membersNearTheFullestView(const std::vector<std::size_t>& members, const std::vector<TimedObservation>& sorted,
                                                   const std::vector<Shape>& shapes, double spread) {
  const auto count = [&](std::size_t i) { return sorted[i].point_count > 0 ? sorted[i].point_count : sorted[i].points.size(); };
  const std::size_t fullest =
      *std::max_element(members.begin(), members.end(), [&](std::size_t a, std::size_t b) { return count(a) < count(b); });
  std::vector<std::size_t> near;
  for (std::size_t member : members)
    if ((shapes[member].centroid - shapes[fullest].centroid).norm() <= spread) near.push_back(member);
  return near;
}

struct StillRun {
  int sensor;
  double begin, end;
  std::vector<std::size_t> members;  // indices into the sorted observations
};

void checkSensorIndices(const std::vector<SensorSpec>& sensors, const std::vector<TimedObservation>& observations) {
  for (const TimedObservation& o : observations) {
    if (o.sensor < 0 || o.sensor >= static_cast<int>(sensors.size())) {
      throw InputError("still-target association: an observation names sensor index " + std::to_string(o.sensor) +
                       " of " + std::to_string(sensors.size()));
    }
  }
}

// By sensor, then time; `order` (if given) receives each sorted observation's index in the input.
void sortBySensorAndTime(std::vector<TimedObservation>* observations, std::vector<std::size_t>* order = nullptr) {
  std::vector<std::size_t> indices(observations->size());
  for (std::size_t i = 0; i < indices.size(); ++i) indices[i] = i;
  const std::vector<TimedObservation>& in = *observations;
  std::stable_sort(indices.begin(), indices.end(), [&](std::size_t a, std::size_t b) {
    return in[a].sensor != in[b].sensor ? in[a].sensor < in[b].sensor : in[a].stamp < in[b].stamp;
  });
  std::vector<TimedObservation> sorted;
  sorted.reserve(indices.size());
  for (std::size_t i : indices) sorted.push_back(std::move((*observations)[i]));
  *observations = std::move(sorted);
  if (order) *order = std::move(indices);
}

// The median spacing of each sensor's observations (0 with fewer than two), from observations sorted
// by sensor and time.
std::vector<double> medianPeriods(std::size_t sensors, const std::vector<TimedObservation>& sorted) {
  std::vector<std::vector<double>> spacing(sensors);
  for (std::size_t i = 1; i < sorted.size(); ++i)
    if (sorted[i].sensor == sorted[i - 1].sensor) spacing[sorted[i].sensor].push_back(sorted[i].stamp - sorted[i - 1].stamp);
  std::vector<double> periods;
  for (std::vector<double>& d : spacing) periods.push_back(median(std::move(d)));
  return periods;
}

double allowedGap(double median_period, const StillnessOptions& options) {
  return std::max(options.max_gap, options.gap_periods * median_period);
}

// What cutting runs takes from sorted observations, computed once (a plane fit per observation): each
// observation's shape, each sensor's median message period and stillness bound.
struct RunInputs {
  std::vector<Shape> shapes;
  std::vector<double> periods;
  std::vector<Eigen::Vector2d> bounds;
};

RunInputs runInputsOf(const std::vector<SensorSpec>& sensors, const std::vector<TimedObservation>& sorted,
                      const StillnessOptions& options) {
  RunInputs inputs;
  inputs.shapes = shapesOf(sensors, sorted);
  inputs.periods = medianPeriods(sensors.size(), sorted);
  inputs.bounds = stillnessBounds(sensors, sorted, inputs.shapes, options);
  return inputs;
}

// Every run of consecutive unmoved observations per sensor (short ones too), from sorted observations.
std::vector<StillRun> cutRuns(const std::vector<SensorSpec>& sensors, const std::vector<TimedObservation>& sorted,
                              const RunInputs& inputs, const StillnessOptions& options) {
  std::vector<StillRun> runs;
  for (std::size_t i = 0; i < sorted.size();) {
    const int sensor = sorted[i].sensor;
    const SensorType type = sensors[sensor].type;
    const double gap = allowedGap(inputs.periods[sensor], options);
    const Eigen::Vector2d& bound = inputs.bounds[sensor];
    StillRun run{sensor, sorted[i].stamp, sorted[i].stamp, {i}};
    // A message unlike the run between ones like it (an arm across the board, the person's chest
    // taken with it) is passed over, not the run's end: the run goes on while a message like it comes
    // within the gap. The next run starts after its last member.
    std::size_t next = i + 1;
    for (std::size_t j = i + 1; j < sorted.size() && sorted[j].sensor == sensor && sorted[j].stamp - run.end <= gap; ++j) {
      const Eigen::Vector2d moved = shapeDifference(inputs.shapes[i], inputs.shapes[j], type);
      if (moved[0] >= bound[0] || moved[1] >= bound[1]) continue;
      run.end = sorted[j].stamp;
      run.members.push_back(j);
      next = j + 1;
    }
    runs.push_back(std::move(run));
    i = next;
  }
  return runs;
}
}  // namespace

namespace {
// One sensor's messages at one still pose: indices into the sorted observations, in time order.
struct PoseMembers {
  int sensor;
  int pose;
  std::vector<std::size_t> members;
};

// What associateStillTarget pools, per sensor and still pose, from observations sorted by sensor and time.
std::vector<PoseMembers> stillMembers(const std::vector<SensorSpec>& sensors, const std::vector<TimedObservation>& observations,
                                      const StillnessOptions& options) {
  // Still runs per sensor: those that lasted.
  const RunInputs inputs = runInputsOf(sensors, observations, options);
  std::vector<StillRun> runs = cutRuns(sensors, observations, inputs, options);
  runs.erase(std::remove_if(runs.begin(), runs.end(),
                            [&](const StillRun& run) { return run.end - run.begin < options.min_duration; }),
             runs.end());

  // Periods: runs of plane-seeing sensors that overlap in time; 2D laser runs join the period they fall in.
  std::vector<std::pair<double, double>> periods;
  std::vector<const StillRun*> plane_runs;
  for (const StillRun& run : runs)
    if (sensors[run.sensor].type != SensorType::kLaser2d) plane_runs.push_back(&run);
  std::sort(plane_runs.begin(), plane_runs.end(), [](const StillRun* a, const StillRun* b) { return a->begin < b->begin; });
  for (const StillRun* run : plane_runs) {
    if (!periods.empty() && run->begin <= periods.back().second) {
      periods.back().second = std::max(periods.back().second, run->end);
    } else {
      periods.emplace_back(run->begin, run->end);
    }
  }

  // One run per sensor and period: its longest.
  std::vector<std::vector<const StillRun*>> chosen(periods.size(), std::vector<const StillRun*>(sensors.size(), nullptr));
  for (const StillRun& run : runs) {
    const double middle = 0.5 * (run.begin + run.end);
    for (std::size_t k = 0; k < periods.size(); ++k) {
      if (middle < periods[k].first || middle > periods[k].second) continue;
      const StillRun*& longest = chosen[k][run.sensor];
      if (!longest || run.end - run.begin > longest->end - longest->begin) longest = &run;
      break;
    }
  }
  // A period only one sensor held still for relates no sensor to another: a sensor whose noise makes its
  // stillness bound wide can take a slow move for a still run.
  const auto seen_by_one = [](const std::vector<const StillRun*>& by_sensor) {
    return std::count_if(by_sensor.begin(), by_sensor.end(), [](const StillRun* run) { return run != nullptr; }) < 2;
  };
  chosen.erase(std::remove_if(chosen.begin(), chosen.end(), seen_by_one), chosen.end());
  // A slow sensor's run can take in a message on either side where the target was nearly still (at
  // 3 Hz the next message comes 0.33 s into the move): each run keeps the messages within half its own
  // period of the span the other sensors' runs agree on (the medians of their first and last stamps).
  std::vector<PoseMembers> still;
  for (std::size_t k = 0; k < chosen.size(); ++k) {
    for (std::size_t s = 0; s < sensors.size(); ++s) {
      const StillRun* run = chosen[k][s];
      if (!run) continue;
      std::vector<double> begins, ends;
      for (std::size_t other = 0; other < sensors.size(); ++other) {
        if (other == s || !chosen[k][other]) continue;
        begins.push_back(chosen[k][other]->begin);
        ends.push_back(chosen[k][other]->end);
      }
      double from = run->begin, to = run->end;
      if (begins.size() >= 2) {
        from = std::max(from, median(begins) - 0.5 * inputs.periods[s]);
        to = std::min(to, median(ends) + 0.5 * inputs.periods[s]);
      }
      std::vector<std::size_t> members;
      for (std::size_t member : run->members)
        if (observations[member].stamp >= from && observations[member].stamp <= to) members.push_back(member);
      if (members.empty()) members = run->members;  // the others disagree with it entirely: keep it whole
      if (options.max_centre_spread > 0.0) {
        members = membersNearTheFullestView(members, observations, inputs.shapes, options.max_centre_spread);
      }
      still.push_back({static_cast<int>(s), static_cast<int>(k), std::move(members)});
    }
  }
  return still;
}
}  // namespace

std::vector<TargetObservation> associateStillTarget(const std::vector<SensorSpec>& sensors,
                                                    std::vector<TimedObservation> observations,
                                                    const StillnessOptions& options) {
  checkSensorIndices(sensors, observations);
  sortBySensorAndTime(&observations);
  std::vector<TargetObservation> associated;
  for (const PoseMembers& pose : stillMembers(sensors, observations, options)) {
    TargetObservation observation;
    observation.sensor = pose.sensor;
    observation.target_pose = pose.pose;
    observation.first_stamp = observations[pose.members.front()].stamp;
    observation.last_stamp = observations[pose.members.back()].stamp;
    // Views of a still pattern have independent pixel noise: each keeps its own plane measurement.
    for (std::size_t i : pose.members) {
      const TimedObservation& member = observations[i];
      observation.points.insert(observation.points.end(), member.points.begin(), member.points.end());
      observation.outline.insert(observation.outline.end(), member.outline.begin(), member.outline.end());
      observation.plane_measurements.insert(observation.plane_measurements.end(), member.plane_measurements.begin(),
                                            member.plane_measurements.end());
    }
    associated.push_back(std::move(observation));
  }
  return associated;
}

std::vector<int> stillPoseOfEachObservation(const std::vector<SensorSpec>& sensors, std::vector<TimedObservation> observations,
                                            const StillnessOptions& options) {
  checkSensorIndices(sensors, observations);
  std::vector<std::size_t> input_index;
  sortBySensorAndTime(&observations, &input_index);
  std::vector<int> pose_of(observations.size(), -1);
  for (const PoseMembers& pose : stillMembers(sensors, observations, options))
    for (std::size_t i : pose.members) pose_of[input_index[i]] = pose.pose;
  return pose_of;
}

std::vector<StillSpan> stillSpans(const std::vector<SensorSpec>& sensors, std::vector<TimedObservation> observations,
                                  const StillnessOptions& options) {
  checkSensorIndices(sensors, observations);
  sortBySensorAndTime(&observations);
  std::vector<StillSpan> spans;
  for (const StillRun& run : cutRuns(sensors, observations, runInputsOf(sensors, observations, options), options))
    if (run.end - run.begin >= options.min_duration) spans.push_back({run.sensor, run.begin, run.end});
  return spans;
}

std::string missingStillnessExplanation(const std::vector<SensorSpec>& sensors,
                                        const std::vector<TimedObservation>& observations,
                                        const std::vector<TargetObservation>& associated,
                                        const StillnessOptions& options) {
  checkSensorIndices(sensors, observations);
  std::vector<int> seen(sensors.size(), 0);
  for (const TimedObservation& o : observations) ++seen[o.sensor];
  std::vector<bool> associated_sensor(sensors.size(), false);
  for (const TargetObservation& o : associated)
    if (o.sensor >= 0 && o.sensor < static_cast<int>(sensors.size())) associated_sensor[o.sensor] = true;
  std::size_t missing = 0;
  while (missing < sensors.size() && (seen[missing] == 0 || associated_sensor[missing])) ++missing;
  if (missing == sensors.size()) return "";

  // Only now the runs again (plane fits per observation), for the sensor that has none.
  std::vector<TimedObservation> sorted = observations;
  sortBySensorAndTime(&sorted);
  const RunInputs inputs = runInputsOf(sensors, sorted, options);
  const double period = inputs.periods[missing];
  const Eigen::Vector2d& bound = inputs.bounds[missing];  // jitter included
  int kept = 0;
  double longest = 0.0;
  for (const StillRun& run : cutRuns(sensors, sorted, inputs, options)) {
    if (run.sensor != static_cast<int>(missing)) continue;
    longest = std::max(longest, run.end - run.begin);
    kept += run.end - run.begin >= options.min_duration;
  }
  std::ostringstream why;
  why << std::setprecision(3) << "sensor '" << sensors[missing].name << "' saw the target in " << seen[missing]
      << " observations but in no still target pose: ";
  if (kept > 0) {
    why << "its " << kept << " still runs overlap no still period of a plane-seeing sensor";
  } else {
    why << "its observations are " << period << " s apart (median); a still run allows gaps up to "
        << allowedGap(period, options) << " s and must last " << options.min_duration
        << " s with the target moving less than " << bound[0] << " rad and " << bound[1]
        << " m (its longest lasted " << longest << " s)";
  }
  return why.str();
}

}  // namespace vocal
