// A camera on a pan servo through the daemon's graph in simulated time (testing/lockstep_robot.h): each frame read
// with the camera's pose when it was taken (what is beside the robot is seen where it is), the gaze turning the
// camera along a mission that arrives, and a servo whose readings stop stopping the robot.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "server/runtime/topics.h"
#include "testing/lockstep_robot.h"
#include "testing/sim_room.h"

namespace corridor {
namespace {

using nlohmann::json;
using testing::LockstepRobot;
using testing::SimRoom;

constexpr double kRad = std::numbers::pi / 180.0;
// A pillar 60 degrees to the left of the camera (at x 1.6, y 3.0 looking east), 1.5 m from it: outside its 85 degree
// view until it turns.
const Eigen::Vector2d kPillar(1.6 + 1.5 * std::cos(60.0 * kRad), 3.0 + 1.5 * std::sin(60.0 * kRad));

SimRoom PanRoom(const std::string& gaze) {
  return SimRoom(10.0, 6.0,
                 "devices: {laser: {driver: none}, camera: {driver: sim, pan: {driver: sim}}}\n"
                 "sim:\n"
                 "  world: room.yaml\n"
                 "  start: {x_m: 1.5, y_m: 3.0, yaw_deg: 0}\n"
                 "  obstacles:\n"
                 "    - {shape: cylinder, x_m: " +
                     std::to_string(kPillar.x()) + ", y_m: " + std::to_string(kPillar.y()) +
                     ", size_m: 0.2, height_m: 1.0}\n"
                     "gaze: {" +
                     gaze + "}\n");
}

// The latest depth scan's points (base frame) within `radius_m` of `at` (map frame, the robot not having moved).
int ScanPointsNear(LockstepRobot& robot, const Eigen::Vector2d& at, double radius_m) {
  const auto lanes = robot.graph().bus().Get(server::topics::kGroundLanes).latest();
  if (!lanes) return 0;
  const Eigen::Vector2d local = robot.sim().true_pose().Inverse().Transform(at);
  return static_cast<int>(std::count_if(lanes->scan.begin(), lanes->scan.end(),
                                        [&](const Eigen::Vector2d& p) { return (p - local).norm() < radius_m; }));
}

TEST(GazeLockstep, ACameraTurnedOnItsServoSeesWhatIsBesideTheRobotWhereItIs) {
  const SimRoom room = PanRoom("enabled: false");
  LockstepRobot robot(room.config());
  robot.StepFor(1.0);
  EXPECT_EQ(ScanPointsNear(robot, kPillar, 0.35), 0) << "the pillar is out of view";
  const auto frame = robot.graph().bus().Get(server::topics::kRgbd).latest();
  ASSERT_TRUE(frame && frame->base_T_camera.has_value()) << "frames carry the camera's pose";
  // Turned 60 degrees to the left: the pillar's near side, where it stands (not straight ahead, where the camera at
  // rest would put it).
  robot.graph().bus().Get(server::topics::kCameraPanTarget).Publish(60.0 * kRad);
  ASSERT_TRUE(robot.StepUntil([&] { return std::abs(robot.sim().pan_rad() - 60.0 * kRad) < 1e-6; }, 2.0));
  robot.StepFor(0.5);
  const auto readings = robot.graph().bus().Get(server::topics::kCameraPan).latest();
  ASSERT_TRUE(readings);
  EXPECT_NEAR(readings->pan_rad, 60.0 * kRad, 1e-6);
  EXPECT_GT(ScanPointsNear(robot, kPillar, 0.35), 10);
  const auto lanes = robot.graph().bus().Get(server::topics::kGroundLanes).latest();
  for (const Eigen::Vector2d& p : lanes->scan) {
    EXPECT_GT(p.y(), -0.05) << "a point right of the robot, where the camera does not look: " << p.transpose();
  }
  // The tracker has it there too (map frame), and the devices are well.
  const json state = robot.State();
  bool tracked = false;
  for (const json& o : state["tracked_objects"]) {
    tracked = tracked || std::hypot(o["x"].get<double>() - kPillar.x(), o["y"].get<double>() - kPillar.y()) < 0.4;
  }
  EXPECT_TRUE(tracked) << state["tracked_objects"].dump();
}

TEST(GazeLockstep, TheGazeTurnsTheCameraAlongAMissionThatArrives) {
  const SimRoom room = PanRoom("enabled: true");
  LockstepRobot robot(room.config());
  // Behind the robot to its right: it turns on the spot, then drives.
  const LockstepRobot::Reply started =
      robot.Call("POST", "/api/v1/missions", {{"waypoints", json::array({{{"x", 1.2}, {"y", 1.2}, {"yaw", 0.0}}})}});
  ASSERT_EQ(started.status, 201) << started.body.dump();
  double widest = 0.0;
  bool bumped = false;
  const json state = robot.StateWhen(
      [&](const json& s) {
        widest = std::max(widest, std::abs(robot.sim().pan_rad()));
        bumped = bumped || s["bumper_pressed"].get<bool>();
        return s["mission"]["status"] != "active";
      },
      60.0);
  EXPECT_EQ(state["mission"]["status"], "succeeded") << state["mission"].dump();
  EXPECT_FALSE(bumped);
  EXPECT_GT(widest, 10.0 * kRad) << "the camera never looked along the path";
  // Done: it looks ahead again.
  ASSERT_TRUE(robot.StepUntil([&] { return std::abs(robot.sim().pan_rad()) < 1e-6; }, 4.0)) << robot.sim().pan_rad();
}

TEST(GazeLockstep, APanServoWhoseReadingsStopStopsTheRobotUntilTheyAreBack) {
  const SimRoom room = PanRoom("enabled: true");
  LockstepRobot robot(room.config());
  const json forward{{"linear_mps", 0.3}, {"angular_rps", 0.0}};
  const auto driving = [&] {
    robot.Call("POST", "/api/v1/teleop", forward);
    return robot.State()["command"]["linear_mps"].get<double>() > 0.0;
  };
  ASSERT_TRUE(robot.StepUntil(driving, 2.0));
  robot.sim().SetPanStopped(true);  // where the camera looks is no longer known: its frames are not used
  ASSERT_TRUE(robot.StepUntil(
      [&] {
        robot.Call("POST", "/api/v1/teleop", forward);
        return robot.State()["stop_reason"] == "no depth frames: not driving forward";
      },
      2.0))
      << robot.State()["stop_reason"];
  robot.sim().SetPanStopped(false);
  EXPECT_TRUE(robot.StepUntil(driving, 2.0));
}

}  // namespace
}  // namespace corridor
