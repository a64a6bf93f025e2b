#include "vocal/core/stamp_association.h"

#include <algorithm>
#include <cmath>
#include <tuple>

namespace vocal {

std::vector<StampMatch> associateStamps(const std::vector<double>& first, const std::vector<double>& second,
                                        double max_difference, double offset) {
  // Candidates within the window, found with a sliding lower bound since both lists are sorted.
  struct Candidate {
    double difference;
    std::size_t first, second;
  };
  std::vector<Candidate> candidates;
  std::size_t window_start = 0;
  for (std::size_t i = 0; i < first.size(); ++i) {
    while (window_start < second.size() && second[window_start] + offset <= first[i] - max_difference) {
      ++window_start;
    }
    for (std::size_t j = window_start; j < second.size() && second[j] + offset < first[i] + max_difference; ++j) {
      const double difference = std::abs(first[i] - (second[j] + offset));
      if (difference < max_difference) {
        candidates.push_back({difference, i, j});
      }
    }
  }
  // Ties are broken by index so the result does not depend on the sort's stability.
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
    return std::tie(a.difference, a.first, a.second) < std::tie(b.difference, b.first, b.second);
  });
  std::vector<bool> first_used(first.size(), false);
  std::vector<bool> second_used(second.size(), false);
  std::vector<StampMatch> matches;
  for (const Candidate& c : candidates) {
    if (!first_used[c.first] && !second_used[c.second]) {
      first_used[c.first] = second_used[c.second] = true;
      matches.push_back({c.first, c.second});
    }
  }
  std::sort(matches.begin(), matches.end(),
            [](const StampMatch& a, const StampMatch& b) { return a.first < b.first; });
  return matches;
}

std::size_t closestStampIndex(const std::vector<double>& sorted_stamps, double stamp) {
  const auto upper = std::lower_bound(sorted_stamps.begin(), sorted_stamps.end(), stamp);
  if (upper == sorted_stamps.begin()) {
    return 0;
  }
  if (upper == sorted_stamps.end()) {
    return sorted_stamps.size() - 1;
  }
  const auto lower = upper - 1;
  return static_cast<std::size_t>((stamp - *lower <= *upper - stamp ? lower : upper) - sorted_stamps.begin());
}

}  // namespace vocal
