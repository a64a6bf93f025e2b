// Per-sensor trust and isolation (sensor_trust.h) on simulated rigs carrying one fault each: the faulty
// sensor is named with its cause and taken out of the graph, and the others stay where they belong.

#include <gtest/gtest.h>

#include "test_support.h"

#include <random>

#include "vocal/calibration/extraction/pattern_observation.h"
#include "vocal/calibration/solver/pose_jackknife.h"
#include "vocal/calibration/solver/sensor_trust.h"
#include "vocal/core/se3.h"
#include "vocal/simulation/rig_simulator.h"

namespace {
enum { kRgbd, kLidar, kLaser, kCamera0, kCamera1 };

struct Rig {
  vocal::SimulatedRig simulated;
  vocal::RigSimulationOptions simulation;
  std::vector<vocal::SensorSpec> specs;
  vocal::CalibrationOptions options;
};

// An RGB-D reference, a 16-ring lidar, a 2D laser and two cameras, 20 board poses, 2 mm range and
// 0.3 px corner noise: what every fault below spoils one sensor of.
Rig healthyRig() {
  Rig rig;
  rig.simulation.target_poses = 20;
  rig.simulation.range_noise = 0.002;
  rig.simulation.pixel_noise = 0.3;
  rig.simulation.seed = 5;
  rig.simulated = vocal::simulateRig(vocal::exampleRig(1, 1, 1, 2), rig.simulation);
  for (const vocal::SimulatedSensor& s : rig.simulated.sensors) rig.specs.push_back(s.spec);
  rig.options.reference_pose = rig.simulated.sensors[kRgbd].reference_from_sensor;
  return rig;
}

// Sensor `sensor` observed again at every pose from where `placement(pose)` puts it.
void replaceObservations(Rig* rig, int sensor, const std::function<Eigen::Isometry3d(int)>& placement) {
  std::vector<vocal::TargetObservation> kept;
  for (const vocal::TargetObservation& o : rig->simulated.observations)
    if (o.sensor != sensor) kept.push_back(o);
  std::mt19937 rng(11);
  for (std::size_t k = 0; k < rig->simulated.reference_from_target.size(); ++k) {
    vocal::SimulatedSensor moved = rig->simulated.sensors[sensor];
    moved.reference_from_sensor = placement(static_cast<int>(k));
    vocal::TargetObservation o = vocal::observeTarget(moved, rig->simulated.reference_from_target[k], 0.5 * rig->simulation.target_width,
                                                      0.5 * rig->simulation.target_height, rig->simulation, &rng);
    if (o.points.empty()) continue;
    o.sensor = sensor;
    o.target_pose = static_cast<int>(k);
    kept.push_back(o);
  }
  rig->simulated.observations = kept;
}

vocal::CalibrationResult calibrate(const Rig& rig) {
  return vocal::calibrateRigWithTrust(rig.specs, rig.simulated.observations, rig.options);
}

// Metres and radians between a sensor's result and its true mount.
std::pair<double, double> errorOf(const Rig& rig, const vocal::CalibrationResult& result, int sensor) {
  const Eigen::Isometry3d e = rig.simulated.sensors[sensor].reference_from_sensor.inverse() * result.sensors[sensor].reference_from_sensor;
  return {e.translation().norm(), vocal::rotationAngle(e)};
}

void expectOthersWithin1cm(const Rig& rig, const vocal::CalibrationResult& result, int faulty) {
  for (int s = 1; s < static_cast<int>(rig.specs.size()); ++s) {
    if (s == faulty) continue;
    const auto [t, r] = errorOf(rig, result, s);
    EXPECT_LT(t, 0.01) << rig.specs[s].name;
    EXPECT_LT(r, 0.01) << rig.specs[s].name;
    EXPECT_EQ(result.sensors[s].distrust, "") << rig.specs[s].name;
    EXPECT_FALSE(result.sensors[s].isolated) << rig.specs[s].name;
  }
}

// The observations of every sensor but `sensor`.
std::vector<vocal::TargetObservation> withoutSensor(const std::vector<vocal::TargetObservation>& observations, int sensor) {
  std::vector<vocal::TargetObservation> kept;
  for (const vocal::TargetObservation& o : observations)
    if (o.sensor != sensor) kept.push_back(o);
  return kept;
}

// `sensor` named (its distrust starting with `said`) and kept out of the graph, the others calibrated
// within 1 cm as if it were not there, and every jackknife re-solve succeeding without it.
vocal::CalibrationResult expectLeftOutAndTheRestCalibrated(const Rig& rig, int sensor, const std::string& said) {
  const vocal::CalibrationResult result = calibrate(rig);
  EXPECT_TRUE(result.trusted) << result.failure;
  if (!result.trusted) return result;
  EXPECT_TRUE(result.sensors[sensor].isolated);
  EXPECT_EQ(result.sensors[sensor].distrust.rfind(said, 0), 0u) << result.sensors[sensor].distrust;
  expectOthersWithin1cm(rig, result, sensor);
  const vocal::PoseJackknife spread = vocal::jackknifeOverPoses(rig.specs, rig.simulated.observations, rig.options, result);
  EXPECT_EQ(spread.solved, spread.poses);
  return result;
}

// A pan-tilt head the rig does not describe: panned by up to `amount` and tilted by half that about a
// pivot 8 cm behind the sensor, anew at each pose.
Eigen::Isometry3d onPanTiltHead(const Eigen::Isometry3d& mount, int pose, double amount) {
  std::mt19937 rng(100 + pose);
  std::uniform_real_distribution<double> turn(-amount, amount);
  const Eigen::Vector3d pivot(0.0, 0.0, -0.08);
  Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
  motion.linear() = (Eigen::AngleAxisd(turn(rng), Eigen::Vector3d::UnitY()) * Eigen::AngleAxisd(0.5 * turn(rng), Eigen::Vector3d::UnitX())).toRotationMatrix();
  motion.translation() = pivot - motion.linear() * pivot;
  return mount * motion;
}
}  // namespace

