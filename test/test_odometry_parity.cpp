// The OpenCL kernels (on PoCL in tests), the fast CPU backend and the CPU reference compute the same
// preprocessed maps and normal equations and, after a full solve, the same pose.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <thread>
#include <tuple>
#include <vector>

#include "test_support.h"

#include "vocal/core/errors.h"
#include "vocal/core/se3.h"
#include "vocal/odometry/cpu_backend.h"
#include "vocal/odometry/fast_cpu_backend.h"
#include "vocal/odometry/icp_dvo_odometry.h"
#include "vocal/simulation/synthetic_sequence.h"
#ifdef VOCAL_HAVE_OPENCL
#include "vocal/odometry/opencl_backend.h"
#include "vocal/odometry/opencl_context.h"
#endif

namespace {
struct FramePair {
  vocal::PinholeCamera camera;
  vocal::RgbdFrame first, second;
  Eigen::Isometry3d first_from_second;
};

FramePair renderPair(int frame_gap, bool kinect_noise, int width = 320, int height = 240) {
  const vocal::SyntheticScene scene = vocal::SyntheticScene::make(vocal::SceneVariant::kIndoorRoom);
  FramePair pair;
  pair.camera = vocal::defaultKinectCamera(width, height);
  vocal::SyntheticTrajectoryOptions options;
  options.frames = frame_gap + 1;
  const vocal::Trajectory path = vocal::generateSyntheticTrajectory(scene.workspace(), options);
  const vocal::RgbdSensorModel model = kinect_noise ? vocal::kinectLikeSensorModel() : vocal::RgbdSensorModel{};
  pair.first = vocal::renderSyntheticFrame(scene, pair.camera, path.front(), model, 1);
  pair.second = vocal::renderSyntheticFrame(scene, pair.camera, path.back(), model, 2);
  pair.first_from_second = path.front().pose.inverse() * path.back().pose;
  return pair;
}

bool openClAvailable() {
#ifdef VOCAL_HAVE_OPENCL
  return !vocal::listOpenClDevices().empty();
#else
  return false;
#endif
}

void expectSameSystem(const vocal::NormalEquations& cpu, const vocal::NormalEquations& gpu, const std::string& what) {
  ASSERT_GT(cpu.count, 100.0) << what;
  // Threshold decisions on float values may flip for a handful of pixels.
  EXPECT_NEAR(gpu.count, cpu.count, 1e-3 * cpu.count + 2) << what;
  EXPECT_LT((gpu.A - cpu.A).norm(), 2e-3 * cpu.A.norm()) << what;
  EXPECT_LT((gpu.b - cpu.b).norm(), 2e-3 * cpu.b.norm() + 1e-6 * cpu.A.norm()) << what;
  EXPECT_NEAR(gpu.squared_residual_sum, cpu.squared_residual_sum, 2e-3 * cpu.squared_residual_sum + 1e-9) << what;
}

vocal::OdometryConfig withThreads(int threads) {
  vocal::OdometryConfig config;
  config.threads = threads;
  return config;
}

// NaN in the same places, values within `tolerance` elsewhere.
void expectSameMap(const std::vector<float>& fast, const std::vector<float>& reference, float tolerance,
                   const std::string& what) {
  ASSERT_EQ(fast.size(), reference.size()) << what;
  std::size_t differ = 0, first = 0;
  for (std::size_t i = 0; i < fast.size(); ++i) {
    const bool same = std::isnan(fast[i]) ? std::isnan(reference[i]) : std::fabs(fast[i] - reference[i]) <= tolerance;
    if (!same && differ++ == 0) first = i;
  }
  EXPECT_EQ(differ, 0u) << what << ": first at pixel " << first << ": " << fast[first] << " vs " << reference[first];
}

using BackendFactory =
    std::function<std::unique_ptr<vocal::OdometryBackend>(const vocal::PinholeCamera&, const vocal::OdometryConfig&)>;

// Every level's systems from the reference and from `make_other`'s backend, at the true motion and
// away from it (where more pairs are rejected): each built alone, and both together as the estimator
// asks for them (one pass on the fast backend); the photometric term with an exposure change mapped
// (which must change it: the brightness reaches every backend's residual).
void expectSameSystemsAsTheReference(const BackendFactory& make_other, int width = 320, int height = 240) {
  for (bool noise : {false, true}) {
    const FramePair pair = renderPair(3, noise, width, height);
    vocal::OdometryConfig config;
    config.depth_noise_quadratic = 0.001;  // pairs weighted by their depth noise (off by default)
    vocal::CpuOdometryBackend reference(pair.camera, config);
    const std::unique_ptr<vocal::OdometryBackend> other = make_other(pair.camera, config);
    for (const vocal::RgbdFrame* frame : {&pair.first, &pair.second}) {
      reference.pushFrame(*frame, vocal::ReferenceUpdate::kPreviousFrame);
      other->pushFrame(*frame, vocal::ReferenceUpdate::kPreviousFrame);
    }
    vocal::Vector6d offset;
    offset << 0.01, -0.005, 0.008, 0.004, -0.003, 0.002;
    // Every ICP pair alike: the depth noise weights must reach the reference's ICP rows.
    vocal::OdometryConfig uniform = config;
    uniform.depth_noise_quadratic = 0.0;
    vocal::CpuOdometryBackend reference_uniform(pair.camera, uniform);
    for (const vocal::RgbdFrame* frame : {&pair.first, &pair.second})
      reference_uniform.pushFrame(*frame, vocal::ReferenceUpdate::kPreviousFrame);
    vocal::BrightnessTransfer exposure;
    exposure.gain = 1.08f;
    exposure.bias = -0.02f;
    for (const Eigen::Isometry3d& T : {pair.first_from_second, vocal::se3Exp(offset) * pair.first_from_second}) {
      for (int level = 0; level < config.levels; ++level) {
        const std::string where = std::string(noise ? "noisy" : "clean") + " level " + std::to_string(level);
        const vocal::NormalEquations icp = reference.icpSystem(level, T), rgb = reference.rgbSystem(level, T, 0.02, exposure);
        EXPECT_GT(std::fabs(rgb.squared_residual_sum - reference.rgbSystem(level, T, 0.02, vocal::BrightnessTransfer()).squared_residual_sum),
                  1e-3 * rgb.squared_residual_sum)
            << "the exposure change did not reach the residuals, " << where;
        EXPECT_GT((icp.A - reference_uniform.icpSystem(level, T).A).norm(), 1e-2 * icp.A.norm())
            << "the depth noise weights did not reach the ICP rows, " << where;
        vocal::NormalEquations icp_together, rgb_together;
        other->trackingSystems(level, T, 0.02, exposure, &icp_together, &rgb_together);
        expectSameSystem(icp, icp_together, "icp " + where);
        expectSameSystem(rgb, rgb_together, "rgb " + where);
        expectSameSystem(icp, other->icpSystem(level, T), "icp alone " + where);
        expectSameSystem(rgb, other->rgbSystem(level, T, 0.02, exposure), "rgb alone " + where);
      }
    }
  }
}

// Noise-free frames determine the pose sharply, so float rounding must not move it; with sensor noise a
// few threshold decisions that flip between float orders move a flat optimum by a fraction of the
// estimate's own error (about 2 mm per frame for ICP alone here). Both are also held to the truth (a
// 4-frame step of about 3 cm), so that agreeing on a wrong answer cannot pass; ICP alone is the weak
// term on the noisy room's far, quantised depth.
void expectSamePoseAsTheReference(const BackendFactory& make_other) {
  for (bool noise : {false, true}) {
    const double tolerance = noise ? 3e-4 : 2e-5;
    const FramePair pair = renderPair(4, noise);
    for (vocal::OdometryMode mode : {vocal::OdometryMode::kIcp, vocal::OdometryMode::kRgb, vocal::OdometryMode::kFused}) {
      vocal::OdometryConfig config;
      config.mode = mode;
      vocal::IcpDvoOdometry reference(pair.camera, config, std::make_unique<vocal::CpuOdometryBackend>(pair.camera, config));
      vocal::IcpDvoOdometry other(pair.camera, config, make_other(pair.camera, config));
      reference.track(pair.first);
      other.track(pair.first);
      const vocal::OdometryResult a = reference.track(pair.second);
      const vocal::OdometryResult b = other.track(pair.second);
      const std::string what = vocal::odometryModeName(mode) + (noise ? " noisy" : " clean");
      ASSERT_TRUE(a.quality.trusted) << what << ": " << a.failure;
      ASSERT_TRUE(b.quality.trusted) << what << ": " << b.failure;
      const Eigen::Isometry3d difference = a.increment.inverse() * b.increment;
      EXPECT_LT(difference.translation().norm(), tolerance) << what;
      EXPECT_LT(vocal::rotationAngle(difference), tolerance) << what;
      const Eigen::Isometry3d error = pair.first_from_second.inverse() * b.increment;
      EXPECT_LT(error.translation().norm(), !noise ? 1e-3 : mode == vocal::OdometryMode::kIcp ? 0.02 : 0.005) << what;
    }
  }
}
}  // namespace

