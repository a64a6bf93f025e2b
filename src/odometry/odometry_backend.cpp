#include "vocal/odometry/odometry_backend.h"

#include <algorithm>

#include "vocal/core/errors.h"
#include "vocal/odometry/cpu_backend.h"
#include "vocal/odometry/fast_cpu_backend.h"
#ifdef VOCAL_HAVE_OPENCL
#include "vocal/odometry/opencl_backend.h"
#include "vocal/odometry/opencl_context.h"
#endif

namespace vocal {

void OdometryBackend::trackingSystems(int level, const Eigen::Isometry3d& reference_from_current,
                                      double huber_threshold, const BrightnessTransfer& brightness, NormalEquations* icp,
                                      NormalEquations* rgb) {
  if (icp) *icp = icpSystem(level, reference_from_current);
  if (rgb) *rgb = rgbSystem(level, reference_from_current, huber_threshold, brightness);
}

std::unique_ptr<OdometryBackend> makeOdometryBackend(const PinholeCamera& camera, const OdometryConfig& config,
                                                     std::string* notice) {
  config.validate();  // before a pool of config.threads is started
  if (config.backend == OdometryBackendKind::kReference) return std::make_unique<CpuOdometryBackend>(camera, config);
  if (config.backend == OdometryBackendKind::kCpu) return std::make_unique<FastCpuOdometryBackend>(camera, config);
#ifdef VOCAL_HAVE_OPENCL
  if (config.backend == OdometryBackendKind::kOpenCl) return std::make_unique<OpenClOdometryBackend>(camera, config);
  // Auto: a GPU is worth OpenCL; on a CPU device (PoCL) the fast CPU backend is faster. A device named
  // in the config is the user's choice and is tried whatever it is.
  const std::vector<OpenClDeviceInfo> devices = listOpenClDevices();
  const bool named = !config.opencl_platform.empty() || !config.opencl_device.empty();
  const bool has_gpu = std::any_of(devices.begin(), devices.end(), [](const OpenClDeviceInfo& d) { return d.is_gpu; });
  if (named || has_gpu) {
    try {
      return std::make_unique<OpenClOdometryBackend>(camera, config);
    } catch (const InputError& e) {
      if (notice) *notice = std::string(e.what()) + ": using the fast CPU backend";
      return std::make_unique<FastCpuOdometryBackend>(camera, config);
    }
  }
  if (notice) *notice = "no GPU OpenCL device found: using the fast CPU backend";
#else
  if (config.backend == OdometryBackendKind::kOpenCl) {
    throw InputError("odometry backend 'opencl' is not built into this vocal (OpenCL was not found at build time)");
  }
  if (notice) *notice = "OpenCL was not found at build time: using the fast CPU backend";
#endif
  return std::make_unique<FastCpuOdometryBackend>(camera, config);
}

}  // namespace vocal
