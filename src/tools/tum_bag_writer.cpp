#include "vocal/tools/tum_bag_writer.h"

#include <rosbag/bag.h>
#include <tf2_msgs/TFMessage.h>

#include "vocal/core/errors.h"
#include "vocal/nodelets/message_conversions.h"

namespace vocal {

TumBagSummary writeTumBag(const TumSequence& sequence, const std::string& bag_path,
                          const std::function<void(std::size_t, std::size_t)>& progress) {
  using T = TumBagTopics;
  rosbag::Bag bag;
  try {
    bag.open(bag_path, rosbag::bagmode::Write);
  } catch (const rosbag::BagException& e) {
    throw InputError(bag_path + ": cannot open bag for writing (" + e.what() + ")");
  }
  TumBagSummary summary;
  try {
    const PinholeCamera& camera = sequence.camera();
    const ros::Time first_stamp(sequence.entry(0).rgb.stamp);

    tf2_msgs::TFMessage static_transforms;
    static_transforms.transforms.push_back(
        toTransformStamped(Eigen::Isometry3d::Identity(), T::kCameraFrame, T::kRgbFrame, first_stamp));
    static_transforms.transforms.push_back(
        toTransformStamped(Eigen::Isometry3d::Identity(), T::kCameraFrame, T::kDepthFrame, first_stamp));
    // A custom connection header replaces rosbag's own, so it must carry the message type too.
    using StaticTraits = ros::message_traits::DataType<tf2_msgs::TFMessage>;
    auto latched = boost::make_shared<ros::M_string>();
    (*latched)["type"] = StaticTraits::value();
    (*latched)["md5sum"] = ros::message_traits::MD5Sum<tf2_msgs::TFMessage>::value();
    (*latched)["message_definition"] = ros::message_traits::Definition<tf2_msgs::TFMessage>::value();
    (*latched)["latching"] = "1";
    (*latched)["callerid"] = "/vocal_tum_to_bag";
    bag.write("/tf_static", first_stamp, static_transforms, latched);

    for (std::size_t i = 0; i < sequence.size(); ++i) {
      const TumFrameEntry& entry = sequence.entry(i);
      const RgbdFrame frame = sequence.loadFrame(i);
      const ros::Time rgb_stamp(entry.rgb.stamp), depth_stamp(entry.depth.stamp);
      bag.write(T::kRgbImage, rgb_stamp, toRgb8Image(frame.color, T::kRgbFrame, rgb_stamp));
      bag.write(T::kRgbInfo, rgb_stamp, toCameraInfo(camera, T::kRgbFrame, rgb_stamp));
      bag.write(T::kDepthImage, depth_stamp, toDepth32FImage(frame.depth, T::kDepthFrame, depth_stamp));
      bag.write(T::kDepthInfo, depth_stamp, toCameraInfo(camera, T::kDepthFrame, depth_stamp));
      ++summary.frames;
      if (progress) progress(i + 1, sequence.size());
    }
    for (const StampedPose& pose : sequence.groundTruth()) {
      const ros::Time stamp(pose.stamp);
      tf2_msgs::TFMessage tf;
      tf.transforms.push_back(toTransformStamped(pose.pose, T::kWorldFrame, T::kCameraFrame, stamp));
      bag.write("/tf", stamp, tf);
      ++summary.ground_truth_poses;
    }
  } catch (const rosbag::BagException& e) {
    throw InputError(bag_path + ": write failed (" + e.what() + ")");
  }
  bag.close();
  return summary;
}

}  // namespace vocal
