#pragma once
// Core types -> ROS messages. Kept out of the core so the math never depends on ROS.

#include <string>

#include <geometry_msgs/TransformStamped.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <Eigen/Geometry>

#include "vocal/core/image.h"
#include "vocal/core/pinhole_camera.h"

namespace vocal {

sensor_msgs::CameraInfo toCameraInfo(const PinholeCamera& camera, const std::string& frame_id, const ros::Time& stamp);
sensor_msgs::Image toRgb8Image(const ColorImage& image, const std::string& frame_id, const ros::Time& stamp);
// 32FC1 metres with NaN where there is no measurement (the TUM bags' and REP-118's convention).
sensor_msgs::Image toDepth32FImage(const DepthImage& depth, const std::string& frame_id, const ros::Time& stamp);
geometry_msgs::TransformStamped toTransformStamped(const Eigen::Isometry3d& parent_from_child,
                                                   const std::string& parent, const std::string& child,
                                                   const ros::Time& stamp);

}  // namespace vocal
