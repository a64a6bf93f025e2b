// The IMU: its files, the gyro's preintegration against closed forms, its bias estimated from what vision
// measures, and its rotation prior in the odometry (every backend, and better rotation than without).

#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "test_support.h"
#include "vocal/core/errors.h"
#include "vocal/core/imu_samples.h"
#include "vocal/core/se3.h"
#include "vocal/core/trajectory_evaluation.h"
#include "vocal/odometry/gravity_correction.h"
#include "vocal/odometry/gyro_preintegration.h"
#include "vocal/odometry/gyro_rotation_prior.h"
#include "vocal/odometry/icp_dvo_odometry.h"
#include "vocal/odometry/odometry_backend.h"
#include "vocal/simulation/blank_wall_visit.h"
#include "vocal/simulation/simulated_imu.h"
#include "vocal/simulation/synthetic_sequence.h"

namespace {
Eigen::Matrix3d exp3(const Eigen::Vector3d& w) {
  return w.norm() < 1e-15 ? Eigen::Matrix3d::Identity() : Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
}
double angleBetween(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) { return Eigen::AngleAxisd(a.transpose() * b).angle(); }

std::vector<vocal::ImuSample> constantRate(const Eigen::Vector3d& rate, double rate_hz, double seconds) {
  std::vector<vocal::ImuSample> samples;
  for (int i = 0; i * (1.0 / rate_hz) <= seconds; ++i) samples.push_back({i / rate_hz, rate, Eigen::Vector3d(0, 0, 9.8)});
  return samples;
}

std::string writeText(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

// A path that turns on all three axes at up to ~1 rad/s and moves, 30 Hz.
vocal::Trajectory turningPath(int poses, double rate_hz) {
  vocal::Trajectory path;
  for (int i = 0; i < poses; ++i) {
    const double t = i / rate_hz;
    vocal::StampedPose p;
    p.stamp = 100.0 + t;
    p.pose.linear() = vocal::rotationFromRollPitchYaw(0.3 * std::sin(1.1 * t), 0.4 * std::sin(0.7 * t + 1.0), 0.8 * std::sin(0.5 * t));
    p.pose.translation() = Eigen::Vector3d(0.3 * std::sin(0.6 * t), 0.2 * std::cos(0.9 * t), 0.1 * t);
    path.push_back(p);
  }
  return path;
}
}  // namespace

TEST(GyroPreintegration, AConstantRateTurnsByRateTimesSpanBetweenSamples) {
  const Eigen::Vector3d rate(0.3, -1.2, 0.5), bias(0.01, -0.02, 0.005);
  std::vector<vocal::ImuSample> samples = constantRate(rate + bias, 200.0, 1.0);
  // t0 and t1 between samples: the ends are interpolated.
  const vocal::GyroDelta delta = vocal::preintegrateGyro(samples, 0.1234, 0.6789, bias, 2.4e-4);
  EXPECT_TRUE(delta.complete);
  EXPECT_LT(angleBetween(delta.rotation, exp3(rate * (0.6789 - 0.1234))), 1e-12);
  EXPECT_EQ(delta.samples, 111);  // 0.125 ... 0.675 s
}

TEST(GyroPreintegration, ARampedRateAboutOneAxisIntegratesExactly) {
  // w(t) = (a + c t) about a fixed axis: the angle is a (t1 - t0) + c (t1^2 - t0^2) / 2; linear
  // interpolation between samples and the trapezoid are exact for it.
  const Eigen::Vector3d axis = Eigen::Vector3d(1, 2, -1).normalized();
  std::vector<vocal::ImuSample> samples;
  for (int i = 0; i <= 100; ++i) samples.push_back({0.01 * i, (0.2 + 1.5 * 0.01 * i) * axis, Eigen::Vector3d::Zero()});
  const double t0 = 0.105, t1 = 0.873;
  const vocal::GyroDelta delta = vocal::preintegrateGyro(samples, t0, t1, Eigen::Vector3d::Zero(), 0.0);
  const double angle = 0.2 * (t1 - t0) + 1.5 * (t1 * t1 - t0 * t0) / 2.0;
  EXPECT_LT(angleBetween(delta.rotation, exp3(angle * axis)), 1e-12);
}

TEST(GyroPreintegration, CovarianceGrowsWithTheNoiseDensitySquaredTimesTheSpan) {
  const vocal::GyroDelta delta = vocal::preintegrateGyro(constantRate(Eigen::Vector3d::Zero(), 200.0, 1.0), 0.2, 0.7,
                                                         Eigen::Vector3d::Zero(), 2.4e-4);
  EXPECT_TRUE(delta.covariance.isApprox(2.4e-4 * 2.4e-4 * 0.5 * Eigen::Matrix3d::Identity(), 1e-9));
}

TEST(GyroPreintegration, SamplesThatDoNotReachTheSpanOrLeaveAGapAreIncomplete) {
  std::vector<vocal::ImuSample> samples = constantRate(Eigen::Vector3d(0, 0, 1), 100.0, 1.0);
  EXPECT_FALSE(vocal::preintegrateGyro(samples, 0.5, 1.2, Eigen::Vector3d::Zero(), 0.0).complete);
  samples.erase(samples.begin() + 40, samples.begin() + 50);  // 0.40-0.49 s missing: a 0.11 s gap
  EXPECT_FALSE(vocal::preintegrateGyro(samples, 0.3, 0.6, Eigen::Vector3d::Zero(), 0.0).complete);
  EXPECT_TRUE(vocal::preintegrateGyro(samples, 0.6, 0.9, Eigen::Vector3d::Zero(), 0.0).complete);
}

TEST(SimulatedImu, ItsGyroIntegratesToThePathsRotationOnceTheBiasIsTakenOff) {
  const vocal::Trajectory path = turningPath(301, 30.0);
  vocal::SimulatedImuOptions options;
  options.extrinsics = vocal::simulatedImuExtrinsics();
  options.extrinsics.noise.gyro_bias_random_walk = 0.0;
  Eigen::Vector3d bias;
  const std::vector<vocal::ImuSample> samples = vocal::simulateImu(path, options, &bias);
  EXPECT_GT(bias.norm(), 0.0);
  EXPECT_LE(bias.cwiseAbs().maxCoeff(), options.bias_limit);
  const Eigen::Matrix3d imu_from_camera = options.extrinsics.camera_in_imu.rotation();
  for (int k = 0; k + 30 < 300; k += 30) {  // 1 s spans: the camera's rotation seen in the IMU frame
    const vocal::GyroDelta delta = vocal::preintegrateGyro(samples, path[k].stamp, path[k + 30].stamp, bias, 0.0);
    const Eigen::Matrix3d truth = imu_from_camera * path[k].pose.linear().transpose() * path[k + 30].pose.linear() * imu_from_camera.transpose();
    EXPECT_LT(angleBetween(delta.rotation, truth), 2e-3) << "span from " << k;  // white noise ~0.1 mrad, the fit's smoothing
  }
}

TEST(SimulatedImu, ItsGyroTurnsAcrossAGapInThePathAsThePathDid) {
  // A 100 Hz motion capture that lost its markers for 0.15 s (TUM's fr1_xyz has a 0.11 s gap).
  vocal::Trajectory path = turningPath(301, 100.0);
  path.erase(path.begin() + 140, path.begin() + 155);
  vocal::SimulatedImuOptions options;
  options.extrinsics = vocal::simulatedImuExtrinsics();
  options.extrinsics.noise.gyro_noise_density = options.extrinsics.noise.gyro_bias_random_walk = 0.0;
  Eigen::Vector3d bias;
  const std::vector<vocal::ImuSample> samples = vocal::simulateImu(path, options, &bias);
  const Eigen::Matrix3d imu_from_camera = options.extrinsics.camera_in_imu.rotation();
  const vocal::StampedPose& before = path[100];
  const vocal::StampedPose& after = path[200];  // 1 s later, across the gap
  const vocal::GyroDelta delta = vocal::preintegrateGyro(samples, before.stamp, after.stamp, bias, 0.0);
  const Eigen::Matrix3d truth = imu_from_camera * before.pose.linear().transpose() * after.pose.linear() * imu_from_camera.transpose();
  EXPECT_LT(angleBetween(delta.rotation, truth), 2e-3);
}

TEST(GyroRotationPrior, ItsBiasConvergesOnWhatVisionMeasuresAgainstKeyframes) {
  const vocal::Trajectory path = turningPath(600, 30.0);  // 20 s
  vocal::SimulatedImuOptions options;
  options.extrinsics = vocal::simulatedImuExtrinsics();
  Eigen::Vector3d bias;
  const std::vector<vocal::ImuSample> samples = vocal::simulateImu(path, options, &bias);
  vocal::GyroRotationPrior prior(options.extrinsics);
  prior.add(samples);
  std::mt19937 random(3);
  std::normal_distribution<double> noise(0.0, 1e-3);  // vision's error against a keyframe: 1 mrad
  for (int k = 1; k < 600; ++k) {
    const int keyframe = k - k % 8;  // a new keyframe every 8 frames
    if (keyframe == k) continue;
    const Eigen::Matrix3d vision =
        path[keyframe].pose.linear().transpose() * path[k].pose.linear() * exp3(Eigen::Vector3d(noise(random), noise(random), noise(random)));
    prior.observe(path[keyframe].stamp, path[k].stamp, vision);
  }
  EXPECT_GT(prior.biasUpdates(), 60);
  // From 0.57 deg/s unknown to under 0.1 deg/s, and the drawn bias within three of its sigmas.
  EXPECT_LT(prior.biasSigma().maxCoeff(), 0.1 * M_PI / 180.0);
  for (int axis = 0; axis < 3; ++axis)
    EXPECT_LT(std::abs(prior.bias()[axis] - bias[axis]), 3.0 * prior.biasSigma()[axis])
        << "axis " << axis << ": estimated " << prior.bias().transpose() << " drawn " << bias.transpose();
  // The prior between two frames then agrees with the path within its own sigma's reach.
  const std::optional<vocal::RotationPrior> between = prior.between(path[500].stamp, path[501].stamp);
  ASSERT_TRUE(between);
  const double error = angleBetween(between->rotation, path[500].pose.linear().transpose() * path[501].pose.linear());
  EXPECT_LT(error, 5.0 * std::sqrt(between->covariance.trace()) + 1e-4);
}

TEST(GyroRotationPrior, BadSamplesAreNamedAndDropped) {
  vocal::GyroRotationPrior prior(vocal::ImuExtrinsics{});
  std::string why;
  EXPECT_TRUE(prior.add({1.0, Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, 9.8)}, &why));
  EXPECT_FALSE(prior.add({0.5, Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, 9.8)}, &why));
  EXPECT_EQ(why, "IMU sample at 0.500000 s: not after the last one (1.000000 s): stamps out of order");
  EXPECT_FALSE(prior.add({2.0, Eigen::Vector3d(NAN, 0, 0), Eigen::Vector3d(0, 0, 9.8)}, &why));
  EXPECT_EQ(why, "IMU sample at 2 s: a value is not finite (NaN or inf)");
  EXPECT_EQ(prior.samples().size(), 1u);
  EXPECT_FALSE(prior.between(1.0, 1.5, &why));
  EXPECT_NE(why.find("the IMU samples do not cover 1.000-1.500 s (IMU clock): they span 1.000-1.000 s"), std::string::npos) << why;
}

