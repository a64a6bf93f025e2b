// The jackknife over target poses against simulated rigs whose errors the solver's covariance does or
// does not see.

#include <gtest/gtest.h>

#include "test_support.h"

#include <iostream>
#include <random>

#include "vocal/calibration/solver/pose_jackknife.h"
#include "vocal/core/se3.h"
#include "vocal/simulation/rig_simulator.h"

namespace {
struct Rig {
  std::vector<vocal::SensorSpec> specs;
  std::vector<vocal::TargetObservation> observations;
  vocal::CalibrationOptions options;
  Eigen::Isometry3d lidar_truth;
};

// An RGB-D sensor (the reference) and a lidar, `poses` target poses, 2 mm noise. With `pose_error`,
// each lidar observation is also tilted about its centre by up to this many radians and shifted along
// its normal by up to 5 cm x pose_error / 0.02, all its points together: what a lidar's ring biases do
// to the plane of each pose, differently at each.
Rig lidarRig(int poses, double pose_error) {
  vocal::RigSimulationOptions options;
  options.target_poses = poses;
  options.range_noise = 0.002;
  options.seed = 4;
  const vocal::SimulatedRig simulated = vocal::simulateRig(vocal::exampleRig(1, 1), options);
  Rig rig;
  for (const auto& s : simulated.sensors) rig.specs.push_back(s.spec);
  rig.options.reference_pose = simulated.sensors[0].reference_from_sensor;
  rig.lidar_truth = simulated.sensors[1].reference_from_sensor;
  rig.observations = simulated.observations;
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (vocal::TargetObservation& o : rig.observations) {
    if (o.sensor != 1 || pose_error == 0.0) continue;
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (const Eigen::Vector3d& p : o.points) centre += p / o.points.size();
    const Eigen::Matrix3d tilt = Eigen::AngleAxisd(pose_error * unit(rng), Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).normalized()).toRotationMatrix();
    const Eigen::Vector3d shift = 2.5 * pose_error * unit(rng) * Eigen::Vector3d::UnitX();
    for (Eigen::Vector3d& p : o.points) p = centre + tilt * (p - centre) + shift;
  }
  return rig;
}
}  // namespace

// Each pose's lidar plane wrong by up to 0.02 rad, its points' noise small: the solver's covariance
// (every point independent) reports a fraction of a milliradian, the rotation is off by several, and
// the spread between poses says so.
TEST(PoseJackknife, SeesErrorsThatDifferFromPoseToPose) {
  const Rig rig = lidarRig(15, 0.02);
  const vocal::CalibrationResult full = vocal::calibrateRig(rig.specs, rig.observations, rig.options);
  const vocal::PoseJackknife jackknife = vocal::jackknifeOverPoses(rig.specs, rig.observations, rig.options, full);
  EXPECT_EQ(jackknife.poses, 15);
  EXPECT_EQ(jackknife.solved, 15);
  const double error = vocal::rotationAngle(rig.lidar_truth.inverse() * full.sensors[1].reference_from_sensor);
  const double solver = full.sensors[1].standard_deviation.tail<3>().norm();
  const double spread = jackknife.standard_deviation[1].tail<3>().norm();
  std::cout << "rotation error " << error * 1000 << " mrad; solver's sigma " << solver * 1000 << ", jackknife " << spread * 1000 << "\n";
  EXPECT_GT(error, 3.0 * solver);   // the solver's sigma does not cover the error
  EXPECT_LT(error, 3.0 * spread);   // the jackknife's does
  EXPECT_EQ(jackknife.standard_deviation[0], vocal::Vector6d::Zero());  // the reference stays fixed
  // Over the default 1 cm / 10 mrad: the lidar (and only it) is reported uncertain.
  const std::vector<std::string> uncertain = vocal::spreadOverTolerance(jackknife, rig.specs, vocal::SpreadTolerance());
  ASSERT_EQ(uncertain.size(), 1u);
  EXPECT_EQ(uncertain[0].rfind("sensor '" + rig.specs[1].name + "' moves ", 0), 0u) << uncertain[0];
  // Within a tolerance wider than its spread, nothing.
  EXPECT_TRUE(vocal::spreadOverTolerance(jackknife, rig.specs, {1.0, 2.0 * spread}).empty());
}

