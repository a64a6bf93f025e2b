#include "vocal/odometry/icp_dvo_odometry.h"

#include <chrono>
#include <cmath>
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
}  // namespace

IcpDvoOdometry::IcpDvoOdometry(const PinholeCamera& camera, const OdometryConfig& config,
                               std::unique_ptr<OdometryBackend> backend)
    : camera_(camera), config_(config), backend_(std::move(backend)) {
  camera_.validate("odometry camera");
  config_.validate();
  if ((camera_.width >> (config_.levels - 1)) < 8 || (camera_.height >> (config_.levels - 1)) < 8) {
    throw InputError("odometry config: " + std::to_string(config_.levels) + " pyramid levels leave less than 8x8 pixels of a " +
                     std::to_string(camera_.width) + "x" + std::to_string(camera_.height) + " image");
  }
  if (!backend_) backend_ = makeOdometryBackend(camera_, config_);
}

void IcpDvoOdometry::reset(const Eigen::Isometry3d& pose) {
  has_reference_ = false;
  residual_level_ = 0.0;
  pose_ = pose;
  pose_covariance_.setZero();
}

double IcpDvoOdometry::residualLevelOf(const OdometryQuality& quality) const {
  return config_.mode == OdometryMode::kIcp ? quality.icp_rmse : quality.rgb_rmse;
}

IcpDvoOdometry::DenseSolve IcpDvoOdometry::solveFrom(const Eigen::Isometry3d& start) {
  const bool use_icp = config_.mode != OdometryMode::kRgb;
  const bool use_rgb = config_.mode != OdometryMode::kIcp;
  DenseSolve solve;
  Eigen::Isometry3d& T = solve.increment;
  T = start;
  double rgb_sigma = std::numeric_limits<double>::infinity();  // no robust weighting until measured
  NormalEquations last_icp, last_rgb;
  double last_count = 0.0;
  int steps = 0;
  for (int level = config_.levels - 1; level >= 0; --level) {
    for (int iteration = 0; iteration < config_.iterations[level]; ++iteration) {
      NormalEquations icp, rgb;
      backend_->trackingSystems(level, T, config_.rgb_huber_factor * rgb_sigma, use_icp ? &icp : nullptr,
                                use_rgb ? &rgb : nullptr);
      if (rgb.count > 0) rgb_sigma = rgb.rmse();
      // Each term is scaled by the inverse variance of its residuals (the fused system is then the
      // information of both); rgb_weight scales the photometric term on top.
      const double icp_scale = use_icp && icp.count > 0 ? 1.0 / std::max(icp.squared_residual_sum / icp.count, kMinIcpVariance) : 0.0;
      const double rgb_scale = use_rgb && rgb.count > 0
                                   ? (use_icp ? config_.rgb_weight : 1.0) / std::max(rgb.squared_residual_sum / rgb.count, kMinRgbVariance)
                                   : 0.0;
      const Matrix6d A = icp_scale * icp.A + rgb_scale * rgb.A;
      const Vector6d b = icp_scale * icp.b + rgb_scale * rgb.b;
      last_icp = icp;
      last_rgb = rgb;
      solve.information = A;
      last_count = icp.count + rgb.count;
      if (last_count < 6) break;  // nothing to solve at this level
      const Vector6d x = A.ldlt().solve(b);
      if (!x.allFinite()) break;
      T = se3Exp(x) * T;
      ++steps;
      // Converged: further steps at this level would not move the estimate.
      if (x.head<3>().norm() < config_.convergence_translation && x.tail<3>().norm() < config_.convergence_rotation) break;
    }
  }

  OdometryQuality& q = solve.quality;
  q.icp_inliers = static_cast<int>(last_icp.count);
  q.rgb_inliers = static_cast<int>(last_rgb.count);
  q.icp_rmse = last_icp.rmse();
  q.rgb_rmse = last_rgb.rmse();
  q.iterations = steps;
  const Eigen::SelfAdjointEigenSolver<Matrix6d> eigen(solve.information, Eigen::EigenvaluesOnly);
  const double smallest = eigen.eigenvalues()[0], largest = eigen.eigenvalues()[5];
  q.condition = smallest > 0.0 ? largest / smallest : std::numeric_limits<double>::infinity();
  q.weakest_information = last_count > 0.0 ? smallest / last_count : 0.0;

  std::ostringstream failure;
  if (use_icp && q.icp_inliers < config_.min_icp_inliers) {
    failure << "too few ICP inliers (" << q.icp_inliers << " < " << config_.min_icp_inliers << ")";
  } else if (use_rgb && q.rgb_inliers < config_.min_rgb_inliers) {
    failure << "too few photometric inliers (" << q.rgb_inliers << " < " << config_.min_rgb_inliers << ")";
  } else if (!(q.condition <= config_.max_condition)) {
    failure << "the system is degenerate (condition " << q.condition << " > " << config_.max_condition
            << "): the scene does not constrain every degree of freedom";
  } else if (T.translation().norm() > config_.max_translation) {
    failure << "implausible jump of " << T.translation().norm() << " m (> " << config_.max_translation << " m)";
  } else if (rotationAngle(T) * 180.0 / M_PI > config_.max_rotation_deg) {
    failure << "implausible rotation of " << rotationAngle(T) * 180.0 / M_PI << " deg (> " << config_.max_rotation_deg
            << " deg)";
  }
  solve.failure = failure.str();
  return solve;
}