// Both passes: the portable one and, where the CPU has it, the AVX2 one (depth smoothing, depth pyramid,
// vertex and normal records).
TEST(FastCpuParity, SameMapsOnEveryLevel) {
  const FramePair pair = renderPair(3, true);
  const vocal::OdometryConfig config;
  const vocal::FramePyramid reference = vocal::buildFramePyramid(pair.second, pair.camera, config);
  for (const vocal::CpuTrackingPass pass : {vocal::CpuTrackingPass::kBest, vocal::CpuTrackingPass::kPortable}) {
    vocal::FastCpuOdometryBackend fast(pair.camera, config, pass);
    fast.pushFrame(pair.second, vocal::ReferenceUpdate::kPreviousFrame);
    for (int level = 0; level < config.levels; ++level) {
      const vocal::PyramidLevel& r = reference[level];
      const vocal::SoaPyramidLevel& f = fast.current()[level];
      const std::string where = "level " + std::to_string(level) + ", " + fast.name();
      ASSERT_EQ(f.width, r.depth.width()) << where;
      ASSERT_EQ(f.height, r.depth.height()) << where;
      expectSameMap(f.depth, r.depth.pixels(), 0.0f, "depth " + where);
      if (level == 0) {
        const vocal::DepthImage smoothed =
            vocal::smoothDepth(r.depth, config.depth_smoothing_radius, static_cast<float>(config.depth_smoothing_factor));
        expectSameMap(f.smoothed_depth, smoothed.pixels(), 0.0f, "smoothed depth " + where);
      }
      expectSameMap(f.intensity, r.intensity.pixels(), 0.0f, "intensity " + where);
      expectSameMap(f.gradient_x, r.gradient_x.pixels(), 0.0f, "gradient_x " + where);
      expectSameMap(f.gradient_y, r.gradient_y.pixels(), 0.0f, "gradient_y " + where);
      std::vector<float> vertex[3], normal[3], reference_vertex[3], reference_normal[3];
      for (std::size_t i = 0; i < f.surface.size(); ++i) {
        const vocal::SurfaceRecord& s = f.surface[i];
        const float fast_values[6] = {s.vx, s.vy, s.vz, s.nx, s.ny, s.nz};
        for (int k = 0; k < 3; ++k) {
          vertex[k].push_back(fast_values[k]);
          normal[k].push_back(fast_values[3 + k]);
          reference_vertex[k].push_back(r.vertices.pixels()[i][k]);
          reference_normal[k].push_back(r.normals.pixels()[i][k]);
        }
        ASSERT_EQ(f.photometric[i].depth, f.depth[i]);
        ASSERT_EQ(f.photometric[i].gradient_x, f.gradient_x[i]);
      }
      for (int k = 0; k < 3; ++k) {
        expectSameMap(vertex[k], reference_vertex[k], 0.0f, "vertex " + std::to_string(k) + " " + where);
        expectSameMap(normal[k], reference_normal[k], 1e-6f, "normal " + std::to_string(k) + " " + where);
      }
    }
  }
}

