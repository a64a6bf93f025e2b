#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "test_support.h"
#include "vocal/core/errors.h"
#include "vocal/core/image_io.h"
#include "vocal/core/se3.h"
#include "vocal/core/tum_sequence.h"
#include "vocal/simulation/blank_wall_visit.h"
#include "vocal/simulation/synthetic_sequence.h"

using vocal_test::makeTempFolder;

namespace {
double luma(const vocal::Rgb8& p) { return 0.299 * p.r + 0.587 * p.g + 0.114 * p.b; }

double bilinearLuma(const vocal::ColorImage& image, double u, double v) {
  const int x = static_cast<int>(std::floor(u)), y = static_cast<int>(std::floor(v));
  const double a = u - x, b = v - y;
  return (1 - b) * ((1 - a) * luma(image(x, y)) + a * luma(image(x + 1, y))) +
         b * ((1 - a) * luma(image(x, y + 1)) + a * luma(image(x + 1, y + 1)));
}
}  // namespace

TEST(SyntheticSequence, ReloadsExactly) {
  const std::string folder = makeTempFolder("reload");
  vocal::SyntheticSequenceOptions options = vocal_test::smallSequenceOptions(6);
  const vocal::SyntheticSequence written = vocal::writeSyntheticSequence(folder, options);
  const vocal::TumSequence sequence = vocal::TumSequence::open(folder);

  EXPECT_EQ(sequence.camera(), written.camera);
  EXPECT_EQ(sequence.cameraSource(), folder + "/camera.yaml");
  ASSERT_EQ(sequence.size(), written.ground_truth.size());
  ASSERT_EQ(sequence.groundTruth().size(), written.ground_truth.size());
  const vocal::SyntheticScene scene = vocal::SyntheticScene::make(options.scene);
  for (std::size_t i = 0; i < sequence.size(); ++i) {
    const vocal::StampedPose& truth = written.ground_truth[i];
    EXPECT_EQ(sequence.groundTruth()[i].stamp, truth.stamp);
    EXPECT_EQ(sequence.entry(i).rgb.stamp, truth.stamp);
    EXPECT_EQ(sequence.groundTruth()[i].pose.translation(), truth.pose.translation());
    EXPECT_LT((sequence.groundTruth()[i].pose.linear() - truth.pose.linear()).norm(), 1e-15);

    const vocal::RgbdFrame loaded = sequence.loadFrame(i);
    const vocal::RgbdFrame rendered =
        vocal::renderSyntheticFrame(scene, written.camera, truth, options.sensor_model, 0);
    EXPECT_EQ(loaded.color.pixels().size(), rendered.color.pixels().size());
    EXPECT_TRUE(loaded.color.pixels() == rendered.color.pixels()) << "colour of frame " << i;
    int valid = 0;
    for (std::size_t p = 0; p < loaded.depth.size(); ++p) {
      const float a = loaded.depth.pixels()[p], b = rendered.depth.pixels()[p];
      ASSERT_EQ(vocal::isValidDepth(a), vocal::isValidDepth(b)) << "pixel " << p;
      if (vocal::isValidDepth(a)) {
        ++valid;
        ASSERT_LE(std::abs(a - b), 0.5 / 5000.0 + 1e-6) << "pixel " << p;
      }
    }
    EXPECT_GT(valid, static_cast<int>(loaded.depth.size()) * 9 / 10);
  }
}

