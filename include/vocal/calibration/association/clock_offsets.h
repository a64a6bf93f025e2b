#pragma once
// A sensor whose clock runs off the others' by a constant (a lidar not synchronised to the host, a
// driver that stamps on arrival): its still runs all come that much late or early against every other
// sensor's, and association by time pairs its views with the wrong poses or none. The runs' starts and
// ends give the offset: the shift that lays the most of its runs over the reference sensor's, refined to
// the medians of their starts' and ends' differences (a message period's lag at a run's start and at its
// end cancel between the two). The offset is then taken off its stamps before association.

#include <string>
#include <vector>

#include "vocal/calibration/association/still_target_association.h"

namespace vocal {

struct ClockOffsetOptions {
  bool enabled = true;
  double max_offset = 5.0;    // seconds searched either way
  double least_offset = 0.1;  // seconds: smaller ones are within what association tolerates, left as they are
  int least_runs = 3;         // still runs that must lie over the reference's
};

struct ClockOffset {
  int sensor = -1;
  int reference = -1;      // the sensor whose clock it is measured against
  double late = 0.0;       // seconds its stamps read late against the reference's (negative: early)
  double sigma = 0.0;      // standard error, seconds
  int runs = 0;            // its still runs laid over the reference's at that offset ...
  int runs_unshifted = 0;  // ... and as stamped
  bool applied = false;    // beyond least_offset and three sigmas, and laying more runs over than as stamped (or
                           // the stamps lay them over the wrong poses)
  // Metres, median over pairs of matched runs: how far the distances between the board's centres at
  // their poses differ from the reference's at the offset, and as stamped (NaN: under three pairs). A
  // distance is the same in every sensor's frame: runs laid over the wrong poses break it.
  double distance_misfit = 0.0;
  double distance_misfit_stamped = 0.0;
  // A shift that lays more runs over the reference's than the one taken, but over the wrong poses (the
  // board's moves between them disagree), in words; empty: none.
  std::string refused;
};

// One entry per sensor with still runs other than the reference (the rig's reference sensor where it has
// still runs, else the sensor with the most): its offset, applied or not. Empty when disabled.
std::vector<ClockOffset> estimateClockOffsets(const std::vector<SensorSpec>& sensors, const std::vector<TimedObservation>& observations,
                                              int reference, const StillnessOptions& stillness = {},
                                              const ClockOffsetOptions& options = {});

// The observations with each applied offset taken off its sensor's stamps.
void applyClockOffsets(const std::vector<ClockOffset>& offsets, std::vector<TimedObservation>* observations);

// An applied offset in words for the user: "sensor 'lidar0' stamps 1.200 s late against 'rgbd0' (18 of
// its still runs over the reference's, 2 as stamped; +-0.004 s): its stamps are corrected before association",
// and a shift refused as laying the runs over the wrong poses.
std::string describeClockOffset(const ClockOffset& offset, const std::vector<SensorSpec>& sensors);

}  // namespace vocal
