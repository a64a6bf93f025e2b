#pragma once
// The timeline of a simulated session: still pose k held for `still` seconds from k * (still + moving),
// then a smooth move (a cosine blend: no jerk at either end) to pose k + 1; the last pose stays.

#include <vector>

namespace vocal {

// Per-pose values (a joint's angles, its readings) at `time` seconds into the session.
std::vector<double> valuesAtTime(const std::vector<std::vector<double>>& per_pose, double time, double still, double moving);

}  // namespace vocal
