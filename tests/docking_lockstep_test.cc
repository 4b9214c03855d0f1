// Docking and charging through the daemon's graph in simulated time (testing/lockstep_robot.h), in a 4 x 3 m room with
// the simulator's dock: docking through the API ends on the dock within 2 cm and 2 degrees by the simulator's truth and
// charges, the face sleeps while it does, a mission from the dock backs off it first, undocking alone backs straight
// off to the staging pose, and an idle robot low on charge goes to its dock by itself. The robot's pose comes from
// wheel odometry with the simulator's default noise, so the map's idea of the dock drifts: docking finds the dock in
// the depth image. (The requests' transport and the console's buttons are tests/docking_test.mjs.)
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <set>
#include <string>

#include "testing/lockstep_robot.h"
#include "testing/sim_room.h"

namespace corridor {
namespace {

using nlohmann::json;
using testing::LockstepRobot;

constexpr double kDockX = 3.2, kDockY = 1.5;  // the docked pose, facing the room's east wall (yaw 0)

// A 4 x 3 m room with the simulator's dock, and its configuration (`extra` added at the end).
testing::SimRoom DockRoom(const std::string& extra = "") {
  return testing::SimRoom(4.0, 3.0,
                          "sim:\n"
                          "  world: room.yaml\n"
                          "  start: {x_m: 1.0, y_m: 1.0, yaw_deg: 90}\n"
                          "  camera: {width: 160, height: 120}\n"
                          "  dock: {enabled: true, x_m: 3.2, y_m: 1.5, yaw_deg: 0}\n" +
                              extra);
}

bool Finished(const json& state) { return state["mission"].is_object() && state["mission"]["status"] != "active"; }

// Steps until the state's mission is over (at most max_s of simulated time); the last state, whatever it says.
json UntilFinished(LockstepRobot& robot, double max_s, std::set<std::string>* phases = nullptr) {
  return robot.StateWhen(
      [&](const json& state) {
        if (phases && state["mission"].is_object() && state["mission"].contains("docking")) {
          phases->insert(state["mission"]["docking"].get<std::string>());
        }
        return Finished(state);
      },
      max_s);
}

// The simulator's truth against a pose: metres and degrees.
std::pair<double, double> Off(const json& state, double x, double y, double yaw) {
  const json& t = state["sim_true_pose"];
  const double d_yaw = std::remainder(t["yaw"].get<double>() - yaw, 2.0 * std::numbers::pi);
  return {std::hypot(t["x"].get<double>() - x, t["y"].get<double>() - y), std::abs(d_yaw) * 180.0 / std::numbers::pi};
}

std::vector<std::string> Actions(const json& mission) {
  std::vector<std::string> out;
  for (const json& w : mission["waypoints"]) out.push_back(w["action"].get<std::string>());
  return out;
}

TEST(DockingLockstep, DocksWithinTwoCentimetresChargesSleepsAndAMissionFromTheDockBacksOffFirst) {
  const testing::SimRoom room = DockRoom();
  LockstepRobot robot(room.config());
  const LockstepRobot::Reply started = robot.Call("POST", "/api/v1/dock", json::object());
  ASSERT_EQ(started.status, 201) << started.body.dump();
  EXPECT_EQ(Actions(started.body), std::vector<std::string>{"dock"});
  std::set<std::string> phases;
  const json done = UntilFinished(robot, 90.0, &phases);
  ASSERT_EQ(done["mission"]["status"], "succeeded") << done["mission"].dump();
  EXPECT_TRUE(phases.contains("approaching")) << json(phases).dump();
  const auto [off_m, off_deg] = Off(done, kDockX, kDockY, 0.0);
  EXPECT_LE(off_m, 0.02);
  EXPECT_LE(off_deg, 2.0);
  EXPECT_EQ(done["docked"], true);
  EXPECT_EQ(done["bumper_pressed"], false) << "it stops short of the face, not against it";

  json charging;
  ASSERT_TRUE(robot.StepUntil(
      [&] {
        charging = robot.State();
        return charging["battery"]["on_charger"] == true && charging["battery"]["charging"] == true;
      },
      5.0))
      << "the battery never charged";
  const double percent = charging["battery"]["percent"].get<double>();
  EXPECT_TRUE(robot.StepUntil([&] { return robot.State()["battery"]["percent"].get<double>() > percent; }, 5.0))
      << "the charge never rose";
  EXPECT_TRUE(robot.StepUntil([&] { return robot.State()["face"] == "sleepy"; }, 5.0)) << "no sleepy face";
  EXPECT_EQ(robot.Call("POST", "/api/v1/dock", json::object()).status, 409) << "docked already";

  // A mission from the dock: off the dock, then on.
  const LockstepRobot::Reply away =
      robot.Call("POST", "/api/v1/missions", {{"waypoints", json::array({{{"x", 1.0}, {"y", 2.0}}})}});
  ASSERT_EQ(away.status, 201) << away.body.dump();
  EXPECT_EQ(Actions(away.body), (std::vector<std::string>{"undock", "go"}));
  json undocking;
  EXPECT_TRUE(robot.StepUntil(
      [&] {
        undocking = robot.State();
        return undocking["mission"]["docking"] == "undocking";
      },
      5.0));
  EXPECT_EQ(undocking["mode"], "docking");
  const json there = UntilFinished(robot, 60.0);
  ASSERT_EQ(there["mission"]["status"], "succeeded") << there["mission"].dump();
  EXPECT_EQ(there["docked"], false);
  EXPECT_EQ(there["battery"]["on_charger"], false);
  EXPECT_LT(Off(there, 1.0, 2.0, 0.0).first, 0.1);
}

TEST(DockingLockstep, UndockingOnItsOwnBacksStraightOffToTheStagingPose) {
  const testing::SimRoom room = DockRoom();
  LockstepRobot robot(room.config());
  ASSERT_EQ(robot.Call("POST", "/api/v1/dock", {{"dock", "dock"}}).status, 201);
  const json on = UntilFinished(robot, 90.0);
  ASSERT_EQ(on["mission"]["status"], "succeeded") << on["mission"].dump();
  const LockstepRobot::Reply undock = robot.Call("POST", "/api/v1/undock");
  ASSERT_EQ(undock.status, 201) << undock.body.dump();
  const json off = UntilFinished(robot, 30.0);
  ASSERT_EQ(off["mission"]["status"], "succeeded") << off["mission"].dump();
  const json& t = off["sim_true_pose"];
  EXPECT_NEAR(t["x"].get<double>(), kDockX - 0.7, 0.05);
  EXPECT_NEAR(t["y"].get<double>(), kDockY, 0.03);
  EXPECT_EQ(off["docked"], false);
}

TEST(DockingLockstep, AnIdleRobotBelowChargeBelowPercentGoesToItsDockByItself) {
  const testing::SimRoom room = DockRoom("  battery: {initial_percent: 15}\ndocking:\n  charge_below_percent: 20\n");
  LockstepRobot robot(room.config());
  json state;
  ASSERT_TRUE(robot.StepUntil(
      [&] {
        state = robot.State();
        return state["mission"].is_object();
      },
      10.0))
      << "no mission to charge";
  EXPECT_EQ(Actions(state["mission"]), std::vector<std::string>{"dock"});
  EXPECT_EQ(state["mission"]["waypoints"][0]["place"], "dock");
  const json done = UntilFinished(robot, 90.0);
  ASSERT_EQ(done["mission"]["status"], "succeeded") << done["mission"].dump();
  EXPECT_TRUE(robot.StepUntil([&] { return robot.State()["battery"]["charging"] == true; }, 5.0)) << "not charging";
}

}  // namespace
}  // namespace corridor