TEST(ImuFiles, ReadBackWhatWasWritten) {
  const std::vector<vocal::ImuSample> samples = constantRate(Eigen::Vector3d(0.1, -0.2, 0.3), 100.0, 0.5);
  const std::string path = ::testing::TempDir() + "/imu_roundtrip.txt";
  vocal::writeImuFile(path, samples);
  const std::vector<vocal::ImuSample> read = vocal::readImuFile(path);
  ASSERT_EQ(read.size(), samples.size());
  EXPECT_NEAR(read[7].stamp, samples[7].stamp, 1e-6);
  EXPECT_TRUE(read[7].angular_velocity.isApprox(samples[7].angular_velocity, 1e-8));
  EXPECT_NEAR(vocal::imuRate(read), 100.0, 1e-6);

  vocal::ImuExtrinsics extrinsics = vocal::simulatedImuExtrinsics();
  extrinsics.time_offset = -0.0125;
  extrinsics.noise.gyro_noise_density = 1e-3;
  const std::string yaml = ::testing::TempDir() + "/imu_extrinsics_roundtrip.yaml";
  vocal::writeImuExtrinsics(yaml, extrinsics);
  const vocal::ImuExtrinsics back = vocal::readImuExtrinsics(yaml);
  EXPECT_TRUE(back.camera_in_imu.isApprox(extrinsics.camera_in_imu, 1e-8));
  EXPECT_EQ(back.imu_frame, extrinsics.imu_frame);
  EXPECT_DOUBLE_EQ(back.time_offset, -0.0125);
  EXPECT_DOUBLE_EQ(back.noise.gyro_noise_density, 1e-3);
}

