#pragma once
// Fast CPU backend, the default where no GPU is there: the math of the CPU reference (parity-tested
// against it) on all cores. Preprocessing runs over rows in parallel into reused float planes; one
// pass over the current frame's pixels builds the ICP and the photometric rows together (8 pixels at a
// time with AVX2 gathers where the CPU has them, picked at run time; a portable pass elsewhere), and
// the rows are reduced in float within an image row, summed in double.

#include <array>
#include <vector>

#include "vocal/core/worker_pool.h"
#include "vocal/odometry/odometry_backend.h"
#include "vocal/odometry/soa_frame_pyramid.h"

namespace vocal {

struct TrackingWarp;
struct TrackingThresholds;

// One image row of the tracking pass, added to packed normal-equation sums (src/odometry/tracking_row.h
// has the implementations).
using TrackRowFunction = void (*)(const SoaPyramidLevel& cur, const SoaPyramidLevel& ref, const TrackingWarp& warp,
                                  const TrackingThresholds& thresholds, int y, double* icp_sums, double* rgb_sums);

// The per-pixel tracking pass: the best this CPU runs (AVX2 + FMA where there), or the portable one
// (any CPU; the parity tests check both).
enum class CpuTrackingPass { kBest, kPortable };

class FastCpuOdometryBackend : public OdometryBackend {
 public:
  // config.threads threads (0: OMP_NUM_THREADS where set, else the cores this process may use).
  FastCpuOdometryBackend(const PinholeCamera& camera, const OdometryConfig& config,
                         CpuTrackingPass pass = CpuTrackingPass::kBest);

  std::string name() const override;
  void pushFrame(const RgbdFrame& frame, ReferenceUpdate update) override;
  void setFinestLevel(int level) override { finest_level_ = level; }
  bool samplesRows() const override { return true; }
  NormalEquations icpSystem(int level, const Eigen::Isometry3d& reference_from_current) override;
  NormalEquations rgbSystem(int level, const Eigen::Isometry3d& reference_from_current,
                            double huber_threshold, const BrightnessTransfer& brightness) override;
  void trackingSystems(int level, const Eigen::Isometry3d& reference_from_current, double huber_threshold,
                       const BrightnessTransfer& brightness, NormalEquations* icp, NormalEquations* rgb) override;
  std::size_t memoryBytes() const override;

  int threads() const { return workers_.threads(); }
  WorkerPool* workers() override { return &workers_; }
  const SoaFramePyramid& current() const { return frames_[current_]; }

 private:
  PinholeCamera camera_;
  OdometryConfig config_;
  WorkerPool workers_;
  SoaFramePyramid frames_[2];  // the reference is the one that is not current; buffers swap roles
  int current_ = 0;
  int finest_level_ = 0;  // setFinestLevel: the finer levels of frames pushed are not built
  TrackRowFunction track_row_;
  std::vector<std::array<double, 2 * kReductionValues>> block_sums_;  // the tracking pass's, per block of rows
};

}  // namespace vocal