BackendFactory fastBackend(vocal::CpuTrackingPass pass) {
  return [pass](const vocal::PinholeCamera& camera, const vocal::OdometryConfig& config) {
    return std::make_unique<vocal::FastCpuOdometryBackend>(camera, config, pass);
  };
}

const vocal::CpuTrackingPass kBothPasses[] = {vocal::CpuTrackingPass::kBest, vocal::CpuTrackingPass::kPortable};

std::string passName(vocal::CpuTrackingPass pass) {
  return pass == vocal::CpuTrackingPass::kBest ? "best pass" : "portable pass";
}

TEST(FastCpuParity, SameNormalEquationsOnEveryLevel) {
  for (vocal::CpuTrackingPass pass : kBothPasses) {
    SCOPED_TRACE(passName(pass));
    expectSameSystemsAsTheReference(fastBackend(pass));
  }
}

// 324 x 242: rows of 324, 162 and 81 pixels end in part-filled blocks of 8.
TEST(FastCpuParity, SameNormalEquationsWhenRowsAreNotWholeBlocks) {
  for (vocal::CpuTrackingPass pass : kBothPasses) {
    SCOPED_TRACE(passName(pass));
    expectSameSystemsAsTheReference(fastBackend(pass), 324, 242);
  }
}

// The vectorised pass is what runs wherever the CPU can: x86-64 with AVX2 + FMA (every CI machine).
TEST(FastCpuParity, BestPassIsTheVectorisedOneWhereTheCpuHasIt) {
  const vocal::PinholeCamera camera = vocal::defaultKinectCamera(320, 240);
  const vocal::OdometryConfig config = withThreads(2);
  EXPECT_EQ(vocal::FastCpuOdometryBackend(camera, config, vocal::CpuTrackingPass::kPortable).name(),
            "cpu fast (2 threads, portable)");
#if defined(__GNUC__) && defined(__x86_64__)
  __builtin_cpu_init();
  const bool avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  EXPECT_EQ(vocal::FastCpuOdometryBackend(camera, config).name(),
            avx2 ? "cpu fast (2 threads, AVX2)" : "cpu fast (2 threads, portable)");
#else
  EXPECT_EQ(vocal::FastCpuOdometryBackend(camera, config).name(), "cpu fast (2 threads, portable)");
#endif
}

