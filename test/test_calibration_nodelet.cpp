// rostest: the vocal/MsgCalibration nodelet calibrates a simulated recording of all four sensor types
// played by rosbag play: the calibrate service succeeds, /tf_static carries extrinsics within the
// issue's bounds, the result files and the fused cloud appear; without a rig it stays idle and says why.

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <mutex>
#include <sstream>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <nodelet/loader.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_srvs/Empty.h>
#include <std_srvs/Trigger.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "ros_test_support.h"
#include "test_support.h"
#include "vocal/core/se3.h"
#include "vocal/nodelets/message_conversions.h"
#include "vocal/simulation/simulated_arm.h"
#include "vocal/simulation/simulated_joint_arm.h"
#include "vocal/tools/calibration_bag.h"
#include "vocal/tools/hand_eye_bag.h"

// Plays a recorded session (once the nodelet subscribes) and gives extraction a second for the last messages.
void playSession(const std::string& bag) {
  ASSERT_NO_FATAL_FAILURE(vocal_test::playBag(bag, 120.0));
  ros::WallDuration(1.0).sleep();
}

// Writes FOLDER/rig.yaml and FOLDER/session.bag: the four sensor types, 8 still poses (0.6 s still, 0.3 s
// moving), seed 5. Returns the simulated sensors, with their true poses.
std::vector<vocal::SimulatedSensor> writeFourSensorSession(const std::string& folder) {
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
  return sensors;
}

// The sensor's transform from base_link on /tf_static within `bound` metres and radians of its truth.
void expectOnTfStaticWithin(const tf2_ros::Buffer& tf_buffer, const vocal::SimulatedSensor& sensor, double bound) {
  geometry_msgs::TransformStamped t;
  try {
    t = tf_buffer.lookupTransform("base_link", sensor.spec.frame_id, ros::Time(0), ros::Duration(5.0));
  } catch (const tf2::TransformException& e) {
    FAIL() << sensor.spec.name << ": " << e.what();
  }
  const Eigen::Isometry3d error = sensor.reference_from_sensor.inverse() * tf2::transformToEigen(t);
  std::cout << sensor.spec.name << " on /tf_static: " << error.translation().norm() * 1000 << " mm / " << vocal::rotationAngle(error) * 1000
            << " mrad from the truth\n";
  EXPECT_LT(error.translation().norm(), bound) << sensor.spec.name;
  EXPECT_LT(vocal::rotationAngle(error), bound) << sensor.spec.name;
}

// The latest /diagnostics status whose name holds `name`, kept under `mutex` (vocal_test::waitUntil).
struct LatestDiagnostics {
  LatestDiagnostics(ros::NodeHandle& nh, const std::string& name)
      : subscriber(nh.subscribe<diagnostic_msgs::DiagnosticArray>("/diagnostics", 10, [this, name](const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
          for (const auto& s : m->status)
            if (s.name.find(name) != std::string::npos) {
              std::lock_guard<std::mutex> lock(mutex);
              status = s;
            }
        })) {}
  // A value by key, "" when absent; call under `mutex`.
  std::string value(const std::string& key) const {
    for (const auto& kv : status.values)
      if (kv.key == key) return kv.value;
    return "";
  }
  std::mutex mutex;
  diagnostic_msgs::DiagnosticStatus status;
  ros::Subscriber subscriber;
};

// One live session: the calibration nodelet `name` loaded on FOLDER/rig.yaml, FOLDER/session.bag played
// into it, ~calibrate called; the reply, the transforms it published and its diagnostics kept.
struct LiveCalibration {
  explicit LiveCalibration(const std::string& name) : name(name), diagnostics(nh, name.substr(1)), tf_listener(tf_buffer, nh) {}

