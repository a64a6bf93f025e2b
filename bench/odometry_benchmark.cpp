// Google Benchmark of the odometry per stage and per frame pair, CPU reference vs fast CPU vs OpenCL,
// at 640x480 and 320x240, on synthetic Kinect-like frames (no data needed).
//   devel/lib/vocal/odometry_benchmark [--benchmark_filter=...]

#include <benchmark/benchmark.h>

#include <cmath>
#include <map>
#include <optional>
#include <memory>

#include "vocal/core/errors.h"
#include "vocal/core/lens_distortion.h"
#include "vocal/core/worker_pool.h"
#include "vocal/odometry/brightness_transfer.h"
#include "vocal/odometry/cpu_backend.h"
#include "vocal/odometry/fast_cpu_backend.h"
#include "vocal/odometry/frame_rectification.h"
#include "vocal/odometry/gravity_correction.h"
#include "vocal/odometry/gyro_rotation_prior.h"
#include "vocal/odometry/icp_dvo_odometry.h"
#include "vocal/simulation/simulated_imu.h"
#include "vocal/simulation/synthetic_sequence.h"
#ifdef VOCAL_HAVE_OPENCL
#include "vocal/odometry/opencl_backend.h"
#endif

namespace {
enum Backend { kReference = 0, kOpenCl = 1, kFastCpu = 2 };

struct Frames {
  vocal::PinholeCamera camera;
  std::vector<vocal::RgbdFrame> frames;
  vocal::Trajectory truth;
};

const Frames& frames(int width) {
  static std::map<int, Frames> cache;
  auto it = cache.find(width);
  if (it != cache.end()) return it->second;
  Frames f;
  f.camera = vocal::defaultKinectCamera(width, width * 3 / 4);
  const vocal::SyntheticScene scene = vocal::SyntheticScene::make(vocal::SceneVariant::kIndoorRoom);
  vocal::SyntheticTrajectoryOptions options;
  options.frames = 8;
  f.truth = vocal::generateSyntheticTrajectory(scene.workspace(), options);
  for (int i = 0; i < options.frames; ++i) {
    f.frames.push_back(vocal::renderSyntheticFrame(scene, f.camera, f.truth[i], vocal::kinectLikeSensorModel(), i));
  }
  return cache.emplace(width, std::move(f)).first->second;
}

std::unique_ptr<vocal::OdometryBackend> makeBackend(Backend backend, const vocal::PinholeCamera& camera,
                                                    const vocal::OdometryConfig& config) {
  if (backend == kReference) return std::make_unique<vocal::CpuOdometryBackend>(camera, config);
  if (backend == kFastCpu) return std::make_unique<vocal::FastCpuOdometryBackend>(camera, config);
#ifdef VOCAL_HAVE_OPENCL
  return std::make_unique<vocal::OpenClOdometryBackend>(camera, config);
#else
  throw vocal::InputError("OpenCL backend not built");
#endif
}

bool skipUnavailable(benchmark::State& state, Backend backend, const vocal::PinholeCamera& camera,
                     const vocal::OdometryConfig& config, std::unique_ptr<vocal::OdometryBackend>* out) {
  try {
    *out = makeBackend(backend, camera, config);
    state.SetLabel((*out)->name());
    return false;
  } catch (const vocal::InputError& e) {
    state.SkipWithError(e.what());
    return true;
  }
}

void BM_Preprocess(benchmark::State& state) {
  const Frames& f = frames(static_cast<int>(state.range(1)));
  std::unique_ptr<vocal::OdometryBackend> backend;
  if (skipUnavailable(state, static_cast<Backend>(state.range(0)), f.camera, {}, &backend)) return;
  std::size_t i = 0;
  for (auto _ : state) backend->pushFrame(f.frames[i++ % f.frames.size()], vocal::ReferenceUpdate::kPreviousFrame);
  state.counters["memory_MB"] = backend->memoryBytes() / 1048576.0;
}

enum Terms { kIcpTerm, kRgbTerm, kBothTerms };

void systemBenchmark(benchmark::State& state, Terms terms) {
  const Frames& f = frames(static_cast<int>(state.range(1)));
  const int level = static_cast<int>(state.range(2));
  std::unique_ptr<vocal::OdometryBackend> backend;
  if (skipUnavailable(state, static_cast<Backend>(state.range(0)), f.camera, {}, &backend)) return;
  backend->pushFrame(f.frames[0], vocal::ReferenceUpdate::kPreviousFrame);
  backend->pushFrame(f.frames[1], vocal::ReferenceUpdate::kPreviousFrame);
  const Eigen::Isometry3d T = f.truth[0].pose.inverse() * f.truth[1].pose;
  for (auto _ : state) {
    vocal::NormalEquations icp, rgb;
    backend->trackingSystems(level, T, 0.02, vocal::BrightnessTransfer(), terms != kRgbTerm ? &icp : nullptr, terms != kIcpTerm ? &rgb : nullptr);
    benchmark::DoNotOptimize(icp);
    benchmark::DoNotOptimize(rgb);
  }
}
void BM_IcpSystem(benchmark::State& state) { systemBenchmark(state, kIcpTerm); }
void BM_RgbSystem(benchmark::State& state) { systemBenchmark(state, kRgbTerm); }
// Both systems of one iteration, as the fused estimator asks for them (one pass on the fast backend).
void BM_BothSystems(benchmark::State& state) { systemBenchmark(state, kBothTerms); }

// Feature initialisation of one frame: ORB extraction (arg 1) or extraction plus matching and PnP
// RANSAC against the previous frame (arg 2), with detection on an image at most `max_width` wide.
void BM_Features(benchmark::State& state) {
  const Frames& f = frames(static_cast<int>(state.range(0)));
  vocal::FeatureAlignmentOptions options;
  options.max_detection_width = static_cast<int>(state.range(2));
  const auto reference = vocal::extractFrameFeatures(f.frames[0], f.camera, options);
  int found = 0;
  for (auto _ : state) {
    const auto current = vocal::extractFrameFeatures(f.frames[1], f.camera, options);
    if (state.range(1) == 2) found += vocal::alignFrameFeatures(*reference, *current, f.camera, options).found;
  }
  state.counters["found_share"] = state.range(1) == 2 ? static_cast<double>(found) / state.iterations() : 0.0;
}

// Rectifying one frame as the estimator does before tracking: freiburg1's lens undone, and with arg 1
// as the defaults do it, a 20 ms rolling shutter's rows turned and shifted by a hand-held motion and
// the depth (taken 5 ms before the colour) on its own grid; arg 0: the lens alone. On every core, as the
// estimator runs it.
void BM_Rectify(benchmark::State& state) {
  const Frames& f = frames(static_cast<int>(state.range(0)));
  const vocal::LensDistortion lens =
      vocal::LensDistortion::fromCameraInfo("plumb_bob", {0.2624, -0.9531, -0.0054, 0.0026, 1.1633}, "freiburg1");
  const vocal::OdometryConfig defaults;
  const vocal::FrameRectification rectification(f.camera, lens, state.range(1) ? defaults.rolling_shutter_readout : 0.0,
                                                state.range(1) ? defaults.depth_time_offset : 0.0);
  const Eigen::Vector3d turning(0.2, 0.5, 0.1), moving(0.3, 0.1, -0.2);
  vocal::WorkerPool workers;
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(rectification.rectify(f.frames[i++ % f.frames.size()], turning, moving, &workers));
}

// The exposure change between two frames (one estimate; the estimator makes one per pyramid level), on
// every core.
void BM_BrightnessTransfer(benchmark::State& state) {
  const Frames& f = frames(static_cast<int>(state.range(0)));
  const Eigen::Isometry3d T = f.truth[0].pose.inverse() * f.truth[1].pose;
  vocal::WorkerPool workers;
  for (auto _ : state)
    benchmark::DoNotOptimize(vocal::estimateBrightnessTransfer(f.frames[0], f.frames[1], f.camera, T, 0.07, &workers));
}

// Preprocessing of the new frame plus the full coarse-to-fine solve: the cost of one frame of odometry.
// camera 1: the defaults (a 20 ms rolling shutter's rows rectified, the affine brightness model; the
// rendered frames have no lens to undo, and rectifying costs the same with one); 0: the frames taken
// as a global-shutter pinhole's with fixed exposure. The rendered frames have a global shutter, so
// camera 1 may iterate differently from a real Kinect: the real sequences' fps are tum_odometry's.
void BM_FramePair(benchmark::State& state) {
  const Frames& f = frames(static_cast<int>(state.range(1)));
  vocal::OdometryConfig config;
  config.mode = static_cast<vocal::OdometryMode>(state.range(2));
  config.feature_initialisation = static_cast<vocal::FeatureInitialisation>(state.range(3));
  if (!state.range(4)) {
    config.rolling_shutter_readout = 0.0;
    config.brightness_model = vocal::BrightnessModel::kFixed;
  }
  std::unique_ptr<vocal::OdometryBackend> backend;
  if (skipUnavailable(state, static_cast<Backend>(state.range(0)), f.camera, config, &backend)) return;
  vocal::IcpDvoOdometry odometry(f.camera, config, std::move(backend));
  std::size_t i = 0;
  for (auto _ : state) odometry.track(f.frames[i++ % f.frames.size()]);
  state.counters["frames_per_second"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void stageArguments(benchmark::internal::Benchmark* b) {
  b->ArgNames({"backend", "width"});
  for (int backend : {kReference, kFastCpu, kOpenCl})
    for (int width : {640, 320}) b->Args({backend, width});
  b->Unit(benchmark::kMillisecond)->UseRealTime();
}
void levelArguments(benchmark::internal::Benchmark* b) {
  b->ArgNames({"backend", "width", "level"});
  for (int backend : {kReference, kFastCpu, kOpenCl})
    for (int width : {640, 320}) b->Args({backend, width, 0});
  b->Unit(benchmark::kMillisecond)->UseRealTime();
}
// features: the FeatureInitialisation (0 always, 1 fallback, 2 off); camera: see BM_FramePair.
void pairArguments(benchmark::internal::Benchmark* b) {
  b->ArgNames({"backend", "width", "mode", "features", "camera"});
  const int fused = static_cast<int>(vocal::OdometryMode::kFused);
  const int always = static_cast<int>(vocal::FeatureInitialisation::kAlways);
  for (int backend : {kReference, kFastCpu, kOpenCl})
    for (int width : {640, 320}) b->Args({backend, width, fused, always, 1});
  for (vocal::FeatureInitialisation features : {vocal::FeatureInitialisation::kFallback, vocal::FeatureInitialisation::kOff})
    for (int width : {640, 320})
      for (int camera : {1, 0}) b->Args({kFastCpu, width, fused, static_cast<int>(features), camera});
  b->Args({kFastCpu, 640, static_cast<int>(vocal::OdometryMode::kIcp), always, 1});
  b->Args({kFastCpu, 640, static_cast<int>(vocal::OdometryMode::kRgb), always, 1});
  b->Unit(benchmark::kMillisecond)->UseRealTime();
}
// The IMU's own cost per frame: a 200 Hz gyro's rotation between two 30 Hz frames (preintegration, the
// camera frame) and the bias update of a keyframe (three more preintegrations over its span), the
// samples of a whole 10 s run held.
void BM_GyroPriorPerFrame(benchmark::State& state) {
  vocal::Trajectory path;
  for (int i = 0; i < 301; ++i) {
    vocal::StampedPose p;
    p.stamp = i / 30.0;
    p.pose.linear() = vocal::rotationFromRollPitchYaw(0.3 * std::sin(1.1 * p.stamp), 0.2 * std::sin(0.7 * p.stamp), 0.5 * std::sin(0.4 * p.stamp));
    path.push_back(p);
  }
  vocal::SimulatedImuOptions options;
  options.extrinsics = vocal::simulatedImuExtrinsics();
  vocal::GyroRotationPrior prior(options.extrinsics);
  prior.add(vocal::simulateImu(path, options));
  int k = 1;
  for (auto _ : state) {
    const std::optional<vocal::RotationPrior> between = prior.between(path[k - 1].stamp, path[k].stamp);
    benchmark::DoNotOptimize(between);
    const int keyframe = k - k % 6;  // a keyframe every 6 frames: one bias update per 6 frames
    prior.observe(path[keyframe].stamp, path[k].stamp, path[keyframe].pose.linear().transpose() * path[k].pose.linear());
    k = k % 299 + 1;
  }
}

// The accelerometer's cost per frame: the gravity correction over its half-second window of 200 Hz
// samples (each turned by the pose interpolated at its stamp), 2 s of samples handed in, as the nodelet
// does.
void BM_GravityCorrectionPerFrame(benchmark::State& state) {
  std::vector<vocal::AccelerometerSample> samples;
  for (int i = 0; i <= 200 * 12; ++i) {
    const double t = i / 200.0;
    samples.push_back({t, Eigen::Vector3d(0.3 * std::sin(t), 0.2, vocal::kStandardGravity)});
  }
  vocal::GravityCorrection gravity(30.0);
  int frame = 0;
  for (auto _ : state) {
    const double t = 0.5 + (frame % 300) / 30.0;
    if (frame % 300 == 0) gravity.reset();
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation() = Eigen::Vector3d(0.1 * t, 0.0, 1.0);
    pose.linear() = vocal::rotationFromRollPitchYaw(0.0, 0.0, 0.2 * t);
    const auto first = std::lower_bound(samples.begin(), samples.end(), t - 2.0,
                                        [](const vocal::AccelerometerSample& s, double stamp) { return s.stamp < stamp; });
    const std::vector<vocal::AccelerometerSample> recent(first, std::upper_bound(first, samples.end(), t,
                                                                                 [](double stamp, const vocal::AccelerometerSample& s) { return stamp < s.stamp; }));
    benchmark::DoNotOptimize(gravity.correct(t, pose, recent, 1.0 / 30.0));
    ++frame;
  }
}
}  // namespace

BENCHMARK(BM_GyroPriorPerFrame)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_GravityCorrectionPerFrame)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Preprocess)->Apply(stageArguments);
BENCHMARK(BM_IcpSystem)->Apply(levelArguments);
BENCHMARK(BM_RgbSystem)->Apply(levelArguments);
BENCHMARK(BM_BothSystems)->Apply(levelArguments);
BENCHMARK(BM_Features)
    ->ArgNames({"width", "stage", "max_width"})
    ->ArgsProduct({{640}, {1, 2}, {640, 320}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_Rectify)->ArgNames({"width", "rolling"})->ArgsProduct({{640, 320}, {0, 1}})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_BrightnessTransfer)->ArgNames({"width"})->Arg(640)->Arg(320)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_FramePair)->Apply(pairArguments);
BENCHMARK_MAIN();
