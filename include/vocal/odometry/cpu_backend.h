#pragma once
// CPU reference backend: plain, readable code of the same per-pixel math as cl_kernels/, accumulated
// in double. Used for parity tests and as the fallback without an OpenCL platform.

#include "vocal/odometry/frame_pyramid.h"
#include "vocal/odometry/odometry_backend.h"

namespace vocal {

class CpuOdometryBackend : public OdometryBackend {
 public:
  CpuOdometryBackend(const PinholeCamera& camera, const OdometryConfig& config);

  std::string name() const override { return "cpu reference"; }
  void pushFrame(const RgbdFrame& frame, ReferenceUpdate update) override;
  NormalEquations icpSystem(int level, const Eigen::Isometry3d& reference_from_current) override;
  NormalEquations rgbSystem(int level, const Eigen::Isometry3d& reference_from_current,
                            double huber_threshold, const BrightnessTransfer& brightness) override;
  bool samplesRows() const override { return true; }
  std::size_t memoryBytes() const override;

  const FramePyramid& reference() const { return reference_; }
  const FramePyramid& current() const { return current_; }

 private:
  PinholeCamera camera_;
  OdometryConfig config_;
  FramePyramid reference_;
  FramePyramid current_;
};

}  // namespace vocal
