#include <gtest/gtest.h>

#include "vocal/core/frame_rate_report.h"

namespace {

TEST(FrameRateReport, EachPeriodsRatesAndSkipsFromTheRunningTotals) {
  vocal::FrameRateReport report;
  const vocal::FrameRatePeriod first = report.update(100.0, 5, 5, 0, 0.05);
  EXPECT_EQ(first.seconds, 0.0);  // nothing to compare with yet
  EXPECT_EQ(vocal::frameSkipWarning(first), "");
  // 30 frames a second arrive, 15 are tracked at 66 ms each, 15 replaced by newer ones.
  const vocal::FrameRatePeriod busy = report.update(102.0, 65, 35, 30, 0.05 + 30 * 0.066);
  EXPECT_DOUBLE_EQ(busy.seconds, 2.0);
  EXPECT_DOUBLE_EQ(busy.received_hz, 30.0);
  EXPECT_DOUBLE_EQ(busy.processed_hz, 15.0);
  EXPECT_EQ(busy.skipped, 30u);
  EXPECT_NEAR(busy.mean_processing_ms, 66.0, 1e-9);
  EXPECT_EQ(vocal::frameSkipWarning(busy),
            "keeping 15.0 of 30.0 frames a second: 30 skipped since the last report (tracking takes 66.0 ms a frame; "
            "is the CPU shared? see the threads setting)");
  // Keeping up again: no warning, though frames were skipped before.
  const vocal::FrameRatePeriod idle = report.update(103.0, 95, 65, 30, 0.05 + 30 * 0.066 + 30 * 0.012);
  EXPECT_EQ(idle.skipped, 0u);
  EXPECT_DOUBLE_EQ(idle.processed_hz, 30.0);
  EXPECT_EQ(vocal::frameSkipWarning(idle), "");
}

}  // namespace
