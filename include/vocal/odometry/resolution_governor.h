#pragma once
// Chooses how finely a live stream's frames are tracked (IcpDvoOdometry::setFinestLevel: a pyramid level
// and its row step), so that tracking keeps pace with the camera on a CPU shared with other work.
//
// Why not only skip frames: a skipped frame doubles the next one's motion, and the dense solve across
// it needs several times the passes (the coarse levels stop at their caps before a two- or three-frame
// motion has converged, the finest level does the rest): skipping makes the next frame slower still.
// One level up tracks every frame at a quarter of the pixels; before it, the input's resolution from
// every other row (keep_pace_row_step) costs a fifth less a frame and nearly none of its accuracy.
//
// The governor chooses among resolutions indexed finest first (keepPaceResolutions lists them), each
// costing more than the next. How: a stream starts at `start` (the row step's where there is one: as
// accurate as every row, and cheaper through the first frames, which are the slowest: the first pair's
// features, buffers allocated; kStartFramesNotTimed are not timed) and tries the next finer one once
// kStartProbeWaitFrames have passed and its running time has room. Each resolution's wall time per
// frame is followed (a running mean of the frames tracked there); while it exceeds the budget (a share of
// the stream's period, measured from the frames' arrivals) the next frames go one coarser. A coarser
// resolution with room to spare tries the finer one after a wait (kFirstProbeWaitFrames; the load may
// have gone), a wait that doubles each time a try fails (up to kMaxProbeWaitFrames).
#include <cstddef>
#include <vector>

namespace vocal {

// A way to track a frame: its finest pyramid level and the step between the rows taken there.
struct TrackingResolution {
  int level = 0;
  int row_step = 1;
};

// A live stream's resolutions, finest first: the input's every row, then (row_step > 1) one row in
// row_step of it, then pyramid levels 1 to min(max_level, levels - 1).
std::vector<TrackingResolution> keepPaceResolutions(int levels, int max_level, int row_step);

class ResolutionGovernor {
 public:
  // `coarsest`: the index of the coarsest resolution it may choose (0: always the finest, the input's).
  // `start`: the one a stream starts at (-1: the coarsest). `budget_share`: the share of the stream's
  // period a frame may take.
  explicit ResolutionGovernor(int coarsest = 1, int start = -1, double budget_share = kDefaultBudgetShare);

  // The resolution (index, finest first) to track the next frame at.
  int resolution() const { return resolution_; }
  // A frame taken from the stream: when it arrived (a steady clock, seconds; not its stamp: a bag played
  // at twice the rate brings frames twice as often) and how many frames the stream had delivered by then
  // (skipped ones included); the period is the arrivals' spacing per frame delivered. tracked() calls it;
  // alone for a frame whose time says nothing of the resolution (the first, which builds the estimator).
  void sawFrame(double arrived, std::size_t frames_received);
  // After a frame: the resolution it was tracked at, the wall time tracking it took, when it arrived and
  // how many frames the stream had delivered by then.
  void tracked(int resolution, double seconds, double arrived, std::size_t frames_received);
  // Forgets the stream (a restart): its period and the resolutions' times.
  void reset();

  // The stream's period (seconds; 0 until two frames were seen), and each resolution's running time per
  // frame (seconds; 0 where none was tracked yet).
  double period() const { return period_; }
  // Seconds a frame may take: the budget share of the period (0 until the period is known).
  double budget() const { return budget_share_ * period_; }
  double secondsAt(int resolution) const {
    return resolution >= 0 && resolution < static_cast<int>(seconds_.size()) ? seconds_[resolution] : 0.0;
  }
  // Frames tracked at each resolution so far (index: resolution).
  const std::vector<std::size_t>& framesAt() const { return frames_; }

  static constexpr double kDefaultBudgetShare = 0.9;
  static constexpr int kFirstProbeWaitFrames = 30;
  // The first try, at a stream's start: its slow frames are 3-5 (100-130 ms each, VM-2A), and the
  // running time must have come down into the room for the finer resolution besides.
  static constexpr int kStartProbeWaitFrames = 10;
  // A stream's first frames tracked: counted, not timed (their time is the start's, not the pace's).
  static constexpr int kStartFramesNotTimed = 5;
  static constexpr int kMaxProbeWaitFrames = 480;

 private:
  int coarsest_ = 1;
  int start_ = 1;
  double budget_share_ = kDefaultBudgetShare;
  int resolution_ = 0;
  std::vector<double> seconds_;
  std::vector<std::size_t> frames_;
  double period_ = 0.0;
  double last_arrival_ = 0.0;
  std::size_t last_received_ = 0;
  bool probing_ = false;         // the last change was a try at a finer resolution
  int probe_wait_ = kStartProbeWaitFrames;
  int frames_since_change_ = 0;
  std::size_t frames_tracked_ = 0;  // since the start
};

}  // namespace vocal
