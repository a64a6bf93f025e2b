#pragma once
// Chooses the finest pyramid level a live stream's frames are tracked at (IcpDvoOdometry::
// setFinestLevel), so that tracking keeps pace with the camera on a CPU shared with other work.
//
// Why not only skip frames: a skipped frame doubles the next one's motion, and the dense solve across
// it needs several times the passes (the coarse levels stop at their caps before a two- or three-frame
// motion has converged, the finest level does the rest): skipping makes the next frame slower still.
// One level up tracks every frame at a quarter of the pixels.
//
// How: a stream starts at the coarsest level (its first frames are the slowest: the first pair's
// features, buffers allocated). Each level's wall time per frame is followed (a running mean of the
// frames tracked there); while it exceeds the budget (a share of the stream's period, measured from the
// frames' arrivals) the next frames go a level coarser. A coarser level with room to spare tries the finer
// one after a wait (kFirstProbeWaitFrames; the load may have gone), a wait that doubles each time a try
// fails (up to kMaxProbeWaitFrames).
#include <cstddef>
#include <vector>

namespace vocal {

class ResolutionGovernor {
 public:
  // `coarsest`: the coarsest level it may choose (0: always the input's resolution). `budget_share`: the
  // share of the stream's period a frame may take.
  explicit ResolutionGovernor(int coarsest = 1, double budget_share = kDefaultBudgetShare);

  // The level to track the next frame at.
  int level() const { return level_; }
  // A frame taken from the stream: when it arrived (a steady clock, seconds; not its stamp: a bag played
  // at twice the rate brings frames twice as often) and how many frames the stream had delivered by then
  // (skipped ones included); the period is the arrivals' spacing per frame delivered. tracked() calls it;
  // alone for a frame whose time says nothing of the level (the first, which builds the estimator).
  void sawFrame(double arrived, std::size_t frames_received);
  // After a frame: the level it was tracked at, the wall time tracking it took, when it arrived and how
  // many frames the stream had delivered by then.
  void tracked(int level, double seconds, double arrived, std::size_t frames_received);
  // Forgets the stream (a restart): its period and the levels' times.
  void reset();

  // The stream's period (seconds; 0 until two frames were seen), and each level's running time per
  // frame (seconds; 0 where none was tracked yet).
  double period() const { return period_; }
  // Seconds a frame may take: the budget share of the period (0 until the period is known).
  double budget() const { return budget_share_ * period_; }
  double secondsAt(int level) const { return level >= 0 && level < static_cast<int>(seconds_.size()) ? seconds_[level] : 0.0; }
  // Frames tracked at each level so far (index: level).
  const std::vector<std::size_t>& framesAt() const { return frames_; }

  static constexpr double kDefaultBudgetShare = 0.9;
  static constexpr int kFirstProbeWaitFrames = 30;
  static constexpr int kMaxProbeWaitFrames = 480;

 private:
  int coarsest_ = 1;
  double budget_share_ = kDefaultBudgetShare;
  int level_ = 0;
  std::vector<double> seconds_;
  std::vector<std::size_t> frames_;
  double period_ = 0.0;
  double last_arrival_ = 0.0;
  std::size_t last_received_ = 0;
  bool probing_ = false;         // the last level change was a try at a finer level
  int probe_wait_ = kFirstProbeWaitFrames;
  int frames_since_change_ = 0;
};

}  // namespace vocal
