#include "vocal/calibration/solver/free_joint_origins.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <ceres/ceres.h>
#include <ceres/manifold.h>

#include "vocal/calibration/solver/joint_origin_prior.h"

namespace vocal {

namespace {
using Block = Eigen::Matrix<double, 6, 6, Eigen::RowMajor>;

// The covariance of each origin block in `problem` that is not held whole (zero for the others); none
// when it cannot be computed.
std::vector<Block> originCovariances(ceres::Problem* problem, std::vector<Vector6d>& origins, bool* computed) {
  std::vector<Block> covariances(origins.size(), Block::Zero());
  std::vector<std::pair<const double*, const double*>> blocks;
  const auto solved = [&](const Vector6d& origin) {
    return problem->HasParameterBlock(origin.data()) && !problem->IsParameterBlockConstant(origin.data());
  };
  for (const Vector6d& origin : origins)
    if (solved(origin)) blocks.emplace_back(origin.data(), origin.data());
  ceres::Covariance covariance(ceres::Covariance::Options{});
  *computed = !blocks.empty() && covariance.Compute(blocks, problem);
  for (std::size_t i = 0; i < origins.size() && *computed; ++i)
    if (solved(origins[i])) covariance.GetCovarianceBlock(origins[i].data(), origins[i].data(), covariances[i].data());
  return covariances;
}
}  // namespace

void addJointOriginPriors(ceres::Problem* problem, std::vector<Vector6d>& origins, const JointTolerances& tolerances) {
  for (Vector6d& origin : origins) {
    if (!problem->HasParameterBlock(origin.data())) continue;
    problem->AddResidualBlock(new ceres::AutoDiffCostFunction<JointOriginPrior, 6, 6>(
                                  new JointOriginPrior{tolerances.origin_rotation_sigma, tolerances.origin_translation_sigma}),
                              nullptr, origin.data());
  }
}

void holdOriginParts(ceres::Problem* problem, std::vector<Vector6d>* origins, const std::vector<std::vector<int>>& held) {
  for (std::size_t i = 0; i < origins->size() && i < held.size(); ++i) {
    double* origin = (*origins)[i].data();
    if (!problem->HasParameterBlock(origin) || held[i].empty()) continue;
    for (const int k : held[i]) origin[k] = 0.0;
    if (held[i].size() == 6) problem->SetParameterBlockConstant(origin);
    else problem->SetManifold(origin, new ceres::SubsetManifold(6, held[i]));
  }
}

bool holdUnfixedOriginParts(ceres::Problem* problem, std::vector<Vector6d>* origins, const JointTolerances& tolerances,
                            std::vector<std::vector<int>>* held) {
  held->resize(origins->size());
  bool computed = false;
  const std::vector<Block> covariances = originCovariances(problem, *origins, &computed);
  bool any = false;
  for (std::size_t i = 0; i < origins->size(); ++i) {
    if (!problem->HasParameterBlock((*origins)[i].data())) continue;
    any = true;
    for (int k = 0; k < 6 && computed; ++k) {
      const double prior = k < 3 ? tolerances.origin_rotation_sigma : tolerances.origin_translation_sigma;
      const bool already = std::find((*held)[i].begin(), (*held)[i].end(), k) != (*held)[i].end();
      if (!already && std::sqrt(std::max(covariances[i](k, k), 0.0)) >= tolerances.unfixed_origin_share * prior) (*held)[i].push_back(k);
    }
    std::sort((*held)[i].begin(), (*held)[i].end());
  }
  holdOriginParts(problem, origins, *held);
  return any;
}

void setFreeOriginResults(ceres::Problem* problem, std::vector<Vector6d>& origins, const std::vector<std::vector<int>>& held,
                          const std::vector<JointDescription>& joints, const JointTolerances& tolerances, std::vector<JointCalibration>* results) {
  bool computed = false;
  const std::vector<Block> covariances = originCovariances(problem, origins, &computed);
  for (std::size_t i = 0; i < origins.size(); ++i) {
    if (!problem->HasParameterBlock(origins[i].data())) continue;
    describeFreeOrigin(joints[i], origins[i], covariances[i].diagonal().cwiseMax(0.0).cwiseSqrt(), i < held.size() ? held[i] : std::vector<int>{},
                       tolerances, &(*results)[i]);
  }
}

}  // namespace vocal
