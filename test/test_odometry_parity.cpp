// The OpenCL kernels (on PoCL in tests) and the CPU reference compute the same normal equations and,
// after a full solve, the same pose.

#include <gtest/gtest.h>

#include "test_support.h"

#include "vocal/core/errors.h"
#include "vocal/core/se3.h"
#include "vocal/core/synthetic_sequence.h"
#include "vocal/odometry/cpu_backend.h"
#include "vocal/odometry/icp_dvo_odometry.h"
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

FramePair renderPair(int frame_gap, bool kinect_noise) {
  const vocal::SyntheticScene scene = vocal::SyntheticScene::make(vocal::SceneVariant::kIndoorRoom);
  FramePair pair;
  pair.camera = vocal::defaultKinectCamera(320, 240);
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
}  // namespace

#ifdef VOCAL_HAVE_OPENCL
TEST(OdometryParity, SameNormalEquationsOnEveryLevel) {
  if (!openClAvailable()) GTEST_SKIP() << "no OpenCL platform on this machine";
  for (bool noise : {false, true}) {
    const FramePair pair = renderPair(3, noise);
    vocal::OdometryConfig config;
    vocal::CpuOdometryBackend cpu(pair.camera, config);
    vocal::OpenClOdometryBackend gpu(pair.camera, config);
    for (const vocal::RgbdFrame* frame : {&pair.first, &pair.second}) {
      cpu.pushFrame(*frame);
      gpu.pushFrame(*frame);
    }
    // Evaluate away from the solution too, where more pairs are rejected.
    vocal::Vector6d offset;
    offset << 0.01, -0.005, 0.008, 0.004, -0.003, 0.002;
    for (const Eigen::Isometry3d& T : {pair.first_from_second, vocal::se3Exp(offset) * pair.first_from_second}) {
      for (int level = 0; level < config.levels; ++level) {
        const std::string where = std::string(noise ? "noisy" : "clean") + " level " + std::to_string(level);
        expectSameSystem(cpu.icpSystem(level, T), gpu.icpSystem(level, T), "icp " + where);
        expectSameSystem(cpu.rgbSystem(level, T, 0.02), gpu.rgbSystem(level, T, 0.02), "rgb " + where);
      }
    }
  }
}

// Noise-free frames determine the pose sharply, so float rounding must not move it; with sensor noise a
// few threshold decisions that flip between float orders move a flat optimum by a fraction of the
// estimate's own error (about 2 mm per frame for ICP alone here).
TEST(OdometryParity, SamePoseAfterAFullSolve) {
  if (!openClAvailable()) GTEST_SKIP() << "no OpenCL platform on this machine";
  for (bool noise : {false, true}) {
  const double tolerance = noise ? 3e-4 : 2e-5;
  const FramePair pair = renderPair(4, noise);
  for (vocal::OdometryMode mode : {vocal::OdometryMode::kIcp, vocal::OdometryMode::kRgb, vocal::OdometryMode::kFused}) {
    vocal::OdometryConfig config;
    config.mode = mode;
    vocal::IcpDvoOdometry cpu(pair.camera, config, std::make_unique<vocal::CpuOdometryBackend>(pair.camera, config));
    vocal::IcpDvoOdometry gpu(pair.camera, config, std::make_unique<vocal::OpenClOdometryBackend>(pair.camera, config));
    cpu.track(pair.first);
    gpu.track(pair.first);
    const vocal::OdometryResult a = cpu.track(pair.second);
    const vocal::OdometryResult b = gpu.track(pair.second);
    ASSERT_TRUE(a.quality.trusted) << a.failure;
    ASSERT_TRUE(b.quality.trusted) << b.failure;
    const Eigen::Isometry3d difference = a.increment.inverse() * b.increment;
    EXPECT_LT(difference.translation().norm(), tolerance) << vocal::odometryModeName(mode) << (noise ? " noisy" : "");
    EXPECT_LT(vocal::rotationAngle(difference), tolerance) << vocal::odometryModeName(mode) << (noise ? " noisy" : "");
  }
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
