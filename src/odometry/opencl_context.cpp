#include "vocal/odometry/opencl_context.h"

#include <algorithm>
#include <cctype>
#include <mutex>
#include <sstream>

#define CL_TARGET_OPENCL_VERSION 120
#include <CL/cl.h>

#include "vocal/core/errors.h"

namespace vocal {

namespace {
std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

std::string platformName(cl_platform_id platform) {
  char name[256] = {};
  clGetPlatformInfo(platform, CL_PLATFORM_NAME, sizeof(name) - 1, name, nullptr);
  return name;
}

std::string deviceName(cl_device_id device) {
  char name[256] = {};
  clGetDeviceInfo(device, CL_DEVICE_NAME, sizeof(name) - 1, name, nullptr);
  return name;
}
}  // namespace

std::vector<OpenClDeviceInfo> listOpenClDevices() {
  // Odometry nodelets in one manager build their estimators on their first frames, each on its own
  // thread: PoCL's first enumeration crashes when two run at once, so every caller takes turns.
  static std::mutex enumeration_mutex;
  std::lock_guard<std::mutex> lock(enumeration_mutex);
  std::vector<OpenClDeviceInfo> devices;
  cl_uint platform_count = 0;
  if (clGetPlatformIDs(0, nullptr, &platform_count) != CL_SUCCESS || platform_count == 0) return devices;
  std::vector<cl_platform_id> platforms(platform_count);
  clGetPlatformIDs(platform_count, platforms.data(), nullptr);
  for (cl_platform_id platform : platforms) {
    cl_uint device_count = 0;
    if (clGetDeviceIDs(platform, CL_DEVICE_TYPE_ALL, 0, nullptr, &device_count) != CL_SUCCESS) continue;
    std::vector<cl_device_id> ids(device_count);
    clGetDeviceIDs(platform, CL_DEVICE_TYPE_ALL, device_count, ids.data(), nullptr);
    for (cl_device_id id : ids) {
      cl_device_type type = 0;
      clGetDeviceInfo(id, CL_DEVICE_TYPE, sizeof(type), &type, nullptr);
      devices.push_back({platformName(platform), deviceName(id), (type & CL_DEVICE_TYPE_GPU) != 0,
                         (type & CL_DEVICE_TYPE_CPU) != 0, id});
    }
  }
  return devices;
}

std::size_t chooseOpenClDevice(const std::vector<OpenClDeviceInfo>& devices, const std::string& platform_filter,
                               const std::string& device_filter) {
  if (devices.empty()) {
    throw InputError(
        "OpenCL: no platform found (no ICD is installed or none loads; on Debian install pocl-opencl-icd for the "
        "CPU, or the GPU vendor's OpenCL driver)");
  }
  std::vector<std::size_t> matching;
  for (std::size_t i = 0; i < devices.size(); ++i) {
    if (lower(devices[i].platform).find(lower(platform_filter)) != std::string::npos &&
        lower(devices[i].device).find(lower(device_filter)) != std::string::npos) {
      matching.push_back(i);
    }
  }
  if (matching.empty()) {
    std::ostringstream message;
    message << "OpenCL: no device matches platform '" << platform_filter << "' and device '" << device_filter
            << "'; found:";
    for (const OpenClDeviceInfo& d : devices) message << " [" << d.platform << ": " << d.device << "]";
    throw InputError(message.str());
  }
  for (std::size_t i : matching)
    if (devices[i].is_gpu) return i;
  for (std::size_t i : matching)
    if (devices[i].is_cpu) return i;
  return matching.front();
}

}  // namespace vocal
