// Camera-IMU calibration: the body spline's derivatives, and waved sessions with known truth.
#include <gtest/gtest.h>

#include <random>

#include "vocal/calibration/solver/camera_imu_calibration.h"
#include "vocal/calibration/solver/cumulative_bspline.h"
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
    // Its stated uncertainty covers the error and it is not withheld.
    EXPECT_TRUE(result.withheld.empty()) << result.withheld;
    EXPECT_LT(error.translation().norm(), 4 * result.sigma.head<3>().norm());
    EXPECT_LT(std::abs(result.time_offset - session.time_offset), 4 * result.time_offset_sigma);
    EXPECT_LT(result.gyro_rms, 1.5 * gyro_sigma);
  }
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
  EXPECT_THROW(
      {
        try {
          calibrateCameraImu(few, session.imu, ImuNoise{});
        } catch (const InputError& e) {
          EXPECT_STREQ(e.what(), "camera-IMU calibration: 10 camera views of the board, at least 20 are needed (wave the rig before the board for 1-3 minutes)");
          throw;
        }
      },
      InputError);
  std::vector<CameraImuView> swapped = session.views;
  std::swap(swapped[3], swapped[4]);
  EXPECT_THROW(
      {
        try {
          calibrateCameraImu(swapped, session.imu, ImuNoise{});
        } catch (const InputError& e) {
          EXPECT_STREQ(e.what(), "camera-IMU calibration: camera view 4's stamp is not after the one before");
          throw;
        }
      },
      InputError);
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

}  // namespace
}  // namespace vocal