// Rows are summed per block and the blocks in order, blocks fixed by the image: every thread count gives
// the same maps and systems to the bit (a bag replayed on another robot gives the same trajectory).
TEST(FastCpuParity, EveryThreadCountGivesTheSameMapsAndSystemsExactly) {
  const FramePair pair = renderPair(3, true);
  struct Result {
    vocal::SoaFramePyramid pyramid;
    std::vector<vocal::NormalEquations> systems;  // icp and rgb per level
  };
  std::vector<Result> results;
  const std::vector<int> counts = {1, 2, 3, 4, 2};
  for (int threads : counts) {
    vocal::FastCpuOdometryBackend fast(pair.camera, withThreads(threads));
    EXPECT_EQ(fast.threads(), threads);
    fast.pushFrame(pair.first, vocal::ReferenceUpdate::kPreviousFrame);
    fast.pushFrame(pair.second, vocal::ReferenceUpdate::kPreviousFrame);
    Result result{fast.current(), {}};
    for (int level = 0; level < 3; ++level) {
      vocal::NormalEquations icp, rgb;
      fast.trackingSystems(level, pair.first_from_second, 0.02, vocal::BrightnessTransfer{1.1f, -0.02f, 1000}, &icp, &rgb);
      ASSERT_GT(icp.count, 100.0);
      ASSERT_GT(rgb.count, 100.0);
      result.systems.push_back(icp);
      result.systems.push_back(rgb);
    }
    results.push_back(result);
  }
  for (std::size_t k = 1; k < results.size(); ++k) {
    SCOPED_TRACE(std::to_string(counts[k]) + " threads against 1");
    for (std::size_t s = 0; s < results[0].systems.size(); ++s) {
      EXPECT_EQ(results[k].systems[s].A, results[0].systems[s].A) << "system " << s;
      EXPECT_EQ(results[k].systems[s].b, results[0].systems[s].b) << "system " << s;
      EXPECT_EQ(results[k].systems[s].count, results[0].systems[s].count) << "system " << s;
      EXPECT_EQ(results[k].systems[s].squared_residual_sum, results[0].systems[s].squared_residual_sum) << "system " << s;
    }
    for (std::size_t level = 0; level < results[0].pyramid.size(); ++level) {
      const vocal::SoaPyramidLevel &a = results[k].pyramid[level], &b = results[0].pyramid[level];
      // Bytes, so that NaN equals NaN.
      auto same = [](const auto& x, const auto& y) {
        return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(x[0])) == 0;
      };
      EXPECT_TRUE(same(a.depth, b.depth) && same(a.intensity, b.intensity) && same(a.gradient_x, b.gradient_x) &&
                  same(a.gradient_y, b.gradient_y) && same(a.smoothed_depth, b.smoothed_depth))
          << "level " << level << " planes";
      EXPECT_TRUE(same(a.surface, b.surface) && same(a.photometric, b.photometric)) << "level " << level << " records";
    }
  }
}

