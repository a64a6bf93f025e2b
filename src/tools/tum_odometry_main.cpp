// tum_odometry TUM_FOLDER --output TRAJ.txt [options]: runs the ICP + DVO estimator over a TUM-layout
// folder, writes the trajectory, prints frames per second and, with ground truth, ATE / RPE.

#include <chrono>
#include <cstdio>
#include <cmath>
#include <fstream>
#include <memory>
#include <optional>
#include <string>

#include "vocal/core/errors.h"
#include "vocal/core/gravity.h"
#include "vocal/core/imu_samples.h"
#include "vocal/core/stamp_association.h"
#include "vocal/core/trajectory_evaluation.h"
#include "vocal/core/tum_sequence.h"
#include "vocal/odometry/gyro_rotation_prior.h"
#include "vocal/odometry/icp_dvo_odometry.h"
#include "vocal/odometry/odometry_config_yaml.h"
#include "vocal/tools/command_line.h"
#include "vocal/tools/trajectory_report.h"

namespace {
const char kUsage[] =
    "usage: tum_odometry TUM_FOLDER --output TRAJ.txt [options]\n"
    "  --config FILE.yaml          odometry settings (keys: see config/odometry.yaml)\n"
    "  --mode icp|rgb|fused        overrides the config's mode\n"
    "  --backend auto|cpu|reference|opencl  overrides the config's backend\n"
    "  --threads N                 CPU threads (overrides the config's; 0 = OMP_NUM_THREADS, else the cores)\n"
    "  --rgb-weight W              overrides the fusion weight of the photometric term\n"
    "  --features always|fallback|off  overrides the config's feature_initialisation\n"
    "  --reference keyframe|frame  overrides the config's tracking_reference\n"
    "  --brightness affine|fixed   overrides the config's brightness_model\n"
    "  --frames N                  only the first N associated frames (after --skip)\n"
    "  --skip N                    start at the N-th associated frame (0 = the first)\n"
    "  --every N                   track every N-th of those frames only, as a live node does that keeps one\n"
    "                              frame in N on a busy CPU (default 1: every frame)\n"
    "  --finest-level L            track at pyramid level L and the coarser ones only, as a live node does\n"
    "                              whose frames come faster than it tracks them (default 0: the input's size)\n"
    "  --finest-row-step N         that level's systems from one row in N, as a live node does before a coarser\n"
    "                              level (keep_pace_row_step; a CPU backend's; default 1: every row)\n"
    "  --start-from-ground-truth   first pose = ground truth at the first frame (default: identity)\n"
    "  --imu FILE                  an IMU's imu.txt (`timestamp wx wy wz ax ay az`; default: the folder's imu.txt\n"
    "                              when there is one): its gyro's rotation between frames as a prior\n"
    "  --imu-extrinsics FILE       its imu_extrinsics.yaml (default: the folder's; required with an IMU)\n"
    "  --imu-weight W              overrides the config's imu_weight (0: ignore the gyro)\n"
    "  --no-imu                    ignore the folder's imu.txt\n"
    "  --gravity-time-constant S   overrides the config's: roll and pitch held to the accelerometer's gravity\n"
    "                              (the folder's accelerometer.txt, a Kinect's; else imu.txt's) with this time\n"
    "                              constant (0: off)\n"
    "  --no-accelerometer          ignore the folder's accelerometer.txt and imu.txt's accelerations\n"
    "  --delta S                   RPE interval (default 1 s)\n"
    "  --quiet                     no progress line\n"
    "  --verbose                   one line of quality figures per frame\n";

bool fileExists(const std::string& path) { return std::ifstream(path).good(); }

// The IMU the flags or the folder give, and a line saying what it is; none without one.
std::unique_ptr<vocal::GyroRotationPrior> openImu(const vocal::CommandLine& args, const std::string& folder, std::string* line) {
  if (args.has("no-imu")) return nullptr;
  const std::string imu_path = args.text("imu", fileExists(folder + "/imu.txt") ? folder + "/imu.txt" : "");
  if (imu_path.empty()) return nullptr;
  const std::string extrinsics_path =
      args.text("imu-extrinsics", fileExists(folder + "/imu_extrinsics.yaml") ? folder + "/imu_extrinsics.yaml" : "");
  if (extrinsics_path.empty()) {
    throw vocal::InputError(imu_path + ": the IMU's pose in the camera is needed: --imu-extrinsics FILE (imu_extrinsics.yaml, README)");
  }
  const std::vector<vocal::ImuSample> samples = vocal::readImuFile(imu_path);
  if (samples.size() < 2) throw vocal::InputError(imu_path + ": fewer than 2 IMU samples");
  auto imu = std::make_unique<vocal::GyroRotationPrior>(vocal::readImuExtrinsics(extrinsics_path));
  imu->add(samples);
  char text[1024];
  std::snprintf(text, sizeof(text), "imu: %zu samples from %s at %.0f Hz, camera in the IMU frame from %s (time offset %.4f s): the gyro's rotation as a prior, its bias estimated online",
                samples.size(), imu_path.c_str(), vocal::imuRate(samples), extrinsics_path.c_str(), imu->extrinsics().time_offset);
  *line = text;
  return imu;
}

// The accelerometer in the camera frame: the folder's accelerometer.txt (a Kinect's, its axes mapped), else
// the IMU's accelerations (through its extrinsics); a line says which. Empty without either.
std::vector<vocal::AccelerometerSample> openAccelerometer(const vocal::CommandLine& args, const vocal::TumSequence& sequence,
                                                          const vocal::GyroRotationPrior* imu, std::string* line) {
  std::vector<vocal::AccelerometerSample> samples;
  if (args.has("no-accelerometer")) {
    *line = "no accelerometer (--no-accelerometer)";
    return samples;
  }
  if (!sequence.accelerometer().empty()) {
    for (vocal::AccelerometerSample s : sequence.accelerometer()) {
      s.specific_force = vocal::opticalFromKinectAccelerometer() * s.specific_force;
      samples.push_back(s);
    }
    *line = "accelerometer: " + std::to_string(samples.size()) + " samples from " + sequence.folder() + "/accelerometer.txt (a Kinect's axes)";
  } else if (imu) {
    const Eigen::Matrix3d camera_from_imu = imu->extrinsics().camera_in_imu.linear().transpose();
    for (const vocal::ImuSample& s : imu->samples())  // the IMU's, already read
      samples.push_back({s.stamp - imu->extrinsics().time_offset, camera_from_imu * s.linear_acceleration});
    *line = "accelerometer: " + std::to_string(samples.size()) + " samples from the IMU's accelerations";
  } else {
    *line = "no accelerometer (no accelerometer.txt in the folder, no IMU)";
  }
  return samples;
}

int run(const vocal::CommandLine& args) {
  if (!args.has("output")) throw vocal::InputError("--output TRAJ.txt is required");
  vocal::OdometryConfig config;
  if (args.has("config")) config = vocal::readOdometryConfigYaml(args.text("config", ""));
  if (args.has("mode")) config.mode = vocal::parseOdometryMode(args.text("mode", ""));
  if (args.has("backend")) config.backend = vocal::parseOdometryBackend(args.text("backend", ""));
  config.threads = args.integer("threads", config.threads);
  config.rgb_weight = args.number("rgb-weight", config.rgb_weight);
  if (args.has("features")) config.feature_initialisation = vocal::parseFeatureInitialisation(args.text("features", ""));
  if (args.has("reference")) config.tracking_reference = vocal::parseTrackingReference(args.text("reference", ""));
  if (args.has("brightness")) config.brightness_model = vocal::parseBrightnessModel(args.text("brightness", ""));
  config.imu_weight = args.number("imu-weight", config.imu_weight);
  config.gravity_time_constant = args.number("gravity-time-constant", config.gravity_time_constant);

  const vocal::TumSequence sequence = vocal::TumSequence::open(args.positional()[0]);
  std::string imu_line;
  const std::unique_ptr<vocal::GyroRotationPrior> imu = openImu(args, args.positional()[0], &imu_line);
  const int skip_arg = args.integer("skip", 0);
  if (skip_arg < 0 || static_cast<std::size_t>(skip_arg) >= sequence.size()) {
    throw vocal::InputError("--skip " + std::to_string(skip_arg) + ": the sequence has " + std::to_string(sequence.size()) +
                            " associated frames");
  }
  const std::size_t skip = static_cast<std::size_t>(skip_arg);
  const std::size_t span =
      std::min<std::size_t>(sequence.size() - skip, args.integer("frames", static_cast<int>(sequence.size() - skip)));
  const int every = args.integer("every", 1);
  if (every < 1) throw vocal::InputError("--every " + std::to_string(every) + ": must be 1 or more");
  const std::size_t frames = (span + every - 1) / every;
  std::string notice;
  auto backend = vocal::makeOdometryBackend(sequence.camera(), config, &notice);
  if (!notice.empty()) std::fprintf(stderr, "%s\n", notice.c_str());
  vocal::IcpDvoOdometry odometry(sequence.camera(), config, std::move(backend), sequence.lens());
  odometry.setFinestLevel(args.integer("finest-level", 0), args.integer("finest-row-step", 1));
  if (odometry.finestRowStep() != args.integer("finest-row-step", 1)) {
    std::fprintf(stderr, "--finest-row-step %d: backend %s tracks every row\n", args.integer("finest-row-step", 1),
                 odometry.backend().name().c_str());
  }
  std::fprintf(stderr, "%zu frames, intrinsics from %s, mode %s, backend %s; %s\n", frames, sequence.cameraSource().c_str(),
               vocal::odometryModeName(config.mode).c_str(), odometry.backend().name().c_str(),
               odometry.cameraModelText().c_str());
  std::fprintf(stderr, "%s\n", imu ? imu_line.c_str() : "no IMU (no imu.txt in the folder, no --imu)");
  std::string accelerometer_line;
  const std::vector<vocal::AccelerometerSample> accelerometer =
      openAccelerometer(args, sequence, imu.get(), &accelerometer_line);
  if (!accelerometer.empty()) {
    char tail[160];
    std::snprintf(tail, sizeof(tail), config.gravity_time_constant > 0.0 ? ": roll and pitch held to its gravity (time constant %.1f s)"
                                                                          : ": not used (gravity_time_constant 0)",
                  config.gravity_time_constant);
    accelerometer_line += tail;
  }
  std::fprintf(stderr, "%s\n", accelerometer_line.c_str());

  if (args.has("start-from-ground-truth")) {
    if (!sequence.hasGroundTruth()) throw vocal::InputError(sequence.folder() + ": --start-from-ground-truth needs groundtruth.txt");
    const auto stamps = vocal::trajectoryStamps(sequence.groundTruth());
    odometry.reset(sequence.groundTruth()[vocal::closestStampIndex(stamps, sequence.entry(skip).rgb.stamp)].pose);
  }

  vocal::Trajectory trajectory;
  double tracking_seconds = 0.0;
  vocal::OdometryTimings stage_sums;
  int failures = 0, feature_fallbacks = 0, keyframes = 0, relocalisations = 0, window_links = 0, window_refined = 0;
  int imu_priors = 0, imu_gaps = 0, degraded = 0, gravity_frames = 0;
  double worst_gravity_error = 0.0;
  std::string last_degraded;
  std::string imu_gap;
  const bool quiet = args.has("quiet");
  for (std::size_t i = 0; i < frames; ++i) {
    const vocal::RgbdFrame frame = sequence.loadFrame(skip + i * every);
    const auto start = std::chrono::steady_clock::now();
    std::optional<vocal::RotationPrior> gyro;
    if (imu && i > 0) {
      gyro = imu->between(trajectory.back().stamp, frame.stamp, &imu_gap);
      ++(gyro ? imu_priors : imu_gaps);
    }
    const bool gravity = !accelerometer.empty() && config.gravity_time_constant > 0.0;
    const vocal::OdometryResult result = odometry.track(frame, gyro ? &*gyro : nullptr, gravity ? &accelerometer : nullptr);
    if (result.gravity_error_deg >= 0.0) {
      ++gravity_frames;
      worst_gravity_error = std::max(worst_gravity_error, result.gravity_error_deg);
    }
    if (imu) {
      if (result.state == vocal::TrackingState::kTracking && result.quality.trusted) {
        imu->observe(result.keyframe_stamp, frame.stamp, result.vision_rotation);
      } else {
        imu->breakWindow();
      }
    }
    tracking_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    trajectory.push_back({frame.stamp, result.pose});
    stage_sums.preprocess_ms += result.timings.preprocess_ms;
    stage_sums.features_ms += result.timings.features_ms;
    stage_sums.solve_ms += result.timings.solve_ms;
    stage_sums.window_ms += result.timings.window_ms;
    window_links += result.window_links;
    window_refined += result.window_correction_m > 0.0;
    feature_fallbacks += result.quality.feature_fallback;
    keyframes += result.new_keyframe;
    relocalisations += result.state == vocal::TrackingState::kRelocalised;
    if (result.state == vocal::TrackingState::kDegraded) {
      ++degraded;
      last_degraded = result.degraded;
    }
    failures += !result.quality.trusted;
    if (!result.window_error.empty()) std::fprintf(stderr, "\nframe %zu: %s\n", i, result.window_error.c_str());
    const std::string event = vocal::trackingEvent(result);
    if (!event.empty()) std::fprintf(stderr, "\nframe %zu (%.6f): %s\n", i, frame.stamp, event.c_str());
    if (args.has("verbose")) {
      const vocal::OdometryQuality& q = result.quality;
      std::fprintf(stderr, "frame %zu: icp %d inliers rmse %.4f m, rgb %d inliers rmse %.4f, %d steps, condition %.3g, "
                   "weakest information %.3g%s, keyframe %d%s%s, features off by %.3f m %.2f deg, brightness x%.3f %+.3f%s%s\n", i, q.icp_inliers, q.icp_rmse, q.rgb_inliers, q.rgb_rmse,
                   q.iterations, q.condition, q.weakest_information, q.converged ? "" : ", not converged", result.keyframe_id,
                   result.new_keyframe ? " (new)" : "", q.feature_fallback ? ", feature fallback" : "", q.feature_disagreement_m,
                   q.feature_disagreement_deg, q.brightness_gain, q.brightness_bias, result.degraded.empty() ? "" : "; degraded: ",
                   result.degraded.c_str());
    } else if (!quiet) {
      std::fprintf(stderr, "\rframe %zu/%zu", i + 1, frames);
    }
  }
  if (!quiet) std::fprintf(stderr, "\n");
  vocal::writeTumTrajectory(args.text("output", ""), trajectory);
  std::printf("frames: %zu\ntracking_failures: %d\nframes_per_second: %.2f\nbackend_memory_mb: %.1f\n", frames, failures,
              frames / std::max(tracking_seconds, 1e-9), odometry.backend().memoryBytes() / 1048576.0);
  const double n = std::max<double>(frames, 1);
  std::printf("preprocess_ms: %.2f\nfeatures_ms: %.2f\nsolve_ms: %.2f\n", stage_sums.preprocess_ms / n,
              stage_sums.features_ms / n, stage_sums.solve_ms / n);
  // Loops the caller ran alone because the OS kept the pool's other threads off their cores.
  const vocal::WorkerPool& workers = odometry.workers();
  std::printf("threads: %d\nloops_alone_percent: %.1f\n", workers.threads(),
              workers.loops() ? 100.0 * workers.loopsAlone() / workers.loops() : 0.0);
  if (config.feature_initialisation == vocal::FeatureInitialisation::kFallback)
    std::printf("feature_fallbacks: %d\n", feature_fallbacks);
  std::printf("keyframes: %d\nrelocalisations: %d\n", keyframes, relocalisations);
  if (imu) {
    const Eigen::Vector3d bias = imu->bias() * 180.0 / M_PI, sigma = imu->biasSigma() * 180.0 / M_PI;
    std::printf("imu_priors: %d\nimu_gaps: %d\ndegraded_frames: %d\ngyro_bias_deg_per_s: %.3f %.3f %.3f (+- %.3f, %d updates)\n", imu_priors, imu_gaps,
                degraded, bias.x(), bias.y(), bias.z(), sigma.maxCoeff(), imu->biasUpdates());
    if (degraded > 0) std::fprintf(stderr, "imu: %d frames degraded (vision held only some directions); the last: %s\n", degraded, last_degraded.c_str());
    if (imu_gaps > 0) std::fprintf(stderr, "imu: %d frames tracked without the gyro; the last because %s\n", imu_gaps, imu_gap.c_str());
  }
  if (!accelerometer.empty() && config.gravity_time_constant > 0.0) {
    std::printf("gravity_frames: %d\nworst_gravity_error_deg: %.2f\n", gravity_frames, worst_gravity_error);
  }
  if (config.local_window_keyframes > 0) {
    std::printf("window_ms: %.2f\nwindow_links: %d\nwindow_refined_keyframes: %d\n", stage_sums.window_ms / n, window_links,
                window_refined);
  }
  if (sequence.hasGroundTruth()) {
    const double delta = args.number("delta", 1.0);
    vocal::printTrajectoryMetrics(stdout, vocal::computeAte(sequence.groundTruth(), trajectory),
                                  vocal::computeRpe(sequence.groundTruth(), trajectory, delta));
  }
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  return vocal::runTool("tum_odometry", kUsage, run, argc, argv,
                        {"output", "config", "mode", "backend", "threads", "rgb-weight", "features", "reference", "brightness", "frames", "skip", "every", "finest-level", "finest-row-step", "delta",
                         "imu", "imu-extrinsics", "imu-weight", "gravity-time-constant"},
                        {"start-from-ground-truth", "quiet", "verbose", "no-imu", "no-accelerometer"}, 1);
}
