// The Open-RMF robot contract's commands (/api/v1/rmf/, the calls of Open-RMF's fleet adapter template) through the
// daemon's graph in simulated time (testing/lockstep_robot.h), in a 4 x 3 m room with the simulator's dock: navigate
// is working while it drives and completed where it was sent; stop cancels it and says so; dock through
// start_activity charges, and undock backs off. (What the template reads, the state against Open-RMF's own schema and
// bad calls over HTTP are tests/rmf_test.mjs.)
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "testing/lockstep_robot.h"
#include "testing/sim_room.h"

namespace corridor {
namespace {

using nlohmann::json;
using testing::LockstepRobot;

testing::SimRoom DockRoom() {
  return testing::SimRoom(4.0, 3.0,
                          "sim:\n"
                          "  world: room.yaml\n"
                          "  start: {x_m: 1.0, y_m: 1.0, yaw_deg: 0}\n"
                          "  camera: {width: 160, height: 120}\n"
                          "  dock: {enabled: true, x_m: 3.2, y_m: 1.5, yaw_deg: 0}\n"
                          "webhooks:\n"
                          "  robot: corridor-1\n");
}

json Completed(LockstepRobot& robot, int cmd_id) {
  const LockstepRobot::Reply reply =
      robot.Call("GET", "/api/v1/rmf/is_command_completed?cmd_id=" + std::to_string(cmd_id));
  EXPECT_EQ(reply.status, 200) << reply.body.dump();
  return reply.body;
}

// Steps until command `cmd_id` is no longer active (at most max_s of simulated time); its last status.
json UntilDone(LockstepRobot& robot, int cmd_id, double max_s) {
  json status;
  robot.StepUntil(
      [&] {
        status = Completed(robot, cmd_id);
        return status["status"] != "active";
      },
      max_s);
  return status;
}

std::string RobotStatus(LockstepRobot& robot) {
  return robot.Call("GET", "/api/v1/rmf/robot_state").body["status"].get<std::string>();
}

TEST(RmfLockstep, NavigateIsWorkingWhileItDrivesThenCompletedWhereItWasSent) {
  const testing::SimRoom room = DockRoom();
  LockstepRobot robot(room.config());
  const std::string map = robot.Call("GET", "/api/v1/rmf/map").body["map_name"].get<std::string>();
  const LockstepRobot::Reply started =
      robot.Call("POST", "/api/v1/rmf/navigate",
                 {{"cmd_id", 7}, {"pose", {2.5, 2.2, std::numbers::pi / 2}}, {"map_name", map}, {"speed_limit", 0.0}});
  ASSERT_EQ(started.status, 201) << started.body.dump();
  const json state = robot.Call("GET", "/api/v1/rmf/robot_state").body;
  EXPECT_EQ(state["status"], "working");
  EXPECT_EQ(state["task_id"], started.body["mission"]);
  EXPECT_EQ(Completed(robot, 7)["completed"], false);
  const json done = UntilDone(robot, 7, 60.0);
  EXPECT_EQ(done["completed"], true) << done.dump();
  const json position = robot.Call("GET", "/api/v1/rmf/position").body["position"];
  EXPECT_LT(std::hypot(position[0].get<double>() - 2.5, position[1].get<double>() - 2.2), 0.05) << position.dump();
  EXPECT_LT(std::abs(position[2].get<double>() - std::numbers::pi / 2), 0.05) << position.dump();
  EXPECT_EQ(RobotStatus(robot), "idle");
}

TEST(RmfLockstep, StopCancelsWhatTheRobotIsDoingAndTheStoppedCommandSaysSo) {
  const testing::SimRoom room = DockRoom();
  LockstepRobot robot(room.config());
  const LockstepRobot::Reply started =
      robot.Call("POST", "/api/v1/rmf/navigate", {{"cmd_id", 8}, {"pose", {3.0, 2.2, 0.0}}, {"map_name", "room"}});
  ASSERT_EQ(started.status, 201) << started.body.dump();
  robot.StepFor(1.0);
  const LockstepRobot::Reply stop = robot.Call("POST", "/api/v1/rmf/stop", {{"cmd_id", 9}});
  ASSERT_EQ(stop.status, 200) << stop.body.dump();
  EXPECT_EQ(Completed(robot, 9)["completed"], true);
  const json stopped = Completed(robot, 8);
  EXPECT_EQ(stopped["completed"], false);
  EXPECT_EQ(stopped["status"], "canceled");
  robot.StepFor(1.0);  // coming to a stop
  const json stood = robot.State()["sim_true_pose"];
  robot.StepFor(2.0);
  const json later = robot.State()["sim_true_pose"];
  EXPECT_LT(std::hypot(later["x"].get<double>() - stood["x"].get<double>(),
                       later["y"].get<double>() - stood["y"].get<double>()),
            0.01);
  EXPECT_EQ(RobotStatus(robot), "idle");
}

TEST(RmfLockstep, DockThroughStartActivityChargesThenUndockBacksOff) {
  const testing::SimRoom room = DockRoom();
  LockstepRobot robot(room.config());
  const LockstepRobot::Reply dock =
      robot.Call("POST", "/api/v1/rmf/start_activity", {{"cmd_id", 10}, {"activity", "dock"}, {"label", "dock"}});
  ASSERT_EQ(dock.status, 201) << dock.body.dump();
  const json docked = UntilDone(robot, 10, 90.0);
  ASSERT_EQ(docked["completed"], true) << docked.dump();
  ASSERT_TRUE(robot.StepUntil([&] { return RobotStatus(robot) == "charging"; }, 5.0));
  const json on = robot.State()["sim_true_pose"];
  EXPECT_LT(std::hypot(on["x"].get<double>() - 3.2, on["y"].get<double>() - 1.5), 0.03) << on.dump();
  const LockstepRobot::Reply undock =
      robot.Call("POST", "/api/v1/rmf/start_activity", {{"cmd_id", 11}, {"activity", "undock"}});
  ASSERT_EQ(undock.status, 201) << undock.body.dump();
  const json off = UntilDone(robot, 11, 30.0);
  EXPECT_EQ(off["completed"], true) << off.dump();
  const json backed = robot.State()["sim_true_pose"];
  EXPECT_GT(std::hypot(backed["x"].get<double>() - 3.2, backed["y"].get<double>() - 1.5), 0.3) << backed.dump();
  EXPECT_NE(RobotStatus(robot), "charging");
}

}  // namespace
}  // namespace corridor