bool IcpDvoOdometry::suspicious(const DenseSolve& solve) const {
  // Without a running level (the first pair) a wrong minimum cannot be told apart: ask the features.
  if (!solve.failure.empty() || residual_level_ <= 0.0) return true;
  return residualLevelOf(solve.quality) > config_.feature_fallback_residual_ratio * residual_level_;
}

OdometryResult IcpDvoOdometry::track(const RgbdFrame& frame) {
  frame.validate("odometry frame");
  if (!frame.color.sameSize(camera_.width, camera_.height)) {
    std::ostringstream message;
    message << "odometry frame: images are " << frame.color.width() << "x" << frame.color.height()
            << " but the camera is " << camera_.width << "x" << camera_.height;
    throw InputError(message.str());
  }
  auto clock = std::chrono::steady_clock::now();
  backend_->pushFrame(frame);
  OdometryResult result;
  result.timings.preprocess_ms = lapMilliseconds(&clock);
  result.pose = pose_;
  result.pose_covariance = pose_covariance_;
  const FeatureInitialisation features_mode = config_.feature_initialisation;
  // Each frame's features are extracted at most once: matched as the current frame, then as the
  // reference. In fallback mode only when asked for, so the frame is kept until then.
  std::shared_ptr<const FrameFeatures> features;
  if (features_mode == FeatureInitialisation::kAlways) features = extractFrameFeatures(frame, camera_);
  auto keepAsReference = [&] {
    reference_features_ = features;
    if (features_mode == FeatureInitialisation::kFallback) reference_frame_ = frame;
  };
  if (!has_reference_) {
    result.timings.features_ms = lapMilliseconds(&clock);
    has_reference_ = true;
    keepAsReference();
    velocity_ = Eigen::Isometry3d::Identity();
    result.first_frame = true;
    result.quality.trusted = true;
    return result;
  }

  // The motion the features agree on (extracting those not extracted yet); none when they do not agree.
  auto featureStart = [&](OdometryResult* into) -> std::optional<Eigen::Isometry3d> {
    if (!reference_features_) reference_features_ = extractFrameFeatures(reference_frame_, camera_);
    if (!features) features = extractFrameFeatures(frame, camera_);
    const FeatureAlignment alignment = alignFrameFeatures(*reference_features_, *features, camera_);
    if (!alignment.found) return std::nullopt;
    into->quality.feature_inliers = alignment.inliers;
    return alignment.reference_from_current;
  };

  DenseSolve solve;
  if (features_mode == FeatureInitialisation::kAlways) {
    const std::optional<Eigen::Isometry3d> start = featureStart(&result);
    result.timings.features_ms = lapMilliseconds(&clock);
    solve = solveFrom(start.value_or(Eigen::Isometry3d::Identity()));
  } else if (features_mode == FeatureInitialisation::kOff) {
    solve = solveFrom(Eigen::Isometry3d::Identity());
  } else {
    solve = solveFrom(velocity_);
    if (suspicious(solve)) {
      result.quality.feature_fallback = true;
      result.timings.solve_ms = lapMilliseconds(&clock);
      const std::optional<Eigen::Isometry3d> start = featureStart(&result);
      result.timings.features_ms = lapMilliseconds(&clock);
      bool retry_won = false;
      if (start) {
        DenseSolve retry = solveFrom(*start);
        // The retry wins when it passes and the first did not, or both pass and it fits better.
        retry_won = retry.failure.empty() &&
                    (!solve.failure.empty() || residualLevelOf(retry.quality) < residualLevelOf(solve.quality));
        if (retry_won) solve = std::move(retry);
      }
      if (!retry_won) result.quality.feature_inliers = 0;  // the result did not start from the features
    }
  }
  keepAsReference();
  const OdometryQuality fallback_flags = result.quality;
  result.quality = solve.quality;
  result.quality.feature_inliers = fallback_flags.feature_inliers;
  result.quality.feature_fallback = fallback_flags.feature_fallback;
  result.failure = solve.failure;
  result.timings.solve_ms += lapMilliseconds(&clock);
  if (!result.failure.empty()) {
    velocity_ = Eigen::Isometry3d::Identity();
    return result;  // increment stays identity, the pose is not moved
  }
  const Eigen::Isometry3d& T = solve.increment;
  // The running residual level a wrong minimum stands out from (an average over about ten frames).
  const double residual = residualLevelOf(solve.quality);
  residual_level_ = residual_level_ > 0.0 ? 0.9 * residual_level_ + 0.1 * residual : residual;
  velocity_ = T;
  result.quality.trusted = true;
  result.increment = T;
  result.covariance = solve.information.inverse();
  // pose_k = pose_{k-1} T: the increment's left perturbation moves into the odometry frame through
  // pose_{k-1}'s adjoint, independent of the errors so far.
  const Matrix6d to_odometry = adjoint(pose_);
  pose_covariance_ += to_odometry * result.covariance * to_odometry.transpose();
  pose_ = pose_ * T;
  result.pose = pose_;
  result.pose_covariance = pose_covariance_;
  return result;
}

}  // namespace vocal
