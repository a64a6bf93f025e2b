#include "vocal/odometry/opencl_backend.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <vector>

#define CL_TARGET_OPENCL_VERSION 120
#include <CL/cl.h>

#include "vocal/core/errors.h"
#include "vocal/odometry/depth_noise_model.h"
#include "vocal/odometry/opencl_context.h"

namespace vocal {

extern const char* const kOdometryKernelSource;  // cl_kernels/odometry.cl, embedded at build time

bool openClBackendBuilt() { return true; }

namespace {
void check(cl_int status, const char* call) {
  if (status != CL_SUCCESS) {
    throw std::runtime_error(std::string("OpenCL: ") + call + " failed with error " + std::to_string(status));
  }
}

// Owns one cl_mem.
struct Buffer {
  cl_mem mem = nullptr;
  std::size_t bytes = 0;
  Buffer() = default;
  Buffer(cl_context context, std::size_t size, cl_mem_flags flags = CL_MEM_READ_WRITE) : bytes(size) {
    cl_int status = CL_SUCCESS;
    mem = clCreateBuffer(context, flags, size, nullptr, &status);
    check(status, "clCreateBuffer");
  }
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;
  Buffer(Buffer&& other) noexcept : mem(other.mem), bytes(other.bytes) { other.mem = nullptr; }
  Buffer& operator=(Buffer&& other) noexcept {
    std::swap(mem, other.mem);
    std::swap(bytes, other.bytes);
    return *this;
  }
  ~Buffer() {
    if (mem) clReleaseMemObject(mem);
  }
};

struct LevelBuffers {
  int width = 0, height = 0;
  Buffer depth, intensity, gradient_x, gradient_y, vertices, normals;
};

struct FrameBuffers {
  Buffer rgb, raw_depth, smoothed_depth, smoothed_vertices;
  std::vector<LevelBuffers> levels;
};

// Bytes of __local memory for a kernel argument.
struct LocalBytes {
  std::size_t bytes;
};

template <typename T>
void setArg(cl_kernel kernel, cl_uint index, const T& value) {
  check(clSetKernelArg(kernel, index, sizeof(T), &value), "clSetKernelArg");
}
void setArg(cl_kernel kernel, cl_uint index, const Buffer& buffer) { setArg(kernel, index, buffer.mem); }
void setArg(cl_kernel kernel, cl_uint index, const LocalBytes& local) {
  check(clSetKernelArg(kernel, index, local.bytes, nullptr), "clSetKernelArg(local)");
}

// Sets every argument of a kernel in order.
template <typename... Args>
void setArgs(cl_kernel kernel, const Args&... args) {
  cl_uint index = 0;
  (setArg(kernel, index++, args), ...);
}

std::size_t roundUp(std::size_t value, std::size_t multiple) { return (value + multiple - 1) / multiple * multiple; }
}  // namespace

struct OpenClOdometryBackend::State {
  PinholeCamera camera;
  OdometryConfig config;
  OpenClDeviceInfo device_info;
  cl_context context = nullptr;
  cl_command_queue queue = nullptr;
  cl_program program = nullptr;
  cl_kernel intensity_from_rgb = nullptr, sanitize_depth = nullptr, smooth_depth = nullptr, downsample_depth = nullptr,
            downsample_intensity = nullptr, gradients = nullptr, vertex_map = nullptr, normal_map = nullptr,
            icp_rows = nullptr, dvo_rows = nullptr;
  std::array<FrameBuffers, 2> frames;
  int current = 0;
  Buffer pose, partials;
  std::size_t local_size = 128, groups = 64;
  std::vector<float> partials_host;

  ~State() {
    for (cl_kernel k : {intensity_from_rgb, sanitize_depth, smooth_depth, downsample_depth, downsample_intensity,
                        gradients, vertex_map, normal_map, icp_rows, dvo_rows}) {
      if (k) clReleaseKernel(k);
    }
    frames = {};
    pose = Buffer();
    partials = Buffer();
    if (program) clReleaseProgram(program);
    if (queue) clReleaseCommandQueue(queue);
    if (context) clReleaseContext(context);
  }

  void run2d(cl_kernel kernel, int width, int height) {
    const std::size_t global[2] = {roundUp(width, 16), roundUp(height, 16)};
    const std::size_t local[2] = {16, 16};
    check(clEnqueueNDRangeKernel(queue, kernel, 2, nullptr, global, local, 0, nullptr, nullptr), "clEnqueueNDRangeKernel");
  }

