#pragma once
// OpenCL platform/device selection and program building, with errors that say what was found.
// Kept free of CL headers so only the backend's .cpp files include them.

#include <memory>
#include <string>
#include <vector>

namespace vocal {

struct OpenClDeviceInfo {
  std::string platform;
  std::string device;
  bool is_gpu = false;
  bool is_cpu = false;
  const void* handle = nullptr;  // the cl_device_id, opaque so this header needs no CL headers
};

// Every device of every platform; empty when there is no platform (no ICD installed). Safe to call
// from several threads at once (calls take turns).
std::vector<OpenClDeviceInfo> listOpenClDevices();

// Picks a device: with no filters the first GPU, else the first CPU device, else the first device;
// filters are case-insensitive substrings of the platform and device names. Returns the index into
// `devices`, or throws InputError listing what was found when nothing matches.
std::size_t chooseOpenClDevice(const std::vector<OpenClDeviceInfo>& devices, const std::string& platform_filter,
                               const std::string& device_filter);

}  // namespace vocal