// A backend told the frames will be tracked from level 1 on (a live stream keeping pace) leaves level 0's
// maps out, and gives the coarser levels' maps and systems to the bit as one that built every level.
TEST(FastCpuParity, FramesBuiltForACoarserFinestLevelGiveTheSameCoarseSystems) {
  const FramePair pair = renderPair(3, true);
  vocal::FastCpuOdometryBackend full(pair.camera, withThreads(2)), coarse(pair.camera, withThreads(2));
  coarse.setFinestLevel(1);
  for (vocal::FastCpuOdometryBackend* backend : {&full, &coarse}) {
    backend->pushFrame(pair.first, vocal::ReferenceUpdate::kPreviousFrame);
    backend->pushFrame(pair.second, vocal::ReferenceUpdate::kPreviousFrame);
  }
  // Level 0's gradients are left as allocated (zero), not computed.
  EXPECT_NE(coarse.current()[0].gradient_x, full.current()[0].gradient_x) << "level 0's maps were built all the same";
  for (int level = 1; level < 3; ++level) {
    vocal::NormalEquations icp[2], rgb[2];
    full.trackingSystems(level, pair.first_from_second, 0.02, vocal::BrightnessTransfer{1.1f, -0.02f, 1000}, &icp[0], &rgb[0]);
    coarse.trackingSystems(level, pair.first_from_second, 0.02, vocal::BrightnessTransfer{1.1f, -0.02f, 1000}, &icp[1], &rgb[1]);
    ASSERT_GT(icp[0].count, 100.0);
    EXPECT_EQ(icp[1].A, icp[0].A) << "level " << level;
    EXPECT_EQ(icp[1].b, icp[0].b) << "level " << level;
    EXPECT_EQ(rgb[1].A, rgb[0].A) << "level " << level;
    EXPECT_EQ(rgb[1].count, rgb[0].count) << "level " << level;
  }
}

