// What real cameras add to the pinhole, global-shutter model, and the odometry undoing it: lens
// distortion and rolling-shutter rows (FrameRectification), exposure changes (BrightnessTransfer).
// Rolling-shutter and exposure sequences are rendered as such; tracking them must gain from the
// model and the model must cost nothing where the camera has no such effect.

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "vocal/core/errors.h"
#include "vocal/core/lens_distortion.h"
#include "vocal/core/se3.h"
#include "vocal/core/trajectory_evaluation.h"
#include "vocal/odometry/brightness_transfer.h"
#include "vocal/odometry/frame_rectification.h"
#include "vocal/odometry/icp_dvo_odometry.h"
#include "vocal/simulation/synthetic_sequence.h"

namespace {
// TUM freiburg1's published lens (plumb_bob).
vocal::LensDistortion freiburg1Lens() {
  return vocal::LensDistortion::fromCameraInfo("plumb_bob", {0.2624, -0.9531, -0.0054, 0.0026, 1.1633}, "test lens");
}

struct Tracked {
  vocal::Trajectory estimate;
  int untrusted = 0;
  int keyframes = 0;
};

Tracked trackFrames(const vocal::PinholeCamera& camera, const vocal::OdometryConfig& config,
                    const std::vector<vocal::RgbdFrame>& frames, const vocal::Trajectory& truth) {
  vocal::IcpDvoOdometry odometry(camera, config);
  odometry.reset(truth.front().pose);
  Tracked run;
  for (const vocal::RgbdFrame& frame : frames) {
    const vocal::OdometryResult result = odometry.track(frame);
    run.estimate.push_back({frame.stamp, result.pose});
    run.untrusted += !result.quality.trusted;
    run.keyframes += result.new_keyframe;
  }
  return run;
}

// Relative pose error over `frames` frames (metres per step of that many frames), the drift measure
// that does not depend on where the trajectory is aligned.
double rpeOver(const vocal::Trajectory& truth, const vocal::Trajectory& estimate, std::size_t frames) {
  double sum = 0.0;
  int n = 0;
  for (std::size_t i = 0; i + frames < estimate.size(); ++i) {
    const Eigen::Isometry3d true_motion = truth[i].pose.inverse() * truth[i + frames].pose;
    const Eigen::Isometry3d found = estimate[i].pose.inverse() * estimate[i + frames].pose;
    sum += (true_motion.inverse() * found).translation().squaredNorm();
    ++n;
  }
  return std::sqrt(sum / std::max(n, 1));
}
}  // namespace

TEST(FrameRectification, LookupIsTheLensProjectionOfTheIdealRayWhenStill) {
  const vocal::PinholeCamera camera = vocal::defaultKinectCamera(640, 480);
  const vocal::LensDistortion lens = freiburg1Lens();
  const vocal::FrameRectification rectification(camera, lens, 0.03);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 639.0), v(0.0, 479.0);
  for (int k = 0; k < 200; ++k) {
    const double x = u(rng), y = v(rng);
    const Eigen::Vector2d expected = vocal::projectThroughLens(camera, lens, camera.backProject(x, y, 1.0));
    const Eigen::Vector2d found = rectification.sourcePixel(x, y, Eigen::Vector3d::Zero());
    ASSERT_NEAR((found - expected).norm(), 0.0, 1e-9) << "at " << x << ", " << y;
  }
  EXPECT_FALSE(vocal::FrameRectification().active());
  EXPECT_FALSE(vocal::FrameRectification(camera, vocal::LensDistortion(), 0.0).active());
  // The lens alone comes out the same whatever the motion: a keyframe rectified at rest is final.
  EXPECT_FALSE(vocal::FrameRectification(camera, lens, 0.0).dependsOnMotion());
  EXPECT_TRUE(vocal::FrameRectification(camera, lens, 0.0, -0.005).dependsOnMotion());
  EXPECT_TRUE(rectification.dependsOnMotion());
  const vocal::FrameRectification lens_only(camera, lens, 0.0);
  const Eigen::Vector3d turning(0.2, -0.5, 0.1);
  EXPECT_EQ(lens_only.sourcePixel(100.0, 50.0, turning), lens_only.sourcePixel(100.0, 50.0, Eigen::Vector3d::Zero()));
}