TEST(ImuFiles, BadLinesAndEntriesAreNamed) {
  const auto message = [](const std::function<void()>& f) {
    try {
      f();
    } catch (const vocal::InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string short_line = writeText("imu_short.txt", "# imu\n1.0 0 0 0 0 0 9.8\n1.1 0 0 0 0 9.8\n");
  EXPECT_EQ(message([&] { vocal::readImuFile(short_line); }),
            short_line + ":3: expected 7 fields 'timestamp wx wy wz ax ay az', found 6");
  const std::string backwards = writeText("imu_backwards.txt", "1.0 0 0 0 0 0 9.8\n0.9 0 0 0 0 0 9.8\n");
  EXPECT_NE(message([&] { vocal::readImuFile(backwards); }).find(backwards + ":2:"), std::string::npos);
  const std::string not_finite = writeText("imu_nan.txt", "1.0 0 nan 0 0 0 9.8\n");
  EXPECT_NE(message([&] { vocal::readImuFile(not_finite); }).find("wy"), std::string::npos);
  const std::string quaternion =
      writeText("imu_quaternion.yaml", "camera_in_imu: {translation: [0, 0, 0], rotation: [0, 0, 0, 2]}\n");
  EXPECT_EQ(message([&] { vocal::readImuExtrinsics(quaternion); }),
            quaternion + ": camera_in_imu.rotation: not a unit quaternion [qx, qy, qz, qw] (norm 2.000000)");
  const std::string missing = writeText("imu_missing.yaml", "imu_frame: imu\n");
  EXPECT_EQ(message([&] { vocal::readImuExtrinsics(missing); }),
            missing + ": camera_in_imu: missing (translation: [x, y, z], rotation: [qx, qy, qz, qw])");
  const std::string negative =
      writeText("imu_negative.yaml", "camera_in_imu: {translation: [0, 0, 0], rotation: [0, 0, 0, 1]}\nnoise: {gyro_noise_density: -1}\n");
  EXPECT_EQ(message([&] { vocal::readImuExtrinsics(negative); }), negative + ": noise.gyro_noise_density: must be a finite number >= 0");
}

#include "vocal/odometry/cpu_backend.h"
#include "vocal/odometry/fast_cpu_backend.h"
#ifdef VOCAL_HAVE_OPENCL
#include "vocal/odometry/opencl_backend.h"
#include "vocal/odometry/opencl_context.h"
#endif

namespace {
struct GyroRun {
  vocal::Trajectory estimate;
  Eigen::Vector3d bias = Eigen::Vector3d::Zero();
};

// A noisy 320x240 room along a fast path, 3 s at 30 Hz, and a consumer gyro along it.
struct GyroScene {
  vocal::PinholeCamera camera = vocal::defaultKinectCamera(320, 240);
  vocal::Trajectory truth;
  std::vector<vocal::RgbdFrame> frames;
  vocal::ImuExtrinsics extrinsics = vocal::simulatedImuExtrinsics();
  std::vector<vocal::ImuSample> samples;
  Eigen::Vector3d bias;
};

const GyroScene& gyroScene() {
  static const GyroScene scene = [] {
    GyroScene s;
    const vocal::SyntheticScene room = vocal::SyntheticScene::make(vocal::SceneVariant::kBareRoom);
    vocal::SyntheticTrajectoryOptions options;
    options.frames = 90;
    options.speed = 0.5;
    options.seed = 4;
    s.truth = vocal::generateSyntheticTrajectory(room.workspace(), options);
    for (std::size_t i = 0; i < s.truth.size(); ++i)
      s.frames.push_back(vocal::renderSyntheticFrame(room, s.camera, s.truth[i], vocal::kinectLikeSensorModel(), 900 + i));
    vocal::SimulatedImuOptions imu;
    imu.extrinsics = s.extrinsics;
    s.samples = vocal::simulateImu(s.truth, imu, &s.bias);
    return s;
  }();
  return scene;
}

// The rendered images' noise is white, pixel by pixel, so the dense terms' information is as honest as
// the gyro's: weight 1. (Real Kinect frames' is not: imu_weight's default was chosen on them.)
vocal::OdometryConfig honestWeights() {
  vocal::OdometryConfig config;
  config.imu_weight = 1.0;
  return config;
}

GyroRun trackWithGyro(std::unique_ptr<vocal::OdometryBackend> backend, bool gyro) {
  const GyroScene& scene = gyroScene();
  const vocal::OdometryConfig config = honestWeights();
  vocal::IcpDvoOdometry odometry(scene.camera, config, std::move(backend));
  odometry.reset(scene.truth.front().pose);
  vocal::GyroRotationPrior imu(scene.extrinsics);
  imu.add(scene.samples);
  GyroRun run;
  for (std::size_t i = 0; i < scene.frames.size(); ++i) {
    std::optional<vocal::RotationPrior> prior;
    if (gyro && i > 0) prior = imu.between(scene.frames[i - 1].stamp, scene.frames[i].stamp);
    if (gyro && i > 0) {
      EXPECT_TRUE(prior) << "frame " << i;
    }
    const vocal::OdometryResult result = odometry.track(scene.frames[i], prior ? &*prior : nullptr);
    if (result.state == vocal::TrackingState::kTracking && result.quality.trusted) {
      imu.observe(result.keyframe_stamp, scene.frames[i].stamp, result.vision_rotation);
    } else {
      imu.breakWindow();
    }
    run.estimate.push_back({scene.frames[i].stamp, result.pose});
  }
  run.bias = imu.bias();
  return run;
}
}  // namespace

// The gyro's prior reaches the system on every backend (it is added on the host, after each backend's
// reduction) and lowers the rotation's drift; translation is no worse.
TEST(OdometryWithGyro, RotationDriftsLessOnEveryBackend) {
  const GyroScene& scene = gyroScene();
  std::map<std::string, std::function<std::unique_ptr<vocal::OdometryBackend>()>> backends;
  const vocal::OdometryConfig config = honestWeights();
  backends["cpu reference"] = [&] { return std::make_unique<vocal::CpuOdometryBackend>(scene.camera, config); };
  backends["cpu fast"] = [&] { return std::make_unique<vocal::FastCpuOdometryBackend>(scene.camera, config); };
#ifdef VOCAL_HAVE_OPENCL
  if (!vocal::listOpenClDevices().empty())
    backends["opencl"] = [&] { return std::make_unique<vocal::OpenClOdometryBackend>(scene.camera, config); };
#endif
  std::map<std::string, GyroRun> with_gyro;
  for (const auto& [name, make] : backends) {
    const GyroRun without = trackWithGyro(make(), false);
    const GyroRun with = trackWithGyro(make(), true);
    const vocal::RpeResult rpe_without = vocal::computeRpe(scene.truth, without.estimate, 0.5, 0.02);
    const vocal::RpeResult rpe_with = vocal::computeRpe(scene.truth, with.estimate, 0.5, 0.02);
    const vocal::AteResult ate_without = vocal::computeAte(scene.truth, without.estimate, 0.02);
    const vocal::AteResult ate_with = vocal::computeAte(scene.truth, with.estimate, 0.02);
    std::printf("%s: rotation RPE %.3f -> %.3f deg/s, translation RPE %.4f -> %.4f m/s, ATE %.4f -> %.4f m\n", name.c_str(),
                rpe_without.rotation_rmse_deg_per_s, rpe_with.rotation_rmse_deg_per_s, rpe_without.translation_rmse_m_per_s, rpe_with.translation_rmse_m_per_s,
                ate_without.rmse, ate_with.rmse);
    EXPECT_LT(rpe_with.rotation_rmse_deg_per_s, 0.9 * rpe_without.rotation_rmse_deg_per_s) << name;
    EXPECT_LT(rpe_with.translation_rmse_m_per_s, 1.1 * rpe_without.translation_rmse_m_per_s + 1e-4) << name;
    EXPECT_LT(ate_with.rmse, 1.1 * ate_without.rmse + 1e-4) << name;
    with_gyro[name] = with;
  }
  // The backends' systems agree (test_odometry_parity): with the same prior, so do their poses.
  const GyroRun& reference = with_gyro.at("cpu reference");
  for (const auto& [name, run] : with_gyro) {
    const Eigen::Isometry3d difference = reference.estimate.back().pose.inverse() * run.estimate.back().pose;
    EXPECT_LT(difference.translation().norm(), 2e-3) << name;
    EXPECT_LT(vocal::rotationAngle(difference), 2e-3) << name;
  }
}

// A pan at 6 rad/s (0.2 rad a frame at 30 Hz) in the room: from the gyro's start every frame is tracked
// and the rotation holds within a degree, closer than vision alone (which here still tracks it too,
// its ORB features finding the start: 2.6 deg).
TEST(OdometryWithGyro, AFastTurnIsTrackedFromTheGyrosStart) {
  constexpr double kRate = 6.0;  // rad/s
  const vocal::SyntheticScene room = vocal::SyntheticScene::make(vocal::SceneVariant::kIndoorRoom);
  const vocal::PinholeCamera camera = vocal::defaultKinectCamera(320, 240);
  const vocal::Trajectory base = vocal::generateSyntheticTrajectory(room.workspace(), vocal::SyntheticTrajectoryOptions{});
  vocal::Trajectory path;
  for (int i = 0; i < 30; ++i) {
    vocal::StampedPose p = base.front();
    p.stamp = base.front().stamp + i / 30.0;
    // Optical y points down: a turn about it is a pan.
    p.pose.linear() = base.front().pose.linear() * Eigen::AngleAxisd(kRate * i / 30.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
    path.push_back(p);
  }
  std::vector<vocal::RgbdFrame> frames;
  for (std::size_t i = 0; i < path.size(); ++i)
    frames.push_back(vocal::renderSyntheticFrame(room, camera, path[i], vocal::kinectLikeSensorModel(), 700 + i));
  vocal::SimulatedImuOptions options;
  options.extrinsics = vocal::simulatedImuExtrinsics();
  const std::vector<vocal::ImuSample> samples = vocal::simulateImu(path, options);
  double worst_without = 0.0;
  for (const bool gyro : {false, true}) {
    vocal::IcpDvoOdometry odometry(camera, vocal::OdometryConfig{});
    odometry.reset(path.front().pose);
    vocal::GyroRotationPrior imu(options.extrinsics);
    imu.add(samples);
    int untracked = 0;
    double worst = 0.0;
    for (std::size_t i = 0; i < frames.size(); ++i) {
      std::optional<vocal::RotationPrior> prior;
      if (gyro && i > 0) prior = imu.between(path[i - 1].stamp, path[i].stamp);
      const vocal::OdometryResult result = odometry.track(frames[i], prior ? &*prior : nullptr);
      untracked += !result.quality.trusted;
      worst = std::max(worst, angleBetween(result.pose.linear(), path[i].pose.linear()));
    }
    std::printf("%s the gyro: %d of %zu frames not tracked, rotation off by up to %.2f deg\n", gyro ? "with" : "without", untracked,
                frames.size(), worst * 180.0 / M_PI);
    if (!gyro) worst_without = worst;
    if (gyro) {
      EXPECT_EQ(untracked, 0);
      EXPECT_LT(worst, 1.0 * M_PI / 180.0);
      EXPECT_LT(worst, 0.5 * worst_without);
    }
  }
}

// The method's own limit: facing a blank wall (one untextured plane) vision holds three directions at
// most. 10 s there, turning and moving, between two looks into the room: with the gyro every frame is
// tracked, degraded while facing the wall (the two in-plane directions guessed, and marked so in the
// covariance), tracking again once the room is back, the rotation within a degree throughout; without,
// the frames at the wall are lost (the pose held while the camera turns), relocalised once the start's
// view is back.
TEST(OdometryWithGyro, ABlankWallIsCrossedOnTheGyroWithTheGuessedDirectionsMarked) {
  vocal::BlankWallVisitOptions visit;
  visit.frame_rate = 15.0;
  const vocal::Trajectory path = vocal::generateBlankWallVisit(visit);
  const auto [dwell_first, dwell_last] = vocal::blankWallDwell(visit);
  const vocal::SyntheticScene scene = vocal::SyntheticScene::make(vocal::SceneVariant::kBlankWall);
  const vocal::PinholeCamera camera = vocal::defaultKinectCamera(320, 240);
  std::vector<vocal::RgbdFrame> frames;
  for (std::size_t i = 0; i < path.size(); ++i)
    frames.push_back(vocal::renderSyntheticFrame(scene, camera, path[i], vocal::kinectLikeSensorModel(), 500 + i));
  vocal::SimulatedImuOptions imu_options;
  imu_options.extrinsics = vocal::simulatedImuExtrinsics();
  const std::vector<vocal::ImuSample> samples = vocal::simulateImu(path, imu_options);
  vocal::OdometryConfig config;  // the defaults, but for a camera that renders every row at once
  config.rolling_shutter_readout = 0.0;
  config.depth_time_offset = 0.0;
  const Eigen::Vector3d wall_normal = Eigen::Vector3d::UnitY();  // the panel's, in the world (= odometry frame)

  double worst_at_the_wall_without = 0.0;
  for (const bool gyro : {false, true}) {
    vocal::IcpDvoOdometry odometry(camera, config);
    odometry.reset(path.front().pose);
    vocal::GyroRotationPrior imu(imu_options.extrinsics);
    imu.add(samples);
    int untracked = 0, dwell_frames = 0, dwell_untracked = 0, dwell_degraded = 0, tracking_at_the_end = 0;
    double worst_at_the_wall = 0.0, worst_in_plane = 0.0, guessed_over_held = std::numeric_limits<double>::infinity();
    vocal::OdometryResult result;
    for (std::size_t i = 0; i < frames.size(); ++i) {
      std::optional<vocal::RotationPrior> prior;
      if (gyro && i > 0) prior = imu.between(path[i - 1].stamp, path[i].stamp);
      result = odometry.track(frames[i], prior ? &*prior : nullptr);
      if (result.state == vocal::TrackingState::kTracking) {
        imu.observe(result.keyframe_stamp, path[i].stamp, result.vision_rotation);
      } else {
        imu.breakWindow();
      }
      untracked += !result.quality.trusted;
      if (i + 15 >= frames.size()) tracking_at_the_end += result.state == vocal::TrackingState::kTracking;
      if (path[i].stamp < dwell_first || path[i].stamp > dwell_last) continue;
      ++dwell_frames;
      dwell_untracked += !result.quality.trusted;
      worst_at_the_wall = std::max(worst_at_the_wall, angleBetween(result.pose.linear(), path[i].pose.linear()) * 180.0 / M_PI);
      if (result.state != vocal::TrackingState::kDegraded || result.guessed_directions.cols() != 2) continue;
      ++dwell_degraded;
      // The pose covariance's translation block: the guessed directions against the wall's normal, which ICP holds.
      const Eigen::Matrix3d position = result.pose_covariance.topLeftCorner<3, 3>();
      for (int k = 0; k < 2; ++k) {
        const Eigen::Vector3d u = result.guessed_directions.col(k);
        worst_in_plane = std::max(worst_in_plane, std::abs(u.dot(wall_normal)));
        guessed_over_held = std::min(guessed_over_held, u.dot(position * u) / wall_normal.dot(position * wall_normal));
      }
    }
    const double end_error = angleBetween(result.pose.linear(), path.back().pose.linear()) * 180.0 / M_PI;
    std::printf("%s the gyro: %d of %zu frames not tracked (%d of %d at the wall), rotation off by up to %.2f deg at the wall, "
                "%.2f deg at the end, position by %.3f m\n", gyro ? "with" : "without", untracked, frames.size(), dwell_untracked,
                dwell_frames, worst_at_the_wall, end_error, (result.pose.translation() - path.back().pose.translation()).norm());
    EXPECT_EQ(tracking_at_the_end, 15) << "tracking picks up when the room is back";
    if (!gyro) {
      worst_at_the_wall_without = worst_at_the_wall;
      EXPECT_GT(dwell_untracked, 0.8 * dwell_frames) << "vision alone cannot hold the wall";
      continue;
    }
    std::printf("with the gyro: %d of %d frames at the wall degraded, guessed directions within %.3f of the wall's plane, "
                "their variance at least %.0fx the normal's\n", dwell_degraded, dwell_frames, worst_in_plane, guessed_over_held);
    EXPECT_EQ(untracked, 0);
    EXPECT_GE(dwell_degraded, 0.9 * dwell_frames);
    EXPECT_LT(worst_in_plane, 0.2);
    EXPECT_GT(guessed_over_held, 100.0);
    EXPECT_LT(worst_at_the_wall, 1.0);
    EXPECT_LT(end_error, 1.0);
    EXPECT_LT(worst_at_the_wall, 0.2 * worst_at_the_wall_without);
  }
}

// The accelerometer's gravity less the camera's own acceleration: a camera swinging 1 m/s^2 along a line
// while its attitude tilts away from the first level by 3 deg: the correction measures the tilt (not the
// swing: 6 deg if taken as gravity) and turns roll / pitch back at 1/time_constant per second, the
// position and the heading untouched.
TEST(GravityCorrection, PullsRollAndPitchBackToTheFirstLevelNotTheSwing) {
  vocal::GravityCorrection gravity(2.0);
  std::vector<vocal::AccelerometerSample> samples;
  const double rate = 30.0, swing = 1.0;  // m/s^2 amplitude along world x
  auto truePose = [&](double t) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation() = Eigen::Vector3d(-swing / 4.0 * std::cos(2.0 * t), 0.0, 1.0);  // x'' = swing cos(2t)
    pose.linear() = vocal::rotationFromRollPitchYaw(0.0, 0.0, 0.3 * t) * vocal::bodyFromOpticalRotation();
    return pose;
  };
  // Accelerometer (camera frame) from the true motion: R^T (a + g up), at 200 Hz.
  for (int i = 0; i <= 200 * 12; ++i) {
    const double t = i / 200.0;
    const Eigen::Vector3d a(swing * std::cos(2.0 * t), 0.0, 0.0);
    samples.push_back({t, truePose(t).linear().transpose() * (a + Eigen::Vector3d(0, 0, vocal::kStandardGravity))});
  }
  // The odometry's estimate: the truth, tilted by 3 deg about world x after the level was fixed (t > 2 s).
  const Eigen::Matrix3d tilt = vocal::so3Exp(Eigen::Vector3d(3.0 * M_PI / 180.0, 0.0, 0.0));
  Eigen::Matrix3d applied = Eigen::Matrix3d::Identity();  // the corrections so far
  double tilt_at_3s = 0.0, tilt_at_end = 0.0;
  for (int i = 0; i <= 12 * rate; ++i) {
    const double t = i / rate;
    Eigen::Isometry3d estimate = truePose(t);
    if (t > 2.0) estimate.linear() = tilt * estimate.linear();
    estimate.linear() = applied * estimate.linear();
    std::string why;
    const Eigen::Isometry3d correction = gravity.correct(t, estimate, samples, i ? 1.0 / rate : 0.0, &why);
    if (t > 1.0) {
      EXPECT_EQ(why, "") << t;
    }
    EXPECT_NEAR((correction * estimate).translation().x(), estimate.translation().x(), 1e-12) << "the position stays";
    applied = correction.linear() * applied;
    const Eigen::Vector3d up = (correction.linear() * estimate.linear()) * truePose(t).linear().transpose() * Eigen::Vector3d::UnitZ();
    const double off = std::acos(std::clamp(up.z(), -1.0, 1.0)) * 180.0 / M_PI;
    if (std::fabs(t - 3.0) < 1e-9) tilt_at_3s = off;
    if (i == 12 * rate) tilt_at_end = off;
    // Heading: the correction turns about a horizontal axis only (the level was fixed while the estimate was true: z up).
    const Eigen::Vector3d turn = vocal::so3Log(correction.linear());
    EXPECT_LE(std::fabs(turn.z()), 1e-3 * turn.norm() + 1e-12) << t;
  }
  std::printf("tilt 3 deg at 2 s: %.2f deg at 3 s, %.3f deg at 12 s (time constant 2 s)\n", tilt_at_3s, tilt_at_end);
  EXPECT_NEAR(tilt_at_3s, 3.0 * std::exp(-1.0 / 2.0), 0.4);  // a share dt / 2 s per frame for a second
  EXPECT_LT(tilt_at_end, 0.05);
  EXPECT_THROW(vocal::GravityCorrection(0.0), vocal::InputError);
}

// Roll and pitch on a run whose gyro misleads: a 1 deg/s bias left unlearned and the gyro trusted far
// above vision (imu_weight 1e5) tilt the estimate degree by degree; the accelerometer's gravity holds the
// tilt (roll / pitch) near the truth, the heading drifting as before.
TEST(OdometryWithGyro, TheAccelerometersGravityHoldsRollAndPitch) {
  const vocal::SyntheticScene room = vocal::SyntheticScene::make(vocal::SceneVariant::kIndoorRoom);
  const vocal::PinholeCamera camera = vocal::defaultKinectCamera(320, 240);
  vocal::SyntheticTrajectoryOptions path_options;
  path_options.frames = 150;
  path_options.frame_rate = 15.0;
  path_options.seed = 6;
  const vocal::Trajectory path = vocal::generateSyntheticTrajectory(room.workspace(), path_options);
  std::vector<vocal::RgbdFrame> frames;
  for (std::size_t i = 0; i < path.size(); ++i)
    frames.push_back(vocal::renderSyntheticFrame(room, camera, path[i], vocal::kinectLikeSensorModel(), 300 + i));
  vocal::SimulatedImuOptions imu_options;
  imu_options.extrinsics = vocal::simulatedImuExtrinsics();
  imu_options.bias_limit = 1.0 * M_PI / 180.0;
  imu_options.seed = 5;
  const std::vector<vocal::ImuSample> samples = vocal::simulateImu(path, imu_options);
  std::vector<vocal::AccelerometerSample> accelerometer;
  const Eigen::Matrix3d camera_from_imu = imu_options.extrinsics.camera_in_imu.linear().transpose();
  for (const vocal::ImuSample& s : samples) accelerometer.push_back({s.stamp, camera_from_imu * s.linear_acceleration});

  auto tiltOf = [](const Eigen::Matrix3d& estimate, const Eigen::Matrix3d& truth) {  // world z up in both
    const Eigen::Vector3d up = estimate * truth.transpose() * Eigen::Vector3d::UnitZ();
    return std::acos(std::clamp(up.z(), -1.0, 1.0)) * 180.0 / M_PI;
  };
  double tilt[2] = {0.0, 0.0}, rotation[2] = {0.0, 0.0};
  for (const bool gravity : {false, true}) {
    vocal::OdometryConfig config;
    config.imu_weight = 1e5;
    config.gravity_time_constant = gravity ? 1.0 : 0.0;
    vocal::IcpDvoOdometry odometry(camera, config);
    odometry.reset(path.front().pose);
    vocal::GyroRotationPrior imu(imu_options.extrinsics);  // its bias never learned: no observe()
    imu.add(samples);
    vocal::OdometryResult result;
    for (std::size_t i = 0; i < frames.size(); ++i) {
      std::optional<vocal::RotationPrior> prior;
      if (i > 0) prior = imu.between(path[i - 1].stamp, path[i].stamp);
      result = odometry.track(frames[i], prior ? &*prior : nullptr, &accelerometer);
      EXPECT_TRUE(result.quality.trusted) << "frame " << i << ": " << result.failure;
      if (gravity && i > 15) {
        EXPECT_GE(result.gravity_error_deg, 0.0) << "frame " << i << ": gravity measured";
      }
    }
    tilt[gravity] = tiltOf(result.pose.linear(), path.back().pose.linear());
    rotation[gravity] = angleBetween(result.pose.linear(), path.back().pose.linear()) * 180.0 / M_PI;
    std::printf("%s gravity: tilt off by %.2f deg, rotation by %.2f deg after %.0f s\n", gravity ? "with" : "without", tilt[gravity],
                rotation[gravity], path.back().stamp - path.front().stamp);
  }
  EXPECT_GT(tilt[false], 2.0) << "the misled gyro tilts the estimate";
  // A drift of ~0.7 deg/s held with a 1 s time constant lags by ~0.7 deg; the accelerometer's bias adds ~0.3.
  EXPECT_LT(tilt[true], 1.5);
  EXPECT_LT(tilt[true], 0.3 * tilt[false]);
}

// A 3 rad/s pan in the untextured room as a real camera takes it: each row exposed for 20 ms (the smear
// 0.06 rad, 30 px at 320x240), read out over 20 ms, depth lost where the pattern smears. Vision alone
// (ICP, 5.7 deg a frame) loses it; from the gyro's start it is tracked. (In the textured room vision
// keeps such a turn, 3.2 deg off at worst, its features finding the start: 0.8 deg with the gyro.)
TEST(OdometryWithGyro, ABlurredTurnVisionAloneLosesIsTrackedWithTheGyro) {
  constexpr double kRate = 3.0;  // rad/s
  const vocal::SyntheticScene room = vocal::SyntheticScene::make(vocal::SceneVariant::kBareRoom);
  const vocal::PinholeCamera camera = vocal::defaultKinectCamera(320, 240);
  const vocal::Trajectory base = vocal::generateSyntheticTrajectory(room.workspace(), vocal::SyntheticTrajectoryOptions{});
  // The path at 300 Hz (what the blur, the rolling shutter and the gyro are taken from), the frames at 30 Hz:
  // at rest for a third of a second, then the pan, its rate rising over 0.1 s (optical y points down: a
  // turn about it is a pan).
  vocal::Trajectory path, frame_poses;
  double angle = 0.0;
  for (int i = 0; i < 300; ++i) {
    const double t = i / 300.0;
    const double ramp = std::clamp((t - 1.0 / 3.0) / 0.1, 0.0, 1.0);
    if (i > 0) angle += kRate * ramp * ramp * (3.0 - 2.0 * ramp) / 300.0;
    vocal::StampedPose p = base.front();
    p.stamp = base.front().stamp + t;
    p.pose.linear() = base.front().pose.linear() * Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitY()).toRotationMatrix();
    path.push_back(p);
    if (i % 10 == 0) frame_poses.push_back(p);
  }
  std::vector<vocal::RgbdFrame> frames;
  for (std::size_t i = 0; i < path.size(); i += 10)
    frames.push_back(vocal::renderRollingShutterFrame(room, camera, path, i, 0.02, vocal::kinectLikeSensorModel(), 800 + i, 0.02));
  vocal::SimulatedImuOptions options;
  options.extrinsics = vocal::simulatedImuExtrinsics();
  const std::vector<vocal::ImuSample> samples = vocal::simulateImu(path, options);
  int untracked[2] = {0, 0};
  double worst[2] = {0.0, 0.0};
  for (const bool gyro : {false, true}) {
    vocal::OdometryConfig config;
    config.depth_time_offset = 0.0;  // rendered together
    vocal::IcpDvoOdometry odometry(camera, config);
    odometry.reset(frame_poses.front().pose);
    vocal::GyroRotationPrior imu(options.extrinsics);
    imu.add(samples);
    for (std::size_t i = 0; i < frames.size(); ++i) {
      std::optional<vocal::RotationPrior> prior;
      if (gyro && i > 0) prior = imu.between(frame_poses[i - 1].stamp, frame_poses[i].stamp);
      const vocal::OdometryResult result = odometry.track(frames[i], prior ? &*prior : nullptr);
      untracked[gyro] += !result.quality.trusted;
      worst[gyro] = std::max(worst[gyro], angleBetween(result.pose.linear(), frame_poses[i].pose.linear()) * 180.0 / M_PI);
    }
    std::printf("%s the gyro: %d of %zu frames not tracked, rotation off by up to %.2f deg\n", gyro ? "with" : "without", untracked[gyro],
                frames.size(), worst[gyro]);
  }
  EXPECT_TRUE(untracked[false] > 0 || worst[false] > 5.0) << "vision alone keeps up: the turn is not the test's";
  EXPECT_EQ(untracked[true], 0);
  EXPECT_LT(worst[true], 1.0);
}
