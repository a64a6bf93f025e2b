// rostest: the vocal/OpenNI2Driver nodelet on the virtual OpenNI2 device (test/virtual_openni2_device.cpp):
// openni2_camera's topics carry the device's frames with their encodings, frames and intrinsics, streams
// start on subscription, and a device_id that matches nothing is reported without bringing the
// manager down.

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <vector>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <nodelet/loader.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include "test_support.h"
#include "virtual_openni2_environment.h"

namespace {
// One in-process manager for the whole test program. OpenNI2 crashes when a thread that called it has
// exited and another thread calls it later (it probes the old thread with pthread_kill); a nodelet
// manager's worker threads live as long as the manager, so one manager must outlive every OpenNI2 call.
nodelet::Loader* manager = nullptr;

struct Latest {
  std::mutex mutex;
  sensor_msgs::Image::ConstPtr rgb, depth;
  sensor_msgs::CameraInfo::ConstPtr rgb_info, depth_info;
  int rgb_count = 0, depth_count = 0;
  std::string bad_device_status;
};

}  // namespace

TEST(Openni2DriverNodelet, PublishesTheVirtualDevicesStreams) {
  ros::NodeHandle nh;
  nh.setParam("/camera/driver/device_id", "VOCAL0001");
  nh.setParam("/camera/driver/depth_registration", true);
  nh.setParam("/camera/driver/use_device_time", false);
  nodelet::M_string remappings;
  nodelet::V_string arguments;
  // The nodelet's topics live in /camera (its namespace), as with openni2_launch.
  ASSERT_TRUE(manager->load("/camera/driver", "vocal/OpenNI2Driver", remappings, arguments));

  Latest latest;
  ros::AsyncSpinner spinner(2);
  spinner.start();
  ros::Subscriber rgb = nh.subscribe<sensor_msgs::Image>("/camera/rgb/image_raw", 2, [&](const sensor_msgs::Image::ConstPtr& m) {
    std::lock_guard<std::mutex> lock(latest.mutex);
    latest.rgb = m;
    ++latest.rgb_count;
  });
  ros::Subscriber depth = nh.subscribe<sensor_msgs::Image>(
      "/camera/depth_registered/image_raw", 2, [&](const sensor_msgs::Image::ConstPtr& m) {
        std::lock_guard<std::mutex> lock(latest.mutex);
        latest.depth = m;
        ++latest.depth_count;
      });
  ros::Subscriber rgb_info = nh.subscribe<sensor_msgs::CameraInfo>(
      "/camera/rgb/camera_info", 2, [&](const sensor_msgs::CameraInfo::ConstPtr& m) {
        std::lock_guard<std::mutex> lock(latest.mutex);
        latest.rgb_info = m;
      });
  ros::Subscriber depth_info = nh.subscribe<sensor_msgs::CameraInfo>(
      "/camera/depth_registered/camera_info", 2, [&](const sensor_msgs::CameraInfo::ConstPtr& m) {
        std::lock_guard<std::mutex> lock(latest.mutex);
        latest.depth_info = m;
      });
  ASSERT_TRUE(vocal_test::waitUntil(latest.mutex, 20.0, [&] {
    return latest.rgb_count >= 3 && latest.depth_count >= 3 && latest.rgb_info && latest.depth_info;
  }))
      << "rgb " << latest.rgb_count << ", depth " << latest.depth_count;

  std::lock_guard<std::mutex> lock(latest.mutex);
  EXPECT_EQ(latest.rgb->encoding, "rgb8");
  EXPECT_EQ(latest.rgb->header.frame_id, "camera_rgb_optical_frame");
  ASSERT_EQ(latest.rgb->width, 640u);
  // Colour (x mod 256, y mod 256, frame mod 256) at pixel (300, 200).
  const std::uint8_t* rgb_pixel = &latest.rgb->data[200 * latest.rgb->step + 3 * 300];
  EXPECT_EQ(rgb_pixel[0], 300 % 256);
  EXPECT_EQ(rgb_pixel[1], 200);

  EXPECT_EQ(latest.depth->encoding, "16UC1");
  EXPECT_EQ(latest.depth->header.frame_id, "camera_rgb_optical_frame") << "registered depth lies in the colour frame";
  ASSERT_EQ(latest.depth->width, 640u);
  std::uint16_t d_10_20 = 0, d_11_20 = 0, d_10_21 = 0, d_0_20 = 1;
  std::memcpy(&d_10_20, &latest.depth->data[20 * latest.depth->step + 2 * 10], 2);
  std::memcpy(&d_11_20, &latest.depth->data[20 * latest.depth->step + 2 * 11], 2);
  std::memcpy(&d_10_21, &latest.depth->data[21 * latest.depth->step + 2 * 10], 2);
  std::memcpy(&d_0_20, &latest.depth->data[20 * latest.depth->step], 2);
  // depth(x, y) = 1000 + x + 2 y + k millimetres; 0 = no measurement on column 0.
  EXPECT_GE(d_10_20, 1000 + 10 + 40);
  EXPECT_EQ(d_11_20 - d_10_20, 1);
  EXPECT_EQ(d_10_21 - d_10_20, 2);
  EXPECT_EQ(d_0_20, 0);

  // No calibration file: the device's field of view gives the ROS default 525 px.
  EXPECT_NEAR(latest.rgb_info->K[0], 525.0, 0.1);
  EXPECT_EQ(latest.rgb_info->header.stamp, latest.rgb->header.stamp);
  EXPECT_NEAR(latest.depth_info->K[0], 525.0, 0.1);
  EXPECT_EQ(latest.depth_info->width, 640u);
}

