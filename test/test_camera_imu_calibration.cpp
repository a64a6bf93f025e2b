// Camera-IMU calibration: the body spline's derivatives, and waved sessions with known truth.
#include <gtest/gtest.h>

#include <random>

#include <yaml-cpp/yaml.h>

#include "test_support.h"
#include "vocal/calibration/rig_description.h"
#include "vocal/calibration/solver/camera_imu_calibration.h"
#include <ceres/jet.h>

#include "vocal/calibration/solver/cumulative_bspline.h"
#include "vocal/calibration/solver/imu_sample_residual.h"
#include "vocal/calibration/solver/spline_camera_view_residual.h"
#include "vocal/calibration/solver/spline_corner_residual.h"
#include "vocal/core/errors.h"
#include "vocal/core/se3.h"
#include "vocal/simulation/waved_camera_imu.h"

namespace vocal {
namespace {

struct RandomSpline {
  explicit RandomSpline(int n, std::uint32_t seed) {
    std::mt19937 random(seed);
    std::normal_distribution<double> normal(0.0, 1.0);
    Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
    for (int k = 0; k < n; ++k) {
      q = q * Eigen::Quaterniond(so3Exp(0.4 * Eigen::Vector3d(normal(random), normal(random), normal(random))));
      rotations.push_back(q);
      positions.push_back(Eigen::Vector3d(normal(random), normal(random), normal(random)));
    }
  }
  SplineRotation<double> rotation(int s, double u) const {
    return evaluateRotationSpline<double>({rotations[s].coeffs().data(), rotations[s + 1].coeffs().data(), rotations[s + 2].coeffs().data(),
                                           rotations[s + 3].coeffs().data()},
                                          u, spacing);
  }
  SplinePosition<double> position(int s, double u) const {
    return evaluatePositionSpline<double>({positions[s].data(), positions[s + 1].data(), positions[s + 2].data(), positions[s + 3].data()}, u,
                                          spacing);
  }
  std::vector<Eigen::Quaterniond> rotations;
  std::vector<Eigen::Vector3d> positions;
  double spacing = 0.05;
};

TEST(CumulativeBSpline, AngularVelocityAndAccelerationMatchFiniteDifferences) {
  const RandomSpline spline(8, 3);
  const double h = 1e-4;  // of u
  for (int s = 0; s < 5; ++s) {
    for (double u : {0.1, 0.37, 0.5, 0.83}) {
      const SplineRotation<double> at = spline.rotation(s, u);
      const Eigen::Matrix3d before = spline.rotation(s, u - h).rotation.toRotationMatrix();
      const Eigen::Matrix3d after = spline.rotation(s, u + h).rotation.toRotationMatrix();
      const Eigen::Vector3d numeric_rate = so3Log(before.transpose() * after) / (2 * h * spline.spacing);
      EXPECT_LT((at.angular_velocity - numeric_rate).norm(), 1e-5 * (1.0 + numeric_rate.norm())) << "segment " << s << " u " << u;
      const Eigen::Vector3d numeric_acceleration =
          (spline.position(s, u + h).position - 2 * spline.position(s, u).position + spline.position(s, u - h).position) /
          (h * h * spline.spacing * spline.spacing);
      EXPECT_LT((spline.position(s, u).acceleration - numeric_acceleration).norm(), 1e-4 * (1.0 + numeric_acceleration.norm()));
    }
  }
}

TEST(CumulativeBSpline, SegmentsJoinWithTheirRatesAndAccelerations) {
  const RandomSpline spline(9, 5);
  for (int s = 0; s + 1 < 6; ++s) {
    const SplineRotation<double> end = spline.rotation(s, 1.0), start = spline.rotation(s + 1, 0.0);
    EXPECT_LT(so3Log(end.rotation.toRotationMatrix().transpose() * start.rotation.toRotationMatrix()).norm(), 1e-12);
    EXPECT_LT((end.angular_velocity - start.angular_velocity).norm(), 1e-9);
    EXPECT_LT((spline.position(s, 1.0).position - spline.position(s + 1, 0.0).position).norm(), 1e-12);
    EXPECT_LT((spline.position(s, 1.0).acceleration - spline.position(s + 1, 0.0).acceleration).norm(), 1e-9);
  }
  // The knots' times: segment s's start is where control point s + 1 weighs most.
  SplineKnots knots{2.0, 0.05, 10};
  EXPECT_EQ(knots.segments(), 7);
  EXPECT_EQ(knots.segmentAt(2.0 + 3.5 * 0.05).index, 3);
  EXPECT_NEAR(knots.segmentAt(2.0 + 3.5 * 0.05).u, 0.5, 1e-9);
  EXPECT_EQ(knots.segmentAt(100.0).index, 6);
}

// The IMU sample's residual on its own: zero where the spline, the biases and gravity predict the sample;
// the sample's error in its sigmas where it is off by a known amount.
TEST(CameraImuResiduals, AnImuSampleAgainstTheSpline) {
  const RandomSpline spline(4, 11);
  const double u = 0.4, weight = 0.25, gravity = 9.80665;
  const Eigen::Vector3d gyro_bias0(0.01, -0.02, 0.005), gyro_bias1(0.012, -0.018, 0.004);
  const Eigen::Vector3d accel_bias0(0.05, 0.0, -0.03), accel_bias1(0.04, 0.01, -0.02);
  const Eigen::Vector3d down = Eigen::Vector3d(0.1, 0.95, -0.2).normalized();
  const SplineRotation<double> rotation = spline.rotation(0, u);
  const SplinePosition<double> position = spline.position(0, u);
  const Eigen::Vector3d rate = rotation.angular_velocity + 0.75 * gyro_bias0 + 0.25 * gyro_bias1;
  const Eigen::Vector3d force = rotation.rotation.conjugate() * (position.acceleration - gravity * down) + 0.75 * accel_bias0 + 0.25 * accel_bias1;
  const auto evaluate = [&](const Eigen::Vector3d& measured_rate, const Eigen::Vector3d& measured_force) {
    const ImuSampleResidual residual(measured_rate, measured_force, u, spline.spacing, weight, 0.003, 0.03, gravity);
    Eigen::Matrix<double, 6, 1> r;
    residual(spline.rotations[0].coeffs().data(), spline.rotations[1].coeffs().data(), spline.rotations[2].coeffs().data(),
             spline.rotations[3].coeffs().data(), spline.positions[0].data(), spline.positions[1].data(), spline.positions[2].data(),
             spline.positions[3].data(), gyro_bias0.data(), gyro_bias1.data(), accel_bias0.data(), accel_bias1.data(), down.data(), r.data());
    return r;
  };
  EXPECT_LT(evaluate(rate, force).norm(), 1e-9);
  const Eigen::Matrix<double, 6, 1> off = evaluate(rate + Eigen::Vector3d(0.006, 0.0, 0.0), force + Eigen::Vector3d(0.0, 0.0, -0.09));
  Eigen::Matrix<double, 6, 1> expected;
  expected << -2.0, 0.0, 0.0, 0.0, 0.0, 3.0;  // measured - predicted, in sigmas, with the sign of predicted - measured
  EXPECT_LT((off - expected).norm(), 1e-9) << off.transpose();
  // Two bias knots a random walk apart.
  const BiasRandomWalkResidual walk(0.002);
  double w[3];
  walk(gyro_bias0.data(), gyro_bias1.data(), w);
  EXPECT_NEAR(w[0], 1.0, 1e-12);
  EXPECT_NEAR(w[1], 1.0, 1e-12);
  EXPECT_NEAR(w[2], -0.5, 1e-12);
}

// A frame's view against the spline: zero where the spline and the camera's pose in the body put the board
// where PnP did; whitened by its covariance; its derivative in the clock offset is the motion's.
TEST(CameraImuResiduals, AViewAgainstTheSplineAtItsStampPlusTheOffset) {
  const RandomSpline spline(4, 12);
  const Eigen::Isometry3d camera_in_body = poseFromTranslationQuaternion({0.02, -0.03, 0.01}, Eigen::Quaterniond(so3Exp({0.1, -1.5, 0.2})));
  const double segment_start = 10.0, stamp = 10.02, offset = 0.005;  // u = 0.5
  const auto bodyAt = [&](double u) {
    Eigen::Isometry3d body = Eigen::Isometry3d::Identity();
    body.linear() = spline.rotation(0, u).rotation.toRotationMatrix();
    body.translation() = spline.position(0, u).position;
    return body;
  };
  PlaneMeasurement view;
  view.sensor_from_pattern = (bodyAt(0.5) * camera_in_body).inverse();
  view.pose_covariance = Eigen::Matrix<double, 6, 6>::Identity() * 1e-6;  // 1 mrad, 1 mm
  const SplineCameraViewResidual residual(view, stamp, segment_start, spline.spacing);
  const Eigen::Quaterniond q(camera_in_body.linear());
  const Eigen::Vector3d t = camera_in_body.translation();
  const auto evaluate = [&](double time_offset) {
    Eigen::Matrix<double, 6, 1> r;
    residual(spline.rotations[0].coeffs().data(), spline.rotations[1].coeffs().data(), spline.rotations[2].coeffs().data(),
             spline.rotations[3].coeffs().data(), spline.positions[0].data(), spline.positions[1].data(), spline.positions[2].data(),
             spline.positions[3].data(), q.coeffs().data(), t.data(), &time_offset, r.data());
    return r;
  };
  EXPECT_LT(evaluate(offset).norm(), 1e-6);
  // The view 1 mm further along the camera's x: -1 sigma there (predicted - measured).
  PlaneMeasurement moved = view;
  moved.sensor_from_pattern.translation() += Eigen::Vector3d(0.001, 0.0, 0.0);
  const SplineCameraViewResidual off(moved, stamp, segment_start, spline.spacing);
  Eigen::Matrix<double, 6, 1> r;
  double o = offset;
  off(spline.rotations[0].coeffs().data(), spline.rotations[1].coeffs().data(), spline.rotations[2].coeffs().data(),
      spline.rotations[3].coeffs().data(), spline.positions[0].data(), spline.positions[1].data(), spline.positions[2].data(),
      spline.positions[3].data(), q.coeffs().data(), t.data(), &o, r.data());
  EXPECT_NEAR(r[3], -1.0, 1e-6);
  EXPECT_LT(r.head<3>().norm() + r.tail<2>().norm(), 1e-6);
  // d residual / d offset by the jets against central differences.
  using Jet = ceres::Jet<double, 1>;
  std::vector<std::array<Jet, 4>> jq(4);
  std::vector<std::array<Jet, 3>> jp(4);
  for (int k = 0; k < 4; ++k) {
    for (int i = 0; i < 4; ++i) jq[k][i] = Jet(spline.rotations[k].coeffs()[i]);
    for (int i = 0; i < 3; ++i) jp[k][i] = Jet(spline.positions[k][i]);
  }
  std::array<Jet, 4> jcq;
  std::array<Jet, 3> jct;
  for (int i = 0; i < 4; ++i) jcq[i] = Jet(q.coeffs()[i]);
  for (int i = 0; i < 3; ++i) jct[i] = Jet(t[i]);
  const Jet joffset(offset, 0);
  Jet jr[6];
  residual(jq[0].data(), jq[1].data(), jq[2].data(), jq[3].data(), jp[0].data(), jp[1].data(), jp[2].data(), jp[3].data(), jcq.data(),
           jct.data(), &joffset, jr);
  const double h = 1e-6;
  const Eigen::Matrix<double, 6, 1> numeric = (evaluate(offset + h) - evaluate(offset - h)) / (2 * h);
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(jr[i].v[0], numeric[i], 1e-3 * (1.0 + std::abs(numeric[i]))) << i;
  EXPECT_GT(numeric.norm(), 1.0);  // the offset moves the view: it is what fixes the offset

  // The same view by its corners through a wide-angle lens: zero where projected, a corner 0.6 px off
  // gives 2 sigmas of 0.3 px in that coordinate alone.
  const PinholeCamera camera{640, 480, 460.0, 460.0, 319.5, 239.5, 1000.0};
  const LensDistortion lens{DistortionModel::kPlumbBob, {-0.28, 0.07, 0.0002, -0.0001, 0.0}};
  const Eigen::Isometry3d camera_from_board = view.sensor_from_pattern;
  std::vector<Eigen::Vector3d> corners;
  std::vector<Eigen::Vector2d> pixels;
  for (const Eigen::Vector3d& c : TargetPattern{3, 4, 0.05}.corners()) {
    corners.push_back(c);
    // The spline's random pose need not face the board: put the corners in front of the camera.
    pixels.push_back(projectThroughLens(camera, lens, camera_from_board * c));
  }
  ASSERT_GT((camera_from_board * corners.front()).z(), 0.0) << "the random spline's view is behind the board";
  pixels[5].y() += 0.6;
  const SplineCornerResidual by_corners(pixels, corners, camera, lens, 0.3, stamp, segment_start, spline.spacing);
  std::vector<double> px(2 * corners.size());
  double o2 = offset;
  by_corners(spline.rotations[0].coeffs().data(), spline.rotations[1].coeffs().data(), spline.rotations[2].coeffs().data(),
             spline.rotations[3].coeffs().data(), spline.positions[0].data(), spline.positions[1].data(), spline.positions[2].data(),
             spline.positions[3].data(), q.coeffs().data(), t.data(), &o2, px.data());
  for (std::size_t i = 0; i < px.size(); ++i) EXPECT_NEAR(px[i], i == 11 ? -2.0 : 0.0, 1e-6) << i;
}

WavedCameraImuOptions sessionOptions(std::uint32_t seed, double duration, double time_offset) {
  WavedCameraImuOptions options;
  options.seed = seed;
  options.duration = duration;
  options.time_offset = time_offset;
  return options;
}

TEST(CameraImuCalibration, WavedSessionsGiveTheCameraInTheImuAndTheClockOffset) {
  const double offsets[] = {0.005, -0.012, 0.02};
  for (std::uint32_t seed = 1; seed <= 3; ++seed) {
    const WavedCameraImuSession session = simulateWavedCameraImu(sessionOptions(seed, 60.0, offsets[seed - 1]));
    ASSERT_GT(session.views.size(), session.frames * 0.6) << "seed " << seed;
    const CameraImuResult result = calibrateCameraImu(session.views, session.imu, ImuNoise{});
    const Eigen::Isometry3d error = session.camera_in_imu.inverse() * result.camera_in_imu;
    const double gyro_sigma = ImuNoise{}.gyro_noise_density * std::sqrt(200.0);
    SCOPED_TRACE("seed " + std::to_string(seed));
    EXPECT_LT(error.translation().norm(), 0.001);
    EXPECT_LT(rotationAngle(error), 0.001);
    EXPECT_NEAR(result.time_offset, session.time_offset, 0.0005);
    EXPECT_LT((result.gyro_bias - session.gyro_bias).cwiseAbs().maxCoeff(), gyro_sigma);
    // The closed forms the solve started from: the offset within a few ms, the rotation within a few degrees.
    EXPECT_NEAR(result.initial_time_offset, session.time_offset, 0.005);
    EXPECT_LT(so3Log(result.initial_rotation.transpose() * session.camera_in_imu.linear()).norm(), 0.05);
    // The corners through the lens instead of the PnP poses: the same to first order.
    CameraImuOptions by_corners;
    by_corners.camera_model = CameraImuCameraModel{WavedCameraImuOptions{}.camera, WavedCameraImuOptions{}.lens, WavedCameraImuOptions{}.pattern};
    if (seed == 1) {
      const CameraImuResult cornered = calibrateCameraImu(session.views, session.imu, ImuNoise{}, by_corners);
      EXPECT_EQ(cornered.views_by_corners, cornered.views);
      EXPECT_LT((cornered.camera_in_imu.translation() - result.camera_in_imu.translation()).norm(), 0.0002);
      EXPECT_NEAR(cornered.time_offset, result.time_offset, 0.0001);
    }
    // Its stated uncertainty covers the error and it is not withheld.
    EXPECT_TRUE(result.withheld.empty()) << result.withheld;
    EXPECT_LT(error.translation().norm(), 4 * result.sigma.head<3>().norm());
    EXPECT_LT(std::abs(result.time_offset - session.time_offset), 4 * result.time_offset_sigma);
    EXPECT_LT(result.gyro_rms, 1.5 * gyro_sigma);
  }
}

// Frames as a detector gives them: corners found the other way round (half a turn about the board's normal),
// and PnP's mirrored solution of a board seen square on (a turn away and back): the first turned back, the
// second left out, the result as without them.
TEST(CameraImuCalibration, BoardsFoundTheOtherWayRoundOrMirroredByPnPAreTakenCareOf) {
  const WavedCameraImuSession session = simulateWavedCameraImu(sessionOptions(1, 20.0, 0.005));
  const CameraImuResult clean = calibrateCameraImu(session.views, session.imu, ImuNoise{});
  EXPECT_EQ(clean.turned_views, 0);
  EXPECT_EQ(clean.left_out_views, 0);
  std::vector<CameraImuView> views = session.views;
  for (std::size_t k = 100; k < 200; ++k) views[k].board = turnedHalfway(views[k].board);  // found the other way from frame 100 to 199
  views[250].board.sensor_from_pattern.linear() =
      views[250].board.sensor_from_pattern.linear() * so3Exp(Eigen::Vector3d(1.1, 0.4, 0.0));  // a mirrored PnP pose
  const CameraImuResult result = calibrateCameraImu(views, session.imu, ImuNoise{});
  EXPECT_EQ(result.turned_views, 100);
  EXPECT_EQ(result.left_out_views, 1);
  EXPECT_LT((result.camera_in_imu.translation() - clean.camera_in_imu.translation()).norm(), 0.0001);
  EXPECT_NEAR(result.time_offset, clean.time_offset, 0.0001);
}

// A recording that starts with the rig at rest while the board is moved before it (the still poses of the
// rig's other sensors): those views are not of a fixed board and are not used.
TEST(CameraImuCalibration, ViewsWhileTheRigRestsAreNotUsed) {
  const WavedCameraImuSession session = simulateWavedCameraImu(sessionOptions(1, 20.0, 0.005));
  const CameraImuResult clean = calibrateCameraImu(session.views, session.imu, ImuNoise{});
  std::vector<CameraImuView> views;
  std::vector<ImuSample> imu;
  std::mt19937 random(7);
  std::normal_distribution<double> noise(0.0, 0.0034);
  for (double t = -12.0; t < -0.5; t += 0.005) {  // at rest: the gyro's noise, gravity
    ImuSample s = session.imu.front();
    s.stamp = t;
    s.angular_velocity = session.gyro_bias + Eigen::Vector3d(noise(random), noise(random), noise(random));
    imu.push_back(s);
  }
  for (double t = -12.0; t < -1.0; t += 0.05) {  // the board carried from pose to pose before it
    CameraImuView v = session.views.front();
    v.stamp = t;
    v.board.sensor_from_pattern.translation() += Eigen::Vector3d(0.1 * std::sin(t), 0.05 * std::cos(2 * t), 0.0);
    v.board.sensor_from_pattern.linear() = v.board.sensor_from_pattern.linear() * so3Exp(Eigen::Vector3d(0.2 * std::sin(t), 0.0, 0.1));
    views.push_back(v);
  }
  views.insert(views.end(), session.views.begin(), session.views.end());
  imu.insert(imu.end(), session.imu.begin(), session.imu.end());
  const CameraImuResult result = calibrateCameraImu(views, imu, ImuNoise{});
  EXPECT_GE(result.views_at_rest, 200);
  EXPECT_LT((result.camera_in_imu.translation() - clean.camera_in_imu.translation()).norm(), 0.0002);
  EXPECT_NEAR(result.time_offset, clean.time_offset, 0.0001);
}

void expectRefused(WavedMotion motion, const std::string& phrase) {
  WavedCameraImuOptions options = sessionOptions(4, 12.0, 0.01);
  options.motion = motion;
  const WavedCameraImuSession session = simulateWavedCameraImu(options);
  try {
    calibrateCameraImu(session.views, session.imu, ImuNoise{});
    FAIL() << "a motion that cannot fix the rotation was calibrated";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(phrase), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("turn the rig about all three axes"), std::string::npos) << e.what();
  }
}

TEST(CameraImuCalibration, MotionsThatCannotFixItAreRefusedWithTheReason) {
  expectRefused(WavedMotion::kNoTurns, "the camera never turns");
  expectRefused(WavedMotion::kOneAxisTurns, "the camera turns about one axis only");
}

TEST(CameraImuCalibration, BadInputIsNamed) {
  const WavedCameraImuSession session = simulateWavedCameraImu(sessionOptions(5, 6.0, 0.0));
  const std::vector<CameraImuView> few(session.views.begin(), session.views.begin() + 10);
  const auto expectRefusal = [](const std::vector<CameraImuView>& views, const std::vector<ImuSample>& imu, const std::string& message) {
    try {
      calibrateCameraImu(views, imu, ImuNoise{});
      ADD_FAILURE() << "calibrated: " << message;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()), message);
    }
  };
  expectRefusal(few, session.imu,
                "camera-IMU calibration: 10 camera views of the board, at least 20 are needed (wave the rig before the board for 1-3 minutes)");
  std::vector<CameraImuView> swapped = session.views;
  std::swap(swapped[3], swapped[4]);
  expectRefusal(swapped, session.imu, "camera-IMU calibration: camera view 4's stamp is not after the one before");
  // An IMU from other minutes: its angular speeds do not follow the camera's.
  std::vector<ImuSample> late = session.imu;
  for (ImuSample& s : late) s.stamp += 3.0;
  try {
    calibrateCameraImu(session.views, late, ImuNoise{});
    FAIL() << "streams that do not overlap were calibrated";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("do the two streams come from the same rig and the same minutes?"), std::string::npos) << e.what();
  }
}