// One row in 2 or 3 of level 0 (a live stream keeping pace): both passes give the reference's sampled
// systems, the other levels every row; the sampled sums stand for the whole image's (times the step:
// inliers within 3 %, the information within 10 %), the motion they solve for within 1 mm / 1 mrad of
// every row's. The OpenCL backend tracks every row and says so.
TEST(FastCpuParity, SampledRowsGiveTheReferencesSampledSystemsStandingForTheWhole) {
  const FramePair pair = renderPair(3, true);
  vocal::OdometryConfig config = withThreads(2);
  vocal::CpuOdometryBackend every_row(pair.camera, config);
  for (const vocal::RgbdFrame* frame : {&pair.first, &pair.second}) every_row.pushFrame(*frame, vocal::ReferenceUpdate::kPreviousFrame);
  vocal::Vector6d offset;
  offset << 0.004, -0.002, 0.003, 0.002, -0.001, 0.001;
  const Eigen::Isometry3d start = vocal::se3Exp(offset) * pair.first_from_second;
  const vocal::BrightnessTransfer exposure{1.05f, -0.01f, 1000};
  for (int step : {2, 3}) {
    vocal::CpuOdometryBackend reference(pair.camera, config);
    EXPECT_TRUE(reference.setSampledRows(0, step));
    for (const vocal::RgbdFrame* frame : {&pair.first, &pair.second}) reference.pushFrame(*frame, vocal::ReferenceUpdate::kPreviousFrame);
    for (vocal::CpuTrackingPass pass : kBothPasses) {
      vocal::FastCpuOdometryBackend fast(pair.camera, config, pass);
      EXPECT_TRUE(fast.setSampledRows(0, step));
      for (const vocal::RgbdFrame* frame : {&pair.first, &pair.second}) fast.pushFrame(*frame, vocal::ReferenceUpdate::kPreviousFrame);
      for (int level = 0; level < config.levels; ++level) {
        const std::string where = passName(pass) + ", one row in " + std::to_string(step) + ", level " + std::to_string(level);
        vocal::NormalEquations icp, rgb;
        fast.trackingSystems(level, start, 0.02, exposure, &icp, &rgb);
        expectSameSystem(reference.icpSystem(level, start), icp, "icp " + where);
        expectSameSystem(reference.rgbSystem(level, start, 0.02, exposure), rgb, "rgb " + where);
        if (level > 0) {
          EXPECT_EQ(icp.count, every_row.icpSystem(level, start).count) << "every row above the sampled level, " << where;
          continue;
        }
        for (const auto& [sampled, whole, term] :
             {std::tuple{icp, every_row.icpSystem(0, start), "icp"}, std::tuple{rgb, every_row.rgbSystem(0, start, 0.02, exposure), "rgb"}}) {
          EXPECT_NEAR(sampled.count, whole.count, 0.03 * whole.count) << term << ", " << where;
          EXPECT_LT((sampled.A - whole.A).norm(), 0.1 * whole.A.norm()) << term << ", " << where;
          EXPECT_NEAR(sampled.rmse(), whole.rmse(), 0.05 * whole.rmse()) << term << ", " << where;
        }
        // One Gauss-Newton step of the fused system from each: the same motion.
        const auto fusedStep = [](const vocal::NormalEquations& i, const vocal::NormalEquations& r) {
          const vocal::Matrix6d A = i.A / (i.squared_residual_sum / i.count) + r.A / (r.squared_residual_sum / r.count);
          const vocal::Vector6d b = i.b / (i.squared_residual_sum / i.count) + r.b / (r.squared_residual_sum / r.count);
          return vocal::Vector6d(A.ldlt().solve(b));
        };
        const vocal::Vector6d difference = fusedStep(icp, rgb) - fusedStep(every_row.icpSystem(0, start), every_row.rgbSystem(0, start, 0.02, exposure));
        EXPECT_LT(difference.head<3>().norm(), 1e-3) << where;
        EXPECT_LT(difference.tail<3>().norm(), 1e-3) << where;
      }
    }
  }
#ifdef VOCAL_HAVE_OPENCL
  if (openClAvailable()) {
    vocal::OpenClOdometryBackend opencl(pair.camera, config);
    EXPECT_FALSE(opencl.setSampledRows(0, 2));
    EXPECT_TRUE(opencl.setSampledRows(0, 1));
  }
#endif
}

// The whole estimator - rolling-shutter rectification, the brightness transfer, the pyramid, the solve -
// tracks a sequence to the same poses, bit for bit, on 1, 2 and 4 threads.
TEST(FastCpuParity, EveryThreadCountTracksTheSamePosesExactly) {
  const vocal::SyntheticScene scene = vocal::SyntheticScene::make(vocal::SceneVariant::kIndoorRoom);
  const vocal::PinholeCamera camera = vocal::defaultKinectCamera(320, 240);
  vocal::SyntheticTrajectoryOptions options;
  options.frames = 12;
  const vocal::Trajectory truth = vocal::generateSyntheticTrajectory(scene.workspace(), options);
  std::vector<vocal::RgbdFrame> frames;
  for (int i = 0; i < options.frames; ++i) {
    frames.push_back(vocal::renderRollingShutterFrame(scene, camera, truth, i, 0.02, vocal::kinectLikeSensorModel(), 40 + i));
  }
  std::vector<std::vector<Eigen::Matrix4d>> poses;
  for (int threads : {1, 2, 4}) {
    vocal::OdometryConfig config = withThreads(threads);
    config.backend = vocal::OdometryBackendKind::kCpu;
    ASSERT_GT(config.rolling_shutter_readout, 0.0);
    ASSERT_EQ(config.brightness_model, vocal::BrightnessModel::kAffine);
    vocal::IcpDvoOdometry odometry(camera, config);
    ASSERT_TRUE(odometry.rectifying());
    poses.emplace_back();
    for (const vocal::RgbdFrame& frame : frames) {
      const vocal::OdometryResult result = odometry.track(frame);
      ASSERT_TRUE(result.quality.trusted) << threads << " threads, frame at " << frame.stamp;
      poses.back().push_back(result.pose.matrix());
    }
  }
  for (std::size_t k = 1; k < poses.size(); ++k) {
    for (std::size_t i = 0; i < frames.size(); ++i) EXPECT_EQ(poses[k][i], poses[0][i]) << "run " << k << ", frame " << i;
  }
}

