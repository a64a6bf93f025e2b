// ResolutionGovernor: how finely a live stream is tracked (indices finest first; "level" below) follows the time its frames take
// against the stream's period.

#include <gtest/gtest.h>

#include <functional>

#include "vocal/odometry/resolution_governor.h"

namespace {
constexpr double kPeriod = 1.0 / 30.0;  // a 30 Hz camera: budget 0.9 * 33.3 = 30 ms

// Feeds `frames` frames, one per period, each taking `seconds(level)`; returns the levels chosen.
struct Stream {
  vocal::ResolutionGovernor governor;
  double arrived = 100.0;  // seconds, as a steady clock gives them
  std::size_t received = 0;
  std::vector<int> levels;
  explicit Stream(int coarsest, int start = -1) : governor(coarsest, start) {}
  void run(int frames, const std::function<double(int)>& seconds, int skipped_per_frame = 0) {
    for (int i = 0; i < frames; ++i) {
      received += 1 + skipped_per_frame;
      arrived += kPeriod * (1 + skipped_per_frame);
      const int level = governor.resolution();
      levels.push_back(level);
      governor.tracked(level, seconds(level), arrived, received);
    }
  }
};
}  // namespace

// A stream starts coarse (its first frames are the slowest), tries the input's resolution after the
// start's wait and stays there while its frames fit the budget.
TEST(ResolutionGovernor, FramesWithinTheBudgetComeToTheInputsResolutionAndStay) {
  Stream stream(1);
  stream.run(300, [](int level) { return level == 0 ? 0.020 : 0.010; });
  const int wait = vocal::ResolutionGovernor::kStartProbeWaitFrames;
  for (int i = 0; i < static_cast<int>(stream.levels.size()); ++i) EXPECT_EQ(stream.levels[i], i < wait ? 1 : 0) << "frame " << i;
  EXPECT_NEAR(stream.governor.period(), kPeriod, 1e-9);
  EXPECT_EQ(stream.governor.framesAt()[0], 300u - wait);
}

TEST(ResolutionGovernor, FramesOverTheBudgetGoOneLevelCoarserAndNoFurther) {
  Stream stream(1);
  // At the input's resolution frames take 40 ms (over 30): back to level 1 after the try's first timed
  // frame (its first rebuilds the reference, not timed).
  stream.run(40, [](int level) { return level == 0 ? 0.040 : 0.010; });
  const int tried = vocal::ResolutionGovernor::kStartProbeWaitFrames;  // frames 0-9 at level 1
  EXPECT_EQ(stream.levels[tried - 1], 1);
  EXPECT_EQ(stream.levels[tried], 0);
  EXPECT_EQ(stream.levels[tried + 1], 0);
  EXPECT_EQ(stream.levels[tried + 2], 1);
  // Level 1 takes 35 ms: still over, but there is no coarser level to go to, and no room to try level 0.
  stream.run(200, [](int level) { return level == 0 ? 0.040 : 0.035; });
  for (std::size_t i = tried + 2; i < stream.levels.size(); ++i) EXPECT_EQ(stream.levels[i], 1) << "frame " << i;
}

TEST(ResolutionGovernor, TheInputsResolutionIsTriedAgainOnceTheLoadHasGone) {
  Stream stream(1);
  stream.run(40, [](int level) { return level == 0 ? 0.020 : 0.010; });  // idle: at level 0 from frame 10
  EXPECT_EQ(stream.levels.back(), 0);
  stream.run(20, [](int level) { return level == 0 ? 0.045 : 0.022; });  // busy: level 1 fits, without room
  EXPECT_EQ(stream.levels.back(), 1);
  const std::size_t busy_end = stream.levels.size();
  stream.run(200, [](int level) { return level == 0 ? 0.018 : 0.009; });  // idle again
  // It tries once level 1 has waited its 30 frames and its mean has fallen below 0.6 of the budget.
  std::size_t back = 0;
  for (std::size_t i = busy_end; i < stream.levels.size() && !back; ++i) {
    if (stream.levels[i] == 0) back = i;
  }
  ASSERT_GT(back, 0u) << "never tried the input's resolution again";
  EXPECT_LE(back - busy_end, static_cast<std::size_t>(vocal::ResolutionGovernor::kFirstProbeWaitFrames + 5));
  for (std::size_t i = back; i < stream.levels.size(); ++i) EXPECT_EQ(stream.levels[i], 0) << "frame " << i;
}

TEST(ResolutionGovernor, AFailedTryWaitsTwiceAsLongBeforeTheNext) {
  Stream stream(1);
  // Level 1 has room (12 ms < 0.6 * 30) but level 0 does not fit (40 ms): each try lasts two frames (the
  // first rebuilds the reference and is not timed).
  stream.run(400, [](int level) { return level == 0 ? 0.040 : 0.012; });
  std::vector<std::size_t> tries;  // where each run of level-0 frames starts
  for (std::size_t i = 0; i < stream.levels.size(); ++i) {
    if (stream.levels[i] == 0 && (i == 0 || stream.levels[i - 1] == 1)) tries.push_back(i);
  }
  ASSERT_GE(tries.size(), 4u);
  // The gaps between tries: the start's wait (10 frames), then the first wait (30) after the first failed
  // try, doubling after each failed try since (60, 120 frames at level 1).
  const int first = vocal::ResolutionGovernor::kFirstProbeWaitFrames;
  EXPECT_EQ(tries[0], static_cast<std::size_t>(vocal::ResolutionGovernor::kStartProbeWaitFrames));
  EXPECT_EQ(tries[1] - tries[0], static_cast<std::size_t>(first + 2));
  EXPECT_EQ(tries[2] - tries[1], static_cast<std::size_t>(2 * first + 2));
  EXPECT_EQ(tries[3] - tries[2], static_cast<std::size_t>(4 * first + 2));
  // Nearly every frame stays at level 1: a try costs two frames.
  EXPECT_EQ(stream.governor.framesAt()[0], 2 * tries.size());
}

