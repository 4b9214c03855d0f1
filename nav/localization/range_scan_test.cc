#include "nav/localization/range_scan.h"

#include <gtest/gtest.h>

#include <numbers>

#include "nav/localization/test_world.h"

namespace corridor::nav {
namespace {

using testworld::Cast;
using testworld::Room;

// A laser turning clockwise once in 0.1 s from forward, on a robot turning left at 1.5 rad/s and driving at 0.5 m/s:
// each beam measured from where the robot was then. Undoing the motion puts every hit on the room's walls as seen
// from the pose at the sweep's end; without it, the far walls smear by up to 15 degrees' worth.
TEST(RangeScanTest, ASweepMeasuredWhileTheRobotMovedIsPutWhereItLiesAtTheStamp) {
  const Twist2 twist{0.5, 1.5};
  const double sweep_s = 0.1;
  const int beams = 360;
  const double increment = 2.0 * std::numbers::pi / beams;
  const Pose2 end{-1.0, 0.5, 0.3};  // the robot at the stamp, in the room
  // Beam i points at angle -pi + i * increment (counter-clockwise); the device turned clockwise from 0, so the beam at
  // angle a was measured when a fraction ((-a) mod 2 pi) / 2 pi of the turn was done.
  const auto age_s = [&](std::size_t i) {
    const double a = -std::numbers::pi + static_cast<double>(i) * increment;
    double turned = std::fmod(-a, 2.0 * std::numbers::pi);
    if (turned < 0.0) turned += 2.0 * std::numbers::pi;
    return (1.0 - turned / (2.0 * std::numbers::pi)) * sweep_s;
  };
  const auto base_at = [&](std::size_t i) { return DriveArc(Pose2{}, twist, -age_s(i)); };  // in the stamp's frame
  std::vector<float> ranges(beams);
  for (int i = 0; i < beams; ++i) {
    const Pose2 world_T_base = end * base_at(static_cast<std::size_t>(i));
    const double a = world_T_base.yaw_rad - std::numbers::pi + i * increment;
    ranges[static_cast<std::size_t>(i)] =
        static_cast<float>(Cast(Room(), world_T_base.translation(), {std::cos(a), std::sin(a)}));
  }
  // The distance from a hit (stamp's base frame) to the nearest wall of the room.
  const auto off_wall = [&](const Eigen::Vector2f& hit) {
    const Eigen::Vector2d p = end.Transform(hit.cast<double>());
    double best = 1e9;
    for (const testworld::Wall& w : Room()) {
      const Eigen::Vector2d e = w.b - w.a;
      const double t = std::clamp((p - w.a).dot(e) / e.squaredNorm(), 0.0, 1.0);
      best = std::min(best, (w.a + t * e - p).norm());
    }
    return best;
  };
  const RangeScan undone = ScanFromRanges(Pose2{}, -std::numbers::pi, increment, ranges, RangeLimits{}, base_at);
  const RangeScan smeared = ScanFromRanges(Pose2{}, -std::numbers::pi, increment, ranges, RangeLimits{});
  ASSERT_EQ(undone.hits.size(), smeared.hits.size());
  double worst_undone = 0.0;
  double worst_smeared = 0.0;
  for (std::size_t i = 0; i < undone.hits.size(); ++i) {
    worst_undone = std::max(worst_undone, off_wall(undone.hits[i]));
    worst_smeared = std::max(worst_smeared, off_wall(smeared.hits[i]));
  }
  EXPECT_LT(worst_undone, 1e-4);
  EXPECT_GT(worst_smeared, 0.3);
}

}  // namespace
}  // namespace corridor::nav