// A camera panning right (turning about its y axis, image content moving left) while the rows are
// read top to bottom: the top row was exposed first, when the camera still looked further left, so
// the ideal middle-instant pixel is found further right in the top row and further left in the bottom
// row, by fx * rate * (readout / 2) at the ends; the middle row is where it is.
TEST(FrameRectification, RowsTurnWithTheCameraOverTheReadout) {
  const vocal::PinholeCamera camera = vocal::defaultKinectCamera(640, 480);
  const double readout = 0.03, rate = 1.0;  // rad/s about +y (x turns towards z: a pan to the right)
  const vocal::FrameRectification rectification(camera, vocal::LensDistortion(), readout);
  const Eigen::Vector3d turning(0.0, rate, 0.0);
  const double expected_shift = camera.fx * std::tan(rate * readout / 2);
  const Eigen::Vector2d top = rectification.sourcePixel(camera.cx, 0.0, turning);
  const Eigen::Vector2d middle = rectification.sourcePixel(camera.cx, camera.height / 2.0, turning);
  const Eigen::Vector2d bottom = rectification.sourcePixel(camera.cx, camera.height - 1.0, turning);
  EXPECT_NEAR(middle.x(), camera.cx, 1e-9);
  EXPECT_NEAR(top.x() - camera.cx, expected_shift, 0.05 * expected_shift);
  EXPECT_NEAR(bottom.x() - camera.cx, -expected_shift, 0.05 * expected_shift);
}

// The rectified image is the exact lookup, interpolated between grid nodes: each output pixel's depth
// (here a code of the input pixel it came from) names the input pixel nearest to the exact lookup.
// A still camera: a moving one's depths are changed to the middle instant (next test).
TEST(FrameRectification, GridInterpolatedLookupMatchesTheExactOne) {
  const vocal::PinholeCamera camera = vocal::defaultKinectCamera(640, 480);
  const vocal::FrameRectification rectification(camera, freiburg1Lens(), 0.03);
  const Eigen::Vector3d turning = Eigen::Vector3d::Zero();
  vocal::RgbdFrame coded;
  coded.color = vocal::ColorImage(640, 480);
  coded.depth = vocal::DepthImage(640, 480);
  for (int y = 0; y < 480; ++y)
    for (int x = 0; x < 640; ++x) coded.depth(x, y) = 1.0f + x + 1000.0f * y;
  const vocal::RgbdFrame out = rectification.rectify(coded, turning);
  int checked = 0, within_half = 0;
  double worst = 0.0;
  for (int y = 0; y < 480; ++y) {
    for (int x = 0; x < 640; ++x) {
      const float code = out.depth(x, y);
      if (!(code > 0.0f)) continue;
      const int sx = static_cast<int>(std::lround(code - 1.0f)) % 1000, sy = static_cast<int>(std::lround(code - 1.0f)) / 1000;
      const Eigen::Vector2d exact = rectification.sourcePixel(x, y, turning);
      const double off = std::max(std::fabs(sx - exact.x()), std::fabs(sy - exact.y()));
      worst = std::max(worst, off);
      within_half += off <= 0.52;
      ++checked;
    }
  }
  std::cout << checked << " pixels looked up; nearest source within 0.52 px of the exact lookup for " << within_half
            << ", worst " << worst << " px\n";
  EXPECT_GT(checked, 640 * 480 * 8 / 10);  // the lens's corners fall outside the image
  EXPECT_GE(within_half, checked * 999 / 1000);
  EXPECT_LT(worst, 1.0);
}