  void run1d(cl_kernel kernel, std::size_t items) {
    const std::size_t global = roundUp(items, 256);
    check(clEnqueueNDRangeKernel(queue, kernel, 1, nullptr, &global, nullptr, 0, nullptr, nullptr),
          "clEnqueueNDRangeKernel");
  }

  cl_kernel makeKernel(const char* name) {
    cl_int status = CL_SUCCESS;
    cl_kernel kernel = clCreateKernel(program, name, &status);
    check(status, name);
    return kernel;
  }

  void uploadPose(const Eigen::Isometry3d& T) {
    std::array<float, 12> values{};
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) values[r * 3 + c] = static_cast<float>(T.linear()(r, c));
      values[9 + r] = static_cast<float>(T.translation()[r]);
    }
    check(clEnqueueWriteBuffer(queue, pose.mem, CL_TRUE, 0, sizeof(values), values.data(), 0, nullptr, nullptr),
          "clEnqueueWriteBuffer(pose)");
  }

  cl_float4 levelCamera(int level) const {
    const PinholeCamera c = pyramidLevelCamera(camera, level);
    return cl_float4{{static_cast<float>(c.fx), static_cast<float>(c.fy), static_cast<float>(c.cx), static_cast<float>(c.cy)}};
  }

  // Runs a row kernel over `items` pixels and adds the groups' partial sums in double.
  NormalEquations reduce(cl_kernel kernel, std::size_t items) {
    const std::size_t used_groups = std::min(groups, std::max<std::size_t>(1, (items + local_size - 1) / local_size));
    const std::size_t global = used_groups * local_size;
    check(clEnqueueNDRangeKernel(queue, kernel, 1, nullptr, &global, &local_size, 0, nullptr, nullptr),
          "clEnqueueNDRangeKernel(rows)");
    check(clEnqueueReadBuffer(queue, partials.mem, CL_TRUE, 0, used_groups * kReductionValues * sizeof(float),
                              partials_host.data(), 0, nullptr, nullptr),
          "clEnqueueReadBuffer(partials)");
    std::array<double, kReductionValues> total{};
    for (std::size_t g = 0; g < used_groups; ++g) {
      for (int k = 0; k < kReductionValues; ++k) total[k] += partials_host[g * kReductionValues + k];
    }
    return NormalEquations::fromPacked(total.data());
  }
};