// Without a fault nothing is flagged or taken out, and every sensor's board agrees with the others' to
// well under the thresholds: the check costs a healthy session nothing.
TEST(SensorTrust, AHealthyRigHasEverySensorTrustedAndInTheGraph) {
  const Rig rig = healthyRig();
  const vocal::CalibrationResult result = calibrate(rig);
  ASSERT_TRUE(result.trusted) << result.failure;
  for (int s = 1; s < 5; ++s) {
    EXPECT_EQ(result.sensors[s].distrust, "") << rig.specs[s].name;
    EXPECT_FALSE(result.sensors[s].isolated);
    EXPECT_GT(result.sensors[s].compared_poses, 10) << rig.specs[s].name;
    EXPECT_LT(vocal::disagreementRatio(result.sensors[s], rig.options.trust), 0.5) << rig.specs[s].name;
  }
  expectOthersWithin1cm(rig, result, -1);
}

// The first session: a camera on a head that moved between poses dragged the fixed sensors.
// Now it is named as moving, taken out, and the rest solved as if it were not there.
TEST(SensorTrust, ACameraOnAnUndescribedJointIsIsolatedAndTheOthersHold) {
  Rig rig = healthyRig();
  const Eigen::Isometry3d mount = rig.simulated.sensors[kCamera0].reference_from_sensor;
  replaceObservations(&rig, kCamera0, [&](int pose) { return onPanTiltHead(mount, pose, 0.3); });
  const vocal::CalibrationResult result = calibrate(rig);
  ASSERT_TRUE(result.trusted) << result.failure;
  EXPECT_TRUE(result.sensors[kCamera0].isolated);
  EXPECT_NE(result.sensors[kCamera0].distrust.find("it moves between poses (is it on a joint"), std::string::npos)
      << result.sensors[kCamera0].distrust;
  EXPECT_NE(result.sensors[kCamera0].distrust.find("taken out of the graph, the others solved without it"), std::string::npos);
  expectOthersWithin1cm(rig, result, kCamera0);
  // The pose jackknife re-solves the same graph (the camera kept out) and so succeeds.
  const vocal::PoseJackknife spread = vocal::jackknifeOverPoses(rig.specs, rig.simulated.observations, rig.options, result);
  EXPECT_EQ(spread.solved, spread.poses);
}

