#include "fuzz_targets.h"

#include <unistd.h>

#include <cmath>
#include <fstream>
#include <stdexcept>
#include <sys/stat.h>

#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>

#include "fuzz_input_reader.h"
#include "vocal/calibration/rig_description.h"
#include "vocal/core/camera_yaml.h"
#include "vocal/core/errors.h"
#include "vocal/core/lens_distortion.h"
#include "vocal/core/tum_sequence.h"
#include "vocal/core/tum_trajectory.h"
#include "vocal/nodelets/message_conversions.h"
#include "vocal/nodelets/parameter_yaml.h"
#include "vocal/odometry/odometry_config_yaml.h"

namespace vocal_fuzz {
namespace {

// A folder of this process's own, so parallel fuzzers and test runs never share a file.
const std::string& scratchFolder() {
  static const std::string folder = [] {
    struct stat info {};
    const std::string base = stat("/dev/shm", &info) == 0 ? "/dev/shm" : "/tmp";
    std::string path = base + "/vocal_fuzz_" + std::to_string(getpid());
    mkdir(path.c_str(), 0700);
    // A listed image that exists, so TUM lists that name it get past the existence check.
    mkdir((path + "/rgb").c_str(), 0700);
    std::ofstream(path + "/rgb/1.png") << "";
    return path;
  }();
  return folder;
}

std::string writeScratchFile(const std::string& name, const std::uint8_t* data, std::size_t size) {
  const std::string path = scratchFolder() + "/" + name;
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  file.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

// Runs `parse`; InputError is the refusal the contract allows, everything else escapes.
template <typename Parse>
void refusedOrTaken(Parse parse) {
  try {
    parse();
  } catch (const vocal::InputError&) {
  }
}

// A broken promise of a conversion's contract: a finding, like a crash.
void require(bool condition, const char* promise) {
  if (!condition) throw std::logic_error(std::string("contract broken: ") + promise);
}

void rigYaml(const std::uint8_t* data, std::size_t size) {
  const std::string path = writeScratchFile("rig.yaml", data, size);
  refusedOrTaken([&] { vocal::readRigDescription(path); });
}

void odometryConfigYaml(const std::uint8_t* data, std::size_t size) {
  const std::string path = writeScratchFile("odometry.yaml", data, size);
  refusedOrTaken([&] { vocal::readOdometryConfigYaml(path); });
}

void cameraYaml(const std::uint8_t* data, std::size_t size) {
  const std::string path = writeScratchFile("camera.yaml", data, size);
  refusedOrTaken([&] {
    const vocal::PinholeCamera camera = vocal::readCameraYaml(path);
    require(camera.width > 0 && camera.height > 0 && std::isfinite(camera.fx) && camera.fx > 0.0,
            "readCameraYaml returns a valid camera");
  });
}

void tumTrajectory(const std::uint8_t* data, std::size_t size) {
  const std::string path = writeScratchFile("trajectory.txt", data, size);
  refusedOrTaken([&] {
    const vocal::Trajectory trajectory = vocal::readTumTrajectory(path);
    for (std::size_t i = 0; i < trajectory.size(); ++i) {
      require(std::isfinite(trajectory[i].stamp) && trajectory[i].pose.matrix().allFinite(), "finite poses");
      require(i == 0 || trajectory[i].stamp > trajectory[i - 1].stamp, "increasing stamps");
    }
  });
}

void tumImageList(const std::uint8_t* data, std::size_t size) {
  const std::string path = writeScratchFile("rgb.txt", data, size);
  refusedOrTaken([&] {
    const std::vector<vocal::TumListEntry> entries = vocal::readTumImageList(path, scratchFolder());
    for (std::size_t i = 1; i < entries.size(); ++i) require(entries[i].stamp > entries[i - 1].stamp, "increasing stamps");
  });
}

// An image message of any layout: size, step and encoding need not agree with the data.
sensor_msgs::Image takeImage(FuzzInputReader& in, std::size_t max_data) {
  sensor_msgs::Image msg;
  msg.height = in.take<std::uint32_t>();
  msg.width = in.take<std::uint32_t>();
  msg.step = in.take<std::uint32_t>();
  msg.is_bigendian = in.take<std::uint8_t>() & 1;
  msg.encoding = in.takeChoice({"rgb8", "bgr8", "rgba8", "bgra8", "mono8", "16UC1", "32FC1", "mono16", "8UC3", "yuv422",
                                "bayer_rggb8", "64FC1"});
  const std::size_t wanted = in.take<std::uint32_t>() % (max_data + 1);  // before remaining(): it consumes bytes
  const std::size_t bytes = std::min(wanted, in.remaining());
  for (std::size_t i = 0; i < bytes; ++i) msg.data.push_back(in.take<std::uint8_t>());
  return msg;
}

void imageMessages(const std::uint8_t* data, std::size_t size) {
  FuzzInputReader in(data, size);
  const sensor_msgs::Image color = takeImage(in, size / 2);
  const sensor_msgs::Image depth = takeImage(in, size);
  refusedOrTaken([&] {
    const vocal::ColorImage image = vocal::fromColorImage(color, "/camera/rgb/image_raw");
    require(image.width() == static_cast<int>(color.width) && image.height() == static_cast<int>(color.height),
            "the colour image has the message's size");
  });
  refusedOrTaken([&] {
    const vocal::DepthImage image = vocal::fromDepthImage(depth, "/camera/depth/image_raw");
    for (int y = 0; y < image.height(); ++y)
      for (int x = 0; x < image.width(); ++x) require(std::isfinite(image(x, y)) && image(x, y) >= 0.0f, "depth >= 0");
  });
  refusedOrTaken([&] { vocal::toRgbdFrame(color, depth, "/camera/rgb/image_raw", "/camera/depth/image_raw"); });
  refusedOrTaken([&] {  // the colour message's bytes as image_transport's compressed image
    sensor_msgs::CompressedImage compressed;
    compressed.format = "jpeg";
    compressed.data = color.data;
    const vocal::ColorImage image = vocal::fromCompressedColorImage(compressed, "/camera/rgb/image_raw/compressed");
    require(image.width() > 0 && image.height() > 0, "a decoded image has pixels");
  });
}

void cameraInfoMessage(const std::uint8_t* data, std::size_t size) {
  FuzzInputReader in(data, size);
  sensor_msgs::CameraInfo msg;
  msg.width = in.take<std::uint32_t>();
  msg.height = in.take<std::uint32_t>();
  msg.distortion_model = in.takeChoice({"plumb_bob", "rational_polynomial", "equidistant", "fisheye", ""});
  msg.D.resize(in.take<std::uint8_t>() % 16);
  for (double& k : msg.D) k = in.take<double>();
  for (double& k : msg.K) k = in.take<double>();
  msg.binning_x = in.take<std::uint8_t>() % 3;
  msg.binning_y = in.take<std::uint8_t>() % 3;
  msg.roi.width = in.take<std::uint8_t>() % 2;
  refusedOrTaken([&] {
    const vocal::PinholeCamera camera = vocal::fromCameraInfo(msg, "/camera/rgb/camera_info");
    require(camera.width > 0 && camera.height > 0 && std::isfinite(camera.fx) && std::isfinite(camera.cy),
            "fromCameraInfo returns a valid camera");
  });
  refusedOrTaken([&] {
    const vocal::LensDistortion lens = vocal::lensDistortionFromCameraInfo(msg, "/camera/rgb/camera_info");
    for (double k : lens.coefficients) require(std::isfinite(k), "finite distortion coefficients");
    // Undistorting iterates: it must end for any coefficients the check let through.
    for (double r : {0.0, 0.3, 1.0, 3.0}) lens.undistort(Eigen::Vector2d(r, -0.5 * r));
  });
}

void pointCloud2Message(const std::uint8_t* data, std::size_t size) {
  FuzzInputReader in(data, size);
  sensor_msgs::PointCloud2 msg;
  msg.fields.resize(in.take<std::uint8_t>() % 8);
  for (sensor_msgs::PointField& field : msg.fields) {
    field.name = in.takeChoice({"x", "y", "z", "ring", "intensity", "rgb"});
    const std::uint8_t wide = in.take<std::uint8_t>();
    field.offset = wide & 0x80 ? in.take<std::uint32_t>() : wide & 0x3f;
    field.datatype = in.take<std::uint8_t>() % 10;
    field.count = 1;
  }
  // Small sizes mostly (so clouds that fit the data are found), any 32-bit value sometimes.
  auto size_field = [&in] {
    const std::uint8_t wide = in.take<std::uint8_t>();
    return wide & 0x80 ? in.take<std::uint32_t>() : static_cast<std::uint32_t>(wide);
  };
  msg.height = size_field();
  msg.width = size_field();
  msg.point_step = size_field();
  msg.row_step = size_field();
  msg.is_bigendian = in.take<std::uint8_t>() & 1;
  msg.data = in.takeRest();
  refusedOrTaken([&] {
    std::vector<int> rings;
    const std::vector<Eigen::Vector3d> points = vocal::fromPointCloud2(msg, "/velodyne_points", &rings);
    for (const Eigen::Vector3d& p : points) require(p.allFinite(), "finite points");
    require(rings.empty() || rings.size() == points.size(), "a ring for every point or none");
  });
}

void laserScanMessage(const std::uint8_t* data, std::size_t size) {
  FuzzInputReader in(data, size);
  sensor_msgs::LaserScan msg;
  msg.angle_min = in.take<float>();
  msg.angle_max = in.take<float>();
  msg.angle_increment = in.take<float>();
  msg.range_min = in.take<float>();
  msg.range_max = in.take<float>();
  while (in.remaining() >= sizeof(float)) msg.ranges.push_back(in.take<float>());
  refusedOrTaken([&] {
    const std::vector<Eigen::Vector3d> points = vocal::fromLaserScan(msg, "/scan");
    for (const Eigen::Vector3d& p : points) require(p.allFinite(), "finite points");
  });
}

// Odometry settings' names and a few of the nodelet's own: the keys parameters mostly take.
const std::vector<std::string> kParameterNames = {
    "mode", "levels", "iterations", "icp_max_distance", "rgb_weight", "rgb_min_gradient", "tracking_reference",
    "keyframes_kept", "backend", "threads", "cpu_threads", "max_depth", "convergence_translation", "feature_initialisation",
    "frame_id", "approx_sync", "depth_noise_quadratic", "keyframe_after_unconverged"};

// A nodelet's private parameters as rosparam hands them over: any nesting of XmlRpc values, keys
// mostly the odometry settings' names.
XmlRpc::XmlRpcValue takeParameter(FuzzInputReader& in, int depth) {
  switch (in.take<std::uint8_t>() % (depth < 3 ? 6 : 4)) {
    case 0: return XmlRpc::XmlRpcValue(static_cast<bool>(in.take<std::uint8_t>() & 1));
    case 1: return XmlRpc::XmlRpcValue(in.take<int>());
    case 2: return XmlRpc::XmlRpcValue(in.take<double>());
    case 3: return XmlRpc::XmlRpcValue(in.takeChoice({"fused", "icp", "rgb", "keyframe", "frame", "auto", "opencl", "nan", "1e400"}));
    case 4: {
      XmlRpc::XmlRpcValue list;
      list.setSize(in.take<std::uint8_t>() % 5);
      for (int i = 0; i < list.size(); ++i) list[i] = takeParameter(in, depth + 1);
      return list;
    }
    default: {
      XmlRpc::XmlRpcValue map;
      map.begin();  // an empty struct, not an invalid value
      const int entries = in.take<std::uint8_t>() % 6;
      for (int i = 0; i < entries && in.remaining() > 0; ++i) {
        const std::string key = in.takeChoice(kParameterNames);
        map[key] = takeParameter(in, depth + 1);
      }
      return map;
    }
  }
}

void odometryParameters(const std::uint8_t* data, std::size_t size) {
  FuzzInputReader in(data, size);
  XmlRpc::XmlRpcValue parameters;
  parameters.begin();
  while (in.remaining() > 0) {
    const std::string key = in.takeChoice(kParameterNames);
    parameters[key] = takeParameter(in, 1);
  }
  refusedOrTaken([&] {
    vocal::odometryConfigFromYaml(vocal::toYaml(parameters), "parameters of /camera/icp_dvo_odometry", vocal::OdometryConfig{}, true);
  });
}

}  // namespace

const std::vector<FuzzTarget>& fuzzTargets() {
  static const std::vector<FuzzTarget> targets = {
      {"rig_yaml", "rig description YAML (readRigDescription)", rigYaml},
      {"odometry_config_yaml", "odometry config YAML (readOdometryConfigYaml)", odometryConfigYaml},
      {"camera_yaml", "camera.yaml, ROS camera_info layout (readCameraYaml)", cameraYaml},
      {"tum_trajectory", "TUM trajectory text (readTumTrajectory)", tumTrajectory},
      {"tum_image_list", "TUM rgb.txt / depth.txt (readTumImageList)", tumImageList},
      {"image_messages", "Image -> colour, depth, RGB-D frame; CompressedImage -> colour (fromColorImage, fromDepthImage, toRgbdFrame, fromCompressedColorImage)",
       imageMessages},
      {"camera_info_message", "CameraInfo -> camera and lens (fromCameraInfo, lensDistortionFromCameraInfo)",
       cameraInfoMessage},
      {"point_cloud2_message", "PointCloud2 with any fields, strides, sizes (fromPointCloud2)", pointCloud2Message},
      {"laser_scan_message", "LaserScan with NaN / inf / empty ranges (fromLaserScan)", laserScanMessage},
      {"odometry_parameters", "the odometry nodelet's private parameters, any XmlRpc nesting (toYaml, odometryConfigFromYaml)",
       odometryParameters},
  };
  return targets;
}

const FuzzTarget* findFuzzTarget(const std::string& name) {
  for (const FuzzTarget& target : fuzzTargets())
    if (name == target.name) return &target;
  return nullptr;
}

}  // namespace vocal_fuzz
