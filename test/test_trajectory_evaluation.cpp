#include <gtest/gtest.h>

#include "test_support.h"

#include <cmath>

#include "vocal/core/errors.h"
#include "vocal/core/se3.h"
#include "vocal/core/trajectory_evaluation.h"
#include "vocal/simulation/synthetic_trajectory.h"

namespace {
vocal::Trajectory groundTruth(int frames = 300) {
  const vocal::SyntheticScene scene = vocal::SyntheticScene::make(vocal::SceneVariant::kIndoorRoom);
  vocal::SyntheticTrajectoryOptions options;
  options.frames = frames;
  return vocal::generateSyntheticTrajectory(scene.workspace(), options);
}
}  // namespace

TEST(TrajectoryEvaluation, SelfIsZero) {
  const vocal::Trajectory truth = groundTruth();
  const vocal::AteResult ate = vocal::computeAte(truth, truth);
  EXPECT_EQ(ate.pairs, truth.size());
  EXPECT_LT(ate.rmse, 1e-9);
  EXPECT_LT(ate.max, 1e-9);
  const vocal::RpeResult rpe = vocal::computeRpe(truth, truth);
  EXPECT_GT(rpe.pairs, 200u);
  EXPECT_LT(rpe.translation_rmse_m_per_s, 1e-9);
  EXPECT_LT(rpe.rotation_rmse_deg_per_s, 1e-6);
}

TEST(TrajectoryEvaluation, RigidlyMovedCopyAlignsToZero) {
  const vocal::Trajectory truth = groundTruth();
  vocal::Vector6d twist;
  twist << 3.0, -1.0, 0.5, 0.2, -0.7, 1.9;
  const Eigen::Isometry3d offset = vocal::se3Exp(twist);
  vocal::Trajectory moved = truth;
  for (vocal::StampedPose& p : moved) p.pose = offset * p.pose;
  const vocal::AteResult ate = vocal::computeAte(truth, moved);
  EXPECT_LT(ate.rmse, 1e-9);
  EXPECT_TRUE((ate.alignment * offset).isApprox(Eigen::Isometry3d::Identity(), 1e-9));
  // Relative motion does not see a global offset at all.
  EXPECT_LT(vocal::computeRpe(truth, moved).translation_rmse_m_per_s, 1e-9);
}

// Positions on a circle, every other one displaced by +-d along z: the alternating error has zero
// mean and no correlation with the circle, so the best alignment is the identity and every error is d.
TEST(TrajectoryEvaluation, AteEqualsAnalyticValue) {
  const int n = 120;
  const double d = 0.037;
  vocal::Trajectory truth, estimate;
  for (int i = 0; i < n; ++i) {
    const double angle = 2.0 * M_PI * i / n;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation() = Eigen::Vector3d(2.0 * std::cos(angle), 2.0 * std::sin(angle), 1.0);
    truth.push_back({100.0 + i * 0.1, pose});
    pose.translation().z() += (i % 2 ? d : -d);
    estimate.push_back({100.0 + i * 0.1, pose});
  }
  const vocal::AteResult ate = vocal::computeAte(truth, estimate);
  EXPECT_NEAR(ate.rmse, d, 1e-12);
  EXPECT_NEAR(ate.median, d, 1e-12);
  EXPECT_NEAR(ate.max, d, 1e-12);
}

// A constant drift velocity r in the world adds r * delta to every relative motion of length delta,
// and a constant body-frame spin w adds a rotation of w * delta: RPE = r m/s and w deg/s.
TEST(TrajectoryEvaluation, RpeEqualsAnalyticDrift) {
  const vocal::Trajectory truth = groundTruth();
  const double drift = 0.05;                // m/s along world x
  const double spin = 2.0 * M_PI / 180.0;   // 2 deg/s about the camera's z
  vocal::Trajectory drifting = truth, spinning;
  for (vocal::StampedPose& p : drifting) p.pose.translation().x() += drift * (p.stamp - truth.front().stamp);
  const vocal::RpeResult translation = vocal::computeRpe(truth, drifting, 1.0);
  EXPECT_NEAR(translation.translation_rmse_m_per_s, drift, 1e-6);  // 30 frames are 1 s to a microsecond

  // Spin only: a fixed camera position, so the spin changes no relative translation.
  for (const vocal::StampedPose& p : truth) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = Eigen::AngleAxisd(spin * (p.stamp - truth.front().stamp), Eigen::Vector3d::UnitZ()).toRotationMatrix();
    spinning.push_back({p.stamp, pose});
  }
  vocal::Trajectory still = spinning;
  for (vocal::StampedPose& p : still) p.pose = Eigen::Isometry3d::Identity();
  const vocal::RpeResult rotation = vocal::computeRpe(still, spinning, 1.0);
  EXPECT_NEAR(rotation.rotation_rmse_deg_per_s, 2.0, 1e-4);
  EXPECT_LT(rotation.translation_rmse_m_per_s, 1e-12);
}

TEST(TrajectoryEvaluation, ErrorsForUnusableInput) {
  const vocal::Trajectory truth = groundTruth(30);
  vocal::Trajectory shifted = truth;
  for (vocal::StampedPose& p : shifted) p.stamp += 1000.0;
  EXPECT_EQ(vocal_test::inputErrorOf([&] { vocal::computeAte(truth, shifted); }),
            "ATE: only 0 estimate poses have a ground-truth pose within 0.020000 s (need at least 3); do the stamps "
            "use the same clock?");
  // 30 frames at 30 Hz span less than the 1 s RPE interval.
  EXPECT_THROW(vocal::computeRpe(truth, truth, 1.0), vocal::InputError);
  EXPECT_NO_THROW(vocal::computeRpe(truth, truth, 0.5));
}
