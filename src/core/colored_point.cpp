#include "vocal/core/colored_point.h"

#include <algorithm>

namespace vocal {

std::vector<ColoredPoint> backProjectFrame(const RgbdFrame& frame, const PinholeCamera& camera, int stride) {
  stride = std::max(stride, 1);
  std::vector<ColoredPoint> points;
  points.reserve(frame.depth.size() / (stride * stride));
  for (int y = 0; y < frame.depth.height(); y += stride) {
    for (int x = 0; x < frame.depth.width(); x += stride) {
      const float z = frame.depth(x, y);
      if (!isValidDepth(z)) continue;
      points.push_back({camera.backProject(x, y, z).cast<float>(), frame.color(x, y)});
    }
  }
  return points;
}

}  // namespace vocal
