#include "vocal/calibration/solver/link_from_joints_cost.h"

#include <ceres/ceres.h>

#include "vocal/calibration/solver/link_from_joints_residual.h"

namespace vocal {

ceres::CostFunction* linkFromJointsCost(const std::vector<JointDescription>* joints, const std::vector<int>& chain,
                                        const std::vector<double>& readings, bool mounted) {
  auto* cost = new ceres::DynamicAutoDiffCostFunction<LinkFromJointsResidual, 4>(new LinkFromJointsResidual{joints, chain, readings, mounted});
  for (int i = 0; i < (mounted ? 2 : 1); ++i) cost->AddParameterBlock(4), cost->AddParameterBlock(3);
  for (std::size_t i = 0; i < 2 * chain.size(); ++i) cost->AddParameterBlock(1);
  for (const int j : chain)
    if ((*joints)[j].free_origin) cost->AddParameterBlock(6);
  cost->SetNumResiduals(6);
  return cost;
}

}  // namespace vocal
