#include "vocal/odometry/fast_cpu_backend.h"

#include <array>
#include <cmath>
#include <vector>

#include "tracking_row.h"

namespace vocal {

namespace {
// Rows of the tracking pass a thread claims at a time; each block's sums are kept apart and added in
// block order, so the systems are the same to the bit whatever the number of threads.
constexpr int kTrackingRowsPerBlock = 4;
}  // namespace

FastCpuOdometryBackend::FastCpuOdometryBackend(const PinholeCamera& camera, const OdometryConfig& config,
                                               CpuTrackingPass pass)
    : camera_(camera), config_(config), workers_(config.threads) {
  TrackRowFunction avx2 = pass == CpuTrackingPass::kBest ? avx2TrackRow() : nullptr;
  track_row_ = avx2 ? avx2 : &trackRowPortable;
}

std::string FastCpuOdometryBackend::name() const {
  const int threads = workers_.threads();
  return "cpu fast (" + std::to_string(threads) + (threads == 1 ? " thread, " : " threads, ") +
         (track_row_ == &trackRowPortable ? "portable" : "AVX2") + ")";
}

void FastCpuOdometryBackend::pushFrame(const RgbdFrame& frame, ReferenceUpdate update) {
  // The old current frame becomes the reference and the old reference's buffers are reused, or the
  // reference stays and the current buffers are overwritten.
  if (update == ReferenceUpdate::kPreviousFrame) current_ ^= 1;
  buildSoaFramePyramid(frame, camera_, config_, workers_, &frames_[current_], track_row_ != &trackRowPortable, finest_level_);
}

void FastCpuOdometryBackend::trackingSystems(int level, const Eigen::Isometry3d& reference_from_current,
                                             double huber_threshold, const BrightnessTransfer& brightness,
                                             NormalEquations* icp, NormalEquations* rgb) {
  const SoaPyramidLevel& cur = frames_[current_].at(level);
  const SoaPyramidLevel& ref = frames_[current_ ^ 1].at(level);
  const TrackingWarp warp(reference_from_current, ref.camera, brightness);
  const float min_gradient = static_cast<float>(config_.rgb_min_gradient.at(level));
  const float max_distance = static_cast<float>(config_.icp_max_distance);
  const TrackingThresholds thresholds{max_distance * max_distance,
                              static_cast<float>(std::cos(config_.icp_max_angle_deg * M_PI / 180.0)),
                              static_cast<float>(config_.rgb_max_depth),
                              static_cast<float>(config_.rgb_max_depth_difference),
                              min_gradient * min_gradient,
                              static_cast<float>(huber_threshold),
                              DepthNoiseModel(config_.depth_noise_floor, config_.depth_noise_quadratic)};
  using Sums = std::array<double, 2 * kReductionValues>;
  // Blocks of the rows taken (every `step`-th from the first), each block's sums apart: the total does
  // not depend on the threads.
  const int step = rowStep(level);
  const int rows = (cur.height + step - 1) / step;
  block_sums_.resize(WorkerPool::blockCount(rows, kTrackingRowsPerBlock));
  workers_.forBlocks(rows, kTrackingRowsPerBlock, [&](int block, int row_begin, int row_end) {
    Sums& sums = block_sums_[block];
    sums.fill(0.0);
    for (int row = row_begin; row < row_end; ++row)
      track_row_(cur, ref, warp, thresholds, row * step, icp ? sums.data() : nullptr, rgb ? sums.data() + kReductionValues : nullptr);
  });
  Sums total{};
  for (const Sums& sums : block_sums_)
    for (int k = 0; k < 2 * kReductionValues; ++k) total[k] += sums[k];
  if (icp) {
    *icp = NormalEquations::fromPacked(total.data());
    *icp *= step;
  }
  if (rgb) {
    *rgb = NormalEquations::fromPacked(total.data() + kReductionValues);
    *rgb *= step;
  }
}

NormalEquations FastCpuOdometryBackend::icpSystem(int level, const Eigen::Isometry3d& reference_from_current) {
  NormalEquations icp;
  trackingSystems(level, reference_from_current, 0.0, BrightnessTransfer(), &icp, nullptr);
  return icp;
}

NormalEquations FastCpuOdometryBackend::rgbSystem(int level, const Eigen::Isometry3d& reference_from_current,
                                                  double huber_threshold, const BrightnessTransfer& brightness) {
  NormalEquations rgb;
  trackingSystems(level, reference_from_current, huber_threshold, brightness, nullptr, &rgb);
  return rgb;
}

std::size_t FastCpuOdometryBackend::memoryBytes() const {
  std::size_t bytes = 0;
  for (const SoaFramePyramid& pyramid : frames_)
    for (const SoaPyramidLevel& level : pyramid) bytes += level.memoryBytes();
  return bytes;
}

}  // namespace vocal
