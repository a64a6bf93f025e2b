// rostest: the vocal/MsgCalibration nodelet calibrates a simulated recording of all four sensor types
// played by rosbag play: the calibrate service succeeds, /tf_static carries extrinsics within the
// issue's bounds, the result files and the fused cloud appear; without a rig it stays idle and says why.

#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <iterator>
#include <mutex>

#include <nodelet/loader.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_srvs/Trigger.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "test_support.h"
#include "vocal/core/se3.h"
#include "vocal/tools/calibration_bag.h"

TEST(CalibrationNodelet, CalibratesAPlayedSession) {
  const std::string folder = vocal_test::makeTempFolder("calibration_nodelet");
  const std::vector<vocal::SimulatedSensor> sensors = vocal::exampleRig(1, 1, 1, 1);
  const vocal::RigDescription rig = vocal::describeSimulatedRig(sensors, vocal::TargetDescription{}, false);
  vocal::writeRigDescription(folder + "/rig.yaml", rig);
  vocal::SimulatedSessionOptions options;
  options.target_poses = 8;
  options.still_seconds = 0.6;
  options.moving_seconds = 0.3;
  options.depth_width = 160;
  options.depth_height = 120;
  options.seed = 5;
  vocal::writeSimulatedCalibrationBag(sensors, rig, options, folder + "/session.bag");

  ros::NodeHandle nh;
  nh.setParam("/calibration/rig", folder + "/rig.yaml");
  nh.setParam("/calibration/output_dir", folder);
  nh.setParam("/calibration/tolerance_rotation", 1e-6);  // every sensor's spread is over it: each reported uncertain
  nh.setParam("/calibration/publish_uncertain", true);    // ... and published all the same, as asked
  nodelet::Loader manager(false);
  ASSERT_TRUE(manager.load("/calibration", "vocal/MsgCalibration", {}, {}));
  std::mutex mutex;
  sensor_msgs::PointCloud2::ConstPtr fused;
  ros::Subscriber fused_sub = nh.subscribe<sensor_msgs::PointCloud2>(
      "/calibration/fused_cloud", 1, [&](const sensor_msgs::PointCloud2::ConstPtr& m) {
        std::lock_guard<std::mutex> lock(mutex);
        fused = m;
      });
  tf2_ros::Buffer tf_buffer;
  tf2_ros::TransformListener tf_listener(tf_buffer, nh);
  ros::AsyncSpinner spinner(2);
  spinner.start();

  const pid_t player = ::fork();
  ASSERT_GE(player, 0);
  if (player == 0) {
    const std::string bag = folder + "/session.bag";
    ::execlp("rosbag", "rosbag", "play", "--quiet", "--wait-for-subscribers", bag.c_str(), static_cast<char*>(nullptr));
    std::perror("exec rosbag");
    ::_exit(127);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(player, &status, 0), player);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "rosbag play failed";
  ros::WallDuration(1.0).sleep();  // the last messages through extraction

  std_srvs::Trigger calibrate;
  ASSERT_TRUE(ros::service::call("/calibration/calibrate", calibrate));
  std::cout << calibrate.response.message << "\n";
  EXPECT_TRUE(calibrate.response.success) << calibrate.response.message;
  EXPECT_EQ(calibrate.response.message.rfind("calibrated 4 sensors, rms ", 0), 0u) << calibrate.response.message;
  // The spread across still poses beside the solver's sigma, in the reply and the result YAML.
  EXPECT_NE(calibrate.response.message.find("; spread across poses (jackknife), solver's sigma in brackets: "), std::string::npos)
      << calibrate.response.message;
  for (std::size_t s = 1; s < sensors.size(); ++s) {
    EXPECT_NE(calibrate.response.message.find("; uncertain: sensor '" + sensors[s].spec.name + "' moves "), std::string::npos)
        << calibrate.response.message;
  }
  EXPECT_EQ(calibrate.response.message.find("withheld"), std::string::npos) << calibrate.response.message;
  // The lidar's ring offsets, estimated from the room's floor and wall, in the reply and the result YAML.
  EXPECT_NE(calibrate.response.message.find("; lidar0 ring offsets "), std::string::npos) << calibrate.response.message;
  std::ifstream result_yaml(folder + "/calibration.yaml");
  const std::string result_text((std::istreambuf_iterator<char>(result_yaml)), std::istreambuf_iterator<char>());
  EXPECT_NE(result_text.find("    translation_spread: ["), std::string::npos) << result_text;
  EXPECT_NE(result_text.find("    ring_offsets:  # from "), std::string::npos) << result_text;

  for (std::size_t s = 1; s < sensors.size(); ++s) {
    geometry_msgs::TransformStamped t;
    try {
      t = tf_buffer.lookupTransform("base_link", sensors[s].spec.frame_id, ros::Time(0), ros::Duration(5.0));
    } catch (const tf2::TransformException& e) {
      FAIL() << sensors[s].spec.name << ": " << e.what();
    }
    const Eigen::Isometry3d error = sensors[s].reference_from_sensor.inverse() * tf2::transformToEigen(t);
    std::cout << sensors[s].spec.name << " on /tf_static: " << error.translation().norm() * 1000 << " mm / "
              << vocal::rotationAngle(error) << " rad from the truth\n";
    EXPECT_LT(error.translation().norm(), 0.005) << sensors[s].spec.name;
    EXPECT_LT(vocal::rotationAngle(error), 0.005) << sensors[s].spec.name;
  }
  for (const char* file : {"/calibration.yaml", "/calibration.urdf", "/calibration.launch"}) {
    EXPECT_TRUE(std::ifstream(folder + file).good()) << file;
  }
  vocal_test::waitUntil(mutex, 5.0, [&] { return fused != nullptr; });
  std::lock_guard<std::mutex> lock(mutex);
  ASSERT_TRUE(fused);
  EXPECT_EQ(fused->header.frame_id, "base_link");
  EXPECT_GT(fused->width, 1000u);
}

TEST(CalibrationNodelet, WithoutARigItStaysIdleAndSaysWhy) {
  nodelet::Loader manager(false);
  ASSERT_TRUE(manager.load("/no_rig", "vocal/MsgCalibration", {}, {}));
  std_srvs::Trigger calibrate;
  ASSERT_TRUE(ros::service::waitForService("/no_rig/calibrate", ros::Duration(5.0)));
  ASSERT_TRUE(ros::service::call("/no_rig/calibrate", calibrate));
  EXPECT_FALSE(calibrate.response.success);
  EXPECT_EQ(calibrate.response.message, "parameter '/no_rig/rig' (the rig description YAML) is not set");
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_calibration_nodelet");
  return RUN_ALL_TESTS();
}
