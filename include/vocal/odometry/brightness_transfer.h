#pragma once
// Exposure changes between two frames as an affine map of intensity: the reference sees the current
// frame's intensity I as gain * I + bias. Real cameras change exposure and gain by themselves (TUM
// freiburg1 steps its mean brightness by up to 10 % between frames); the photometric residual then
// compares mapped intensities, so a change neither pulls the motion nor inflates the residual that
// keyframe choice and the wrong-minimum test read.

#include <Eigen/Geometry>

#include "vocal/core/pinhole_camera.h"
#include "vocal/core/rgbd_frame.h"

namespace vocal {

class WorkerPool;

struct BrightnessTransfer {
  float gain = 1.0f;
  float bias = 0.0f;  // in intensity units (0..1)
  int samples = 0;    // pixel pairs it was estimated from (0: the identity, nothing estimated)
};

// The transfer from `current` to `reference` (intensity 0..1, BT.601 luma) over the pixels both see
// at the motion reference_from_current: every `stride`-th pixel of the current frame with depth is
// moved into the reference; pairs where the reference's depth disagrees by more than
// `max_depth_difference` (occluded), or either intensity is clipped, are left out. Matching the two
// sets' medians and interquartile ranges is insensitive to the motion being off by a few pixels (the
// same surfaces are sampled, only not pixel for pixel) and to the few pixels that move on their own.
// Returns the identity when fewer than `min_samples` pairs are found or the map is implausible (gain
// outside [0.5, 2]). On `workers` where given (the same result with any number of threads), else on
// the calling thread.
BrightnessTransfer estimateBrightnessTransfer(const RgbdFrame& reference, const RgbdFrame& current,
                                              const PinholeCamera& camera, const Eigen::Isometry3d& reference_from_current,
                                              double max_depth_difference, WorkerPool* workers = nullptr,
                                              int stride = 4, int min_samples = 500);

}  // namespace vocal
