#include "vocal/odometry/icp_dvo_odometry.h"

#include <chrono>
#include <cmath>
#include <future>
#include <iomanip>
#include <limits>
#include <optional>
#include <sstream>

#include <Eigen/Eigenvalues>

#include "vocal/core/errors.h"
#include "vocal/core/lap_timer.h"

namespace vocal {

namespace {
// Floors of the residual variances used to weight the terms: a noise-free synthetic frame must not
// make one term infinitely trusted.
constexpr double kMinIcpVariance = 1e-3 * 1e-3;          // (1 mm)^2
constexpr double kMinRgbVariance = (1.0 / 255) * (1.0 / 255);  // one 8-bit level
// How far (as a share of its length) a dense motion may be from the features' before it counts as a
// wrong minimum, where no running residual level can tell.
constexpr double kFeatureMotionTolerance = 0.5;
// The pose covariance reported while lost: nothing is known (the nav_msgs convention for "unknown").
constexpr double kLostVariance = 1e6;
// The share of a window's correction of the estimate the published pose takes in per frame: most of
// it within ten frames, no step a jump.
constexpr double kCorrectionSharePerFrame = 0.2;
// The motion model a degraded frame's free translation comes from: constant velocity, its speed fading
// with this time constant (a hand-held camera or a robot does not keep a speed for long unseen), off by
// an acceleration of this much (the solve's information), and by this much speed per second of guessing
// (the covariance: a hand-held camera's speed is 0.2-0.4 m/s on TUM's freiburg1, which the guess may
// miss entirely).
constexpr double kGuessedSpeedTimeConstant = 1.0;  // seconds
constexpr double kGuessedAcceleration = 2.0;       // m/s^2
constexpr double kGuessedSpeedSigma = 0.3;         // m/s
}  // namespace

IcpDvoOdometry::IcpDvoOdometry(const PinholeCamera& camera, const OdometryConfig& config,
                               std::unique_ptr<OdometryBackend> backend, const LensDistortion& lens)
    : camera_(camera), lens_(lens), config_(config), backend_(std::move(backend)) {
  camera_.validate("odometry camera");
  config_.validate();
  if ((camera_.width >> (config_.levels - 1)) < 8 || (camera_.height >> (config_.levels - 1)) < 8) {
    throw InputError("odometry config: " + std::to_string(config_.levels) + " pyramid levels leave less than 8x8 pixels of a " +
                     std::to_string(camera_.width) + "x" + std::to_string(camera_.height) + " image");
  }
  if (!backend_) backend_ = makeOdometryBackend(camera_, config_);
  workers_ = backend_->workers();
  if (!workers_) {
    own_workers_ = std::make_unique<WorkerPool>(config_.threads);
    workers_ = own_workers_.get();
  }
  rectification_ = FrameRectification(camera_, config_.undistort_lens ? lens_ : LensDistortion(), config_.rolling_shutter_readout,
                                      config_.depth_time_offset);
  if (config_.local_window_keyframes > 0) window_.emplace(config_.local_window_keyframes);
  if (config_.gravity_time_constant > 0.0 && !window_) gravity_.emplace(config_.gravity_time_constant);
  residual_levels_.assign(config_.levels, 0.0);
}

void IcpDvoOdometry::setFinestLevel(int level, int row_step) {
  if (level < 0 || level >= config_.levels || config_.iterations[level] <= 0) {
    std::ostringstream message;
    message << "odometry: finest level " << level << " cannot be tracked (levels 0 to " << config_.levels - 1
            << " with iterations: " << (level >= 0 && level < config_.levels ? "this one has none" : "out of range") << ")";
    throw InputError(message.str());
  }
  if (row_step < 1 || row_step > kMaxFinestRowStep) {
    throw InputError("odometry: a finest level's row step must be in [1, " + std::to_string(kMaxFinestRowStep) + "], got " +
                     std::to_string(row_step));
  }
  finest_level_ = level;
  backend_->setFinestLevel(level);
  // A backend that does not sample rows builds every row (and keeps none of the step).
  finest_row_step_ = backend_->setSampledRows(level, row_step) ? row_step : 1;
}

void IcpDvoOdometry::reset(const Eigen::Isometry3d& pose) {
  if (window_job_.valid()) window_job_.wait();  // its links are of the keyframes forgotten now
  window_job_ = {};
  keyframes_.clear();
  active_.reset();
  next_keyframe_id_ = 0;
  backend_reference_id_ = backend_current_id_ = -1;
  active_from_last_ = velocity_ = Eigen::Isometry3d::Identity();
  velocity_seconds_ = 0.0;
  lost_frames_ = 0;
  residual_levels_.assign(config_.levels, 0.0);
  pose_ = published_pose_ = pose;
  unpublished_correction_ = Eigen::Isometry3d::Identity();
  if (window_) window_->clear();
  pose_covariance_.setZero();
  guessed_covariance_.setZero();
  if (gravity_) gravity_->reset();
}

std::string trackingStateName(TrackingState state) {
  switch (state) {
    case TrackingState::kTracking: return "tracking";
    case TrackingState::kDegraded: return "degraded";
    case TrackingState::kRelocalised: return "relocalised";
    case TrackingState::kPredicted: return "predicted";
    case TrackingState::kLost: return "lost";
  }
  return "unknown";
}

std::string trackingEvent(const OdometryResult& result) {
  std::ostringstream event;
  if (!result.quality.trusted) {
    event << "not tracked (" << trackingStateName(result.state) << ", frame " << result.lost_frames
          << " of the gap): " << result.failure;
  } else if (result.state == TrackingState::kRelocalised) {
    event << "relocalised against keyframe " << result.keyframe_id << " after " << result.lost_frames << " lost frames";
  }
  return event.str();
}

int IcpDvoOdometry::inliersOf(const OdometryQuality& quality) const {
  return config_.mode == OdometryMode::kRgb ? quality.rgb_inliers : quality.icp_inliers;
}

double IcpDvoOdometry::residualOf(const DenseSolve& solve) const {
  // A left-out term's residual (a few hundred pixels at a blank wall's edge) says nothing of the fit.
  return solve.residual_term_left_out ? 0.0 : residualLevelOf(solve.quality);
}

double IcpDvoOdometry::residualLevelOf(const OdometryQuality& quality) const {
  return config_.mode == OdometryMode::kIcp ? quality.icp_rmse : quality.rgb_rmse;
}

namespace {
// The gyro's rotation as a prior on the solve's: r = Log(R_prior^T R) with R moved by the step's left
// perturbation Exp(w) R, so dr/dw = R^T (r small); its information (the prior's covariance is of a
// right perturbation of the current frame) added to the rotation block, as the other terms' are.
void addRotationPrior(const RotationPrior& prior, const Eigen::Matrix3d& rotation, Matrix6d* A, Vector6d* b) {
  const Eigen::Vector3d r = so3Log(prior.rotation.transpose() * rotation);
  const Eigen::Matrix3d information = prior.covariance.inverse();
  A->bottomRightCorner<3, 3>() += rotation * information * rotation.transpose();
  b->tail<3>() -= rotation * information * r;
}

// The translation directions vision does not hold. The translation block's information with the
// rotation eliminated (the gyro holds it) is split into directions; one with less than
// kMinTranslationShare of the total is free. Asked at the coarsest level only: there a plane's normals
// are smooth and its in-plane share is 0.4-1.0 % (synthetic wall, Kinect noise), where the real TUM
// sequences' weakest direction keeps 3.1 % or more; at the finer levels the wall's noisy normals put
// 1.3-3.5 % there, information that is noise and biased (ICP facing one wall slides along it at 0.3 m/s).
constexpr double kMinTranslationShare = 0.015;

Eigen::Matrix3Xd freeTranslationDirections(const Matrix6d& A) {
  const Eigen::Matrix3d tr = A.topRightCorner<3, 3>();
  const Eigen::Matrix3d held_rotation = A.topLeftCorner<3, 3>() - tr * A.bottomRightCorner<3, 3>().ldlt().solve(tr.transpose());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(held_rotation);
  const double total = eigen.eigenvalues().sum();
  Eigen::Matrix3Xd free(3, 0);
  for (int i = 0; i < 3; ++i) {
    if (total > 0.0 && std::isfinite(total) && eigen.eigenvalues()[i] >= kMinTranslationShare * total) continue;
    free.conservativeResize(3, free.cols() + 1);
    free.col(free.cols() - 1) = eigen.eigenvectors().col(i);
  }
  return free;
}

// The motion model's translation t_guess where vision is degraded: along the free directions vision's
// information is taken out (rows and columns projected away) and the guess's put in; along the others
// the guess is added beside vision's, which near a blank wall is thin and may be biased (a frame that
// still sees a strip of the room slid 4 cm along it). Not on frames vision fully holds: on the real TUM
// sequences a guess beside every frame made fr1_rpy's ATE worse than no gyro (0.0167 against 0.0164).
// The residual t - t_guess moves under the left perturbation by v + w x t: its Jacobian is [I, -[t]x].
// `added`: the guess's information.
void addTranslationGuess(const Eigen::Matrix3Xd& free, const Eigen::Vector3d& guess, double guess_information,
                         const Eigen::Vector3d& translation, Matrix6d* A, Vector6d* b, Matrix6d* added) {
  Matrix6d keep = Matrix6d::Identity();
  keep.topLeftCorner<3, 3>() -= free * free.transpose();
  *A = keep * *A * keep;
  *b = keep * *b;
  Eigen::Matrix<double, 3, 6> J;
  J << Eigen::Matrix3d::Identity(), -skew(translation);
  *added = guess_information * J.transpose() * J;
  *A += *added;
  *b -= guess_information * J.transpose() * (translation - guess);
}
}  // namespace

IcpDvoOdometry::DenseSolve IcpDvoOdometry::solveFrom(const RgbdFrame& reference, const RgbdFrame& current,
                                                     const Eigen::Isometry3d& start, const Eigen::Isometry3d& last,
                                                     OdometryBackend* backend, const MotionPrior* prior) {
  if (!backend) backend = backend_.get();
  // The window's backend runs beside tracking: its loops on its own threads (if any), never on tracking's.
  WorkerPool* workers = backend == backend_.get() ? workers_ : backend->workers();
  // The window's links, off the tracking path, are solved at the input's resolution.
  const int finest = backend == backend_.get() ? finest_level_ : 0;
  const bool use_icp = config_.mode != OdometryMode::kRgb;
  const bool use_rgb = config_.mode != OdometryMode::kIcp;
  DenseSolve solve;
  solve.quality.finest_level = finest;
  solve.quality.finest_row_step = backend == backend_.get() ? finest_row_step_ : 1;
  solve.level_residual.assign(config_.levels, 0.0);
  solve.level_inliers.assign(config_.levels, 0);
  Eigen::Isometry3d& T = solve.increment;
  T = start;
  double rgb_sigma = std::numeric_limits<double>::infinity();  // no robust weighting until measured
  NormalEquations last_icp, last_rgb;
  double last_count = 0.0;
  int steps = 0;
  BrightnessTransfer brightness;
  for (int level = config_.levels - 1; level >= finest; --level) {
    // The finest level's steps cost four times a coarser one's; it stops at a looser threshold.
    const double factor = level == 0 ? config_.finest_convergence_factor : 1.0;
    // Once per level, where the motion has improved: the pixels both frames see depend on it.
    if (use_rgb && config_.brightness_model == BrightnessModel::kAffine && config_.iterations[level] > 0) {
      brightness = estimateBrightnessTransfer(reference, current, camera_, T, config_.rgb_max_depth_difference, workers);
    }
    for (int iteration = 0; iteration < config_.iterations[level]; ++iteration) {
      NormalEquations icp, rgb;
      backend->trackingSystems(level, T, config_.rgb_huber_factor * rgb_sigma, brightness, use_icp ? &icp : nullptr,
                                use_rgb ? &rgb : nullptr);
      if (rgb.count > 0) rgb_sigma = rgb.rmse();
      bool icp_left_out = false, rgb_left_out = false;
      if (prior) {
        // With a gyro a term too thin to trust is left out (the priors carry what it would have said),
        // where without one the frame fails the inlier checks below.
        const int shrink = 2 * level;  // the minima are for the finest level: a quarter per level above
        icp_left_out = use_icp && icp.count < (config_.min_icp_inliers >> shrink);
        rgb_left_out = use_rgb && rgb.count < (config_.min_rgb_inliers >> shrink);
        std::ostringstream left_out;
        if (icp_left_out) left_out << "ICP term left out: too few inliers (" << icp.count << " < " << (config_.min_icp_inliers >> shrink) << ")";
        if (rgb_left_out) {
          left_out << (icp_left_out ? "; " : "") << "photometric term left out: too few inliers (" << rgb.count << " < "
                   << (config_.min_rgb_inliers >> shrink) << ")";
        }
        solve.terms_left_out = left_out.str();
        solve.residual_term_left_out = config_.mode == OdometryMode::kIcp ? icp_left_out : rgb_left_out;
      }
      // Each term is scaled by the inverse variance of its residuals (the fused system is then the
      // information of both); rgb_weight scales the photometric term on top.
      const double icp_scale = use_icp && !icp_left_out && icp.count > 0 ? 1.0 / std::max(icp.squared_residual_sum / icp.count, kMinIcpVariance) : 0.0;
      const double rgb_scale = use_rgb && !rgb_left_out && rgb.count > 0
                                   ? (use_icp ? config_.rgb_weight : 1.0) / std::max(rgb.squared_residual_sum / rgb.count, kMinRgbVariance)
                                   : 0.0;
      Matrix6d A = icp_scale * icp.A + rgb_scale * rgb.A;
      Vector6d b = icp_scale * icp.b + rgb_scale * rgb.b;
      if (prior) {
        // Where vision alone would step from here: the motion a gyro's bias is measured against.
        const Vector6d vision_step = A.ldlt().solve(b);
        if (vision_step.allFinite()) solve.vision_only = se3Exp(vision_step) * T;
        addRotationPrior(prior->rotation, T.linear(), &A, &b);
        if (level == config_.levels - 1) solve.guessed = freeTranslationDirections(A);  // then held for the finer levels
        solve.guess_information.setZero();
        if (solve.guessed.cols() > 0 || icp_left_out || rgb_left_out) {
          addTranslationGuess(solve.guessed, prior->translation, prior->translation_information, T.translation(), &A, &b,
                              &solve.guess_information);
        }
      }
      last_icp = icp;
      last_rgb = rgb;
      {
        OdometryQuality pass;
        pass.icp_inliers = static_cast<int>(icp.count);
        pass.rgb_inliers = static_cast<int>(rgb.count);
        pass.icp_rmse = icp.rmse();
        pass.rgb_rmse = rgb.rmse();
        const bool residual_left_out = config_.mode == OdometryMode::kIcp ? icp_left_out : rgb_left_out;
        solve.level_residual[level] = residual_left_out ? 0.0 : residualLevelOf(pass);
        solve.level_inliers[level] = inliersOf(pass);
      }
      solve.information = A;
      last_count = icp.count + rgb.count;
      if (last_count < 6 && !prior) break;  // nothing to solve at this level
      const Vector6d x = A.ldlt().solve(b);
      if (!x.allFinite()) break;
      T = se3Exp(x) * T;
      ++steps;
      // Converged: further steps at this level would not move the estimate.
      if (x.head<3>().norm() < factor * config_.convergence_translation &&
          x.tail<3>().norm() < factor * config_.convergence_rotation) {
        if (level == finest) solve.quality.converged = true;
        break;
      }
    }
  }

  if (!prior) solve.vision_only = T;
  OdometryQuality& q = solve.quality;
  if (config_.iterations[finest] == 0) q.converged = true;  // nothing asked of the finest level
  q.icp_inliers = static_cast<int>(last_icp.count);
  q.rgb_inliers = static_cast<int>(last_rgb.count);
  q.icp_rmse = last_icp.rmse();
  q.rgb_rmse = last_rgb.rmse();
  q.iterations = steps;
  q.brightness_gain = brightness.gain;
  q.brightness_bias = brightness.bias;
  const Eigen::SelfAdjointEigenSolver<Matrix6d> eigen(solve.information, Eigen::EigenvaluesOnly);
  const double smallest = eigen.eigenvalues()[0], largest = eigen.eigenvalues()[5];
  q.condition = smallest > 0.0 ? largest / smallest : std::numeric_limits<double>::infinity();
  q.weakest_information = last_count > 0.0 ? smallest / last_count : 0.0;

  const Eigen::Isometry3d jump = last.inverse() * T;
  std::ostringstream failure;
  // With a prior the terms too thin were left out, the priors filling what they leave free. The minima
  // are for the input's resolution: a quarter per level left out.
  const int min_icp_inliers = config_.min_icp_inliers >> (2 * finest), min_rgb_inliers = config_.min_rgb_inliers >> (2 * finest);
  if (!prior && use_icp && q.icp_inliers < min_icp_inliers) {
    failure << "too few ICP inliers (" << q.icp_inliers << " < " << min_icp_inliers << ")";
  } else if (!prior && use_rgb && q.rgb_inliers < min_rgb_inliers) {
    failure << "too few photometric inliers (" << q.rgb_inliers << " < " << min_rgb_inliers << ")";
  } else if (!(q.condition <= config_.max_condition)) {
    failure << "the system is degenerate (condition " << q.condition << " > " << config_.max_condition
            << "): the scene does not constrain every degree of freedom";
  } else if (jump.translation().norm() > config_.max_translation) {
    failure << "implausible jump of " << jump.translation().norm() << " m (> " << config_.max_translation << " m)";
  } else if (rotationAngle(jump) * 180.0 / M_PI > config_.max_rotation_deg) {
    failure << "implausible rotation of " << rotationAngle(jump) * 180.0 / M_PI << " deg (> " << config_.max_rotation_deg
            << " deg)";
  }
  solve.failure = failure.str();
  return solve;
}

IcpDvoOdometry::ResidualCheck IcpDvoOdometry::residualCheckOf(const DenseSolve& solve) const {
  const int finest = solve.quality.finest_level;
  for (int level = finest; level < config_.levels; ++level) {
    if (!(residual_levels_[level] > 0.0)) continue;
    const double residual = level == finest ? residualOf(solve) : solve.level_residual[level];
    if (level != finest && !(residual > 0.0)) continue;
    return {level, residual, residual_levels_[level]};
  }
  return {};
}

bool IcpDvoOdometry::suspicious(const DenseSolve& solve) const {
  // Without a running level (the first pair) a wrong minimum cannot be told apart: ask the features.
  const ResidualCheck check = residualCheckOf(solve);
  if (!solve.failure.empty() || check.level < 0) return true;
  return check.residual > config_.feature_fallback_residual_ratio * check.running;
}

void IcpDvoOdometry::pushToBackend(const RgbdFrame& frame, ReferenceUpdate update) {
  backend_->pushFrame(frame, update);
  if (update == ReferenceUpdate::kPreviousFrame) backend_reference_built_ = backend_current_built_;
  backend_current_built_ = finest_level_;
}

void IcpDvoOdometry::pushAgainst(const Keyframe& keyframe, const RgbdFrame& frame) {
  // A keyframe built for a coarser finest level than tracked now is built again.
  if (backend_reference_id_ == keyframe.id && backend_reference_built_ <= finest_level_) {
    pushToBackend(frame, ReferenceUpdate::kKeep);
  } else {
    if (backend_current_id_ != keyframe.id || backend_current_built_ > finest_level_)
      pushToBackend(keyframe.frame, ReferenceUpdate::kPreviousFrame);
    pushToBackend(frame, ReferenceUpdate::kPreviousFrame);
  }
  backend_reference_id_ = keyframe.id;
  backend_current_id_ = -1;
}

std::string IcpDvoOdometry::cameraModelText() const {
  std::ostringstream text;
  text << (lens_.isNone() ? std::string("no lens distortion given")
                          : config_.undistort_lens ? "lens " + distortionModelName(lens_.model) + " undone"
                                                   : "lens " + distortionModelName(lens_.model) + " ignored (undistort_lens false)");
  if (config_.rolling_shutter_readout > 0.0) {
    text << ", rows of a " << std::fixed << std::setprecision(3) << config_.rolling_shutter_readout
         << " s rolling shutter rectified (rolling_shutter_readout: 0 for a global-shutter camera)";
  } else {
    text << ", global shutter";
  }
  if (config_.depth_time_offset != 0.0) {
    text << ", depth taken " << std::fixed << std::setprecision(3) << std::fabs(config_.depth_time_offset) << " s "
         << (config_.depth_time_offset < 0.0 ? "before" : "after") << " the colour";
  }
  text << ", brightness " << (config_.brightness_model == BrightnessModel::kAffine ? "affine" : "fixed");
  return text.str();
}

Vector6d IcpDvoOdometry::velocityPerSecond() const {
  return velocity_seconds_ > 0.0 ? Vector6d(se3Log(velocity_) / velocity_seconds_) : Vector6d::Zero();
}

void IcpDvoOdometry::addKeyframe(const RgbdFrame& frame, std::shared_ptr<const FrameFeatures> features) {
  auto keyframe = std::make_shared<Keyframe>();
  keyframe->id = next_keyframe_id_++;
  keyframe->frame = frame;
  keyframe->features = std::move(features);
  keyframe->pose = pose_;
  keyframe->pose_covariance = pose_covariance_;
  keyframe->first_inliers.assign(config_.levels, 0);
  keyframe->first_residual.assign(config_.levels, 0.0);
  guessed_covariance_.setZero();  // now in the keyframe's
  keyframes_.push_back(keyframe);
  while (static_cast<int>(keyframes_.size()) > config_.keyframes_kept) keyframes_.pop_front();
  active_ = std::move(keyframe);
}

bool IcpDvoOdometry::keyframeWornOut(const Keyframe& keyframe, const DenseSolve& solve) const {
  if (config_.tracking_reference == TrackingReference::kFrame) return true;
  const int level = solve.quality.finest_level;
  const bool overlap_lost = keyframe.first_inliers[level] > 0 &&
                            inliersOf(solve.quality) < config_.keyframe_min_overlap * keyframe.first_inliers[level];
  const bool fit_lost = keyframe.first_residual[level] > 0.0 &&
                        residualOf(solve) > config_.keyframe_max_residual_growth * keyframe.first_residual[level];
  const bool unconverged = config_.keyframe_after_unconverged && !solve.quality.converged;
  return overlap_lost || fit_lost || unconverged || solve.increment.translation().norm() > config_.keyframe_max_translation ||
         rotationAngle(solve.increment) * 180.0 / M_PI > config_.keyframe_max_rotation_deg;
}

IcpDvoOdometry::DenseSolve IcpDvoOdometry::trackAgainstActive(const RgbdFrame& frame, const Eigen::Isometry3d& predicted,
                                                              const std::optional<Eigen::Isometry3d>& extrapolated,
                                                              const MotionPrior* prior, std::shared_ptr<const FrameFeatures>* features,
                                                              OdometryResult* result) {
  auto clock = std::chrono::steady_clock::now();
  // The motion the features agree on (extracting those not extracted yet), asked for at most once.
  bool features_asked = false;
  std::optional<Eigen::Isometry3d> feature_motion;
  auto featureMotion = [&]() -> std::optional<Eigen::Isometry3d> {
    if (features_asked) return feature_motion;
    features_asked = true;
    if (!active_->features) active_->features = extractFrameFeatures(active_->frame, camera_);
    if (!*features) *features = extractFrameFeatures(frame, camera_);
    const FeatureAlignment alignment = alignFrameFeatures(*active_->features, **features, camera_);
    if (alignment.found) {
      feature_motion = alignment.reference_from_current;
      result->quality.feature_inliers = alignment.inliers;
    }
    result->timings.features_ms += lapMilliseconds(&clock);
    return feature_motion;
  };

  DenseSolve solve;
  switch (config_.feature_initialisation) {
    case FeatureInitialisation::kAlways:
      solve = solveFrom(active_->frame, frame, featureMotion().value_or(predicted), active_from_last_, nullptr, prior);
      break;
    case FeatureInitialisation::kOff:
      solve = solveFrom(active_->frame, frame, prior ? predicted : active_from_last_, active_from_last_, nullptr, prior);  // no motion since the last frame but the gyro's
      break;
    case FeatureInitialisation::kFallback: {
      solve = solveFrom(active_->frame, frame, predicted, active_from_last_, nullptr, prior);
      if (!suspicious(solve)) break;
      result->quality.feature_fallback = true;
      result->timings.solve_ms += lapMilliseconds(&clock);
      // A retry wins when it passes and the first did not, or both pass and it fits better.
      const auto retryFrom = [&](const Eigen::Isometry3d& start) {
        DenseSolve retry = solveFrom(active_->frame, frame, start, active_from_last_, nullptr, prior);
        const bool won = retry.failure.empty() && (!solve.failure.empty() || residualLevelOf(retry.quality) < residualLevelOf(solve.quality));
        if (won) solve = std::move(retry);
        return won;
      };
      const std::optional<Eigen::Isometry3d> start = featureMotion();
      const bool features_won = start && retryFrom(*start);
      if (!features_won) result->quality.feature_inliers = 0;  // the result did not start from the features
      if (!start && extrapolated) retryFrom(*extrapolated);
      break;
    }
  }
  result->timings.solve_ms += lapMilliseconds(&clock);
  // Without a running level (the first pair, after a reset or a loss) a wrong minimum does not stand
  // out by its residual: the features check it, extracted for that alone when initialisation is off.
  if (solve.failure.empty() && residualCheckOf(solve).level < 0) featureMotion();
  rejectWrongMinimum(feature_motion, &solve);
  return solve;
}

void IcpDvoOdometry::rejectWrongMinimum(const std::optional<Eigen::Isometry3d>& feature_motion, DenseSolve* solve) const {
  if (feature_motion) {
    const Eigen::Isometry3d disagreement = feature_motion->inverse() * solve->increment;
    solve->quality.feature_disagreement_m = disagreement.translation().norm();
    solve->quality.feature_disagreement_deg = rotationAngle(disagreement) * 180.0 / M_PI;
  }
  if (!solve->failure.empty()) return;
  std::ostringstream failure;
  const ResidualCheck check = residualCheckOf(*solve);
  if (solve->residual_term_left_out) {
    // The term the level is of was left out (too few inliers, a gyro holding the motion): its residual,
    // over a few hundred pixels at a blank wall's edge, says nothing of a wrong minimum.
  } else if (check.level >= 0) {
    if (check.residual > config_.wrong_minimum_residual_ratio * check.running) {
      failure << "a wrong minimum: the " << (config_.mode == OdometryMode::kIcp ? "ICP" : "photometric") << " RMSE "
              << check.residual << " is " << check.residual / check.running << "x the running level (> "
              << config_.wrong_minimum_residual_ratio << "x)";
      if (check.level != solve->quality.finest_level) failure << " at pyramid level " << check.level;
    }
  } else if (!feature_motion) {
    // Back from a loss with nothing to compare with: the dense minimum may be any.
    if (lost_frames_ > 0) {
      failure << "after " << lost_frames_ << " lost frames neither a running residual level nor matching features "
              << "confirm the dense motion";
    }
  } else {
    // Only where the residual cannot tell: a correct dense motion fits at the running level even where
    // the features' is centimetres off (wide baselines at low resolution). Features locate a motion to
    // a fraction of its length, so the bound grows with it.
    const double max_translation = std::max(config_.wrong_minimum_feature_translation,
                                            kFeatureMotionTolerance * feature_motion->translation().norm());
    const double max_rotation_deg = std::max(config_.wrong_minimum_feature_rotation_deg,
                                             kFeatureMotionTolerance * rotationAngle(*feature_motion) * 180.0 / M_PI);
    if (solve->quality.feature_disagreement_m > max_translation || solve->quality.feature_disagreement_deg > max_rotation_deg) {
      failure << "a wrong minimum: the dense motion is " << solve->quality.feature_disagreement_m << " m and "
              << solve->quality.feature_disagreement_deg << " deg from the features' (> " << max_translation << " m or "
              << max_rotation_deg << " deg)";
    }
  }
  solve->failure = failure.str();
}

bool IcpDvoOdometry::relocalise(const RgbdFrame& frame, std::shared_ptr<const FrameFeatures>* features,
                                DenseSolve* solve, OdometryResult* result) {
  auto clock = std::chrono::steady_clock::now();
  if (!*features) *features = extractFrameFeatures(frame, camera_);
  std::shared_ptr<Keyframe> best;
  FeatureAlignment best_alignment;
  for (auto keyframe = keyframes_.rbegin(); keyframe != keyframes_.rend(); ++keyframe) {  // newest first
    if (!(*keyframe)->features) (*keyframe)->features = extractFrameFeatures((*keyframe)->frame, camera_);
    const FeatureAlignment alignment = alignFrameFeatures(*(*keyframe)->features, **features, camera_);
    if (alignment.found && alignment.inliers > best_alignment.inliers) {
      best = *keyframe;
      best_alignment = alignment;
    }
  }
  result->timings.features_ms += lapMilliseconds(&clock);
  if (!best) return false;
  pushAgainst(*best, frame);
  result->timings.preprocess_ms += lapMilliseconds(&clock);
  // The last pose is a prediction (or older): the refinement must instead stay near the features' motion.
  DenseSolve refined = solveFrom(best->frame, frame, best_alignment.reference_from_current, best_alignment.reference_from_current);
  rejectWrongMinimum(best_alignment.reference_from_current, &refined);
  result->timings.solve_ms += lapMilliseconds(&clock);
  if (!refined.failure.empty()) return false;
  active_ = best;
  *solve = std::move(refined);
  result->quality.feature_inliers = best_alignment.inliers;
  return true;
}

void IcpDvoOdometry::startWindow(int tracked_against, const DenseSolve& solve, OdometryResult* result) {
  const Keyframe& added = *active_;
  window_->addKeyframe(added.id, added.pose);
  window_->addLink({tracked_against, added.id, solve.increment, solve.information});
  if (window_job_.valid()) {
    result->window_links_skipped = true;  // the last keyframe's links are still being solved
    return;
  }
  // The new keyframe against the newest earlier ones of the window (a bounded cost per keyframe: a
  // failed solve, too little overlap or a poor fit, is not replaced by an older one).
  const std::shared_ptr<WindowJob> job = newLinkJob(tracked_against, solve);
  const int links = config_.local_window_links + static_cast<int>(job->references.size());
  for (auto earlier = keyframes_.rbegin(); earlier != keyframes_.rend(); ++earlier) {
    if (static_cast<int>(job->references.size()) == links) break;
    const Keyframe& reference = **earlier;
    const std::optional<Eigen::Isometry3d> reference_pose = window_->pose(reference.id);
    if (reference.id == added.id || reference.id == tracked_against || !reference_pose) continue;
    job->references.push_back({reference.id, reference.frame, reference_pose->inverse() * added.pose});
  }
  runLinkJob(job, result);
}

std::shared_ptr<IcpDvoOdometry::WindowJob> IcpDvoOdometry::newLinkJob(int tracked_against, const DenseSolve& solve) {
  auto job = std::make_shared<WindowJob>();
  job->added_id = active_->id;
  job->added_frame = active_->frame;
  job->residual_level = residual_levels_[0];  // the links are solved at the input's resolution
  // Tracked coarser than the input (keeping pace with a busy CPU): the link it was tracked by is solved
  // again at the input's resolution, so that keyframe to keyframe - where drift adds up - keeps its accuracy.
  if (solve.quality.finest_level > 0 && config_.keep_pace_refines_keyframes) {
    for (const std::shared_ptr<Keyframe>& earlier : keyframes_) {
      if (earlier->id != tracked_against) continue;
      job->references.push_back({earlier->id, earlier->frame, solve.increment});
      coarse_link_ = {tracked_against, active_->id, solve.increment, solve.information};
    }
  }
  return job;
}

void IcpDvoOdometry::runLinkJob(const std::shared_ptr<WindowJob>& job, OdometryResult* result) {
  if (job->references.empty()) return;
  if (!config_.local_window_background) {
    applyLinks(solveWindowLinks(*job), result);
    return;
  }
  window_job_ = std::async(std::launch::async, [this, job] { return solveWindowLinks(*job); });
}

void IcpDvoOdometry::applyLinks(const std::vector<KeyframeLink>& links, OdometryResult* result) {
  if (window_) applyWindowLinks(links, result);
  else applyRefinedLinks(links, result);
}

std::vector<KeyframeLink> IcpDvoOdometry::solveWindowLinks(const WindowJob& job) {
  if (!window_backend_) {
    OdometryConfig config = config_;
    if (config_.local_window_background) config.threads = 1;  // beside the tracking's threads, not on top of them
    window_backend_ = makeOdometryBackend(camera_, config);
  }
  std::vector<KeyframeLink> links;
  for (const WindowJob::Reference& reference : job.references) {
    window_backend_->pushFrame(reference.frame, ReferenceUpdate::kPreviousFrame);
    window_backend_->pushFrame(job.added_frame, ReferenceUpdate::kPreviousFrame);
    const DenseSolve link = solveFrom(reference.frame, job.added_frame, reference.start, reference.start, window_backend_.get());
    // Failed checks, or a wrong minimum by the running residual level (as tracking tells them).
    if (!link.failure.empty()) continue;
    if (job.residual_level > 0.0 && residualLevelOf(link.quality) > config_.wrong_minimum_residual_ratio * job.residual_level) continue;
    links.push_back({reference.id, job.added_id, link.increment, link.information});
  }
  return links;
}

void IcpDvoOdometry::refineCoarseLink(int tracked_against, const DenseSolve& solve, OdometryResult* result) {
  if (window_job_.valid()) {
    result->window_links_skipped = true;  // the last keyframe's link is still being solved
    return;
  }
  runLinkJob(newLinkJob(tracked_against, solve), result);  // none when that keyframe is no longer kept
}

void IcpDvoOdometry::applyRefinedLinks(const std::vector<KeyframeLink>& links, OdometryResult* result) {
  for (const KeyframeLink& link : links) {
    if (link.from_id != coarse_link_.from_id || link.to_id != coarse_link_.to_id) continue;
    // The new keyframe's pose changes by this (its own frame); a larger change than a wrong start is
    // allowed is not a refinement.
    const Eigen::Isometry3d change = coarse_link_.from_T_to.inverse() * link.from_T_to;
    if (!change.matrix().allFinite() || change.translation().norm() > config_.wrong_minimum_feature_translation ||
        rotationAngle(change) * 180.0 / M_PI > config_.wrong_minimum_feature_rotation_deg)
      continue;
    const auto refined = std::find_if(keyframes_.begin(), keyframes_.end(),
                                      [&](const std::shared_ptr<Keyframe>& k) { return k->id == link.to_id; });
    if (refined == keyframes_.end()) continue;
    // It moves by the change (on the right: what gravity corrected since stays), every keyframe made after
    // it with it. Rotations kept orthonormal: each keyframe's pose is built on the one before, so a
    // rounding error would compound.
    const Eigen::Isometry3d was = (*refined)->pose;
    for (auto k = refined; k != keyframes_.end(); ++k) {
      Eigen::Isometry3d pose = was * change * (was.inverse() * (*k)->pose);
      pose.linear() = Eigen::Quaterniond(pose.rotation()).normalized().toRotationMatrix();
      (*k)->pose = pose;
    }
    ++result->window_links;
    moveEstimateWithKeyframes(result);
  }
}

void IcpDvoOdometry::applyWindowLinks(const std::vector<KeyframeLink>& links, OdometryResult* result) {
  for (const KeyframeLink& link : links) window_->addLink(link);
  result->window_links += static_cast<int>(links.size());
  if (links.empty() || !window_->optimise()) return;
  for (const std::shared_ptr<Keyframe>& keyframe : keyframes_) {
    if (const std::optional<Eigen::Isometry3d> refined = window_->pose(keyframe->id)) keyframe->pose = *refined;
  }
  moveEstimateWithKeyframes(result);
}

void IcpDvoOdometry::moveEstimateWithKeyframes(OdometryResult* result) {
  // The estimate moves with the active keyframe; what is published does not, yet.
  const Eigen::Isometry3d estimate = active_->pose * active_from_last_;
  const Eigen::Isometry3d moved = pose_.inverse() * estimate;
  result->window_correction_m = moved.translation().norm();
  result->window_correction_deg = rotationAngle(moved) * 180.0 / M_PI;
  unpublished_correction_ = unpublished_correction_ * pose_ * estimate.inverse();
  pose_ = estimate;
}

void IcpDvoOdometry::collectWindow(bool wait, OdometryResult* result) {
  if (!window_job_.valid()) return;
  if (!wait && window_job_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return;
  std::vector<KeyframeLink> links;
  try {
    links = window_job_.get();
  } catch (const std::exception& e) {
    // Its backend could not be made or failed: tracking goes on without the window.
    result->window_error = std::string(window_ ? "the local window's links could not be solved, the window is off from now: "
                                               : "a keyframe's link could not be solved again at the input's resolution; keyframes "
                                                 "made coarser are not linked again from now: ") +
                           e.what();
    window_.reset();
    window_failed_ = true;
    return;
  }
  if (active_) applyLinks(links, result);
}

void IcpDvoOdometry::finishWindow() {
  OdometryResult ignored;
  collectWindow(true, &ignored);
}

IcpDvoOdometry::~IcpDvoOdometry() {
  if (window_job_.valid()) window_job_.wait();
}

void IcpDvoOdometry::publish(OdometryResult* result) {
  // Lost, the pose stays (and so does what is left of a window's correction).
  Eigen::Isometry3d published = published_pose_;
  if (result->state != TrackingState::kLost) {
    published = unpublished_correction_ * pose_;
    unpublished_correction_ = se3Exp((1.0 - kCorrectionSharePerFrame) * se3Log(unpublished_correction_));
  }
  result->increment = published_pose_.inverse() * published;
  result->pose = published_pose_ = published;
}

OdometryResult IcpDvoOdometry::track(const RgbdFrame& input, const RotationPrior* gyro, const std::vector<AccelerometerSample>* accelerometer) {
  input.validate("odometry frame");
  if (!input.color.sameSize(camera_.width, camera_.height)) {
    std::ostringstream message;
    message << "odometry frame: images are " << input.color.width() << "x" << input.color.height()
            << " but the camera is " << camera_.width << "x" << camera_.height;
    throw InputError(message.str());
  }
  auto clock = std::chrono::steady_clock::now();
  const double since_last = input.stamp - last_stamp_;
  // The frame's time for the motion model (the last measured one's when the stamps do not say).
  const double frame_seconds = since_last > 0.0 ? since_last : velocity_seconds_;
  last_stamp_ = input.stamp;
  if (rectification_.active()) {
    // The rows turn with the last measured motion (none known yet: the lens alone).
    const Vector6d twist = velocityPerSecond();
    rectified_ = rectification_.rectify(input, twist.tail<3>(), twist.head<3>(), workers_);
  }
  const RgbdFrame& frame = rectification_.active() ? rectified_ : input;
  // A keyframe made now keeps the frame as given when its rows could not be turned (no motion yet).
  const bool rectified_at_rest = rectification_.dependsOnMotion() && !(velocity_seconds_ > 0.0);
  OdometryResult result;
  // Each frame's features are extracted at most once: matched as the current frame, kept with it if
  // it becomes a keyframe. In fallback mode only when asked for.
  std::shared_ptr<const FrameFeatures> features;
  if (config_.feature_initialisation == FeatureInitialisation::kAlways) {
    features = extractFrameFeatures(frame, camera_);
    result.timings.features_ms = lapMilliseconds(&clock);
  }
  if (!active_) {
    pushToBackend(frame, ReferenceUpdate::kPreviousFrame);
    result.timings.preprocess_ms = lapMilliseconds(&clock);
    addKeyframe(frame, features);
    if (rectified_at_rest) active_->unrectified = input;
    backend_current_id_ = active_->id;
    velocity_ = active_from_last_ = Eigen::Isometry3d::Identity();
    result.first_frame = true;
    result.quality.trusted = true;
    result.new_keyframe = true;
    result.keyframe_id = active_->id;
    if (window_) window_->addKeyframe(active_->id, active_->pose);
    if (gravity_ && accelerometer) gravity_->correct(input.stamp, pose_, *accelerometer, 0.0);  // its history starts
    publish(&result);
    result.pose_covariance = pose_covariance_;
    return result;
  }

  if (window_ || window_job_.valid()) {
    // Links solved in the background since the last frame: the keyframes move before this frame is
    // placed on its keyframe.
    result.timings.preprocess_ms += lapMilliseconds(&clock);  // the rectification
    collectWindow(false, &result);
    result.timings.window_ms += lapMilliseconds(&clock);
  }
  pushAgainst(*active_, frame);
  result.timings.preprocess_ms += lapMilliseconds(&clock);
  // Frame to frame the solve starts from the last motion (constant velocity). Against a keyframe it
  // starts from the last frame's pose: a velocity taken from two keyframe-relative estimates doubles
  // their error along weakly constrained directions, which the next solve keeps rather than removes
  // (measured on noisy synthetic frames: ATE 30 mm with it, 0.1 mm without; docs/benchmarks.md).
  Eigen::Isometry3d predicted =
      config_.tracking_reference == TrackingReference::kFrame ? active_from_last_ * velocity_ : active_from_last_;
  // With a gyro the rotation is predicted from it, and held to it with its information; the motion
  // model's translation stands by for directions vision leaves free.
  std::optional<MotionPrior> prior;
  if (gyro && config_.imu_weight > 0.0) {
    prior.emplace();
    prior->rotation = RotationPrior{active_from_last_.linear() * gyro->rotation, gyro->covariance / config_.imu_weight};
    predicted.linear() = prior->rotation.rotation;
    const Vector6d step = velocity_seconds_ > 0.0 ? Vector6d(se3Log(velocity_) * (frame_seconds / velocity_seconds_) *
                                                             std::exp(-frame_seconds / kGuessedSpeedTimeConstant))
                                                  : Vector6d::Zero();
    prior->translation = (active_from_last_ * se3Exp(step)).translation();
    const double sigma = std::max(kGuessedAcceleration * frame_seconds * frame_seconds, 1e-3);
    prior->translation_information = config_.imu_weight / (sigma * sigma);
  }
  // Against a keyframe the solve starts from the last pose; where that fails and the features give no
  // start either, from the last motion carried on (not first: see above).
  std::optional<Eigen::Isometry3d> extrapolated;
  if (config_.tracking_reference == TrackingReference::kKeyframe && !prior && velocity_seconds_ > 0.0)
    extrapolated = active_from_last_ * se3Exp(se3Log(velocity_) * (frame_seconds / velocity_seconds_));
  DenseSolve solve = trackAgainstActive(frame, predicted, extrapolated, prior ? &*prior : nullptr, &features, &result);
  const bool relocalised = !solve.failure.empty() && config_.relocalisation && relocalise(frame, &features, &solve, &result);
  clock = std::chrono::steady_clock::now();

  const OdometryQuality fallback_flags = result.quality;
  result.quality = solve.quality;
  result.quality.feature_inliers = fallback_flags.feature_inliers;
  result.quality.feature_fallback = fallback_flags.feature_fallback;
  result.failure = solve.failure;
  result.keyframe_id = active_->id;
  if (!result.failure.empty()) {
    // Not tracked: the reference stays the keyframe; a short gap is bridged by the last motion.
    result.lost_frames = ++lost_frames_;
    if (lost_frames_ <= config_.max_predicted_frames) {
      result.state = TrackingState::kPredicted;
      // The prediction may be off by as much as the motion it repeats (at least 1 cm and 0.01 rad).
      Vector6d sigma;
      sigma.head<3>().setConstant(std::max(velocity_.translation().norm(), 0.01));
      sigma.tail<3>().setConstant(std::max(rotationAngle(velocity_), 0.01));
      const Matrix6d to_odometry = adjoint(pose_);
      pose_covariance_ += to_odometry * sigma.cwiseAbs2().asDiagonal() * to_odometry.transpose();
      Eigen::Isometry3d step = velocity_;
      if (prior) step.linear() = gyro->rotation;  // the gyro's turn, the last translation
      pose_ = pose_ * step;
      active_from_last_ = active_from_last_ * step;
      result.pose_covariance = pose_covariance_;
    } else {
      result.state = TrackingState::kLost;
      result.pose_covariance = Matrix6d::Identity() * kLostVariance;
    }
    publish(&result);
    result.timings.solve_ms += lapMilliseconds(&clock);
    return result;
  }

  Keyframe& keyframe = *active_;
  const Eigen::Isometry3d& T = solve.increment;  // keyframe <- current
  const bool degraded = solve.guessed.cols() > 0 || !solve.terms_left_out.empty();
  result.state = relocalised || lost_frames_ > 0 ? TrackingState::kRelocalised
                 : degraded                      ? TrackingState::kDegraded
                                                 : TrackingState::kTracking;
  result.lost_frames = lost_frames_;
  // After a loss the last motion is kept: the pose before it was a prediction.
  if (result.state == TrackingState::kTracking || result.state == TrackingState::kDegraded) {
    velocity_ = active_from_last_.inverse() * T;
    velocity_seconds_ = since_last;
    if (!keyframe.unrectified.color.empty() && velocity_seconds_ > 0.0) {
      // Rectified before any motion was known: its rows turned now, preprocessed again when next used.
      const Vector6d twist = velocityPerSecond();
      keyframe.frame = rectification_.rectify(keyframe.unrectified, twist.tail<3>(), twist.head<3>(), workers_);
      keyframe.unrectified = RgbdFrame();
      keyframe.features.reset();
      if (backend_reference_id_ == keyframe.id) backend_reference_id_ = -1;
      if (backend_current_id_ == keyframe.id) backend_current_id_ = -1;
    }
  }
  lost_frames_ = 0;
  // The running residual level a wrong minimum stands out from (an average over about ten frames); a
  // degraded frame's (a blank wall's) says nothing of the level where vision works.
  const double residual = residualOf(solve);
  if (!degraded) {
    // Every level the solve passed through keeps its own level, so a frame tracked coarser finds one.
    for (int level = solve.quality.finest_level; level < config_.levels; ++level) {
      const double at_level = level == solve.quality.finest_level ? residual : solve.level_residual[level];
      double& running = residual_levels_[level];
      if (at_level > 0.0) running = running > 0.0 ? 0.9 * running + 0.1 * at_level : at_level;
    }
  }
  result.quality.trusted = true;
  // The motion model's guess enters the covariance with its own information, not the weight the solve
  // gave it against the dense terms; each degraded frame adds a speed's uncertainty along the guessed
  // directions (the guess errs the more, the longer it lasts).
  const double weight = config_.imu_weight > 0.0 ? config_.imu_weight : 1.0;
  result.covariance = (solve.information - solve.guess_information * (1.0 - 1.0 / weight)).inverse();
  // pose = keyframe pose * T: T's left perturbation moves into the odometry frame through the keyframe
  // pose's adjoint; the keyframe's own uncertainty adds (drift grows per keyframe, not per frame).
  const Matrix6d to_odometry = adjoint(keyframe.pose);
  // A speed's uncertainty over this frame's time along the guessed directions (keyframe frame).
  Matrix6d guessed_step = Matrix6d::Zero();
  const double step_sigma = kGuessedSpeedSigma * frame_seconds;
  guessed_step.topLeftCorner<3, 3>() = step_sigma * step_sigma * solve.guessed * solve.guessed.transpose();
  if (degraded) {
    result.guessed_directions = keyframe.pose.linear() * solve.guessed;
    guessed_covariance_ += to_odometry * guessed_step * to_odometry.transpose();
    std::ostringstream text;
    text << "vision constrains " << 3 - solve.guessed.cols() << " of 3 translation directions";
    if (solve.guessed.cols() > 0) {
      text << ", the motion model guesses " << solve.guessed.cols() << " (odometry frame:";
      for (int i = 0; i < result.guessed_directions.cols(); ++i) {
        text << std::fixed << std::setprecision(2) << (i ? "; " : " ") << result.guessed_directions(0, i) << " "
             << result.guessed_directions(1, i) << " " << result.guessed_directions(2, i);
      }
      text << ")";
    }
    text << ", the gyro holds the rotation";
    if (!solve.terms_left_out.empty()) text << "; " << solve.terms_left_out;
    result.degraded = text.str();
  }
  pose_covariance_ = keyframe.pose_covariance + to_odometry * result.covariance * to_odometry.transpose() + guessed_covariance_;
  result.covariance += guessed_step;  // the motion's own covariance says the guess too
  pose_ = keyframe.pose * T;
  active_from_last_ = T;
  result.keyframe_stamp = keyframe.frame.stamp;
  result.vision_rotation = solve.vision_only.linear();
  result.pose_covariance = pose_covariance_;
  for (int level = solve.quality.finest_level; level < config_.levels; ++level) {
    if (keyframe.first_inliers[level] > 0) continue;
    const bool finest = level == solve.quality.finest_level;
    keyframe.first_inliers[level] = finest ? inliersOf(solve.quality) : solve.level_inliers[level];
    keyframe.first_residual[level] = finest ? residual : solve.level_residual[level];
  }
  if (keyframeWornOut(keyframe, solve)) {
    const int tracked_against = keyframe.id;  // `keyframe` may leave the kept ones now
    addKeyframe(frame, features);
    if (rectified_at_rest) active_->unrectified = input;
    backend_current_id_ = active_->id;
    active_from_last_ = Eigen::Isometry3d::Identity();
    result.new_keyframe = true;
    if (window_) {
      result.timings.solve_ms += lapMilliseconds(&clock);
      startWindow(tracked_against, solve, &result);
      result.timings.window_ms += lapMilliseconds(&clock);
    } else if (solve.quality.finest_level > 0 && config_.keep_pace_refines_keyframes && !window_failed_) {
      result.timings.solve_ms += lapMilliseconds(&clock);
      refineCoarseLink(tracked_against, solve, &result);
      result.timings.window_ms += lapMilliseconds(&clock);
    }
  }
  if (gravity_ && accelerometer) {
    // Roll and pitch toward gravity's level: the keyframe turns with the estimate, so frames tracked
    // against it keep the correction.
    std::string why_not;
    const Eigen::Isometry3d correction = gravity_->correct(input.stamp, pose_, *accelerometer, since_last, &why_not);
    if (gravity_->started() && why_not.empty()) result.gravity_error_deg = gravity_->lastError() * 180.0 / M_PI;
    active_->pose = correction * active_->pose;
    pose_ = correction * pose_;
  }
  publish(&result);
  result.timings.solve_ms += lapMilliseconds(&clock);
  return result;
}

}  // namespace vocal
