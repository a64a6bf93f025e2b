#pragma once
// Smooth 6-DoF camera paths inside a scene's workspace: sums of incommensurate sinusoids in position
// and roll/pitch/yaw, paced so that the mean translational speed equals the requested one.

#include <cstdint>

#include "vocal/core/tum_trajectory.h"
#include "vocal/simulation/synthetic_scene.h"

namespace vocal {

struct SyntheticTrajectoryOptions {
  int frames = 300;
  double frame_rate = 30.0;     // Hz
  double speed = 0.25;          // mean translational speed, m/s (TUM fr1_xyz: about 0.24)
  double start_stamp = 1.0e9;   // seconds; stamps are rounded to microseconds like TUM's
  std::uint32_t seed = 1;       // picks the phases of the sinusoids
};

// Poses of the optical frame in the world (z up). Throws InputError for non-positive frames, rate or
// a negative speed.
Trajectory generateSyntheticTrajectory(const CameraWorkspace& workspace, const SyntheticTrajectoryOptions& options);

}  // namespace vocal
