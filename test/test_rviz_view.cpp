// rostest: what a user sees in rviz after `roslaunch vocal play_tum_bag.launch odometry:=true rviz:=true`,
// checked without a display. A bag written by tum_to_bag (the camera's body frame x forward, z up, its
// optical frames rotated children, the Kinect's accelerometer on /imu) is played into the odometry
// nodelet; odom must start level (REP-105: z up, the camera's tilt undone), the fused room's floor must
// be horizontal in it, and config/odometry.rviz's default view must have the fused cloud in its frustum.

#include <gtest/gtest.h>

#include <cmath>
#include <mutex>
#include <random>

#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/point_cloud2_iterator.h>
#include <std_srvs/Empty.h>
#include <yaml-cpp/yaml.h>

#include "ros_test_support.h"
#include "test_support.h"
#include "vocal/core/se3.h"
#include "vocal/core/stamp_association.h"
#include "vocal/core/tum_sequence.h"
#include "vocal/nodelets/message_conversions.h"
#include "vocal/simulation/synthetic_sequence.h"
#include "vocal/tools/tum_bag_writer.h"

namespace {

// The orbit view rviz opens with: eye at focal + distance (cos p cos y, cos p sin y, sin p), looking at
// the focal point, z up; vertical field of view `fov`.
struct OrbitView {
  Eigen::Vector3d focal = Eigen::Vector3d::Zero();
  double distance = 10.0, pitch = 0.785, yaw = 0.785, fov = 0.785398;
  std::string fixed_frame;
};

OrbitView readOrbitView(const std::string& path) {
  const YAML::Node root = YAML::LoadFile(path);
  const YAML::Node manager = root["Visualization Manager"];
  const YAML::Node view = manager["Views"]["Current"];
  EXPECT_EQ(view["Class"].as<std::string>(), "rviz/Orbit");
  OrbitView orbit;
  orbit.fixed_frame = manager["Global Options"]["Fixed Frame"].as<std::string>();
  orbit.distance = view["Distance"].as<double>();
  orbit.pitch = view["Pitch"].as<double>();
  orbit.yaw = view["Yaw"].as<double>();
  if (view["Field of View"]) orbit.fov = view["Field of View"].as<double>();
  if (const YAML::Node focal = view["Focal Point"]) {
    orbit.focal = Eigen::Vector3d(focal["X"].as<double>(), focal["Y"].as<double>(), focal["Z"].as<double>());
  }
  return orbit;
}

// Whether `p` is in the view's frustum, for a render area `aspect` times as wide as high.
bool inView(const OrbitView& view, double aspect, const Eigen::Vector3d& p) {
  const Eigen::Vector3d eye =
      view.focal + view.distance * Eigen::Vector3d(std::cos(view.pitch) * std::cos(view.yaw),
                                                   std::cos(view.pitch) * std::sin(view.yaw), std::sin(view.pitch));
  const Eigen::Vector3d forward = (view.focal - eye).normalized();
  const Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d up = right.cross(forward);
  const Eigen::Vector3d d = p - eye;
  const double z = d.dot(forward);
  const double half = std::tan(0.5 * view.fov);
  return z > 0.01 && std::fabs(d.dot(up)) < half * z && std::fabs(d.dot(right)) < aspect * half * z;
}

// The normal of the largest plane among the points below `below_z` (RANSAC, 3 cm), turned upwards.
Eigen::Vector3d floorNormal(const std::vector<Eigen::Vector3d>& cloud, double below_z, int* support) {
  std::vector<Eigen::Vector3d> low;
  for (const Eigen::Vector3d& p : cloud)
    if (p.z() < below_z) low.push_back(p);
  std::mt19937 rng(3);
  std::uniform_int_distribution<std::size_t> pick(0, low.empty() ? 0 : low.size() - 1);
  Eigen::Vector3d best = Eigen::Vector3d::Zero();
  *support = 0;
  for (int trial = 0; trial < 500 && low.size() >= 3; ++trial) {
    const Eigen::Vector3d a = low[pick(rng)], b = low[pick(rng)], c = low[pick(rng)];
    Eigen::Vector3d n = (b - a).cross(c - a);
    if (n.norm() < 1e-6) continue;
    n.normalize();
    int count = 0;
    for (const Eigen::Vector3d& p : low) count += std::fabs(n.dot(p - a)) < 0.03;
    if (count > *support) {
      *support = count;
      best = n.z() < 0.0 ? -n : n;
    }
  }
  return best;
}

std::vector<Eigen::Vector3d> cloudPoints(const sensor_msgs::PointCloud2& cloud) {
  std::vector<Eigen::Vector3d> points;
  for (sensor_msgs::PointCloud2ConstIterator<float> x(cloud, "x"), y(cloud, "y"), z(cloud, "z"); x != x.end(); ++x, ++y, ++z)
    points.emplace_back(*x, *y, *z);
  return points;
}

// The angle between the world's up and odom's up, both seen from the camera at its first frame.
double startTiltError(const Eigen::Isometry3d& odom_from_body, const Eigen::Isometry3d& world_from_optical) {
  const Eigen::Matrix3d odom_from_optical = odom_from_body.linear() * vocal::bodyFromOpticalRotation();
  const Eigen::Vector3d up_by_odom = odom_from_optical.transpose() * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d up_by_world = world_from_optical.linear().transpose() * Eigen::Vector3d::UnitZ();
  return std::acos(std::clamp(up_by_odom.dot(up_by_world), -1.0, 1.0));
}

class RvizView : public ::testing::Test {
 protected:
  void SetUp() override {
    subscribers_ = {nh_.subscribe<nav_msgs::Odometry>("/odom", 1000,
                                                      [this](const nav_msgs::Odometry::ConstPtr& m) {
                                                        std::lock_guard<std::mutex> lock(mutex_);
                                                        odom_.push_back(m);
                                                      }),
                    nh_.subscribe<sensor_msgs::PointCloud2>("/fused_cloud", 2, [this](const sensor_msgs::PointCloud2::ConstPtr& m) {
                      std::lock_guard<std::mutex> lock(mutex_);
                      fused_cloud_ = m;
                    })};
    spinner_.start();
    // Each test's bag starts afresh (its stamps may run on from the last one's).
    ros::service::waitForService("/reset_odom", ros::Duration(30.0));
    std_srvs::Empty reset;
    ASSERT_TRUE(ros::service::call("/reset_odom", reset));
  }