// [x, y, z, qx, qy, qz, qw] (ground_truth.yaml), and an entry's translation and rotation (calibration.yaml).
Eigen::Isometry3d poseFromList(const YAML::Node& list) {
  return poseFromTranslationQuaternion({list[0].as<double>(), list[1].as<double>(), list[2].as<double>()},
                                       Eigen::Quaterniond(list[6].as<double>(), list[3].as<double>(), list[4].as<double>(), list[5].as<double>()));
}
Eigen::Isometry3d poseOfEntry(const YAML::Node& entry) {
  const YAML::Node t = entry["translation"], q = entry["rotation"];
  return poseFromTranslationQuaternion({t[0].as<double>(), t[1].as<double>(), t[2].as<double>()},
                                       Eigen::Quaterniond(q[3].as<double>(), q[0].as<double>(), q[1].as<double>(), q[2].as<double>()));
}

// Through the tools as a user runs them: a waved session recorded as a bag (rendered images, sensor_msgs/Imu),
// calibrate_rig, its files against the truth.
TEST(CameraImuCalibration, AWavedSessionThroughTheTools) {
  const std::string folder = vocal_test::makeTempFolder("cli_camera_imu");
  vocal_test::RunResult r = vocal_test::runTool("simulate_calibration_session " + folder + " --waved-imu --seconds 30 --seed 2 --time-offset -0.012 --compressed");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = vocal_test::runTool("calibrate_rig " + folder + "/rig.yaml " + folder + "/session.bag --quiet --output-dir " + folder);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("imu 'imu' against camera 'camera': the board in "), std::string::npos) << r.output;
  const YAML::Node truth = YAML::LoadFile(folder + "/ground_truth.yaml");
  const Eigen::Isometry3d camera_in_imu = poseFromList(truth["camera_in_imu"]);
  // Kalibr's layout: T_cam_imu and timeshift_cam_imu.
  const YAML::Node chain = YAML::LoadFile(folder + "/camchain-imucam.yaml");
  Eigen::Matrix4d t_cam_imu;
  for (int row = 0; row < 4; ++row)
    for (int col = 0; col < 4; ++col) t_cam_imu(row, col) = chain["cam0"]["T_cam_imu"][row][col].as<double>();
  const Eigen::Isometry3d kalibr_error = Eigen::Isometry3d(t_cam_imu) * camera_in_imu;
  EXPECT_LT(kalibr_error.translation().norm(), 0.001);
  EXPECT_LT(rotationAngle(kalibr_error), 0.001);
  EXPECT_NEAR(chain["cam0"]["timeshift_cam_imu"].as<double>(), truth["time_offset"].as<double>(), 0.0005);
  EXPECT_EQ(chain["cam0"]["rostopic"].as<std::string>(), "/camera/image_raw/compressed");
  // The IMU in the rig, through the camera the rig gives.
  const YAML::Node result = YAML::LoadFile(folder + "/calibration.yaml");
  const YAML::Node imu = result["imus"][0];
  EXPECT_EQ(imu["name"].as<std::string>(), "imu");
  EXPECT_TRUE(imu["published"].as<bool>());
  const Eigen::Isometry3d rig_error = poseFromList(truth["imu_in_rig"]).inverse() * poseOfEntry(imu);
  EXPECT_LT(rig_error.translation().norm(), 0.001);
  EXPECT_LT(rotationAngle(rig_error), 0.001);
  EXPECT_NE(vocal_test::readText(folder + "/calibration.launch").find("base_link imu_link"), std::string::npos);

  // A rig turned about its optical axis only: withheld with the reason, nothing published, exit 1.
  const std::string one_axis = vocal_test::makeTempFolder("cli_camera_imu_one_axis");
  r = vocal_test::runTool("simulate_calibration_session " + one_axis + " --waved-imu --seconds 10 --motion one-axis");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = vocal_test::runTool("calibrate_rig " + one_axis + "/rig.yaml " + one_axis + "/session.bag --quiet --output-dir " + one_axis);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("withheld: imu 'imu' not calibrated: camera-IMU calibration: the camera turns about one axis only"), std::string::npos)
      << r.output;
  EXPECT_NE(vocal_test::readText(one_axis + "/calibration.urdf").find("<!-- imu_link withheld: not calibrated: "), std::string::npos);
}

