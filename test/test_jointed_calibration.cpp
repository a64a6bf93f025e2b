// MSG-Cal with a sensor behind joints (a camera on a pan-tilt head) in the same graph as rigid sensors:
// joint offsets and mounts against the truth of simulated heads.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <functional>
#include <iterator>
#include <limits>
#include <map>
#include <random>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl_parser/kdl_parser.hpp>

#include "test_support.h"

#include "vocal/calibration/association/hand_eye_association.h"
#include "vocal/calibration/association/joint_positions.h"
#include "vocal/calibration/extraction/board_outline.h"
#include "vocal/calibration/extraction/pattern_observation.h"
#include "vocal/calibration/output/calibrated_urdf.h"
#include "vocal/calibration/point_statistics.h"
#include "vocal/calibration/rig_description.h"
#include "vocal/calibration/solver/hand_eye_calibration.h"
#include "vocal/calibration/solver/sensor_trust.h"
#include "vocal/calibration/urdf_joints.h"
#include "vocal/core/pinhole_camera.h"
#include "vocal/simulation/simulated_joint_arm.h"
#include "vocal/calibration/solver/graph_calibration.h"
#include "vocal/core/errors.h"
#include "vocal/core/se3.h"
#include "vocal/simulation/rig_simulator.h"
#include "vocal/simulation/simulated_pan_tilt.h"

namespace {
// The rig of the simulator with its camera on a pan-tilt head: rgbd0 (the reference) and lidar0 fixed,
// camera0 on the head's tilt link, every pose's views as each sensor sees the board; with `head_laser`, a
// 2D laser (kHeadLaser) on the tilt link too, 5 cm under the camera, scanning across its line of sight.
struct PanTiltSession {
  std::vector<vocal::SensorSpec> specs;
  std::vector<vocal::SimulatedSensor> fixed;  // the truth of the rigid ones
  vocal::SimulatedPanTilt head;
  std::vector<vocal::TargetObservation> observations;
  vocal::CalibrationOptions options;
};

constexpr int kCamera = 2;
constexpr int kHeadLaser = 3;

PanTiltSession panTiltSession(std::uint32_t seed, double pixel_noise = 0.2, double backlash = 0.001, double encoder_counts = 4096.0,
                              const Eigen::Vector3d& tilt_origin_error = Eigen::Vector3d::Zero(), bool head_laser = false) {
  PanTiltSession session;
  session.fixed = vocal::exampleRig(1, 1, 0, 1);
  if (head_laser) {
    vocal::SimulatedSensor laser;
    laser.spec = {"head_laser", vocal::SensorType::kLaser2d, "head_laser"};
    laser.reference_from_sensor.linear() = vocal::rotationFromRollPitchYaw(0.12, 0.01, -0.02);  // its mount on the tilt link
    laser.reference_from_sensor.translation() = Eigen::Vector3d(0.05, 0.0, -0.02);
    session.fixed.push_back(laser);
  }
  vocal::RigSimulationOptions simulation;
  simulation.target_poses = 16;
  simulation.range_noise = 0.001;
  simulation.pixel_noise = pixel_noise;
  simulation.seed = seed;
  const vocal::SimulatedRig boards = vocal::simulateRig({}, simulation);
  Eigen::Isometry3d mount = Eigen::Isometry3d::Identity();  // the camera 6 cm ahead of the tilt axis, looking along x
  mount.linear() = vocal::rotationFromRollPitchYaw(0.01, -0.02, 0.015) * vocal::bodyFromOpticalRotation();
  mount.translation() = Eigen::Vector3d(0.06, 0.01, 0.03);
  vocal::SimulatedPanTiltOptions head_options;
  head_options.seed = seed;
  head_options.wander = 0.3;
  head_options.backlash = backlash;
  head_options.encoder_counts = encoder_counts;
  head_options.tilt_origin_error = tilt_origin_error;
  session.head = vocal::simulatePanTilt(boards.reference_from_target, mount, head_options);
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> direction(0, 1);
  for (const vocal::SimulatedSensor& s : session.fixed) session.specs.push_back(s.spec);
  for (int k = 0; k < simulation.target_poses; ++k) {
    const Eigen::Isometry3d& board = boards.reference_from_target[k];
    for (int s = 0; s < static_cast<int>(session.fixed.size()); ++s) {
      vocal::SimulatedSensor placed = session.fixed[s];
      const std::vector<double>& angles = session.head.angles[k];
      if (s == kCamera) placed.reference_from_sensor = session.head.baseFromSensor(angles);
      if (s == kHeadLaser) placed.reference_from_sensor = session.head.baseFromSensor(angles, session.fixed[s].reference_from_sensor);
      vocal::TargetObservation o = vocal::observeTarget(placed, board, 0.45, 0.35, simulation, &rng);
      if (o.points.empty()) continue;
      o.sensor = s;
      o.target_pose = k;
      if (s >= kCamera) o.joint_positions = session.head.reported(angles, {2 * direction(rng) - 1, 2 * direction(rng) - 1});
      session.observations.push_back(o);
    }
  }
  session.options.reference_pose = session.fixed[0].reference_from_sensor;
  session.options.mounts.joints = session.head.joints;
  for (vocal::JointDescription& joint : session.options.mounts.joints) joint.offset = 0.0;  // unknown
  session.options.mounts.joints[1].origin.translation() -= tilt_origin_error;  // the model's
  session.options.mounts.chains = {{}, {}, session.head.chain};
  if (head_laser) session.options.mounts.chains.push_back(session.head.chain);
  return session;
}

// The camera where the result puts it at each still pose against where it was, rms over the poses (each
// pose's own error holds the encoders' quantisation and backlash: up to 1 mrad per joint).
double cameraErrorTranslation(const PanTiltSession& session, const vocal::CalibrationResult& result, double* rotation) {
  double translation = 0.0, poses = 0.0;
  *rotation = 0.0;
  for (const vocal::TargetObservation& o : session.observations) {
    if (o.sensor != kCamera) continue;
    const Eigen::Isometry3d difference =
        session.head.baseFromSensor(session.head.angles[o.target_pose]).inverse() * result.rigFromSensorAt(o);
    translation += difference.translation().squaredNorm();
    *rotation += std::pow(vocal::rotationAngle(difference), 2);
    poses += 1.0;
  }
  *rotation = std::sqrt(*rotation / poses);
  return std::sqrt(translation / poses);
}
// A pose as calibration.yaml and ground_truth.yaml write it: translation, rotation [qx qy qz qw].
Eigen::Isometry3d yamlPose(const YAML::Node& n) {
  const std::vector<double> t = n["translation"].as<std::vector<double>>(), q = n["rotation"].as<std::vector<double>>();
  return vocal::poseFromTranslationQuaternion({t[0], t[1], t[2]}, Eigen::Quaterniond(q[3], q[0], q[1], q[2]));
}
}  // namespace

