#include "vocal/tools/tum_bag_writer.h"

#include "vocal/core/imu_samples.h"

#include <rosbag/bag.h>
#include <tf2_msgs/TFMessage.h>

#include "vocal/core/errors.h"
#include "vocal/core/se3.h"
#include "vocal/nodelets/message_conversions.h"
#include "vocal/tools/bag_file.h"

namespace vocal {

namespace {
// /tf_static is latched: a custom connection header replaces rosbag's own, so it carries the type too.
void writeStaticTransforms(rosbag::Bag* bag, const tf2_msgs::TFMessage& transforms, const ros::Time& stamp) {
  auto latched = boost::make_shared<ros::M_string>();
  (*latched)["type"] = ros::message_traits::DataType<tf2_msgs::TFMessage>::value();
  (*latched)["md5sum"] = ros::message_traits::MD5Sum<tf2_msgs::TFMessage>::value();
  (*latched)["message_definition"] = ros::message_traits::Definition<tf2_msgs::TFMessage>::value();
  (*latched)["latching"] = "1";
  (*latched)["callerid"] = "/vocal_tum_to_bag";
  bag->write("/tf_static", stamp, transforms, latched);
}

// What differs between the layouts: topics, frames, encodings and the static transforms.
struct LayoutSpec {
  const char *rgb_image, *rgb_info, *depth_image, *depth_info, *rgb_frame, *depth_frame;
  sensor_msgs::Image (*color)(const ColorImage&, const std::string&, const ros::Time&);
  sensor_msgs::Image (*depth)(const DepthImage&, const std::string&, const ros::Time&);
  std::vector<std::pair<std::string, Eigen::Isometry3d>> static_transforms;  // parent -> child frame
  const char* static_parent;
};

// REP-103: the optical frame looks along z with x right and y down; the camera's body frame has x
// forward, y left, z up.
Eigen::Isometry3d bodyFromOptical() {
  Eigen::Isometry3d body_from_optical = Eigen::Isometry3d::Identity();
  body_from_optical.linear() = bodyFromOpticalRotation();
  return body_from_optical;
}

LayoutSpec layoutSpec(BagLayout layout) {
  if (layout == BagLayout::kTum) {
    using T = TumBagTopics;
    Eigen::Isometry3d body_from_accelerometer = bodyFromOptical();
    body_from_accelerometer.linear() *= opticalFromKinectAccelerometer();
    return {T::kRgbImage, T::kRgbInfo, T::kDepthImage, T::kDepthInfo, T::kRgbFrame, T::kDepthFrame,
            &toRgb8Image, &toDepth32FImage,
            {{T::kRgbFrame, bodyFromOptical()}, {T::kDepthFrame, bodyFromOptical()},
             {T::kAccelerometerFrame, body_from_accelerometer}},
            T::kCameraFrame};
  }
  using T = OpenNi2BagTopics;
  return {T::kRgbImage, T::kRgbInfo, T::kDepthImage, T::kDepthInfo, T::kOpticalFrame, T::kOpticalFrame,
          &toBgr8Image, &toDepth16UImage, {{T::kOpticalFrame, bodyFromOptical()}}, T::kCameraFrame};
}

void writeFrames(const TumSequence& sequence, const TumBagOptions& options, rosbag::Bag* bag,
                 const std::function<void(std::size_t, std::size_t)>& progress, TumBagSummary* summary) {
  const LayoutSpec spec = layoutSpec(options.layout);
  const PinholeCamera& camera = sequence.camera();
  // The folder's lens (TUM's published D for freiburg1/2): its images are not undistorted, and a
  // camera_info without it would have the odometry take them as a pinhole's.
  const LensDistortion& lens = sequence.lens();
  const ros::Time first_stamp(sequence.entry(0).rgb.stamp);
  tf2_msgs::TFMessage static_transforms;
  for (const auto& [child, parent_from_child] : spec.static_transforms)
    static_transforms.transforms.push_back(toTransformStamped(parent_from_child, spec.static_parent, child, first_stamp));
  if (!options.imu_folder.empty()) {
    const ImuExtrinsics imu = readImuExtrinsics(options.imu_folder + "/imu_extrinsics.yaml");
    static_transforms.transforms.push_back(toTransformStamped(imu.camera_in_imu.inverse(), spec.rgb_frame, imu.imu_frame, first_stamp));
  }
  writeStaticTransforms(bag, static_transforms, first_stamp);
  for (std::size_t i = 0; i < sequence.size(); ++i) {
    const TumFrameEntry& entry = sequence.entry(i);
    const RgbdFrame frame = sequence.loadFrame(i);
    const ros::Time rgb_stamp(entry.rgb.stamp), depth_stamp(entry.depth.stamp);
    bag->write(spec.rgb_image, rgb_stamp, spec.color(frame.color, spec.rgb_frame, rgb_stamp));
    if (!options.without_camera_info) bag->write(spec.rgb_info, rgb_stamp, toCameraInfo(camera, spec.rgb_frame, rgb_stamp, lens));
    if (!options.without_depth) {
      bag->write(spec.depth_image, depth_stamp, spec.depth(frame.depth, spec.depth_frame, depth_stamp));
      if (!options.without_camera_info)
        bag->write(spec.depth_info, depth_stamp, toCameraInfo(camera, spec.depth_frame, depth_stamp, lens));
    }
    ++summary->frames;
    if (progress) progress(i + 1, sequence.size());
  }
}

// The TUM layout carries the ground truth as world -> kinect transforms (a real recording has none):
// the folder's poses are the optical frame's, kinect is its body frame.
void writeGroundTruth(const TumSequence& sequence, rosbag::Bag* bag, TumBagSummary* summary) {
  using T = TumBagTopics;
  const Eigen::Isometry3d optical_from_body = bodyFromOptical().inverse();
  for (const StampedPose& pose : sequence.groundTruth()) {
    const ros::Time stamp(pose.stamp);
    tf2_msgs::TFMessage tf;
    tf.transforms.push_back(toTransformStamped(pose.pose * optical_from_body, T::kWorldFrame, T::kCameraFrame, stamp));
    bag->write("/tf", stamp, tf);
    ++summary->ground_truth_poses;
  }
}

// The TUM layout carries the folder's accelerometer on /imu (no gyro: orientation and rates marked absent).
void writeAccelerometer(const TumSequence& sequence, rosbag::Bag* bag, TumBagSummary* summary) {
  for (const AccelerometerSample& sample : sequence.accelerometer()) {
    bag->write(TumBagTopics::kImu, ros::Time(sample.stamp), toAccelerometerImu(sample, TumBagTopics::kAccelerometerFrame));
    ++summary->accelerometer_samples;
  }
}
// A simulated (or recorded) IMU's samples as a RealSense driver publishes them: gyro and accelerometer.
void writeImu(const std::string& folder, rosbag::Bag* bag, TumBagSummary* summary) {
  const ImuExtrinsics imu = readImuExtrinsics(folder + "/imu_extrinsics.yaml");
  for (const ImuSample& sample : readImuFile(folder + "/imu.txt")) {
    bag->write(kImuTopic, ros::Time(sample.stamp), toImuMessage(sample, imu.imu_frame));
    ++summary->imu_samples;
  }
}
}  // namespace

BagLayout parseBagLayout(const std::string& name) {
  if (name == "tum") return BagLayout::kTum;
  if (name == "openni2") return BagLayout::kOpenNi2;
  throw InputError("bag layout '" + name + "' is unknown: expected tum or openni2");
}

TumBagSummary writeTumBag(const TumSequence& sequence, const std::string& bag_path, const TumBagOptions& options,
                          const std::function<void(std::size_t, std::size_t)>& progress) {
  rosbag::Bag bag;
  openBag(&bag, bag_path, rosbag::bagmode::Write);
  TumBagSummary summary;
  try {
    writeFrames(sequence, options, &bag, progress, &summary);
    if (!options.imu_folder.empty()) writeImu(options.imu_folder, &bag, &summary);
    if (options.layout == BagLayout::kTum) {
      writeGroundTruth(sequence, &bag, &summary);
      writeAccelerometer(sequence, &bag, &summary);
    }
  } catch (const rosbag::BagException& e) {
    throw InputError(bag_path + ": write failed (" + e.what() + ")");
  }
  bag.close();
  return summary;
}

}  // namespace vocal