// `camera` of the still-pose or arm session in `session` waved with an IMU in a recording of its own (`board`:
// the session's board as simulate_calibration_session's options), the IMU added to the session's rig
// (rig_imu.yaml), and calibrate_rig on both into `session`: its run.
vocal_test::RunResult calibrateWithWavedImu(const std::string& session, const std::string& waved, const std::string& camera,
                                            const std::string& board) {
  vocal_test::RunResult r = vocal_test::runTool("simulate_calibration_session " + waved + " --waved-imu --seconds 20 --camera-name " + camera +
                                                " --seed 4 " + board);
  if (r.exit_code != 0) return r;
  vocal_test::writeText(session + "/rig_imu.yaml", vocal_test::readText(session + "/rig.yaml") +
                                                       "  - {name: imu, type: imu, frame_id: imu_link, imu_topic: /imu/data, camera: " + camera +
                                                       "}\n");
  return vocal_test::runTool("calibrate_rig " + session + "/rig_imu.yaml " + session + "/session.bag --imu-bag " + waved +
                             "/session.bag --quiet --output-dir " + session);
}

// One rig: a still-pose session of an RGB-D camera (the reference), a lidar and a camera, and the camera
// waved with an IMU in a recording of its own; every sensor, the IMU included, in base_link.
TEST(CameraImuCalibration, AnImuJoinsARigCalibratedAtStillPoses) {
  const std::string still = vocal_test::makeTempFolder("cli_imu_rig_still"), waved = vocal_test::makeTempFolder("cli_imu_rig_waved");
  vocal_test::RunResult r =
      vocal_test::runTool("simulate_calibration_session " + still + " --rgbd 1 --lidar 1 --laser 0 --camera 1 --poses 8 --seed 3");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = calibrateWithWavedImu(still, waved, "camera0", "--pattern-cols 8 --pattern-rows 6 --square 0.06 --board-width 0.9 --board-height 0.7");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // The truth: camera0's mount from the still session's, the camera in the IMU from the waved one's.
  const RigDescription truth = readRigDescription(still + "/ground_truth.yaml");
  const Eigen::Isometry3d imu_truth = *truth.sensors[2].pose * poseFromList(YAML::LoadFile(waved + "/ground_truth.yaml")["camera_in_imu"]).inverse();
  const YAML::Node result = YAML::LoadFile(still + "/calibration.yaml");
  const Eigen::Isometry3d camera_error = truth.sensors[2].pose->inverse() * poseOfEntry(result["sensors"][2]);
  const Eigen::Isometry3d imu_error = imu_truth.inverse() * poseOfEntry(result["imus"][0]);
  // The IMU as right as the camera it is placed through, to a millimetre / milliradian more.
  EXPECT_LT(imu_error.translation().norm(), camera_error.translation().norm() + 0.001 + 0.05 * rotationAngle(camera_error));
  EXPECT_LT(rotationAngle(imu_error), rotationAngle(camera_error) + 0.001);
  EXPECT_LT(imu_error.translation().norm(), 0.005);
  EXPECT_NE(vocal_test::readText(still + "/calibration.launch").find("base_link imu_link"), std::string::npos);
  EXPECT_NE(vocal_test::readText(still + "/calibration.launch").find("base_link lidar0"), std::string::npos);
  // The IMU as the rig's reference (its pose given, the RGB-D camera's not): calibrated first, its camera
  // placed through it, the others from the still poses in its frame.
  RigDescription imu_reference = readRigDescription(still + "/rig_imu.yaml");
  imu_reference.sensors[0].pose.reset();
  imu_reference.imus[0].pose = imu_truth;
  writeRigDescription(still + "/rig_imu_reference.yaml", imu_reference);
  const std::string placed = vocal_test::makeTempFolder("cli_imu_rig_reference");
  r = vocal_test::runTool("calibrate_rig " + still + "/rig_imu_reference.yaml " + still + "/session.bag --imu-bag " + waved +
                          "/session.bag --quiet --output-dir " + placed);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("(placed through the reference imu 'imu': the still poses' reference)"), std::string::npos) << r.output;
  const YAML::Node by_imu = YAML::LoadFile(placed + "/calibration.yaml");
  for (int s = 0; s < 3; ++s) {
    const Eigen::Isometry3d error = truth.sensors[s].pose->inverse() * poseOfEntry(by_imu["sensors"][s]);
    EXPECT_LT(error.translation().norm(), 0.003) << s;
    EXPECT_LT(rotationAngle(error), 0.003) << s;
  }
  EXPECT_LT((poseOfEntry(by_imu["imus"][0]).matrix() - imu_truth.matrix()).norm(), 1e-6);  // where the rig gives it

  r = vocal_test::runTool("calibrate_rig " + still + "/rig.yaml " + still + "/session.bag --imu-bag " + waved + "/session.bag --quiet");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(r.output, "calibrate_rig: error: option --imu-bag: the rig has no sensor of type imu\n");
}