TEST(JointedCalibration, PanTiltOffsetsAndMountsWithTheRigidSensors) {
  for (const std::uint32_t seed : {1u, 2u, 3u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    PanTiltSession session = panTiltSession(seed);
    // The CAD mount known: both offsets are solvable.
    session.options.mounts.known_mounts = {std::nullopt, std::nullopt, session.head.mount};
    const vocal::CalibrationResult known = vocal::calibrateRig(session.specs, session.observations, session.options);
    ASSERT_TRUE(known.trusted) << known.failure;
    for (int j = 0; j < 2; ++j) {
      EXPECT_TRUE(known.joints[j].held.empty()) << known.joints[j].held;
      EXPECT_NEAR(known.joints[j].offset, session.head.joints[j].offset, 0.001) << session.head.joints[j].name;
      EXPECT_GT(known.joints[j].standard_deviation, 0.0);
    }
    double rotation = 0.0;
    EXPECT_LT(cameraErrorTranslation(session, known, &rotation), 0.002);
    EXPECT_LT(rotation, 0.002);
    const Eigen::Isometry3d lidar_error = session.fixed[1].reference_from_sensor.inverse() * known.sensors[1].reference_from_sensor;
    EXPECT_LT(lidar_error.translation().norm(), 0.002);
    EXPECT_LT(vocal::rotationAngle(lidar_error), 0.002);

    // The mount unknown too: the tilt offset is the mount's to take up (held, said why); the pan offset
    // and the camera at every pose still come out.
    session.options.mounts.known_mounts.clear();
    const vocal::CalibrationResult free = vocal::calibrateRig(session.specs, session.observations, session.options);
    ASSERT_TRUE(free.trusted) << free.failure;
    EXPECT_TRUE(free.joints[0].held.empty()) << free.joints[0].held;
    // ... weakly: a tilt over 0.6 rad turns the pan axis in the camera's frame little, and the mount takes
    // up most of a pan offset; its sigma says so (5-7 mrad here), and the camera at each pose holds.
    EXPECT_NEAR(free.joints[0].offset, session.head.joints[0].offset, 3.5 * free.joints[0].standard_deviation);
    EXPECT_GT(free.joints[0].standard_deviation, 0.003);
    EXPECT_NE(free.joints[0].weak.find("move 'head_tilt_joint' over more than its"), std::string::npos) << free.joints[0].weak;
    EXPECT_NE(free.joints[1].held.find("no joint after it moved"), std::string::npos) << free.joints[1].held;
    EXPECT_LT(cameraErrorTranslation(session, free, &rotation), 0.003);
    EXPECT_LT(rotation, 0.004);
  }
}

// A 2D laser on the head beside its camera (a sensor on any link): its scan lines join the graph through
// the same joints, seen from its own block per still pose tied to the chain times its mount. With the
// camera's CAD mount known and the board's edges held, both offsets are solved and the laser's mount lands
// within 2 mm / 2 mrad; nothing else moves (the camera as without the laser, within 0.1 mm / 0.1 mrad).
TEST(JointedCalibration, A2dLaserOnTheHeadBesideItsCamera) {
  for (const std::uint32_t seed : {1u, 2u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    PanTiltSession session = panTiltSession(seed, 0.2, 0.001, 4096.0, Eigen::Vector3d::Zero(), true);
    vocal::CalibrationOptions& options = session.options;
    options.board_edges.enabled = true;
    options.board_edges.width = 0.9;
    options.board_edges.height = 0.7;
    options.mounts.known_mounts = {std::nullopt, std::nullopt, session.head.mount, std::nullopt};
    int laser_views = 0;
    for (const vocal::TargetObservation& o : session.observations) laser_views += o.sensor == kHeadLaser;
    ASSERT_GE(laser_views, 6);
    const vocal::CalibrationResult result = vocal::calibrateRig(session.specs, session.observations, options);
    ASSERT_TRUE(result.trusted) << result.failure;
    for (int j = 0; j < 2; ++j) EXPECT_NEAR(result.joints[j].offset, session.head.joints[j].offset, 0.001) << session.head.joints[j].name;
    double worst_t = 0.0, worst_r = 0.0;
    for (const vocal::TargetObservation& o : session.observations) {
      if (o.sensor != kHeadLaser) continue;
      const Eigen::Isometry3d truth = session.head.baseFromSensor(session.head.angles[o.target_pose], session.fixed[kHeadLaser].reference_from_sensor);
      const Eigen::Isometry3d difference = truth.inverse() * result.rigFromSensorAt(o);
      worst_t = std::max(worst_t, difference.translation().norm());
      worst_r = std::max(worst_r, vocal::rotationAngle(difference));
    }
    // At each pose the encoders' counts and backlash leave up to 1.4 mrad between the joints' readings and
    // where they were.
    EXPECT_LT(worst_t, 0.002);
    EXPECT_LT(worst_r, 0.003);
    const Eigen::Isometry3d mount_error = session.fixed[kHeadLaser].reference_from_sensor.inverse() * result.sensors[kHeadLaser].reference_from_sensor;
    EXPECT_LT(mount_error.translation().norm(), 0.002);
    EXPECT_LT(vocal::rotationAngle(mount_error), 0.002);
    EXPECT_GT(result.sensors[kHeadLaser].standard_deviation.head<3>().norm(), 0.0);

    // The same session without the laser: the camera where it was.
    PanTiltSession without = session;
    without.specs.pop_back();
    without.options.mounts.chains.pop_back();
    without.options.mounts.known_mounts.pop_back();
    without.observations.erase(std::remove_if(without.observations.begin(), without.observations.end(),
                                              [](const vocal::TargetObservation& o) { return o.sensor == kHeadLaser; }),
                               without.observations.end());
    const vocal::CalibrationResult alone = vocal::calibrateRig(without.specs, without.observations, without.options);
    ASSERT_TRUE(alone.trusted) << alone.failure;
    double with_r = 0.0, alone_r = 0.0;
    EXPECT_NEAR(cameraErrorTranslation(session, result, &with_r), cameraErrorTranslation(without, alone, &alone_r), 1e-4);
    EXPECT_NEAR(with_r, alone_r, 1e-4);
  }
}

// A head whose tilt joint sits 8 mm ahead of and 10 mm above where its model says: with the model's origin
// the camera lands over a centimetre off; with the tilt's origin free (and its CAD mount known) the
// still-pose graph finds the shift within its stated sigmas and the camera is right within what the
// encoders leave at each pose, the rigid lidar unmoved.
TEST(JointedCalibration, AFreeTiltOriginTakesUpAHeadBuiltOffItsDrawing) {
  for (const std::uint32_t seed : {1u, 2u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const Eigen::Vector3d error(0.008, 0.0, 0.01);
    PanTiltSession session = panTiltSession(seed, 0.2, 0.001, 4096.0, error);
    session.options.mounts.known_mounts = {std::nullopt, std::nullopt, session.head.mount};
    const vocal::CalibrationResult model = vocal::calibrateRig(session.specs, session.observations, session.options);
    double model_rotation = 0.0;
    const double model_translation = cameraErrorTranslation(session, model, &model_rotation);
    session.options.mounts.joints[1].free_origin = true;
    const vocal::CalibrationResult free = vocal::calibrateRig(session.specs, session.observations, session.options);
    ASSERT_TRUE(free.trusted) << free.failure;
    double rotation = 0.0;
    const double translation = cameraErrorTranslation(session, free, &rotation);
    const vocal::JointCalibration& tilt = free.joints[1];
    std::printf("tilt origin off by (8, 0, 10) mm, seed %u: model's origin %.2f mm / %.2f mrad rms over the poses, tilt free %.2f mm / %.2f mrad, "
                "shift (%+.2f %+.2f %+.2f) mm; %s\n",
                seed, 1000 * model_translation, 1000 * model_rotation, 1000 * translation, 1000 * rotation, 1000 * tilt.origin_correction[3],
                1000 * tilt.origin_correction[4], 1000 * tilt.origin_correction[5], tilt.origin_observability.c_str());
    // The encoders' 1.5 mrad counts and 1 mrad of backlash at each pose stay in the camera's error.
    EXPECT_GT(model_translation, 0.01);
    EXPECT_LT(translation, 0.004);
    EXPECT_LT(rotation, 0.003);
    ASSERT_TRUE(tilt.origin_free);
    for (int k = 0; k < 3; ++k) {
      EXPECT_GT(tilt.origin_sigma[3 + k], 0.0);
      EXPECT_NEAR(tilt.origin_correction[3 + k], error[k], 3.0 * tilt.origin_sigma[3 + k]) << "shift along " << "xyz"[k];
    }
    // A turn of the tilt's origin about the pan axis is the pan's offset: held, said.
    EXPECT_NE(tilt.origin_observability.find("held at the model's (the session's motion does not fix it): turn about z"), std::string::npos)
        << tilt.origin_observability;
    EXPECT_FALSE(free.joints[0].origin_free);
    // The result's joints are the solved ones: what places the camera at each pose.
    EXPECT_TRUE(free.mounts.joints[1].origin.isApprox(tilt.origin));
    EXPECT_FALSE(free.mounts.joints[1].free_origin);
    const Eigen::Isometry3d lidar_error = session.fixed[1].reference_from_sensor.inverse() * free.sensors[1].reference_from_sensor;
    EXPECT_LT(lidar_error.translation().norm(), 0.002);
  }
}

TEST(JointedCalibration, IgnoringTheJointsIsFarOff) {
  // The same session solved as if the camera were fixed (its views at joint positions read as one mount):
  // the solver cannot fit it, the camera lands centimetres off at some pose.
  PanTiltSession session = panTiltSession(4);
  vocal::CalibrationOptions rigid = session.options;
  rigid.mounts = {};
  const vocal::CalibrationResult ignored = vocal::calibrateRig(session.specs, session.observations, rigid);
  double rotation = 0.0, translation = cameraErrorTranslation(session, ignored, &rotation);
  EXPECT_GT(std::max(translation / 0.002, rotation / 0.002), 10.0);
  EXPECT_GT(ignored.sensors[kCamera].disagreement_angle, 0.02);
}

TEST(JointedCalibration, RefusesWhatItCannotSolve) {
  PanTiltSession session = panTiltSession(5);
  // A reference behind joints.
  vocal::CalibrationOptions options = session.options;
  options.mounts.chains = {session.head.chain, {}, {}};
  EXPECT_NE(vocal_test::inputErrorOf([&] { vocal::calibrateRig(session.specs, session.observations, options); })
                .find("the reference sensor 'rgbd0' is behind joints"),
            std::string::npos);
  // A jointed view without its joint positions.
  std::vector<vocal::TargetObservation> observations = session.observations;
  for (vocal::TargetObservation& o : observations)
    if (o.sensor == kCamera) o.joint_positions.pop_back();
  const std::string missing = vocal_test::inputErrorOf([&] { vocal::calibrateRig(session.specs, observations, session.options); });
  EXPECT_NE(missing.find("'camera0' is behind 2 joints, but its view at still pose"), std::string::npos) << missing;
  // The head never moved its tilt: nothing after the pan moved, so neither offset is solvable.
  observations = session.observations;
  for (vocal::TargetObservation& o : observations)
    if (o.sensor == kCamera) o.joint_positions[1] = 0.3;
  const vocal::CalibrationResult result = vocal::calibrateRig(session.specs, observations, session.options);
  EXPECT_FALSE(result.joints[0].held.empty());
  EXPECT_LT(result.joints[1].motion, 1e-9);
}

namespace {
// A head and an arm-like chain with rotated origins, a prismatic joint, a fixed joint and a slanted axis.
const char kTestUrdf[] = R"(<?xml version="1.0"?>
<robot name="test_robot">
  <link name="base_link"/><link name="torso"/><link name="pan"/><link name="tilt"/><link name="camera_mount"/>
  <joint name="torso_lift" type="prismatic">
    <parent link="base_link"/><child link="torso"/><origin xyz="0.1 0 0.4" rpy="0 0 0.2"/><axis xyz="0 0 1"/>
    <limit lower="0" upper="0.4" effort="1" velocity="1"/>
  </joint>
  <joint name="head_pan" type="continuous">
    <parent link="torso"/><child link="pan"/><origin xyz="0.05 0.02 0.6" rpy="0.01 -0.02 0.3"/><axis xyz="0 0 1"/>
  </joint>
  <joint name="head_tilt" type="revolute">
    <parent link="pan"/><child link="tilt"/><origin xyz="0.03 0 0.08" rpy="0.1 0.05 -0.1"/><axis xyz="0.1 1 0.05"/>
    <calibration rising="0.0123"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/>
  </joint>
  <joint name="mount" type="fixed">
    <parent link="tilt"/><child link="camera_mount"/><origin xyz="0.06 0.01 0.03" rpy="-1.57 0 -1.57"/>
  </joint>
</robot>
)";
}  // namespace

TEST(JointedCalibration, UrdfJointsMatchKdlsForwardKinematics) {
  const std::vector<vocal::JointDescription> joints = vocal::urdfJointsFromString(kTestUrdf, "test URDF");
  ASSERT_EQ(joints.size(), 4u);
  const std::vector<int> chain = vocal::jointChain(joints, "base_link", "camera_mount", "test");
  ASSERT_EQ(chain.size(), 4u);
  std::vector<double> offsets(joints.size(), 0.0);
  for (std::size_t j = 0; j < joints.size(); ++j)
    if (joints[j].name == "head_tilt") {
      EXPECT_DOUBLE_EQ(joints[j].offset, 0.0123);  // robot_calibration's rising
    }
  KDL::Tree tree;
  ASSERT_TRUE(kdl_parser::treeFromString(kTestUrdf, tree));
  KDL::Chain kdl_chain;
  ASSERT_TRUE(tree.getChain("base_link", "camera_mount", kdl_chain));
  KDL::ChainFkSolverPos_recursive solver(kdl_chain);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> position(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<double> positions;
    KDL::JntArray q(kdl_chain.getNrOfJoints());
    unsigned int moving = 0;
    for (const int j : chain) {
      positions.push_back(joints[j].type == vocal::JointType::kFixed ? 0.0 : position(rng));
      if (joints[j].type != vocal::JointType::kFixed) q(moving++) = positions.back();
    }
    KDL::Frame frame;
    ASSERT_GE(solver.JntToCart(q, frame), 0);
    const Eigen::Isometry3d ours = vocal::chainPose(joints, chain, positions, offsets);
    for (int r = 0; r < 3; ++r) {
      EXPECT_NEAR(ours.translation()[r], frame.p(r), 1e-9);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(ours.linear()(r, c), frame.M(r, c), 1e-9);
    }
  }
  EXPECT_NE(vocal_test::inputErrorOf([] { vocal::urdfJointsFromString("<robot><link", "robot_description"); })
                .find("robot_description: not a URDF robot description"),
            std::string::npos);
  EXPECT_NE(vocal_test::inputErrorOf([&] { vocal::jointChain(joints, "base_link", "gripper", "sensor 'x'"); })
                .find("sensor 'x': no chain of joints leads from 'base_link' to 'gripper'"),
            std::string::npos);
}

TEST(JointedCalibration, CalibratedUrdfCarriesTheOffsets) {
  // robot_calibration's <calibration rising>: replaced where the joint has one, added where not; read back
  // by urdf::Model as the offsets; the rest of the file as it was.
  const std::string calibrated = vocal::withJointOffsets(kTestUrdf, {{"head_tilt", -0.0042}, {"head_pan", 0.0017}}, "robot.urdf");
  for (const vocal::JointDescription& joint : vocal::urdfJointsFromString(calibrated, "calibrated URDF")) {
    const double expected = joint.name == "head_tilt" ? -0.0042 : joint.name == "head_pan" ? 0.0017 : 0.0;
    EXPECT_DOUBLE_EQ(joint.offset, expected) << joint.name;
  }
  EXPECT_EQ(calibrated.find("0.0123"), std::string::npos) << calibrated;  // the old one gone
  EXPECT_NE(calibrated.find("<joint name=\"mount\" type=\"fixed\">"), std::string::npos);
  EXPECT_NE(vocal_test::inputErrorOf([] { vocal::withJointOffsets(kTestUrdf, {{"gripper", 0.1}}, "robot.urdf"); })
                .find("robot.urdf: the URDF has no joint 'gripper' to write its offset to"),
            std::string::npos);
}

// A solved free origin in the robot's URDF: the joint's <origin> replaced, read back by urdf::Model as
// written; the other joints' as they were.
TEST(JointedCalibration, CalibratedUrdfCarriesTheFreeOrigins) {
  Eigen::Isometry3d origin = vocal::poseFromTranslationQuaternion({0.011, -0.002, 1.213}, Eigen::Quaterniond(Eigen::AngleAxisd(0.004, Eigen::Vector3d::UnitX())));
  const std::string calibrated = vocal::withJointOrigins(kTestUrdf, {{"head_pan", origin}}, "robot.urdf");
  const std::vector<vocal::JointDescription> before = vocal::urdfJointsFromString(kTestUrdf, "URDF");
  const std::vector<vocal::JointDescription> after = vocal::urdfJointsFromString(calibrated, "calibrated URDF");
  ASSERT_EQ(before.size(), after.size());
  for (std::size_t j = 0; j < after.size(); ++j) {
    const Eigen::Isometry3d& expected = after[j].name == "head_pan" ? origin : before[j].origin;
    EXPECT_TRUE(after[j].origin.isApprox(expected, 1e-8)) << after[j].name;
  }
  EXPECT_NE(vocal_test::inputErrorOf([&] { vocal::withJointOrigins(kTestUrdf, {{"gripper", origin}}, "robot.urdf"); })
                .find("robot.urdf: the URDF has no joint 'gripper' to write its origin to"),
            std::string::npos);
}

TEST(JointedCalibration, RigYamlNamesTheJointsOrTheUrdf) {
  const std::string dir = vocal_test::makeTempFolder("jointed_rig");
  const std::string sensors =
      "sensors:\n"
      "  - {name: lidar, type: lidar3d, frame_id: velodyne, cloud_topic: /points, pose: [0, 0, 1, 0, 0, 0, 1]}\n"
      "  - {name: head, type: rgbd, frame_id: head_optical, parent: tilt, depth_topic: /d, camera_info_topic: /i}\n";
  const std::string head = "reference_frame: base_link\ntarget: {type: checkerboard, rows: 6, cols: 8, square_size: 0.06, width: 0.9, height: 0.7}\n";
  const std::string joints =
      "joints:\n"
      "  - {name: pan, type: revolute, parent: base_link, child: pan_link, origin: [0, 0, 1.2, 0, 0, 0, 1], axis: [0, 0, 1]}\n"
      "  - {name: tilt, type: revolute, parent: pan_link, child: tilt, axis: [0, 1, 0], offset: 0.01}\n";
  vocal_test::writeText(dir + "/rig.yaml", head + joints + sensors);
  const vocal::RigDescription rig = vocal::readRigDescription(dir + "/rig.yaml");
  EXPECT_FALSE(rig.handEye());
  EXPECT_EQ(rig.reference_sensor, 0);
  const vocal::JointedMounts mounts = rig.jointedMounts();
  ASSERT_EQ(mounts.chains.size(), 2u);
  EXPECT_TRUE(mounts.chains[0].empty());
  EXPECT_EQ(mounts.chains[1], (std::vector<int>{0, 1}));
  EXPECT_DOUBLE_EQ(mounts.joints[1].offset, 0.01);
  // Written and read back alike.
  vocal::writeRigDescription(dir + "/again.yaml", rig);
  const vocal::RigDescription again = vocal::readRigDescription(dir + "/again.yaml");
  ASSERT_EQ(again.joints.size(), 2u);
  EXPECT_EQ(again.sensors[1].parent, "tilt");
  EXPECT_TRUE(again.joints[0].origin.isApprox(rig.joints[0].origin));

  // The same from a URDF beside the YAML.
  vocal_test::writeText(dir + "/robot.urdf", kTestUrdf);
  vocal_test::writeText(dir + "/urdf_rig.yaml", head + "urdf: robot.urdf\n" + sensors.substr(0, sensors.find("  - {name: head")) +
                                                    "  - {name: head, type: camera, frame_id: c, parent: camera_mount, image_topic: /c, "
                                                    "camera_info_topic: /ci, pose: [0, 0, 0, 0, 0, 0, 1], pose_known: true}\n");
  const vocal::RigDescription from_urdf = vocal::readRigDescription(dir + "/urdf_rig.yaml");
  const vocal::JointedMounts urdf_mounts = from_urdf.jointedMounts();
  ASSERT_EQ(urdf_mounts.chains[1].size(), 4u);
  EXPECT_TRUE(urdf_mounts.knownMount(1).has_value());

  // What a user gets wrong, named.
  const auto errorOf = [&](const std::string& text) {
    vocal_test::writeText(dir + "/bad.yaml", text);
    return vocal_test::inputErrorOf([&] { vocal::readRigDescription(dir + "/bad.yaml"); });
  };
  EXPECT_NE(errorOf(head + joints + sensors.substr(0, sensors.find("  - {name: head")) +
                    "  - {name: head, type: rgbd, frame_id: h, parent: wrist, depth_topic: /d, camera_info_topic: /i, pose_known: true}\n")
                .find("'pose_known' holds the 'pose' of a sensor behind joints"),
            std::string::npos);
  EXPECT_NE(errorOf(head + "joints:\n  - {name: pan, type: revolute, parent: base_link, child: pan_link}\n" + sensors).find("'pan': missing 'axis'"),
            std::string::npos);
  EXPECT_NE(errorOf(head + "joints:\n  - {name: pan, type: ball, parent: base_link, child: pan_link, axis: [0, 0, 1]}\n" + sensors)
                .find("joint type 'ball' is unknown"),
            std::string::npos);
  EXPECT_NE(errorOf(head + "joints:\n  - {name: pan, type: revolute, parent: base_link, child: pan_link, axis: [0, 0, 0]}\n" + sensors)
                .find("'axis' is zero"),
            std::string::npos);
  EXPECT_NE(errorOf(head + "joints:\n  - {name: tilt, type: revolute, parent: elsewhere, child: tilt, axis: [0, 1, 0]}\n" + sensors)
                .find("no chain of joints leads from 'base_link' to 'tilt' (the frame 'elsewhere' is no joint's child)"),
            std::string::npos);
  EXPECT_NE(errorOf(head + "urdf: missing.urdf\n" + sensors).find("missing.urdf: cannot read the URDF"), std::string::npos);
  // Joints from the parameter server: the rig is finished when they are given (the nodelet reads them).
  vocal_test::writeText(dir + "/param_rig.yaml", head + "urdf_param: /robot_description\n" + sensors.substr(0, sensors.find("  - {name: head")) +
                                                      "  - {name: head, type: camera, frame_id: c, parent: camera_mount, image_topic: /c, "
                                                      "camera_info_topic: /ci}\n");
  vocal::RigDescription from_param = vocal::readRigDescription(dir + "/param_rig.yaml");
  EXPECT_TRUE(from_param.joints.empty());
  EXPECT_EQ(from_param.urdf_param, "/robot_description");
  vocal::setRigJoints(&from_param, vocal::urdfJointsFromString(kTestUrdf, "/robot_description"), "param_rig.yaml");
  EXPECT_EQ(from_param.jointedMounts().chains[1].size(), 4u);
  vocal::RigDescription wrong_robot = vocal::readRigDescription(dir + "/param_rig.yaml");
  EXPECT_NE(vocal_test::inputErrorOf([&] { vocal::setRigJoints(&wrong_robot, {}, "param_rig.yaml"); })
                .find("param_rig.yaml: sensors[1] 'head': its parent 'camera_mount' is no link of the rig's joints (the URDF in /robot_description)"),
            std::string::npos);
  EXPECT_NE(errorOf(head + joints + "urdf: robot.urdf\n" + sensors).find("give the joints in one of 'joints', 'urdf' (a file) or 'urdf_param' (a parameter), not several"), std::string::npos);
}

// `free_joint_origins` marks the joints whose origin the graph solves, an arm's or a head's (written and read
// back alike); a name that is no joint's, or no list, is refused with what to give.
TEST(JointedCalibration, FreeJointOriginsAreNamedInTheRig) {
  const std::string dir = vocal_test::makeTempFolder("free_origins");
  const std::string arm =
      "reference_frame: base_link\n"
      "target: {type: checkerboard, rows: 6, cols: 8, square_size: 0.06, width: 0.9, height: 0.7, parent: base_link}\n"
      "joints:\n"
      "  - {name: shoulder, type: revolute, parent: base_link, child: upper_arm, origin: [0, 0, 0.2, 0, 0, 0, 1], axis: [0, 1, 0]}\n"
      "  - {name: elbow, type: revolute, parent: upper_arm, child: tool, origin: [0, 0, 0.5, 0, 0, 0, 1], axis: [0, 1, 0]}\n"
      "sensors:\n"
      "  - {name: wrist, type: camera, frame_id: w, parent: tool, image_topic: /c, camera_info_topic: /ci}\n";
  vocal_test::writeText(dir + "/rig.yaml", "free_joint_origins: [elbow]\n" + arm);
  const vocal::RigDescription rig = vocal::readRigDescription(dir + "/rig.yaml");
  ASSERT_TRUE(rig.handEye());
  EXPECT_FALSE(rig.joints[0].free_origin);
  EXPECT_TRUE(rig.joints[1].free_origin);
  vocal::writeRigDescription(dir + "/again.yaml", rig);
  EXPECT_TRUE(vocal::readRigDescription(dir + "/again.yaml").joints[1].free_origin);
  const auto errorOf = [&](const std::string& text) {
    vocal_test::writeText(dir + "/bad.yaml", text);
    return vocal_test::inputErrorOf([&] { vocal::readRigDescription(dir + "/bad.yaml"); });
  };
  EXPECT_NE(errorOf("free_joint_origins: [wrist]\n" + arm).find("'free_joint_origins' names 'wrist', which is no joint of the rig (its joints: shoulder, elbow)"),
            std::string::npos);
  EXPECT_NE(errorOf("free_joint_origins: elbow\n" + arm).find("'free_joint_origins' must list joint names"), std::string::npos);
  // A head's joints too (the still-pose graph's).
  const std::string head =
      "reference_frame: base_link\ntarget: {type: checkerboard, rows: 6, cols: 8, square_size: 0.06, width: 0.9, height: 0.7}\n"
      "free_joint_origins: [pan]\n"
      "joints:\n  - {name: pan, type: revolute, parent: base_link, child: pan_link, axis: [0, 0, 1]}\n"
      "sensors:\n"
      "  - {name: lidar, type: lidar3d, frame_id: velodyne, cloud_topic: /points, pose: [0, 0, 1, 0, 0, 0, 1]}\n"
      "  - {name: head, type: rgbd, frame_id: h, parent: pan_link, depth_topic: /d, camera_info_topic: /i}\n";
  vocal_test::writeText(dir + "/head.yaml", head);
  EXPECT_TRUE(vocal::readRigDescription(dir + "/head.yaml").jointedMounts().joints[0].free_origin);
}

TEST(JointedCalibration, JointReadingsAttachWhereTheJointsWereStill) {
  vocal::JointedMounts mounts;
  mounts.joints.resize(2);
  mounts.joints[0].name = "pan", mounts.joints[1].name = "tilt";
  mounts.chains = {{}, {0, 1}};
  // 200 Hz: still at 0.2 / -0.1 until 1 s, then the pan turns.
  std::vector<std::vector<vocal::JointReading>> readings(2);
  for (int i = 0; i < 400; ++i) {
    const double t = i / 200.0;
    readings[0].push_back({t, t < 1.0 ? 0.2 : 0.2 + 0.5 * (t - 1.0)});
    readings[1].push_back({t, -0.1 + (i % 2 ? 0.0015 : 0.0)});  // one encoder count of flicker
  }
  std::vector<vocal::TargetObservation> views(4);
  views[0].sensor = 0;  // rigid: untouched
  views[1].sensor = 1, views[1].first_stamp = 0.2, views[1].last_stamp = 0.8, views[1].target_pose = 0;
  views[2].sensor = 1, views[2].first_stamp = 0.9, views[2].last_stamp = 1.5, views[2].target_pose = 1;  // the pan turned
  views[3].sensor = 1, views[3].first_stamp = 2.5, views[3].last_stamp = 2.6, views[3].target_pose = 2;  // after the last reading
  vocal::JointPositionCounts counts;
  const std::vector<vocal::TargetObservation> kept =
      vocal::attachJointPositions(views, mounts, readings,
                                  {{"lidar", vocal::SensorType::kLidar3d, "lidar"}, {"head", vocal::SensorType::kRgbd, "head"}}, {}, &counts);
  ASSERT_EQ(kept.size(), 2u);
  EXPECT_TRUE(kept[0].joint_positions.empty());
  ASSERT_EQ(kept[1].joint_positions.size(), 2u);
  EXPECT_DOUBLE_EQ(kept[1].joint_positions[0], 0.2);
  EXPECT_NEAR(kept[1].joint_positions[1], -0.1, 0.0016);
  EXPECT_EQ(counts.kept, 1);
  EXPECT_EQ(counts.moving, 1);
  EXPECT_EQ(counts.unread, 1);
  EXPECT_NE(counts.first.find("sensor 'head' at still pose 1: joint 'pan' moved"), std::string::npos) << counts.first;
}

// A recorded pan-tilt session (rendered depth, lidar and laser scans, /joint_states at 200 Hz with encoder
// counts and backlash) through calibrate_rig, as a user runs it.
TEST(JointedCalibration, PanTiltSessionThroughCalibrateRig) {
  const std::string folder = vocal_test::makeTempFolder("cli_pan_tilt");
  vocal_test::RunResult r = vocal_test::runTool("simulate_calibration_session " + folder + " --pan-tilt --pose-known --poses 14");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("the head's joints on /joint_states at 200 Hz; true zero offsets: head_pan_joint "), std::string::npos) << r.output;
  // The camera's mount known (CAD): both offsets solved, within 1 mrad of the truth.
  r = vocal_test::runTool("calibrate_rig " + folder + "/rig.yaml " + folder + "/session.bag --quiet --output-dir " + folder + "/known");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("views of the sensors behind them: 14 kept, 0 dropped while the joints moved, 0 without a reading"),
            std::string::npos) << r.output;
  const YAML::Node truth = YAML::LoadFile(folder + "/ground_truth.yaml");
  const YAML::Node known = YAML::LoadFile(folder + "/known/calibration.yaml");
  for (int j = 0; j < 2; ++j) {
    EXPECT_EQ(known["joints"][j]["name"].as<std::string>(), truth["joints"][j]["name"].as<std::string>());
    EXPECT_TRUE(known["joints"][j]["solved"].as<bool>());
    EXPECT_NEAR(known["joints"][j]["offset"].as<double>(), truth["joints"][j]["offset"].as<double>(), 0.001);
    EXPECT_DOUBLE_EQ(known["calibration"][truth["joints"][j]["name"].as<std::string>()].as<double>(), known["joints"][j]["offset"].as<double>());
  }
  EXPECT_EQ(known["sensors"][2]["parent"].as<std::string>(), "head_tilt_link");
  const std::vector<double> laser = known["sensors"][1]["translation"].as<std::vector<double>>();
  const std::vector<double> laser_truth = truth["sensors"][1]["pose"].as<std::vector<double>>();
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(laser[i], laser_truth[i], 0.002);
  std::ifstream launch(folder + "/known/calibration.launch");
  const std::string launch_text((std::istreambuf_iterator<char>(launch)), std::istreambuf_iterator<char>());
  EXPECT_NE(launch_text.find(" head_tilt_link head_camera_depth_optical_frame\"/>"), std::string::npos) << launch_text;

  // The mount unknown too: the tilt's offset is the mount's to take up, said so.
  std::string rig_text;
  {
    std::ifstream rig(folder + "/rig.yaml");
    rig_text.assign((std::istreambuf_iterator<char>(rig)), std::istreambuf_iterator<char>());
  }
  const std::size_t known_at = rig_text.find(", pose_known: true");
  ASSERT_NE(known_at, std::string::npos) << rig_text;
  const std::string free_text =
      rig_text.substr(0, known_at) + rig_text.substr(known_at + 18, rig_text.find(",\n     pose:", known_at) - known_at - 18) + "}\n";
  vocal_test::writeText(folder + "/free.yaml", free_text);
  r = vocal_test::runTool("calibrate_rig " + folder + "/free.yaml " + folder + "/session.bag --quiet");
  EXPECT_EQ(r.exit_code, 0) << r.output;  // the camera, judged by where it is at the still poses, is published
  EXPECT_NE(r.output.find("head_tilt_joint         +0.00 mrad +- 0.00"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("held: no joint after it moved over the session, so the mount of the sensor behind it takes up its offset"),
            std::string::npos) << r.output;
  EXPECT_NE(r.output.find("(in head_tilt_link)"), std::string::npos) << r.output;

  // Ignoring the joints (the camera as if fixed): far off, not trusted, and the message says what to do.
  std::string rigid_text = free_text;
  rigid_text.erase(rigid_text.find(", parent: head_tilt_link"), std::string(", parent: head_tilt_link").size());
  vocal_test::writeText(folder + "/rigid.yaml", rigid_text);
  r = vocal_test::runTool("calibrate_rig " + folder + "/rigid.yaml " + folder + "/session.bag --quiet");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("NOT TRUSTED: sensor 'head_camera': its board views lie"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("a sensor on joints: name them in the rig, 'joints:' or 'urdf:', and its 'parent' link"), std::string::npos)
      << r.output;

  // Joint states on another topic than the rig says: refused, naming it.
  vocal_test::writeText(folder + "/elsewhere.yaml", "joint_states_topic: /robot/joint_states\n" + rig_text);
  r = vocal_test::runTool("calibrate_rig " + folder + "/elsewhere.yaml " + folder + "/session.bag --quiet");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("the bag has no sensor_msgs/JointState on /robot/joint_states naming any of them (head_pan_joint, head_tilt_joint)"),
            std::string::npos) << r.output;
}

