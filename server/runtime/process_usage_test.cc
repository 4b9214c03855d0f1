#include "server/runtime/process_usage.h"

#include <gtest/gtest.h>

#include <time.h>

#include <chrono>

namespace corridor::server {
namespace {

drivers::TimeNs NowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

double ProcessCpuS() {
  timespec t{};
  ::clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// The share of a core reported over a window is the process's CPU time over it (as the kernel's own clock counts it,
// to its 10 ms ticks), however busy the machine is; the memory is this process's.
TEST(ProcessUsageTest, AWindowsShareIsTheProcessesCpuTimeOverIt) {
  ProcessUsage usage;
  const double cpu_before = ProcessCpuS();
  const drivers::TimeNs start = NowNs();
  EXPECT_FALSE(usage.Sample(start).has_value()) << "no window has passed yet";
  volatile double sink = 0.0;
  while (drivers::ToSeconds(NowNs() - start) < 1.2 * ProcessUsage::kWindowS) sink = sink + 1.0;
  const double cpu_after = ProcessCpuS();
  const drivers::TimeNs end = NowNs();
  const std::optional<ProcessUsageSample> sample = usage.Sample(end);
  ASSERT_TRUE(sample.has_value());
  const double expected = 100.0 * (cpu_after - cpu_before) / drivers::ToSeconds(end - start);
  EXPECT_NEAR(sample->cpu_percent, expected, 5.0);
  EXPECT_GT(sample->resident_mb, 1.0);
  EXPECT_LT(sample->resident_mb, 1000.0);
  // Asked again within the window: the same sample, /proc not read again.
  const std::optional<ProcessUsageSample> again = usage.Sample(NowNs());
  ASSERT_TRUE(again.has_value());
  EXPECT_EQ(again->cpu_percent, sample->cpu_percent);
}

}  // namespace
}  // namespace corridor::server
