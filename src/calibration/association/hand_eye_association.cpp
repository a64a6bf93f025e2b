#include "vocal/calibration/association/hand_eye_association.h"

#include <algorithm>
#include <map>
#include <utility>

#include "vocal/core/se3.h"

namespace vocal {

namespace {
struct Span {
  double start = 0.0, end = 0.0;
  // The tool's at the span's middle sample: its first may be the end of the arm's approach, within the
  // drift bound but not yet where it stood.
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
};

// Whether `to` lies beyond the drift bounds from `from`.
bool drifted(const Eigen::Isometry3d& from, const Eigen::Isometry3d& to, const ToolStillnessOptions& options) {
  const Eigen::Isometry3d drift = from.inverse() * to;
  return drift.translation().norm() > options.max_translation || rotationAngle(drift) > options.max_rotation;
}

// Runs of samples within the drift bounds of the run's first sample (the tool, and each link), no gap
// longer than max_gap.
std::vector<Span> stillSpans(const std::vector<FramePoseSample>& samples, const ToolStillnessOptions& options) {
  std::vector<Span> spans;
  std::size_t first = 0;
  for (std::size_t i = 1; i <= samples.size(); ++i) {
    bool ends = i == samples.size();
    if (!ends) {
      ends = drifted(samples[first].pose, samples[i].pose, options) || samples[i].stamp - samples[i - 1].stamp > options.max_gap;
      for (std::size_t l = 0; l < samples[i].links.size() && l < samples[first].links.size() && !ends; ++l)
        ends = drifted(samples[first].links[l], samples[i].links[l], options);
    }
    if (!ends) continue;
    if (samples[i - 1].stamp - samples[first].stamp >= options.min_duration) {
      spans.push_back({samples[first].stamp, samples[i - 1].stamp, samples[(first + i - 1) / 2].pose});
    }
    first = i;
  }
  return spans;
}

// Whether the tool's pose is known at `stamp`: between two samples no further apart than max_gap.
bool toolKnownAt(const std::vector<FramePoseSample>& samples, double stamp, const ToolStillnessOptions& options) {
  const auto after = std::lower_bound(samples.begin(), samples.end(), stamp,
                                      [](const FramePoseSample& s, double t) { return s.stamp < t; });
  if (after == samples.end()) return false;
  if (after->stamp == stamp) return true;
  return after != samples.begin() && after->stamp - std::prev(after)->stamp <= options.max_gap;
}
}  // namespace

HandEyeAssociation associateToolStillness(std::vector<FramePoseSample> samples, const std::vector<TimedObservation>& views,
                                          const ToolStillnessOptions& options) {
  std::sort(samples.begin(), samples.end(), [](const FramePoseSample& a, const FramePoseSample& b) { return a.stamp < b.stamp; });
  HandEyeAssociation association;
  const std::vector<Span> spans = stillSpans(samples, options);
  association.still_spans = static_cast<int>(spans.size());
  std::vector<HandEyeStation> stations(spans.size());
  for (std::size_t k = 0; k < spans.size(); ++k) stations[k].base_from_tool = spans[k].pose;
  for (const TimedObservation& view : views) {
    if (view.plane_measurements.empty() && view.points.empty()) continue;
    const auto span = std::find_if(spans.begin(), spans.end(), [&](const Span& s) { return view.stamp >= s.start && view.stamp <= s.end; });
    if (span == spans.end()) {
      if (toolKnownAt(samples, view.stamp, options)) {
        ++association.views_in_motion;
      } else {
        ++association.views_without_tool;
      }
      continue;
    }
    HandEyeStation& station = stations[span - spans.begin()];
    if (station.views.empty() || view.stamp < station.first_stamp) station.first_stamp = view.stamp;
    station.last_stamp = std::max(station.last_stamp, view.stamp);
    if (view.plane_measurements.empty()) {
      station.views.push_back({view.sensor, PlaneMeasurement{}, view.points, view.outline});  // a range sensor's board points
    }
    for (const PlaneMeasurement& pattern : view.plane_measurements) station.views.push_back({view.sensor, pattern, {}, {}});
  }
  for (HandEyeStation& station : stations) {
    if (station.views.empty()) {
      ++association.spans_without_view;
    } else {
      association.stations.push_back(std::move(station));
    }
  }
  return association;
}

std::vector<TargetObservation> stillPoseObservations(const std::vector<HandEyeStation>& stations, const TargetPattern& pattern) {
  const std::vector<Eigen::Vector3d> corners = pattern.corners();
  std::map<std::pair<int, int>, TargetObservation> pooled;  // (sensor, station)
  for (std::size_t k = 0; k < stations.size(); ++k) {
    for (const HandEyeView& view : stations[k].views) {
      TargetObservation& o = pooled[{view.sensor, static_cast<int>(k)}];
      o.sensor = view.sensor;
      o.target_pose = static_cast<int>(k);
      o.first_stamp = stations[k].first_stamp, o.last_stamp = stations[k].last_stamp;
      o.points.insert(o.points.end(), view.points.begin(), view.points.end());
      o.outline.insert(o.outline.end(), view.outline.begin(), view.outline.end());
      if (!view.points.empty()) continue;
      o.plane_measurements.push_back(view.pattern);
      for (const Eigen::Vector3d& c : corners) o.points.push_back(view.pattern.sensor_from_pattern * c);
    }
  }
  std::vector<TargetObservation> observations;
  for (auto& entry : pooled) observations.push_back(std::move(entry.second));
  return observations;
}

}  // namespace vocal