TEST(Openni2DriverNodelet, AnUnknownDeviceIsReportedAndTheManagerLives) {
  ros::NodeHandle nh;
  nh.setParam("/missing/driver/device_id", "#4");
  Latest latest;
  ros::Subscriber diagnostics = nh.subscribe<diagnostic_msgs::DiagnosticArray>(
      "/diagnostics", 10, [&](const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
        std::lock_guard<std::mutex> lock(latest.mutex);
        for (const auto& s : m->status)
          if (s.name.find("missing/driver") != std::string::npos) latest.bad_device_status = s.message;
      });
  ros::AsyncSpinner spinner(1);
  spinner.start();
  nodelet::M_string remappings;
  nodelet::V_string arguments;
  ASSERT_TRUE(manager->load("/missing/driver", "vocal/OpenNI2Driver", remappings, arguments));
  EXPECT_TRUE(vocal_test::waitUntil(latest.mutex, 10.0, [&] { return latest.bad_device_status.rfind("device_id", 0) == 0; }));
  ros::WallDuration(4.0).sleep();  // through a retry: still reported, the process alive
  std::lock_guard<std::mutex> lock(latest.mutex);
  EXPECT_EQ(latest.bad_device_status, "device_id '#4': there is no device 4, 1 connected");
  EXPECT_TRUE(manager->unload("/missing/driver"));
}

// A stream without a field of view (the virtual device told to report 0, as recordings without it do):
// camera_info carries finite nominal intrinsics, and the warning is in the diagnostics.
TEST(Openni2DriverNodelet, AStreamWithoutAFieldOfViewGetsNominalIntrinsicsAndAWarning) {
  manager->unload("/camera/driver");  // one device: the virtual one is opened again below
  ::setenv("VOCAL_VIRTUAL_OPENNI2_NO_FOV", "color", 1);
  ros::NodeHandle nh;
  nh.setParam("/nofov/driver/depth_registration", false);
  nh.setParam("/nofov/driver/use_device_time", false);
  Latest latest;
  std::string colour_note, level_message;
  ros::AsyncSpinner spinner(2);
  spinner.start();
  ros::Subscriber rgb_info = nh.subscribe<sensor_msgs::CameraInfo>(
      "/nofov/rgb/camera_info", 2, [&](const sensor_msgs::CameraInfo::ConstPtr& m) {
        std::lock_guard<std::mutex> lock(latest.mutex);
        latest.rgb_info = m;
      });
  ros::Subscriber diagnostics = nh.subscribe<diagnostic_msgs::DiagnosticArray>(
      "/diagnostics", 10, [&](const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
        std::lock_guard<std::mutex> lock(latest.mutex);
        for (const auto& s : m->status) {
          if (s.name.find("nofov/driver") == std::string::npos) continue;
          level_message = s.message;
          for (const auto& kv : s.values)
            if (kv.key == "colour intrinsics") colour_note = kv.value;
        }
      });
  nodelet::M_string remappings;
  nodelet::V_string arguments;
  ASSERT_TRUE(manager->load("/nofov/driver", "vocal/OpenNI2Driver", remappings, arguments));
  EXPECT_TRUE(vocal_test::waitUntil(latest.mutex, 20.0, [&] { return latest.rgb_info && !colour_note.empty(); }));
  std::lock_guard<std::mutex> lock(latest.mutex);
  ASSERT_TRUE(latest.rgb_info);
  for (double k : latest.rgb_info->K) EXPECT_TRUE(std::isfinite(k));
  EXPECT_NEAR(latest.rgb_info->K[0], 525.0, 0.1);
  EXPECT_NEAR(latest.rgb_info->K[4], 525.0, 0.1);
  EXPECT_EQ(colour_note, "the colour stream reports no usable field of view (0 x 0 rad): intrinsics from the nominal "
                         "Kinect / Xtion colour focal length (525 px at 640 wide)");
  EXPECT_EQ(level_message, "nominal or borrowed intrinsics: see below");
  ::unsetenv("VOCAL_VIRTUAL_OPENNI2_NO_FOV");
  EXPECT_TRUE(manager->unload("/nofov/driver"));
}