TEST(BrightnessTransfer, RecoversAnExposureChangeEvenWithTheMotionOff) {
  const vocal::SyntheticScene scene = vocal::SyntheticScene::make(vocal::SceneVariant::kIndoorRoom);
  const vocal::PinholeCamera camera = vocal::defaultKinectCamera(320, 240);
  vocal::SyntheticTrajectoryOptions options;
  options.frames = 4;
  const vocal::Trajectory path = vocal::generateSyntheticTrajectory(scene.workspace(), options);
  const vocal::RgbdFrame reference = vocal::renderSyntheticFrame(scene, camera, path[0], {}, 0);
  vocal::RgbdFrame current = vocal::renderSyntheticFrame(scene, camera, path[3], {}, 0);
  // The current frame darker: I_cur = (I_ref - 0.02) / 1.2, so the reference sees it as 1.2 I + 0.02.
  for (vocal::Rgb8& p : current.color.pixels()) {
    auto darker = [](std::uint8_t c) { return static_cast<std::uint8_t>(std::clamp((c - 5.1) / 1.2 + 0.5, 0.0, 255.0)); };
    p = {darker(p.r), darker(p.g), darker(p.b)};
  }
  const Eigen::Isometry3d motion = path[0].pose.inverse() * path[3].pose;
  for (const Eigen::Isometry3d& start : {motion, motion * vocal::se3Exp((vocal::Vector6d() << 0.01, -0.01, 0, 0, 0.005, 0).finished())}) {
    const vocal::BrightnessTransfer transfer = vocal::estimateBrightnessTransfer(reference, current, camera, start, 0.07);
    EXPECT_GT(transfer.samples, 1000);
    EXPECT_NEAR(transfer.gain, 1.2, 0.03);
    EXPECT_NEAR(transfer.bias, 0.02, 0.01);
  }
  // Nothing in common (the current frame all black): the identity, nothing estimated.
  vocal::RgbdFrame black = current;
  for (vocal::Rgb8& p : black.color.pixels()) p = {};
  const vocal::BrightnessTransfer none = vocal::estimateBrightnessTransfer(reference, black, camera, motion, 0.07);
  EXPECT_EQ(none.samples, 0);
  EXPECT_EQ(none.gain, 1.0f);
  EXPECT_EQ(none.bias, 0.0f);
}

// A camera that steps its exposure by 12 % every few frames, as freiburg1's Kinect does: with the
// affine model keyframes survive the steps and the track drifts less than with intensities compared
// as they are; and keyframes stay at least as good as frame to frame.
TEST(OdometryBrightness, AffineModelWinsThroughExposureSteps) {
  const vocal::SyntheticScene scene = vocal::SyntheticScene::make(vocal::SceneVariant::kIndoorRoom);
  const vocal::PinholeCamera camera = vocal::defaultKinectCamera(320, 240);
  vocal::SyntheticTrajectoryOptions options;
  options.frames = 60;
  options.speed = 0.4;
  const vocal::Trajectory truth = vocal::generateSyntheticTrajectory(scene.workspace(), options);
  std::vector<vocal::RgbdFrame> frames;
  const double gains[] = {1.0, 1.12, 0.9, 1.05, 0.85, 1.0, 1.15, 0.95};
  for (int i = 0; i < options.frames; ++i) {
    frames.push_back(vocal::renderSyntheticFrame(scene, camera, truth[i], vocal::kinectLikeSensorModel(), 700 + i));
    const double gain = gains[(i / 5) % 8];
    for (vocal::Rgb8& p : frames.back().color.pixels()) {
      auto exposed = [&](std::uint8_t c) { return static_cast<std::uint8_t>(std::min(255.0, c * gain + 0.5)); };
      p = {exposed(p.r), exposed(p.g), exposed(p.b)};
    }
  }
  vocal::OdometryConfig config;
  config.rolling_shutter_readout = 0.0;  // the renderer's global shutter,
  config.depth_time_offset = 0.0;        // depth and colour at one instant
  config.brightness_model = vocal::BrightnessModel::kFixed;
  const Tracked fixed = trackFrames(camera, config, frames, truth);
  config.brightness_model = vocal::BrightnessModel::kAffine;
  const Tracked affine = trackFrames(camera, config, frames, truth);
  config.tracking_reference = vocal::TrackingReference::kFrame;
  const Tracked affine_frame = trackFrames(camera, config, frames, truth);
  const double drift_fixed = rpeOver(truth, fixed.estimate, 10), drift_affine = rpeOver(truth, affine.estimate, 10);
  const double drift_frame = rpeOver(truth, affine_frame.estimate, 10);
  std::cout << "exposure steps: drift over 10 frames, intensities as they are " << drift_fixed * 1000 << " mm ("
            << fixed.keyframes << " keyframes, " << fixed.untrusted << " untrusted), affine " << drift_affine * 1000
            << " mm (" << affine.keyframes << " keyframes), affine frame to frame " << drift_frame * 1000 << " mm\n";
  EXPECT_EQ(affine.untrusted, 0);
  EXPECT_LT(drift_affine, 0.7 * drift_fixed);
  EXPECT_LT(affine.keyframes, fixed.keyframes);
  EXPECT_LE(drift_affine, drift_frame);
}

