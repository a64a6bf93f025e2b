#pragma once
// Renders a synthetic scene along a trajectory into a TUM-layout folder: rgb/*.png (8-bit),
// depth/*.png (16-bit, 5000 per metre), rgb.txt, depth.txt, groundtruth.txt and camera.yaml.

#include <cstdint>
#include <functional>
#include <string>

#include "vocal/core/pinhole_camera.h"
#include "vocal/core/rgbd_frame.h"
#include "vocal/simulation/rgbd_sensor_model.h"
#include "vocal/simulation/synthetic_scene.h"
#include "vocal/simulation/synthetic_trajectory.h"

namespace vocal {

struct SyntheticSequenceOptions {
  SceneVariant scene = SceneVariant::kIndoorRoom;
  int width = 640;
  int height = 480;
  SyntheticTrajectoryOptions trajectory;
  // When set, poses come from this TUM trajectory file instead of being generated.
  std::string trajectory_path;
  // When not empty (and no trajectory_path), these poses instead of generated ones.
  Trajectory poses;
  RgbdSensorModel sensor_model;  // ideal images unless noise / drop-outs are switched on
  // Frames [covered_from, covered_from + covered_frames) show a hand over the lens (coverLens).
  int covered_from = 0;
  int covered_frames = 0;
  // Seconds from the first row's exposure to the last (renderRollingShutterFrame); 0: a global shutter.
  double rolling_shutter_readout = 0.0;
  // Seconds each row is exposed: colour blurred along the motion, depth lost where it smears (0: sharp).
  double exposure = 0.0;
};

// Renders one frame; `noise_seed` makes the depth model reproducible.
RgbdFrame renderSyntheticFrame(const SyntheticScene& scene, const PinholeCamera& camera,
                               const StampedPose& world_from_camera, const RgbdSensorModel& sensor_model,
                               std::uint32_t noise_seed);

// Renders frame `index` of `path` as a rolling-shutter camera takes it: rows are exposed one after
// another over `readout_seconds` (first to last), the middle row at the frame's stamp, each band of
// rows from the pose the camera had then (interpolated along the path). What a Kinect's colour and
// depth sensors do; renderSyntheticFrame is the global-shutter case.
// With `exposure_seconds` > 0 each row is also exposed over that long, centred on its instant: its colour
// the mean of the views in between (motion blur), its depth lost where they disagree by more than 2 % (a
// structured-light pattern smeared across depths), as a fast turn does to a real camera.
RgbdFrame renderRollingShutterFrame(const SyntheticScene& scene, const PinholeCamera& camera, const Trajectory& path,
                                    std::size_t index, double readout_seconds, const RgbdSensorModel& sensor_model,
                                    std::uint32_t noise_seed, double exposure_seconds = 0.0);

// A hand held over the lens: no depth (closer than the sensor's minimum range) and a dark, nearly
// uniform colour image with sensor noise; what tracking must survive without inventing motion.
void coverLens(std::uint32_t noise_seed, RgbdFrame* frame);

struct SyntheticSequence {
  PinholeCamera camera;
  Trajectory ground_truth;
};

// Creates `folder` (and rgb/, depth/) if needed and writes every file; `progress(done, total)` is
// called after each frame. Throws InputError for bad options or files that cannot be written.
SyntheticSequence writeSyntheticSequence(const std::string& folder, const SyntheticSequenceOptions& options,
                                         const std::function<void(int, int)>& progress = nullptr);

}  // namespace vocal