namespace {
// A 6-joint arm's hand-eye stations (simulated_joint_arm.h): every camera view from the truth, the tool
// from the readings (offsets unknown), with the arm's chain for the graph.
struct JointArmSession {
  vocal::SimulatedJointArm arm;
  std::vector<vocal::HandEyeStation> stations;
  vocal::HandEyeOptions options;
};

JointArmSession jointArmSession(vocal::HandEyeSetup setup, std::uint32_t seed, double reading_noise, bool head = false,
                                double elbow_length_error = 0.0) {
  JointArmSession session;
  vocal::SimulatedArmOptions arm_options;
  arm_options.setup = setup;
  arm_options.poses = 15;
  arm_options.seed = seed;
  vocal::SimulatedJointArmOptions joint_options;
  joint_options.seed = seed;
  joint_options.reading_noise = reading_noise;
  joint_options.head = head;
  joint_options.elbow_length_error = elbow_length_error;
  session.arm = vocal::simulateJointArm(arm_options, joint_options);
  std::mt19937 rng(seed);
  session.stations = vocal::simulateHandEyeStations(session.arm.arm, {7, 10, 0.03}, vocal::defaultKinectCamera(640, 480), 3, 0.2, &rng);
  for (std::size_t k = 0; k < session.stations.size(); ++k) session.stations[k].joint_positions = session.arm.allReadings(k);
  vocal::ArmJoints arm;
  arm.joints = session.arm.model_joints;  // offsets unknown, origins the model's
  arm.chain = session.arm.chain;
  if (head) arm.read = vocal::jointsOfChains(arm.chain, {session.arm.head_chain});
  session.options.arm_joints = arm;
  return session;
}
}  // namespace

// How a calibration (joint offsets per joint of the chain, the camera on the tool, the board in the base)
// puts the board in the camera's view at each still pose's true joint angles read by noise-free encoders
// (angle less the true offset), against the truth: rms (m, rad) over the poses. What the calibration
// leaves wrong, not the readings' noise at one pose, and free of what no session fixes (the first joint's
// offset turns the base under both the arm and the board; the last joint's turns the tool).
std::pair<double, double> wristCameraError(const JointArmSession& session, const std::vector<double>& offsets, const Eigen::Isometry3d& camera,
                                           const Eigen::Isometry3d& board) {
  std::vector<double> by_joint(session.arm.joints.size(), 0.0);
  for (std::size_t i = 0; i < session.arm.chain.size(); ++i) by_joint[session.arm.chain[i]] = offsets[i];
  const std::vector<double> zero(session.arm.joints.size(), 0.0);
  double translation = 0.0, rotation = 0.0;
  for (std::size_t k = 0; k < session.arm.readings.size(); ++k) {
    std::vector<double> readings = session.arm.angles[k];
    for (std::size_t i = 0; i < readings.size(); ++i) readings[i] -= session.arm.joints[session.arm.chain[i]].offset;
    const Eigen::Isometry3d found = (vocal::chainPose(session.arm.joints, session.arm.chain, readings, by_joint) * camera).inverse() * board;
    const Eigen::Isometry3d truth =
        (vocal::chainPose(session.arm.joints, session.arm.chain, session.arm.angles[k], zero) * session.arm.arm.camera).inverse() * session.arm.arm.board;
    const Eigen::Isometry3d error = truth.inverse() * found;
    translation += error.translation().squaredNorm();
    rotation += std::pow(vocal::rotationAngle(error), 2);
  }
  const double n = static_cast<double>(session.arm.readings.size());
  return {std::sqrt(translation / n), std::sqrt(rotation / n)};
}

// The board in the base frame a closed form's camera implies: the mean over the stations' first views.
Eigen::Isometry3d boardFromClosedForm(const JointArmSession& session, const Eigen::Isometry3d& camera) {
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Vector4d quaternion = Eigen::Vector4d::Zero();
  for (const vocal::HandEyeStation& station : session.stations) {
    const Eigen::Isometry3d board = station.base_from_tool * camera * station.views.front().pattern.sensor_from_pattern;
    translation += board.translation();
    Eigen::Quaterniond q(board.rotation());
    if (q.coeffs().dot(quaternion) < 0.0) q.coeffs() = -q.coeffs();
    quaternion += q.coeffs();
  }
  Eigen::Isometry3d board = Eigen::Isometry3d::Identity();
  board.linear() = Eigen::Quaterniond(quaternion.normalized()).toRotationMatrix();
  board.translation() = translation / static_cast<double>(session.stations.size());
  return board;
}

// The camera on a 6-joint arm's wrist over a fixed board, the tool from the arm's readings (offsets
// drawn from +-5 mrad, 16-bit encoders, a reading error per pose): the joints' offsets in the graph,
// against OpenCV's closed forms on the tool poses the uncalibrated readings give (what tf says), each
// judged by where it puts the board in the camera's view over the arm's poses (wristCameraError).
TEST(JointedCalibration, WristCameraWithTheArmsJointOffsetsBesideOpenCv) {
  for (const double noise : {0.0002, 0.001}) {
    for (const std::uint32_t seed : {1u, 2u}) {
      SCOPED_TRACE("seed " + std::to_string(seed) + ", reading noise " + std::to_string(noise));
      const JointArmSession session = jointArmSession(vocal::HandEyeSetup::kEyeInHand, seed, noise);
      const vocal::HandEyeResult result = vocal::calibrateArmRig({{vocal::SensorType::kCamera, true}}, false, session.stations, session.options);
      std::vector<double> offsets;
      for (const vocal::JointCalibration& joint : result.joints) offsets.push_back(joint.offset);
      const auto [translation, rotation] = wristCameraError(session, offsets, result.camera(), result.board);
      const std::vector<double> uncalibrated(session.arm.chain.size(), 0.0);
      double best_translation = 1e9, best_rotation = 1e9;
      for (const vocal::HandEyeClosedForm& c : result.closed_forms) {
        const auto [t, r] = wristCameraError(session, uncalibrated, c.camera, boardFromClosedForm(session, c.camera));
        best_translation = std::min(best_translation, t), best_rotation = std::min(best_rotation, r);
      }
      std::printf("wrist camera, seed %u, reading noise %.1f mrad: vocal %.2f mm / %.2f mrad, OpenCV's best %.2f mm / %.2f mrad\n", seed,
                  1000 * noise, 1000 * translation, 1000 * rotation, 1000 * best_translation, 1000 * best_rotation);
      EXPECT_LT(translation, 0.002);
      EXPECT_LT(rotation, 0.002);
      EXPECT_LE(translation, best_translation);
      // The first and last joints' offsets are the base's and the tool's to take up: held, said why.
      EXPECT_NE(result.joints.front().held.find("no joint before it moved"), std::string::npos) << result.joints.front().held;
      EXPECT_NE(result.joints.back().held.find("no joint after it moved"), std::string::npos) << result.joints.back().held;
      for (std::size_t i = 1; i + 1 < result.joints.size(); ++i) {
        EXPECT_TRUE(result.joints[i].held.empty());
        EXPECT_NEAR(result.joints[i].offset, session.arm.joints[i].offset, 3.0 * result.joints[i].standard_deviation);
      }
    }
  }
}

// The wrist camera as the fixed board sees it through the arm at 20 configurations the session never
// visited (each joint within the range its still poses covered), the calibrated kinematics (the model's
// joints, the solved offsets and free origins, at the encoders' noise-free readings) against the true:
// the worst (m, rad).
std::pair<double, double> unvisitedWristCameraError(const JointArmSession& session, const vocal::HandEyeResult& result) {
  std::vector<vocal::JointDescription> calibrated = session.options.arm_joints->joints;
  std::vector<double> offsets(calibrated.size(), 0.0);
  for (std::size_t i = 0; i < session.arm.chain.size(); ++i) {
    const int j = session.arm.chain[i];
    offsets[j] = result.joints[i].offset;
    if (result.joints[i].origin_free) calibrated[j].origin = result.joints[i].origin;
  }
  std::vector<double> low(session.arm.chain.size(), 1e9), high(session.arm.chain.size(), -1e9);
  for (const std::vector<double>& angles : session.arm.angles)
    for (std::size_t i = 0; i < angles.size(); ++i) low[i] = std::min(low[i], angles[i]), high[i] = std::max(high[i], angles[i]);
  std::mt19937 rng(11);
  const std::vector<double> zero(session.arm.joints.size(), 0.0);
  double translation = 0.0, rotation = 0.0;
  for (int configuration = 0; configuration < 20; ++configuration) {
    std::vector<double> angles, readings;
    for (std::size_t i = 0; i < low.size(); ++i) {
      angles.push_back(std::uniform_real_distribution<double>(low[i], high[i])(rng));
      readings.push_back(angles.back() - session.arm.joints[session.arm.chain[i]].offset);
    }
    const Eigen::Isometry3d truth =
        session.arm.arm.board.inverse() * vocal::chainPose(session.arm.joints, session.arm.chain, angles, zero) * session.arm.arm.camera;
    const Eigen::Isometry3d found = result.board.inverse() * vocal::chainPose(calibrated, session.arm.chain, readings, offsets) * result.camera();
    const Eigen::Isometry3d error = truth.inverse() * found;
    translation = std::max(translation, error.translation().norm());
    rotation = std::max(rotation, vocal::rotationAngle(error));
  }
  return {translation, rotation};
}