// A fast-moving camera whose rows are read over 30 ms (a Kinect's colour and depth sensors): rows moved
// to one instant track it far better than rows taken as one instant. Resampling costs a little (a
// global-shutter camera with the readout set to 0 tracks best), and the setting is not free: on a
// global-shutter camera a 30 ms readout moves rows by a motion that is not there (docs: set 0).
TEST(OdometryRollingShutter, RectifiedRowsTrackATurningCamera) {
  const vocal::SyntheticScene scene = vocal::SyntheticScene::make(vocal::SceneVariant::kIndoorRoom);
  const vocal::PinholeCamera camera = vocal::defaultKinectCamera(320, 240);
  vocal::SyntheticTrajectoryOptions options;
  options.frames = 45;
  options.speed = 0.6;
  const vocal::Trajectory truth = vocal::generateSyntheticTrajectory(scene.workspace(), options);
  std::vector<vocal::RgbdFrame> rolling, global;
  double fastest_turn = 0.0;
  for (int i = 0; i < options.frames; ++i) {
    rolling.push_back(vocal::renderRollingShutterFrame(scene, camera, truth, i, 0.03, vocal::kinectLikeSensorModel(), 900 + i));
    global.push_back(vocal::renderSyntheticFrame(scene, camera, truth[i], vocal::kinectLikeSensorModel(), 900 + i));
    if (i > 0) {
      fastest_turn = std::max(fastest_turn, vocal::rotationAngle(truth[i - 1].pose.inverse() * truth[i].pose) * options.frame_rate);
    }
  }
  vocal::OdometryConfig config;
  config.rolling_shutter_readout = 0.0;
  config.depth_time_offset = 0.0;  // the renderer's depth and colour are of one instant
  const Tracked as_one_instant = trackFrames(camera, config, rolling, truth);
  const Tracked global_as_global = trackFrames(camera, config, global, truth);
  config.rolling_shutter_readout = 0.03;
  const Tracked rectified = trackFrames(camera, config, rolling, truth);
  const Tracked global_rectified = trackFrames(camera, config, global, truth);
  const double drift_plain = rpeOver(truth, as_one_instant.estimate, 10), drift_rectified = rpeOver(truth, rectified.estimate, 10);
  const double drift_global = rpeOver(truth, global_as_global.estimate, 10);
  const double drift_global_rectified = rpeOver(truth, global_rectified.estimate, 10);
  std::cout << "rolling shutter (30 ms, 0.6 m/s, turns up to " << fastest_turn << " rad/s): drift over 10 frames, rows as one instant "
            << drift_plain * 1000 << " mm, rectified " << drift_rectified * 1000 << " mm; global shutter "
            << drift_global * 1000 << " mm, with the 30 ms setting " << drift_global_rectified * 1000 << " mm\n";
  EXPECT_EQ(rectified.untrusted, 0);
  EXPECT_LT(drift_rectified, 0.7 * drift_plain);
  EXPECT_LT(drift_global, drift_rectified);
  EXPECT_GT(drift_global_rectified, 2.0 * drift_global);
}

