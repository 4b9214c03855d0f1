// The serial text driver against an emulated ROSArduinoBridge board on a pseudo-terminal
// (testing/emulators/serial_text_emulator.h): real serial I/O on real threads, since the transport is the point; every
// wait is for a condition, with a deadline.
#include "drivers/serial_text/serial_text_base.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <string>
#include <vector>

#include "testing/emulators/serial_text_emulator.h"
#include "testing/eventually.h"
#include "testing/latest_reports.h"
#include "testing/pumping.h"

namespace corridor::drivers::serial_text {
namespace {

using corridor::testing::Eventually;
using corridor::testing::LatestReports;
using corridor::testing::Pumping;
using corridor::testing::SerialTextEmulator;
using namespace std::chrono_literals;

std::filesystem::path Link(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("corridor_serial_text_" + name + "_" + std::to_string(::getpid()));
}

SerialTextOptions OptionsFor(const std::filesystem::path& port, double command_timeout_s = 10.0) {
  SerialTextOptions options;
  options.port = port;
  options.wheels = {0.065, 0.20, 1920.0};  // the emulator's
  options.command_timeout_s = command_timeout_s;
  options.reconnect_s = 0.1;
  options.boot_s = 1.0;
  return options;
}

// Speeds go to the board in whole counts a frame (1920 counts a turn of a 65 mm wheel, 30 frames a second: 9.4 mm/s).
bool Near(std::pair<double, double> wheels, double left, double right) {
  return std::abs(wheels.first - left) < 0.006 && std::abs(wheels.second - right) < 0.006;
}

TEST(SerialTextBaseTest, ItWaitsForTheBoardToBootDrivesTheWheelsAndItsOdometryFollowsThem) {
  const std::filesystem::path link = Link("drive");
  SerialTextEmulator board(link);
  SteadyClock clock;
  SerialTextBase base(OptionsFor(link), clock);
  LatestReports latest;
  latest.Connect(base);
  ASSERT_TRUE(Eventually([&] { return base.status().state == LinkState::kRunning; }, 3000ms))
      << base.status().last_error;
  // Forward at 0.2 m/s (the 32-bit counts wrap on the way: the board starts them near it).
  base.SetVelocity({0.2, 0.0});
  ASSERT_TRUE(Eventually([&] { return Near(board.wheels_mps(), 0.2, 0.2); }, 2000ms));
  ASSERT_TRUE(Eventually([&] { return latest.Odometry().odom_T_base.x_m > 0.3; }, 5000ms));
  EXPECT_TRUE(latest.VelocityReaches(0.2, 0.0, 0.03)) << latest.Odometry().velocity.linear_mps;
  const WheelOdometry o = latest.Odometry();
  EXPECT_NEAR(o.odom_T_base.y_m, 0.0, 0.01);
  EXPECT_NEAR(o.odom_T_base.yaw_rad, 0.0, 0.02);
  // Turning on the spot at 1 rad/s: each wheel at 100 mm/s.
  base.SetVelocity({0.0, 1.0});
  ASSERT_TRUE(Eventually([&] { return Near(board.wheels_mps(), -0.1, 0.1); }, 2000ms))
      << board.wheels_mps().first << ", " << board.wheels_mps().second;
  const double yaw0 = latest.Odometry().odom_T_base.yaw_rad;
  ASSERT_TRUE(Eventually([&] { return latest.Odometry().odom_T_base.yaw_rad > yaw0 + 0.5; }, 3000ms));
  EXPECT_TRUE(latest.VelocityReaches(0.0, 1.0, 0.12)) << latest.Odometry().velocity.angular_rps;
  const SerialTextStatus status = base.status();
  EXPECT_EQ(status.bad_lines, 0u);
  EXPECT_EQ(status.implausible, 0u);
  EXPECT_EQ(board.invalid_commands(), 0);
}

// A control loop that is late now and then takes one reply late and the next at once: the counts between them cover
// the time between their questions, not between their takings, and are believed.
TEST(SerialTextBaseTest, RepliesTakenLateAndThenAtOnceAreBelieved) {
  const std::filesystem::path link = Link("late");
  SerialTextEmulator board(link);
  std::mutex mutex;
  std::vector<WheelOdometry> reports;
  SteadyClock clock;
  SerialTextBase base(OptionsFor(link), clock);
  base.SetOdometryHandler([&](const WheelOdometry& o) {
    std::lock_guard lock(mutex);
    reports.push_back(o);
  });
  const auto count = [&] {
    std::lock_guard lock(mutex);
    return reports.size();
  };
  ASSERT_TRUE(Eventually([&] { return base.status().state == LinkState::kRunning; }, 3000ms))
      << base.status().last_error;
  // Every other reply is taken 100 ms after its question and the next 10 ms after: stamped when taken, every report's
  // velocity would be off by the ratio of the two.
  Pumping pump(base, {100ms, 10ms});
  base.SetVelocity({0.2, 0.0});
  ASSERT_TRUE(Eventually([&] { return Near(board.wheels_mps(), 0.2, 0.2); }, 2000ms));
  // The velocity window (0.1 s) reaches back past the last change of speed two replies on.
  const std::size_t steady = count() + 2;
  ASSERT_TRUE(Eventually([&] { return count() >= steady + 12; }, 5000ms));
  EXPECT_EQ(base.status().implausible, 0u);
  EXPECT_EQ(base.status().restarts, 0u);
  std::lock_guard lock(mutex);
  for (std::size_t i = steady; i < reports.size(); ++i) {
    EXPECT_NEAR(reports[i].velocity.linear_mps, 0.2, 0.05) << "report " << i - steady << " of the steady ones";
  }
}

TEST(SerialTextBaseTest, WhenCommandsStopComingTheWheelsStop) {
  const std::filesystem::path link = Link("timeout");
  SerialTextEmulator board(link);
  SteadyClock clock;
  SerialTextOptions options = OptionsFor(link, 0.3);
  options.max_linear_accel_mps2 = 2.0;  // under way well within the timeout
  SerialTextBase base(options, clock);
  ASSERT_TRUE(Eventually([&] { return base.status().state == LinkState::kRunning; }, 3000ms));
  base.SetVelocity({0.3, 0.0});
  ASSERT_TRUE(Eventually([&] { return board.wheels_mps().first > 0.1; }, 3000ms));
  ASSERT_TRUE(Eventually([&] { return Near(board.wheels_mps(), 0.0, 0.0); }, 2000ms));
}

TEST(SerialTextBaseTest, NoiseAndALostDigitCostAReplyNotThePose) {
  const std::filesystem::path link = Link("noise");
  SerialTextEmulator board(link);
  SteadyClock clock;
  SerialTextBase base(OptionsFor(link), clock);
  LatestReports latest;
  latest.Connect(base);
  ASSERT_TRUE(Eventually([&] { return base.status().replies >= 5; }, 3000ms)) << base.status().last_error;
  board.Noise("\x13\xFF garbage\r\n");
  ASSERT_TRUE(Eventually([&] { return base.status().bad_lines >= 1; }, 2000ms));
  // A digit lost from a count would move the pose by kilometres: the reply is dropped.
  board.DropAByte();
  ASSERT_TRUE(Eventually([&] { return base.status().implausible >= 1; }, 2000ms));
  const std::uint64_t replies = base.status().replies;
  ASSERT_TRUE(Eventually([&] { return base.status().replies >= replies + 5; }, 2000ms));
  const WheelOdometry o = latest.Odometry();
  EXPECT_NEAR(o.odom_T_base.x_m, 0.0, 1e-9);
  EXPECT_NEAR(o.odom_T_base.y_m, 0.0, 1e-9);
  EXPECT_EQ(base.status().state, LinkState::kRunning);
  EXPECT_EQ(base.status().restarts, 0u);
}

// Replies lost on the line leave their asks unanswered, and the replies after them are paired with asks before their
// own: the velocity still holds, and no reply is taken for a wrong one.
TEST(SerialTextBaseTest, LostRepliesCostNeitherTheVelocityNorAReply) {
  const std::filesystem::path link = Link("lost");
  SerialTextEmulator board(link);
  SteadyClock clock;
  SerialTextBase base(OptionsFor(link), clock);
  LatestReports latest;
  latest.Connect(base);
  base.SetVelocity({0.2, 0.0});
  ASSERT_TRUE(Eventually([&] { return latest.Odometry().odom_T_base.x_m > 0.1; }, 3000ms)) << base.status().last_error;
  board.LoseReplies(10);
  const std::uint64_t replies = base.status().replies;
  ASSERT_TRUE(Eventually([&] { return base.status().replies >= replies + 20; }, 3000ms));
  EXPECT_NEAR(latest.Odometry().velocity.linear_mps, 0.2, 0.05);
  EXPECT_EQ(base.status().implausible, 0u);
  EXPECT_EQ(base.status().state, LinkState::kRunning);
}

TEST(SerialTextBaseTest, ABoardThatRestartsWithThePortOpenIsTakenUpWithoutThePoseJumping) {
  const std::filesystem::path link = Link("restart");
  SerialTextEmulator board(link);
  SteadyClock clock;
  SerialTextBase base(OptionsFor(link), clock);
  LatestReports latest;
  latest.Connect(base);
  base.SetVelocity({0.2, 0.0});
  ASSERT_TRUE(Eventually([&] { return latest.Odometry().odom_T_base.x_m > 0.1; }, 3000ms));
  board.Restart();  // counting from zero again, after its boot
  ASSERT_TRUE(Eventually([&] { return base.status().restarts >= 1; }, 3000ms)) << base.status().last_error;
  const double x = latest.Odometry().odom_T_base.x_m;
  EXPECT_LT(x, 1.0);
  ASSERT_TRUE(Eventually([&] { return Near(board.wheels_mps(), 0.2, 0.2); }, 2000ms));
  ASSERT_TRUE(Eventually([&] { return latest.Odometry().odom_T_base.x_m > x + 0.05; }, 2000ms));
  EXPECT_LT(latest.Odometry().odom_T_base.x_m, x + 1.0);
}

TEST(SerialTextBaseTest, ASlowBoardIsStillDriven) {
  const std::filesystem::path link = Link("slow");
  SerialTextEmulator board(link);
  board.Slow(0.03);  // every answer 30 ms late: later than the next question
  SteadyClock clock;
  SerialTextBase base(OptionsFor(link), clock);
  base.SetVelocity({0.1, 0.0});
  ASSERT_TRUE(Eventually([&] { return Near(board.wheels_mps(), 0.1, 0.1); }, 3000ms)) << base.status().last_error;
  EXPECT_EQ(base.status().state, LinkState::kRunning);
}

TEST(SerialTextBaseTest, UnpluggedOrSilentItSaysSoStopsAndDrivesAgainWhenTheBoardIsBack) {
  const std::filesystem::path link = Link("unplug");
  SerialTextEmulator board(link);
  SteadyClock clock;
  SerialTextBase base(OptionsFor(link), clock);
  std::vector<LinkState> states;
  std::mutex mutex;
  base.SetLinkHandler([&](const LinkStatus& s) {
    std::lock_guard lock(mutex);
    states.push_back(s.state);
  });
  base.SetVelocity({0.2, 0.0});
  ASSERT_TRUE(Eventually([&] { return Near(board.wheels_mps(), 0.2, 0.2); }, 3000ms));
  board.Silence();
  ASSERT_TRUE(Eventually([&] { return base.status().state == LinkState::kSilent; }, 2000ms));
  {
    std::lock_guard lock(mutex);
    EXPECT_NE(std::find(states.begin(), states.end(), LinkState::kStale), states.end()) << "stale before silent";
  }
  board.Resume();
  ASSERT_TRUE(Eventually([&] { return base.status().state == LinkState::kRunning; }, 3000ms));
  board.Unplug();
  ASSERT_TRUE(Eventually([&] { return base.status().state == LinkState::kDisconnected; }, 3000ms));
  board.Replug();
  ASSERT_TRUE(Eventually([&] { return base.status().state == LinkState::kRunning; }, 3000ms))
      << ToString(base.status().state) << " " << base.status().last_error;
  base.SetVelocity({0.1, 0.0});
  ASSERT_TRUE(Eventually([&] { return Near(board.wheels_mps(), 0.1, 0.1); }, 2000ms));
  EXPECT_GT(base.status().reconnects, 0u);
}

TEST(SerialTextBaseTest, ABoardThatNeverAnswersIsReportedAndTheDriverKeepsTrying) {
  const std::filesystem::path link = Link("mute");
  SerialTextEmulator board(link);
  board.Silence();
  SteadyClock clock;
  SerialTextOptions options = OptionsFor(link);
  options.boot_s = 0.2;
  SerialTextBase base(options, clock);
  ASSERT_TRUE(Eventually([&] { return base.status().reconnects >= 2; }, 3000ms));
  EXPECT_NE(base.status().last_error.find("no answer"), std::string::npos) << base.status().last_error;
  EXPECT_NE(base.status().state, LinkState::kRunning);
  board.Resume();
  ASSERT_TRUE(Eventually([&] { return base.status().state == LinkState::kRunning; }, 3000ms));
}

TEST(SerialTextBaseTest, BadOptionsAreRefused) {
  SteadyClock clock;
  EXPECT_THROW(SerialTextBase(SerialTextOptions{}, clock), std::invalid_argument);
  SerialTextOptions options;
  options.port = "/dev/null";  // a port, but no wheels
  EXPECT_THROW(SerialTextBase(options, clock), std::invalid_argument);
  options = OptionsFor("/dev/null");
  options.pid_rate_hz = 0.0;
  EXPECT_THROW(SerialTextBase(options, clock), std::invalid_argument);
}

}  // namespace
}  // namespace corridor::drivers::serial_text
