// The local window's pose graph: the refined poses are the weighted least-squares fit of the links,
// in the links' own frames, with the oldest linked keyframe held.

#include <gtest/gtest.h>

#include "test_support.h"

#include "vocal/core/errors.h"
#include "vocal/core/se3.h"
#include "vocal/core/trajectory_evaluation.h"
#include "vocal/odometry/icp_dvo_odometry.h"
#include "vocal/odometry/keyframe_window.h"
#include "vocal/simulation/synthetic_sequence.h"

namespace {

Eigen::Isometry3d poseAt(double yaw, const Eigen::Vector3d& translation) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  pose.translation() = translation;
  return pose;
}

// Rotations held by a large information, translations weighted alike: the translations are then the
// linear least-squares fit, which the test works out by hand.
vocal::Matrix6d stiffRotation() {
  vocal::Vector6d diagonal;
  diagonal << 1.0, 1.0, 1.0, 1e8, 1e8, 1e8;
  return diagonal.asDiagonal();
}

vocal::KeyframeLink link(int from, int to, const Eigen::Isometry3d& from_T_to) {
  return {from, to, from_T_to, stiffRotation()};
}

}  // namespace

// Keyframes 1 and 2 are turned 90 degrees, so a link's error of 1 cm along the x of the keyframe it
// ends in is 1 cm along the odometry frame's y; the direct link 0 -> 2 is exact. In the odometry frame
// the links then ask p1 = (0.1, 0.01), p2 - p1 = (0, 0.11), p2 = (0.1, 0.1); their least-squares fit
// with keyframe 0 held (by hand) is p1 = (0.1, 0.01 / 3), p2 = (0.1, 0.32 / 3), to within what the
// stiff rotations and the solver's tolerance leave (microns). A link read in the wrong frame (the
// odometry frame's x instead of its keyframe's) lands millimetres elsewhere.
TEST(KeyframeWindow, RefinedPosesAreTheLeastSquaresFitOfTheLinksInTheirFrames) {
  const Eigen::Isometry3d truth[3] = {Eigen::Isometry3d::Identity(), poseAt(M_PI / 2, {0.1, 0.0, 0.0}),
                                      poseAt(M_PI / 2, {0.1, 0.1, 0.0})};
  const Eigen::Isometry3d one_cm_along_x = poseAt(0.0, {0.01, 0.0, 0.0});
  vocal::KeyframeWindow window(4);
  // As tracked: the chain with its errors.
  const Eigen::Isometry3d link01 = truth[0].inverse() * truth[1] * one_cm_along_x;
  const Eigen::Isometry3d link12 = truth[1].inverse() * truth[2] * one_cm_along_x;
  window.addKeyframe(0, truth[0]);
  window.addKeyframe(1, truth[0] * link01);
  window.addKeyframe(2, truth[0] * link01 * link12);
  window.addLink(link(0, 1, link01));
  window.addLink(link(1, 2, link12));
  EXPECT_FALSE(window.optimise()) << "a chain alone fits exactly: nothing to refine";
  window.addLink(link(0, 2, truth[0].inverse() * truth[2]));
  ASSERT_TRUE(window.optimise());
  EXPECT_TRUE(window.pose(0)->isApprox(truth[0], 1e-12)) << "the oldest keyframe is held";
  const Eigen::Vector3d expected1(0.1, 0.01 / 3, 0.0), expected2(0.1, 0.32 / 3, 0.0);
  EXPECT_LT((window.pose(1)->translation() - expected1).norm(), 1e-5) << window.pose(1)->translation().transpose();
  EXPECT_LT((window.pose(2)->translation() - expected2).norm(), 1e-5) << window.pose(2)->translation().transpose();
  EXPECT_LT(vocal::rotationAngle(truth[2].inverse() * *window.pose(2)), 1e-6);
}

// A pair solved again (a keyframe tracked coarse, its link solved at full resolution) replaces its link,
// and even a chain is placed again by it: the newer keyframe moves to the held one times the new link.
TEST(KeyframeWindow, ALinkSolvedAgainReplacesThePairsAndPlacesTheChainAgain) {
  vocal::KeyframeWindow window(3);
  const Eigen::Isometry3d coarse = poseAt(0.01, {0.1, 0.0, 0.0}), fine = poseAt(0.0, {0.1, 0.002, 0.0});
  window.addKeyframe(0, Eigen::Isometry3d::Identity());
  window.addKeyframe(1, coarse);
  window.addLink(link(0, 1, coarse));
  EXPECT_FALSE(window.optimise());
  window.addLink(link(0, 1, fine));
  EXPECT_EQ(window.linkCount(), 1);
  ASSERT_TRUE(window.optimise());
  EXPECT_TRUE(window.pose(1)->isApprox(fine, 1e-6)) << window.pose(1)->matrix();
  EXPECT_FALSE(window.optimise()) << "placed: the chain fits exactly again";
}

TEST(KeyframeWindow, TheOldestLeavesWithItsLinks) {
  vocal::KeyframeWindow window(2);
  window.addKeyframe(0, Eigen::Isometry3d::Identity());
  window.addKeyframe(1, poseAt(0.0, {0.1, 0.0, 0.0}));
  window.addLink(link(0, 1, poseAt(0.0, {0.1, 0.0, 0.0})));
  EXPECT_EQ(window.linkCount(), 1);
  window.addKeyframe(2, poseAt(0.0, {0.2, 0.0, 0.0}));
  EXPECT_EQ(window.ids(), (std::vector<int>{1, 2}));
  EXPECT_EQ(window.linkCount(), 0);
  EXPECT_FALSE(window.pose(0).has_value());
  window.addLink(link(0, 2, Eigen::Isometry3d::Identity()));  // keyframe 0 has left: ignored
  EXPECT_EQ(window.linkCount(), 0);
}

