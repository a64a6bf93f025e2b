#pragma once
// The rate a live node keeps against the rate its input arrives at, over each report period: what a
// robot integrator reads in the diagnostics when the CPU is shared and frames are skipped (the newest
// frame replaces one still waiting, so latency never grows; the rate falls instead).

#include <cstddef>
#include <string>

namespace vocal {

struct FrameRatePeriod {
  double seconds = 0.0;        // since the last report (0: the first report)
  double received_hz = 0.0;    // frames that arrived per second
  double processed_hz = 0.0;   // frames tracked (or dropped as bad) per second
  std::size_t skipped = 0;     // frames replaced by a newer one before they were tracked
  double mean_processing_ms = 0.0;  // per frame processed in the period
};

class FrameRateReport {
 public:
  // The period since the last call, from the running totals at `now_seconds` (a monotonic clock).
  FrameRatePeriod update(double now_seconds, std::size_t received, std::size_t processed, std::size_t skipped,
                         double processing_seconds);

 private:
  bool started_ = false;
  double last_seconds_ = 0.0;
  std::size_t last_received_ = 0, last_processed_ = 0, last_skipped_ = 0;
  double last_processing_seconds_ = 0.0;
};

// "" when nothing was skipped in the period; else e.g. "keeping 14.9 of 30.0 frames a second: 46
// skipped since the last report (tracking takes 66.1 ms a frame; is the CPU shared?)".
std::string frameSkipWarning(const FrameRatePeriod& period);

}  // namespace vocal