// A point seen in two frames must reappear where the ground-truth motion puts it: back-project pixels of
// frame A with the depth read from its PNG, move them by the ground-truth motion, project into B, read
// B's depth there (inverse depth is affine on a plane, so it interpolates exactly inside one surface),
// and project the result back into A.
TEST(SyntheticSequence, RendersConsistentlyAcrossViews) {
  const std::string folder = makeTempFolder("consistency");
  vocal::SyntheticSequenceOptions options;
  options.width = 320;
  options.height = 240;
  options.trajectory.frames = 16;
  options.trajectory.speed = 0.5;
  vocal::writeSyntheticSequence(folder, options);
  const vocal::TumSequence sequence = vocal::TumSequence::open(folder);
  const vocal::PinholeCamera& camera = sequence.camera();
  const vocal::RgbdFrame a = sequence.loadFrame(0), b = sequence.loadFrame(15);
  const Eigen::Isometry3d b_from_a = sequence.groundTruth()[15].pose.inverse() * sequence.groundTruth()[0].pose;
  ASSERT_GT(b_from_a.translation().norm(), 0.1);  // a real baseline

  int compared = 0, occluded = 0;
  double worst_pixel_error = 0.0, luma_error_sum = 0.0;
  for (int v = 2; v < camera.height - 2; v += 3) {
    for (int u = 2; u < camera.width - 2; u += 3) {
      const float za = a.depth(u, v);
      if (!vocal::isValidDepth(za)) continue;
      const Eigen::Vector3d in_b = b_from_a * camera.backProject(u, v, za);
      const Eigen::Vector2d uv = camera.project(in_b);
      if (in_b.z() <= 0.0 || !camera.contains(uv.x(), uv.y()) || uv.x() >= camera.width - 1 || uv.y() >= camera.height - 1)
        continue;
      const int x = static_cast<int>(uv.x()), y = static_cast<int>(uv.y());
      const float z00 = b.depth(x, y), z10 = b.depth(x + 1, y), z01 = b.depth(x, y + 1), z11 = b.depth(x + 1, y + 1);
      if (!vocal::isValidDepth(z00) || !vocal::isValidDepth(z10) || !vocal::isValidDepth(z01) || !vocal::isValidDepth(z11))
        continue;
      const double i00 = 1.0 / z00, i10 = 1.0 / z10, i01 = 1.0 / z01, i11 = 1.0 / z11;
      // The four neighbours lie on one surface only if their inverse depths are affine and close
      // (a straight depth edge through the block is affine too, but jumps).
      const double spread = std::max({i00, i10, i01, i11}) - std::min({i00, i10, i01, i11});
      if (std::abs(i00 + i11 - i10 - i01) > 2e-3 * i00 || spread > 0.03 * i00) continue;
      const double fx = uv.x() - x, fy = uv.y() - y;
      const double z_b = 1.0 / ((1 - fy) * ((1 - fx) * i00 + fx * i10) + fy * ((1 - fx) * i01 + fx * i11));
      if (z_b < in_b.z() - 0.01) {
        ++occluded;  // something nearer hides the point in B
        continue;
      }
      const Eigen::Vector2d back = camera.project(b_from_a.inverse() * camera.backProject(uv.x(), uv.y(), z_b));
      worst_pixel_error = std::max(worst_pixel_error, (back - Eigen::Vector2d(u, v)).norm());
      luma_error_sum += std::abs(bilinearLuma(b.color, uv.x(), uv.y()) - luma(a.color(u, v)));
      ++compared;
    }
  }
  RecordProperty("compared_points", compared);
  ASSERT_GT(compared, 3000);
  EXPECT_LT(worst_pixel_error, 0.5);
  // Brightness constancy holds: colour is view independent, only interpolation differs.
  EXPECT_LT(luma_error_sum / compared, 2.0);
  std::cout << "compared " << compared << " points (" << occluded << " occluded): worst reprojection "
            << worst_pixel_error << " px, mean luma difference " << luma_error_sum / compared << "\n";
}

