#pragma once
// RGB-D odometry: point-to-plane ICP and dense photometric odometry (DVO) fused in one weighted 6x6
// system per iteration, solved coarse to fine (Whelan et al. 2013), each frame against a keyframe (or
// the previous frame). A loss is bridged by a constant-velocity prediction, then reported, and ended
// by relocalising against a recent keyframe.

#include <deque>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "vocal/core/lens_distortion.h"
#include "vocal/core/pinhole_camera.h"
#include "vocal/core/rgbd_frame.h"
#include "vocal/core/se3.h"
#include "vocal/core/worker_pool.h"
#include "vocal/odometry/feature_alignment.h"
#include "vocal/odometry/frame_rectification.h"
#include "vocal/odometry/gravity_correction.h"
#include "vocal/odometry/gyro_rotation_prior.h"
#include "vocal/odometry/keyframe_window.h"
#include "vocal/odometry/odometry_backend.h"
#include "vocal/odometry/odometry_config.h"

namespace vocal {

enum class TrackingState {
  kTracking,     // tracked against the keyframe (or the previous frame)
  // Tracked with a gyro where vision does not constrain every direction (one plane, a blank wall,
  // darkness): the rotation held by the gyro, the translation vision leaves free guessed by the motion
  // model; the covariance says which directions (OdometryResult::degraded names them).
  kDegraded,
  kRelocalised,  // tracked again after a loss, against a recent keyframe
  kPredicted,    // not tracked; the pose is the constant-velocity prediction (a short gap)
  kLost,         // not tracked for longer than the prediction bridges; the pose stays
};
std::string trackingStateName(TrackingState state);  // tracking, degraded, relocalised, predicted, lost

struct OdometryQuality {
  int finest_level = 0;       // the finest pyramid level tracked (0: the input's resolution; setFinestLevel)
  int finest_row_step = 1;    // one row in this many of it entered the systems (setFinestLevel)
  int icp_inliers = 0;        // at the finest level tracked, last iteration
  int rgb_inliers = 0;
  double icp_rmse = 0.0;      // metres, each pair weighted by its depth noise (as a pair at 1 m)
  double rgb_rmse = 0.0;      // intensity units
  int iterations = 0;         // solver steps over all levels
  bool converged = false;     // the finest level's last update fell below the convergence thresholds
  double condition = 0.0;     // of the final system (largest / smallest eigenvalue)
  double weakest_information = 0.0;  // smallest eigenvalue of the final system per inlier
  bool trusted = false;       // the increment passed every check and was applied
  int feature_inliers = 0;    // features agreeing on the starting motion (0: started from none)
  bool feature_fallback = false;  // fallback mode: the first solve was suspicious, features were asked
  // Between the dense motion and the one the features agree on, when they were asked (else -1).
  double feature_disagreement_m = -1.0;
  double feature_disagreement_deg = -1.0;
  // The current frame's intensity as the reference saw it at the finest level (brightness model
  // affine; 1 and 0 when fixed or not estimable).
  double brightness_gain = 1.0;
  double brightness_bias = 0.0;
};

// Wall-clock milliseconds of one track() call per stage.
struct OdometryTimings {
  double preprocess_ms = 0.0;  // pyramids, maps, gradients (the backend's pushFrame)
  double features_ms = 0.0;    // ORB extraction, matching and PnP (feature initialisation)
  double solve_ms = 0.0;       // the coarse-to-fine dense solve(s) and the result checks
  double window_ms = 0.0;      // the local window on this thread: its pose graph, and its links' solves
                               // unless they run in the background
};

struct OdometryResult {
  bool first_frame = false;  // the first frame (or the first after a reset) only sets the reference
  Eigen::Isometry3d increment = Eigen::Isometry3d::Identity();  // previous camera <- current camera
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();       // odometry frame <- current camera
  // Of the twist [v; w] of the motion from the reference (the keyframe) to this frame, a left
  // perturbation in the keyframe camera frame.
  Matrix6d covariance = Matrix6d::Identity();
  // Of the pose's twist in the odometry frame (left perturbation): the keyframe's plus that of the
  // motion from it (frame to frame: grows with every increment); grown by each prediction; 1e6 on the
  // diagonal while lost; zero after a reset (the start pose is given).
  Matrix6d pose_covariance = Matrix6d::Zero();
  OdometryQuality quality;
  OdometryTimings timings;
  std::string failure;  // why tracking was not trusted; empty when it was
  TrackingState state = TrackingState::kTracking;
  int keyframe_id = 0;       // the keyframe this frame was tracked against (ids count from 0 per reset)
  bool new_keyframe = false; // this frame became the keyframe the next ones are tracked against
  // Local window: the dense links between keyframes (besides the tracked ones) added to it in this
  // call, and how far the window's refinement then moved the estimate (0 when it did not run). In the
  // background a new keyframe's links arrive some frames later, or are skipped when the last
  // keyframe's were still being solved.
  int window_links = 0;
  double window_correction_m = 0.0;
  double window_correction_deg = 0.0;
  bool window_links_skipped = false;
  std::string window_error;  // why the window stopped (its background solve failed); empty while it works
  int lost_frames = 0;       // consecutive frames not tracked, this one included (relocalised: before it)
  // Tracked: the keyframe's stamp and the rotation keyframe <- current as vision alone measured it (a
  // gyro prior's pull taken out), what the gyro's bias is estimated from (GyroRotationPrior::observe).
  double keyframe_stamp = 0.0;
  Eigen::Matrix3d vision_rotation = Eigen::Matrix3d::Identity();
  // With an accelerometer's up: how far roll / pitch were from the reference level before this frame's
  // correction (degrees; -1: no correction, e.g. the body accelerating, or none asked).
  double gravity_error_deg = -1.0;
  // Degraded: what vision did not give, e.g. "vision constrains 1 of 3 translation directions, the motion
  // model guesses 2 (0.00 0.00 1.00 ...); photometric term left out: too few inliers (12 < 500)"; empty
  // otherwise. The translation directions guessed, unit, in the odometry frame (one per column); the
  // pose covariance grows along them with each degraded frame.
  std::string degraded;
  Eigen::Matrix3Xd guessed_directions = Eigen::Matrix3Xd(3, 0);
};

// One line for a log about a frame that was not tracked ("not tracked (predicted, frame 2 of the
// gap): <failure>") or was relocalised ("relocalised against keyframe 3 after 10 lost frames");
// empty for a frame tracked as usual.
std::string trackingEvent(const OdometryResult& result);

class IcpDvoOdometry {
 public:
  // Throws InputError for an invalid camera or config, or when the backend cannot be made. `lens`: the
  // camera's distortion (camera_info's D), undone before tracking when config.undistort_lens.
  IcpDvoOdometry(const PinholeCamera& camera, const OdometryConfig& config,
                 std::unique_ptr<OdometryBackend> backend = nullptr, const LensDistortion& lens = {});
  ~IcpDvoOdometry();  // waits for the local window's links being solved in the background
  IcpDvoOdometry(const IcpDvoOdometry&) = delete;
  IcpDvoOdometry& operator=(const IcpDvoOdometry&) = delete;