// A camera turning at 1 rad/s and moving at 0.5 m/s with its rows read over 30 ms: rectified with
// that motion, the frame is the one a global-shutter camera takes at the middle row's instant (up to
// resampling); taken as it is, it is off by pixels.
TEST(FrameRectification, UndoesARenderedRollingShutterOfAMovingCamera) {
  const vocal::SyntheticScene scene = vocal::SyntheticScene::make(vocal::SceneVariant::kIndoorRoom);
  const vocal::PinholeCamera camera = vocal::defaultKinectCamera(320, 240);
  vocal::SyntheticTrajectoryOptions options;
  options.frames = 1;
  const vocal::Trajectory start = vocal::generateSyntheticTrajectory(scene.workspace(), options);
  vocal::Vector6d twist;  // m/s and rad/s in the camera frame
  twist << 0.3, -0.1, 0.4, 0.2, 1.0, 0.1;
  vocal::Trajectory path;
  for (int i = 0; i < 3; ++i) {
    const double t = i / 30.0;
    path.push_back({100.0 + t, start[0].pose * vocal::se3Exp(twist * t)});
  }
  const vocal::RgbdFrame rolling = vocal::renderRollingShutterFrame(scene, camera, path, 1, 0.03, {}, 0);
  const vocal::RgbdFrame global = vocal::renderSyntheticFrame(scene, camera, path[1], {}, 0);
  const vocal::RgbdFrame rectified = vocal::FrameRectification(camera, vocal::LensDistortion(), 0.03)
                                         .rectify(rolling, twist.tail<3>(), twist.head<3>());
  // The share of pixels whose depth is more than 1 % off the global-shutter frame's (a pixel's shift
  // shows at depth edges and along slanted surfaces).
  auto meanDepthDifference = [&](const vocal::RgbdFrame& frame) {
    int off = 0, n = 0;
    for (int y = 8; y < camera.height - 8; ++y)
      for (int x = 8; x < camera.width - 8; ++x)
        if (frame.depth(x, y) > 0.0f && global.depth(x, y) > 0.0f) off += std::fabs(frame.depth(x, y) - global.depth(x, y)) > 0.01f * global.depth(x, y), ++n;
    return static_cast<double>(off) / std::max(n, 1);
  };
  auto meanColourDifference = [&](const vocal::RgbdFrame& frame) {
    double sum = 0.0;
    int n = 0;
    for (int y = 8; y < camera.height - 8; ++y)
      for (int x = 8; x < camera.width - 8; ++x)
        if (frame.depth(x, y) > 0.0f) sum += std::abs(vocal::luma8(frame.color(x, y)) - vocal::luma8(global.color(x, y))), ++n;
    return sum / std::max(n, 1);
  };
  const double depth_as_is = meanDepthDifference(rolling), depth_rectified = meanDepthDifference(rectified);
  const double colour_as_is = meanColourDifference(rolling), colour_rectified = meanColourDifference(rectified);
  std::cout << "against the global-shutter frame: depth more than 1 % off at " << depth_as_is * 100 << " % of the pixels as read, "
            << depth_rectified * 100 << " % rectified; colour " << colour_as_is << " vs " << colour_rectified << " levels off\n";
  EXPECT_LT(depth_rectified, 0.5 * depth_as_is);
  EXPECT_LT(colour_rectified, 0.5 * colour_as_is);
}