// A camera on an arm's tool with an IMU beside it (a wrist camera with its own IMU): the camera from the
// arm's still poses, the IMU from a waved recording of its own, placed through the camera in the tool's
// frame; a head camera's IMU in the head's link. An IMU as an arm rig's reference is refused, naming what
// to give instead.
TEST(CameraImuCalibration, AnImuJoinsAnArmsRigOnTheToolOrAHead) {
  const std::string arm = vocal_test::makeTempFolder("cli_imu_arm"), waved = vocal_test::makeTempFolder("cli_imu_arm_waved");
  vocal_test::RunResult r = vocal_test::runTool("simulate_calibration_session " + arm + " --eye-in-hand --poses 12 --seed 1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string arm_board = "--pattern-cols 10 --pattern-rows 7 --square 0.03 --board-width 0.36 --board-height 0.27";
  r = calibrateWithWavedImu(arm, waved, "arm_camera", arm_board);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("imu in arm_tool"), std::string::npos) << r.output;
  const Eigen::Isometry3d camera_truth = poseOfEntry(YAML::LoadFile(arm + "/ground_truth.yaml")["sensors"]["arm_camera"]["pose"]);
  const Eigen::Isometry3d imu_truth = camera_truth * poseFromList(YAML::LoadFile(waved + "/ground_truth.yaml")["camera_in_imu"]).inverse();
  const YAML::Node result = YAML::LoadFile(arm + "/calibration.yaml");
  ASSERT_TRUE(result["imus"]) << vocal_test::readText(arm + "/calibration.yaml");
  EXPECT_EQ(result["imus"][0]["parent"].as<std::string>(), "arm_tool");
  EXPECT_TRUE(result["imus"][0]["published"].as<bool>());
  const Eigen::Isometry3d imu_error = imu_truth.inverse() * poseOfEntry(result["imus"][0]);
  EXPECT_LT(imu_error.translation().norm(), 0.003);
  EXPECT_LT(rotationAngle(imu_error), 0.003);
  EXPECT_NE(vocal_test::readText(arm + "/calibration.launch").find("arm_tool imu_link"), std::string::npos);
  EXPECT_NE(vocal_test::readText(arm + "/calibration.urdf").find("<parent link=\"arm_tool\"/>\n  <child link=\"imu_link\"/>"), std::string::npos)
      << vocal_test::readText(arm + "/calibration.urdf");

  // A head camera's IMU beside the arm (a mobile manipulator's): in the head's tilt link, as right as the
  // camera's mount there (which takes up the held tilt offset), to a millimetre / milliradian more.
  const std::string head = vocal_test::makeTempFolder("cli_imu_head"), head_waved = vocal_test::makeTempFolder("cli_imu_head_waved");
  r = vocal_test::runTool("simulate_calibration_session " + head + " --eye-to-hand --arm --head --poses 12 --seed 1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = calibrateWithWavedImu(head, head_waved, "head_camera", arm_board);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const Eigen::Isometry3d head_camera_truth = poseOfEntry(YAML::LoadFile(head + "/ground_truth.yaml")["sensors"]["head_camera"]["pose"]);
  const Eigen::Isometry3d head_imu_truth =
      head_camera_truth * poseFromList(YAML::LoadFile(head_waved + "/ground_truth.yaml")["camera_in_imu"]).inverse();
  const YAML::Node head_result = YAML::LoadFile(head + "/calibration.yaml");
  EXPECT_EQ(head_result["imus"][0]["parent"].as<std::string>(), "head_tilt_link");
  const Eigen::Isometry3d head_camera_error = head_camera_truth.inverse() * poseOfEntry(head_result["sensors"][1]);
  const Eigen::Isometry3d head_imu_error = head_imu_truth.inverse() * poseOfEntry(head_result["imus"][0]);
  EXPECT_LT(head_imu_error.translation().norm(), head_camera_error.translation().norm() + 0.001 + 0.05 * rotationAngle(head_camera_error));
  EXPECT_LT(rotationAngle(head_imu_error), rotationAngle(head_camera_error) + 0.001);
  EXPECT_NE(vocal_test::readText(head + "/calibration.launch").find("head_tilt_link imu_link"), std::string::npos);

  RigDescription imu_reference = readRigDescription(arm + "/rig_imu.yaml");
  imu_reference.imus[0].pose = imu_truth;
  writeRigDescription(arm + "/rig_imu_reference.yaml", imu_reference);
  r = vocal_test::runTool("calibrate_rig " + arm + "/rig_imu_reference.yaml " + arm + "/session.bag --imu-bag " + waved + "/session.bag --quiet");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(r.output, "calibrate_rig: error: " + arm + "/rig_imu_reference.yaml: imu 'imu': its 'pose' makes it the reference of a rig with "
                      "joints or an arm, which is not supported: give the pose of a sensor fixed in arm_base (or none), and the IMU is placed "
                      "through its camera\n");
}

TEST(CameraImuCalibration, TheRigsImuEntryIsChecked) {
  const std::string folder = vocal_test::makeTempFolder("rig_imu_checks");
  const std::string head = "reference_frame: base_link\ntarget: {type: checkerboard, rows: 6, cols: 7, square_size: 0.05}\nsensors:\n"
                           "  - {name: cam, type: camera, frame_id: cam, image_topic: /i, camera_info_topic: /c, pose: [0, 0, 0, 0, 0, 0, 1]}\n";
  const auto refusal = [&](const std::string& imu_line) {
    vocal_test::writeText(folder + "/rig.yaml", head + imu_line);
    try {
      readRigDescription(folder + "/rig.yaml");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const std::string file = folder + "/rig.yaml";
  EXPECT_EQ(refusal("  - {name: imu, type: imu, frame_id: imu}\n"),
            file + ": sensors[1] 'imu': an imu sensor needs 'imu_topic' (its sensor_msgs/Imu)");
  EXPECT_EQ(refusal("  - {name: imu, type: imu, frame_id: imu, imu_topic: /imu, camera: left}\n"),
            file + ": imu 'imu': its camera 'left' is no camera of the rig");
  EXPECT_EQ(refusal("  - {name: imu, type: imu, frame_id: imu, imu_topic: /imu, gyroscope_noise_density: -1}\n"),
            file + ": sensors[1] 'imu': 'gyroscope_noise_density' must be a positive number (got -1)");
  EXPECT_EQ(refusal("  - {name: imu, type: imu, frame_id: imu, imu_topic: /imu, pose: [0, 0, 0, 0, 0, 0, 1]}\n"),
            file + ": imu 'imu': its 'pose' makes it the rig's reference, and so does the pose of sensor 'cam': give one reference's pose");
  EXPECT_EQ(refusal("  - {name: imu, type: imu, frame_id: imu, imu_topic: /imu, rate: 200}\n"),
            file + ": sensors[1] 'imu': unknown key 'rate'");
  // Read back as written.
  vocal_test::writeText(file, head + "  - {name: imu, type: imu, frame_id: imu, imu_topic: /imu, accelerometer_noise_density: 0.004}\n");
  const RigDescription rig = readRigDescription(file);
  ASSERT_EQ(rig.imus.size(), 1u);
  EXPECT_EQ(rig.imus[0].camera, 0);
  EXPECT_EQ(rig.imus[0].noise.accel_noise_density, 0.004);
  writeRigDescription(folder + "/again.yaml", rig);
  const RigDescription again = readRigDescription(folder + "/again.yaml");
  ASSERT_EQ(again.imus.size(), 1u);
  EXPECT_EQ(again.imus[0].imu_topic, "/imu");
  EXPECT_EQ(again.imus[0].noise.accel_noise_density, 0.004);
}

}  // namespace
}  // namespace vocal