  // Estimates the frame's pose (against the keyframe, or the previous frame). Throws InputError when
  // the frame does not fit the camera (size, colour vs depth); bad content (no valid depth, no texture
  // or structure, a jump, a wrong minimum) is reported in the result with its state (predicted or lost).
  // `gyro`: the camera's rotation since the last frame as an IMU measured it (gyro_rotation_prior.h):
  // the solve starts from it and holds the rotation to it with its information (times imu_weight).
  // With it, a frame whose vision leaves directions free (one plane, no texture, no depth) is tracked
  // degraded instead of lost: the translation there from the motion model.
  // `accelerometer`: its samples in the camera frame (m/s^2, the camera's clock, stamps increasing, at
  // least the last second's): with config.gravity_time_constant > 0 gravity (the specific force less the
  // camera's acceleration) pulls roll and pitch toward the level of its first window (GravityCorrection),
  // on tracked frames.
  OdometryResult track(const RgbdFrame& frame, const RotationPrior* gyro = nullptr,
                       const std::vector<AccelerometerSample>* accelerometer = nullptr);

  // The finest pyramid level the next frames are tracked at: 0 (the default) is the input's resolution;
  // each level above leaves the finest out, a quarter of the pixels at a time, for a live stream that
  // comes faster than the frames are tracked (ResolutionGovernor): a coarser estimate of every frame
  // rather than frames skipped. The keyframe's overlap and fit, the running residual level and the
  // inlier minima are kept per level, so switching makes no keyframe and no suspicious frame of itself.
  // `row_step` > 1: that level's systems from one row in row_step (OdometryBackend::setSampledRows), the
  // step before a coarser level where the backend does so (a CPU's; else every row, finestRowStep() 1):
  // on the real TUM sequences RPE within 1.5 % of every row's at 2, where level 1 is 3-12 % above.
  // Throws InputError for a level outside [0, levels), one with no iterations or a row_step outside [1, 8].
  void setFinestLevel(int level, int row_step = 1);
  int finestLevel() const { return finest_level_; }
  int finestRowStep() const { return finest_row_step_; }

