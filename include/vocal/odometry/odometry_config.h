#pragma once
// Settings of the ICP + DVO estimator. Defaults are the reference values of the public
// implementations (Whelan et al. 2013, Kintinuous / ElasticFusion) unless docs/benchmarks.md says a
// measurement chose otherwise.

#include <string>
#include <vector>

namespace vocal {

enum class OdometryMode { kIcp, kRgb, kFused };
enum class OdometryBackendKind { kAuto, kCpu, kReference, kOpenCl };
enum class FeatureInitialisation { kAlways, kFallback, kOff };
enum class TrackingReference { kKeyframe, kFrame };
enum class BrightnessModel { kAffine, kFixed };

// The sparsest rows a finest level may be tracked from (OdometryConfig::keep_pace_row_step).
constexpr int kMaxFinestRowStep = 8;

struct OdometryConfig {
  OdometryMode mode = OdometryMode::kFused;

  // Pyramid: level 0 is the input resolution, each further level halves it. Iterations are listed from
  // the finest level to the coarsest (the solver runs coarse to fine).
  int levels = 3;
  std::vector<int> iterations = {10, 5, 4};
  // A level stops early once an update moves less than this (metres, radians). Measured on fr1_xyz
  // (docs/benchmarks.md): 1e-5 -> 3e-4 cut the solve from 19 to 11 ms a frame, RPE 0.0193 -> 0.0191;
  // 1e-3 raised RPE to 0.0203.
  double convergence_translation = 3e-4;
  double convergence_rotation = 3e-4;
  // The finest level stops at this times those thresholds: its steps cost four times a coarser
  // level's (by pixel count). On every real TUM sequence (3 starts each, docs/benchmarks.md) 3 kept
  // RPE (desk 0.0167 -> 0.0165, rpy 0.0227 -> 0.0225, xyz 0.0137 -> 0.0138) and cut the solve by
  // 1.9-3.3 ms a frame; 5 raised the untextured room's RPE by half (0.0069 -> 0.0101).
  double finest_convergence_factor = 3.0;

  // ICP: projective association, then rejection of far or differently oriented pairs.
  double icp_max_distance = 0.10;        // metres
  double icp_max_angle_deg = 20.0;
  double depth_pyramid_sigma = 0.03;     // metres; 5x5 averaging keeps neighbours within 3 sigma
  // Edge-preserving smoothing of the input depth before vertex and normal maps: the average of the
  // neighbours within `radius` pixels whose depth is within factor * z^2 of the centre (0 = off).
  // Removes structured-light noise and disparity steps that otherwise bias point-to-plane ICP.
  int depth_smoothing_radius = 3;
  double depth_smoothing_factor = 0.03;   // 1 / metres
  // The depth's noise along the ray, sqrt(floor^2 + (quadratic * z^2)^2) metres (DepthNoiseModel):
  // each ICP pair is weighted by the inverse variance of its point-to-plane residual, so that far,
  // noisy points count for less. Measured on the real TUM freiburg1 frames (bench/depth_noise.py, all
  // three sequences alike): 1.0 mm * z^2 above a 0.5 mm floor, i.e. quadratic 0.001. Off (0: every
  // pair alike) by default: beside the photometric weight below, it did not lower RPE on the real
  // sequences (docs/benchmarks.md).
  double depth_noise_floor = 0.0005;      // metres
  double depth_noise_quadratic = 0.0;     // 1 / metres

  // DVO: photometric residuals on intensity in [0, 1].
  double rgb_max_depth = 6.0;            // metres
  double rgb_max_depth_difference = 0.07;  // warped depth vs reference depth, metres
  std::vector<double> rgb_min_gradient = {0.012, 0.008, 0.004};  // per level, intensity per pixel
  double rgb_huber_factor = 1.345;       // Huber threshold in units of the residual's standard deviation
  // How the current frame's intensity maps onto the reference's. kAffine: a gain and bias per frame
  // pair, estimated at each pyramid level (BrightnessTransfer: cameras change exposure by themselves);
  // kFixed: intensities compared as they are.
  BrightnessModel brightness_model = BrightnessModel::kAffine;

  // What real cameras depart from the pinhole, global-shutter model by (FrameRectification): the lens
  // distortion given with the camera (camera_info's D) is undone, and a rolling shutter's rows, read
  // one after another over this many seconds, are turned to the middle row's instant along the last
  // measured rotation (0: a global shutter).
  bool undistort_lens = true;
  double rolling_shutter_readout = 0.02;
  // Seconds the depth image is taken after the colour image (negative: before), a property of the
  // camera like its readout: the depth is turned from its instant to the colour's along the last
  // measured motion. The stamps cannot say it: TUM freiburg1's differences between the two (0-11 ms)
  // made tracking worse used so. 0: taken together.
  double depth_time_offset = -0.005;