  void run(const std::string& folder) {
    nh.setParam(name + "/rig", folder + "/rig.yaml");
    ASSERT_TRUE(manager.load(name, "vocal/MsgCalibration", {}, {}));
    spinner.start();
    ASSERT_NO_FATAL_FAILURE(playSession(folder + "/session.bag"));
    ASSERT_TRUE(ros::service::call(name + "/calibrate", calibrate));
    std::cout << calibrate.response.message << "\n";
  }
  // parent <- child as published; fails the test when there is none.
  Eigen::Isometry3d published(const std::string& parent, const std::string& child) {
    try {
      return tf2::transformToEigen(tf_buffer.lookupTransform(parent, child, ros::Time(0), ros::Duration(5.0)));
    } catch (const tf2::TransformException& e) {
      ADD_FAILURE() << e.what();
      return Eigen::Isometry3d::Identity();
    }
  }

  std::string name;
  ros::NodeHandle nh;
  nodelet::Loader manager{false};
  LatestDiagnostics diagnostics;
  tf2_ros::Buffer tf_buffer;
  tf2_ros::TransformListener tf_listener;
  ros::AsyncSpinner spinner{2};
  std_srvs::Trigger calibrate;
};

TEST(CalibrationNodelet, CalibratesAPlayedSession) {
  const std::string folder = vocal_test::makeTempFolder("calibration_nodelet");
  const std::vector<vocal::SimulatedSensor> sensors = writeFourSensorSession(folder);

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

  ASSERT_NO_FATAL_FAILURE(playSession(folder + "/session.bag"));

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

  for (std::size_t s = 1; s < sensors.size(); ++s) expectOnTfStaticWithin(tf_buffer, sensors[s], 0.005);
  for (const char* file : {"/calibration.yaml", "/calibration.urdf", "/calibration.launch"}) {
    EXPECT_TRUE(std::ifstream(folder + file).good()) << file;
  }
  vocal_test::waitUntil(mutex, 5.0, [&] { return fused != nullptr; });
  std::lock_guard<std::mutex> lock(mutex);
  ASSERT_TRUE(fused);
  EXPECT_EQ(fused->header.frame_id, "base_link");
  EXPECT_GT(fused->width, 1000u);
}