  // Forgets the reference frame; the next frame starts again at `pose`.
  void reset(const Eigen::Isometry3d& pose = Eigen::Isometry3d::Identity());
  // Waits for the local window's links being solved in the background and refines the window with
  // them now (the next frame's pose shows it); nothing without a window or a pending job.
  void finishWindow();

  // The pose published for the last frame (result.pose).
  const Eigen::Isometry3d& pose() const { return published_pose_; }
  // The estimate of the last frame: with the local window, the published pose plus what it has not yet
  // taken in of the window's refinements (without, the same).
  const Eigen::Isometry3d& estimatedPose() const { return pose_; }
  const Matrix6d& poseCovariance() const { return pose_covariance_; }
  const OdometryBackend& backend() const { return *backend_; }
  // The threads of the estimator's loops (the backend's where it has them).
  const WorkerPool& workers() const { return *workers_; }
  const PinholeCamera& camera() const { return camera_; }
  const LensDistortion& lens() const { return lens_; }
  // Whether frames are rectified before tracking (a lens to undo or a rolling shutter), and the last
  // frame given to track() as tracked (undistorted, rows turned to one instant): what clouds built
  // from it should use. Empty before the first frame or when not rectifying.
  bool rectifying() const { return rectification_.active(); }
  const RgbdFrame& lastRectifiedFrame() const { return rectified_; }
  const OdometryConfig& config() const { return config_; }
  // What the estimator undoes of the real camera, for the user: e.g. "lens plumb_bob undone, rows of a
  // 0.020 s rolling shutter rectified (rolling_shutter_readout: 0 for a global-shutter camera), depth
  // taken 0.005 s before the colour, brightness affine".
  std::string cameraModelText() const;

