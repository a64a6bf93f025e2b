#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_msgs/TFMessage.h>

#include "test_support.h"
#include "vocal/core/errors.h"
#include "vocal/core/tum_sequence.h"
#include "vocal/tools/tum_bag_writer.h"

using T = vocal::TumBagTopics;

TEST(TumBagWriter, WritesTheBenchmarkLayout) {
  const std::string folder = vocal_test::makeTempFolder("bag");
  vocal::SyntheticSequenceOptions options = vocal_test::smallSequenceOptions(5);
  options.sensor_model.missing_fraction = 0.05;  // so NaN depth is exercised
  vocal::writeSyntheticSequence(folder + "/seq", options);
  const vocal::TumSequence sequence = vocal::TumSequence::open(folder + "/seq");
  const vocal::TumBagSummary summary = vocal::writeTumBag(sequence, folder + "/seq.bag");
  EXPECT_EQ(summary.frames, 5u);
  EXPECT_EQ(summary.ground_truth_poses, 5u);
  ASSERT_EQ(sequence.accelerometer().size(), 5u);
  EXPECT_EQ(summary.accelerometer_samples, 5u);

  rosbag::Bag bag(folder + "/seq.bag", rosbag::bagmode::Read);
  std::map<std::string, int> counts;
  std::size_t rgb_index = 0, depth_index = 0, tf_index = 0, imu_index = 0;
  // /tf_static first (messages at the first stamp come in no fixed order): kinect -> each child.
  std::map<std::string, Eigen::Isometry3d> body_from_child;
  for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery("/tf_static"))) {
    EXPECT_EQ(m.getConnectionHeader()->at("latching"), "1");
    const auto tf = m.instantiate<tf2_msgs::TFMessage>();
    ASSERT_TRUE(tf);
    for (const auto& t : tf->transforms) {
      EXPECT_EQ(t.header.frame_id, T::kCameraFrame);
      body_from_child[t.child_frame_id] = tf2::transformToEigen(t.transform);
    }
  }
  ASSERT_EQ(body_from_child.size(), 3u);
  for (const rosbag::MessageInstance& m : rosbag::View(bag)) {
    ++counts[m.getTopic()];
    if (m.getTopic() == T::kRgbImage) {
      const auto image = m.instantiate<sensor_msgs::Image>();
      ASSERT_TRUE(image);
      const vocal::RgbdFrame frame = sequence.loadFrame(rgb_index);
      EXPECT_EQ(image->encoding, "rgb8");
      EXPECT_EQ(image->header.frame_id, T::kRgbFrame);
      EXPECT_EQ(image->header.stamp.toSec(), ros::Time(sequence.entry(rgb_index).rgb.stamp).toSec());
      ASSERT_EQ(image->data.size(), frame.color.size() * 3);
      EXPECT_EQ(std::memcmp(image->data.data(), frame.color.data(), image->data.size()), 0);
      ++rgb_index;
    } else if (m.getTopic() == T::kDepthImage) {
      const auto image = m.instantiate<sensor_msgs::Image>();
      ASSERT_TRUE(image);
      const vocal::RgbdFrame frame = sequence.loadFrame(depth_index);
      EXPECT_EQ(image->encoding, "32FC1");
      EXPECT_EQ(image->header.frame_id, T::kDepthFrame);
      const float* depth = reinterpret_cast<const float*>(image->data.data());
      int missing = 0;
      for (std::size_t p = 0; p < frame.depth.size(); ++p) {
        if (vocal::isValidDepth(frame.depth.pixels()[p])) {
          ASSERT_EQ(depth[p], frame.depth.pixels()[p]);
        } else {
          ASSERT_TRUE(std::isnan(depth[p]));
          ++missing;
        }
      }
      EXPECT_GT(missing, 0);
      ++depth_index;
    } else if (m.getTopic() == T::kRgbInfo || m.getTopic() == T::kDepthInfo) {
      const auto info = m.instantiate<sensor_msgs::CameraInfo>();
      ASSERT_TRUE(info);
      EXPECT_EQ(info->K[0], sequence.camera().fx);
      EXPECT_EQ(info->K[2], sequence.camera().cx);
      EXPECT_EQ(info->K[4], sequence.camera().fy);
      EXPECT_EQ(info->K[5], sequence.camera().cy);
      EXPECT_EQ(info->width, 160u);
    } else if (m.getTopic() == "/tf") {
      const auto tf = m.instantiate<tf2_msgs::TFMessage>();
      ASSERT_TRUE(tf);
      ASSERT_EQ(tf->transforms.size(), 1u);
      const auto& t = tf->transforms[0];
      EXPECT_EQ(t.header.frame_id, T::kWorldFrame);
      EXPECT_EQ(t.child_frame_id, T::kCameraFrame);
      const Eigen::Vector3d expected = sequence.groundTruth()[tf_index].pose.translation();
      EXPECT_NEAR(t.transform.translation.x, expected.x(), 1e-12);
      EXPECT_NEAR(t.transform.translation.z, expected.z(), 1e-12);
      // kinect is the camera's body frame (x forward, z up): its optical frame is the folder's pose.
      const Eigen::Isometry3d world_from_optical = tf2::transformToEigen(t.transform) * body_from_child.at(T::kRgbFrame);
      EXPECT_TRUE(world_from_optical.isApprox(sequence.groundTruth()[tf_index].pose, 1e-9)) << "pose " << tf_index;
      ++tf_index;
    } else if (m.getTopic() == T::kImu) {
      const auto imu = m.instantiate<sensor_msgs::Imu>();
      ASSERT_TRUE(imu);
      EXPECT_EQ(imu->header.frame_id, T::kAccelerometerFrame);
      EXPECT_EQ(imu->orientation_covariance[0], -1.0);  // REP-145: no orientation
      const vocal::AccelerometerSample& sample = sequence.accelerometer()[imu_index];
      EXPECT_EQ(imu->header.stamp, ros::Time(sample.stamp));
      EXPECT_EQ(imu->linear_acceleration.y, sample.specific_force.y());
      // At rest the accelerometer reads up: in the body frame, the world's up seen from the camera.
      const Eigen::Matrix3d world_from_body =
          sequence.groundTruth()[imu_index].pose.linear() * body_from_child.at(T::kRgbFrame).linear().transpose();
      const Eigen::Vector3d up_in_body = body_from_child.at(T::kAccelerometerFrame).linear() * sample.specific_force.normalized();
      EXPECT_GT((world_from_body * up_in_body).z(), 0.99) << "sample " << imu_index;
      ++imu_index;
    }
  }
  EXPECT_EQ(counts[T::kRgbImage], 5);
  EXPECT_EQ(counts[T::kDepthImage], 5);
  EXPECT_EQ(counts[T::kRgbInfo], 5);
  EXPECT_EQ(counts[T::kDepthInfo], 5);
  EXPECT_EQ(counts["/tf"], 5);
  EXPECT_EQ(counts["/tf_static"], 1);
  EXPECT_EQ(counts[T::kImu], 5);
}

TEST(TumBagWriter, UnwritableBagIsNamed) {
  const std::string folder = vocal_test::makeTempFolder("bag_error");
  vocal::writeSyntheticSequence(folder + "/seq", vocal_test::smallSequenceOptions(2));
  const vocal::TumSequence sequence = vocal::TumSequence::open(folder + "/seq");
  const std::string error = vocal_test::inputErrorOf([&] { vocal::writeTumBag(sequence, folder + "/no/such/dir/out.bag"); });
  EXPECT_EQ(error.rfind(folder + "/no/such/dir/out.bag: cannot open bag for writing", 0), 0u) << error;
}