TEST(ResolutionGovernor, ThePeriodCountsTheFramesSkippedBetweenTrackedOnes) {
  Stream stream(1);
  // Every other frame skipped: tracked frames 66.7 ms apart, but the camera's period is 33.3 ms: 20 ms
  // has no room for level 0 (budget 30 ms; against 60 it would have).
  stream.run(100, [](int level) { return level == 0 ? 0.050 : 0.020; }, 1);
  EXPECT_NEAR(stream.governor.period(), kPeriod, 1e-9);
  for (const int level : stream.levels) EXPECT_EQ(level, 1);
}

// The first frame only builds the estimator (its time is not the level's) but gives the period a start:
// the first frame timed can already be judged.
TEST(ResolutionGovernor, AFrameOnlySeenGivesThePeriodAStart) {
  vocal::ResolutionGovernor governor(1);
  governor.sawFrame(100.0, 1);
  governor.tracked(1, 0.010, 100.0 + 2 * kPeriod, 3);  // one frame skipped meanwhile
  EXPECT_NEAR(governor.period(), kPeriod, 1e-9);
  EXPECT_EQ(governor.framesAt()[1], 1u);
  EXPECT_EQ(governor.framesAt()[0], 0u);
}

TEST(ResolutionGovernor, CoarsestZeroAlwaysTracksTheInputsResolution) {
  Stream stream(0);
  stream.run(100, [](int) { return 0.100; });
  for (const int level : stream.levels) EXPECT_EQ(level, 0);
}

TEST(ResolutionGovernor, ResetForgetsTheStream) {
  Stream stream(1);
  stream.run(40, [](int level) { return level == 0 ? 0.020 : 0.010; });
  EXPECT_EQ(stream.governor.resolution(), 0);
  stream.governor.reset();
  EXPECT_EQ(stream.governor.resolution(), 1);  // starting coarse again
  EXPECT_EQ(stream.governor.period(), 0.0);
  EXPECT_EQ(stream.governor.secondsAt(0), 0.0);
  EXPECT_EQ(stream.governor.framesAt()[0], 0u);
}

// The resolutions a live stream may be tracked at, finest first: every row, one row in keep_pace_row_step
// (where more than 1), then the pyramid levels up to keep_pace_max_level (no further than the pyramid).
TEST(KeepPaceResolutions, EveryRowThenTheRowStepThenTheCoarserLevels) {
  const auto listed = [](int levels, int max_level, int row_step) {
    std::vector<std::pair<int, int>> pairs;
    for (const vocal::TrackingResolution& r : vocal::keepPaceResolutions(levels, max_level, row_step)) pairs.emplace_back(r.level, r.row_step);
    return pairs;
  };
  using Pairs = std::vector<std::pair<int, int>>;
  EXPECT_EQ(listed(3, 1, 2), (Pairs{{0, 1}, {0, 2}, {1, 1}}));
  EXPECT_EQ(listed(3, 1, 1), (Pairs{{0, 1}, {1, 1}}));
  EXPECT_EQ(listed(3, 0, 3), (Pairs{{0, 1}, {0, 3}}));
  EXPECT_EQ(listed(3, 5, 1), (Pairs{{0, 1}, {1, 1}, {2, 1}}));
  EXPECT_EQ(listed(1, 1, 1), (Pairs{{0, 1}}));
}

// Every row just over the budget (32 ms of 30), every other row within it (26 ms), level 1 well within
// (12 ms): the stream starts at level 1, tries every other row after the start's wait and stays there - not
// at level 1, where a quarter of the pixels would cost accuracy, and without trying every row again
// (26 ms leaves no room for it).
TEST(ResolutionGovernor, ARowStepJustWithinTheBudgetIsWhereTheStreamStays) {
  Stream stream(2);
  stream.run(300, [](int resolution) { return resolution == 0 ? 0.032 : resolution == 1 ? 0.026 : 0.012; });
  const int wait = vocal::ResolutionGovernor::kStartProbeWaitFrames;
  for (int i = 0; i < static_cast<int>(stream.levels.size()); ++i) EXPECT_EQ(stream.levels[i], i < wait ? 2 : 1) << "frame " << i;
}

// A stream may start finer than the coarsest (the nodelet: at the row step): its first frames, the
// slowest (the first pair's features: 130 ms here), are counted but not timed, so they send it no
// coarser; after them it holds where its frames fit.
TEST(ResolutionGovernor, AStreamStartsWhereToldAndItsFirstFramesAreNotTimed) {
  Stream stream(2, 1);
  const int slow = vocal::ResolutionGovernor::kStartFramesNotTimed;
  int frame = 0;
  stream.run(200, [&](int resolution) { return frame++ < slow ? 0.130 : resolution == 0 ? 0.032 : resolution == 1 ? 0.026 : 0.012; });
  for (int i = 0; i < static_cast<int>(stream.levels.size()); ++i) EXPECT_EQ(stream.levels[i], 1) << "frame " << i;
  EXPECT_EQ(stream.governor.framesAt()[1], 200u);
  EXPECT_NEAR(stream.governor.secondsAt(1), 0.026, 1e-9);
  // Timed, such a start goes coarser at once.
  Stream timed(2, 1);
  timed.run(20, [&](int resolution) { return resolution == 2 ? 0.012 : 0.130; });
  EXPECT_EQ(timed.levels[slow], 1);
  EXPECT_EQ(timed.levels[slow + 1], 2);
}