  // Fusion: A = A_icp / var_icp + rgb_weight * A_rgb / var_rgb (b likewise), each term scaled by the
  // variance of its residuals in that iteration: 1 trusts both by their measured noise. On real Kinect
  // frames the photometric term is worth more than that (why is not measured; likely the ICP term's
  // errors are correlated across the image, which its variance does not show): on every real TUM
  // sequence RPE falls from 3 to 20 (fr1_xyz 0.0168 -> 0.0137, desk 0.0215 -> 0.0173,
  // rpy 0.0392 -> 0.0230); at 30 xyz rises again (0.0146); a simulated untextured room stays within a
  // quarter of ICP alone (docs/benchmarks.md).
  double rgb_weight = 20.0;
  // A gyro's rotation between frames (IcpDvoOdometry::track's `gyro`) enters the system with its
  // information (rates' noise and the bias left unknown) times this; 0 ignores the gyro. The dense terms'
  // information counts every pixel as independent, which they are not: against it the gyro's honest
  // figure is worth about this much more (chosen on every real TUM sequence with a simulated consumer
  // gyro: 300 and 1000 both lower rotational RPE by 30-55 %, 1000 also translation's; docs/benchmarks.md).
  double imu_weight = 1000.0;
  // An accelerometer's gravity (IcpDvoOdometry::track's `accelerometer`) pulls the attitude's roll and
  // pitch toward the first window's level with this time constant (GravityCorrection; seconds; 0: off).
  // On the real TUM sequences with their Kinect's accelerometer (fr1_rpy, fr1_xyz; 5-10 s) 30 s is
  // neutral (within 0.8 % on every figure, with or without a gyro), 10 s costs up to 1.3 % of rotational RPE
  // with a gyro, 2 s up to 27 %: their runs are too short to drift, and that accelerometer reads up to
  // 3-5 deg off the level vision keeps. On a long run whose attitude drifts it holds the tilt (test:
  // 7.1 -> 1.2 deg after 10 s at 1 s). Not applied while a local window refines the keyframes (its poses
  // would undo it).
  double gravity_time_constant = 30.0;

  // Where each frame's dense solve starts. The dense terms converge only within a few centimetres and
  // degrees; ORB features (FeatureAlignment) also find faster motion, at a cost per frame.
  //  kAlways: from the motion the features of the two frames agree on, when enough do.
  //  kFallback: from the last motion (constant velocity); the features are extracted and the solve
  //    repeated from their motion only when that solve fails its checks or its residual is more than
  //    feature_fallback_residual_ratio times the running level (a wrong minimum).
  //  kOff: from no motion.
  // The fallback is the default: on fr1_xyz it asks for features on 16 of 294 frames, and catches the
  // wrong minima (8x the level) that dropped frames cause (docs/benchmarks.md).
  FeatureInitialisation feature_initialisation = FeatureInitialisation::kFallback;
  double feature_fallback_residual_ratio = 2.0;

  // What each frame is tracked against. kKeyframe: a keyframe, kept while the frames still overlap it
  // well (dense VO with keyframes, Kerl et al. 2013): drift grows per keyframe instead of per frame.
  // kFrame: the previous trusted frame.
  TrackingReference tracking_reference = TrackingReference::kKeyframe;
  // A frame becomes the new keyframe when its inliers fall below this share of those the first frame
  // tracked against the keyframe had, or it is farther from the keyframe than these.
  double keyframe_min_overlap = 0.7;
  double keyframe_max_residual_growth = 1.5;  // ... or its residual rose above this times the first's
  double keyframe_max_translation = 0.3;  // metres
  double keyframe_max_rotation_deg = 15.0;
  // ... or its solve against the keyframe used every iteration of the finest level without converging
  // (the keyframe is far enough that the dense solve's basin is stretched).
  bool keyframe_after_unconverged = false;
  int keyframes_kept = 10;               // the most recent keyframes relocalisation tries
  // Local window: each new keyframe is also solved densely against up to local_window_links earlier
  // keyframes (beyond the one it was tracked against), and the poses of the last local_window_keyframes
  // keyframes are refined together by a pose graph of those solves, the oldest held (a local form of
  // Kerl et al. 2013's keyframe graph: odometry, no loop closure). 0: no window. The estimate moves with
  // the refined keyframe; the published pose takes the change in over a few frames (never a jump).
  int local_window_keyframes = 0;
  int local_window_links = 1;
  // The window's links solved on a thread of their own (one CPU thread, or the GPU), off the tracking
  // path: a live stream loses no frame to them; a new keyframe's links are skipped while the last
  // keyframe's are still being solved. False: solved within the frame that made the keyframe (the
  // same trajectory every run).
  bool local_window_background = true;

