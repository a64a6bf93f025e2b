#include "vocal/calibration/consensus_filter.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "vocal/calibration/pairwise_initialization.h"
#include "vocal/core/errors.h"

namespace vocal {

std::set<std::pair<int, int>> rejectInconsistentObservations(const std::vector<std::map<int, Plane>>& planes,
                                                            const ConsensusOptions& options) {
  std::mt19937 rng(options.seed);
  std::map<std::pair<int, int>, int> votes;
  const double min_cos = std::cos(options.max_angle);
  for (std::size_t a = 0; a < planes.size(); ++a) {
    for (std::size_t b = a + 1; b < planes.size(); ++b) {
      std::vector<int> shared;
      for (const auto& entry : planes[a])
        if (planes[b].count(entry.first)) shared.push_back(entry.first);
      if (static_cast<int>(shared.size()) < std::max(options.min_shared_poses, 3)) continue;
      auto agrees = [&](const Eigen::Isometry3d& a_from_b, int k) {
        const Plane predicted = transformPlane(a_from_b, planes[b].at(k));
        const Plane& seen = planes[a].at(k);
        return predicted.normal.dot(seen.normal) > min_cos && std::abs(predicted.offset - seen.offset) < options.max_offset;
      };
      std::vector<int> best;
      for (int iteration = 0; iteration < options.iterations; ++iteration) {
        std::vector<int> sample = shared;
        std::shuffle(sample.begin(), sample.end(), rng);
        sample.resize(3);
        std::vector<Plane> in_a, in_b;
        for (int k : sample) {
          in_a.push_back(planes[a].at(k));
          in_b.push_back(planes[b].at(k));
        }
        Eigen::Isometry3d a_from_b;
        try {
          a_from_b = alignPlanes(in_a, in_b, "consensus sample");
        } catch (const InputError&) {
          continue;  // near-parallel sample: no model
        }
        std::vector<int> inliers;
        for (int k : shared)
          if (agrees(a_from_b, k)) inliers.push_back(k);
        if (inliers.size() > best.size()) best = inliers;
      }
      if (best.size() < 3) continue;  // no consensus: this pair casts no votes
      for (int k : shared) {
        const int vote = std::binary_search(best.begin(), best.end(), k) ? 1 : -1;
        votes[{static_cast<int>(a), k}] += vote;
        votes[{static_cast<int>(b), k}] += vote;
      }
    }
  }
  std::set<std::pair<int, int>> rejected;
  for (const auto& entry : votes)
    if (entry.second < 0) rejected.insert(entry.first);
  return rejected;
}

}  // namespace vocal
