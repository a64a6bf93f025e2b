// MSG-Cal with a sensor behind joints (a camera on a pan-tilt head) in the same graph as rigid sensors:
// joint offsets and mounts against the truth of simulated heads.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "test_support.h"

#include "vocal/calibration/solver/graph_calibration.h"
#include "vocal/core/errors.h"
#include "vocal/core/se3.h"
#include "vocal/simulation/rig_simulator.h"
#include "vocal/simulation/simulated_pan_tilt.h"

namespace {
// The rig of the simulator with its camera on a pan-tilt head: rgbd0 (the reference) and lidar0 fixed,
// camera0 on the head's tilt link, every pose's views as each sensor sees the board.
struct PanTiltSession {
  std::vector<vocal::SensorSpec> specs;
  std::vector<vocal::SimulatedSensor> fixed;  // the truth of the rigid ones
  vocal::SimulatedPanTilt head;
  std::vector<vocal::TargetObservation> observations;
  vocal::CalibrationOptions options;
};

constexpr int kCamera = 2;

PanTiltSession panTiltSession(std::uint32_t seed, double pixel_noise = 0.2, double backlash = 0.001, double encoder_counts = 4096.0) {
  PanTiltSession session;
  session.fixed = vocal::exampleRig(1, 1, 0, 1);
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
  session.head = vocal::simulatePanTilt(boards.reference_from_target, mount, head_options);
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> direction(0, 1);
  for (const vocal::SimulatedSensor& s : session.fixed) session.specs.push_back(s.spec);
  for (int k = 0; k < simulation.target_poses; ++k) {
    const Eigen::Isometry3d& board = boards.reference_from_target[k];
    for (int s = 0; s < 3; ++s) {
      vocal::SimulatedSensor placed = session.fixed[s];
      const std::vector<double>& angles = session.head.angles[k];
      if (s == kCamera) placed.reference_from_sensor = session.head.baseFromSensor(angles);
      vocal::TargetObservation o = vocal::observeTarget(placed, board, 0.45, 0.35, simulation, &rng);
      if (o.points.empty()) continue;
      o.sensor = s;
      o.target_pose = k;
      if (s == kCamera) o.joint_positions = session.head.reported(angles, {2 * direction(rng) - 1, 2 * direction(rng) - 1});
      session.observations.push_back(o);
    }
  }
  session.options.reference_pose = session.fixed[0].reference_from_sensor;
  session.options.mounts.joints = session.head.joints;
  for (vocal::JointDescription& joint : session.options.mounts.joints) joint.offset = 0.0;  // unknown
  session.options.mounts.chains = {{}, {}, session.head.chain};
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