// Isolation off: the moving camera is still named, and said to be in the graph.
TEST(SensorTrust, WithIsolationOffTheSensorIsNamedAndKept) {
  Rig rig = healthyRig();
  const Eigen::Isometry3d mount = rig.simulated.sensors[kCamera0].reference_from_sensor;
  replaceObservations(&rig, kCamera0, [&](int pose) { return onPanTiltHead(mount, pose, 0.3); });
  rig.options.trust.isolate = false;
  const vocal::CalibrationResult result = calibrate(rig);
  EXPECT_FALSE(result.sensors[kCamera0].isolated);
  EXPECT_NE(result.sensors[kCamera0].distrust.find("; kept in the graph (isolation is off)"), std::string::npos)
      << result.sensors[kCamera0].distrust;
}

// A lidar knocked 3 cm / 30 mrad at pose 10 of 20: named with the pose it moved at.
TEST(SensorTrust, ABumpedLidarIsNamedWithThePoseItMovedAt) {
  Rig rig = healthyRig();
  const Eigen::Isometry3d mount = rig.simulated.sensors[kLidar].reference_from_sensor;
  Eigen::Isometry3d bump = Eigen::Isometry3d::Identity();
  bump.linear() = Eigen::AngleAxisd(0.03, Eigen::Vector3d(1.0, 1.0, 0.0).normalized()).toRotationMatrix();
  bump.translation() = 0.03 * Eigen::Vector3d(1.0, -1.0, 1.0).normalized();
  replaceObservations(&rig, kLidar, [&](int pose) { return pose >= 10 ? mount * bump : mount; });
  const vocal::CalibrationResult result = calibrate(rig);
  EXPECT_TRUE(result.sensors[kLidar].isolated);
  EXPECT_NE(result.sensors[kLidar].distrust.find("its placement from the still poses before pose 10 and from those after differ by "), std::string::npos)
      << result.sensors[kLidar].distrust;
  expectOthersWithin1cm(rig, result, kLidar);
}

// A camera whose camera_info gives a focal length 5 % long sees the board 5 % farther at the right
// angle. Its translation along its view takes up most of it (the board stands 1.3-1.9 m away), so only
// the share that grows with range is left to see: named as a scale error, and taken out.
TEST(SensorTrust, ACameraWithAWrongFocalLengthIsNamedAsAScaleError) {
  Rig rig = healthyRig();
  for (vocal::TargetObservation& o : rig.simulated.observations) {
    if (o.sensor != kCamera1) continue;
    for (Eigen::Vector3d& p : o.points) p *= 1.05;
    for (vocal::PlaneMeasurement& m : o.plane_measurements) m.sensor_from_pattern.translation() *= 1.05;
  }
  const vocal::CalibrationResult result = calibrate(rig);
  EXPECT_TRUE(result.sensors[kCamera1].isolated);
  // Part of the 4.8 % goes into the camera's rotation and translation; what is left grows with range.
  EXPECT_GT(result.sensors[kCamera1].disagreement_scale, 0.02);
  EXPECT_LT(result.sensors[kCamera1].disagreement_scale, 0.06);
  EXPECT_NE(result.sensors[kCamera1].distrust.find("% too long (+-"), std::string::npos) << result.sensors[kCamera1].distrust;
  EXPECT_NE(result.sensors[kCamera1].distrust.find("a scale error - check its camera_info (focal length) and the target's square size"),
            std::string::npos)
      << result.sensors[kCamera1].distrust;
  expectOthersWithin1cm(rig, result, kCamera1);
}