 private:
  // A frame later ones are tracked against, kept for relocalisation.
  struct Keyframe {
    int id = 0;
    RgbdFrame frame;  // to preprocess again (relocalisation) and to extract features from when needed
    // The frame as given while `frame` is rectified without the camera's motion (none was known yet:
    // a rolling shutter's rows not turned); rectified again, and emptied, once a motion is measured.
    RgbdFrame unrectified;
    std::shared_ptr<const FrameFeatures> features;  // null until needed
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    Matrix6d pose_covariance = Matrix6d::Zero();
    // Per pyramid level, of the first frame tracked against it at that level (0: none yet), what later
    // frames' overlap and fit at the same level compare with.
    std::vector<int> first_inliers;
    std::vector<double> first_residual;
  };
  // With a gyro, what is known of a frame's motion (keyframe <- current) before vision: the gyro's
  // rotation, and the motion model's translation with its information (both times imu_weight).
  struct MotionPrior {
    RotationPrior rotation;
    Eigen::Vector3d translation = Eigen::Vector3d::Zero();
    double translation_information = 0.0;
  };
  struct DenseSolve {
    Eigen::Isometry3d increment = Eigen::Isometry3d::Identity();
    Matrix6d information = Matrix6d::Zero();  // the final fused system's A
    // With a gyro prior: where the last step would have gone on vision alone (else the increment).
    Eigen::Isometry3d vision_only = Eigen::Isometry3d::Identity();
    // With a motion prior, at the last step: the translation directions (keyframe frame, unit columns)
    // held to the motion model because vision's information there was below its, the information that
    // added, and the terms left out for too few inliers ("photometric term left out: ...").
    Eigen::Matrix3Xd guessed = Eigen::Matrix3Xd(3, 0);
    Matrix6d guess_information = Matrix6d::Zero();
    std::string terms_left_out;
    bool residual_term_left_out = false;  // the term residualLevelOf reads was among them
    // Per pyramid level, of its last pass (0 where the level was not tracked, or that term left out):
    // what the running levels and a keyframe's first frame keep per level.
    std::vector<double> level_residual;
    std::vector<int> level_inliers;
    OdometryQuality quality;
    std::string failure;  // empty when every check passed
  };
  // The coarse-to-fine ICP + DVO solve of `current` against `reference` (the frames the backend holds)
  // from `start` (keyframe <- current), and its checks; a jump is measured from `last` (the last
  // frame's pose in the keyframe).
  // `prior`: the rotation reference <- current a gyro predicts, added to every level's system, and the
  // motion model's translation, added where vision leaves a direction free; with it a term with too few
  // inliers is left out instead of failing the solve.
  DenseSolve solveFrom(const RgbdFrame& reference, const RgbdFrame& current, const Eigen::Isometry3d& start,
                       const Eigen::Isometry3d& last, OdometryBackend* backend = nullptr, const MotionPrior* prior = nullptr);
  // The residual a wrong minimum shows in: photometric RMSE (ICP's in ICP mode).
  double residualLevelOf(const OdometryQuality& quality) const;
  // That of a solve, 0 when its term was left out: the fit and wrong-minimum checks then pass it by.
  double residualOf(const DenseSolve& solve) const;
  // The residual a wrong minimum is told by and the running level it is compared with: at the solve's
  // finest level, or where that level has none yet (a stream that started coarse tracks at it for the
  // first time) at the finest coarser one that has (level -1: none at any, e.g. the first pair).
  struct ResidualCheck {
    int level = -1;
    double residual = 0.0;  // 0: its term was left out
    double running = 0.0;
  };
  ResidualCheck residualCheckOf(const DenseSolve& solve) const;
  // Failed, or a residual far above the running level: worth a second start from the features.
  bool suspicious(const DenseSolve& solve) const;
  // Makes the backend track `frame` against `keyframe` (preprocessing the keyframe again if the backend
  // no longer holds it).
  void pushAgainst(const Keyframe& keyframe, const RgbdFrame& frame);
  // Pushes a frame to the backend, built for the finest level tracked now.
  void pushToBackend(const RgbdFrame& frame, ReferenceUpdate update);
  // The dense solve against the active keyframe from `predicted` (keyframe <- current), with the
  // feature fallback the config asks for, and the wrong-minimum test. `extrapolated`: where the last
  // measured motion carries on to over the time since the last frame, the fallback's second start
  // when the features give none (frames skipped on a busy CPU move several frames' worth).
  DenseSolve trackAgainstActive(const RgbdFrame& frame, const Eigen::Isometry3d& predicted,
                                const std::optional<Eigen::Isometry3d>& extrapolated, const MotionPrior* prior,
                                std::shared_ptr<const FrameFeatures>* features, OdometryResult* result);
  // Marks a passing solve as failed when its residual is far above the running level, or its motion
  // far from the one the features agree on (when they were asked).
  void rejectWrongMinimum(const std::optional<Eigen::Isometry3d>& feature_motion, DenseSolve* solve) const;
  // Matches the frame's features against the recent keyframes (the active one included) and refines
  // the best match densely; on success that keyframe becomes the active one.
  bool relocalise(const RgbdFrame& frame, std::shared_ptr<const FrameFeatures>* features, DenseSolve* solve,
                  OdometryResult* result);
  // Whether the keyframe should be replaced after `solve` (always frame to frame).
  bool keyframeWornOut(const Keyframe& keyframe, const DenseSolve& solve) const;
  void addKeyframe(const RgbdFrame& frame, std::shared_ptr<const FrameFeatures> features);
  // The dense links of a new keyframe to earlier ones, to be solved: copies of the frames, as a
  // keyframe's frame may be rectified again meanwhile.
  struct WindowJob {
    struct Reference {
      int id = 0;
      RgbdFrame frame;
      Eigen::Isometry3d start;  // the reference keyframe <- the new one, as the window has them
    };
    int added_id = 0;
    RgbdFrame added_frame;
    std::vector<Reference> references;
    double residual_level = 0.0;  // the running level when the job was made
  };
  // The local window after the active keyframe was made from a frame tracked against keyframe
  // `tracked_against` by `solve`: both join the window with their link, and the new keyframe's dense
  // links to earlier ones are solved (now, or in the background when config.local_window_background).
  void startWindow(int tracked_against, const DenseSolve& solve, OdometryResult* result);
  // A job for the active keyframe, made from a frame `solve` tracked against keyframe `tracked_against`:
  // that link again where it was tracked coarser than the input (keep_pace_refines_keyframes), else none yet.
  std::shared_ptr<WindowJob> newLinkJob(int tracked_against, const DenseSolve& solve);
  // Solves a job's links now (then applies them) or in the background (config.local_window_background).
  void runLinkJob(const std::shared_ptr<WindowJob>& job, OdometryResult* result);
  // Into the window when there is one, else as refined coarse links.
  void applyLinks(const std::vector<KeyframeLink>& links, OdometryResult* result);
  // The links of a job on the window's own backend; touches nothing the tracking uses.
  std::vector<KeyframeLink> solveWindowLinks(const WindowJob& job);
  // Adds links to the window and refines it: the keyframes and the estimate move, the published pose
  // follows them over the next frames.
  void applyWindowLinks(const std::vector<KeyframeLink>& links, OdometryResult* result);
  // Without a window: the active keyframe, made from a frame `solve` tracked coarser than the input
  // against keyframe `tracked_against` (keeping pace), gets that link solved again at the input's
  // resolution (config.keep_pace_refines_keyframes; on the window's thread when background) ...
  void refineCoarseLink(int tracked_against, const DenseSolve& solve, OdometryResult* result);
  // ... and is moved by the difference, with every keyframe after it and the estimate.
  void applyRefinedLinks(const std::vector<KeyframeLink>& links, OdometryResult* result);
  // The estimate after the keyframes moved: on the active one; the published pose follows over frames.
  void moveEstimateWithKeyframes(OdometryResult* result);
  // Applies the background job's links once it has finished (`wait`: waits for it).
  void collectWindow(bool wait, OdometryResult* result);
  // The result's pose and increment from the estimate pose_: the estimate with the part of the
  // window's corrections not yet let through (so /odom never jumps), that part shrunk for the next
  // frame; the last published pose again while lost.
  void publish(OdometryResult* result);
  // The last measured motion per second (twist [v; w] of last <- current over its time; zero before one).
  Vector6d velocityPerSecond() const;
  int inliersOf(const OdometryQuality& quality) const;