// An arm whose upper arm is 1 cm longer than its model (a link length off the maker's URDF): with the
// model's origins held, the joints' offsets and the camera bend to fit the still poses and miss elsewhere;
// with the elbow's origin free (free_joint_origins), the graph finds the length, says which parts of the
// origin the session fixed and which it held at the model's, and the wrist camera lands right at
// configurations the session never visited.
TEST(JointedCalibration, AFreeElbowOriginTakesUpAnUpperArmLongerThanItsModel) {
  for (const std::uint32_t seed : {1u, 2u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    JointArmSession session = jointArmSession(vocal::HandEyeSetup::kEyeInHand, seed, 0.0002, false, 0.01);
    const vocal::HandEyeResult held = vocal::calibrateArmRig({{vocal::SensorType::kCamera, true}}, false, session.stations, session.options);
    for (const vocal::JointCalibration& joint : held.joints) EXPECT_FALSE(joint.origin_free);
    const auto [held_translation, held_rotation] = unvisitedWristCameraError(session, held);
    constexpr int kElbow = 2;
    session.options.arm_joints->joints[kElbow].free_origin = true;
    const vocal::HandEyeResult free = vocal::calibrateArmRig({{vocal::SensorType::kCamera, true}}, false, session.stations, session.options);
    const auto [translation, rotation] = unvisitedWristCameraError(session, free);
    const vocal::JointCalibration& elbow = free.joints[kElbow];
    std::printf("upper arm 10 mm long, seed %u: model's origins held %.2f mm / %.2f mrad at unvisited configurations, elbow free %.2f mm / "
                "%.2f mrad, its shift along the link %+.2f +- %.2f mm; %s\n",
                seed, 1000 * held_translation, 1000 * held_rotation, 1000 * translation, 1000 * rotation, 1000 * elbow.origin_correction[5],
                1000 * elbow.origin_sigma[5], elbow.origin_observability.c_str());
    EXPECT_GT(held_translation, 0.005);
    EXPECT_LT(translation, 0.003);
    EXPECT_LT(rotation, 0.002);
    ASSERT_TRUE(elbow.origin_free);
    EXPECT_NEAR(elbow.origin_correction[5], 0.01, 0.002);
    EXPECT_NEAR(elbow.origin.translation().z(), 0.51, 0.002);
    EXPECT_GT(elbow.origin_sigma[5], 0.0);
    // A shift across the link (x) turns the shoulder and the elbow alike: held, said; the turn about the
    // elbow's own axis is its offset's, not named.
    EXPECT_EQ(elbow.origin_sigma[3], 0.0);
    EXPECT_NE(elbow.origin_observability.find("shift along z"), std::string::npos);
    EXPECT_NE(elbow.origin_observability.find("held at the model's (the session's motion does not fix it): shift along x"), std::string::npos)
        << elbow.origin_observability;
    EXPECT_EQ(elbow.origin_observability.find("turn about y"), std::string::npos);
    for (std::size_t i = 1; i + 1 < free.joints.size(); ++i) {
      EXPECT_NEAR(free.joints[i].offset, session.arm.joints[i].offset, 3.0 * free.joints[i].standard_deviation + 1e-3);
    }
  }
}

// A camera fixed on a post whose pose the rig gives (the reference), the board in a 6-joint arm's gripper:
// the camera stays exactly where the rig put it, and the base frame it ties down makes the first joint's
// offset solvable (held when no pose is given: the camera's own pose took it up); the board on the tool
// lands right at arm configurations the session never visited.
TEST(JointedCalibration, AGivenFixedCameraHoldsTheBaseFrameAndFixesTheFirstJoint) {
  for (const std::uint32_t seed : {1u, 2u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const JointArmSession session = jointArmSession(vocal::HandEyeSetup::kEyeToHand, seed, 0.0002);
    const Eigen::Isometry3d given = session.arm.arm.camera;  // base <- camera, true
    const vocal::HandEyeResult result =
        vocal::calibrateArmRig({{vocal::SensorType::kCamera, false, given, "post_camera"}}, true, session.stations, session.options);
    ASSERT_EQ(result.held.size(), 1u);
    EXPECT_TRUE(result.held[0]);
    EXPECT_LT((result.camera().translation() - given.translation()).norm(), 1e-12);
    EXPECT_LT(vocal::rotationAngle(given.inverse() * result.camera()), 1e-12);
    EXPECT_EQ(result.cameraSigma().norm(), 0.0);
    EXPECT_EQ(result.sensor_spreads[0].norm(), 0.0);
    const vocal::JointCalibration& first = result.joints.front();
    EXPECT_TRUE(first.held.empty()) << first.held;
    EXPECT_EQ(first.fixed_by, "the pose the rig gives 'post_camera' and joints that moved after it");
    EXPECT_NEAR(first.offset, session.arm.joints[session.arm.chain.front()].offset, 0.0005);
    EXPECT_NE(result.joints.back().held.find("no joint after it moved"), std::string::npos) << result.joints.back().held;
    // The board in the base frame at configurations between the still poses' (each joint drawn within the
    // range the session covered), from encoders reading the true angle less the true offset.
    std::mt19937 rng(seed);
    std::vector<double> solved(session.arm.joints.size(), 0.0), zero(session.arm.joints.size(), 0.0);
    for (std::size_t i = 0; i < session.arm.chain.size(); ++i) solved[session.arm.chain[i]] = result.joints[i].offset;
    double worst_translation = 0.0, worst_rotation = 0.0;
    for (int n = 0; n < 20; ++n) {
      std::vector<double> angles(session.arm.chain.size()), readings(session.arm.chain.size());
      for (std::size_t i = 0; i < angles.size(); ++i) {
        double low = 1e9, high = -1e9;
        for (const std::vector<double>& pose : session.arm.angles) low = std::min(low, pose[i]), high = std::max(high, pose[i]);
        angles[i] = std::uniform_real_distribution<double>(low, high)(rng);
        readings[i] = angles[i] - session.arm.joints[session.arm.chain[i]].offset;
      }
      const Eigen::Isometry3d truth = vocal::chainPose(session.arm.joints, session.arm.chain, angles, zero) * session.arm.arm.board;
      const Eigen::Isometry3d found = vocal::chainPose(session.arm.joints, session.arm.chain, readings, solved) * result.board;
      worst_translation = std::max(worst_translation, (found.translation() - truth.translation()).norm());
      worst_rotation = std::max(worst_rotation, vocal::rotationAngle(truth.inverse() * found));
    }
    std::printf("given fixed camera, seed %u: first joint %.2f mrad (truth %.2f), the board at 20 unvisited configurations within "
                "%.2f mm / %.2f mrad\n", seed, 1000 * first.offset, 1000 * session.arm.joints[session.arm.chain.front()].offset,
                1000 * worst_translation, 1000 * worst_rotation);
    EXPECT_LT(worst_translation, 0.002);
    EXPECT_LT(worst_rotation, 0.002);

    // No pose given: the camera's own pose takes the first joint's offset up, held and said what would solve it.
    const vocal::HandEyeResult free = vocal::calibrateArmRig({{vocal::SensorType::kCamera, false}}, true, session.stations, session.options);
    EXPECT_FALSE(free.held[0]);
    EXPECT_EQ(free.joints.front().offset, 0.0);
    EXPECT_NE(free.joints.front().held.find("give a fixed sensor's pose in the rig (the reference) to solve it"), std::string::npos)
        << free.joints.front().held;
  }
}

namespace {
// A camera's views of the board at each still pose where the whole pattern is in view: three images each,
// 0.2 px of noise, as sensor `sensor`; how many poses saw it.
int addCameraViews(JointArmSession* session, int sensor, const std::function<Eigen::Isometry3d(std::size_t)>& base_from_camera,
                   std::uint32_t seed) {
  const vocal::PinholeCamera lens = vocal::defaultKinectCamera(640, 480);
  const vocal::TargetPattern pattern{7, 10, 0.03};
  const std::vector<Eigen::Vector3d> corners = pattern.corners();
  const bool in_hand = session->arm.arm.setup == vocal::HandEyeSetup::kEyeInHand;
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.2);
  int seen = 0;
  for (std::size_t k = 0; k < session->stations.size(); ++k) {
    const Eigen::Isometry3d board = in_hand ? session->arm.arm.board : session->arm.arm.true_tool[k] * session->arm.arm.board;
    const Eigen::Isometry3d camera_from_board = base_from_camera(k).inverse() * board;
    const bool in_view = std::all_of(corners.begin(), corners.end(), [&](const Eigen::Vector3d& c) {
      const Eigen::Vector3d p = camera_from_board * c;
      const Eigen::Vector2d uv = lens.project(p);
      return p.z() > 0.1 && lens.contains(uv.x(), uv.y());
    });
    if (!in_view) continue;
    ++seen;
    for (int v = 0; v < 3; ++v) {
      std::vector<Eigen::Vector2d> pixels;
      for (const Eigen::Vector3d& c : corners) pixels.push_back(lens.project(camera_from_board * c) + Eigen::Vector2d(noise(rng), noise(rng)));
      session->stations[k].views.push_back({sensor, vocal::observePattern(pixels, pattern, lens, "camera").plane, {}, {}});
    }
  }
  return seen;
}

// The worst distance and angle (m, rad) over 20 configurations of the joints drawn within the ranges the
// still poses covered (none of them visited) between the truth and a calibration (its offsets per joint
// read) of where `chain`'s link puts something at `mount` in it (true: `true_mount`); chain empty: fixed.
std::pair<double, double> errorAtUnvisitedConfigurations(const JointArmSession& session, const std::vector<int>& read,
                                                         const vocal::HandEyeResult& result, const std::vector<int>& chain,
                                                         const Eigen::Isometry3d& mount, const Eigen::Isometry3d& true_mount) {
  std::vector<double> solved(session.arm.joints.size(), 0.0), zero(session.arm.joints.size(), 0.0);
  for (std::size_t i = 0; i < read.size(); ++i) solved[read[i]] = result.joints[i].offset;
  std::mt19937 rng(7);
  double worst_translation = 0.0, worst_rotation = 0.0;
  for (int n = 0; n < 20; ++n) {
    std::vector<double> angles, readings;
    for (const int j : chain) {
      const std::size_t i = static_cast<std::size_t>(std::find(read.begin(), read.end(), j) - read.begin());
      double low = 1e9, high = -1e9;
      for (std::size_t k = 0; k < session.stations.size(); ++k) {
        const std::vector<double> all = session.arm.allReadings(k);
        low = std::min(low, all[i]), high = std::max(high, all[i]);
      }
      const double reading = std::uniform_real_distribution<double>(low, high)(rng);
      readings.push_back(reading);
      angles.push_back(reading + session.arm.joints[j].offset);
    }
    const Eigen::Isometry3d truth = vocal::chainPose(session.arm.joints, chain, angles, zero) * true_mount;
    const Eigen::Isometry3d found = vocal::chainPose(session.arm.joints, chain, readings, solved) * mount;
    worst_translation = std::max(worst_translation, (found.translation() - truth.translation()).norm());
    worst_rotation = std::max(worst_rotation, vocal::rotationAngle(truth.inverse() * found));
  }
  return {worst_translation, worst_rotation};
}
}  // namespace

namespace {
std::vector<vocal::TargetObservation> stillPoseObservations(const std::vector<vocal::HandEyeStation>& stations) {
  return vocal::stillPoseObservations(stations, vocal::TargetPattern{7, 10, 0.03});
}
}  // namespace

// The board in an arm's gripper as a frame of the still-pose graph (issue 44's one graph): each still
// pose's board tied to the arm's chain at its readings times the board's mount on the tool, as a sensor
// behind joints is tied to its chain. A post camera whose pose the rig gives (the reference) and a second
// fixed camera before it: the first joint's offset solved within 0.5 mrad of the truth, the second camera
// within 2 mm / 2 mrad of the truth in the base frame, and the board at configurations the session never
// visited within 2 mm / 2 mrad - as the arm's own graph gives them on the same stations; with each camera
// view held by its plane and outline, and by its whole pose (what calibrate_rig --one-graph holds).
TEST(JointedCalibration, TheArmsBoardIsAFrameOfTheStillPoseGraph) {
  for (const std::uint32_t seed : {1u, 2u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    JointArmSession session = jointArmSession(vocal::HandEyeSetup::kEyeToHand, seed, 0.0002);
    const Eigen::Isometry3d post = session.arm.arm.camera;  // base <- camera, true
    const Eigen::Isometry3d side = post * Eigen::Translation3d(0.25, 0.05, 0.0) * Eigen::AngleAxisd(-0.25, Eigen::Vector3d::UnitY());
    const int seen = addCameraViews(&session, 1, [&](std::size_t) { return side; }, seed + 100);
    ASSERT_GE(seen, 8);

    const std::vector<vocal::TargetObservation> observations = stillPoseObservations(session.stations);
    vocal::CalibrationOptions options;
    options.reference_pose = post;
    options.board_edges.enabled = true;
    options.board_edges.width = 0.36, options.board_edges.height = 0.27;
    options.mounts.joints = session.arm.model_joints;
    options.mounts.board_chain = session.arm.chain;
    for (std::size_t k = 0; k < session.stations.size(); ++k) options.mounts.board_readings[static_cast<int>(k)] = session.arm.readings[k];
    const std::vector<vocal::SensorSpec> sensors = {{"post_camera", vocal::SensorType::kCamera, "post"},
                                                    {"side_camera", vocal::SensorType::kCamera, "side"}};
    const std::vector<int>& chain = session.arm.chain;
    const vocal::HandEyeResult arm = vocal::calibrateArmRig(
        {{vocal::SensorType::kCamera, false, post, "post_camera"}, {vocal::SensorType::kCamera, false, std::nullopt, "side_camera"}}, true,
        session.stations, session.options);
    const auto [arm_board_translation, arm_board_rotation] =
        errorAtUnvisitedConfigurations(session, chain, arm, chain, arm.board, session.arm.arm.board);
    for (const bool camera_pose : {false, true}) {
      SCOPED_TRACE(camera_pose ? "cameras' whole poses" : "cameras' planes and outlines");
      options.board_edges.camera_pose = camera_pose;
      const vocal::CalibrationResult result = vocal::calibrateRig(sensors, observations, options);
      ASSERT_TRUE(result.trusted) << result.failure;
      ASSERT_TRUE(result.board_mount.has_value());
      EXPECT_LT((result.sensors[0].reference_from_sensor.translation() - post.translation()).norm(), 1e-12);
      EXPECT_LT(vocal::rotationAngle(post.inverse() * result.sensors[0].reference_from_sensor), 1e-12);

      const vocal::JointCalibration& first = result.joints[chain.front()];
      EXPECT_TRUE(first.held.empty()) << first.held;
      EXPECT_EQ(first.fixed_by, "the reference's given pose (the rig frame) and joints that moved after it");
      const double first_truth = session.arm.joints[chain.front()].offset;
      EXPECT_NEAR(first.offset, first_truth, 0.0005);
      EXPECT_NE(result.joints[chain.back()].held.find("so the board's mount takes up its offset"), std::string::npos)
          << result.joints[chain.back()].held;
      const double side_translation = (result.sensors[1].reference_from_sensor.translation() - side.translation()).norm();
      const double side_rotation = vocal::rotationAngle(side.inverse() * result.sensors[1].reference_from_sensor);
      EXPECT_LT(side_translation, 0.002);
      EXPECT_LT(side_rotation, 0.002);

      // The board at configurations the session never visited, from both graphs' offsets and mounts.
      vocal::HandEyeResult as_arm;
      as_arm.board = *result.board_mount;
      for (const int j : chain) as_arm.joints.push_back(result.joints[j]);
      const auto [board_translation, board_rotation] =
          errorAtUnvisitedConfigurations(session, chain, as_arm, chain, *result.board_mount, session.arm.arm.board);
      EXPECT_LT(board_translation, 0.002);
      EXPECT_LT(board_rotation, 0.002);

      std::printf("the arm's board in the still-pose graph (%s), seed %u (%d of %zu poses seen by the side camera): first joint %.2f mrad (truth "
                  "%.2f; the arm's graph %.2f), side camera %.2f mm / %.2f mrad (the arm's graph %.2f / %.2f), the board at unvisited "
                  "configurations %.2f / %.2f (the arm's graph %.2f / %.2f)\n",
                  camera_pose ? "cameras' whole poses" : "cameras' planes and outlines", seed, seen, session.stations.size(), 1000 * first.offset,
                  1000 * first_truth, 1000 * arm.joints.front().offset,
                  1000 * side_translation, 1000 * side_rotation, 1000 * (arm.sensors[1].translation() - side.translation()).norm(),
                  1000 * vocal::rotationAngle(side.inverse() * arm.sensors[1]), 1000 * board_translation, 1000 * board_rotation,
                  1000 * arm_board_translation, 1000 * arm_board_rotation);
    }
  }

  // Without the board's outline the graph has its plane alone per pose, not a pose to tie: refused.
  JointArmSession session = jointArmSession(vocal::HandEyeSetup::kEyeToHand, 1, 0.0002);
  vocal::CalibrationOptions options;
  options.reference_pose = session.arm.arm.camera;
  options.mounts.joints = session.arm.model_joints;
  options.mounts.board_chain = session.arm.chain;
  try {
    vocal::calibrateRig({{"post_camera", vocal::SensorType::kCamera, "post"}}, stillPoseObservations(session.stations), options);
    ADD_FAILURE() << "a board behind joints was calibrated by its planes alone";
  } catch (const vocal::InputError& e) {
    EXPECT_STREQ(e.what(), "calibration: the board is on a frame that moves (an arm's tool), which needs its full pose at each still pose: "
                           "give the board's size and keep its edges (board_edges)");
  }
  // A still pose without the arm's readings: named.
  options.board_edges.enabled = true;
  options.board_edges.width = 0.36, options.board_edges.height = 0.27;
  for (std::size_t k = 1; k < session.stations.size(); ++k) options.mounts.board_readings[static_cast<int>(k)] = session.arm.readings[k];
  try {
    vocal::calibrateRig({{"post_camera", vocal::SensorType::kCamera, "post"}}, stillPoseObservations(session.stations), options);
    ADD_FAILURE() << "a still pose without the arm's readings was calibrated";
  } catch (const vocal::InputError& e) {
    EXPECT_STREQ(e.what(), "calibration: the board is behind 6 joints, but still pose 0 has 0 readings of them, or one not finite");
  }
}

// The camera on the wrist over a board lying still on the table (eye-in-hand) as the still-pose graph
// holds it (calibrate_rig --one-graph): no sensor's pose given, the arm's base the rig frame, the board one
// pose in it. From the arm's joints: the first joint held (the board takes up its offset) and said why,
// the middle joints within three sigmas of the truth, the camera and the board over the arm's poses within
// 1 mm / 1 mrad of the truth and no worse than the arm's own graph by 0.1 mm / 0.1 mrad; from the tool
// poses tf reports: the camera's mount within 1 mm / 1 mrad of the truth and 0.1 / 0.1 of the arm's graph.
TEST(JointedCalibration, AWristCameraOverAStillBoardThroughTheStillPoseGraph) {
  const std::vector<vocal::SensorSpec> sensors = {{"wrist_camera", vocal::SensorType::kCamera, "wrist"}};
  for (const std::uint32_t seed : {1u, 2u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const JointArmSession session = jointArmSession(vocal::HandEyeSetup::kEyeInHand, seed, 0.0002);
    const std::vector<int>& chain = session.arm.chain;
    std::vector<vocal::TargetObservation> observations = stillPoseObservations(session.stations);
    for (vocal::TargetObservation& o : observations) o.joint_positions = session.arm.readings[o.target_pose];
    vocal::CalibrationOptions options;
    options.reference_sensor = -1;
    options.board_edges.enabled = true;
    options.board_edges.width = 0.36, options.board_edges.height = 0.27;
    options.board_edges.camera_pose = true;
    options.mounts.board_fixed = true;
    options.mounts.joints = session.arm.model_joints;
    options.mounts.chains = {chain};

    const vocal::HandEyeResult arm = vocal::calibrateArmRig({{vocal::SensorType::kCamera, true}}, false, session.stations, session.options);
    std::vector<double> arm_offsets;
    for (const vocal::JointCalibration& joint : arm.joints) arm_offsets.push_back(joint.offset);
    const auto [arm_translation, arm_rotation] = wristCameraError(session, arm_offsets, arm.camera(), arm.board);

    const vocal::CalibrationResult result = vocal::calibrateRigWithTrust(sensors, observations, options);
    ASSERT_TRUE(result.trusted) << result.failure;
    ASSERT_TRUE(result.board_mount.has_value());
    EXPECT_TRUE(result.sensors[0].distrust.empty()) << result.sensors[0].distrust;
    EXPECT_EQ(result.joints[chain.front()].held,
              "the first joint from the base, whose frame is the rig's: the board lying still in it takes up its offset");
    EXPECT_NE(result.joints[chain.back()].held.find("so the mount of the sensor behind it takes up its offset"), std::string::npos)
        << result.joints[chain.back()].held;
    std::vector<double> offsets;
    for (std::size_t i = 0; i < chain.size(); ++i) {
      const vocal::JointCalibration& joint = result.joints[chain[i]];
      offsets.push_back(joint.offset);
      if (i == 0 || i + 1 == chain.size()) continue;
      EXPECT_TRUE(joint.held.empty()) << joint.held;
      EXPECT_EQ(joint.fixed_by, "the board lying still in the base frame and joints that moved after it");
      EXPECT_NEAR(joint.offset, session.arm.joints[chain[i]].offset, 3.0 * joint.standard_deviation + 1e-5);
    }
    const auto [translation, rotation] = wristCameraError(session, offsets, result.sensors[0].reference_from_sensor, *result.board_mount);
    EXPECT_LT(translation, 0.001);
    EXPECT_LT(rotation, 0.001);
    EXPECT_LT(translation, arm_translation + 0.0001);
    EXPECT_LT(rotation, arm_rotation + 0.0001);

    // The same arm as a calibrated arm's tf reports its tool (where it truly was): the camera on that tool.
    std::vector<vocal::HandEyeStation> tf_stations = session.stations;
    vocal::CalibrationOptions from_tf = options;
    from_tf.mounts = vocal::JointedMounts{};
    from_tf.mounts.board_fixed = true;
    from_tf.mounts.on_reported_tool = {true};
    for (std::size_t k = 0; k < tf_stations.size(); ++k) {
      tf_stations[k].base_from_tool = session.arm.arm.true_tool[k];
      from_tf.mounts.tool_poses[static_cast<int>(k)] = tf_stations[k].base_from_tool;
    }
    const vocal::CalibrationResult tf = vocal::calibrateRigWithTrust(sensors, stillPoseObservations(tf_stations), from_tf);
    ASSERT_TRUE(tf.trusted) << tf.failure;
    vocal::HandEyeOptions arm_tf_options = session.options;
    arm_tf_options.arm_joints.reset();
    const vocal::HandEyeResult arm_tf = vocal::calibrateArmRig({{vocal::SensorType::kCamera, true}}, false, tf_stations, arm_tf_options);
    const Eigen::Isometry3d& mount = tf.sensors[0].reference_from_sensor;
    const double tf_translation = (mount.translation() - session.arm.arm.camera.translation()).norm();
    const double tf_rotation = vocal::rotationAngle(session.arm.arm.camera.inverse() * mount);
    EXPECT_LT(tf_translation, 0.001);
    EXPECT_LT(tf_rotation, 0.001);
    EXPECT_LT((mount.translation() - arm_tf.camera().translation()).norm(), 0.0001);
    EXPECT_LT(vocal::rotationAngle(arm_tf.camera().inverse() * mount), 0.0001);
    std::printf("wrist camera over a still board in the still-pose graph, seed %u: from the joints %.2f mm / %.2f mrad over the arm's poses "
                "(the arm's graph %.2f / %.2f); from tf %.2f / %.2f off the truth (the arm's graph %.2f / %.2f)\n", seed, 1000 * translation,
                1000 * rotation, 1000 * arm_translation, 1000 * arm_rotation, 1000 * tf_translation, 1000 * tf_rotation,
                1000 * (arm_tf.camera().translation() - session.arm.arm.camera.translation()).norm(),
                1000 * vocal::rotationAngle(session.arm.arm.camera.inverse() * arm_tf.camera()));
  }

  // A sensor given as the reference while the board lies still in the base: refused, naming it.
  const JointArmSession session = jointArmSession(vocal::HandEyeSetup::kEyeInHand, 1, 0.0002);
  vocal::CalibrationOptions options;
  options.board_edges.enabled = true;
  options.board_edges.width = 0.36, options.board_edges.height = 0.27;
  options.mounts.board_fixed = true;
  options.mounts.on_reported_tool = {true};
  for (std::size_t k = 0; k < session.stations.size(); ++k) options.mounts.tool_poses[static_cast<int>(k)] = session.stations[k].base_from_tool;
  try {
    vocal::calibrateRig(sensors, stillPoseObservations(session.stations), options);
    ADD_FAILURE() << "a reference sensor was taken with the board lying still in the base";
  } catch (const vocal::InputError& e) {
    EXPECT_STREQ(e.what(), "calibration: the board lies still in the arm's base frame, which is then the rig frame: no sensor is the reference "
                           "(reference_sensor -1), but sensor index 0 was given");
  }
  // A still pose without the tool's pose: named.
  options.reference_sensor = -1;
  options.mounts.tool_poses.erase(2);
  try {
    vocal::calibrateRig(sensors, stillPoseObservations(session.stations), options);
    ADD_FAILURE() << "a still pose without the tool's pose was calibrated";
  } catch (const vocal::InputError& e) {
    EXPECT_STREQ(e.what(), "calibration: sensor 'wrist_camera' is on the arm's tool, but still pose 2 has no tool pose the arm reported");
  }
}

// A second camera on the arm's forearm (behind its first three joints) beside the main camera - on the
// tool over the fixed board, or fixed before the board in the gripper - the tool and the forearm from the
// joints: the forearm camera's mount in its link within 2 mm / 2 mrad of the truth and the main camera's as
// without it; the same rig from tf (no joints) refused.
TEST(JointedCalibration, ACameraOnTheForearmBesideTheMainCamera) {
  constexpr int kForearm = vocal::SimulatedJointArm::kForearmJoints;
  for (const vocal::HandEyeSetup setup : {vocal::HandEyeSetup::kEyeInHand, vocal::HandEyeSetup::kEyeToHand}) {
    for (const std::uint32_t seed : {1u, 2u}) {
      SCOPED_TRACE(vocal::handEyeSetupName(setup) + ", seed " + std::to_string(seed));
      const bool in_hand = setup == vocal::HandEyeSetup::kEyeInHand;
      JointArmSession session = jointArmSession(setup, seed, 0.0002);
      const Eigen::Isometry3d mount = session.arm.arm.forearm_camera;  // forearm_link <- camera, true
      const std::vector<vocal::HandEyeStation> main_stations = session.stations;
      const int seen = addCameraViews(&session, 1, [&](std::size_t k) { return session.arm.forearmAt(session.arm.angles[k]) * mount; }, seed + 100);
      ASSERT_GE(seen, 4);
      vocal::HandEyeSensor forearm(vocal::SensorType::kCamera, true, std::nullopt, "forearm_camera");
      forearm.link_chain.assign(session.arm.chain.begin(), session.arm.chain.begin() + kForearm);
      const vocal::HandEyeSensor main_camera(vocal::SensorType::kCamera, in_hand, std::nullopt, "main_camera");
      const vocal::HandEyeResult result = vocal::calibrateArmRig({main_camera, forearm}, !in_hand, session.stations, session.options);
      const vocal::HandEyeResult main_alone = vocal::calibrateArmRig({main_camera}, !in_hand, main_stations, session.options);
      const double translation = (result.sensors[1].translation() - mount.translation()).norm();
      const double rotation = vocal::rotationAngle(mount.inverse() * result.sensors[1]);
      const double main_moved = (result.camera().translation() - main_alone.camera().translation()).norm();
      std::printf("forearm camera, %s, seed %u, %d of %zu still poses: %.2f mm / %.2f mrad (sigma %.2f mm); main camera %.3f mm from its "
                  "pose without it\n", vocal::handEyeSetupName(setup).c_str(), seed, seen, session.stations.size(), 1000 * translation,
                  1000 * rotation, 1000 * result.sensor_sigmas[1].head<3>().norm(), 1000 * main_moved);
      EXPECT_LT(translation, 0.002);
      EXPECT_LT(rotation, 0.002);
      if (in_hand) {
        EXPECT_LT(main_moved, 0.001);
      } else {
        // The post camera in the base frame the held first joint defines (its offset turns that frame
        // about the joint's axis, through the base's origin). The forearm camera's views change what the
        // joints after it are solved to, and the post camera with them (1.5-1.7 mm on these seeds, closer
        // to the truth on one, farther on the other): judged against the truth, both within 2 mm / 2 mrad.
        const vocal::JointDescription& first = session.arm.joints[session.arm.chain.front()];
        const Eigen::Isometry3d expected = Eigen::Isometry3d(Eigen::AngleAxisd(-first.offset, first.axis)) * session.arm.arm.camera;
        const auto offTruth = [&](const vocal::HandEyeResult& r) {
          return std::make_pair((r.camera().translation() - expected.translation()).norm(), vocal::rotationAngle(expected.inverse() * r.camera()));
        };
        const auto [with_t, with_r] = offTruth(result);
        const auto [alone_t, alone_r] = offTruth(main_alone);
        std::printf("  the post camera off the truth: %.2f mm / %.2f mrad with the forearm camera, %.2f / %.2f without\n", 1000 * with_t,
                    1000 * with_r, 1000 * alone_t, 1000 * alone_r);
        EXPECT_LT(with_t, 0.002);
        EXPECT_LT(with_r, 0.002);
      }

      vocal::HandEyeOptions from_tf = session.options;
      from_tf.arm_joints.reset();
      try {
        vocal::calibrateArmRig({main_camera, forearm}, !in_hand, session.stations, from_tf);
        ADD_FAILURE() << "a forearm camera without the arm's joints was calibrated";
      } catch (const vocal::InputError& e) {
        EXPECT_STREQ(e.what(), "hand-eye calibration: 'forearm_camera' sits on a link of the arm before the tool, which needs the arm's joints "
                               "(their readings and chain)");
      }
    }
  }
}

// A robot with a pan-tilt head beside its arm (two branches from the base, both read on /joint_states):
// the head's camera watches the board the arm holds beside a camera on a post, or alone (the main camera
// then, its closed form over the tool's motion in the head's link), or watches the fixed board beside a
// camera on the wrist. Each camera, in the base frame at joint configurations the session never visited,
// within 2 mm / 2 mrad of the truth (2.5 for the head camera alone); the head's and the arm's first joints fix each other's offset (a turn
// of either moves one branch against the other) within their standard deviations, the tilt's is taken up
// by the head camera's mount.
TEST(JointedCalibration, AHeadAndAnArmInOneSession) {
  for (const vocal::HandEyeSetup setup : {vocal::HandEyeSetup::kEyeInHand, vocal::HandEyeSetup::kEyeToHand}) {
    for (const std::uint32_t seed : {1u, 2u}) {
      for (const bool head_alone : {false, true}) {
        const bool in_hand = setup == vocal::HandEyeSetup::kEyeInHand;
        if (in_hand && head_alone) continue;  // a head alone over a fixed board is a head's rig (graph_calibration.h)
        SCOPED_TRACE(vocal::handEyeSetupName(setup) + ", seed " + std::to_string(seed) + (head_alone ? ", the head camera alone" : ""));
        JointArmSession session = jointArmSession(setup, seed, 0.0002, true);
        const std::vector<int>& head = session.arm.head_chain;
        if (head_alone)
          for (vocal::HandEyeStation& s : session.stations) s.views.clear();
        const int head_sensor = head_alone ? 0 : 1;
        const int seen = addCameraViews(&session, head_sensor, [&](std::size_t k) { return session.arm.headAt(session.arm.head_angles[k]) * session.arm.arm.head_camera; },
                                        seed + 100);
        ASSERT_GE(seen, 10);
        vocal::HandEyeSensor head_camera(vocal::SensorType::kCamera, true, std::nullopt, "head_camera");
        head_camera.link_chain = head;
        std::vector<vocal::HandEyeSensor> sensors = {head_camera};
        if (!head_alone) sensors.insert(sensors.begin(), vocal::HandEyeSensor(vocal::SensorType::kCamera, in_hand, std::nullopt, "main_camera"));
        const vocal::HandEyeResult result = vocal::calibrateArmRig(sensors, !in_hand, session.stations, session.options);
        EXPECT_EQ(result.main_camera, 0);
        const std::vector<int>& read = session.options.arm_joints->readJoints();
        ASSERT_EQ(result.joints.size(), 8u);
        const auto [head_t, head_r] = errorAtUnvisitedConfigurations(session, read, result, head, result.sensors[head_sensor], session.arm.arm.head_camera);
        std::printf("%s%s, seed %u, head camera saw %d of %zu poses: in the base frame within %.2f mm / %.2f mrad at 20 unvisited head "
                    "configurations; first joints: arm %+.2f mrad (truth %+.2f, %s), head %+.2f (truth %+.2f, %s)\n",
                    vocal::handEyeSetupName(setup).c_str(), head_alone ? " (head camera alone)" : "", seed, seen, session.stations.size(),
                    1000 * head_t, 1000 * head_r, 1000 * result.joints[0].offset, 1000 * session.arm.joints[0].offset,
                    result.joints[0].held.empty() ? "solved" : "held", 1000 * result.joints[6].offset,
                    1000 * session.arm.joints[head[0]].offset, result.joints[6].held.empty() ? "solved" : "held");
        // Alone, the head camera also carries the wrist joints' offsets (2-3 mrad sigmas): 1.94 mm on seed 2.
        const double bound = head_alone ? 0.0025 : 0.002;
        EXPECT_LT(head_t, bound);
        EXPECT_LT(head_r, bound);
        // The first joints solved, each by the other branch, within what they state of themselves (1-4 mrad:
        // the two branches' first axes are parallel, a metre apart); the tilt's offset left to the head
        // camera's mount.
        for (const int i : {0, 6}) {
          EXPECT_TRUE(result.joints[i].held.empty()) << result.joints[i].held;
          EXPECT_GT(result.joints[i].standard_deviation, 0.0);
          EXPECT_LT(std::abs(result.joints[i].offset - session.arm.joints[read[i]].offset), 3 * result.joints[i].standard_deviation)
              << session.arm.joints[read[i]].name;
        }
        EXPECT_NE(result.joints[0].fixed_by.find("'head_pan_joint' that moved on another branch"), std::string::npos)
            << result.joints[0].fixed_by;
        EXPECT_EQ(result.joints[7].held, "no joint after it moved, so the poses of the sensors on 'head_tilt_link' take up its offset");
        if (head_alone) continue;
        const auto [main_t, main_r] =
            in_hand ? errorAtUnvisitedConfigurations(session, read, result, session.arm.chain, result.camera(), session.arm.arm.camera)
                    : errorAtUnvisitedConfigurations(session, read, result, {}, result.camera(), session.arm.arm.camera);
        std::printf("  the %s camera within %.2f mm / %.2f mrad\n", in_hand ? "wrist" : "post", 1000 * main_t, 1000 * main_r);
        EXPECT_LT(main_t, 0.002);
        EXPECT_LT(main_r, 0.002);
      }
    }
  }
}

// A 2D laser on the tool beside the wrist camera, over the fixed board, the tool from the joints: its scan
// plane (its z = 0, 270 degrees at 0.25-degree steps, 10 mm of range noise) turned to cross the board below
// the tool; its board points as range errors along its beams and its scan's ends on the board's outline.
// The laser's mount on the tool, against the truth turned by the held last joint's offset, within 3 of
// its stated sigmas.
TEST(JointedCalibration, A2dLaserOnTheToolBesideTheWristCamera) {
  for (const std::uint32_t seed : {1u, 2u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    JointArmSession session = jointArmSession(vocal::HandEyeSetup::kEyeInHand, seed, 0.0002);
    // 6 cm beside the wrist camera, its x along the tool's z (ahead, down at the board), its scan plane
    // holding the tool's z and x turned 0.15 rad about x: the line crosses the board at a slant.
    const Eigen::Isometry3d mount = vocal::poseFromTranslationQuaternion(
        {-0.06, 0.02, 0.0}, Eigen::Quaterniond(Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitY()) * Eigen::AngleAxisd(0.15, Eigen::Vector3d::UnitX())));
    const double width = 0.36, height = 0.27;
    std::mt19937 rng(seed + 300);
    std::normal_distribution<double> noise(0.0, 0.01);
    int crossed = 0;
    for (std::size_t k = 0; k < session.stations.size(); ++k) {
      const Eigen::Isometry3d laser_from_board = (session.arm.arm.true_tool[k] * mount).inverse() * session.arm.arm.board;
      const Eigen::Vector3d normal = laser_from_board.linear().col(2), origin = laser_from_board.translation();
      std::vector<Eigen::Vector3d> points;
      for (double angle = -135.0; angle <= 135.0; angle += 0.25) {
        const Eigen::Vector3d ray(std::cos(angle * M_PI / 180.0), std::sin(angle * M_PI / 180.0), 0.0);
        const double along = ray.dot(normal);
        if (std::abs(along) < 1e-6) continue;
        const double range = origin.dot(normal) / along;
        const Eigen::Vector3d on_board = laser_from_board.inverse() * (range * ray);
        if (range <= 0.05 || std::abs(on_board.x()) > width / 2 || std::abs(on_board.y()) > height / 2) continue;
        points.push_back((range + noise(rng)) * ray);
      }
      if (points.size() < 20) continue;
      ++crossed;
      // Its ends as the extraction gives them: half a step past the last returns, on the line's fit.
      const vocal::PrincipalAxes line = vocal::principalAxesOf(points);
      const Eigen::Vector3d across = Eigen::Vector3d(-line.axes(1, 0), line.axes(0, 0), 0.0).normalized();
      const std::vector<Eigen::Vector3d> ends = vocal::boardOutlinePoints(
          points, vocal::Plane{across, -across.dot(line.centroid)}, vocal::ScanSpacing{0.25 * M_PI / 180.0, 0.0, vocal::ScanPattern::kSpinning});
      session.stations[k].views.push_back({1, {}, points, ends});
    }
    ASSERT_GE(crossed, 8);
    vocal::HandEyeOptions options = session.options;
    options.board_width = width, options.board_height = height;
    const vocal::HandEyeResult result = vocal::calibrateArmRig(
        {{vocal::SensorType::kCamera, true, std::nullopt, "wrist_camera"}, {vocal::SensorType::kLaser2d, true, std::nullopt, "wrist_laser"}}, false,
        session.stations, options);
    const vocal::JointDescription& last = session.arm.joints[session.arm.chain.back()];
    const Eigen::Isometry3d expected = Eigen::Isometry3d(Eigen::AngleAxisd(last.offset - result.joints.back().offset, last.axis)) * mount;
    const double translation = (result.sensors[1].translation() - expected.translation()).norm();
    const double rotation = vocal::rotationAngle(expected.inverse() * result.sensors[1]);
    std::printf("2D laser on the tool, seed %u, %d of %zu poses crossed the board: %.2f mm / %.2f mrad (sigma %.2f mm / %.2f mrad)\n", seed,
                crossed, session.stations.size(), 1000 * translation, 1000 * rotation, 1000 * result.sensor_sigmas[1].head<3>().norm(),
                1000 * result.sensor_sigmas[1].tail<3>().norm());
    // Weak here, and said so: every still pose looks at the board's centre, so the lines cross it near one
    // place and the laser's turn within its scan plane and its shift along its central beam are fixed
    // mainly by the scan's ends (5-13 mm / mrad sigmas).
    EXPECT_LT(translation, 0.003);
    EXPECT_LT(rotation, 0.01);
    EXPECT_LT(translation, 3 * result.sensor_sigmas[1].head<3>().norm());
    EXPECT_LT(rotation, 3 * result.sensor_sigmas[1].tail<3>().norm());
  }
}

// A 2D laser on the tool beside the wrist camera as a robot records it (simulate_calibration_session
// --eye-in-hand --beside: its scans on /tool_laser/scan), the tool from /tf or from the joint states, through
// calibrate_rig: the laser lands in arm_tool within what it states of itself (weakly fixed: every pose looks
// at the board's centre); where it moves over the tolerance between re-solves it is withheld, told what
// poses to add. With joints, the tool frame is the model's: the truth turned by the held last joint's offset.
TEST(JointedCalibration, A2dLaserOnTheToolThroughCalibrateRig) {
  // The tool from /tf at seed 1 (published); from the joints at seed 2 (withheld).
  for (const auto& [arm, seed] : {std::pair<std::string, int>{"", 1}, {" --arm", 2}}) {
    SCOPED_TRACE("seed " + std::to_string(seed) + arm);
    const std::string folder = vocal_test::makeTempFolder("cli_tool_laser");
    vocal_test::RunResult r = vocal_test::runTool("simulate_calibration_session " + folder + " --eye-in-hand --beside --poses 12 --seed " +
                                                  std::to_string(seed) + arm);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    r = vocal_test::runTool("calibrate_rig " + folder + "/rig.yaml " + folder + "/session.bag --quiet --output-dir " + folder);
    EXPECT_NE(r.output.find("12 still poses of the arm with the board in view"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("tool_laser in arm_tool"), std::string::npos) << r.output;
    const YAML::Node rig = YAML::LoadFile(folder + "/rig.yaml");
    const YAML::Node truth = YAML::LoadFile(folder + "/ground_truth.yaml");
    const YAML::Node result = YAML::LoadFile(folder + "/calibration.yaml");
    ASSERT_EQ(result["sensors"].size(), 2u);
    // The model's tool frame: the true one turned by what the held last joint's offset leaves.
    Eigen::Isometry3d tool_turn = Eigen::Isometry3d::Identity();
    if (!arm.empty()) {
      const auto axis = rig["joints"][5]["axis"].as<std::vector<double>>();
      tool_turn = Eigen::AngleAxisd(truth["joints"][5]["offset"].as<double>() - result["joints"][5]["offset"].as<double>(),
                                    Eigen::Vector3d(axis[0], axis[1], axis[2]).normalized());
    }
    for (const YAML::Node& sensor : result["sensors"]) {
      const std::string name = sensor["name"].as<std::string>();
      EXPECT_EQ(sensor["parent"].as<std::string>(), "arm_tool") << name;
      const Eigen::Isometry3d error = (tool_turn * yamlPose(truth["sensors"][name]["pose"])).inverse() * yamlPose(sensor);
      const double metres = error.translation().norm(), radians = vocal::rotationAngle(error);
      const auto sd = sensor["translation_stddev"].as<std::vector<double>>();
      const auto rd = sensor["rotation_stddev"].as<std::vector<double>>();
      std::printf("seed %d%s: %s in arm_tool %.2f mm / %.2f mrad from the truth (stddev %.2f mm / %.2f mrad)\n", seed, arm.c_str(),
                  name.c_str(), 1000 * metres, 1000 * radians, 1000 * Eigen::Vector3d(sd[0], sd[1], sd[2]).norm(),
                  1000 * Eigen::Vector3d(rd[0], rd[1], rd[2]).norm());
      EXPECT_LT(metres, 3 * Eigen::Vector3d(sd[0], sd[1], sd[2]).norm()) << name;
      EXPECT_LT(radians, 3 * Eigen::Vector3d(rd[0], rd[1], rd[2]).norm()) << name;
      EXPECT_LT(metres, name == "tool_laser" ? 0.006 : 0.001) << name;
      EXPECT_LT(radians, name == "tool_laser" ? 0.012 : 0.002) << name;
    }
    // Seed 2's laser moves about the tolerance between re-solves (9.4 mrad; 11.9 with its scan ends held
    // within 1 cm each): published or withheld, it is told how to fix it when withheld. Seed 1's published.
    const bool laser_published = result["sensors"][1]["published"].as<bool>();
    if (seed == 1) EXPECT_TRUE(laser_published);
    EXPECT_EQ(r.exit_code, laser_published ? 0 : 1) << r.output;
    if (!laser_published) {
      EXPECT_NE(r.output.find("withheld: sensor 'tool_laser' is kept out of calibration.urdf and calibration.launch: uncertain: it moves "),
                std::string::npos) << r.output;
      EXPECT_NE(r.output.find("add arm poses whose scan line crosses the board at other places and slants, near its edges too"),
                std::string::npos) << r.output;
    }
  }
}

// The arm before a camera on a post whose pose rig.yaml gives, with a lidar, an RGB-D camera and a 2D laser
// beside it (simulate_calibration_session --eye-to-hand --arm --beside --given-reference and `options`),
// in `folder`, calibrated by calibrate_rig with its defaults: calibrate_rig's run.
namespace {
vocal_test::RunResult calibratedArmBeforeAGivenCamera(const std::string& folder, const std::string& options) {
  const vocal_test::RunResult simulated =
      vocal_test::runTool("simulate_calibration_session " + folder + " --eye-to-hand --arm --beside --given-reference " + options);
  EXPECT_EQ(simulated.exit_code, 0) << simulated.output;
  return vocal_test::runTool("calibrate_rig " + folder + "/rig.yaml " + folder + "/session.bag --quiet --output-dir " + folder);
}

// Every sensor of an arm session's calibration.yaml but the first (the given reference) against the truth
// in arm_base: within 2 mm / 2 mrad (the 2D laser 5 mm / 5 mrad) and within 3 of what it states.
// From the second sensor (the first is the given reference) or from `first`; each against its truth in the
// base frame turned by `base_turn` (what a held joint offset turns it by).
void expectFixedSensorsNearTheTruth(const YAML::Node& result, const YAML::Node& truth, const std::string& label, std::size_t first = 1,
                                    const Eigen::Isometry3d& base_turn = Eigen::Isometry3d::Identity()) {
  for (std::size_t s = first; s < result["sensors"].size(); ++s) {
    const YAML::Node sensor = result["sensors"][s];
    const std::string name = sensor["name"].as<std::string>();
    const Eigen::Isometry3d error = (base_turn * yamlPose(truth["sensors"][name]["pose"])).inverse() * yamlPose(sensor);
    const double metres = error.translation().norm(), radians = vocal::rotationAngle(error);
    std::printf("%s%s in arm_base: %.2f mm / %.2f mrad from the truth\n", label.c_str(), name.c_str(), 1000 * metres, 1000 * radians);
    const auto sd = sensor["translation_stddev"].as<std::vector<double>>();
    const auto rd = sensor["rotation_stddev"].as<std::vector<double>>();
    EXPECT_LT(metres, 3 * Eigen::Vector3d(sd[0], sd[1], sd[2]).norm()) << name;
    EXPECT_LT(radians, 3 * Eigen::Vector3d(rd[0], rd[1], rd[2]).norm()) << name;
    EXPECT_LT(metres, name == "arm_laser" ? 0.005 : 0.002) << name;
    EXPECT_LT(radians, name == "arm_laser" ? 0.005 : 0.002) << name;
  }
}
}  // namespace

// The arm holds the board before a camera on a post whose pose the rig gives (the reference), a lidar, an
// RGB-D camera and a 2D laser fixed beside it, 24 still poses, the tool from the joint states: the camera
// stays where the rig put it, the first joint's offset is solved (what fixed it said), the fixed sensors
// land in the base frame within 2 mm / 2 mrad and the 2D laser within what it states of itself. The laser's
// beam as wide as a SICK LMS1xx's (8 mm + 15 mrad x range across): its scan ends run on past the board's
// edges by the beam's radius, which the graph finds (4 mm + 7.5 mrad x range; 11.5 mm at 1 m).
TEST(JointedCalibration, ArmBeforeAGivenCameraALidarAndA2dLaserThroughCalibrateRig) {
  const std::string folder = vocal_test::makeTempFolder("cli_joint_arm_given");
  const vocal_test::RunResult r = calibratedArmBeforeAGivenCamera(folder, "--poses 24 --laser-beam 0.008,0.015");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("arm_camera held at the pose the rig gives in arm_base"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("fixed by the pose the rig gives 'arm_camera' and joints that moved after it"), std::string::npos) << r.output;
  const std::string beam_line = "arm_laser's beam as its scan ends reach past the board's edges: radius ";
  const std::size_t beam_at = r.output.find(beam_line);
  ASSERT_NE(beam_at, std::string::npos) << r.output;
  const std::size_t at_1m = r.output.find("(", beam_at);
  ASSERT_NE(at_1m, std::string::npos);
  EXPECT_NEAR(std::stod(r.output.substr(at_1m + 1)), 11.5, 2.0) << r.output.substr(beam_at, 120);
  const YAML::Node rig = YAML::LoadFile(folder + "/rig.yaml");
  const YAML::Node truth = YAML::LoadFile(folder + "/ground_truth.yaml");
  const YAML::Node result = YAML::LoadFile(folder + "/calibration.yaml");
  // The camera where rig.yaml put it (to the digits the YAML carries).
  const std::vector<double> given = rig["sensors"][0]["pose"].as<std::vector<double>>();
  const Eigen::Isometry3d camera = yamlPose(result["sensors"][0]);
  EXPECT_TRUE(result["sensors"][0]["held"].as<bool>());
  EXPECT_LT((camera.translation() - Eigen::Vector3d(given[0], given[1], given[2])).norm(), 1e-6);
  const Eigen::Quaterniond given_rotation(given[6], given[3], given[4], given[5]);
  EXPECT_LT(vocal::rotationAngle(Eigen::Isometry3d(given_rotation).inverse() * camera), 1e-6);
  EXPECT_TRUE(result["joints"][0]["solved"].as<bool>());
  EXPECT_NEAR(result["joints"][0]["offset"].as<double>(), truth["joints"][0]["offset"].as<double>(), 0.0005);
  expectFixedSensorsNearTheTruth(result, truth, "");
  EXPECT_EQ(result["sensors"].size(), 4u);
}

// The same arm session through the one graph (calibrate_rig --one-graph: the still-pose graph with the
// board a frame on the tool, its pose per still pose tied to the arm's joints; issue 44): the camera where
// the rig put it, the first joint's offset within 0.5 mrad of the truth, the lidar and the RGB-D camera
// within 2 mm / 2 mrad and the 2D laser within 5 mm / 5 mrad of the truth in arm_base (the arm's own graph's
// bounds above), each within 3 of what it states. A rig whose arm moves its camera over a fixed board: refused, with
// what the option takes for now.
TEST(JointedCalibration, ArmSessionThroughTheOneGraph) {
  const std::string folder = vocal_test::makeTempFolder("cli_joint_arm_one_graph");
  const vocal_test::RunResult simulated =
      vocal_test::runTool("simulate_calibration_session " + folder + " --eye-to-hand --arm --beside --given-reference --poses 16");
  ASSERT_EQ(simulated.exit_code, 0) << simulated.output;
  const vocal_test::RunResult r =
      vocal_test::runTool("calibrate_rig " + folder + "/rig.yaml " + folder + "/session.bag --quiet --one-graph --output-dir " + folder);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("one graph: the board a frame on arm_tool (from the arm's joints), 16 still poses"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("arm_camera      0.50000    0.90000    0.60000"), std::string::npos) << r.output;
  const std::size_t first = r.output.find("  shoulder_pan_joint ");
  ASSERT_NE(first, std::string::npos) << r.output;
  const YAML::Node truth = YAML::LoadFile(folder + "/ground_truth.yaml");
  EXPECT_NEAR(1e-3 * std::stod(r.output.substr(first + 20)), truth["joints"][0]["offset"].as<double>(), 0.0005) << r.output.substr(first, 120);
  EXPECT_NE(r.output.find("fixed by the reference's given pose (the rig frame) and joints that moved after it", first), std::string::npos);
  const YAML::Node result = YAML::LoadFile(folder + "/calibration.yaml");
  ASSERT_EQ(result["sensors"].size(), 4u);
  EXPECT_EQ(result["joints"][0]["name"].as<std::string>(), "shoulder_pan_joint");
  EXPECT_NEAR(result["joints"][0]["offset"].as<double>(), truth["joints"][0]["offset"].as<double>(), 0.0005);
  EXPECT_EQ(result["board"]["parent"].as<std::string>(), "arm_tool");
  // The board's mount on the tool, turned by the last joint's true offset (held: no joint after it moves
  // the board, so the mount takes it up).
  EXPECT_FALSE(result["joints"][5]["solved"].as<bool>());
  const vocal::RigDescription described = vocal::readRigDescription(folder + "/rig.yaml");
  const auto last = std::find_if(described.joints.begin(), described.joints.end(),
                                 [&](const vocal::JointDescription& j) { return j.name == result["joints"][5]["name"].as<std::string>(); });
  ASSERT_NE(last, described.joints.end());
  const Eigen::Isometry3d expected =
      Eigen::Isometry3d(Eigen::AngleAxisd(truth["joints"][5]["offset"].as<double>(), last->axis)) * yamlPose(truth["board"]["pose"]);
  const Eigen::Isometry3d board_error = expected.inverse() * yamlPose(result["board"]);
  std::printf("one graph: the board on arm_tool %.2f mm / %.2f mrad from the truth (the last joint's offset in it)\n",
              1000 * board_error.translation().norm(), 1000 * vocal::rotationAngle(board_error));
  EXPECT_LT(board_error.translation().norm(), 0.002);
  EXPECT_LT(vocal::rotationAngle(board_error), 0.002);
  expectFixedSensorsNearTheTruth(result, truth, "one graph: ");

}

// The same arm before the given camera, its RGB-D camera bumped 1 cm / 10 mrad half way through (16
// poses; simulate_calibration_session --faults): its views disagree far beyond their noise, so the arm's
// poses are split in time and it is placed apart before and after: named as moved from pose 9 on (not as
// uncertain: no number of poses would make it right), withheld, reported where it sits after the bump, and
// its two placements pull on none of the other sensors (the lidar within 2 mm / 3 mrad of the truth).
TEST(JointedCalibration, ASensorBumpedPartWayThroughAnArmSessionIsNamedAndKeptApart) {
  const std::string folder = vocal_test::makeTempFolder("cli_joint_arm_bumped");
  const vocal_test::RunResult r = calibratedArmBeforeAGivenCamera(folder, "--poses 16 --faults bumped:arm_rgbd:0.01");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("withheld: sensor 'arm_rgbd' is kept out of calibration.urdf and calibration.launch: it moved part-way through "
                          "the session: its placement from the arm poses before pose 9 and from those after differ by"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("withheld: sensor 'arm_lidar'"), std::string::npos) << r.output;
  const YAML::Node truth = YAML::LoadFile(folder + "/ground_truth.yaml");
  const YAML::Node result = YAML::LoadFile(folder + "/calibration.yaml");
  // The bump as the simulator makes it (calibration_bag.cpp's faultyPlacement): in the sensor's frame.
  Eigen::Isometry3d bump = Eigen::Isometry3d::Identity();
  bump.linear() = Eigen::AngleAxisd(0.01, Eigen::Vector3d(1.0, 1.0, 0.0).normalized()).toRotationMatrix();
  bump.translation() = 0.01 * Eigen::Vector3d(1.0, -1.0, 1.0).normalized();
  for (const YAML::Node& sensor : result["sensors"]) {
    const std::string name = sensor["name"].as<std::string>();
    if (name != "arm_rgbd" && name != "arm_lidar") continue;
    const Eigen::Isometry3d expected = yamlPose(truth["sensors"][name]["pose"]) * (name == "arm_rgbd" ? bump : Eigen::Isometry3d::Identity());
    const Eigen::Isometry3d error = expected.inverse() * yamlPose(sensor);
    std::printf("%s in arm_base: %.2f mm / %.2f mrad from the truth%s\n", name.c_str(), 1000 * error.translation().norm(),
                1000 * vocal::rotationAngle(error), name == "arm_rgbd" ? " after the bump" : "");
    EXPECT_EQ(sensor["published"].as<bool>(), name != "arm_rgbd") << name;
    EXPECT_LT(error.translation().norm(), 0.002) << name;
    EXPECT_LT(vocal::rotationAngle(error), 0.003) << name;
  }
}

// The same bumped session through the one graph (calibrate_rig --one-graph): the arm pins every pose's
// board, so the RGB-D camera's move is judged in its own sigmas (not the hand-held boards' 15 mm / 20 mrad,
// which a 1 cm / 10 mrad bump stays under): named as moved part-way from still pose 8 (the ninth), taken
// out of the graph and withheld; the lidar, solved without it, within 2 mm / 3 mrad of the truth.
TEST(JointedCalibration, ASensorBumpedPartWayThroughAnArmSessionIsTakenOutOfTheOneGraph) {
  const std::string folder = vocal_test::makeTempFolder("cli_joint_arm_bumped_one_graph");
  const vocal_test::RunResult simulated = vocal_test::runTool("simulate_calibration_session " + folder +
                                                              " --eye-to-hand --arm --beside --given-reference --poses 16 --faults bumped:arm_rgbd:0.01");
  ASSERT_EQ(simulated.exit_code, 0) << simulated.output;
  const vocal_test::RunResult r =
      vocal_test::runTool("calibrate_rig " + folder + "/rig.yaml " + folder + "/session.bag --quiet --one-graph --output-dir " + folder);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("NOT TRUSTED: sensor 'arm_rgbd': its placement from the still poses before pose 8 and from those after differ by "),
            std::string::npos) << r.output;
  EXPECT_NE(r.output.find("it moved part-way through the session (bumped, or a loose mount); fix it and record again; taken out of the graph"),
            std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("withheld: sensor 'arm_lidar'"), std::string::npos) << r.output;
  const YAML::Node truth = YAML::LoadFile(folder + "/ground_truth.yaml");
  const YAML::Node result = YAML::LoadFile(folder + "/calibration.yaml");
  ASSERT_EQ(result["sensors"][1]["name"].as<std::string>(), "arm_lidar");
  ASSERT_EQ(result["sensors"][2]["name"].as<std::string>(), "arm_rgbd");
  EXPECT_FALSE(result["sensors"][2]["published"].as<bool>());
  const Eigen::Isometry3d error = yamlPose(truth["sensors"]["arm_lidar"]["pose"]).inverse() * yamlPose(result["sensors"][1]);
  std::printf("one graph, the RGB-D camera bumped: the lidar %.2f mm / %.2f mrad from the truth\n", 1000 * error.translation().norm(),
              1000 * vocal::rotationAngle(error));
  EXPECT_LT(error.translation().norm(), 0.002);
  EXPECT_LT(vocal::rotationAngle(error), 0.003);
}

// A 6-joint arm's session as a robot records it (images, /joint_states at 200 Hz, /tf from the readings)
// through calibrate_rig with a rig that names the arm's joints: the tool from the joint states, the
// joints' offsets solved, OpenCV's closed forms beside.
TEST(JointedCalibration, ArmSessionThroughCalibrateRig) {
  const std::string folder = vocal_test::makeTempFolder("cli_joint_arm");
  vocal_test::RunResult r = vocal_test::runTool("simulate_calibration_session " + folder + " --eye-in-hand --arm --poses 10");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = vocal_test::runTool("calibrate_rig " + folder + "/rig.yaml " + folder + "/session.bag --quiet --output-dir " + folder);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find(" joint readings on /joint_states: the tool arm_tool from the arm's 6 joints"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("10 still poses of the arm with the board in view"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("shoulder_pan_joint      +0.00 mrad +- 0.00"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("held: no joint after it moved, so the poses on the tool"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("OpenCV's calibrateHandEye on the same poses, for arm_camera"), std::string::npos) << r.output;
  const YAML::Node truth = YAML::LoadFile(folder + "/ground_truth.yaml");
  const YAML::Node result = YAML::LoadFile(folder + "/calibration.yaml");
  ASSERT_EQ(result["joints"].size(), 6u);
  for (std::size_t j = 1; j + 1 < 6; ++j) {  // the first and last are held
    EXPECT_TRUE(result["joints"][j]["solved"].as<bool>());
    EXPECT_NEAR(result["joints"][j]["offset"].as<double>(), truth["joints"][j]["offset"].as<double>(),
                std::max(0.002, 3.0 * result["joints"][j]["offset_stddev"].as<double>()))
        << truth["joints"][j]["name"].as<std::string>();
  }
  EXPECT_TRUE(result["calibration"]["elbow_joint"]);
  // The camera's focal lengths refined with the arm's motion: printed and written; the simulator's
  // camera_info is right, so they stay within 0.5 % of it.
  r = vocal_test::runTool("calibrate_rig " + folder + "/rig.yaml " + folder + "/session.bag --quiet --refine-intrinsics --output-dir " + folder);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("intrinsics: arm_camera: focal lengths fx "), std::string::npos) << r.output;
  const YAML::Node intrinsics = YAML::LoadFile(folder + "/calibration.yaml")["sensors"][0]["intrinsics"];
  ASSERT_TRUE(intrinsics) << "no intrinsics in calibration.yaml";
  const std::vector<double> given = intrinsics["given"].as<std::vector<double>>(), refined = intrinsics["refined"].as<std::vector<double>>();
  EXPECT_NEAR(refined[0], given[0], 0.005 * given[0]);
  EXPECT_DOUBLE_EQ(refined[2], given[2]);
  // Without the joint states the rig cannot place the tool: said so.
  vocal_test::writeText(folder + "/elsewhere.yaml", "joint_states_topic: /arm/joint_states\n" + [&] {
    std::ifstream rig(folder + "/rig.yaml");
    return std::string((std::istreambuf_iterator<char>(rig)), std::istreambuf_iterator<char>());
  }());
  r = vocal_test::runTool("calibrate_rig " + folder + "/elsewhere.yaml " + folder + "/session.bag --quiet");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("the arm's tool 'arm_tool' comes from its joints, but the bag has no sensor_msgs/JointState on /arm/joint_states"),
            std::string::npos) << r.output;
}

// An arm whose upper arm is 1 cm longer than its URDF says, its elbow's origin free, through
// calibrate_rig: the origin printed with what the session fixed, written to calibration.yaml (the length
// within its sigma of the truth) and into robot_calibrated.urdf's <origin>, the other joints' as they were.
TEST(JointedCalibration, FreeElbowOriginThroughCalibrateRig) {
  const std::string folder = vocal_test::makeTempFolder("cli_free_origin");
  vocal_test::RunResult r = vocal_test::runTool("simulate_calibration_session " + folder +
                                                " --eye-in-hand --arm --poses 12 --link-error 0.01 --free-origins elbow_joint");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // The rig's joints as the robot's URDF (the maker's model), named by the rig instead of its list.
  vocal::RigDescription rig = vocal::readRigDescription(folder + "/rig.yaml");
  std::ostringstream urdf;
  urdf << std::setprecision(12) << "<?xml version=\"1.0\"?>\n<robot name=\"arm\">\n  <link name=\"arm_base\"/>\n";
  for (const vocal::JointDescription& joint : rig.joints) {
    const Eigen::Vector3d t = joint.origin.translation(), rpy = vocal::rollPitchYawFromRotation(joint.origin.rotation());
    urdf << "  <link name=\"" << joint.child << "\"/>\n  <joint name=\"" << joint.name << "\" type=\"revolute\">\n    <parent link=\""
         << joint.parent << "\"/>\n    <child link=\"" << joint.child << "\"/>\n    <origin xyz=\"" << t.x() << " " << t.y() << " " << t.z()
         << "\" rpy=\"" << rpy.x() << " " << rpy.y() << " " << rpy.z() << "\"/>\n    <axis xyz=\"" << joint.axis.x() << " " << joint.axis.y() << " "
         << joint.axis.z() << "\"/>\n    <limit lower=\"-6.28\" upper=\"6.28\" effort=\"100\" velocity=\"3\"/>\n  </joint>\n";
  }
  urdf << "</robot>\n";
  vocal_test::writeText(folder + "/robot.urdf", urdf.str());
  rig.urdf = "robot.urdf";
  vocal::writeRigDescription(folder + "/urdf_rig.yaml", rig);
  r = vocal_test::runTool("calibrate_rig " + folder + "/urdf_rig.yaml " + folder + "/session.bag --quiet --output-dir " + folder);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("origin xyz"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("held at the model's (the session's motion does not fix it): shift along x"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("and the 1 free origins as solved"), std::string::npos) << r.output;
  const YAML::Node elbow = YAML::LoadFile(folder + "/calibration.yaml")["joints"][2];
  ASSERT_EQ(elbow["name"].as<std::string>(), "elbow_joint");
  const std::vector<double> correction = elbow["origin"]["correction"].as<std::vector<double>>();
  const std::vector<double> sigma = elbow["origin"]["correction_stddev"].as<std::vector<double>>();
  EXPECT_NEAR(correction[5], 0.01, std::max(0.002, 3.0 * sigma[5]));
  EXPECT_DOUBLE_EQ(sigma[3], 0.0);  // held
  const YAML::Node truth = YAML::LoadFile(folder + "/ground_truth.yaml")["joints"][2]["origin"]["translation"];
  EXPECT_NEAR(elbow["origin"]["xyz"][2].as<double>(), truth[2].as<double>(), std::max(0.002, 3.0 * sigma[5]));
  std::ifstream calibrated(folder + "/robot_calibrated.urdf");
  const std::vector<vocal::JointDescription> written =
      vocal::urdfJointsFromString(std::string((std::istreambuf_iterator<char>(calibrated)), std::istreambuf_iterator<char>()), "robot_calibrated.urdf");
  ASSERT_EQ(written.size(), rig.joints.size());
  for (const vocal::JointDescription& joint : written) {
    const auto model = std::find_if(rig.joints.begin(), rig.joints.end(), [&](const vocal::JointDescription& j) { return j.name == joint.name; });
    ASSERT_NE(model, rig.joints.end()) << joint.name;
    const double z = joint.name == "elbow_joint" ? elbow["origin"]["xyz"][2].as<double>() : model->origin.translation().z();
    EXPECT_NEAR(joint.origin.translation().z(), z, 1e-8) << joint.name;
  }
}

namespace {
// A simulated arm session with a camera on the forearm (`setup`: --eye-in-hand or --eye-to-hand) written
// to `folder` and calibrated there by calibrate_rig: how far the forearm camera lands from the truth in
// forearm_link (m, rad); NaN when a tool failed.
std::pair<double, double> forearmCameraThroughCalibrateRig(const std::string& folder, const std::string& setup) {
  constexpr double kFailed = std::numeric_limits<double>::quiet_NaN();
  vocal_test::RunResult r = vocal_test::runTool("simulate_calibration_session " + folder + " " + setup + " --arm --forearm --poses 12");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  if (r.exit_code != 0) return {kFailed, kFailed};
  r = vocal_test::runTool("calibrate_rig " + folder + "/rig.yaml " + folder + "/session.bag --quiet --output-dir " + folder);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("forearm_camera in forearm_link"), std::string::npos) << r.output;
  const YAML::Node result = YAML::LoadFile(folder + "/calibration.yaml")["sensors"][1];
  EXPECT_EQ(result["name"].as<std::string>(), "forearm_camera");
  EXPECT_EQ(result["parent"].as<std::string>(), "forearm_link");
  const Eigen::Isometry3d expected = yamlPose(YAML::LoadFile(folder + "/ground_truth.yaml")["sensors"]["forearm_camera"]["pose"]);
  const Eigen::Isometry3d found = yamlPose(result);
  return {(found.translation() - expected.translation()).norm(), vocal::rotationAngle(expected.inverse() * found)};
}
}  // namespace

// A camera on the arm's forearm beside the wrist camera, the tool and the forearm from /joint_states,
// through calibrate_rig: the forearm camera in forearm_link within 2 mm / 2 mrad of the truth and written
// there; the tool found as the link furthest along the chain whichever sensor the rig lists first; the
// same rig without the joints refused with what to do. With the board in the gripper before a camera on a
// post: the forearm camera as well.
TEST(JointedCalibration, ForearmCameraThroughCalibrateRig) {
  const std::string folder = vocal_test::makeTempFolder("cli_forearm");
  const auto [metres, radians] = forearmCameraThroughCalibrateRig(folder, "--eye-in-hand");
  std::printf("forearm camera through calibrate_rig: %.2f mm / %.2f mrad\n", 1000 * metres, 1000 * radians);
  EXPECT_LT(metres, 0.002);
  EXPECT_LT(radians, 0.002);
  const std::string urdf_text = vocal_test::readText(folder + "/calibration.urdf");
  EXPECT_NE(urdf_text.find("<parent link=\"forearm_link\"/>"), std::string::npos) << urdf_text;

  const std::string rig_text = vocal_test::readText(folder + "/rig.yaml");
  // The forearm camera listed first: the tool is still arm_tool, the wrist camera the main one.
  const std::size_t wrist_at = rig_text.find("  - {name: arm_camera"), forearm_at = rig_text.find("  - {name: forearm_camera");
  ASSERT_NE(wrist_at, std::string::npos);
  ASSERT_NE(forearm_at, std::string::npos);
  const std::string swapped = rig_text.substr(0, wrist_at) + rig_text.substr(forearm_at) + rig_text.substr(wrist_at, forearm_at - wrist_at);
  vocal_test::writeText(folder + "/swapped.yaml", swapped);
  const std::optional<vocal::HandEyeRig> arm = vocal::readRigDescription(folder + "/swapped.yaml").handEye();
  ASSERT_TRUE(arm.has_value());
  EXPECT_EQ(arm->tool_frame, "arm_tool");
  EXPECT_EQ(arm->camera, 1);
  EXPECT_EQ(arm->link_chains, std::vector<std::vector<int>>({{0, 1, 2}, {}}));

  // Without the joints the forearm is a second frame tf would have to move: refused, saying what is needed.
  const std::size_t joints_at = rig_text.find("joints:\n"), sensors_at = rig_text.find("sensors:\n");
  ASSERT_NE(joints_at, std::string::npos);
  vocal_test::writeText(folder + "/no_joints.yaml", rig_text.substr(0, joints_at) + rig_text.substr(sensors_at));
  try {
    vocal::readRigDescription(folder + "/no_joints.yaml");
    ADD_FAILURE() << "a forearm camera without the arm's joints was accepted";
  } catch (const vocal::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("its parent 'forearm_link' is a second moving frame besides 'arm_tool'; one moving frame per rig (a sensor "
                                         "on an arm's other links needs the arm's joints: 'joints:' or 'urdf:')"),
              std::string::npos) << e.what();
  }

  // The board in the gripper before a camera on a post, the forearm camera watching it too.
  const auto [to_hand_metres, to_hand_radians] = forearmCameraThroughCalibrateRig(vocal_test::makeTempFolder("cli_forearm_to_hand"), "--eye-to-hand");
  std::printf("forearm camera before the board in the gripper, through calibrate_rig: %.2f mm / %.2f mrad\n", 1000 * to_hand_metres,
              1000 * to_hand_radians);
  EXPECT_LT(to_hand_metres, 0.002);
  EXPECT_LT(to_hand_radians, 0.002);
}

namespace {
// The worst distance and angle, over a simulated arm session's still poses, between where the truth puts
// sensor `name` (on a link the joints move) in the base frame - its chain at the true angles (ground_truth's
// arm_angles, then head_angles) times its true mount - and where calibration.yaml `result` puts it: the chain
// at the readings noise-free encoders give there, with the offsets as solved, times its mount as solved (a
// held last offset and the mount trade exactly). `from_the_board`: seen from the board lying still in the
// base, true and as solved (eye-in-hand, where the held first joint turns the base frame and the board alike).
std::pair<double, double> worstOnItsLinkAtStillPoses(const std::string& folder, const std::string& name, bool from_the_board = false) {
  const vocal::RigDescription rig = vocal::readRigDescription(folder + "/rig.yaml");
  const YAML::Node truth = YAML::LoadFile(folder + "/ground_truth.yaml");
  const YAML::Node result = YAML::LoadFile(folder + "/calibration.yaml");
  std::vector<double> true_offsets(rig.joints.size(), 0.0), solved_offsets(rig.joints.size(), 0.0);
  const auto indexOf = [&](const std::string& joint) {
    for (std::size_t j = 0; j < rig.joints.size(); ++j)
      if (rig.joints[j].name == joint) return j;
    ADD_FAILURE() << "no joint " << joint;
    return std::size_t{0};
  };
  for (const YAML::Node& j : truth["joints"]) true_offsets[indexOf(j["name"].as<std::string>())] = j["offset"].as<double>();
  for (const YAML::Node& j : result["joints"]) solved_offsets[indexOf(j["name"].as<std::string>())] = j["offset"].as<double>();
  YAML::Node solved;
  for (const YAML::Node& sensor : result["sensors"])
    if (sensor["name"].as<std::string>() == name) solved = sensor;
  if (!solved) {
    ADD_FAILURE() << "no sensor " << name << " in the result";
    return {1.0, 1.0};
  }
  const std::string link = solved["parent"].as<std::string>();
  const std::vector<int> chain = vocal::jointChain(rig.joints, rig.reference_frame, link, name);
  const std::vector<int> arm = vocal::jointChain(rig.joints, rig.reference_frame, "arm_tool", "the arm");
  const Eigen::Isometry3d true_mount = yamlPose(truth["sensors"][name]["pose"]), mount = yamlPose(solved);
  const std::vector<double> zero(rig.joints.size(), 0.0);
  double worst_t = 0.0, worst_r = 0.0;
  for (std::size_t k = 0; k < truth["arm_angles"].size(); ++k) {
    std::vector<double> angle_of(rig.joints.size(), 0.0);
    const std::vector<double> arm_angles = truth["arm_angles"][k].as<std::vector<double>>();
    for (std::size_t i = 0; i < arm.size(); ++i) angle_of[arm[i]] = arm_angles[i];
    if (truth["head_angles"]) {
      const std::vector<int> head = vocal::jointChain(rig.joints, rig.reference_frame, "head_tilt_link", "the head");
      const std::vector<double> head_angles = truth["head_angles"][k].as<std::vector<double>>();
      for (std::size_t i = 0; i < head.size(); ++i) angle_of[head[i]] = head_angles[i];
    }
    std::vector<double> angles, readings;
    for (const int j : chain) angles.push_back(angle_of[j]), readings.push_back(angle_of[j] - true_offsets[j]);
    Eigen::Isometry3d expected = vocal::chainPose(rig.joints, chain, angles, zero) * true_mount;
    Eigen::Isometry3d found = vocal::chainPose(rig.joints, chain, readings, solved_offsets) * mount;
    if (from_the_board) {  // the one graph's "board", the arm's graph's "target"; a camera sees the print on it (true: at its centre)
      Eigen::Isometry3d board = yamlPose(result["board"] ? result["board"] : result["target"]);
      if (result["board"] && result["board"]["print"] && solved["type"].as<std::string>() == "camera") {
        const std::vector<double> print = result["board"]["print"].as<std::vector<double>>();
        board = board * Eigen::Translation3d(print[0], print[1], 0.0) * Eigen::AngleAxisd(print[2], Eigen::Vector3d::UnitZ());
      }
      expected = yamlPose(truth["board"]["pose"]).inverse() * expected;
      found = board.inverse() * found;
    }
    worst_t = std::max(worst_t, (found.translation() - expected.translation()).norm());
    worst_r = std::max(worst_r, vocal::rotationAngle(expected.inverse() * found));
  }
  return {worst_t, worst_r};
}
}  // namespace

// A head beside the arm through the tools: simulate_calibration_session --eye-to-hand --arm --head, then
// calibrate_rig. The head camera (in head_tilt_link, behind the head's joints as calibrated) in the base
// frame at each still pose's true head angles read by noise-free encoders, and the post camera in the
// base frame, within 2 mm / 2 mrad of the truth; each first joint fixed by the other branch.
TEST(JointedCalibration, HeadAndArmThroughCalibrateRig) {
  const std::string folder = vocal_test::makeTempFolder("cli_head_arm");
  vocal_test::RunResult r = vocal_test::runTool("simulate_calibration_session " + folder + " --eye-to-hand --arm --head --poses 12");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = vocal_test::runTool("calibrate_rig " + folder + "/rig.yaml " + folder + "/session.bag --quiet --output-dir " + folder);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("head_camera in head_tilt_link"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("fixed by 'head_pan_joint' that moved on another branch"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("fixed by 'shoulder_pan_joint' that moved on another branch"), std::string::npos) << r.output;
  const YAML::Node truth = YAML::LoadFile(folder + "/ground_truth.yaml");
  const YAML::Node result = YAML::LoadFile(folder + "/calibration.yaml");
  ASSERT_EQ(result["sensors"][1]["name"].as<std::string>(), "head_camera");
  EXPECT_EQ(result["sensors"][1]["parent"].as<std::string>(), "head_tilt_link");
  ASSERT_EQ(truth["head_angles"].size(), 12u);
  const auto [worst_t, worst_r] = worstOnItsLinkAtStillPoses(folder, "head_camera");
  const Eigen::Isometry3d post = yamlPose(result["sensors"][0]), true_post = yamlPose(truth["sensors"]["arm_camera"]["pose"]);
  const double post_t = (post.translation() - true_post.translation()).norm(), post_r = vocal::rotationAngle(true_post.inverse() * post);
  std::printf("head and arm through calibrate_rig: the head camera in arm_base within %.2f mm / %.2f mrad at the still poses, the post "
              "camera %.2f mm / %.2f mrad\n", 1000 * worst_t, 1000 * worst_r, 1000 * post_t, 1000 * post_r);
  EXPECT_LT(worst_t, 0.002);
  EXPECT_LT(worst_r, 0.002);
  EXPECT_LT(post_t, 0.002);
  EXPECT_LT(post_r, 0.002);
  const std::string urdf_text = vocal_test::readText(folder + "/calibration.urdf");
  EXPECT_NE(urdf_text.find("<parent link=\"head_tilt_link\"/>"), std::string::npos) << urdf_text;
}

// Sensors on the arm's links through the one graph (calibrate_rig --one-graph; issue 44): a camera on the
// forearm, then a camera on a pan-tilt head beside the arm, each watching the board in the gripper with the
// post camera's pose given. Each is a frame of the still-pose graph on its own chain (the forearm's first
// three joints, the head's two) read from the same /joint_states as the board's, so the joints they share
// with the board's chain are one unknown: each lands in the base frame within 2 mm / 2 mrad of the truth at
// every still pose (the arm graph's bound), is written on its link, the first joint's offset solved within 3
// of its sigma of the truth and fixed by the given pose; the head's tilt, last on its chain, held. The
// forearm's one view whose pattern was found shifted by a square is held by its plane only, and said.
TEST(JointedCalibration, SensorsOnTheArmsLinksThroughTheOneGraph) {
  for (const std::string link_sensor : {"forearm", "head"}) {
    SCOPED_TRACE(link_sensor);
    const std::string folder = vocal_test::makeTempFolder("cli_one_graph_" + link_sensor);
    const vocal_test::RunResult simulated = vocal_test::runTool("simulate_calibration_session " + folder + " --eye-to-hand --arm --" +
                                                                link_sensor + " --given-reference --poses 12");
    ASSERT_EQ(simulated.exit_code, 0) << simulated.output;
    const vocal_test::RunResult r =
        vocal_test::runTool("calibrate_rig " + folder + "/rig.yaml " + folder + "/session.bag --quiet --one-graph --output-dir " + folder);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    const std::string name = link_sensor + "_camera", link = link_sensor == "head" ? "head_tilt_link" : "forearm_link";
    const YAML::Node truth = YAML::LoadFile(folder + "/ground_truth.yaml");
    const YAML::Node result = YAML::LoadFile(folder + "/calibration.yaml");
    ASSERT_EQ(result["sensors"].size(), 2u);
    EXPECT_EQ(result["sensors"][1]["name"].as<std::string>(), name);
    EXPECT_EQ(result["sensors"][1]["parent"].as<std::string>(), link);
    EXPECT_TRUE(result["sensors"][1]["published"].as<bool>());
    const auto [worst_t, worst_r] = worstOnItsLinkAtStillPoses(folder, name);
    std::printf("one graph: the %s camera in arm_base within %.2f mm / %.2f mrad of the truth at the still poses, the first joint's offset "
                "%+.2f mrad (truth %+.2f) +- %.2f\n", link_sensor.c_str(), 1000 * worst_t, 1000 * worst_r, 1000 * result["joints"][0]["offset"].as<double>(),
                1000 * truth["joints"][0]["offset"].as<double>(), 1000 * result["joints"][0]["offset_stddev"].as<double>());
    EXPECT_LT(worst_t, 0.002);
    EXPECT_LT(worst_r, 0.002);
    EXPECT_EQ(result["joints"][0]["fixed_by"].as<std::string>(), "the reference's given pose (the rig frame) and joints that moved after it");
    EXPECT_LT(std::abs(result["joints"][0]["offset"].as<double>() - truth["joints"][0]["offset"].as<double>()),
              3 * result["joints"][0]["offset_stddev"].as<double>());
    if (link_sensor == "forearm") {  // seed 1's forearm view whose pattern was found shifted by a square
      EXPECT_NE(r.output.find("1 camera view held by its plane only: the board over 15 mm / 50 mrad from where the started rig put it (a "
                              "pattern found shifted by a square, or something else seen)"),
                std::string::npos) << r.output;
    }
    if (link_sensor == "head") {
      EXPECT_NE(r.output.find("  head_tilt_joint         +0.00 mrad +- 0.00, moved 0.261 rad, held: no joint after it moved over the session, so "
                              "the mount of the sensor behind it takes up its offset"),
                std::string::npos) << r.output;
    }
    const std::string urdf_text = vocal_test::readText(folder + "/calibration.urdf");
    EXPECT_NE(urdf_text.find("<parent link=\"" + link + "\"/>"), std::string::npos) << urdf_text;
  }
}

// An arm holding the board before fixed sensors none of whose poses the rig gives, through the one graph
// (calibrate_rig --one-graph; issue 44): the arm's base is the rig frame, the post camera started from the
// eye-to-hand closed form, the others from it.
// - The tool from tf (a camera, a lidar, an RGB-D camera, a 2D laser): each within 2 mm / 2 mrad of the
//   truth (the laser 5 mm / 5 mrad) and within 3 of what it states.
// - The tool from the joints: the first joint's offset turns the board and every fixed sensor alike, so it
//   is held and said why; the sensors within the same bounds of the truth turned by that offset.
// - With a head beside the arm: the head's chain does not share the arm's first joint, so both first joints
//   are solved (within 3 of their sigma of the truth), the post camera and the head camera (at every still
//   pose) within 2 mm / 2 mrad; the head camera placed from the post camera's views, not by a closed form.
TEST(JointedCalibration, AnArmBeforeSensorsNoneOfWhosePosesIsGivenThroughTheOneGraph) {
  for (const std::string setup : {"--beside", "--arm --beside", "--arm --head"}) {
    SCOPED_TRACE(setup);
    const std::string folder = vocal_test::makeTempFolder("cli_one_graph_no_reference");
    const vocal_test::RunResult simulated = vocal_test::runTool("simulate_calibration_session " + folder + " --eye-to-hand --poses 12 " + setup);
    ASSERT_EQ(simulated.exit_code, 0) << simulated.output;
    const vocal_test::RunResult r =
        vocal_test::runTool("calibrate_rig " + folder + "/rig.yaml " + folder + "/session.bag --quiet --one-graph --output-dir " + folder);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("12 still poses, no sensor's pose given: arm_base, the arm's base, is the rig frame"), std::string::npos) << r.output;
    const YAML::Node truth = YAML::LoadFile(folder + "/ground_truth.yaml");
    const YAML::Node result = YAML::LoadFile(folder + "/calibration.yaml");
    if (setup == "--beside") {
      ASSERT_EQ(result["sensors"].size(), 4u);
      expectFixedSensorsNearTheTruth(result, truth, "one graph, no pose given, tf: ", 0);
      continue;
    }
    ASSERT_EQ(result["joints"][0]["name"].as<std::string>(), "shoulder_pan_joint");
    const double pan = truth["joints"][0]["offset"].as<double>();
    if (setup == "--arm --beside") {
      ASSERT_EQ(result["sensors"].size(), 4u);
      EXPECT_FALSE(result["joints"][0]["solved"].as<bool>());
      EXPECT_NE(r.output.find("held: the first joint from the base, whose frame is the rig's: the sensors fixed in it take up its offset "
                              "(give one sensor's pose, the reference, to solve it)"),
                std::string::npos) << r.output;
      // The readings short by the true offset: the board, and with it every fixed sensor, turned back by it.
      expectFixedSensorsNearTheTruth(result, truth, "one graph, no pose given, joints: ", 0,
                                     Eigen::Isometry3d(Eigen::AngleAxisd(-pan, Eigen::Vector3d::UnitZ())));
      continue;
    }
    ASSERT_EQ(result["sensors"].size(), 2u);
    ASSERT_EQ(result["sensors"][1]["name"].as<std::string>(), "head_camera");
    for (const int j : {0, 6}) {
      ASSERT_EQ(truth["joints"][j]["name"].as<std::string>(), result["joints"][j]["name"].as<std::string>());
      EXPECT_EQ(result["joints"][j]["fixed_by"].as<std::string>(), "the base frame (the rig's) and joints that moved after it") << j;
      EXPECT_LT(std::abs(result["joints"][j]["offset"].as<double>() - truth["joints"][j]["offset"].as<double>()),
                3 * result["joints"][j]["offset_stddev"].as<double>()) << j;
    }
    const auto [worst_t, worst_r] = worstOnItsLinkAtStillPoses(folder, "head_camera");
    const Eigen::Isometry3d post = yamlPose(result["sensors"][0]), true_post = yamlPose(truth["sensors"]["arm_camera"]["pose"]);
    const double post_t = (post.translation() - true_post.translation()).norm(), post_r = vocal::rotationAngle(true_post.inverse() * post);
    std::printf("one graph, no pose given, head and arm: the head camera in arm_base within %.2f mm / %.2f mrad at the still poses, the post "
                "camera %.2f mm / %.2f mrad; the first joints %+.2f / %+.2f mrad (truth %+.2f / %+.2f)\n", 1000 * worst_t, 1000 * worst_r,
                1000 * post_t, 1000 * post_r, 1000 * result["joints"][0]["offset"].as<double>(), 1000 * result["joints"][6]["offset"].as<double>(),
                1000 * pan, 1000 * truth["joints"][6]["offset"].as<double>());
    EXPECT_LT(worst_t, 0.002);
    EXPECT_LT(worst_r, 0.002);
    EXPECT_LT(post_t, 0.002);
    EXPECT_LT(post_r, 0.002);
  }
}

// The camera and a 2D laser on the tool over a board lying still on the table (simulate_calibration_session
// --eye-in-hand --beside), the tool from the arm's joints or from tf, through calibrate_rig --one-graph: the
// base the rig frame, the first joint held and said why, the board's parent the base; each sensor as the
// board sees it at the still poses (a camera: the print on it) within 0.1 mm / 0.1 mrad (the camera) and
// 1 mm / 1 mrad (the laser, 3-4 mm / 6-7 mrad off in both) of where the arm's own graph puts it, the camera
// within 1 mm / 1 mrad of the truth.
TEST(JointedCalibration, SensorsOnTheToolOverAStillBoardThroughTheOneGraph) {
  for (const std::string tool : {"joints", "tf"}) {
    SCOPED_TRACE(tool);
    const std::string folder = vocal_test::makeTempFolder("cli_one_graph_in_hand_" + tool);
    const std::string arm_folder = folder + "/arm";
    std::filesystem::create_directories(arm_folder);
    ASSERT_EQ(vocal_test::runTool("simulate_calibration_session " + folder + " --eye-in-hand --beside --poses 12" +
                                  (tool == "joints" ? " --arm" : "")).exit_code, 0);
    const std::string command = "calibrate_rig " + folder + "/rig.yaml " + folder + "/session.bag --quiet --output-dir ";
    const vocal_test::RunResult r = vocal_test::runTool(command + folder + " --one-graph");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    ASSERT_EQ(vocal_test::runTool(command + arm_folder).exit_code, 0);
    for (const char* file : {"/rig.yaml", "/ground_truth.yaml"}) std::filesystem::copy_file(folder + file, arm_folder + file);  // beside its result
    EXPECT_NE(r.output.find("one graph: the board lying still in arm_base (the rig frame), the sensors on arm_tool (from " +
                            std::string(tool == "joints" ? "the arm's joints" : "tf") + "), 12 still poses"),
              std::string::npos) << r.output;
    const YAML::Node result = YAML::LoadFile(folder + "/calibration.yaml");
    EXPECT_EQ(result["board"]["parent"].as<std::string>(), "arm_base");
    ASSERT_EQ(result["sensors"].size(), 2u);
    for (const YAML::Node& sensor : result["sensors"]) EXPECT_EQ(sensor["parent"].as<std::string>(), "arm_tool");
    if (tool == "joints") {
      EXPECT_NE(r.output.find("  shoulder_pan_joint      +0.00 mrad +- 0.00, moved 0.842 rad, held: the first joint from the base, whose frame "
                              "is the rig's: the board lying still in it takes up its offset"),
                std::string::npos) << r.output;
    }
    // From tf the base is where tf says (the arm calibrated): each mount against its truth on the tool.
    const auto errorOf = [&](const std::string& in, const std::string& name) -> std::pair<double, double> {
      if (tool == "joints") return worstOnItsLinkAtStillPoses(in, name, true);
      for (const YAML::Node& sensor : YAML::LoadFile(in + "/calibration.yaml")["sensors"]) {
        if (sensor["name"].as<std::string>() != name) continue;
        const Eigen::Isometry3d error = yamlPose(YAML::LoadFile(folder + "/ground_truth.yaml")["sensors"][name]["pose"]).inverse() * yamlPose(sensor);
        return {error.translation().norm(), vocal::rotationAngle(error)};
      }
      ADD_FAILURE() << "no sensor " << name << " in " << in;
      return {1.0, 1.0};
    };
    const auto [camera_t, camera_r] = errorOf(folder, "arm_camera");
    const auto [laser_t, laser_r] = errorOf(folder, "tool_laser");
    const auto [arm_camera_t, arm_camera_r] = errorOf(arm_folder, "arm_camera");
    const auto [arm_laser_t, arm_laser_r] = errorOf(arm_folder, "tool_laser");
    std::printf("one graph, eye-in-hand from %s: the camera from the board %.2f mm / %.2f mrad off the truth (the arm's graph %.2f / %.2f), the "
                "laser %.2f / %.2f (%.2f / %.2f)\n", tool.c_str(), 1000 * camera_t, 1000 * camera_r, 1000 * arm_camera_t, 1000 * arm_camera_r,
                1000 * laser_t, 1000 * laser_r, 1000 * arm_laser_t, 1000 * arm_laser_r);
    EXPECT_LT(camera_t, 0.001);
    EXPECT_LT(camera_r, 0.001);
    EXPECT_LT(camera_t, arm_camera_t + 0.0001);
    EXPECT_LT(camera_r, arm_camera_r + 0.0001);
    EXPECT_LT(laser_t, arm_laser_t + 0.001);
    EXPECT_LT(laser_r, arm_laser_r + 0.001);
  }
}