  // Plays the bag as play_tum_bag.launch does, without its motion capture, once the nodelet listens.
  static void playBag(const std::string& bag, double rate) {
    using T = vocal::TumBagTopics;
    vocal_test::playBag(bag, 120.0,
                        {"--delay", "0.5", "--rate", std::to_string(rate), "--topics", T::kRgbImage, T::kDepthImage, T::kRgbInfo,
                         T::kImu, "/tf_static"});
  }

  // The odometry's first pose and its fused cloud once the bag has played (at least `frames` tracked:
  // a frame the synchroniser's queue overflows on is lost) and the map is published.
  void collect(std::size_t frames, Eigen::Isometry3d* first_pose, std::vector<Eigen::Vector3d>* cloud) {
    vocal_test::waitUntil(mutex_, 20.0, [&] { return odom_.size() >= frames; });
    ros::WallDuration(2.5).sleep();  // the last frames, and the fused cloud's timer publishes the last keyframes
    std::lock_guard<std::mutex> lock(mutex_);
    ASSERT_GE(odom_.size(), frames);
    ASSERT_TRUE(fused_cloud_);
    EXPECT_EQ(odom_.front()->header.frame_id, "odom");
    EXPECT_EQ(odom_.front()->child_frame_id, vocal::TumBagTopics::kCameraFrame);
    EXPECT_EQ(fused_cloud_->header.frame_id, "odom");
    const auto& p = odom_.front()->pose.pose;
    *first_pose = vocal::poseFromTranslationQuaternion(Eigen::Vector3d(p.position.x, p.position.y, p.position.z),
                                                       Eigen::Quaterniond(p.orientation.w, p.orientation.x, p.orientation.y, p.orientation.z));
    *cloud = cloudPoints(*fused_cloud_);
  }