TEST(SyntheticSequence, KinectNoiseGrowsWithDepthSquared) {
  const vocal::SyntheticScene scene = vocal::SyntheticScene::make(vocal::SceneVariant::kIndoorRoom);
  const vocal::PinholeCamera camera = vocal::defaultKinectCamera(320, 240);
  const vocal::Trajectory path = vocal::generateSyntheticTrajectory(scene.workspace(), {});
  vocal::RgbdSensorModel noise_only;
  noise_only.axial_noise = true;
  // Bins of depth: measured standard deviation of (noisy - ideal) against the model's sigma(z).
  std::vector<double> sum_sq(10, 0.0), sigma_sum(10, 0.0);
  std::vector<int> count(10, 0);
  for (int k = 0; k < 4; ++k) {
    const vocal::RgbdFrame ideal = vocal::renderSyntheticFrame(scene, camera, path[k * 60], {}, 0);
    const vocal::RgbdFrame noisy = vocal::renderSyntheticFrame(scene, camera, path[k * 60], noise_only, k + 1);
    for (std::size_t p = 0; p < ideal.depth.size(); ++p) {
      const double z = ideal.depth.pixels()[p];
      if (!vocal::isValidDepth(noisy.depth.pixels()[p])) continue;
      const int bin = std::min(9, static_cast<int>(z));
      sum_sq[bin] += std::pow(noisy.depth.pixels()[p] - z, 2);
      sigma_sum[bin] += vocal::RgbdSensorModel::axialSigma(z);
      ++count[bin];
    }
  }
  int bins_checked = 0;
  for (int bin = 0; bin < 10; ++bin) {
    if (count[bin] < 2000) continue;
    const double measured = std::sqrt(sum_sq[bin] / count[bin]);
    const double expected = sigma_sum[bin] / count[bin];
    EXPECT_NEAR(measured, expected, 0.15 * expected) << "depth bin " << bin << " m";
    ++bins_checked;
  }
  EXPECT_GE(bins_checked, 2);

  // Drop-outs: about the requested fraction plus the depth edges; quantisation leaves discrete depths.
  const vocal::RgbdSensorModel kinect = vocal::kinectLikeSensorModel(0.1);
  const vocal::RgbdFrame frame = vocal::renderSyntheticFrame(scene, camera, path[0], kinect, 5);
  const double missing = std::count(frame.depth.pixels().begin(), frame.depth.pixels().end(), 0.0f) /
                         static_cast<double>(frame.depth.size());
  EXPECT_GT(missing, 0.1);
  EXPECT_LT(missing, 0.2);
}

TEST(SyntheticSequence, VariantsHaveTheStructureTheyPromise) {
  const vocal::PinholeCamera camera = vocal::defaultKinectCamera(160, 120);
  auto colours = [](const vocal::ColorImage& image) {
    std::set<int> unique;
    for (const vocal::Rgb8& p : image.pixels()) unique.insert(p.r << 16 | p.g << 8 | p.b);
    return unique.size();
  };
  for (vocal::SceneVariant variant :
       {vocal::SceneVariant::kIndoorRoom, vocal::SceneVariant::kTexturedWall, vocal::SceneVariant::kBareRoom, vocal::SceneVariant::kBlankWall}) {
    const vocal::SyntheticScene scene = vocal::SyntheticScene::make(variant);
    vocal::SyntheticTrajectoryOptions trajectory_options;
    trajectory_options.frames = 150;
    trajectory_options.speed = 0.5;
    const vocal::Trajectory path = vocal::generateSyntheticTrajectory(scene.workspace(), trajectory_options);
    for (std::size_t k = 0; k < path.size(); k += 30) {
      const vocal::RenderedView view = scene.render(camera, path[k].pose);
      const auto valid = std::count_if(view.depth.pixels().begin(), view.depth.pixels().end(), vocal::isValidDepth);
      EXPECT_EQ(valid, static_cast<long>(view.depth.size())) << "every ray hits a surface";
      if (variant == vocal::SceneVariant::kBareRoom || variant == vocal::SceneVariant::kBlankWall) {
        // The blank wall's workspace faces the panel: one untextured plane fills the view.
        EXPECT_LE(colours(view.color), variant == vocal::SceneVariant::kBlankWall ? 1u : 20u) << "untextured: one shade per surface orientation";
      } else {
        EXPECT_GT(colours(view.color), 1000u) << "textured";
      }
      if (variant == vocal::SceneVariant::kTexturedWall || variant == vocal::SceneVariant::kBlankWall) {
        // One plane: inverse depth is affine in the pixel coordinates everywhere.
        const auto& d = view.depth;
        for (int v = 0; v + 1 < d.height(); v += 7)
          for (int u = 0; u + 1 < d.width(); u += 7)
            ASSERT_NEAR(1 / d(u, v) + 1 / d(u + 1, v + 1), 1 / d(u + 1, v) + 1 / d(u, v + 1), 1e-5);
      }
    }
  }
  EXPECT_THROW(vocal::parseSceneVariant("garden"), vocal::InputError);
}