OpenClOdometryBackend::OpenClOdometryBackend(const PinholeCamera& camera, const OdometryConfig& config)
    : state_(std::make_unique<State>()) {
  // Two estimators in one process (two odometry nodelets in one manager) may be built at once: the
  // context and program build are serialised (the enumeration is, in listOpenClDevices), as not every
  // OpenCL implementation makes them thread-safe.
  static std::mutex setup_mutex;
  std::lock_guard<std::mutex> setup_lock(setup_mutex);
  State& s = *state_;
  s.camera = camera;
  s.config = config;
  const std::vector<OpenClDeviceInfo> devices = listOpenClDevices();
  const std::size_t chosen = chooseOpenClDevice(devices, config.opencl_platform, config.opencl_device);
  s.device_info = devices[chosen];

  cl_device_id device = static_cast<cl_device_id>(const_cast<void*>(s.device_info.handle));
  cl_int status = CL_SUCCESS;
  s.context = clCreateContext(nullptr, 1, &device, nullptr, nullptr, &status);
  check(status, "clCreateContext");
  s.queue = clCreateCommandQueue(s.context, device, 0, &status);
  check(status, "clCreateCommandQueue");
  const char* source = kOdometryKernelSource;
  s.program = clCreateProgramWithSource(s.context, 1, &source, nullptr, &status);
  check(status, "clCreateProgramWithSource");
  if (clBuildProgram(s.program, 1, &device, "-cl-std=CL1.2", nullptr, nullptr) != CL_SUCCESS) {
    std::size_t log_size = 0;
    clGetProgramBuildInfo(s.program, device, CL_PROGRAM_BUILD_LOG, 0, nullptr, &log_size);
    std::string log(log_size, '\0');
    clGetProgramBuildInfo(s.program, device, CL_PROGRAM_BUILD_LOG, log_size, &log[0], nullptr);
    throw InputError("OpenCL: cl_kernels/odometry.cl does not build on " + s.device_info.device + ":\n" + log);
  }
  s.intensity_from_rgb = s.makeKernel("intensity_from_rgb");
  s.sanitize_depth = s.makeKernel("sanitize_depth");
  s.smooth_depth = s.makeKernel("smooth_depth");
  s.downsample_depth = s.makeKernel("downsample_depth");
  s.downsample_intensity = s.makeKernel("downsample_intensity");
  s.gradients = s.makeKernel("gradients");
  s.vertex_map = s.makeKernel("vertex_map");
  s.normal_map = s.makeKernel("normal_map");
  s.icp_rows = s.makeKernel("icp_rows");
  s.dvo_rows = s.makeKernel("dvo_rows");

  std::size_t max_group = 0;
  clGetKernelWorkGroupInfo(s.icp_rows, device, CL_KERNEL_WORK_GROUP_SIZE, sizeof(max_group), &max_group, nullptr);
  while (s.local_size > max_group && s.local_size > 1) s.local_size /= 2;
  cl_uint compute_units = 1;
  clGetDeviceInfo(device, CL_DEVICE_MAX_COMPUTE_UNITS, sizeof(compute_units), &compute_units, nullptr);
  s.groups = std::max<std::size_t>(32, 8 * static_cast<std::size_t>(compute_units));

  const std::size_t pixels = static_cast<std::size_t>(camera.width) * camera.height;
  for (FrameBuffers& frame : s.frames) {
    frame.rgb = Buffer(s.context, pixels * 3, CL_MEM_READ_ONLY);
    frame.raw_depth = Buffer(s.context, pixels * sizeof(float), CL_MEM_READ_ONLY);
    frame.smoothed_depth = Buffer(s.context, pixels * sizeof(float));
    frame.smoothed_vertices = Buffer(s.context, pixels * sizeof(cl_float4));
    frame.levels.resize(config.levels);
    for (int level = 0; level < config.levels; ++level) {
      LevelBuffers& l = frame.levels[level];
      l.width = camera.width >> level;
      l.height = camera.height >> level;
      const std::size_t n = static_cast<std::size_t>(l.width) * l.height;
      l.depth = Buffer(s.context, n * sizeof(float));
      l.intensity = Buffer(s.context, n * sizeof(float));
      l.gradient_x = Buffer(s.context, n * sizeof(float));
      l.gradient_y = Buffer(s.context, n * sizeof(float));
      l.vertices = Buffer(s.context, n * sizeof(cl_float4));
      l.normals = Buffer(s.context, n * sizeof(cl_float4));
    }
  }
  s.pose = Buffer(s.context, 12 * sizeof(float), CL_MEM_READ_ONLY);
  s.partials = Buffer(s.context, s.groups * kReductionValues * sizeof(float));
  s.partials_host.resize(s.groups * kReductionValues);
}

OpenClOdometryBackend::~OpenClOdometryBackend() = default;

std::string OpenClOdometryBackend::name() const {
  return "opencl: " + state_->device_info.device + " (" + state_->device_info.platform + ")";
}

void OpenClOdometryBackend::pushFrame(const RgbdFrame& frame, ReferenceUpdate update) {
  State& s = *state_;
  if (update == ReferenceUpdate::kPreviousFrame) s.current = 1 - s.current;
  FrameBuffers& f = s.frames[s.current];
  const int pixels = s.camera.width * s.camera.height;
  check(clEnqueueWriteBuffer(s.queue, f.rgb.mem, CL_TRUE, 0, f.rgb.bytes, frame.color.data(), 0, nullptr, nullptr),
        "clEnqueueWriteBuffer(rgb)");
  check(clEnqueueWriteBuffer(s.queue, f.raw_depth.mem, CL_TRUE, 0, f.raw_depth.bytes, frame.depth.data(), 0, nullptr,
                             nullptr),
        "clEnqueueWriteBuffer(depth)");

  LevelBuffers& base = f.levels[0];
  setArgs(s.intensity_from_rgb, f.rgb, base.intensity, pixels);
  s.run1d(s.intensity_from_rgb, pixels);
  setArgs(s.sanitize_depth, f.raw_depth, base.depth, static_cast<float>(s.config.min_depth),
          static_cast<float>(s.config.max_depth), pixels);
  s.run1d(s.sanitize_depth, pixels);

  for (int level = 0; level < s.config.levels; ++level) {
    LevelBuffers& l = f.levels[level];
    if (level > 0) {
      const LevelBuffers& above = f.levels[level - 1];
      setArgs(s.downsample_depth, above.depth, above.width, above.height, l.depth, l.width, l.height,
              static_cast<float>(3.0 * s.config.depth_pyramid_sigma));
      s.run2d(s.downsample_depth, l.width, l.height);
      setArgs(s.downsample_intensity, above.intensity, above.width, above.height, l.intensity, l.width, l.height);
      s.run2d(s.downsample_intensity, l.width, l.height);
    }
    setArgs(s.gradients, l.intensity, l.width, l.height, l.gradient_x, l.gradient_y);
    s.run2d(s.gradients, l.width, l.height);
    const PinholeCamera c = pyramidLevelCamera(s.camera, level);
    const float fx_inv = static_cast<float>(1.0 / c.fx), fy_inv = static_cast<float>(1.0 / c.fy);
    const float cx = static_cast<float>(c.cx), cy = static_cast<float>(c.cy);
    setArgs(s.vertex_map, l.depth, l.width, l.height, fx_inv, fy_inv, cx, cy, l.vertices);
    s.run2d(s.vertex_map, l.width, l.height);
    const bool smooth_normals = level == 0 && s.config.depth_smoothing_radius > 0;
    if (smooth_normals) {
      // Normals from smoothed depth, points from raw depth (see frame_pyramid.cpp).
      setArgs(s.smooth_depth, l.depth, f.smoothed_depth, l.width, l.height, s.config.depth_smoothing_radius,
              static_cast<float>(s.config.depth_smoothing_factor));
      s.run2d(s.smooth_depth, l.width, l.height);
      setArgs(s.vertex_map, f.smoothed_depth, l.width, l.height, fx_inv, fy_inv, cx, cy, f.smoothed_vertices);
      s.run2d(s.vertex_map, l.width, l.height);
    }
    setArgs(s.normal_map, smooth_normals ? f.smoothed_vertices : l.vertices, l.width, l.height, l.normals);
    s.run2d(s.normal_map, l.width, l.height);
  }
}

