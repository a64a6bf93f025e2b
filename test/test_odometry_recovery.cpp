// Keyframes and recovery: tracking against a keyframe drifts less than frame to frame; a covered lens
// is bridged by a prediction, then reported lost, then relocalised against a keyframe without a jump.

#include <gtest/gtest.h>

#include <vector>

#include "vocal/core/se3.h"
#include "vocal/core/trajectory_evaluation.h"
#include "vocal/odometry/icp_dvo_odometry.h"
#include "vocal/simulation/synthetic_sequence.h"

namespace {
struct Sequence {
  vocal::PinholeCamera camera;
  vocal::Trajectory truth;
  std::vector<vocal::RgbdFrame> frames;
};

// A noisy 320x240 room sequence; frames [covered_from, covered_from + covered) behind a hand.
Sequence makeSequence(int frames, int covered_from = 0, int covered = 0) {
  const vocal::SyntheticScene scene = vocal::SyntheticScene::make(vocal::SceneVariant::kIndoorRoom);
  Sequence sequence;
  sequence.camera = vocal::defaultKinectCamera(320, 240);
  vocal::SyntheticTrajectoryOptions options;
  options.frames = frames;
  sequence.truth = vocal::generateSyntheticTrajectory(scene.workspace(), options);
  for (int i = 0; i < frames; ++i) {
    const std::uint32_t seed = 500 + i;
    sequence.frames.push_back(
        vocal::renderSyntheticFrame(scene, sequence.camera, sequence.truth[i], vocal::kinectLikeSensorModel(), seed));
    if (i >= covered_from && i < covered_from + covered) vocal::coverLens(seed, &sequence.frames.back());
  }
  return sequence;
}

struct TrackedRun {
  std::vector<vocal::OdometryResult> results;
  vocal::Trajectory estimate, trusted_estimate;  // every pose; the trusted ones only
};

TrackedRun track(const Sequence& sequence, const vocal::OdometryConfig& config) {
  vocal::IcpDvoOdometry odometry(sequence.camera, config);
  odometry.reset(sequence.truth.front().pose);
  TrackedRun run;
  for (const vocal::RgbdFrame& frame : sequence.frames) {
    run.results.push_back(odometry.track(frame));
    run.estimate.push_back({frame.stamp, run.results.back().pose});
    if (run.results.back().quality.trusted) run.trusted_estimate.push_back({frame.stamp, run.results.back().pose});
  }
  return run;
}
}  // namespace

TEST(OdometryKeyframes, KeyframesDriftLessThanFrameToFrame) {
  const Sequence sequence = makeSequence(90);
  vocal::OdometryConfig config;
  config.tracking_reference = vocal::TrackingReference::kFrame;
  const TrackedRun frame_to_frame = track(sequence, config);
  config.tracking_reference = vocal::TrackingReference::kKeyframe;
  const TrackedRun keyframed = track(sequence, config);
  int keyframes = 0;
  for (const vocal::OdometryResult& result : keyframed.results) {
    ASSERT_TRUE(result.quality.trusted) << result.failure;
    EXPECT_EQ(result.state, vocal::TrackingState::kTracking);
    keyframes += result.new_keyframe;
  }
  for (const vocal::OdometryResult& result : frame_to_frame.results) EXPECT_TRUE(result.new_keyframe);
  const double ate_frame = vocal::computeAte(sequence.truth, frame_to_frame.estimate).rmse;
  const double ate_keyframe = vocal::computeAte(sequence.truth, keyframed.estimate).rmse;
  std::cout << "90 noisy frames: ATE frame to frame " << ate_frame * 1000 << " mm, against keyframes " << ate_keyframe * 1000
            << " mm (" << keyframes << " keyframes)\n";
  EXPECT_LT(keyframes, 30) << "a keyframe must serve several frames";
  EXPECT_LT(ate_keyframe, 0.5 * ate_frame);
}

// keyframe_after_unconverged: a frame whose solve used every iteration of the finest level without
// converging becomes the keyframe (its keyframe is too far for the dense basin). One iteration a level
// and a convergence threshold no update meets make every solve unconverged: each frame becomes a
// keyframe with the rule, and a keyframe serves several frames without it.
TEST(OdometryKeyframes, AnUnconvergedSolveMakesTheFrameTheKeyframe) {
  const Sequence sequence = makeSequence(12);
  vocal::OdometryConfig config;
  config.iterations = {1, 1, 1};
  config.convergence_translation = config.convergence_rotation = 1e-12;
  for (const bool rule : {false, true}) {
    config.keyframe_after_unconverged = rule;
    const TrackedRun run = track(sequence, config);
    int keyframes = 0;
    for (std::size_t i = 1; i < run.results.size(); ++i) {
      ASSERT_TRUE(run.results[i].quality.trusted) << run.results[i].failure;
      EXPECT_FALSE(run.results[i].quality.converged);
      keyframes += run.results[i].new_keyframe;
    }
    if (rule) {
      EXPECT_EQ(keyframes, 11);
    } else {
      EXPECT_LT(keyframes, 6);
    }
  }
}

