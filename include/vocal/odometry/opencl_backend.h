#pragma once
// OpenCL backend: the kernels of cl_kernels/odometry.cl (embedded at build time) on the chosen device.
// Buffers for two frames are allocated once for the camera size and reused frame after frame.

#include <memory>

#include "vocal/odometry/odometry_backend.h"

namespace vocal {

class OpenClOdometryBackend : public OdometryBackend {
 public:
  // Throws InputError naming what was found when no platform or matching device is usable, or with the
  // build log when the kernels do not compile.
  OpenClOdometryBackend(const PinholeCamera& camera, const OdometryConfig& config);
  ~OpenClOdometryBackend() override;

  std::string name() const override;
  void pushFrame(const RgbdFrame& frame, ReferenceUpdate update) override;
  NormalEquations icpSystem(int level, const Eigen::Isometry3d& reference_from_current) override;
  NormalEquations rgbSystem(int level, const Eigen::Isometry3d& reference_from_current,
                            double huber_threshold, const BrightnessTransfer& brightness) override;
  std::size_t memoryBytes() const override;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// True when this build has the OpenCL backend compiled in.
bool openClBackendBuilt();

}  // namespace vocal