// Tracking against a keyframe: a frame pushed with kKeep replaces only the current frame. Every
// backend then builds exactly the systems of the pair (keyframe, frame) pushed afresh.
TEST(OdometryParity, KeepingTheReferenceReplacesOnlyTheCurrentFrame) {
  const FramePair pair = renderPair(3, true);
  const FramePair other = renderPair(6, true);  // its frames are pushed in between
  std::vector<std::unique_ptr<vocal::OdometryBackend>> kept, fresh;
  kept.push_back(std::make_unique<vocal::CpuOdometryBackend>(pair.camera, vocal::OdometryConfig{}));
  fresh.push_back(std::make_unique<vocal::CpuOdometryBackend>(pair.camera, vocal::OdometryConfig{}));
  kept.push_back(std::make_unique<vocal::FastCpuOdometryBackend>(pair.camera, withThreads(2)));
  fresh.push_back(std::make_unique<vocal::FastCpuOdometryBackend>(pair.camera, withThreads(2)));
#ifdef VOCAL_HAVE_OPENCL
  if (openClAvailable()) {
    vocal::OdometryConfig config;
    config.backend = vocal::OdometryBackendKind::kOpenCl;
    kept.push_back(vocal::makeOdometryBackend(pair.camera, config));
    fresh.push_back(vocal::makeOdometryBackend(pair.camera, config));
  }
#endif
  for (std::size_t k = 0; k < kept.size(); ++k) {
    SCOPED_TRACE(kept[k]->name());
    // The reference stays pair.first through three frames; only the last is the current one.
    kept[k]->pushFrame(pair.first, vocal::ReferenceUpdate::kPreviousFrame);
    kept[k]->pushFrame(other.second, vocal::ReferenceUpdate::kPreviousFrame);
    kept[k]->pushFrame(other.first, vocal::ReferenceUpdate::kKeep);
    kept[k]->pushFrame(pair.second, vocal::ReferenceUpdate::kKeep);
    fresh[k]->pushFrame(pair.first, vocal::ReferenceUpdate::kPreviousFrame);
    fresh[k]->pushFrame(pair.second, vocal::ReferenceUpdate::kPreviousFrame);
    for (int level = 0; level < 3; ++level) {
      vocal::NormalEquations kept_icp, kept_rgb, fresh_icp, fresh_rgb;
      kept[k]->trackingSystems(level, pair.first_from_second, 0.02, vocal::BrightnessTransfer(), &kept_icp, &kept_rgb);
      fresh[k]->trackingSystems(level, pair.first_from_second, 0.02, vocal::BrightnessTransfer(), &fresh_icp, &fresh_rgb);
      ASSERT_GT(fresh_icp.count, 100.0);
      EXPECT_EQ(kept_icp.A, fresh_icp.A) << "level " << level;
      EXPECT_EQ(kept_icp.b, fresh_icp.b) << "level " << level;
      EXPECT_EQ(kept_rgb.A, fresh_rgb.A) << "level " << level;
      EXPECT_EQ(kept_rgb.count, fresh_rgb.count) << "level " << level;
    }
  }
}

TEST(FastCpuParity, SamePoseAfterAFullSolve) {
  for (vocal::CpuTrackingPass pass : kBothPasses) {
    SCOPED_TRACE(passName(pass));
    expectSamePoseAsTheReference(fastBackend(pass));
  }
}