// The same camera_info 5 % long, the camera's views fitted from its corners with it, and the cameras'
// intrinsics refined (CalibrationOptions::intrinsics): the corners' perspective and the other sensors'
// boards put the focal length back within a pixel, and the camera is right and trusted.
TEST(SensorTrust, ACameraWithAWrongFocalLengthIsRightWithItsIntrinsicsRefined) {
  Rig rig = healthyRig();
  const vocal::PinholeCamera truth = vocal::defaultKinectCamera();
  vocal::PinholeCamera given = truth;
  given.fx *= 1.05, given.fy *= 1.05;
  std::mt19937 rng(12);
  std::normal_distribution<double> pixel_noise(0.0, rig.simulation.pixel_noise);
  int refitted = 0;
  for (vocal::TargetObservation& o : rig.simulated.observations) {
    if (o.sensor != kCamera1) continue;
    const Eigen::Isometry3d camera_from_board =
        rig.simulated.sensors[kCamera1].reference_from_sensor.inverse() * rig.simulated.reference_from_target[o.target_pose];
    std::vector<Eigen::Vector2d> corners;
    for (const Eigen::Vector3d& corner : rig.simulation.pattern.corners())
      corners.push_back(truth.project(camera_from_board * corner) + Eigen::Vector2d(pixel_noise(rng), pixel_noise(rng)));
    const vocal::PatternObservation seen = vocal::observePattern(corners, rig.simulation.pattern, given, "camera1");
    o.points = seen.points;
    o.plane_measurements = {seen.plane};
    ++refitted;
  }
  ASSERT_GE(refitted, 10);
  rig.options.intrinsics.enabled = true;
  const vocal::CalibrationResult result = calibrate(rig);
  const vocal::SensorCalibration& camera = result.sensors[kCamera1];
  ASSERT_TRUE(camera.intrinsicsRefined());
  EXPECT_NEAR(camera.given_intrinsics[0], given.fx, 1e-9);
  std::cout << "camera1 fx " << camera.given_intrinsics[0] << " -> " << camera.refined_intrinsics[0] << " (sigma " << camera.intrinsics_sigma[0]
            << "), truth " << truth.fx << "\n";
  EXPECT_NEAR(camera.refined_intrinsics[0], truth.fx, 1.0);
  EXPECT_NEAR(camera.refined_intrinsics[1], truth.fy, 1.0);
  EXPECT_EQ(camera.refined_intrinsics[2], given.cx);  // the principal point held (IntrinsicsRefinementOptions::principal_point)
  EXPECT_GT(camera.intrinsics_sigma[0], 0.0);
  EXPECT_FALSE(camera.isolated);
  EXPECT_EQ(camera.distrust, "");
  const auto [t, r] = errorOf(rig, result, kCamera1);
  std::cout << "camera1 " << 1000 * t << " mm / " << 1000 * r << " mrad from the truth\n";
  EXPECT_LT(t, 0.005);
  EXPECT_LT(r, 0.005);
  expectOthersWithin1cm(rig, result, kCamera1);
  // The cameras with the right camera_info move less than a pixel.
  EXPECT_NEAR(result.sensors[kCamera0].refined_intrinsics[0], truth.fx, 1.0);
}

// The reference is the frame everything is expressed in: it cannot be the one kept out.
TEST(SensorTrust, TheReferenceCannotBeKeptOutOfTheGraph) {
  Rig rig = healthyRig();
  rig.options.isolated_sensors = {kRgbd};
  EXPECT_EQ(vocal_test::inputErrorOf([&] { vocal::calibrateRig(rig.specs, rig.simulated.observations, rig.options); }),
            "calibration: the reference sensor 'rgbd0' cannot be kept out of the graph");
  rig.options.isolated_sensors = {7};
  EXPECT_EQ(vocal_test::inputErrorOf([&] { vocal::calibrateRig(rig.specs, rig.simulated.observations, rig.options); }),
            "calibration: isolated sensor index 7 is not one of the 5 sensors");
}

