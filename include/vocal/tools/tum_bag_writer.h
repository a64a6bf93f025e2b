#pragma once
// Writes a TUM-layout folder as a rosbag in the TUM benchmark's own bag layout, so ROS tests and users
// can play real or synthetic sequences:
//   /camera/rgb/image_color   sensor_msgs/Image rgb8          frame openni_rgb_optical_frame
//   /camera/depth/image       sensor_msgs/Image 32FC1 metres  frame openni_depth_optical_frame (NaN = none)
//   /camera/rgb/camera_info, /camera/depth/camera_info (depth is registered: same intrinsics)
//   /tf        world -> kinect at every ground-truth stamp (kinect = the optical centre)
//   /tf_static kinect -> openni_rgb_optical_frame and openni_depth_optical_frame (identity), latched

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
  static constexpr const char* kWorldFrame = "world";
  static constexpr const char* kCameraFrame = "kinect";
};

struct TumBagSummary {
  std::size_t frames = 0;             // associated rgb + depth pairs written
  std::size_t ground_truth_poses = 0; // /tf messages
};

// Throws InputError naming the bag if it cannot be written, or the image that cannot be read.
TumBagSummary writeTumBag(const TumSequence& sequence, const std::string& bag_path,
                          const std::function<void(std::size_t, std::size_t)>& progress = nullptr);

}  // namespace vocal
