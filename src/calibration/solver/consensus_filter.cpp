#include "vocal/calibration/solver/consensus_filter.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "vocal/calibration/solver/pairwise_initialization.h"
#include "vocal/core/errors.h"

namespace vocal {

namespace {
// The shared poses whose centre keeps its distance to at least half of the other poses' centres from
// one sensor to the other (distances are what a rigid transform keeps).
std::vector<int> posesKeepingCentreDistances(const std::map<int, Eigen::Vector3d>& in_a, const std::map<int, Eigen::Vector3d>& in_b,
                                             const std::vector<int>& shared, double tolerance) {
  std::vector<int> kept;
  for (int k : shared) {
    int agreeing = 0;
    for (int l : shared) {
      if (l == k) continue;
      const double difference = (in_a.at(k) - in_a.at(l)).norm() - (in_b.at(k) - in_b.at(l)).norm();
      agreeing += std::abs(difference) < tolerance;
    }
    if (2 * agreeing >= static_cast<int>(shared.size()) - 1) kept.push_back(k);
  }
  return kept;
}
}  // namespace

std::set<std::pair<int, int>> rejectInconsistentObservations(const std::vector<std::map<int, Plane>>& planes,
                                                            const ConsensusOptions& options,
                                                            const std::vector<std::map<int, Eigen::Vector3d>>* centres) {
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
      bool centres_known = centres != nullptr;
      for (int k : shared) centres_known = centres_known && (*centres)[a].count(k) && (*centres)[b].count(k);
      if (best.size() < 3 && centres_known) {
        best = posesKeepingCentreDistances((*centres)[a], (*centres)[b], shared, options.max_centre_difference);
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
