#include <gtest/gtest.h>

#include <random>

#include "vocal/core/se3.h"

using vocal::Vector6d;

TEST(Se3, ExpLogRoundTrip) {
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0.0, 1.0);
  for (double scale : {1e-14, 1e-7, 1e-3, 0.3, 2.5}) {
    for (int k = 0; k < 20; ++k) {
      Vector6d twist;
      for (int i = 0; i < 6; ++i) twist[i] = scale * n(rng);
      if (twist.tail<3>().norm() > 3.0) continue;  // log is unique only for angles below pi
      const Vector6d back = vocal::se3Log(vocal::se3Exp(twist));
      EXPECT_LT((back - twist).norm(), 1e-9 * std::max(1.0, scale)) << "scale " << scale;
    }
  }
}

TEST(Se3, AdjointMovesTwistsBetweenFrames) {
  std::mt19937 rng(4);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int k = 0; k < 20; ++k) {
    Vector6d pose_twist, twist;
    for (int i = 0; i < 6; ++i) pose_twist[i] = n(rng), twist[i] = 0.2 * n(rng);
    const Eigen::Isometry3d pose = vocal::se3Exp(pose_twist);
    const Eigen::Isometry3d moved = vocal::se3Exp(vocal::adjoint(pose) * twist);
    const Eigen::Isometry3d expected = pose * vocal::se3Exp(twist) * pose.inverse();
    EXPECT_LT((moved.matrix() - expected.matrix()).norm(), 1e-9);
  }
}

TEST(Se3, ExpMatchesAngleAxisAndPureTranslation) {
  Vector6d twist = Vector6d::Zero();
  twist.head<3>() = Eigen::Vector3d(1, 2, 3);
  EXPECT_TRUE(vocal::se3Exp(twist).translation().isApprox(Eigen::Vector3d(1, 2, 3)));
  twist.setZero();
  twist[5] = 0.5;
  const Eigen::Matrix3d expected = Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  EXPECT_TRUE(vocal::se3Exp(twist).linear().isApprox(expected, 1e-12));
  EXPECT_NEAR(vocal::rotationAngle(vocal::se3Exp(twist)), 0.5, 1e-12);
}

TEST(Se3, RotationAngleIsAccurateNearZeroAndPi) {
  for (double angle : {1e-9, 1e-4, 1.0, 3.1}) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = Eigen::AngleAxisd(angle, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    EXPECT_NEAR(vocal::rotationAngle(pose), angle, 1e-12 + 1e-9 * angle);
  }
}

TEST(Se3, InterpolationHitsEndpointsAndMidpoint) {
  Vector6d twist;
  twist << 0.4, -0.2, 1.0, 0.1, 0.3, -0.2;
  const Eigen::Isometry3d a = Eigen::Isometry3d::Identity();
  const Eigen::Isometry3d b = vocal::se3Exp(twist);
  EXPECT_TRUE(vocal::interpolatePose(a, b, 0.0).isApprox(a, 1e-12));
  EXPECT_TRUE(vocal::interpolatePose(a, b, 1.0).isApprox(b, 1e-12));
  const Eigen::Isometry3d mid = vocal::interpolatePose(a, b, 0.5);
  EXPECT_NEAR(vocal::rotationAngle(mid), 0.5 * vocal::rotationAngle(b), 1e-12);
}

TEST(Se3, OpticalFrameConvention) {
  const Eigen::Matrix3d R = vocal::bodyFromOpticalRotation();
  EXPECT_NEAR(R.determinant(), 1.0, 1e-15);
  EXPECT_TRUE((R * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::UnitX()));   // looks forward
  EXPECT_TRUE((R * Eigen::Vector3d::UnitX()).isApprox(-Eigen::Vector3d::UnitY()));  // right
  EXPECT_TRUE((R * Eigen::Vector3d::UnitY()).isApprox(-Eigen::Vector3d::UnitZ()));  // down
  // Positive pitch looks down.
  const Eigen::Vector3d forward = vocal::rotationFromRollPitchYaw(0, 0.3, 0) * Eigen::Vector3d::UnitX();
  EXPECT_LT(forward.z(), 0.0);
}

namespace vocal {
namespace {
TEST(Se3, RollPitchYawRoundTripsWithSmallAnglesForSmallTurns) {
  // Eigen's eulerAngles may give a turn near the identity as three angles near pi; URDF readers want ~0.
  const Eigen::Vector3d small = rollPitchYawFromRotation(rotationFromRollPitchYaw(-0.008, 0.012, -0.02));
  EXPECT_NEAR(small[0], -0.008, 1e-12);
  EXPECT_NEAR(small[1], 0.012, 1e-12);
  EXPECT_NEAR(small[2], -0.02, 1e-12);
  for (const Eigen::Vector3d& rpy : {Eigen::Vector3d(2.9, -1.2, -3.0), Eigen::Vector3d(-1.5708, 0.0, -1.5708), Eigen::Vector3d(0.3, 1.5707963267948966, 0.1)}) {
    const Eigen::Matrix3d r = rotationFromRollPitchYaw(rpy[0], rpy[1], rpy[2]);
    const Eigen::Vector3d back = rollPitchYawFromRotation(r);
    EXPECT_LT((rotationFromRollPitchYaw(back[0], back[1], back[2]) - r).norm(), 1e-7) << rpy.transpose();  // asin loses half the digits at pitch pi/2
    EXPECT_LE(std::abs(back[1]), M_PI / 2 + 1e-12);
  }
}
}  // namespace
}  // namespace vocal
