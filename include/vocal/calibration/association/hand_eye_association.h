#pragma once
// The still poses of a robot arm (hand-eye), from the tool's pose as tf reports it: the arm stands still
// when its tool does, which the arm's own pose stream says at its own rate (100-1000 Hz), however few
// images the camera took there. Each still span of the tool collects every sensor's views within it.

#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "vocal/calibration/association/still_target_association.h"
#include "vocal/calibration/extraction/pattern_observation.h"
#include "vocal/calibration/solver/hand_eye_calibration.h"

namespace vocal {

// The tool's pose in the reference frame at one instant (a tf lookup).
struct FramePoseSample {
  double stamp = 0.0;  // seconds
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  // Other links sensors sit on (a head's, from its joints), the same ones at every sample: a still span
  // is one where they stand still too (the arm may hold the board while the head turns to look again).
  std::vector<Eigen::Isometry3d> links;
};

struct ToolStillnessOptions {
  double max_translation = 0.0005;  // metres the tool may drift within a still span ...
  double max_rotation = 0.002;      // ... and radians
  double min_duration = 0.4;        // seconds a span must last
  double max_gap = 0.2;             // seconds between samples: a longer silence of tf ends a span
};

struct HandEyeAssociation {
  std::vector<HandEyeStation> stations;  // in time order, each with at least one view
  int still_spans = 0;          // the tool's still spans found
  int spans_without_view = 0;   // ... in which no sensor saw the board
  int views_in_motion = 0;      // views outside every still span (the arm moving)
  int views_without_tool = 0;   // ... taken where the tool's pose is not known (before, after or between tf)
};

// `samples` in any order; `views`: every sensor's observations (a camera's plane_measurements, a range
// sensor's points), any order.
HandEyeAssociation associateToolStillness(std::vector<FramePoseSample> samples, const std::vector<TimedObservation>& views,
                                          const ToolStillnessOptions& options = {});

// An arm's stations as the still-pose graph (graph_calibration.h) takes them: per (sensor, station) one
// observation, its target pose the station's index, pooling that sensor's views there - a camera's plane
// measurements with `pattern`'s corners placed by each as its points, a range sensor's points and outline.
std::vector<TargetObservation> stillPoseObservations(const std::vector<HandEyeStation>& stations, const TargetPattern& pattern);

}  // namespace vocal