// A device that stops sending mid-stream (the virtual device told to stall after 20 frames, as one
// pulled off its USB bus does): the stall is named in the diagnostics, the device is closed and
// reopened, frames flow again to the same subscriber, and their stamps keep increasing.
TEST(Openni2DriverNodelet, ADeviceThatStopsSendingIsNamedAndReopened) {
  manager->unload("/camera/driver");  // one device: the virtual one is opened again below
  ::setenv("VOCAL_VIRTUAL_OPENNI2_STALL_AFTER", "20", 1);
  ros::NodeHandle nh;
  nh.setParam("/stall/driver/stall_timeout", 1.0);
  std::mutex mutex;
  std::vector<ros::Time> stamps;
  std::string stall_message, reopens = "0";
  ros::AsyncSpinner spinner(2);
  spinner.start();
  ros::Subscriber rgb = nh.subscribe<sensor_msgs::Image>("/stall/rgb/image_raw", 50, [&](const sensor_msgs::Image::ConstPtr& m) {
    std::lock_guard<std::mutex> lock(mutex);
    stamps.push_back(m->header.stamp);
  });
  ros::Subscriber diagnostics = nh.subscribe<diagnostic_msgs::DiagnosticArray>(
      "/diagnostics", 10, [&](const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
        std::lock_guard<std::mutex> lock(mutex);
        for (const auto& s : m->status) {
          if (s.name.find("stall/driver") == std::string::npos) continue;
          if (s.message.find("no colour frame for") != std::string::npos) stall_message = s.message;
          for (const auto& kv : s.values)
            if (kv.key == "reopened after a stall") reopens = kv.value;
        }
      });
  nodelet::M_string remappings;
  nodelet::V_string arguments;
  ASSERT_TRUE(manager->load("/stall/driver", "vocal/OpenNI2Driver", remappings, arguments));
  // 20 frames, a stall, the reopened device's 20 frames.
  EXPECT_TRUE(vocal_test::waitUntil(mutex, 30.0, [&] { return stamps.size() >= 30 && reopens != "0"; }))
      << stamps.size() << " frames, reopened " << reopens << " times";
  ::unsetenv("VOCAL_VIRTUAL_OPENNI2_STALL_AFTER");
  EXPECT_TRUE(manager->unload("/stall/driver"));
  std::lock_guard<std::mutex> lock(mutex);
  EXPECT_EQ(stall_message.rfind("vocal://virtual/1: no colour frame for ", 0), 0u) << stall_message;
  EXPECT_NE(stall_message.find(" s (unplugged, or its USB bus stalled): closed, reopening every 3 s"), std::string::npos)
      << stall_message;
  for (std::size_t i = 1; i < stamps.size(); ++i) EXPECT_GT(stamps[i], stamps[i - 1]) << "frame " << i;
}

int main(int argc, char** argv) {
  vocal_test::reexecWithVirtualOpenni2(argv);
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_openni2_driver_nodelet");
  nodelet::Loader loader(false);
  manager = &loader;
  const int result = RUN_ALL_TESTS();
  loader.clear();
  return result;
}
