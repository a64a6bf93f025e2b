// The odometry backends' work per frame, timed with a steady clock, and each backend's normal
// equations against the reference's on the same frame pair. ROS-free and OpenCV-free, so that it also
// builds on a GPU machine that has only a compiler and an OpenCL driver
// (bench/backend_timing_standalone.sh); odometry_benchmark is the Google Benchmark of the same stages.
//   backend_timing [REPEATS]   (default 200; the reference backend runs 10)
// Synthetic Kinect-like frames of the textured room at 640x480 and 320x240. "A frame's dense work" is
// one preprocessing plus the tracking systems of 3 iterations a level (what a converging frame needs)
// up to the default schedule's 10 / 5 / 4; the 6x6 solves and brightness transfers are left out.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "vocal/core/errors.h"
#include "vocal/odometry/cpu_backend.h"
#include "vocal/odometry/fast_cpu_backend.h"
#include "vocal/simulation/rgbd_sensor_model.h"
#include "vocal/simulation/synthetic_scene.h"
#include "vocal/simulation/synthetic_trajectory.h"
#ifdef VOCAL_HAVE_OPENCL
#include "vocal/odometry/opencl_backend.h"
#endif

namespace {
using Clock = std::chrono::steady_clock;

double millisecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// The larger of the relative differences of A and b.
double relativeDifference(const vocal::NormalEquations& a, const vocal::NormalEquations& reference) {
  return std::max((a.A - reference.A).norm() / reference.A.norm(), (a.b - reference.b).norm() / reference.b.norm());
}

void timeBackends(int width, int repeats) {
  const vocal::PinholeCamera camera = vocal::defaultKinectCamera(width, width * 3 / 4);
  const vocal::SyntheticScene scene = vocal::SyntheticScene::make(vocal::SceneVariant::kIndoorRoom);
  vocal::SyntheticTrajectoryOptions options;
  options.frames = 8;
  const vocal::Trajectory truth = vocal::generateSyntheticTrajectory(scene.workspace(), options);
  std::vector<vocal::RgbdFrame> frames;
  for (int i = 0; i < options.frames; ++i) {
    vocal::RenderedView view = scene.render(camera, truth[i].pose);
    vocal::applyDepthSensorModel(vocal::kinectLikeSensorModel(), i, &view.depth);
    vocal::applyColorSensorModel(vocal::kinectLikeSensorModel(), i, &view.color);
    vocal::RgbdFrame frame;
    frame.stamp = truth[i].stamp;
    frame.color = std::move(view.color);
    frame.depth = std::move(view.depth);
    frames.push_back(std::move(frame));
  }
  const vocal::OdometryConfig config;
  std::vector<std::unique_ptr<vocal::OdometryBackend>> backends;
  backends.push_back(std::make_unique<vocal::CpuOdometryBackend>(camera, config));
  backends.push_back(std::make_unique<vocal::FastCpuOdometryBackend>(camera, config));
#ifdef VOCAL_HAVE_OPENCL
  try {
    backends.push_back(std::make_unique<vocal::OpenClOdometryBackend>(camera, config));
  } catch (const vocal::InputError& e) {
    std::printf("OpenCL backend not timed: %s\n", e.what());
  }
#endif
  const Eigen::Isometry3d motion = truth[0].pose.inverse() * truth[1].pose;
  constexpr int kLevels = 3;
  vocal::NormalEquations reference_icp[kLevels], reference_rgb[kLevels];
  for (std::size_t b = 0; b < backends.size(); ++b) {
    vocal::OdometryBackend& backend = *backends[b];
    const int n = b == 0 ? std::min(repeats, 10) : repeats;
    for (const vocal::RgbdFrame& frame : frames) backend.pushFrame(frame, vocal::ReferenceUpdate::kPreviousFrame);  // warm-up
    Clock::time_point start = Clock::now();
    for (int i = 0; i < n; ++i) backend.pushFrame(frames[i % frames.size()], vocal::ReferenceUpdate::kPreviousFrame);
    const double preprocess_ms = millisecondsSince(start) / n;
    backend.pushFrame(frames[0], vocal::ReferenceUpdate::kPreviousFrame);
    backend.pushFrame(frames[1], vocal::ReferenceUpdate::kPreviousFrame);
    double level_ms[kLevels];
    for (int level = 0; level < kLevels; ++level) {
      vocal::NormalEquations icp, rgb;
      backend.trackingSystems(level, motion, 0.02, vocal::BrightnessTransfer(), &icp, &rgb);
      if (b == 0) {
        reference_icp[level] = icp;
        reference_rgb[level] = rgb;
      } else {
        std::printf("  level %d against the reference: ICP %.1e, photometric %.1e (relative); inliers %.0f / %.0f (reference %.0f / %.0f)\n",
                    level, relativeDifference(icp, reference_icp[level]), relativeDifference(rgb, reference_rgb[level]), icp.count,
                    rgb.count, reference_icp[level].count, reference_rgb[level].count);
      }
      start = Clock::now();
      for (int i = 0; i < n; ++i) {
        vocal::NormalEquations timed_icp, timed_rgb;
        backend.trackingSystems(level, motion, 0.02, vocal::BrightnessTransfer(), &timed_icp, &timed_rgb);
      }
      level_ms[level] = millisecondsSince(start) / n;
    }
    const double converging = preprocess_ms + 3 * (level_ms[0] + level_ms[1] + level_ms[2]);
    const double schedule = preprocess_ms + 10 * level_ms[0] + 5 * level_ms[1] + 4 * level_ms[2];
    std::printf("%s, %dx%d: preprocessing %.3f ms; both systems at level 0 %.3f ms, 1 %.3f, 2 %.3f; a frame's dense work "
                "%.2f ms (3 iterations a level) to %.2f ms (10 / 5 / 4)\n",
                backend.name().c_str(), camera.width, camera.height, preprocess_ms, level_ms[0], level_ms[1], level_ms[2],
                converging, schedule);
  }
}
}  // namespace

int main(int argc, char** argv) {
  const int repeats = argc > 1 ? std::atoi(argv[1]) : 200;
  if (repeats < 1) {
    std::fprintf(stderr, "usage: backend_timing [REPEATS >= 1]\n");
    return 2;
  }
  for (const int width : {640, 320}) timeBackends(width, repeats);
  return 0;
}
