#include "vocal/odometry/resolution_governor.h"

#include <algorithm>

namespace vocal {
namespace {
// Weight of a new frame's time in its level's running mean: a load that comes shows within a few frames,
// one slow frame (a keyframe's features, a fallback's second solve) does not move it over the budget.
constexpr double kTimeWeight = 0.2;
// Weight of a new spacing in the period's running mean: arrivals jitter by a few milliseconds.
constexpr double kPeriodWeight = 0.1;
// A coarser level tries the finer one when its own frames take less than this share of the budget:
// the finer level costs 1.5-2x (the finest level's passes are four times a coarser one's; the
// preprocessing is the same), so less room would only fail the try.
constexpr double kRoomForFiner = 0.6;
// Frames a try at the finer level must hold within the budget before it counts as back for good.
constexpr int kProbeHoldFrames = 10;
}  // namespace

ResolutionGovernor::ResolutionGovernor(int coarsest, double budget_share)
    : coarsest_(std::max(0, coarsest)),
      budget_share_(budget_share),
      // The first frames are the slowest (the first pair's features, buffers allocated, caches cold): a
      // stream starts coarse and tries the input's resolution once the first wait is over.
      level_(coarsest_),
      seconds_(coarsest_ + 1, 0.0),
      frames_(coarsest_ + 1, 0) {}

void ResolutionGovernor::reset() {
  *this = ResolutionGovernor(coarsest_, budget_share_);
}

void ResolutionGovernor::sawFrame(double arrived, std::size_t frames_received) {
  if (last_received_ > 0 && frames_received > last_received_ && arrived > last_arrival_) {
    const double spacing = (arrived - last_arrival_) / static_cast<double>(frames_received - last_received_);
    period_ = period_ > 0.0 ? (1.0 - kPeriodWeight) * period_ + kPeriodWeight * spacing : spacing;
  }
  last_arrival_ = arrived;
  last_received_ = frames_received;
}

void ResolutionGovernor::tracked(int level, double seconds, double arrived, std::size_t frames_received) {
  sawFrame(arrived, frames_received);
  if (level < 0 || level > coarsest_) return;
  ++frames_[level];
  const bool trying = probing_ && level == level_;
  if (trying && frames_since_change_ == 0) {
    // A try's first frame builds the reference again at the finer level: it says nothing of the pace.
    ++frames_since_change_;
    return;
  }
  double& mean = seconds_[level];
  // A try's first timed frame replaces what was known of its level: that was measured under another load.
  const bool first_timed = trying && frames_since_change_ == 1;
  mean = mean > 0.0 && !first_timed ? (1.0 - kTimeWeight) * mean + kTimeWeight * seconds : seconds;
  ++frames_since_change_;
  if (period_ <= 0.0 || coarsest_ == 0) return;

  const double budget = this->budget();
  if (level_ < coarsest_ && seconds_[level_] > budget) {
    // Falling behind here: coarser from the next frame (a failed try waits twice as long next time).
    if (probing_) probe_wait_ = std::min(2 * probe_wait_, kMaxProbeWaitFrames);
    probing_ = false;
    ++level_;
    frames_since_change_ = 0;
    return;
  }
  if (probing_ && frames_since_change_ >= kProbeHoldFrames) {
    probing_ = false;  // the finer level holds: the load has gone
    probe_wait_ = kFirstProbeWaitFrames;
  }
  if (level_ > 0 && !probing_ && frames_since_change_ >= probe_wait_ && seconds_[level_] < kRoomForFiner * budget) {
    --level_;
    probing_ = true;
    frames_since_change_ = 0;
  }
}

}  // namespace vocal
