#include "vocal/core/frame_rate_report.h"

#include <cstdio>

namespace vocal {

FrameRatePeriod FrameRateReport::update(double now_seconds, std::size_t received, std::size_t processed, std::size_t skipped,
                                        double processing_seconds) {
  FrameRatePeriod period;
  if (started_ && now_seconds > last_seconds_) {
    period.seconds = now_seconds - last_seconds_;
    period.received_hz = (received - last_received_) / period.seconds;
    period.processed_hz = (processed - last_processed_) / period.seconds;
    period.skipped = skipped - last_skipped_;
    if (processed > last_processed_) period.mean_processing_ms = 1000.0 * (processing_seconds - last_processing_seconds_) / (processed - last_processed_);
  }
  started_ = true;
  last_seconds_ = now_seconds;
  last_received_ = received;
  last_processed_ = processed;
  last_skipped_ = skipped;
  last_processing_seconds_ = processing_seconds;
  return period;
}

std::string frameSkipWarning(const FrameRatePeriod& period) {
  if (period.skipped == 0 || period.seconds <= 0.0) return "";
  char text[256];
  std::snprintf(text, sizeof(text),
                "keeping %.1f of %.1f frames a second: %zu skipped since the last report (tracking takes %.1f ms a frame; "
                "is the CPU shared? see the threads setting)",
                period.processed_hz, period.received_hz, period.skipped, period.mean_processing_ms);
  return text;
}

}  // namespace vocal
