#include "vocal/odometry/fast_cpu_backend.h"

#include <array>
#include <cmath>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "tracking_row.h"

namespace vocal {

namespace {
int resolveThreads(int requested) {
  if (requested > 0) return requested;
#ifdef _OPENMP
  return omp_get_num_procs();
#else
  return 1;
#endif
}
}  // namespace

FastCpuOdometryBackend::FastCpuOdometryBackend(const PinholeCamera& camera, const OdometryConfig& config,
                                               CpuTrackingPass pass)
    : camera_(camera), config_(config), threads_(resolveThreads(config.cpu_threads)) {
  TrackRowFunction avx2 = pass == CpuTrackingPass::kBest ? avx2TrackRow() : nullptr;
  track_row_ = avx2 ? avx2 : &trackRowPortable;
}

std::string FastCpuOdometryBackend::name() const {
  return "cpu fast (" + std::to_string(threads_) + (threads_ == 1 ? " thread, " : " threads, ") +
         (track_row_ == &trackRowPortable ? "portable" : "AVX2") + ")";
}

void FastCpuOdometryBackend::pushFrame(const RgbdFrame& frame, ReferenceUpdate update) {
  // The old current frame becomes the reference and the old reference's buffers are reused, or the
  // reference stays and the current buffers are overwritten.
  if (update == ReferenceUpdate::kPreviousFrame) current_ ^= 1;
  buildSoaFramePyramid(frame, camera_, config_, threads_, &frames_[current_], track_row_ != &trackRowPortable);
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
  // Per thread, then summed in thread order: the same result for the same thread count every time.
  std::vector<std::array<double, 2 * kReductionValues>> partial(threads_);
#pragma omp parallel num_threads(threads_)
  {
#ifdef _OPENMP
    const int thread = omp_get_thread_num();
#else
    const int thread = 0;
#endif
    std::array<double, 2 * kReductionValues>& sums = partial[thread];
    sums.fill(0.0);
#pragma omp for schedule(static, 4)
    for (int y = 0; y < cur.height; ++y)
      track_row_(cur, ref, warp, thresholds, y, icp ? sums.data() : nullptr, rgb ? sums.data() + kReductionValues : nullptr);
  }
  std::array<double, 2 * kReductionValues> total{};
  for (const auto& sums : partial)
    for (int k = 0; k < 2 * kReductionValues; ++k) total[k] += sums[k];
  if (icp) *icp = NormalEquations::fromPacked(total.data());
  if (rgb) *rgb = NormalEquations::fromPacked(total.data() + kReductionValues);
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
