// MSG-Cal on a real recording as a user runs it: the recording's folder written as a bag by
// still_poses_to_bag, then calibrate_rig with its default flags, against the authors' own estimates.
// Runs when ../shared/data/real_rigs is there, and says loudly when it is not.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <Eigen/SVD>
#include <yaml-cpp/yaml.h>

#include "test_support.h"
#include "vocal/core/se3.h"

namespace {
using vocal_test::RunResult;

// The mean of the authors' estimates (reference_estimates.csv: roll,pitch,yaw,x,y,z, the camera's pose
// in the lidar frame, R = Rz(yaw) Ry(pitch) Rx(roll)): translations averaged, rotations by their
// chordal mean.
Eigen::Isometry3d authorsMean(const std::string& csv_path, int* count) {
  std::ifstream csv(csv_path);
  std::string line;
  std::getline(csv, line);  // header
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Matrix3d rotations = Eigen::Matrix3d::Zero();
  *count = 0;
  while (std::getline(csv, line)) {
    double v[6];
    if (std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf,%lf,%lf", &v[0], &v[1], &v[2], &v[3], &v[4], &v[5]) != 6) continue;
    rotations += (Eigen::AngleAxisd(v[2], Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(v[1], Eigen::Vector3d::UnitY()) *
                  Eigen::AngleAxisd(v[0], Eigen::Vector3d::UnitX())).toRotationMatrix();
    translation += Eigen::Vector3d(v[3], v[4], v[5]);
    ++*count;
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(rotations, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Isometry3d mean = Eigen::Isometry3d::Identity();
  mean.linear() = svd.matrixU() * svd.matrixV().transpose();
  mean.translation() = translation / std::max(*count, 1);
  return mean;
}
}  // namespace

// A fisheye camera and a VLP-16 in an office (ACFR's cam_lidar_calibration sample, 20 still poses of a
// board on a tripod): calibrate_rig with default flags lands the camera within 3 cm / 0.02 rad of the
// authors' mean; its ring offsets are within a VLP-16's +-3 cm or refused (the office's planes asked for
// +10 to +14 cm, which put the camera 17 cm off, each plane for its own: 15 % of their say within 15 mm
// of the median); and the result's own spread across poses is honest about its error - a camera it calls
// uncertain is withheld from the launch file and the exit status says so. Published since one misdetected
// corner is left out of its pose.
TEST(RealRigCalibration, FisheyeCameraAndVlp16InAnOfficeWithDefaultFlags) {
  const std::string data = vocal_test::realRigFolder("vlp16_fisheye_office");
  if (data.empty()) GTEST_SKIP() << "real rig recording not present";
  const std::string folder = vocal_test::makeTempFolder("real_rig_office");
  // As the recording's README suggests: each pose 0.6 s of images and clouds at 10 Hz, poses 2 s apart.
  RunResult r = vocal_test::runTool("still_poses_to_bag " + data + " " + folder + "/session.bag");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("wrote 20 poses (pose01 ... pose20): 120 images on /camera/image_raw, 120 clouds on /velodyne_points"),
            std::string::npos) << r.output;
  r = vocal_test::runTool("calibrate_rig " + std::string(VOCAL_SOURCE_DIR) + "/config/vlp16_fisheye_office_rig.yaml " + folder +
          "/session.bag --quiet --output-dir " + folder);
  ASSERT_NE(r.output.find("20 still target poses"), std::string::npos) << r.output;
  // pose14.jpg: the detector puts one corner 8 px off (its other corners and every other view's within 0.8 px).
  EXPECT_NE(r.output.find("camera       camera   target in 120 of 120 messages (6 with a corner the detector misplaced, left out of "
                          "the board's pose)"),
            std::string::npos) << r.output;

  const YAML::Node result = YAML::LoadFile(folder + "/calibration.yaml");
  const YAML::Node lidar = result["sensors"][0], camera = result["sensors"][1];
  ASSERT_EQ(camera["name"].as<std::string>(), "camera");
  const YAML::Node rings = lidar["ring_offsets"];
  ASSERT_TRUE(rings) << "a VLP-16's ring offsets are estimated by default";
  ASSERT_EQ(rings["offset_m"].size(), 16u);
  if (rings["applied"].as<bool>()) {
    for (const double offset : rings["offset_m"].as<std::vector<double>>()) EXPECT_LE(std::abs(offset), 0.03);
  } else {
    EXPECT_EQ(rings["verdict"].as<std::string>().rfind("refused: ", 0), 0u) << rings["verdict"].as<std::string>();
  }
  EXPECT_NE(r.output.find("  ring offsets " + rings["verdict"].as<std::string>() + "\n"), std::string::npos) << r.output;

  int estimates = 0;
  const Eigen::Isometry3d reference = authorsMean(data + "/reference_estimates.csv", &estimates);
  ASSERT_EQ(estimates, 50);
  const auto t = camera["translation"].as<std::vector<double>>();
  const auto q = camera["rotation"].as<std::vector<double>>();
  const Eigen::Isometry3d found =
      vocal::poseFromTranslationQuaternion(Eigen::Vector3d(t[0], t[1], t[2]), Eigen::Quaterniond(q[3], q[0], q[1], q[2]));
  const Eigen::Isometry3d error = reference.inverse() * found;
  const double metres = (found.translation() - reference.translation()).norm(), radians = vocal::rotationAngle(error);
  std::cerr << "camera against the authors' mean: " << 1000 * metres << " mm, " << 1000 * radians << " mrad\n";
  EXPECT_LT(metres, 0.03);
  EXPECT_LT(radians, 0.02);

  // Honest: the spread across poses is no less than a third of the error, and the verdict follows it.
  const auto spread = camera["translation_spread"].as<std::vector<double>>();
  const double spread_norm = Eigen::Vector3d(spread[0], spread[1], spread[2]).norm();
  EXPECT_GT(3 * spread_norm, metres) << "spread " << 1000 * spread_norm << " mm";
  const bool published = camera["published"].as<bool>();
  std::ifstream launch_file(folder + "/calibration.launch");
  std::stringstream launch;
  launch << launch_file.rdbuf();
  if (published) {
    EXPECT_NE(launch.str().find(" velodyne camera_optical\"/>"), std::string::npos) << launch.str();
  } else {
    EXPECT_EQ(launch.str().find(" velodyne camera_optical\"/>"), std::string::npos) << launch.str();
    EXPECT_NE(launch.str().find("<!-- camera_optical withheld: uncertain: it moves "), std::string::npos) << launch.str();
  }
  EXPECT_EQ(r.exit_code, published ? 0 : 1) << r.output;
  // With that corner kept, pose 13's board stood 15 mm off the lidar's and the camera moved 10.6 mm between
  // re-solves (withheld); without it 8.7 mm, and the camera is published.
  EXPECT_TRUE(published) << "spread " << 1000 * spread_norm << " mm";
  if (spread_norm > 0.01) {
    EXPECT_FALSE(published) << "a camera that moves over 1 cm between re-solves is not published by default";
    EXPECT_NE(r.output.find("withheld: sensor 'camera' is kept out of calibration.urdf and calibration.launch: uncertain: it moves "),
              std::string::npos) << r.output;
  }
}

namespace {
// A sensor's pose from calibration.yaml or reference.yaml (translation, rotation [qx qy qz qw]).
Eigen::Isometry3d poseOf(const YAML::Node& node) {
  const auto t = node["translation"].as<std::vector<double>>();
  const auto q = node["rotation"].as<std::vector<double>>();
  return vocal::poseFromTranslationQuaternion(Eigen::Vector3d(t[0], t[1], t[2]), Eigen::Quaterniond(q[3], q[0], q[1], q[2]).normalized());
}
}  // namespace

// An Ouster OS1-64 and a stereo pair in a vehicle lab, a board held by a person (PBPC-Cal's recordings, 11
// still poses): still_poses_to_bag writes both cameras' streams, calibrate_rig with default flags
// calibrates the three in one rig. The room asks the OS1's rings for +8 to +67 mm, beyond its
// specification, and the board's held-out poses gain too little from them to take them: refused, named.
// Honest: a camera farther than 30 mm / 20 mrad from the author's result, or a pair whose relative pose
// is over 3 mm / 3 mrad from the factory's stereo calibration, is not published as right.
TEST(RealRigCalibration, Os1AndAStereoPairInALabWithDefaultFlags) {
  const std::string data = vocal_test::realRigFolder("os1_64_stereo_lab");
  if (data.empty()) GTEST_SKIP() << "real rig recording not present";
  const std::string folder = vocal_test::makeTempFolder("real_rig_lab");
  RunResult r = vocal_test::runTool("still_poses_to_bag " + data + " " + folder +
                                    "/session.bag --cloud-topic /os_cloud_node/points --lidar-frame os_sensor");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("wrote 11 poses (pose01 ... pose11): 66 images on /camera/image_raw, 66 images on /camera_right/image_raw, "
                          "66 clouds on /os_cloud_node/points"),
            std::string::npos) << r.output;
  r = vocal_test::runTool("calibrate_rig " + std::string(VOCAL_SOURCE_DIR) + "/config/os1_64_stereo_lab_rig.yaml " + folder +
                          "/session.bag --quiet --output-dir " + folder);
  ASSERT_NE(r.output.find("11 still target poses"), std::string::npos) << r.output;

  const YAML::Node result = YAML::LoadFile(folder + "/calibration.yaml");
  const YAML::Node rings = result["sensors"][0]["ring_offsets"];
  ASSERT_TRUE(rings) << "an OS1-64's ring offsets are estimated by default";
  ASSERT_EQ(rings["offset_m"].size(), 64u);
  const std::vector<double> offsets = rings["offset_m"].as<std::vector<double>>();
  const double largest = std::max(std::abs(*std::min_element(offsets.begin(), offsets.end())), *std::max_element(offsets.begin(), offsets.end()));
  if (largest > 0.03 && !rings["applied"].as<bool>()) {
    EXPECT_EQ(rings["verdict"].as<std::string>().rfind("refused: ", 0), 0u) << rings["verdict"].as<std::string>();
    EXPECT_NE(rings["verdict"].as<std::string>().find("beyond the lidar's specification"), std::string::npos) << rings["verdict"].as<std::string>();
  }
  if (rings["applied"].as<bool>() && largest > 0.03) {
    EXPECT_NE(r.output.find("warning: lidar: the room's planes ("), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(") and the board agree its ranges read +"), std::string::npos) << r.output;
  }

  const YAML::Node reference = YAML::LoadFile(data + "/reference.yaml");
  std::map<std::string, Eigen::Isometry3d> found;
  std::map<std::string, bool> published;
  for (const YAML::Node& sensor : result["sensors"]) {
    found[sensor["name"].as<std::string>()] = poseOf(sensor);
    published[sensor["name"].as<std::string>()] = sensor["published"].as<bool>();
  }
  for (const std::string camera : {"left_camera", "right_camera"}) {
    const Eigen::Isometry3d author = poseOf(reference[camera]);
    const double metres = (found[camera].translation() - author.translation()).norm();
    const double radians = vocal::rotationAngle(author.inverse() * found[camera]);
    std::cerr << camera << " against the author's result: " << 1000 * metres << " mm, " << 1000 * radians << " mrad, "
              << (published[camera] ? "published" : "withheld") << "\n";
    if (metres > 0.03 || radians > 0.02) EXPECT_FALSE(published[camera]) << camera << " is off and published";
  }
  const Eigen::Isometry3d pair = found["left_camera"].inverse() * found["right_camera"];
  const Eigen::Isometry3d factory = poseOf(reference["stereo"]);
  const double pair_metres = (pair.translation() - factory.translation()).norm(), pair_radians = vocal::rotationAngle(factory.inverse() * pair);
  std::cerr << "the pair against the factory's stereo calibration: " << 1000 * pair_metres << " mm, " << 1000 * pair_radians << " mrad\n";
  if (pair_metres > 0.003 || pair_radians > 0.003) {
    EXPECT_FALSE(published["left_camera"] && published["right_camera"]) << "a stereo pair off its factory calibration is published";
  }
  EXPECT_EQ(r.exit_code, published["left_camera"] && published["right_camera"] ? 0 : 1) << r.output;
}

// A Franka arm with a camera on its wrist over a chessboard on the table (ViSP's hand-eye sample, 8 still
// poses, the tool's pose on /tf): calibrate_rig with default flags puts the camera within 2 mm / 0.2
// degrees of the authors' own result, publishes it in the tool frame, and lists OpenCV's closed forms.
TEST(RealRigCalibration, CameraOnAFrankaWristWithDefaultFlags) {
  const std::string data = vocal_test::realRigFolder("franka_eye_in_hand", "session.bag");
  if (data.empty()) GTEST_SKIP() << "real rig recording not present";
  const std::string folder = vocal_test::makeTempFolder("real_rig_franka");
  const RunResult r = vocal_test::runTool("calibrate_rig " + std::string(VOCAL_SOURCE_DIR) + "/config/franka_eye_in_hand_rig.yaml " + data +
                                          "/session.bag --quiet --output-dir " + folder);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("8 still poses of the arm with the board in view (of 8 still; 0 views while the arm moved"), std::string::npos)
      << r.output;
  const YAML::Node result = YAML::LoadFile(folder + "/calibration.yaml");
  EXPECT_EQ(result["setup"].as<std::string>(), "eye-in-hand");
  const YAML::Node camera = result["sensors"][0];
  EXPECT_EQ(camera["parent"].as<std::string>(), "panda_EE");
  EXPECT_TRUE(camera["published"].as<bool>());
  const auto t = camera["translation"].as<std::vector<double>>();
  const auto q = camera["rotation"].as<std::vector<double>>();
  const Eigen::Isometry3d found =
      vocal::poseFromTranslationQuaternion(Eigen::Vector3d(t[0], t[1], t[2]), Eigen::Quaterniond(q[3], q[0], q[1], q[2]));
  // The recording's README: the authors' result, camera optical frame in panda_EE.
  const Eigen::Isometry3d reference = vocal::poseFromTranslationQuaternion(
      Eigen::Vector3d(0.0577, -0.0339, -0.0423), Eigen::Quaterniond(0.70320, 0.00076, 0.00411, 0.71098).normalized());
  const double metres = (found.translation() - reference.translation()).norm();
  const double radians = vocal::rotationAngle(reference.inverse() * found);
  std::cerr << "wrist camera against the authors' result: " << 1000 * metres << " mm, " << radians * 180 / M_PI << " deg\n";
  EXPECT_LT(metres, 0.002);
  EXPECT_LT(radians, 0.2 * M_PI / 180);
  // Honest: its standard deviation is no less than a third of that.
  const auto sd = camera["translation_stddev"].as<std::vector<double>>();
  EXPECT_GT(3 * Eigen::Vector3d(sd[0], sd[1], sd[2]).norm(), metres);
  EXPECT_EQ(result["closed_forms"].size(), 5u);
  std::ifstream launch_file(folder + "/calibration.launch");
  std::stringstream launch;
  launch << launch_file.rdbuf();
  EXPECT_NE(launch.str().find(" panda_EE camera_color_optical_frame\"/>"), std::string::npos) << launch.str();
}

// The same Franka session through the still-pose graph (calibrate_rig --one-graph): the base the rig frame,
// the board lying still in it, the camera on the tool tf reports, each view weighted by what the views
// disagree by beyond their noise (the arm's kinematics, the lens): the camera within 0.2 mm / 0.2 mrad of
// the arm's own graph and 2 mm / 0.2 degrees of the authors', published in the tool frame, the board's parent named.
TEST(RealRigCalibration, CameraOnAFrankaWristThroughTheOneGraph) {
  const std::string data = vocal_test::realRigFolder("franka_eye_in_hand", "session.bag");
  if (data.empty()) GTEST_SKIP() << "real rig recording not present";
  const std::string command = "calibrate_rig " + std::string(VOCAL_SOURCE_DIR) + "/config/franka_eye_in_hand_rig.yaml " + data + "/session.bag --quiet";
  const std::string arm_folder = vocal_test::makeTempFolder("real_rig_franka_arm"), one_folder = vocal_test::makeTempFolder("real_rig_franka_one");
  const RunResult arm = vocal_test::runTool(command + " --output-dir " + arm_folder);
  ASSERT_EQ(arm.exit_code, 0) << arm.output;
  const RunResult one = vocal_test::runTool(command + " --one-graph --output-dir " + one_folder);
  EXPECT_EQ(one.exit_code, 0) << one.output;
  EXPECT_NE(one.output.find("one graph: the board lying still in panda_link0 (the rig frame), the sensors on panda_EE (from tf), 8 still poses\n"),
            std::string::npos)
      << one.output;
  EXPECT_NE(one.output.find("the camera views disagree beyond the corners' noise and the arm's repeatability by"), std::string::npos) << one.output;
  const auto cameraIn = [](const std::string& folder) {
    const YAML::Node camera = YAML::LoadFile(folder + "/calibration.yaml")["sensors"][0];
    const auto t = camera["translation"].as<std::vector<double>>();
    const auto q = camera["rotation"].as<std::vector<double>>();
    return vocal::poseFromTranslationQuaternion(Eigen::Vector3d(t[0], t[1], t[2]), Eigen::Quaterniond(q[3], q[0], q[1], q[2]));
  };
  const YAML::Node result = YAML::LoadFile(one_folder + "/calibration.yaml");
  EXPECT_EQ(result["sensors"][0]["parent"].as<std::string>(), "panda_EE");
  EXPECT_TRUE(result["sensors"][0]["published"].as<bool>());
  EXPECT_EQ(result["board"]["parent"].as<std::string>(), "panda_link0");
  const Eigen::Isometry3d found = cameraIn(one_folder), by_arm = cameraIn(arm_folder);
  const Eigen::Isometry3d reference = vocal::poseFromTranslationQuaternion(
      Eigen::Vector3d(0.0577, -0.0339, -0.0423), Eigen::Quaterniond(0.70320, 0.00076, 0.00411, 0.71098).normalized());
  const double metres = (found.translation() - reference.translation()).norm(), radians = vocal::rotationAngle(reference.inverse() * found);
  const double from_arm_metres = (found.translation() - by_arm.translation()).norm(), from_arm_radians = vocal::rotationAngle(by_arm.inverse() * found);
  std::cerr << "wrist camera through the one graph: " << 1000 * metres << " mm, " << radians * 180 / M_PI << " deg from the authors' result; "
            << 1000 * from_arm_metres << " mm, " << 1000 * from_arm_radians << " mrad from the arm's graph\n";
  EXPECT_LT(metres, 0.002);
  EXPECT_LT(radians, 0.2 * M_PI / 180);
  EXPECT_LT(from_arm_metres, 0.0002);
  EXPECT_LT(from_arm_radians, 0.0002);
  std::ifstream launch_file(one_folder + "/calibration.launch");
  std::stringstream launch;
  launch << launch_file.rdbuf();
  EXPECT_NE(launch.str().find(" panda_EE camera_color_optical_frame\"/>"), std::string::npos) << launch.str();
}

// The folder's pairs are checked before anything is written: an image without its cloud is named.
TEST(RealRigCalibration, StillPosesToBagNamesAPoseWithoutItsCloud) {
  const std::string folder = vocal_test::makeTempFolder("still_poses_missing");
  std::filesystem::create_directories(folder + "/images");
  std::filesystem::create_directories(folder + "/clouds");
  vocal_test::writeText(folder + "/images/pose01.png", "");
  const RunResult r = vocal_test::runTool("still_poses_to_bag " + folder + " " + folder + "/out.bag");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.output, "still_poses_to_bag: error: " + folder + "/images/pose01.png: no cloud of the same pose (" + folder +
                          "/clouds/pose01.pcd)\n");
}

// A stereo pair's folder (images_right/) needs every pose's right image: the one missing is named.
TEST(RealRigCalibration, StillPosesToBagNamesAPoseWithoutItsRightImage) {
  const std::string folder = vocal_test::makeTempFolder("still_poses_missing_right");
  for (const char* sub : {"/images", "/clouds", "/images_right"}) std::filesystem::create_directories(folder + sub);
  for (const char* name : {"pose01", "pose02"}) {
    vocal_test::writeText(folder + "/images/" + name + ".png", "");
    vocal_test::writeText(folder + "/clouds/" + name + ".pcd", "");
  }
  vocal_test::writeText(folder + "/images_right/pose01.png", "");
  const RunResult r = vocal_test::runTool("still_poses_to_bag " + folder + " " + folder + "/out.bag");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.output, "still_poses_to_bag: error: " + folder + "/images/pose02.png: no right image of the same pose in " + folder +
                          "/images_right\n");
}