// What the estimator says it undoes (the nodelet logs it, the tools print it): the user of a
// global-shutter camera must see the rolling-shutter setting and how to turn it off.
TEST(OdometryCameraModel, TextSaysWhatIsUndoneAndHowToTurnTheShutterOff) {
  const vocal::PinholeCamera camera = vocal::defaultKinectCamera(320, 240);
  EXPECT_EQ(vocal::IcpDvoOdometry(camera, vocal::OdometryConfig{}, nullptr, freiburg1Lens()).cameraModelText(),
            "lens plumb_bob undone, rows of a 0.020 s rolling shutter rectified (rolling_shutter_readout: 0 for a "
            "global-shutter camera), depth taken 0.005 s before the colour, brightness affine");
  vocal::OdometryConfig config;
  config.rolling_shutter_readout = 0.0;
  config.depth_time_offset = 0.0;
  config.undistort_lens = false;
  config.brightness_model = vocal::BrightnessModel::kFixed;
  EXPECT_EQ(vocal::IcpDvoOdometry(camera, config, nullptr, freiburg1Lens()).cameraModelText(),
            "lens plumb_bob ignored (undistort_lens false), global shutter, brightness fixed");
  EXPECT_EQ(vocal::IcpDvoOdometry(camera, config).cameraModelText(), "no lens distortion given, global shutter, brightness fixed");
}

// Depth taken 10 ms before the colour by a camera panning at 1 rad/s: the depth's pixels are looked up
// where the camera then saw them (fx tan(0.01) = 5 px across), the colour's stay where they are.
TEST(FrameRectification, DepthTakenBeforeTheColourIsTurnedToTheColoursInstant) {
  const vocal::PinholeCamera camera = vocal::defaultKinectCamera(640, 480);
  const double offset = -0.01, rate = 1.0;
  const vocal::FrameRectification rectification(camera, vocal::LensDistortion(), 0.0, offset);
  const Eigen::Vector3d turning(0.0, rate, 0.0);
  EXPECT_TRUE(rectification.active());
  EXPECT_NEAR(rectification.sourcePixel(camera.cx, camera.cy, turning, offset).x() - camera.cx,
              -camera.fx * std::tan(rate * offset), 1e-9);
  vocal::RgbdFrame coded;
  coded.color = vocal::ColorImage(640, 480);
  coded.depth = vocal::DepthImage(640, 480);
  for (int y = 0; y < 480; ++y)
    for (int x = 0; x < 640; ++x) {
      coded.depth(x, y) = 1.0f + x + 1000.0f * y;
      coded.color(x, y) = {static_cast<std::uint8_t>(x % 251), static_cast<std::uint8_t>(y % 251), 7};
    }
  const vocal::RgbdFrame out = rectification.rectify(coded, turning);
  int checked = 0, colour_moved = 0;
  double worst = 0.0;
  for (int y = 20; y < 460; ++y) {
    for (int x = 20; x < 620; ++x) {
      const int code = static_cast<int>(std::lround(out.depth(x, y) - 1.0f));
      const Eigen::Vector2d exact = rectification.sourcePixel(x, y, turning, offset);
      worst = std::max(worst, std::max(std::fabs(code % 1000 - exact.x()), std::fabs(code / 1000 - exact.y())));
      colour_moved += !(out.color(x, y).r == coded.color(x, y).r && out.color(x, y).g == coded.color(x, y).g);
      ++checked;
    }
  }
  EXPECT_LT(worst, 0.75) << "of " << checked << " depth pixels";
  EXPECT_EQ(colour_moved, 0);
  EXPECT_GT(std::fabs(out.depth(320, 240) - coded.depth(320, 240)), 4.0f) << "the depth must have moved by about 5 px";
  // Taken together: nothing to turn, nothing to do.
  EXPECT_FALSE(vocal::FrameRectification(camera, vocal::LensDistortion(), 0.0, 0.0).active());
}

