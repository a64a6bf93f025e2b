#include "vocal/core/depth_sensor_model.h"

#include <cmath>
#include <random>

namespace vocal {

void applyDepthSensorModel(const DepthSensorModel& model, const PinholeCamera& camera, std::uint32_t seed,
                           DepthImage* depth) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> gaussian(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const DepthImage ideal = *depth;
  // Disparity in pixels is focal * baseline / z; the device reports it in 1/8 pixel steps.
  const double focal_baseline = camera.fx * 0.075;
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
        z += DepthSensorModel::axialSigma(z) * gaussian(rng);
      }
      if (model.quantize_disparity) {
        const double disparity = std::round(8.0 * focal_baseline / z) / 8.0;
        z = focal_baseline / disparity;
      }
      (*depth)(x, y) = static_cast<float>(z);
    }
  }
}

}  // namespace vocal
