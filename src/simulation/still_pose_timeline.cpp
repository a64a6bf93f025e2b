#include "vocal/simulation/still_pose_timeline.h"

#include <algorithm>
#include <cmath>

namespace vocal {

std::vector<double> valuesAtTime(const std::vector<std::vector<double>>& per_pose, double time, double still, double moving) {
  const int poses = static_cast<int>(per_pose.size());
  const int k = std::max(0, std::min(poses - 1, static_cast<int>(time / (still + moving))));
  const double into = time - k * (still + moving);
  if (k == poses - 1 || into <= still) return per_pose[k];
  const double alpha = 0.5 - 0.5 * std::cos(M_PI * std::min(1.0, (into - still) / moving));
  std::vector<double> blended(per_pose[k].size());
  for (std::size_t j = 0; j < blended.size(); ++j) blended[j] = (1.0 - alpha) * per_pose[k][j] + alpha * per_pose[k + 1][j];
  return blended;
}

}  // namespace vocal