  // Tracking loss: frames whose solve fails a check are not trusted. The first of them are bridged by
  // a constant-velocity prediction (state predicted); after that the odometry is lost, and each frame
  // is matched by its ORB features against the recent keyframes (relocalisation), refined densely.
  int max_predicted_frames = 5;
  bool relocalisation = true;
  // A wrong minimum, not trusted: a solve whose residual is this many times the running level, or -
  // where there is no running level yet (the first pair, after a reset or a loss) - whose motion is
  // farther than this (or half the motion's length) from the one ORB features agree on.
  double wrong_minimum_residual_ratio = 5.0;
  double wrong_minimum_feature_translation = 0.05;  // metres
  double wrong_minimum_feature_rotation_deg = 5.0;

  // Depth outside this range is treated as missing.
  double min_depth = 0.3;
  double max_depth = 8.0;

  // Result checks.
  double max_translation = 0.3;          // metres per frame; larger increments are rejected
  double max_rotation_deg = 30.0;        // degrees per frame
  int min_icp_inliers = 500;             // at level 0, scaled by 1/4 per level
  int min_rgb_inliers = 500;
  double max_condition = 1e5;            // of the final 6x6 system; a plane alone gives ~1e7

  // kAuto: OpenCL on a GPU when there is one, else the fast CPU backend. kCpu: the fast CPU backend.
  // kReference: the plain CPU reference (parity tests). kOpenCl: any OpenCL device, PoCL's CPU one too.
  OdometryBackendKind backend = OdometryBackendKind::kAuto;
  // A live stream (the nodelet, skip_to_newest) whose frames come faster than they are tracked - a CPU
  // shared with the robot's other work - is tracked without its finest pyramid levels, up to this one,
  // before frames are skipped (ResolutionGovernor), and at full resolution again once there is time:
  // a skipped frame doubles the next one's motion and its solve's cost, where level 1 tracks every frame
  // at a quarter of the pixels (RPE 6-15 % above the input's resolution on the real TUM sequences). With
  // one busy process on 2 vCPUs the nodelet kept 93-98 % of a 30 Hz stream so, 16-82 % skipping alone
  // (docs/benchmarks.md). 0: always the
  // input's resolution (frames skipped instead); above levels - 1, the coarsest level. Offline tools track
  // every frame at level 0.
  int keep_pace_max_level = 1;
  // Before a coarser level, such a stream's finest level is tracked from one row in this many
  // (IcpDvoOdometry::setFinestLevel's row_step; a CPU backend's, a GPU tracks every row): at 2 a frame
  // costs 16-20 % less, the RPE within 1.5 % of every row's on the real TUM sequences, where level 1 is
  // 3-12 % above (docs/benchmarks.md). 1: no such step (straight to the coarser level). At most kMaxFinestRowStep.
  int keep_pace_row_step = 2;
  // A keyframe made while tracking coarser than the input (keeping pace) has the link it was tracked by
  // solved again at the input's resolution (on the local window's thread where local_window_background)
  // and is moved by the difference, with the keyframes after it: drift, which adds up from keyframe to
  // keyframe, keeps the input's accuracy (offline at level 1 on the real TUM sequences: RPE 3-11 % above
  // level 0 instead of 6-15 %; docs/benchmarks.md). With a local window, the window's link is replaced.
  bool keep_pace_refines_keyframes = true;
  // Threads of the fast CPU backend and of the estimator's own loops (the calling thread included); 0 =
  // OMP_NUM_THREADS where set, else the cores this process may run on. Idle threads sleep, so a
  // robot's other processes get the cores back between frames.
  int threads = 0;
  // OpenCL device choice: empty = first GPU, else first CPU device. Matched as substrings of the
  // platform and device names.
  std::string opencl_platform;
  std::string opencl_device;

  // Throws InputError naming the setting when a value is unusable.
  void validate() const;
};

OdometryMode parseOdometryMode(const std::string& name);         // icp, rgb, fused
std::string odometryModeName(OdometryMode mode);
OdometryBackendKind parseOdometryBackend(const std::string& name);  // auto, cpu, reference, opencl
FeatureInitialisation parseFeatureInitialisation(const std::string& name);  // always, fallback, off
TrackingReference parseTrackingReference(const std::string& name);  // keyframe, frame
BrightnessModel parseBrightnessModel(const std::string& name);      // affine, fixed

}  // namespace vocal
