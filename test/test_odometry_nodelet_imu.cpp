// The odometry nodelet with an IMU (rostest odometry_nodelet_imu.test): a synthetic sequence and a
// consumer gyro + accelerometer simulated along it, played from a bag as a RealSense driver publishes
// them. Every frame gets the gyro's prior and is tracked against the truth; the diagnostics say so, with
// the bias and the accelerometer's level; a NaN message is named, dropped and counted.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/Imu.h>
#include <tf2_eigen/tf2_eigen.h>

#include "ros_test_support.h"
#include "test_support.h"
#include "vocal/core/imu_samples.h"
#include "vocal/core/se3.h"
#include "vocal/core/tum_sequence.h"
#include "vocal/simulation/simulated_imu.h"
#include "vocal/simulation/synthetic_sequence.h"
#include "vocal/tools/tum_bag_writer.h"

namespace {
std::string diagnosticValue(const diagnostic_msgs::DiagnosticStatus& status, const std::string& key) {
  for (const auto& kv : status.values)
    if (kv.key == key) return kv.value;
  return "";
}
}  // namespace

TEST(OdometryNodeletImu, EveryFrameGetsTheGyrosPriorAndTheDiagnosticsSaySo) {
  ros::NodeHandle nh;
  std::mutex mutex;
  std::vector<nav_msgs::Odometry::ConstPtr> odom;
  diagnostic_msgs::DiagnosticStatus status;
  const ros::Subscriber odom_sub = nh.subscribe<nav_msgs::Odometry>("/odom", 100, [&](const nav_msgs::Odometry::ConstPtr& m) {
    std::lock_guard<std::mutex> lock(mutex);
    odom.push_back(m);
  });
  const ros::Subscriber diagnostics_sub =
      nh.subscribe<diagnostic_msgs::DiagnosticArray>("/diagnostics", 10, [&](const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
        std::lock_guard<std::mutex> lock(mutex);
        for (const auto& s : m->status)
          if (s.name.find("icp_dvo_odometry") != std::string::npos) status = s;
      });
  ros::AsyncSpinner spinner(2);
  spinner.start();

  const std::string folder = vocal_test::makeTempFolder("odometry_nodelet_imu");
  const int frames = 45;
  vocal::SyntheticSequenceOptions options = vocal_test::smallSequenceOptions(frames);
  options.sensor_model = vocal::kinectLikeSensorModel();
  vocal::writeSyntheticSequence(folder + "/seq", options);
  const vocal::TumSequence sequence = vocal::TumSequence::open(folder + "/seq");
  vocal::SimulatedImuOptions imu;
  imu.extrinsics = vocal::simulatedImuExtrinsics();
  std::filesystem::create_directories(folder + "/seq_imu");
  vocal::writeImuFile(folder + "/seq_imu/imu.txt", vocal::simulateImu(sequence.groundTruth(), imu));
  vocal::writeImuExtrinsics(folder + "/seq_imu/imu_extrinsics.yaml", imu.extrinsics);
  vocal::TumBagOptions bag_options;
  bag_options.imu_folder = folder + "/seq_imu";
  vocal::writeTumBag(sequence, folder + "/with_imu.bag", bag_options);
  // One IMU message broken (a NaN rate): named, dropped, counted; the frames around it still get a prior
  // (200 Hz: the neighbours span the gap).
  {
    rosbag::Bag in(folder + "/with_imu.bag", rosbag::bagmode::Read), out(folder + "/played.bag", rosbag::bagmode::Write);
    int imu_index = 0;
    for (const rosbag::MessageInstance& m : rosbag::View(in)) {
      if (m.getTopic() == vocal::kImuTopic && imu_index++ == 100) {
        sensor_msgs::Imu broken = *m.instantiate<sensor_msgs::Imu>();
        broken.angular_velocity.z = std::nan("");
        out.write(m.getTopic(), m.getTime(), broken);
      } else {
        out.write(m.getTopic(), m.getTime(), m, m.getConnectionHeader());
      }
    }
  }
  ASSERT_NO_FATAL_FAILURE(vocal_test::playBag(folder + "/played.bag", 60.0,
                                              {"--delay", "0.5", "--rate", "0.5", "--topics", vocal::TumBagTopics::kRgbImage,
                                               vocal::TumBagTopics::kDepthImage, vocal::TumBagTopics::kRgbInfo, vocal::kImuTopic, "/tf_static"}));
  ASSERT_TRUE(vocal_test::waitUntil(mutex, 10.0, [&] { return odom.size() >= static_cast<std::size_t>(frames); }))
      << odom.size() << " of " << frames << " odometry messages";
  ros::WallDuration(1.5).sleep();  // the diagnostics after the last frame

  std::lock_guard<std::mutex> lock(mutex);
  double worst_rotation = 0.0;
  for (std::size_t i = 0; i < odom.size(); ++i) {
    ASSERT_NEAR(odom[i]->header.stamp.toSec(), sequence.entry(i).rgb.stamp, 1e-4);
    Eigen::Isometry3d estimate;
    tf2::fromMsg(odom[i]->pose.pose, estimate);
    // odom is the camera's first pose, levelled by the accelerometer: compare rotations between frames.
    Eigen::Isometry3d first;
    tf2::fromMsg(odom.front()->pose.pose, first);
    const Eigen::Isometry3d truth = sequence.groundTruth().front().pose.inverse() * sequence.groundTruth()[i].pose;
    worst_rotation = std::max(worst_rotation, vocal::rotationAngle(truth.inverse() * (first.inverse() * estimate)));
  }
  const int with_prior = std::stoi("0" + diagnosticValue(status, "frames with the gyro's rotation prior"));
  std::cout << "with an IMU: " << odom.size() << " odometry messages, worst rotation error " << worst_rotation * 180.0 / M_PI
            << " deg; diagnostics: " << status.message << "; frames with the gyro's prior " << with_prior << ", without "
            << diagnosticValue(status, "frames without it") << ", bias " << diagnosticValue(status, "gyro bias (deg/s)") << ", level "
            << diagnosticValue(status, "roll / pitch off the first level by (accelerometer)") << ", odom "
            << diagnosticValue(status, "odom") << "\n";
  EXPECT_EQ(odom.size(), static_cast<std::size_t>(frames));
  EXPECT_LT(worst_rotation, 0.02);
  EXPECT_GE(with_prior, frames - 3) << "every frame after the first should get the gyro's prior";
  EXPECT_EQ(diagnosticValue(status, "/camera/imu messages dropped"), "1");
  EXPECT_NE(diagnosticValue(status, "gyro bias (deg/s)"), "");
  EXPECT_NE(diagnosticValue(status, "odom").find("levelled by the accelerometer on /camera/imu"), std::string::npos)
      << diagnosticValue(status, "odom");
  EXPECT_NE(diagnosticValue(status, "roll / pitch off the first level by (accelerometer)").find("deg (last)"), std::string::npos)
      << diagnosticValue(status, "roll / pitch off the first level by (accelerometer)");
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_odometry_nodelet_imu");
  ros::NodeHandle nh;
  const int result = RUN_ALL_TESTS();
  vocal_test::removeTempFolders();
  return result;
}
