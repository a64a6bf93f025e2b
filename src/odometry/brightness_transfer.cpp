#include "vocal/odometry/brightness_transfer.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "vocal/core/worker_pool.h"

namespace vocal {

namespace {
// Luma in 0..1, as the backends compute it.
float intensityOf(const Rgb8& p) { return (0.299f * p.r + 0.587f * p.g + 0.114f * p.b) * (1.0f / 255.0f); }

// Intensities within this distance of black or white may be clipped: they do not follow the map.
constexpr float kClipMargin = 8.0f / 255.0f;
// Sampled rows a thread takes at a time.
constexpr int kSampleRowsPerBlock = 8;

struct Quartiles {
  float lower, median, upper;
};

// The 0.25, 0.5 and 0.75 quantiles of `values` (reordered). Once the median is in place each quartile
// is found in the half it lies in: the same values as searched over the whole set, at half the work.
Quartiles quartilesOf(std::vector<float>* values) {
  auto at = [values](double q) { return values->begin() + static_cast<std::ptrdiff_t>(q * (values->size() - 1)); };
  const auto lower = at(0.25), median = at(0.5), upper = at(0.75);
  std::nth_element(values->begin(), median, values->end());
  std::nth_element(values->begin(), lower, median);
  std::nth_element(median + 1, upper, values->end());
  return {*lower, *median, *upper};
}
}  // namespace

BrightnessTransfer estimateBrightnessTransfer(const RgbdFrame& reference, const RgbdFrame& current,
                                              const PinholeCamera& camera, const Eigen::Isometry3d& reference_from_current,
                                              double max_depth_difference, WorkerPool* workers, int stride,
                                              int min_samples) {
  const Eigen::Matrix3f R = reference_from_current.linear().cast<float>();
  const Eigen::Vector3f t = reference_from_current.translation().cast<float>();
  const float fx = static_cast<float>(camera.fx), fy = static_cast<float>(camera.fy);
  const float cx = static_cast<float>(camera.cx), cy = static_cast<float>(camera.cy);
  const int w = current.depth.width(), h = current.depth.height();
  const int sampled_rows = (h + stride - 1) / stride;
  // Pairs found per block of sampled rows (no two threads fill one vector); the quantiles do not
  // depend on the order the blocks are joined in.
  struct Pairs {
    std::vector<float> current, reference;
  };
  std::vector<Pairs> found(WorkerPool::blockCount(sampled_rows, kSampleRowsPerBlock));
  const auto sampleRows = [&](int block, int row_begin, int row_end) {
    Pairs& mine = found[block];
    for (int y = row_begin * stride; y < row_end * stride && y < h; y += stride) {
      for (int x = 0; x < w; x += stride) {
        const float z = current.depth(x, y);
        if (!isValidDepth(z)) continue;
        const Eigen::Vector3f p = R * Eigen::Vector3f((x - cx) / fx * z, (y - cy) / fy * z, z) + t;
        if (!(p.z() > 0.0f)) continue;
        const int u = static_cast<int>(std::lround(fx * p.x() / p.z() + cx)), v = static_cast<int>(std::lround(fy * p.y() / p.z() + cy));
        if (u < 0 || v < 0 || u >= w || v >= h) continue;
        const float zr = reference.depth(u, v);
        if (!isValidDepth(zr) || std::fabs(zr - p.z()) > max_depth_difference) continue;
        const float ic = intensityOf(current.color(x, y)), ir = intensityOf(reference.color(u, v));
        if (std::min(ic, ir) < kClipMargin || std::max(ic, ir) > 1.0f - kClipMargin) continue;
        mine.current.push_back(ic);
        mine.reference.push_back(ir);
      }
    }
  };
  WorkerPool& pool = workers ? *workers : WorkerPool::callerOnly();
  pool.forBlocks(sampled_rows, kSampleRowsPerBlock, sampleRows);
  std::vector<float> seen_current, seen_reference;
  for (const Pairs& pairs : found) {
    seen_current.insert(seen_current.end(), pairs.current.begin(), pairs.current.end());
    seen_reference.insert(seen_reference.end(), pairs.reference.begin(), pairs.reference.end());
  }
  BrightnessTransfer transfer;
  if (static_cast<int>(seen_current.size()) < min_samples) return transfer;
  Quartiles seen[2]{};
  std::vector<float>* sets[2] = {&seen_current, &seen_reference};
  pool.forEach(2, 1, [&](int set) { seen[set] = quartilesOf(sets[set]); });
  const Quartiles& seen_in_current = seen[0];
  const Quartiles& seen_in_reference = seen[1];
  const float current_spread = seen_in_current.upper - seen_in_current.lower;
  const float reference_spread = seen_in_reference.upper - seen_in_reference.lower;
  if (!(current_spread > 0.0f)) return transfer;
  const float gain = reference_spread / current_spread;
  if (!(gain >= 0.5f && gain <= 2.0f)) return transfer;
  transfer.gain = gain;
  transfer.bias = seen_in_reference.median - gain * seen_in_current.median;
  transfer.samples = static_cast<int>(seen_current.size());
  return transfer;
}

}  // namespace vocal