// Only independent noise on every point: the spread between poses is what the covariance says.
TEST(PoseJackknife, AgreesWithTheSolverWhenPointsAreIndependent) {
  const Rig rig = lidarRig(15, 0.0);
  const vocal::CalibrationResult full = vocal::calibrateRig(rig.specs, rig.observations, rig.options);
  const vocal::PoseJackknife jackknife = vocal::jackknifeOverPoses(rig.specs, rig.observations, rig.options, full);
  for (const auto& [from, name] : {std::pair<int, const char*>{0, "translation"}, {3, "rotation"}}) {
    const double solver = full.sensors[1].standard_deviation.segment<3>(from).norm();
    const double spread = jackknife.standard_deviation[1].segment<3>(from).norm();
    std::cout << name << ": solver's sigma " << solver * 1000 << ", jackknife " << spread * 1000 << " (mm or mrad)\n";
    EXPECT_GT(spread, solver / 3.0) << name;
    EXPECT_LT(spread, solver * 3.0) << name;
  }
  EXPECT_TRUE(vocal::spreadOverTolerance(jackknife, rig.specs, vocal::SpreadTolerance()).empty());
}

// The line a user reads: the spread, the tolerance, the axes it is largest along and about, and the
// likely cause or the poses that would pin this type of sensor down.
TEST(PoseJackknife, NamesTheUncertainSensorItsAxesAndTheLikelyCause) {
  vocal::PoseJackknife jackknife;
  jackknife.standard_deviation = {vocal::Vector6d::Zero(), (vocal::Vector6d() << 0.003, 0.004, 0.012, 0.001, 0.008, 0.002).finished(),
                                  vocal::Vector6d::Constant(0.001)};
  std::vector<vocal::SensorSpec> specs(3);
  specs[0].name = "camera";
  specs[1].name = "velodyne";
  specs[1].type = vocal::SensorType::kLidar3d;
  specs[2].name = "laser";
  specs[2].type = vocal::SensorType::kLaser2d;
  const std::vector<std::string> uncertain = vocal::spreadOverTolerance(jackknife, specs, vocal::SpreadTolerance());
  ASSERT_EQ(uncertain.size(), 1u);
  EXPECT_EQ(uncertain[0],
            "sensor 'velodyne' moves 13.0 mm / 8.3 mrad between re-solves without one pose (tolerance 10.0 mm / 10.0 mrad), "
            "most along the rig's z and about its y: its result may be off by as much; a 3D lidar's per-ring range biases "
            "(its intrinsic calibration, the driver's calibration file) tilt every plane it sees alike, which moves its height "
            "and pitch together and no choice of poses undoes: calibrate where it sees walls and floor around it, which its "
            "ring offsets are estimated from");
  // A tighter rotation tolerance takes the laser in too, with its own advice.
  const std::vector<std::string> tight = vocal::spreadOverTolerance(jackknife, specs, {0.01, 0.0015});
  ASSERT_EQ(tight.size(), 2u);
  EXPECT_NE(tight[1].find("sensor 'laser' moves 1.7 mm / 1.7 mrad"), std::string::npos) << tight[1];
  EXPECT_NE(tight[1].find("where its one line crosses tilted targets"), std::string::npos) << tight[1];
}

TEST(PoseJackknife, NeedsThreeReSolves) {
  const Rig rig = lidarRig(3, 0.0);
  const vocal::CalibrationResult full = vocal::calibrateRig(rig.specs, rig.observations, rig.options);
  EXPECT_EQ(vocal_test::inputErrorOf([&] { vocal::jackknifeOverPoses(rig.specs, rig.observations, rig.options, full); }),
            "pose jackknife: only 0 of 3 re-solves without one target pose succeeded; at least 3 are needed");
}
