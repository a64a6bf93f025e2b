#include "vocal/calibration/solver/intrinsics_refinement.h"

#include <utility>
#include <vector>

#include <ceres/ceres.h>
#include <ceres/manifold.h>

#include "vocal/core/se3.h"

namespace vocal {

PlaneMeasurement movedByIntrinsics(const PlaneMeasurement& view, const Eigen::Vector4d& dk) {
  PlaneMeasurement moved = view;
  const Eigen::Matrix<double, 6, 1> change = view.pose_per_intrinsics * dk;
  moved.sensor_from_pattern.linear() = view.sensor_from_pattern.linear() * so3Exp(change.head<3>());
  moved.sensor_from_pattern.translation() += change.tail<3>();
  return moved;
}

void addIntrinsicsPrior(ceres::Problem* problem, double* intrinsics, const IntrinsicsRefinementOptions& options) {
  const Eigen::Vector4d sigma(options.focal_sigma, options.focal_sigma, options.centre_sigma, options.centre_sigma);
  problem->AddResidualBlock(new ceres::AutoDiffCostFunction<IntrinsicsPrior, 4, 4>(new IntrinsicsPrior{sigma}), nullptr, intrinsics);
  if (!options.principal_point) problem->SetManifold(intrinsics, new ceres::SubsetManifold(4, {2, 3}));
}

void addIntrinsicsEvidence(ceres::Problem* problem, const PlaneMeasurement& view, double* intrinsics) {
  if (view.evidence_matrix.isZero()) return;
  problem->AddResidualBlock(new ceres::AutoDiffCostFunction<IntrinsicsEvidenceResidual, 4, 4>(
                                new IntrinsicsEvidenceResidual{view.evidence_matrix, view.evidence_offset}),
                            nullptr, intrinsics);
}

Eigen::Vector4d intrinsicsSigma(ceres::Problem* problem, double* intrinsics, const Eigen::Vector4d& given) {
  if (!problem->HasParameterBlock(intrinsics)) return Eigen::Vector4d::Zero();
  ceres::Covariance covariance{ceres::Covariance::Options{}};
  const std::vector<std::pair<const double*, const double*>> blocks = {{intrinsics, intrinsics}};
  if (!covariance.Compute(blocks, problem)) return Eigen::Vector4d::Zero();
  Eigen::Matrix4d relative;
  covariance.GetCovarianceBlock(intrinsics, intrinsics, relative.data());
  const Eigen::Vector4d scale(given[0], given[1], given[0], given[1]);
  return relative.diagonal().cwiseMax(0.0).cwiseSqrt().cwiseProduct(scale);
}

}  // namespace vocal
