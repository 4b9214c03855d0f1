// A rotating laser's sweeps: their timing, and each beam's age from it (drivers/laser2d.h).
#include "drivers/laser_sweep.h"

#include <gtest/gtest.h>

#include <numbers>

namespace corridor::drivers {
namespace {

constexpr TimeNs kSecond = 1'000'000'000;

// One revolution of 360 points a degree apart, clockwise from forward, ending at the next start flag at `end_ns`.
std::optional<LaserScan> Revolution(SweepAssembler& sweeps, TimeNs end_ns) {
  for (int i = 1; i < 360; ++i) sweeps.Add(SweepPoint{false, 10, static_cast<double>(i), 2.0}, end_ns);
  return sweeps.Add(SweepPoint{true, 10, 0.0, 2.0}, end_ns);
}

TEST(LaserSweepTest, ASweepTakesTheTimeBetweenStartFlagsTurningClockwiseFromForward) {
  SweepAssembler sweeps;
  EXPECT_FALSE(sweeps.Add(SweepPoint{true, 10, 0.0, 2.0}, kSecond));
  const std::optional<LaserScan> first = Revolution(sweeps, kSecond + kSecond / 10);
  ASSERT_TRUE(first);
  EXPECT_NEAR(first->sweep_s, 0.1, 1e-9);
  EXPECT_TRUE(first->sweep_clockwise);
  EXPECT_NEAR(first->sweep_start_rad, 0.5 * std::numbers::pi / 180.0, 1e-12);  // half a beam left of forward
  // Forward was measured first (a whole sweep before the stamp); the robot's right (-90 degrees in the scan, 90
  // clockwise) a quarter of the turn later; its left (90, the device's 270) three quarters.
  const auto beam = [&](double deg) {
    return static_cast<std::size_t>(
        std::lround((deg * std::numbers::pi / 180.0 - first->angle_min_rad) / first->angle_increment_rad));
  };
  // (To half a beam's time: a beam holds what was measured within half a degree of it.)
  constexpr double kBeamS = 0.1 / 360.0;
  EXPECT_NEAR(BeamAgeS(*first, beam(0.0)), 0.1, kBeamS);
  EXPECT_NEAR(BeamAgeS(*first, beam(-90.0)), 0.075, kBeamS);
  EXPECT_NEAR(BeamAgeS(*first, beam(90.0)), 0.025, kBeamS);
  EXPECT_NEAR(BeamAgeS(*first, beam(1.0)), kBeamS, kBeamS);  // the last measured, just left of forward
  // After a gap of more than a second (the device restarted), the sweep's timing is unknown: every beam at the stamp.
  const std::optional<LaserScan> late = Revolution(sweeps, 5 * kSecond);
  ASSERT_TRUE(late);
  EXPECT_EQ(late->sweep_s, 0.0);
  EXPECT_EQ(BeamAgeS(*late, beam(0.0)), 0.0);
}

}  // namespace
}  // namespace corridor::drivers