NormalEquations OpenClOdometryBackend::icpSystem(int level, const Eigen::Isometry3d& reference_from_current) {
  State& s = *state_;
  const LevelBuffers& cur = s.frames[s.current].levels.at(level);
  const LevelBuffers& ref = s.frames[1 - s.current].levels.at(level);
  s.uploadPose(reference_from_current);
  const DepthNoiseModel noise(s.config.depth_noise_floor, s.config.depth_noise_quadratic);
  const cl_float4 depth_noise{{2.0f * noise.floor_squared, noise.quadratic_squared, noise.variance_at_one_metre, 0.0f}};
  setArgs(s.icp_rows, cur.vertices, cur.normals, ref.vertices, ref.normals, cur.width, cur.height, s.pose,
          s.levelCamera(level), static_cast<float>(s.config.icp_max_distance),
          static_cast<float>(std::cos(s.config.icp_max_angle_deg * M_PI / 180.0)), depth_noise,
          LocalBytes{kReductionValues * s.local_size * sizeof(float)}, s.partials);
  return s.reduce(s.icp_rows, static_cast<std::size_t>(cur.width) * cur.height);
}

NormalEquations OpenClOdometryBackend::rgbSystem(int level, const Eigen::Isometry3d& reference_from_current,
                                                 double huber_threshold, const BrightnessTransfer& brightness) {
  State& s = *state_;
  const LevelBuffers& cur = s.frames[s.current].levels.at(level);
  const LevelBuffers& ref = s.frames[1 - s.current].levels.at(level);
  s.uploadPose(reference_from_current);
  const cl_float4 limits{{static_cast<float>(s.config.rgb_max_depth), static_cast<float>(s.config.rgb_max_depth_difference),
                          static_cast<float>(s.config.rgb_min_gradient.at(level)), static_cast<float>(huber_threshold)}};
  setArgs(s.dvo_rows, cur.vertices, cur.intensity, ref.depth, ref.intensity, ref.gradient_x, ref.gradient_y, cur.width,
          cur.height, s.pose, s.levelCamera(level), limits, cl_float2{{brightness.gain, brightness.bias}}, LocalBytes{kReductionValues * s.local_size * sizeof(float)},
          s.partials);
  return s.reduce(s.dvo_rows, static_cast<std::size_t>(cur.width) * cur.height);
}

std::size_t OpenClOdometryBackend::memoryBytes() const {
  std::size_t bytes = state_->pose.bytes + state_->partials.bytes;
  for (const FrameBuffers& f : state_->frames) {
    bytes += f.rgb.bytes + f.raw_depth.bytes + f.smoothed_depth.bytes + f.smoothed_vertices.bytes;
    for (const LevelBuffers& l : f.levels) {
      bytes += l.depth.bytes + l.intensity.bytes + l.gradient_x.bytes + l.gradient_y.bytes + l.vertices.bytes +
               l.normals.bytes;
    }
  }
  return bytes;
}

}  // namespace vocal
