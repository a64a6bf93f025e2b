#pragma once
// Core types <-> ROS messages. Kept out of the core so the math never depends on ROS. Conversions
// from messages throw InputError naming `what` (the topic) and the problem.

#include <string>

#include <geometry_msgs/TransformStamped.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>
#include <Eigen/Geometry>

#include "vocal/core/colored_point.h"
#include "vocal/core/gravity.h"
#include "vocal/core/imu_samples.h"
#include "vocal/core/image.h"
#include "vocal/core/lens_distortion.h"
#include "vocal/core/pinhole_camera.h"
#include "vocal/core/rgbd_frame.h"

namespace vocal {

// With the lens's distortion_model and D (none: plumb_bob with zeros, as uncalibrated drivers publish).
sensor_msgs::CameraInfo toCameraInfo(const PinholeCamera& camera, const std::string& frame_id, const ros::Time& stamp,
                                     const LensDistortion& distortion = {});
sensor_msgs::Image toRgb8Image(const ColorImage& image, const std::string& frame_id, const ros::Time& stamp);
// bgr8: what openni2_camera publishes for colour.
sensor_msgs::Image toBgr8Image(const ColorImage& image, const std::string& frame_id, const ros::Time& stamp);
// mono8: the colour image's luma (ITU-R BT.601), as monochrome camera drivers publish.
sensor_msgs::Image toMono8Image(const ColorImage& image, const std::string& frame_id, const ros::Time& stamp);
// 32FC1 metres with NaN where there is no measurement (the TUM bags' and REP-118's convention).
sensor_msgs::Image toDepth32FImage(const DepthImage& depth, const std::string& frame_id, const ros::Time& stamp);
// 16UC1 whole millimetres with 0 where there is no measurement (openni2_camera's raw depth).
sensor_msgs::Image toDepth16UImage(const DepthImage& depth, const std::string& frame_id, const ros::Time& stamp);
// x, y, z float32 and rgb packed into a float32 (PCL's PointXYZRGB layout, what rviz colours by).
sensor_msgs::PointCloud2 toPointCloud2(const std::vector<ColoredPoint>& points, const std::string& frame_id,
                                       const ros::Time& stamp);
// What a Velodyne driver publishes (velodyne_pointcloud's PointXYZIR): x, y, z, intensity float32 and
// ring uint16 in 32-byte points; without `rings`, no ring field (a driver of a lidar without rings).
sensor_msgs::PointCloud2 toLidarPointCloud2(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& rings,
                                            const std::string& frame_id, const ros::Time& stamp);
geometry_msgs::TransformStamped toTransformStamped(const Eigen::Isometry3d& parent_from_child,
                                                   const std::string& parent, const std::string& child,
                                                   const ros::Time& stamp);

// rgb8, bgr8, rgba8, bgra8 or mono8 (grey copied to all three channels); a camera's raw Bayer mosaic
// (bayer_rggb8, bayer_bggr8, bayer_gbrg8, bayer_grbg8: demosaiced), YUV 4:2:2 (yuv422 - UYVY - and
// yuv422_yuy2) and mono16 (scaled by the image's brightest pixel) as RGB.
ColorImage fromColorImage(const sensor_msgs::Image& msg, const std::string& what);
// What image_transport's compressed transport publishes: a JPEG (quality 95) of the image's luma.
sensor_msgs::CompressedImage toCompressedJpeg(const ColorImage& image, const std::string& frame_id, const ros::Time& stamp);
// image_transport's compressed images (JPEG or PNG, colour or grey), as robots often record cameras.
ColorImage fromCompressedColorImage(const sensor_msgs::CompressedImage& msg, const std::string& what);
// Whether a topic is image_transport's compressed one (".../compressed"): subscribe CompressedImage there.
bool isCompressedImageTopic(const std::string& topic);
// 16UC1 millimetres (0 = none) or 32FC1 metres (NaN, inf or <= 0 = none); metres, 0 where none.
DepthImage fromDepthImage(const sensor_msgs::Image& msg, const std::string& what);
// Intrinsics from K; depth_scale 1000 (OpenNI millimetres). Refuses an uncalibrated (zero) K and
// binning or a region of interest.
PinholeCamera fromCameraInfo(const sensor_msgs::CameraInfo& msg, const std::string& what);
// The lens model of distortion_model and D (LensDistortion::fromCameraInfo's checks, naming `what`).
LensDistortion lensDistortionFromCameraInfo(const sensor_msgs::CameraInfo& msg, const std::string& what);
// The lens the odometry undoes: camera_info's D, or none (tracked as a pinhole) when it cannot be read;
// `problem` then says why and the caller says it once. Empty when the lens was read.
LensDistortion odometryLensFromCameraInfo(const sensor_msgs::CameraInfo& msg, const std::string& what, std::string* problem);
// The x, y, z (float32 or float64) of every finite point but the origin (a driver's no-return: NaN or
// all zeros in an organised cloud), in the cloud's frame. With `rings`, each of those
// points' `ring` field (the laser a spinning lidar's driver says it came from: velodyne, ouster and
// hesai drivers publish one, any integer type); left empty when the cloud has no such field.
std::vector<Eigen::Vector3d> fromPointCloud2(const sensor_msgs::PointCloud2& msg, const std::string& what,
                                             std::vector<int>* rings = nullptr);
// The scan's returns within [range_min, range_max] as points in its plane (z = 0), in beam order.
std::vector<Eigen::Vector3d> fromLaserScan(const sensor_msgs::LaserScan& msg, const std::string& what);
sensor_msgs::LaserScan toLaserScan(const std::vector<float>& ranges, double angle_min, double angle_increment,
                                   double range_max, const std::string& frame_id, const ros::Time& stamp);
// An accelerometer-only sensor_msgs/Imu (REP-145: orientation and angular velocity marked absent by a
// covariance of -1), as a Kinect's driver publishes its accelerometer.
sensor_msgs::Imu toAccelerometerImu(const AccelerometerSample& sample, const std::string& frame_id);
// Its linear acceleration; throws naming `what` when a value is not finite.
AccelerometerSample fromImuAcceleration(const sensor_msgs::Imu& msg, const std::string& what);
// Its angular velocity and linear acceleration (a gyro's message); throws naming `what` when a value is not finite.
ImuSample fromImuMessage(const sensor_msgs::Imu& msg, const std::string& what);
// A gyro + accelerometer sensor_msgs/Imu (orientation marked absent), as a RealSense driver publishes one.
sensor_msgs::Imu toImuMessage(const ImuSample& sample, const std::string& frame_id);
// One frame of registered images: depth and camera_info must match the colour image's size.
RgbdFrame toRgbdFrame(const sensor_msgs::Image& color, const sensor_msgs::Image& depth, const std::string& color_what,
                      const std::string& depth_what);

}  // namespace vocal