  ros::NodeHandle nh_;
  std::mutex mutex_;
  std::vector<nav_msgs::Odometry::ConstPtr> odom_;
  sensor_msgs::PointCloud2::ConstPtr fused_cloud_;
  std::vector<ros::Subscriber> subscribers_;
  ros::AsyncSpinner spinner_{2};
};

// The synthetic room the demo renders (the camera starts pitched 6-20 deg down and rolled): odom is
// level, the floor horizontal, and the default view holds the room.
TEST_F(RvizView, DemoRoomStandsUprightInTheDefaultView) {
  const std::string folder = vocal_test::makeTempFolder("rviz_view");
  const int frames = 60;
  vocal::SyntheticSequenceOptions options = vocal_test::smallSequenceOptions(frames);
  options.sensor_model = vocal::kinectLikeSensorModel();
  vocal::writeSyntheticSequence(folder + "/seq", options);
  const vocal::TumSequence sequence = vocal::TumSequence::open(folder + "/seq");
  ASSERT_EQ(sequence.accelerometer().size(), sequence.groundTruth().size());
  vocal::writeTumBag(sequence, folder + "/seq.bag");
  ASSERT_NO_FATAL_FAILURE(playBag(folder + "/seq.bag", 0.5));
  Eigen::Isometry3d first_pose;
  std::vector<Eigen::Vector3d> cloud;
  collect(frames * 2 / 3, &first_pose, &cloud);
  if (HasFatalFailure()) return;

  const double camera_tilt = startTiltError(Eigen::Isometry3d::Identity(), sequence.groundTruth().front().pose);
  const double tilt_error = startTiltError(first_pose, sequence.groundTruth().front().pose);
  std::cout << "synthetic room: the camera started " << camera_tilt * 180 / M_PI << " deg from level; odom's up is "
            << tilt_error * 180 / M_PI << " deg from the world's\n";
  ASSERT_GT(camera_tilt, 0.1);  // the check means something: unlevelled, odom would be this far off
  EXPECT_LT(tilt_error, 1.0 * M_PI / 180);

  int support = 0;
  const Eigen::Vector3d floor = floorNormal(cloud, -0.5, &support);
  const double floor_tilt = std::acos(std::clamp(floor.z(), -1.0, 1.0));
  std::cout << "fused cloud: " << cloud.size() << " points; floor plane of " << support << " points, normal "
            << floor_tilt * 180 / M_PI << " deg from z\n";
  EXPECT_GT(support, static_cast<int>(cloud.size() / 5));
  EXPECT_LT(floor_tilt, 2.0 * M_PI / 180);

  const OrbitView view = readOrbitView(std::string(VOCAL_SOURCE_DIR) + "/config/odometry.rviz");
  EXPECT_EQ(view.fixed_frame, "odom");
  // The render area of rviz's 1200 x 800 window beside its Displays panel: 820 x 710 pixels
  // (docs/images/rviz_demo.png, made by scripts/rviz_screenshot).
  std::size_t inside = 0;
  for (const Eigen::Vector3d& p : cloud) inside += inView(view, 820.0 / 710.0, p);
  const double share = static_cast<double>(inside) / std::max<std::size_t>(cloud.size(), 1);
  std::cout << "the default view holds " << 100.0 * share << " % of the fused cloud\n";
  EXPECT_GT(share, 0.9);
}

// A real Kinect's accelerometer (TUM freiburg1_xyz, its motion capture's z up): odom within 5 deg of
// level (the sensor's own error, test_gravity.cpp) where the camera started 38 deg down.
TEST_F(RvizView, RealKinectAccelerometerLevelsOdom) {
  const std::string folder = vocal_test::tumDataFolder();
  if (folder.empty()) GTEST_SKIP() << "TUM data not found: the real accelerometer is not checked";
  const vocal::TumSequence sequence = vocal::TumSequence::open(folder);
  ASSERT_FALSE(sequence.accelerometer().empty());
  const std::string bag = vocal_test::makeTempFolder("rviz_view_real") + "/fr1_xyz.bag";
  vocal::writeTumBag(sequence, bag);
  ASSERT_NO_FATAL_FAILURE(playBag(bag, 1.0));
  Eigen::Isometry3d first_pose;
  std::vector<Eigen::Vector3d> cloud;
  collect(sequence.size() / 3, &first_pose, &cloud);
  if (HasFatalFailure()) return;
  const std::vector<double> stamps = vocal::trajectoryStamps(sequence.groundTruth());
  const double first_stamp = odom_.front()->header.stamp.toSec();
  const Eigen::Isometry3d truth = sequence.groundTruth()[vocal::closestStampIndex(stamps, first_stamp)].pose;
  const double camera_tilt = startTiltError(Eigen::Isometry3d::Identity(), truth);
  const double tilt_error = startTiltError(first_pose, truth);
  std::cout << "freiburg1_xyz: the camera started " << camera_tilt * 180 / M_PI << " deg from level; odom's up is "
            << tilt_error * 180 / M_PI << " deg from the motion capture's\n";
  EXPECT_LT(tilt_error, 5.0 * M_PI / 180);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_rviz_view");
  return RUN_ALL_TESTS();
}
