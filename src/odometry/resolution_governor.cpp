#include "vocal/odometry/resolution_governor.h"

#include <algorithm>

namespace vocal {
namespace {
// Weight of a new frame's time in its resolution's running mean: a load that comes shows within a few frames,
// one slow frame (a keyframe's features, a fallback's second solve) does not move it over the budget.
constexpr double kTimeWeight = 0.2;
// Weight of a new spacing in the period's running mean: arrivals jitter by a few milliseconds.
constexpr double kPeriodWeight = 0.1;
// A coarser resolution tries the finer one when its own frames take less than this share of the budget:
// a finer level costs 1.5-2x (the finest level's passes are four times a coarser one's; the
// preprocessing is the same), every row 1.2x every other one, so less room would only fail the try.
constexpr double kRoomForFiner = 0.6;
// Frames a try at the finer resolution must hold within the budget before it counts as back for good.
constexpr int kProbeHoldFrames = 10;
}  // namespace

std::vector<TrackingResolution> keepPaceResolutions(int levels, int max_level, int row_step) {
  std::vector<TrackingResolution> resolutions{{0, 1}};
  if (row_step > 1) resolutions.push_back({0, row_step});
  for (int level = 1; level <= std::min(max_level, levels - 1); ++level) resolutions.push_back({level, 1});
  return resolutions;
}

ResolutionGovernor::ResolutionGovernor(int coarsest, int start, double budget_share)
    : coarsest_(std::max(0, coarsest)),
      start_(start < 0 ? coarsest_ : std::min(start, coarsest_)),
      budget_share_(budget_share),
      // The first frames are the slowest (the first pair's features, buffers allocated, caches cold): a
      // stream starts at `start` and tries finer once the start's wait is over.
      resolution_(start_),
      seconds_(coarsest_ + 1, 0.0),
      frames_(coarsest_ + 1, 0) {}

void ResolutionGovernor::reset() {
  *this = ResolutionGovernor(coarsest_, start_, budget_share_);
}

void ResolutionGovernor::sawFrame(double arrived, std::size_t frames_received) {
  if (last_received_ > 0 && frames_received > last_received_ && arrived > last_arrival_) {
    const double spacing = (arrived - last_arrival_) / static_cast<double>(frames_received - last_received_);
    period_ = period_ > 0.0 ? (1.0 - kPeriodWeight) * period_ + kPeriodWeight * spacing : spacing;
  }
  last_arrival_ = arrived;
  last_received_ = frames_received;
}

void ResolutionGovernor::tracked(int resolution, double seconds, double arrived, std::size_t frames_received) {
  sawFrame(arrived, frames_received);
  if (resolution < 0 || resolution > coarsest_) return;
  ++frames_[resolution];
  if (++frames_tracked_ <= static_cast<std::size_t>(kStartFramesNotTimed)) {
    ++frames_since_change_;
    return;
  }
  const bool trying = probing_ && resolution == resolution_;
  if (trying && frames_since_change_ == 0) {
    // A try's first frame may build the reference again at a finer level: it says nothing of the pace.
    ++frames_since_change_;
    return;
  }
  double& mean = seconds_[resolution];
  // A try's first timed frame replaces what was known of its resolution: that was measured under another load.
  const bool first_timed = trying && frames_since_change_ == 1;
  mean = mean > 0.0 && !first_timed ? (1.0 - kTimeWeight) * mean + kTimeWeight * seconds : seconds;
  ++frames_since_change_;
  if (period_ <= 0.0 || coarsest_ == 0) return;

  const double budget = this->budget();
  if (resolution_ < coarsest_ && seconds_[resolution_] > budget) {
    // Falling behind here: coarser from the next frame (a failed try waits twice as long next time).
    if (probing_) probe_wait_ = std::min(std::max(2 * probe_wait_, kFirstProbeWaitFrames), kMaxProbeWaitFrames);
    probing_ = false;
    ++resolution_;
    frames_since_change_ = 0;
    return;
  }
  if (probing_ && frames_since_change_ >= kProbeHoldFrames) {
    probing_ = false;  // the finer resolution holds: the load has gone
    probe_wait_ = kFirstProbeWaitFrames;
  }
  if (resolution_ > 0 && !probing_ && frames_since_change_ >= probe_wait_ && seconds_[resolution_] < kRoomForFiner * budget) {
    --resolution_;
    probing_ = true;
    frames_since_change_ = 0;
  }
}

}  // namespace vocal
