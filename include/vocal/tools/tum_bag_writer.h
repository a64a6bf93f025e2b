#pragma once
// Writes a TUM-layout folder as a rosbag, so ROS tests and users can play real or synthetic sequences.
// The TUM benchmark's own bag layout:
//   /camera/rgb/image_color   sensor_msgs/Image rgb8          frame openni_rgb_optical_frame
//   /camera/depth/image       sensor_msgs/Image 32FC1 metres  frame openni_depth_optical_frame (NaN = none)
//   /camera/rgb/camera_info, /camera/depth/camera_info (depth is registered: same intrinsics)
//   /imu       sensor_msgs/Imu, the Kinect's accelerometer (when the folder has accelerometer.txt), frame
//              openni_accelerometer_frame (x left, y up, z forward)
//   /tf        world -> kinect at every ground-truth stamp (kinect: the camera's body frame at the optical
//              centre, x forward, z up, REP-103)
//   /tf_static kinect -> openni_rgb_optical_frame, openni_depth_optical_frame (optical axes: z forward,
//              y down) and openni_accelerometer_frame, latched
// or what openni2_launch records from a Kinect / Xtion with depth registration on:
//   /camera/rgb/image_rect_color         bgr8                     frame camera_rgb_optical_frame
//   /camera/depth_registered/image_raw   16UC1 millimetres (0 = none), the same frame
//   /camera/rgb/camera_info, /camera/depth_registered/camera_info
//   /tf_static camera_link -> camera_rgb_optical_frame (REP-103 optical axes), latched; no ground truth

#include <cstddef>
#include <functional>
#include <string>

#include "vocal/core/tum_sequence.h"

namespace vocal {

struct TumBagTopics {
  static constexpr const char* kRgbImage = "/camera/rgb/image_color";
  static constexpr const char* kRgbInfo = "/camera/rgb/camera_info";
  static constexpr const char* kDepthImage = "/camera/depth/image";
  static constexpr const char* kDepthInfo = "/camera/depth/camera_info";
  static constexpr const char* kRgbFrame = "openni_rgb_optical_frame";
  static constexpr const char* kDepthFrame = "openni_depth_optical_frame";
  static constexpr const char* kImu = "/imu";
  static constexpr const char* kAccelerometerFrame = "openni_accelerometer_frame";
  static constexpr const char* kWorldFrame = "world";
  static constexpr const char* kCameraFrame = "kinect";
};

struct OpenNi2BagTopics {
  static constexpr const char* kRgbImage = "/camera/rgb/image_rect_color";
  static constexpr const char* kRgbInfo = "/camera/rgb/camera_info";
  static constexpr const char* kDepthImage = "/camera/depth_registered/image_raw";
  static constexpr const char* kDepthInfo = "/camera/depth_registered/camera_info";
  static constexpr const char* kOpticalFrame = "camera_rgb_optical_frame";
  static constexpr const char* kCameraFrame = "camera_link";
};

// An IMU with gyro (TumBagOptions::imu_folder), in either layout: where a RealSense driver publishes it.
constexpr const char* kImuTopic = "/camera/imu";

enum class BagLayout { kTum, kOpenNi2 };

struct TumBagOptions {
  BagLayout layout = BagLayout::kTum;
  // Streams to leave out (recordings with a stream missing, for tests of the readers' errors).
  bool without_depth = false;
  bool without_camera_info = false;
  // A folder with imu.txt and imu_extrinsics.yaml (simulate_imu): its samples on kImuTopic (gyro and
  // accelerometer, the IMU's frame) and the IMU's pose as a static transform from the colour optical frame.
  std::string imu_folder;
};

struct TumBagSummary {
  std::size_t frames = 0;             // associated rgb + depth pairs written
  std::size_t ground_truth_poses = 0; // /tf messages
  std::size_t accelerometer_samples = 0;  // /imu messages
  std::size_t imu_samples = 0;            // kImuTopic messages
};

// Throws InputError naming the bag if it cannot be written, or the image that cannot be read.
TumBagSummary writeTumBag(const TumSequence& sequence, const std::string& bag_path, const TumBagOptions& options = {},
                          const std::function<void(std::size_t, std::size_t)>& progress = nullptr);

BagLayout parseBagLayout(const std::string& name);  // tum, openni2

}  // namespace vocal
