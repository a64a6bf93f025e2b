#pragma once
// The TUM RGB-D benchmark's metrics: ATE (RMSE of positions after a rigid alignment, Horn's method) and
// RPE (error of relative motion over a fixed time delta).

#include <vector>

#include <Eigen/Geometry>

#include "vocal/core/tum_trajectory.h"

namespace vocal {

// Rigid transform T minimising sum |T * model_i - data_i|^2 (rotation + translation, no scale).
// Throws InputError for fewer than 3 points or lists of different lengths.
Eigen::Isometry3d alignRigid(const std::vector<Eigen::Vector3d>& model, const std::vector<Eigen::Vector3d>& data);

struct AteResult {
  std::size_t pairs = 0;
  double rmse = 0.0, mean = 0.0, median = 0.0, max = 0.0;  // metres
  Eigen::Isometry3d alignment = Eigen::Isometry3d::Identity();  // maps the estimate onto ground truth
  std::vector<double> stamps;                      // estimate stamps of the associated pairs
  std::vector<Eigen::Vector3d> ground_truth;       // associated positions
  std::vector<Eigen::Vector3d> aligned_estimate;   // aligned positions
  std::vector<double> errors;                      // per pair, metres
};

// Associates by stamp (TUM rule, max_difference seconds). Throws InputError when fewer than 3 pairs
// associate.
AteResult computeAte(const Trajectory& ground_truth, const Trajectory& estimate, double max_difference = 0.02);

struct RpeResult {
  std::size_t pairs = 0;
  double delta = 1.0;                 // seconds
  double translation_rmse_m_per_s = 0.0;
  double rotation_rmse_deg_per_s = 0.0;
};

// For each estimate pose i, the pose j closest to stamp_i + delta and the ground-truth poses nearest
// to both (within max_difference) give one relative error; pairs whose interval misses delta by more
// than max_difference (the end of the sequence) are skipped. Throws InputError when no pair is left.
RpeResult computeRpe(const Trajectory& ground_truth, const Trajectory& estimate, double delta = 1.0,
                     double max_difference = 0.02);

}  // namespace vocal