// The blank wall visit: the room (textured, many colours) before and after, the panel alone (one colour,
// one plane) all through the dwell, at the requested rate; bad spans refused.
TEST(BlankWallVisit, FacesThePanelAloneThroughTheDwellAndTheRoomAroundIt) {
  const vocal::SyntheticScene scene = vocal::SyntheticScene::make(vocal::SceneVariant::kBlankWall);
  const vocal::PinholeCamera camera = vocal::defaultKinectCamera(80, 60);
  vocal::BlankWallVisitOptions options;
  options.frame_rate = 10.0;
  const vocal::Trajectory path = vocal::generateBlankWallVisit(options);
  EXPECT_EQ(path.size(), 181u);  // 4 + 1 + 10 + 1 + 2 s at 10 Hz, both ends
  EXPECT_NEAR(path[1].stamp - path[0].stamp, 0.1, 1e-6);
  const auto [first, last] = vocal::blankWallDwell(options);
  EXPECT_DOUBLE_EQ(first, options.start_stamp + 5.0);
  EXPECT_DOUBLE_EQ(last, options.start_stamp + 15.0);
  const int panel = static_cast<int>(scene.surfaces().size()) - 1;
  for (const vocal::StampedPose& pose : path) {
    const bool dwelling = pose.stamp >= first && pose.stamp <= last;
    const bool in_room = pose.stamp < first - options.turn_seconds || pose.stamp > last + options.turn_seconds;
    int on_panel = 0, hits = 0;
    for (int v = 0; v < camera.height; v += 4) {
      for (int u = 0; u < camera.width; u += 4) {
        const Eigen::Vector3d ray = pose.pose.linear() * Eigen::Vector3d((u - camera.cx) / camera.fx, (v - camera.cy) / camera.fy, 1.0);
        double t = 0.0;
        int surface = -1;
        if (!scene.intersect(pose.pose.translation(), ray, &t, &surface)) continue;
        ++hits;
        on_panel += surface == panel;
      }
    }
    ASSERT_GT(hits, 0);
    if (dwelling) EXPECT_EQ(on_panel, hits) << "at " << pose.stamp - options.start_stamp << " s the view leaves the panel";
    if (in_room) EXPECT_LT(on_panel, hits / 3) << "at " << pose.stamp - options.start_stamp << " s the panel blocks the room";
  }
  options.turn_seconds = 0.0;
  EXPECT_THROW(vocal::generateBlankWallVisit(options), vocal::InputError);
}

TEST(SyntheticTrajectory, MovesAtTheRequestedSpeedAndRate) {
  const vocal::SyntheticScene scene = vocal::SyntheticScene::make(vocal::SceneVariant::kIndoorRoom);
  vocal::SyntheticTrajectoryOptions options;
  options.frames = 900;
  options.speed = 0.3;
  options.frame_rate = 30.0;
  const vocal::Trajectory path = vocal::generateSyntheticTrajectory(scene.workspace(), options);
  double length = 0.0, max_step_angle = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i) {
    length += (path[i].pose.translation() - path[i - 1].pose.translation()).norm();
    max_step_angle = std::max(max_step_angle, vocal::rotationAngle(path[i - 1].pose.inverse() * path[i].pose));
    EXPECT_NEAR(path[i].stamp - path[i - 1].stamp, 1.0 / 30.0, 1.1e-6);
  }
  const double duration = path.back().stamp - path.front().stamp;
  EXPECT_NEAR(length / duration, 0.3, 0.05);
  EXPECT_LT(max_step_angle, 0.05);  // smooth: well under 3 degrees per frame
  options.frames = 0;
  EXPECT_THROW(vocal::generateSyntheticTrajectory(scene.workspace(), options), vocal::InputError);
}

TEST(SyntheticSequence, BadOptionsAreErrors) {
  vocal::SyntheticSequenceOptions options = vocal_test::smallSequenceOptions(2);
  options.sensor_model.missing_fraction = 1.5;
  EXPECT_EQ(vocal_test::inputErrorOf([&] { vocal::writeSyntheticSequence(makeTempFolder("bad_options"), options); }),
            "synthetic sequence: missing fraction 1.500000 must be in [0, 1)");
  options = vocal_test::smallSequenceOptions(2);
  options.rolling_shutter_readout = -0.01;
  EXPECT_EQ(vocal_test::inputErrorOf([&] { vocal::writeSyntheticSequence(makeTempFolder("bad_readout"), options); }),
            "synthetic sequence: rolling shutter readout -0.010000 s must be in [0, 0.1]");
}
