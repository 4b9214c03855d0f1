#include "drivers/sim/battery_sim.h"

#include <gtest/gtest.h>

namespace corridor::drivers::sim {
namespace {

TEST(BatterySimTest, DrainsWithTimeAndFasterWithMotion) {
  SimBatteryOptions o;
  o.capacity_wh = 10.0;
  o.initial_percent = 50.0;
  o.idle_w = 10.0;
  o.drive_w_per_mps = 20.0;
  BatterySim idle(o);
  BatterySim driving(o);
  for (int i = 0; i < 360; ++i) {  // six minutes
    idle.Step(1.0, {}, false);
    driving.Step(1.0, {0.5, 0.0}, false);
  }
  EXPECT_NEAR(idle.charge(), 0.5 - 1.0 / 10.0, 1e-9);     // 1 Wh of 10
  EXPECT_NEAR(driving.charge(), 0.5 - 2.0 / 10.0, 1e-9);  // twice the power
  const BatteryState s = driving.State(42);
  EXPECT_EQ(s.stamp_ns, 42);
  EXPECT_FALSE(s.charging);
  EXPECT_FALSE(s.on_charger);
  EXPECT_LT(s.current_a, 0.0);
  EXPECT_NEAR(s.voltage_v, o.empty_v + 0.3 * (o.full_v - o.empty_v), 1e-9);
}

TEST(BatterySimTest, ChargesOnTheChargerTaperingToFull) {
  SimBatteryOptions o;
  o.capacity_wh = 10.0;
  o.initial_percent = 10.0;
  o.charge_w = 20.0;
  BatterySim battery(o);
  battery.Step(360.0, {}, true);  // 2 Wh at full power
  EXPECT_NEAR(battery.charge(), 0.3, 1e-9);
  EXPECT_TRUE(battery.State(0).charging);
  EXPECT_TRUE(battery.State(0).on_charger);
  EXPECT_GT(battery.State(0).current_a, 0.0);
  for (int i = 0; i < 20000; ++i) battery.Step(1.0, {}, true);
  EXPECT_GT(battery.charge(), 0.99);
  EXPECT_LE(battery.charge(), 1.0);
  // Above taper_from the power falls: the last tenth takes longer than the tenth before the taper.
  BatterySim low(o), high(o);
  o.initial_percent = 85.0;
  high = BatterySim(o);
  low.Step(1.0, {}, true);
  high.Step(1.0, {}, true);
  EXPECT_LT(high.State(0).current_a, low.State(0).current_a);
}

TEST(BatterySimTest, BadOptionsAreRefused) {
  SimBatteryOptions o;
  o.capacity_wh = 0.0;
  EXPECT_THROW(BatterySim{o}, std::invalid_argument);
  o = {};
  o.initial_percent = 120.0;
  EXPECT_THROW(BatterySim{o}, std::invalid_argument);
  o = {};
  o.full_v = o.empty_v;
  EXPECT_THROW(BatterySim{o}, std::invalid_argument);
}

}  // namespace
}  // namespace corridor::drivers::sim
