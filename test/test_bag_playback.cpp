// rostest: a sequence written by tum_to_bag plays back through a live ROS graph (rosbag play) with
// every topic, stamp, image and ground-truth transform intact.

#include <gtest/gtest.h>

#include <atomic>
#include <cstring>
#include <mutex>

#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <tf2_msgs/TFMessage.h>

#include "ros_test_support.h"
#include "test_support.h"
#include "vocal/core/tum_sequence.h"
#include "vocal/tools/tum_bag_writer.h"

using T = vocal::TumBagTopics;

namespace {
struct Received {
  std::mutex mutex;
  std::vector<sensor_msgs::Image::ConstPtr> rgb, depth;
  std::vector<sensor_msgs::CameraInfo::ConstPtr> rgb_info, depth_info;
  std::vector<tf2_msgs::TFMessage::ConstPtr> tf, tf_static;
  std::vector<sensor_msgs::Imu::ConstPtr> imu;
};

template <typename M>
ros::Subscriber collect(ros::NodeHandle& nh, const std::string& topic, Received* received,
                        std::vector<typename M::ConstPtr>* into) {
  return nh.subscribe<M>(topic, 100, [received, into](const typename M::ConstPtr& msg) {
    std::lock_guard<std::mutex> lock(received->mutex);
    into->push_back(msg);
  });
}
}  // namespace

TEST(BagPlayback, EveryTopicArrivesIntact) {
  const std::string folder = vocal_test::makeTempFolder("playback");
  vocal::writeSyntheticSequence(folder + "/seq", vocal_test::smallSequenceOptions(20));
  const vocal::TumSequence sequence = vocal::TumSequence::open(folder + "/seq");
  const std::string bag = folder + "/seq.bag";
  vocal::writeTumBag(sequence, bag);

  ros::NodeHandle nh;
  Received received;
  std::vector<ros::Subscriber> subscribers = {
      collect<sensor_msgs::Image>(nh, T::kRgbImage, &received, &received.rgb),
      collect<sensor_msgs::Image>(nh, T::kDepthImage, &received, &received.depth),
      collect<sensor_msgs::CameraInfo>(nh, T::kRgbInfo, &received, &received.rgb_info),
      collect<sensor_msgs::CameraInfo>(nh, T::kDepthInfo, &received, &received.depth_info),
      collect<tf2_msgs::TFMessage>(nh, "/tf", &received, &received.tf),
      collect<tf2_msgs::TFMessage>(nh, "/tf_static", &received, &received.tf_static),
      collect<sensor_msgs::Imu>(nh, T::kImu, &received, &received.imu)};
  ros::AsyncSpinner spinner(2);
  spinner.start();

  ASSERT_NO_FATAL_FAILURE(vocal_test::playBag(bag));
  // Let the last messages through the transport.
  for (int i = 0; i < 40; ++i) {
    {
      std::lock_guard<std::mutex> lock(received.mutex);
      if (received.rgb.size() == 20 && received.depth.size() == 20 && received.tf.size() == 20 && received.imu.size() == 20) break;
    }
    ros::WallDuration(0.05).sleep();
  }

  std::lock_guard<std::mutex> lock(received.mutex);
  ASSERT_EQ(received.rgb.size(), 20u);
  ASSERT_EQ(received.depth.size(), 20u);
  EXPECT_EQ(received.rgb_info.size(), 20u);
  EXPECT_EQ(received.depth_info.size(), 20u);
  ASSERT_EQ(received.tf.size(), 20u);
  EXPECT_EQ(received.tf_static.size(), 1u);
  ASSERT_EQ(received.imu.size(), 20u);
  EXPECT_EQ(received.imu[0]->linear_acceleration.z, sequence.accelerometer()[0].specific_force.z());
  for (std::size_t i = 0; i < 20; ++i) {
    const vocal::RgbdFrame frame = sequence.loadFrame(i);
    const auto& rgb = *received.rgb[i];
    EXPECT_EQ(rgb.header.stamp, ros::Time(sequence.entry(i).rgb.stamp));
    ASSERT_EQ(rgb.data.size(), frame.color.size() * 3);
    EXPECT_EQ(std::memcmp(rgb.data.data(), frame.color.data(), rgb.data.size()), 0) << "rgb frame " << i;
    const float* depth = reinterpret_cast<const float*>(received.depth[i]->data.data());
    EXPECT_EQ(depth[frame.depth.size() / 2], frame.depth.pixels()[frame.depth.size() / 2]);
    const auto& t = received.tf[i]->transforms.at(0);
    EXPECT_EQ(t.child_frame_id, T::kCameraFrame);
    EXPECT_NEAR(t.transform.translation.y, sequence.groundTruth()[i].pose.translation().y(), 1e-12);
  }
  EXPECT_EQ(received.rgb_info[0]->K[0], sequence.camera().fx);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_bag_playback");
  return RUN_ALL_TESTS();
}
