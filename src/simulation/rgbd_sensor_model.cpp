#include "vocal/simulation/rgbd_sensor_model.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace vocal {

namespace {
// Zero-mean, unit-variance noise correlated over (2 radius + 1)^2 pixels: structured-light sensors
// match speckle blocks of about 7x7 pixels of their 640x480 IR image, so neighbouring pixels share
// much of their error (Khoshelham and Elberink 2012); independent per-pixel noise would make local
// surface normals far worse than real.
Image<float> correlatedUnitNoise(int width, int height, int radius, std::mt19937* rng) {
  const int taps = 2 * radius + 1;
  std::normal_distribution<float> gaussian(0.0f, 1.0f);
  Image<float> white(width, height);
  for (float& v : white.pixels()) v = gaussian(*rng);
  // Separable box filter over a taps x taps window, wrapping at the borders so every output averages
  // exactly taps^2 independent values; scaling by taps restores unit variance.
  Image<float> rows(width, height), out(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      float sum = 0.0f;
      for (int d = -radius; d <= radius; ++d) sum += white((x + d + width) % width, y);
      rows(x, y) = sum;
    }
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      float sum = 0.0f;
      for (int d = -radius; d <= radius; ++d) sum += rows(x, (y + d + height) % height);
      out(x, y) = sum / taps;
    }
  return out;
}
}  // namespace

void applyDepthSensorModel(const RgbdSensorModel& model, std::uint32_t seed, DepthImage* depth) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const DepthImage ideal = *depth;
  // Sizes in the sensor's native 640-pixel-wide IR image scale to the rendered resolution.
  const double native_scale = depth->width() / 640.0;
  const int radius = std::max(1, static_cast<int>(std::lround(3 * native_scale)));
  const Image<float> unit_noise =
      model.axial_noise ? correlatedUnitNoise(depth->width(), depth->height(), radius, &rng) : Image<float>();
  // Disparity in native IR pixels is focal * baseline / z; the device reports it in 1/8 pixel steps,
  // whatever resolution the depth image is delivered at.
  const double focal_baseline = RgbdSensorModel::kNativeFocalPx * RgbdSensorModel::kBaselineM;
  for (int y = 0; y < depth->height(); ++y) {
    for (int x = 0; x < depth->width(); ++x) {
      double z = ideal(x, y);
      if (!isValidDepth(static_cast<float>(z)) || z < model.min_depth || z > model.max_depth) {
        (*depth)(x, y) = 0.0f;
        continue;
      }
      if (model.drop_discontinuities) {
        bool jump = false;
        const int dx[] = {1, -1, 0, 0}, dy[] = {0, 0, 1, -1};
        for (int k = 0; k < 4 && !jump; ++k) {
          const int nx = x + dx[k], ny = y + dy[k];
          if (nx < 0 || ny < 0 || nx >= depth->width() || ny >= depth->height()) continue;
          const double n = ideal(nx, ny);
          jump = !isValidDepth(static_cast<float>(n)) || std::abs(n - z) > 0.05 * z;
        }
        if (jump) {
          (*depth)(x, y) = 0.0f;
          continue;
        }
      }
      if (model.missing_fraction > 0.0 && uniform(rng) < model.missing_fraction) {
        (*depth)(x, y) = 0.0f;
        continue;
      }
      if (model.axial_noise) {
        z += RgbdSensorModel::axialSigma(z) * unit_noise(x, y);
      }
      if (model.quantize_disparity) {
        const double disparity = std::round(8.0 * focal_baseline / z) / 8.0;
        z = focal_baseline / disparity;
      }
      (*depth)(x, y) = static_cast<float>(z);
    }
  }
}

void applyColorSensorModel(const RgbdSensorModel& model, std::uint32_t seed, ColorImage* color) {
  if (!(model.color_noise_sigma > 0.0)) return;
  std::mt19937 rng(seed ^ 0x5bd1e995u);
  std::normal_distribution<double> gaussian(0.0, model.color_noise_sigma);
  auto noisy = [&](std::uint8_t c) {
    return static_cast<std::uint8_t>(std::clamp(std::lround(c + gaussian(rng)), 0L, 255L));
  };
  for (Rgb8& p : color->pixels()) p = {noisy(p.r), noisy(p.g), noisy(p.b)};
}

RgbdSensorModel kinectLikeSensorModel(double missing_fraction) {
  RgbdSensorModel model;
  model.color_noise_sigma = 2.0;
  model.axial_noise = true;
  model.quantize_disparity = true;
  model.missing_fraction = missing_fraction;
  model.drop_discontinuities = true;
  return model;
}

}  // namespace vocal
