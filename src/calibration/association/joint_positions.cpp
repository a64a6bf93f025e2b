#include "vocal/calibration/association/joint_positions.h"

#include <algorithm>
#include <cstdio>

namespace vocal {

std::vector<TargetObservation> attachJointPositions(std::vector<TargetObservation> views, const JointedMounts& mounts,
                                                    const std::vector<std::vector<JointReading>>& readings,
                                                    const std::vector<SensorSpec>& sensors, const JointStillnessOptions& options,
                                                    JointPositionCounts* counts) {
  JointPositionCounts local;
  JointPositionCounts& count = counts ? *counts : local;
  std::vector<TargetObservation> kept;
  kept.reserve(views.size());
  for (TargetObservation& view : views) {
    if (!mounts.jointed(view.sensor)) {
      kept.push_back(std::move(view));
      continue;
    }
    // The readings over its run; where none fell within it (one message, sparse readings), the nearest within the margin.
    double begin = view.first_stamp, end = view.last_stamp;
    view.joint_positions.clear();
    std::string problem;
    for (const int j : mounts.chains[view.sensor]) {
      const JointDescription& joint = mounts.joints[j];
      if (joint.type == JointType::kFixed) {
        view.joint_positions.push_back(0.0);
        continue;
      }
      const std::vector<JointReading>& own = j < static_cast<int>(readings.size()) ? readings[j] : std::vector<JointReading>{};
      const auto after = [](const JointReading& r, double t) { return r.stamp < t; };
      const auto first = std::lower_bound(own.begin(), own.end(), begin, after);
      std::vector<double> positions;
      for (auto it = first; it != own.end() && it->stamp <= end; ++it) positions.push_back(it->position);
      if (positions.empty()) {
        const JointReading* nearest = nullptr;
        for (auto it : {first, first == own.begin() ? own.end() : first - 1}) {
          if (it == own.end()) continue;
          const double gap = it->stamp < begin ? begin - it->stamp : it->stamp - end;
          if (gap <= options.margin && (!nearest || gap < (nearest->stamp < begin ? begin - nearest->stamp : nearest->stamp - end))) nearest = &*it;
        }
        if (nearest) positions.push_back(nearest->position);
        begin -= options.margin, end += options.margin;  // for the message below
      }
      char line[300];
      if (positions.empty()) {
        std::snprintf(line, sizeof(line), "no reading of joint '%s' between %.3f and %.3f s", joint.name.c_str(), begin, end);
        problem = line, ++count.unread;
        break;
      }
      const auto [low, high] = std::minmax_element(positions.begin(), positions.end());
      const bool prismatic = joint.type == JointType::kPrismatic;
      if (*high - *low > (prismatic ? options.max_prismatic_motion : options.max_motion)) {
        std::snprintf(line, sizeof(line), "joint '%s' moved %.1f %s during it (more than %.1f)", joint.name.c_str(), 1000.0 * (*high - *low),
                      prismatic ? "mm" : "mrad", 1000.0 * (prismatic ? options.max_prismatic_motion : options.max_motion));
        problem = line, ++count.moving;
        break;
      }
      std::nth_element(positions.begin(), positions.begin() + positions.size() / 2, positions.end());
      view.joint_positions.push_back(positions[positions.size() / 2]);
    }
    if (problem.empty()) {
      ++count.kept;
      kept.push_back(std::move(view));
    } else if (count.first.empty()) {
      const std::string name = view.sensor < static_cast<int>(sensors.size()) ? sensors[view.sensor].name : std::to_string(view.sensor);
      count.first = "sensor '" + name + "' at still pose " + std::to_string(view.target_pose) + ": " + problem;
    }
  }
  return kept;
}

}  // namespace vocal