// Where a moving camera's rows are looked up outside the input (the image's edges, turned and shifted
// over the readout), the rectified frame has no depth and the colour of the nearest border pixel: a
// black band there was an edge that moved with the estimated motion, and in an untextured room the
// photometric term tracked it rather than the room (OdometryAccuracy.RollingShutterUntexturedRoom...).
TEST(FrameRectification, LookupsOutsideTheInputGiveNoDepthAndNoFalseEdge) {
  const vocal::PinholeCamera camera = vocal::defaultKinectCamera(160, 120);
  vocal::RgbdFrame frame;
  frame.color = vocal::ColorImage(camera.width, camera.height);
  frame.depth = vocal::DepthImage(camera.width, camera.height, 2.0f);
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x) frame.color(x, y) = {100, 120, 140};
  const vocal::RgbdFrame rectified = vocal::FrameRectification(camera, freiburg1Lens(), 0.03)
                                         .rectify(frame, Eigen::Vector3d(0.5, 2.0, 0.3), Eigen::Vector3d(0.5, 0.2, 0.1));
  int outside = 0, off_colour = 0;
  for (int y = 0; y < camera.height; ++y) {
    for (int x = 0; x < camera.width; ++x) {
      outside += rectified.depth(x, y) == 0.0f;
      const vocal::Rgb8 c = rectified.color(x, y);
      off_colour += c.r != 100 || c.g != 120 || c.b != 140;
    }
  }
  EXPECT_GT(outside, camera.width) << "the motion must take some lookups outside the input for this test to mean anything";
  EXPECT_EQ(off_colour, 0);
}

// The AVX2 pass (8 pixels of a grid cell at a time, where the CPU has it) gives the portable loop's
// output to the bit: every colour byte and depth value, with a lens, turning and moving rows, depth
// taken at another instant, lookups leaving the image, and missing depth.
TEST(FrameRectification, VectorPassGivesThePortableOutputExactly) {
  const vocal::PinholeCamera camera = vocal::defaultKinectCamera(164, 120);  // the last cell is partial
  const vocal::SyntheticScene scene = vocal::SyntheticScene::make(vocal::SceneVariant::kIndoorRoom);
  const vocal::Trajectory path = vocal::generateSyntheticTrajectory(scene.workspace(), vocal::SyntheticTrajectoryOptions{});
  vocal::RgbdFrame frame = vocal::renderSyntheticFrame(scene, camera, path.front(), vocal::kinectLikeSensorModel(), 7);
  for (int x = 0; x < camera.width; x += 5) frame.depth(x, 60) = std::numeric_limits<float>::quiet_NaN();
  for (int x = 0; x < camera.width; x += 3) frame.depth(x, 30) = 0.0f;
  struct Case {
    double readout, depth_offset;
    Eigen::Vector3d angular, linear;
  };
  for (const Case& c : {Case{0.0, 0.0, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()},
                        Case{0.03, 0.0, Eigen::Vector3d(0.5, 2.0, 0.3), Eigen::Vector3d::Zero()},
                        Case{0.03, 0.0, Eigen::Vector3d(0.5, -1.5, 0.3), Eigen::Vector3d(0.6, -0.3, 0.4)},
                        Case{0.03, -0.008, Eigen::Vector3d(-1.0, 2.0, 0.2), Eigen::Vector3d(0.6, 0.2, -0.5)}}) {
    const vocal::FrameRectification portable(camera, freiburg1Lens(), c.readout, c.depth_offset, false);
    const vocal::FrameRectification best(camera, freiburg1Lens(), c.readout, c.depth_offset, true);
    const vocal::RgbdFrame expected = portable.rectify(frame, c.angular, c.linear);
    const vocal::RgbdFrame actual = best.rectify(frame, c.angular, c.linear);
    int colour_differences = 0, depth_differences = 0, outside = 0;
    for (int y = 0; y < camera.height; ++y) {
      for (int x = 0; x < camera.width; ++x) {
        const vocal::Rgb8 e = expected.color(x, y), a = actual.color(x, y);
        colour_differences += e.r != a.r || e.g != a.g || e.b != a.b;
        depth_differences += std::memcmp(&expected.depth(x, y), &actual.depth(x, y), sizeof(float)) != 0;
        outside += expected.depth(x, y) == 0.0f;
      }
    }
    EXPECT_EQ(colour_differences, 0) << "readout " << c.readout << ", depth offset " << c.depth_offset;
    EXPECT_EQ(depth_differences, 0) << "readout " << c.readout << ", depth offset " << c.depth_offset;
    EXPECT_GT(outside, camera.width) << "some lookups must leave the image or miss depth for this to mean anything";
  }
}