  PinholeCamera camera_;
  LensDistortion lens_;
  OdometryConfig config_;
  FrameRectification rectification_;
  RgbdFrame rectified_;
  std::unique_ptr<OdometryBackend> backend_;
  // The threads of the estimator's own loops: the backend's where it has them, else a pool of
  // config.threads of its own (a GPU backend's host side).
  std::unique_ptr<WorkerPool> own_workers_;
  WorkerPool* workers_ = nullptr;
  Eigen::Isometry3d pose_ = Eigen::Isometry3d::Identity();  // of the last frame (tracked or predicted)
  // What was published for the last frame, and published = correction * estimate: a window's correction
  // of the estimate enters the published pose a share per frame.
  Eigen::Isometry3d published_pose_ = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d unpublished_correction_ = Eigen::Isometry3d::Identity();
  std::optional<KeyframeWindow> window_;             // the local window (none when off)
  std::unique_ptr<OdometryBackend> window_backend_;  // solves the window's links (made when first needed)
  std::future<std::vector<KeyframeLink>> window_job_;  // the links being solved in the background
  KeyframeLink coarse_link_;     // the coarse link being solved again (refineCoarseLink), as tracked
  bool window_failed_ = false;   // the window's backend failed: no more links solved
  Matrix6d pose_covariance_ = Matrix6d::Zero();
  // What degraded frames since the active keyframe added to the pose covariance along the directions
  // the motion model guessed (odometry frame); a new keyframe takes it into its own.
  Matrix6d guessed_covariance_ = Matrix6d::Zero();
  std::optional<GravityCorrection> gravity_;  // with config.gravity_time_constant > 0
  std::deque<std::shared_ptr<Keyframe>> keyframes_;  // the recent ones, oldest first; empty before the first frame
  std::shared_ptr<Keyframe> active_;                 // the one frames are tracked against
  int next_keyframe_id_ = 0;
  // What the backend holds: the keyframe ids of its reference and current frames (-1: another frame).
  int backend_reference_id_ = -1;
  int backend_current_id_ = -1;
  // The finest level each of the backend's frames was built for (setFinestLevel).
  int backend_reference_built_ = 0;
  int backend_current_built_ = 0;
  Eigen::Isometry3d active_from_last_ = Eigen::Isometry3d::Identity();  // the last frame's pose in the keyframe
  Eigen::Isometry3d velocity_ = Eigen::Isometry3d::Identity();  // the last tracked frame-to-frame motion
  double velocity_seconds_ = 0.0;  // the time velocity_ spans (0: no motion measured since the reset)
  double last_stamp_ = 0.0;        // of the last frame given to track()
  int lost_frames_ = 0;          // consecutive frames not tracked
  int finest_level_ = 0;         // setFinestLevel
  int finest_row_step_ = 1;      // setFinestLevel: as the backend samples that level's rows
  // Per pyramid level, the running average of trusted frames' residualLevelOf there (0: none yet).
  std::vector<double> residual_levels_;
};

}  // namespace vocal