// Every kind of bad message on every sensor's topics: each is dropped and counted against its sensor
// in the diagnostics, the last problem is named there, and the nodelet (in this process's manager)
// still answers. Messages that are odd but valid (NaN and inf depth, NaN ranges, no beams) are taken.
TEST(CalibrationNodelet, BadMessagesAreDroppedAndCountedPerSensor) {
  const std::string folder = vocal_test::makeTempFolder("calibration_nodelet_bad_messages");
  const std::vector<vocal::SimulatedSensor> sensors = vocal::exampleRig(1, 1, 1, 1);
  const vocal::RigDescription rig = vocal::describeSimulatedRig(sensors, vocal::TargetDescription{}, false);
  vocal::writeRigDescription(folder + "/rig.yaml", rig);
  ros::NodeHandle nh;
  nh.setParam("/bad/rig", folder + "/rig.yaml");
  nodelet::Loader manager(false);
  ASSERT_TRUE(manager.load("/bad", "vocal/MsgCalibration", {}, {}));
  LatestDiagnostics diagnostics(nh, "bad");
  ros::AsyncSpinner spinner(2);
  spinner.start();

  std::map<std::string, ros::Publisher> publishers;
  auto publish = [&](const std::string& topic, const auto& msg) {
    using Msg = std::decay_t<decltype(msg)>;
    if (!publishers.count(topic)) {
      publishers[topic] = nh.advertise<Msg>(topic, 10);
      const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(5.0);
      while (publishers[topic].getNumSubscribers() == 0 && ros::WallTime::now() < deadline) ros::WallDuration(0.02).sleep();
    }
    publishers[topic].publish(msg);
    ros::WallDuration(0.2).sleep();  // one message at a time through the nodelet, in order across topics
  };
  std::map<std::string, int> expected_drops;
  const vocal::PinholeCamera camera = vocal::defaultKinectCamera(32, 24);
  // The laser last: its problem is the one the summary names at the end.
  std::vector<vocal::RigSensorDescription> in_order = rig.sensors;
  std::stable_partition(in_order.begin(), in_order.end(),
                        [](const vocal::RigSensorDescription& d) { return d.spec.type != vocal::SensorType::kLaser2d; });
  ASSERT_EQ(in_order.back().spec.type, vocal::SensorType::kLaser2d);
  for (const vocal::RigSensorDescription& d : in_order) {
    const std::string& name = d.spec.name;
    const ros::Time t(100.0);
    switch (d.spec.type) {
      case vocal::SensorType::kCamera: {
        sensor_msgs::CameraInfo uncalibrated = vocal::toCameraInfo(camera, d.spec.frame_id, t);
        uncalibrated.K = {};
        publish(d.camera_info_topic, uncalibrated);  // K = 0
        const sensor_msgs::Image image = vocal::toMono8Image(vocal::ColorImage(32, 24), d.spec.frame_id, t);
        publish(d.image_topic, image);  // no usable camera_info yet
        publish(d.camera_info_topic, vocal::toCameraInfo(camera, d.spec.frame_id, t));
        sensor_msgs::Image wrong_encoding = image;
        wrong_encoding.encoding = "16UC1";
        publish(d.image_topic, wrong_encoding);
        sensor_msgs::Image truncated = image;
        truncated.data.resize(10);
        publish(d.image_topic, truncated);
        expected_drops[name] = 4;
        break;
      }
      case vocal::SensorType::kRgbd: {
        sensor_msgs::CameraInfo binned = vocal::toCameraInfo(camera, d.spec.frame_id, t);
        binned.binning_x = 2;
        publish(d.camera_info_topic, binned);
        publish(d.camera_info_topic, vocal::toCameraInfo(camera, d.spec.frame_id, t));
        sensor_msgs::Image colour_as_depth = vocal::toRgb8Image(vocal::ColorImage(32, 24), d.spec.frame_id, t);
        publish(d.depth_topic, colour_as_depth);
        // NaN and inf depth are "no measurement": taken, not dropped.
        vocal::DepthImage nan_depth(32, 24, std::numeric_limits<float>::quiet_NaN());
        nan_depth(3, 3) = std::numeric_limits<float>::infinity();
        publish(d.depth_topic, vocal::toDepth32FImage(nan_depth, d.spec.frame_id, t));
        expected_drops[name] = 2;
        break;
      }
      case vocal::SensorType::kLidar3d: {
        sensor_msgs::PointCloud2 cloud = vocal::toLidarPointCloud2({Eigen::Vector3d(1, 2, 3)}, {0}, d.spec.frame_id, t);
        sensor_msgs::PointCloud2 no_x = cloud;
        no_x.fields.erase(no_x.fields.begin());
        publish(d.cloud_topic, no_x);
        sensor_msgs::PointCloud2 wrapping = cloud;  // width x point_step wraps in 32 bits (found by fuzzing)
        wrapping.width = 65536, wrapping.point_step = 65536, wrapping.row_step = 16;
        publish(d.cloud_topic, wrapping);
        const float nan = std::numeric_limits<float>::quiet_NaN();
        // Valid, but no point is finite, and a lidar's first cloud needs 1000 points to learn its ring spacing.
        publish(d.cloud_topic, vocal::toLidarPointCloud2({Eigen::Vector3d(nan, 0, 0)}, {0}, d.spec.frame_id, t));
        expected_drops[name] = 3;
        break;
      }
      case vocal::SensorType::kLaser2d: {
        sensor_msgs::LaserScan scan = vocal::toLaserScan({1.0f, 1.0f}, -0.5, 0.01, 10.0, d.spec.frame_id, t);
        sensor_msgs::LaserScan no_increment = scan;
        no_increment.angle_increment = 0.0f;
        publish(d.scan_topic, no_increment);
        sensor_msgs::LaserScan nan_ranges = scan;
        nan_ranges.ranges = {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()};
        publish(d.scan_topic, nan_ranges);
        publish(d.scan_topic, vocal::toLaserScan({}, -0.5, 0.01, 10.0, d.spec.frame_id, t));  // no beams
        expected_drops[name] = 1;
        break;
      }
    }
  }
  const std::string last_problem = in_order.back().scan_topic + ": angle_min must be finite and angle_increment finite and non-zero";
  auto dropsAsExpected = [&] {
    if (diagnostics.status.message != last_problem) return false;
    for (const auto& drops : expected_drops) {
      const std::string suffix = ", " + std::to_string(drops.second) + " dropped";
      const std::string value = diagnostics.value(drops.first);
      if (value.size() < suffix.size() || value.compare(value.size() - suffix.size(), suffix.size(), suffix) != 0) return false;
    }
    return true;
  };
  EXPECT_TRUE(vocal_test::waitUntil(diagnostics.mutex, 10.0, dropsAsExpected)) << [&] {
    std::lock_guard<std::mutex> lock(diagnostics.mutex);
    std::ostringstream seen;
    seen << "summary '" << diagnostics.status.message << "'";
    for (const auto& kv : diagnostics.status.values) seen << "; " << kv.key << ": " << kv.value;
    return seen.str();
  }();
  // Still answering: calibrating from nothing says so.
  std_srvs::Trigger calibrate;
  ASSERT_TRUE(ros::service::call("/bad/calibrate", calibrate));
  EXPECT_FALSE(calibrate.response.success);
  EXPECT_FALSE(calibrate.response.message.empty());
  std::cout << "calibrate after bad messages: " << calibrate.response.message << "\n";
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

// A camera on a pan-tilt head the rig does not describe, played live: the reply names it NOT TRUSTED and
// success is false (a script acting on it applies nothing it cannot trust); the others reach /tf_static
// within 1 cm, the moving camera does not.
TEST(CalibrationNodelet, ASensorThatMovesStaysOffTfStatic) {
  const std::string folder = vocal_test::makeTempFolder("calibration_nodelet_fault");
  std::vector<vocal::SimulatedSensor> sensors = vocal::exampleRig(1, 1, 0, 2);
  for (vocal::SimulatedSensor& s : sensors) s.spec.name = "fault_" + s.spec.name, s.spec.frame_id = "fault_" + s.spec.frame_id;
  const vocal::RigDescription rig = vocal::describeSimulatedRig(sensors, vocal::TargetDescription{}, false);
  vocal::writeRigDescription(folder + "/rig.yaml", rig);
  vocal::SimulatedSessionOptions options;
  options.target_poses = 10;
  options.depth_width = 160;
  options.depth_height = 120;
  options.seed = 5;
  options.faults.push_back({vocal::SimulatedSensorFault::Kind::kMoves, 2, 0.3});  // fault_camera0
  vocal::writeSimulatedCalibrationBag(sensors, rig, options, folder + "/session.bag");

  ros::NodeHandle nh;
  nh.setParam("/calibration_fault/rig", folder + "/rig.yaml");
  nodelet::Loader manager(false);
  ASSERT_TRUE(manager.load("/calibration_fault", "vocal/MsgCalibration", {}, {}));
  tf2_ros::Buffer tf_buffer;
  tf2_ros::TransformListener tf_listener(tf_buffer, nh);
  ros::AsyncSpinner spinner(2);
  spinner.start();
  ASSERT_NO_FATAL_FAILURE(playSession(folder + "/session.bag"));

  std_srvs::Trigger calibrate;
  ASSERT_TRUE(ros::service::call("/calibration_fault/calibrate", calibrate));
  std::cout << calibrate.response.message << "\n";
  EXPECT_FALSE(calibrate.response.success) << calibrate.response.message;
  EXPECT_NE(calibrate.response.message.find("; NOT TRUSTED: fault_camera0: its board views lie "), std::string::npos)
      << calibrate.response.message;
  EXPECT_NE(calibrate.response.message.find("; withheld from /tf_static: fault_camera0 (not trusted)"), std::string::npos)
      << calibrate.response.message;
  for (const int s : {1, 3}) expectOnTfStaticWithin(tf_buffer, sensors[s], 0.01);
  EXPECT_FALSE(tf_buffer.canTransform("base_link", sensors[2].spec.frame_id, ros::Time(0), ros::Duration(1.0)))
      << "the moving camera reached /tf_static";
}

// A session played into a nodelet whose ~max_held_mb its first poses fill: the diagnostics say the
// session is full, what it holds and, per sensor, how many messages were counted but not kept; the
// ~calibrate reply says so with what to do; ~reset empties it.
TEST(CalibrationNodelet, ASessionOverItsMemoryBudgetSaysItIsFull) {
  const std::string folder = vocal_test::makeTempFolder("calibration_nodelet_memory");
  const std::vector<vocal::SimulatedSensor> sensors = writeFourSensorSession(folder);

  ros::NodeHandle nh;
  nh.setParam("/memory/rig", folder + "/rig.yaml");
  nh.setParam("/memory/max_held_mb", 0.5);
  nodelet::Loader manager(false);
  ASSERT_TRUE(manager.load("/memory", "vocal/MsgCalibration", {}, {}));
  LatestDiagnostics diagnostics(nh, "memory");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  ASSERT_NO_FATAL_FAILURE(playSession(folder + "/session.bag"));

  const std::string advice =
      "the session is full (~max_held_mb 0.5): later still poses are not kept; call ~calibrate now, or raise ~max_held_mb and ~reset";
  const auto value = [&](const std::string& key) { return diagnostics.value(key); };
  ASSERT_TRUE(vocal_test::waitUntil(diagnostics.mutex, 5.0, [&] { return diagnostics.status.message == advice; }))
      << diagnostics.status.message;
  {
    std::lock_guard<std::mutex> lock(diagnostics.mutex);
    EXPECT_NE(value("memory").find(" of target data held in "), std::string::npos) << value("memory");
    EXPECT_NE(value("memory").find(" (budget 0.5 MB)"), std::string::npos) << value("memory");
    EXPECT_NE(value("memory").find("; FULL: later messages are counted, not kept"), std::string::npos) << value("memory");
    for (const vocal::SimulatedSensor& s : sensors) {
      EXPECT_NE(value(s.spec.name).find(" not kept (the session is full)"), std::string::npos) << s.spec.name << ": " << value(s.spec.name);
    }
  }
  std_srvs::Trigger calibrate;
  ASSERT_TRUE(ros::service::call("/memory/calibrate", calibrate));
  std::cout << calibrate.response.message << "\n";
  EXPECT_NE(calibrate.response.message.find(
                "; the session was full (~max_held_mb 0.5): still poses after it filled were not kept; for more, raise ~max_held_mb and ~reset"),
            std::string::npos)
      << calibrate.response.message;

  std_srvs::Empty reset;
  ASSERT_TRUE(ros::service::call("/memory/reset", reset));
  EXPECT_TRUE(vocal_test::waitUntil(diagnostics.mutex, 5.0, [&] { return value("memory") == "0.0 MB of target data held in 0 messages (budget 0.5 MB)"; }))
      << value("memory");
}

// A camera on a simulated arm's wrist over a fixed board, the arm on live tf as rosbag play gives it (a
// moving base -> flange, a /tf_static flange -> tool): ~calibrate names the camera in the tool frame
// within 1 mm / 1 mrad of the truth, /tf_static carries it from the tool frame, the diagnostics count the
// tool poses.
TEST(CalibrationNodelet, ACameraOnAnArmFromLiveTf) {
  const std::string folder = vocal_test::makeTempFolder("calibration_nodelet_arm");
  vocal::SimulatedArmOptions arm_options;
  arm_options.poses = 6;
  arm_options.seed = 2;
  const vocal::SimulatedArm arm = vocal::simulateArm(arm_options);
  vocal::TargetDescription target;
  target.pattern = {7, 10, 0.03};
  target.width = 0.36;
  target.height = 0.27;
  const vocal::RigDescription rig = vocal::simulatedHandEyeRig(vocal::HandEyeSetup::kEyeInHand, target);
  vocal::writeRigDescription(folder + "/rig.yaml", rig);
  vocal::writeSimulatedHandEyeBag(arm, rig, {}, folder + "/session.bag");

  LiveCalibration live("/arm_calibration");
  live.nh.setParam("/arm_calibration/output_dir", folder);
  ASSERT_NO_FATAL_FAILURE(live.run(folder));
  const std_srvs::Trigger& calibrate = live.calibrate;
  EXPECT_TRUE(calibrate.response.success) << calibrate.response.message;
  EXPECT_EQ(calibrate.response.message.rfind("calibrated 1 sensor (eye-in-hand) from 6 still arm poses; arm_camera_optical in arm_tool at [", 0), 0u)
      << calibrate.response.message;
  EXPECT_NE(calibrate.response.message.find("; OpenCV's closed forms for arm_camera against it: Tsai "), std::string::npos) << calibrate.response.message;
  const Eigen::Isometry3d error = arm.camera.inverse() * live.published("arm_tool", "arm_camera_optical");
  std::cout << "arm camera on /tf_static: " << error.translation().norm() * 1000 << " mm / " << vocal::rotationAngle(error) * 1000 << " mrad\n";
  EXPECT_LT(error.translation().norm(), 0.001);
  EXPECT_LT(vocal::rotationAngle(error), 0.001);
  std::lock_guard<std::mutex> lock(live.diagnostics.mutex);
  EXPECT_NE(live.diagnostics.value("tool").find(" poses of arm_tool in arm_base from tf, "), std::string::npos) << live.diagnostics.value("tool");
}

// The joints as a URDF (what robot_description holds): revolute joints with their origins and axes.
std::string urdfOf(const std::vector<vocal::JointDescription>& joints) {
  std::ostringstream urdf;
  urdf.precision(12);
  urdf << "<?xml version=\"1.0\"?>\n<robot name=\"head\">\n  <link name=\"" << joints.front().parent << "\"/>\n";
  for (const vocal::JointDescription& joint : joints) {
    const Eigen::Vector3d t = joint.origin.translation(), ypr = joint.origin.rotation().eulerAngles(2, 1, 0);
    urdf << "  <link name=\"" << joint.child << "\"/>\n  <joint name=\"" << joint.name << "\" type=\"continuous\">\n    <parent link=\""
         << joint.parent << "\"/><child link=\"" << joint.child << "\"/>\n    <origin xyz=\"" << t.x() << " " << t.y() << " " << t.z()
         << "\" rpy=\"" << ypr[2] << " " << ypr[1] << " " << ypr[0] << "\"/><axis xyz=\"" << joint.axis.x() << " " << joint.axis.y() << " "
         << joint.axis.z() << "\"/>\n  </joint>\n";
  }
  urdf << "</robot>\n";
  return urdf.str();
}

// A camera on a pan-tilt head in front of a fixed lidar and 2D laser, the head's joints from the URDF on
// the parameter server (urdf_param: /robot_description) and on /joint_states at 200 Hz as rosbag play
// gives them, the camera's mount known: ~calibrate names both joints' offsets within 1 mrad of the truth,
// /tf_static carries the camera from the tilt link, the diagnostics count the joint states.
TEST(CalibrationNodelet, ACameraOnAPanTiltHeadFromLiveJointStates) {
  const std::string folder = vocal_test::makeTempFolder("calibration_nodelet_pan_tilt");
  const std::vector<vocal::SimulatedSensor> sensors = vocal::panTiltRig();
  vocal::SimulatedSessionOptions options;
  options.target_poses = 10;
  options.still_seconds = 0.6;
  options.moving_seconds = 0.4;
  options.depth_width = 160;
  options.depth_height = 120;
  options.seed = 3;
  vocal::RigDescription rig = vocal::describeSimulatedRig(sensors, vocal::TargetDescription{}, false);
  vocal::RigDescription truth = vocal::describeSimulatedRig(sensors, vocal::TargetDescription{}, true);
  vocal::putOnPanTiltHead(sensors, &options, &rig, &truth, true);
  vocal::writeSimulatedCalibrationBag(sensors, rig, options, folder + "/session.bag");
  LiveCalibration live("/head_calibration");
  live.nh.setParam("/robot_description", urdfOf(rig.joints));
  rig.urdf_param = "/robot_description";
  vocal::writeRigDescription(folder + "/rig.yaml", rig);
  ASSERT_NO_FATAL_FAILURE(live.run(folder));
  const std_srvs::Trigger& calibrate = live.calibrate;
  EXPECT_TRUE(calibrate.response.success) << calibrate.response.message;
  for (const vocal::JointDescription& joint : truth.joints) {
    const std::string key = "; joint " + joint.name + " offset ";
    const std::size_t at = calibrate.response.message.find(key);
    ASSERT_NE(at, std::string::npos) << calibrate.response.message;
    const double offset = std::stod(calibrate.response.message.substr(at + key.size())) / 1000.0;  // mrad
    EXPECT_NEAR(offset, joint.offset, 0.001) << joint.name;
  }
  EXPECT_TRUE(live.published("head_tilt_link", "head_camera_depth_optical_frame").isApprox(sensors.back().reference_from_sensor, 1e-6));
  ASSERT_NO_FATAL_FAILURE(expectOnTfStaticWithin(live.tf_buffer, sensors[1], 0.003));  // the 2D laser beside it
  std::lock_guard<std::mutex> lock(live.diagnostics.mutex);
  EXPECT_NE(live.diagnostics.value("joints").find(" joint states on /joint_states ("), std::string::npos) << live.diagnostics.value("joints");
}

// A camera on a 6-joint arm's wrist, the tool from live /joint_states (rosbag play): ~calibrate names the
// arm's joint offsets (the first and last held) and the camera in the tool frame; /tf_static carries it.
TEST(CalibrationNodelet, ACameraOnAnArmFromLiveJointStates) {
  const std::string folder = vocal_test::makeTempFolder("calibration_nodelet_joint_arm");
  vocal::SimulatedArmOptions arm_options;
  arm_options.poses = 8;
  arm_options.seed = 3;
  const vocal::SimulatedJointArm joint_arm = vocal::simulateJointArm(arm_options);
  vocal::TargetDescription target;
  target.pattern = {7, 10, 0.03};
  target.width = 0.36;
  target.height = 0.27;
  const vocal::RigDescription rig = vocal::simulatedJointArmRig(vocal::HandEyeSetup::kEyeInHand, target, joint_arm);
  vocal::writeRigDescription(folder + "/rig.yaml", rig);
  vocal::HandEyeBagOptions bag_options;
  bag_options.joint_arm = &joint_arm;
  vocal::writeSimulatedHandEyeBag(joint_arm.arm, rig, bag_options, folder + "/session.bag");

  LiveCalibration live("/joint_arm_calibration");
  ASSERT_NO_FATAL_FAILURE(live.run(folder));
  const std_srvs::Trigger& calibrate = live.calibrate;
  EXPECT_TRUE(calibrate.response.success) << calibrate.response.message;
  EXPECT_EQ(calibrate.response.message.rfind("calibrated 1 sensor (eye-in-hand) from 8 still arm poses; joint shoulder_pan_joint offset +0.00 mrad", 0), 0u)
      << calibrate.response.message;
  EXPECT_NE(calibrate.response.message.find("; joint elbow_joint offset "), std::string::npos) << calibrate.response.message;
  // Against the mount the last joint's held offset leaves: R(axis, d6) * the true mount.
  const vocal::JointDescription& last = joint_arm.joints.back();
  const Eigen::Isometry3d expected = Eigen::Isometry3d(Eigen::AngleAxisd(last.offset, last.axis)) * joint_arm.arm.camera;
  const Eigen::Isometry3d error = expected.inverse() * live.published("arm_tool", "arm_camera_optical");
  std::cout << "joint arm camera on /tf_static: " << error.translation().norm() * 1000 << " mm / " << vocal::rotationAngle(error) * 1000 << " mrad\n";
  EXPECT_LT(error.translation().norm(), 0.003);
  EXPECT_LT(vocal::rotationAngle(error), 0.003);
  std::lock_guard<std::mutex> lock(live.diagnostics.mutex);
  EXPECT_NE(live.diagnostics.value("joints").find(" joint states on /joint_states ("), std::string::npos) << live.diagnostics.value("joints");
  EXPECT_EQ(live.diagnostics.value("tool"), "");  // no tf lookups: the tool comes from the joints
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_calibration_nodelet");
  return RUN_ALL_TESTS();
}
