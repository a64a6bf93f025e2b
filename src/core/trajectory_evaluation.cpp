#include "vocal/core/trajectory_evaluation.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <Eigen/Geometry>

#include "vocal/core/errors.h"
#include "vocal/core/se3.h"
#include "vocal/core/stamp_association.h"

namespace vocal {

Eigen::Isometry3d alignRigid(const std::vector<Eigen::Vector3d>& model, const std::vector<Eigen::Vector3d>& data) {
  if (model.size() != data.size() || model.size() < 3) {
    throw InputError("rigid alignment needs two lists of at least 3 matched points, got " +
                     std::to_string(model.size()) + " and " + std::to_string(data.size()));
  }
  // Horn's / Umeyama's closed form without scale, as the TUM benchmark's evaluate_ate.py.
  Eigen::Matrix3Xd from(3, model.size()), to(3, data.size());
  for (std::size_t i = 0; i < model.size(); ++i) {
    from.col(static_cast<Eigen::Index>(i)) = model[i];
    to.col(static_cast<Eigen::Index>(i)) = data[i];
  }
  return Eigen::Isometry3d(Eigen::umeyama(from, to, false));
}

AteResult computeAte(const Trajectory& ground_truth, const Trajectory& estimate, double max_difference) {
  const std::vector<StampMatch> matches =
      associateStamps(trajectoryStamps(estimate), trajectoryStamps(ground_truth), max_difference);
  if (matches.size() < 3) {
    throw InputError("ATE: only " + std::to_string(matches.size()) + " estimate poses have a ground-truth pose within " +
                     std::to_string(max_difference) + " s (need at least 3); do the stamps use the same clock?");
  }
  AteResult result;
  std::vector<Eigen::Vector3d> estimate_positions;
  for (const StampMatch& m : matches) {
    result.stamps.push_back(estimate[m.first].stamp);
    estimate_positions.push_back(estimate[m.first].pose.translation());
    result.ground_truth.push_back(ground_truth[m.second].pose.translation());
  }
  result.pairs = matches.size();
  result.alignment = alignRigid(estimate_positions, result.ground_truth);
  double squared_sum = 0.0;
  for (std::size_t i = 0; i < matches.size(); ++i) {
    result.aligned_estimate.push_back(result.alignment * estimate_positions[i]);
    const double error = (result.aligned_estimate.back() - result.ground_truth[i]).norm();
    result.errors.push_back(error);
    squared_sum += error * error;
  }
  result.rmse = std::sqrt(squared_sum / result.pairs);
  result.mean = std::accumulate(result.errors.begin(), result.errors.end(), 0.0) / result.pairs;
  result.max = *std::max_element(result.errors.begin(), result.errors.end());
  std::vector<double> sorted = result.errors;
  std::sort(sorted.begin(), sorted.end());
  const std::size_t mid = sorted.size() / 2;
  result.median = sorted.size() % 2 ? sorted[mid] : 0.5 * (sorted[mid - 1] + sorted[mid]);
  return result;
}

RpeResult computeRpe(const Trajectory& ground_truth, const Trajectory& estimate, double delta, double max_difference) {
  if (!(delta > 0.0)) {
    throw InputError("RPE: delta must be positive, got " + std::to_string(delta));
  }
  RpeResult result;
  result.delta = delta;
  if (ground_truth.empty() || estimate.empty()) {
    throw InputError("RPE: the ground truth or the estimate is empty");
  }
  const std::vector<double> estimate_stamps = trajectoryStamps(estimate);
  const std::vector<double> truth_stamps = trajectoryStamps(ground_truth);
  double translation_squared = 0.0, rotation_squared = 0.0;
  for (std::size_t i = 0; i < estimate.size(); ++i) {
    const std::size_t j = closestStampIndex(estimate_stamps, estimate_stamps[i] + delta);
    if (std::abs(estimate_stamps[j] - estimate_stamps[i] - delta) > max_difference) continue;
    const std::size_t gi = closestStampIndex(truth_stamps, estimate_stamps[i]);
    const std::size_t gj = closestStampIndex(truth_stamps, estimate_stamps[j]);
    if (std::abs(truth_stamps[gi] - estimate_stamps[i]) > max_difference ||
        std::abs(truth_stamps[gj] - estimate_stamps[j]) > max_difference) {
      continue;
    }
    const Eigen::Isometry3d estimate_motion = estimate[i].pose.inverse() * estimate[j].pose;
    const Eigen::Isometry3d true_motion = ground_truth[gi].pose.inverse() * ground_truth[gj].pose;
    const Eigen::Isometry3d error = true_motion.inverse() * estimate_motion;
    translation_squared += error.translation().squaredNorm();
    rotation_squared += std::pow(rotationAngle(error), 2);
    ++result.pairs;
  }
  if (result.pairs == 0) {
    throw InputError("RPE: no pose pair " + std::to_string(delta) +
                     " s apart has ground truth within " + std::to_string(max_difference) +
                     " s; the sequence may be shorter than delta");
  }
  result.translation_rmse_m_per_s = std::sqrt(translation_squared / result.pairs) / delta;
  result.rotation_rmse_deg_per_s = std::sqrt(rotation_squared / result.pairs) * 180.0 / M_PI / delta;
  return result;
}

}  // namespace vocal
