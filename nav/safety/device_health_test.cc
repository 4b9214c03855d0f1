#include "nav/safety/device_health.h"

#include <gtest/gtest.h>

namespace corridor::nav {
namespace {

TEST(DeviceWatchTest, OkWhileDataFlowThenStaleThenDisconnectedWhenTheDriverLosesIt) {
  DeviceWatch watch(0.1);
  EXPECT_EQ(watch.State(0.0, LinkView::kNotWatched), DeviceState::kStale);  // nothing yet
  EXPECT_LT(watch.AgeS(0.0), 0.0);
  for (int i = 0; i <= 30; ++i) watch.Arrived(i * 0.1);  // 10 Hz for 3 s
  EXPECT_EQ(watch.State(3.05, LinkView::kNotWatched), DeviceState::kOk);
  EXPECT_NEAR(watch.RateHz(3.0), 10.0, 1e-9);
  EXPECT_NEAR(watch.AgeS(3.05), 0.05, 1e-9);
  EXPECT_EQ(watch.State(3.11, LinkView::kNotWatched), DeviceState::kStale);
  EXPECT_EQ(watch.State(3.05, LinkView::kStale), DeviceState::kStale);  // the driver knows first
  EXPECT_EQ(watch.State(3.05, LinkView::kGone), DeviceState::kDisconnected);
  EXPECT_EQ(watch.State(3.05, LinkView::kUp), DeviceState::kOk);
  // The rate falls as the silence grows, to nothing after a whole window.
  EXPECT_NEAR(watch.RateHz(4.0), 5.0, 1e-9);
  EXPECT_EQ(watch.RateHz(5.5), 0.0);
}

TEST(DeviceWatchTest, RateCountsFromTheFirstArrivalAndBadTimesAreRefused) {
  DeviceWatch watch(0.5);
  watch.Arrived(100.0);
  watch.Arrived(100.02);
  watch.Arrived(100.04);
  EXPECT_NEAR(watch.RateHz(100.04), 50.0, 1e-6);
  EXPECT_THROW(DeviceWatch(0.0), std::invalid_argument);
  EXPECT_THROW(DeviceWatch(0.1, -1.0), std::invalid_argument);
}

}  // namespace
}  // namespace corridor::nav