TEST(OdometryBackendChoice, EachKindMakesItsBackend) {
  const vocal::PinholeCamera camera = vocal::defaultKinectCamera(320, 240);
  vocal::OdometryConfig config;
  config.backend = vocal::OdometryBackendKind::kReference;
  EXPECT_EQ(vocal::makeOdometryBackend(camera, config)->name(), "cpu reference");
  config.backend = vocal::OdometryBackendKind::kCpu;
  config.threads = 3;
  const std::string pass = vocal::FastCpuOdometryBackend(camera, config).name().find("AVX2") != std::string::npos
                               ? "AVX2" : "portable";
  EXPECT_EQ(vocal::makeOdometryBackend(camera, config)->name(), "cpu fast (3 threads, " + pass + ")");
  config.threads = 1;
  EXPECT_EQ(vocal::makeOdometryBackend(camera, config)->name(), "cpu fast (1 thread, " + pass + ")");
  // Auto: OpenCL only on a GPU; everywhere else (CI, PoCL's CPU device) the fast CPU backend, said so.
  config.backend = vocal::OdometryBackendKind::kAuto;
  std::string notice;
  const std::unique_ptr<vocal::OdometryBackend> automatic = vocal::makeOdometryBackend(camera, config, &notice);
#ifdef VOCAL_HAVE_OPENCL
  bool has_gpu = false;
  for (const vocal::OpenClDeviceInfo& d : vocal::listOpenClDevices()) has_gpu |= d.is_gpu;
  if (has_gpu) GTEST_SKIP() << "a GPU is present: auto picks OpenCL (" << automatic->name() << ")";
  EXPECT_EQ(notice, "no GPU OpenCL device found: using the fast CPU backend");
#else
  EXPECT_EQ(notice, "OpenCL was not found at build time: using the fast CPU backend");
#endif
  EXPECT_EQ(automatic->name(), "cpu fast (1 thread, " + pass + ")");
}

#ifdef VOCAL_HAVE_OPENCL
TEST(OdometryParity, SameNormalEquationsOnEveryLevel) {
  if (!openClAvailable()) GTEST_SKIP() << "no OpenCL platform on this machine";
  expectSameSystemsAsTheReference([](const vocal::PinholeCamera& camera, const vocal::OdometryConfig& config) {
    return std::make_unique<vocal::OpenClOdometryBackend>(camera, config);
  });
}

TEST(OdometryParity, SamePoseAfterAFullSolve) {
  if (!openClAvailable()) GTEST_SKIP() << "no OpenCL platform on this machine";
  expectSamePoseAsTheReference([](const vocal::PinholeCamera& camera, const vocal::OdometryConfig& config) {
    return std::make_unique<vocal::OpenClOdometryBackend>(camera, config);
  });
}

// Three odometry nodelets in one manager build their estimators at once on their first frames. The
// race is in the OpenCL implementation's first enumeration (PoCL crashed in about half the fresh
// processes that enumerated from 8 threads at once), so each try is a fresh process: a death test
// in "threadsafe" style runs the statement in a new run of this program.
TEST(OpenClDevicesDeathTest, ListedFromManyThreadsAtOnceInAFreshProcess) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  for (int attempt = 0; attempt < 10; ++attempt) {
    EXPECT_EXIT(
        {
          std::vector<std::thread> threads;
          for (int i = 0; i < 8; ++i) threads.emplace_back([] { vocal::listOpenClDevices(); });
          for (std::thread& t : threads) t.join();
          std::exit(0);
        },
        ::testing::ExitedWithCode(0), "")
        << "attempt " << attempt;
  }
}

TEST(OdometryParity, DeviceChoiceErrorsNameWhatWasFound) {
  const std::vector<vocal::OpenClDeviceInfo> devices = {{"Portable Computing Language", "pthread-cpu", false, true},
                                                        {"NVIDIA CUDA", "NVIDIA H100", true, false}};
  EXPECT_EQ(vocal::chooseOpenClDevice(devices, "", ""), 1u);  // the GPU first
  EXPECT_EQ(vocal::chooseOpenClDevice(devices, "portable", ""), 0u);
  EXPECT_EQ(vocal_test::inputErrorOf([&] { vocal::chooseOpenClDevice(devices, "", "radeon"); }),
            "OpenCL: no device matches platform '' and device 'radeon'; found: [Portable Computing Language: "
            "pthread-cpu] [NVIDIA CUDA: NVIDIA H100]");
  EXPECT_THROW(vocal::chooseOpenClDevice({}, "", ""), vocal::InputError);
}
#endif