// A hand over the lens for 10 frames (a third of a second): 5 frames bridged by the last motion
// (predicted), then lost (covariance of nothing known), then relocalised against the keyframe with
// the hole reported; the trajectory after it as good as an unbroken run's.
TEST(OdometryRecovery, ACoveredLensIsPredictedThenLostThenRelocalised) {
  const int covered_from = 30, covered = 10;
  const Sequence unbroken = makeSequence(60);
  const Sequence sequence = makeSequence(60, covered_from, covered);
  const vocal::OdometryConfig config;
  ASSERT_EQ(config.max_predicted_frames, 5);
  const TrackedRun reference = track(unbroken, config);
  const TrackedRun run = track(sequence, config);
  for (int i = 0; i < 60; ++i) {
    const vocal::OdometryResult& result = run.results[i];
    SCOPED_TRACE("frame " + std::to_string(i));
    if (i < covered_from) {
      EXPECT_EQ(result.state, vocal::TrackingState::kTracking);
    } else if (i < covered_from + config.max_predicted_frames) {
      EXPECT_EQ(result.state, vocal::TrackingState::kPredicted);
      EXPECT_FALSE(result.quality.trusted);
      EXPECT_EQ(result.failure, "too few ICP inliers (0 < 500)");
      EXPECT_EQ(result.lost_frames, i - covered_from + 1);
      // The prediction moves on by the last motion and says it is less sure with every frame.
      EXPECT_TRUE(result.increment.isApprox(run.results[covered_from - 1].increment, 1e-9));
      EXPECT_GT(result.pose_covariance.trace(), run.results[i - 1].pose_covariance.trace());
      EXPECT_LT(result.pose_covariance.trace(), 1.0);
    } else if (i < covered_from + covered) {
      EXPECT_EQ(result.state, vocal::TrackingState::kLost);
      EXPECT_FALSE(result.quality.trusted);
      EXPECT_GE(result.pose_covariance.diagonal().minCoeff(), 1e6);
      EXPECT_TRUE(result.pose.isApprox(run.results[i - 1].pose)) << "a lost pose stays";
    } else if (i == covered_from + covered) {
      EXPECT_EQ(result.state, vocal::TrackingState::kRelocalised);
      EXPECT_TRUE(result.quality.trusted) << result.failure;
      EXPECT_EQ(result.lost_frames, covered) << "the hole is reported";
    } else {
      EXPECT_EQ(result.state, vocal::TrackingState::kTracking) << result.failure;
    }
  }
  // After relocalising, the pose continues from the keyframe's: no jump against the unbroken run.
  const int first_back = covered_from + covered;
  const double jump = (reference.results[first_back].pose.inverse() * run.results[first_back].pose).translation().norm();
  const double ate_unbroken = vocal::computeAte(unbroken.truth, reference.estimate).rmse;
  const double ate_tracked = vocal::computeAte(sequence.truth, run.trusted_estimate).rmse;
  const double final_unbroken = (unbroken.truth.back().pose.inverse() * reference.results.back().pose).translation().norm();
  const double final_error = (sequence.truth.back().pose.inverse() * run.results.back().pose).translation().norm();
  std::cout << "covered lens: relocalised " << jump * 1000 << " mm from the unbroken run's pose; ATE of the tracked frames "
            << ate_tracked * 1000 << " mm (unbroken " << ate_unbroken * 1000 << " mm), final error " << final_error * 1000
            << " mm (unbroken " << final_unbroken * 1000 << " mm)\n";
  EXPECT_LT(jump, 0.002);
  // Within 2x of the unbroken run; a tenth of a millimetre of slack for runs that are nearly exact.
  EXPECT_LT(ate_tracked, 2.0 * ate_unbroken + 1e-4);
  EXPECT_LT(final_error, 2.0 * final_unbroken + 1e-4);
}

// The camera comes back somewhere else: far from the keyframe it left, but at a view an older
// keyframe holds. Relocalisation matches the frame against the recent keyframes by features.
TEST(OdometryRecovery, RelocalisesAgainstAnOlderKeyframe) {
  const Sequence sequence = makeSequence(70);
  vocal::OdometryConfig config;
  config.keyframe_max_translation = 0.1;  // several keyframes on the way, the first one far behind
  vocal::IcpDvoOdometry odometry(sequence.camera, config);
  odometry.reset(sequence.truth.front().pose);
  int first_keyframe_frames = 0, last_keyframe = 0;
  for (int i = 0; i < 60; ++i) {
    const vocal::OdometryResult result = odometry.track(sequence.frames[i]);
    ASSERT_TRUE(result.quality.trusted) << i << ": " << result.failure;
    first_keyframe_frames += result.keyframe_id == 0;
    last_keyframe = result.keyframe_id;
  }
  ASSERT_GT(last_keyframe, 0) << "the camera must have left the first keyframe for this test to mean anything";
  // Back to a view near the start (the camera was carried back while covered).
  const vocal::OdometryResult back = odometry.track(sequence.frames[first_keyframe_frames / 2]);
  EXPECT_EQ(back.state, vocal::TrackingState::kRelocalised) << back.failure;
  EXPECT_TRUE(back.quality.trusted) << back.failure;
  EXPECT_GT(back.quality.feature_inliers, 0);
  EXPECT_LT(back.keyframe_id, last_keyframe) << "an older keyframe, not the one in use";
  const double error = (sequence.truth[first_keyframe_frames / 2].pose.inverse() * back.pose).translation().norm();
  EXPECT_LT(error, 0.005) << "relocalised against keyframe " << back.keyframe_id;
}

// Without relocalisation (and no prediction) the covered frames are lost at once; when the lens is
// free the dense solve alone picks up against the keyframe, no features matched.
TEST(OdometryRecovery, WithoutRelocalisationALostCameraStaysLost) {
  const Sequence sequence = makeSequence(50, 20, 10);
  vocal::OdometryConfig config;
  config.relocalisation = false;
  config.max_predicted_frames = 0;
  const TrackedRun run = track(sequence, config);
  for (int i = 20; i < 30; ++i) EXPECT_EQ(run.results[i].state, vocal::TrackingState::kLost) << i;
  // The dense solve alone picks up again from the last pose when the camera is still near it.
  EXPECT_EQ(run.results[30].state, vocal::TrackingState::kRelocalised) << run.results[30].failure;
  EXPECT_EQ(run.results[30].quality.feature_inliers, 0) << "no features were matched";
}
