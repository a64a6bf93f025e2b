#pragma once
// What a structured-light sensor (Kinect / Xtion) does to ideal depth: range limits, axial noise that
// grows with depth squared, disparity quantisation, and missing pixels (random drop-outs and depth
// discontinuities).

#include <cstdint>

#include "vocal/core/image.h"
#include "vocal/core/pinhole_camera.h"

namespace vocal {

struct DepthSensorModel {
  double min_depth = 0.4;  // metres; nearer or farther measurements are missing
  double max_depth = 8.0;
  bool axial_noise = false;  // sigma(z) = 0.0012 + 0.0019 (z - 0.4)^2 m (Nguyen et al. 2012)
  bool quantize_disparity = false;  // 1/8 pixel disparity steps, baseline 7.5 cm
  double missing_fraction = 0.0;    // random drop-out probability per pixel
  bool drop_discontinuities = false;  // pixels next to a depth jump above 5 % are missing

  // Noise standard deviation at depth z (metres).
  static double axialSigma(double z) { return 0.0012 + 0.0019 * (z - 0.4) * (z - 0.4); }
};

// Applies the model in place; `seed` makes the noise reproducible (use one per frame).
void applyDepthSensorModel(const DepthSensorModel& model, const PinholeCamera& camera, std::uint32_t seed,
                           DepthImage* depth);

}  // namespace vocal