// A sensor that shares only two still poses with the others (a clock far off theirs, a camera that saw
// the board twice): it cannot be placed (three planes fix a pose), so it is named and left out, the
// others calibrated without it - the whole rig is not refused - and the jackknife re-solves them all.
TEST(SensorTrust, ASensorWithTooFewSharedPosesIsNamedAndTheRestCalibrated) {
  Rig rig = healthyRig();
  std::vector<vocal::TargetObservation> kept;
  int camera_views = 0;
  for (const vocal::TargetObservation& o : rig.simulated.observations)
    if (o.sensor != kCamera1 || camera_views++ < 2) kept.push_back(o);
  rig.simulated.observations = kept;
  expectLeftOutAndTheRestCalibrated(rig, kCamera1, "it shares 2 still poses at most with another sensor, and 3 are needed to place it, "
                                                   "so it is not calibrated");
}

// A sensor whose views cannot place it (a lidar that saw the board only at four poses, where it stood
// turned the same way): named with why, the others calibrated without it - before, the whole rig was
// refused with "the target planes are too close to parallel".
TEST(SensorTrust, ASensorWhoseViewsCannotPlaceItIsNamedAndTheRestCalibrated) {
  Rig rig = healthyRig();
  std::vector<vocal::TargetObservation> kept = withoutSensor(rig.simulated.observations, kLidar);
  // Four more poses, the board moved but not turned from the first pose, seen by the reference and the lidar.
  std::mt19937 rng(13);
  const int first_extra = static_cast<int>(rig.simulated.reference_from_target.size());
  for (int k = 0; k < 4; ++k) {
    Eigen::Isometry3d board = rig.simulated.reference_from_target[0];
    board.translation() += Eigen::Vector3d(0.1 * k, 0.15 * (k % 2), -0.1 * (k / 2));
    for (const int sensor : {kRgbd, kLidar}) {
      vocal::TargetObservation o = vocal::observeTarget(rig.simulated.sensors[sensor], board, 0.5 * rig.simulation.target_width,
                                                        0.5 * rig.simulation.target_height, rig.simulation, &rng);
      ASSERT_FALSE(o.points.empty());
      o.sensor = sensor;
      o.target_pose = first_extra + k;
      kept.push_back(o);
    }
  }
  rig.simulated.observations = kept;
  // The graph alone cannot place it.
  const std::string refusal = vocal_test::inputErrorOf([&] { vocal::calibrateRig(rig.specs, rig.simulated.observations, rig.options); });
  EXPECT_EQ(refusal.rfind("calibration of 'lidar0' against 'rgbd0': the target planes are too close to parallel", 0), 0u) << refusal;
  expectLeftOutAndTheRestCalibrated(rig, kLidar, "its views of the board cannot place it (calibration of 'lidar0' against 'rgbd0': the "
                                                 "target planes are too close to parallel");
}

// A sensor that never saw the target (a wrong topic, a crop box beside the board): the others are
// calibrated without it, and it is named rather than the whole calibration refused.
TEST(SensorTrust, ASensorThatNeverSawTheTargetIsNamedAndTheRestCalibrated) {
  Rig rig = healthyRig();
  rig.simulated.observations = withoutSensor(rig.simulated.observations, kCamera1);
  const std::string said =
      "it never saw the target in a still pose, so it is not calibrated (its pose in the result is a placeholder); the others were "
      "solved without it";
  EXPECT_EQ(expectLeftOutAndTheRestCalibrated(rig, kCamera1, said).sensors[kCamera1].distrust, said);
  // The reference itself cannot be left out.
  const std::vector<vocal::TargetObservation> no_reference = withoutSensor(rig.simulated.observations, kRgbd);
  EXPECT_EQ(vocal_test::inputErrorOf([&] { vocal::calibrateRigWithTrust(rig.specs, no_reference, rig.options); }),
            "calibration: sensor 'rgbd0' never sees the target: its pose is unconstrained in all 6 DoF");
}
