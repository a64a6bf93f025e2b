#pragma once
// Association of two stamp lists by the TUM benchmark's rule (associate.py): every pair closer than
// max_difference is a candidate; candidates are taken greedily from the closest, each stamp used at
// most once; the result is sorted by the first list.

#include <cstddef>
#include <vector>

namespace vocal {

struct StampMatch {
  std::size_t first = 0;   // index into the first list
  std::size_t second = 0;  // index into the second list
};

// Both lists must be sorted ascending. `offset` is added to the second list's stamps.
std::vector<StampMatch> associateStamps(const std::vector<double>& first, const std::vector<double>& second,
                                        double max_difference, double offset = 0.0);

// Index of the stamp in the sorted list closest to `stamp` (the list must not be empty).
std::size_t closestStampIndex(const std::vector<double>& sorted_stamps, double stamp);

}  // namespace vocal
