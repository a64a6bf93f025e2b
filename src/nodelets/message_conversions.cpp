#include "vocal/nodelets/message_conversions.h"

#include <cstring>
#include <limits>

#include <sensor_msgs/image_encodings.h>

namespace vocal {

sensor_msgs::CameraInfo toCameraInfo(const PinholeCamera& camera, const std::string& frame_id, const ros::Time& stamp) {
  sensor_msgs::CameraInfo info;
  info.header.stamp = stamp;
  info.header.frame_id = frame_id;
  info.width = camera.width;
  info.height = camera.height;
  info.distortion_model = "plumb_bob";
  info.D.assign(5, 0.0);
  info.K = {camera.fx, 0.0, camera.cx, 0.0, camera.fy, camera.cy, 0.0, 0.0, 1.0};
  info.R = {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0};
  info.P = {camera.fx, 0.0, camera.cx, 0.0, 0.0, camera.fy, camera.cy, 0.0, 0.0, 0.0, 1.0, 0.0};
  return info;
}

sensor_msgs::Image toRgb8Image(const ColorImage& image, const std::string& frame_id, const ros::Time& stamp) {
  sensor_msgs::Image msg;
  msg.header.stamp = stamp;
  msg.header.frame_id = frame_id;
  msg.width = image.width();
  msg.height = image.height();
  msg.encoding = sensor_msgs::image_encodings::RGB8;
  msg.step = 3 * image.width();
  msg.data.resize(static_cast<std::size_t>(msg.step) * msg.height);
  static_assert(sizeof(Rgb8) == 3, "Rgb8 must be tightly packed");
  std::memcpy(msg.data.data(), image.data(), msg.data.size());
  return msg;
}

sensor_msgs::Image toDepth32FImage(const DepthImage& depth, const std::string& frame_id, const ros::Time& stamp) {
  sensor_msgs::Image msg;
  msg.header.stamp = stamp;
  msg.header.frame_id = frame_id;
  msg.width = depth.width();
  msg.height = depth.height();
  msg.encoding = sensor_msgs::image_encodings::TYPE_32FC1;
  msg.step = sizeof(float) * depth.width();
  msg.data.resize(static_cast<std::size_t>(msg.step) * msg.height);
  float* out = reinterpret_cast<float*>(msg.data.data());
  for (std::size_t i = 0; i < depth.size(); ++i) {
    out[i] = isValidDepth(depth.pixels()[i]) ? depth.pixels()[i] : std::numeric_limits<float>::quiet_NaN();
  }
  return msg;
}

geometry_msgs::TransformStamped toTransformStamped(const Eigen::Isometry3d& parent_from_child,
                                                   const std::string& parent, const std::string& child,
                                                   const ros::Time& stamp) {
  geometry_msgs::TransformStamped msg;
  msg.header.stamp = stamp;
  msg.header.frame_id = parent;
  msg.child_frame_id = child;
  const Eigen::Vector3d t = parent_from_child.translation();
  const Eigen::Quaterniond q(parent_from_child.rotation());
  msg.transform.translation.x = t.x();
  msg.transform.translation.y = t.y();
  msg.transform.translation.z = t.z();
  msg.transform.rotation.x = q.x();
  msg.transform.rotation.y = q.y();
  msg.transform.rotation.z = q.z();
  msg.transform.rotation.w = q.w();
  return msg;
}

}  // namespace vocal
