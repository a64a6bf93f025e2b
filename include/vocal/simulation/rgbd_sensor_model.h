#pragma once
// What a structured-light RGB-D sensor (Kinect / Xtion) does to ideal images: for depth, range limits,
// axial noise that grows with depth squared, disparity quantisation, and missing pixels (random
// drop-outs and depth discontinuities); for colour, pixel noise.

#include <cstdint>

#include "vocal/core/image.h"

namespace vocal {

struct RgbdSensorModel {
  double min_depth = 0.4;  // metres; nearer or farther measurements are missing
  double max_depth = 8.0;
  // sigma(z) = 0.0012 + 0.0019 (z - 0.4)^2 m (Nguyen et al. 2012), spatially correlated over ~7 px
  bool axial_noise = false;
  bool quantize_disparity = false;  // 1/8 pixel steps of the native disparity (580 px focal, 7.5 cm)
  double missing_fraction = 0.0;    // random drop-out probability per pixel
  bool drop_discontinuities = false;  // pixels next to a depth jump above 5 % are missing
  double color_noise_sigma = 0.0;     // Gaussian colour noise, 8-bit levels

  static constexpr double kNativeFocalPx = 580.0;  // Kinect IR camera at 640x480
  static constexpr double kBaselineM = 0.075;

  // Noise standard deviation at depth z (metres).
  static double axialSigma(double z) { return 0.0012 + 0.0019 * (z - 0.4) * (z - 0.4); }
};

// Kinect-like depth noise, quantisation and drop-outs, and colour noise of 2 levels, as the
// command-line --kinect-noise switch sets them.
RgbdSensorModel kinectLikeSensorModel(double missing_fraction = 0.02);

// Apply the model in place; `seed` makes the noise reproducible (use one per frame).
void applyDepthSensorModel(const RgbdSensorModel& model, std::uint32_t seed, DepthImage* depth);
void applyColorSensorModel(const RgbdSensorModel& model, std::uint32_t seed, ColorImage* color);

}  // namespace vocal