TEST(KeyframeWindow, ASizeBelowTwoIsAnError) {
  EXPECT_EQ(vocal_test::inputErrorOf([] { vocal::KeyframeWindow window(1); }),
            "keyframe window: size 1 < 2 (nothing to refine)");
}

// The estimator with the window on, on noisy synthetic frames: new keyframes get dense links to earlier
// ones and move; what is published takes the change in a share per frame, so that no published
// increment is farther from the true motion than without the window by more than a millimetre. Solved
// within the frame (repeatable) and in the background (links arrive frames later, or are skipped).
TEST(OdometryLocalWindow, KeyframesAreLinkedAndRefinedWithoutAJumpInThePublishedPose) {
  const vocal::SyntheticScene scene = vocal::SyntheticScene::make(vocal::SceneVariant::kIndoorRoom);
  const vocal::PinholeCamera camera = vocal::defaultKinectCamera(320, 240);
  vocal::SyntheticTrajectoryOptions options;
  options.frames = 80;
  const vocal::Trajectory truth = vocal::generateSyntheticTrajectory(scene.workspace(), options);
  std::vector<vocal::RgbdFrame> frames;
  for (int i = 0; i < options.frames; ++i)
    frames.push_back(vocal::renderSyntheticFrame(scene, camera, truth[i], vocal::kinectLikeSensorModel(), 500 + i));
  enum Run { kOff, kWithinTheFrame, kInTheBackground };
  double ate[3], worst_increment_error[3];
  int links[3] = {0, 0, 0}, refined[3] = {0, 0, 0}, skipped[3] = {0, 0, 0};
  double largest_correction[3] = {0.0, 0.0, 0.0};
  for (const Run run : {kOff, kWithinTheFrame, kInTheBackground}) {
    vocal::OdometryConfig config;
    config.keyframe_max_translation = 0.1;  // keyframes often enough for a window on 80 frames
    config.local_window_keyframes = run == kOff ? 0 : 4;
    config.local_window_links = 2;
    config.local_window_background = run == kInTheBackground;
    vocal::IcpDvoOdometry odometry(camera, config);
    odometry.reset(truth.front().pose);
    vocal::Trajectory estimate;
    worst_increment_error[run] = 0.0;
    double last_correction = 0.0;  // by the refinement of the frame before
    for (int i = 0; i < options.frames; ++i) {
      const vocal::OdometryResult result = odometry.track(frames[i]);
      ASSERT_TRUE(result.quality.trusted) << "frame " << i << ": " << result.failure;
      estimate.push_back({frames[i].stamp, result.pose});
      EXPECT_TRUE(result.pose.isApprox(odometry.pose())) << "pose() is what was published";
      links[run] += result.window_links;
      refined[run] += result.window_correction_m > 0.0;
      largest_correction[run] = std::max(largest_correction[run], result.window_correction_m);
      skipped[run] += result.window_links_skipped;
      if (run == kWithinTheFrame && result.window_links > 0) {
        EXPECT_TRUE(result.new_keyframe) << "frame " << i;
      }
      // A refinement moves the estimate at once and the published pose a share per frame: a frame after
      // it, most of the move is still to come.
      const double unpublished = (odometry.estimatedPose().inverse() * result.pose).translation().norm();
      if (last_correction > 0.0 && result.window_correction_m == 0.0) {
        EXPECT_GT(unpublished, 0.5 * last_correction) << "frame " << i;
      }
      last_correction = result.window_correction_m;
      if (run == kOff) {
        EXPECT_EQ(unpublished, 0.0);
      }
      if (i == 0) continue;
      const Eigen::Isometry3d error = (truth[i - 1].pose.inverse() * truth[i].pose).inverse() * result.increment;
      worst_increment_error[run] = std::max(worst_increment_error[run], error.translation().norm());
    }
    odometry.finishWindow();
    ate[run] = vocal::computeAte(truth, estimate).rmse;
    std::cout << "window " << (run == kOff ? "off" : run == kWithinTheFrame ? "within the frame" : "in the background")
              << ": ATE " << ate[run] * 1000 << " mm, worst increment error " << worst_increment_error[run] * 1000 << " mm, "
              << links[run] << " links, " << refined[run] << " refinements (largest " << largest_correction[run] * 1000
              << " mm), " << skipped[run] << " keyframes skipped\n";
  }
  EXPECT_EQ(links[kOff] + refined[kOff] + skipped[kOff], 0);
  EXPECT_EQ(skipped[kWithinTheFrame], 0);
  for (const Run run : {kWithinTheFrame, kInTheBackground}) {
    EXPECT_GT(links[run], 3) << run;
    EXPECT_GT(refined[run], 1) << run;
    EXPECT_LT(ate[run], 0.01) << run;
    EXPECT_LT(ate[run], 1.25 * ate[kOff]) << run;
    EXPECT_LT(worst_increment_error[run], worst_increment_error[kOff] + 0.001) << run;
  }
}
