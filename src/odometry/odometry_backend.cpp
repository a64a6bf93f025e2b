#include "vocal/odometry/odometry_backend.h"

#include "vocal/core/errors.h"
#include "vocal/odometry/cpu_backend.h"
#ifdef VOCAL_HAVE_OPENCL
#include "vocal/odometry/opencl_backend.h"
#endif

namespace vocal {

std::unique_ptr<OdometryBackend> makeOdometryBackend(const PinholeCamera& camera, const OdometryConfig& config,
                                                     std::string* notice) {
  if (config.backend == OdometryBackendKind::kCpu) {
    return std::make_unique<CpuOdometryBackend>(camera, config);
  }
#ifdef VOCAL_HAVE_OPENCL
  if (config.backend == OdometryBackendKind::kOpenCl) {
    return std::make_unique<OpenClOdometryBackend>(camera, config);
  }
  try {
    return std::make_unique<OpenClOdometryBackend>(camera, config);
  } catch (const InputError& e) {
    if (notice) *notice = std::string(e.what()) + ": using the CPU reference backend";
    return std::make_unique<CpuOdometryBackend>(camera, config);
  }
#else
  if (config.backend == OdometryBackendKind::kOpenCl) {
    throw InputError("odometry backend 'opencl' is not built into this vocal (OpenCL was not found at build time)");
  }
  if (notice) *notice = "OpenCL was not found at build time: using the CPU reference backend";
  return std::make_unique<CpuOdometryBackend>(camera, config);
#endif
}

}  // namespace vocal
