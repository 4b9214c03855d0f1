// Local navigation and people through the daemon's graph in simulated time (testing/lockstep_robot.h), in a 10 x 6 m
// room the map shows empty: a pillar only the camera sees is passed round by MORP-RB, a camera that stops answering
// stops the robot until it is back, and simulated people are tracked (by the laser, or without one in the camera's
// view), remembered where they turn round, and leave their mark on plans. Everything is checked against the
// simulator's truth at the same simulated instant. (The console drawing people, tracks and traffic, and the traffic
// image's transport, are tests/local_navigation_test.mjs.)
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include <Eigen/Core>

#include "testing/lockstep_robot.h"
#include "testing/sim_room.h"

namespace corridor {
namespace {

using nlohmann::json;
using testing::LockstepRobot;
using testing::SimRoom;

constexpr double kPillarX = 5.0, kPillarY = 3.05, kPillarR = 0.3;

// The room with the robot at its west end looking east; `laser`: the laser's driver (sim or none); `sim`: more keys of
// the sim section; `rest`: more sections.
SimRoom Room(const std::string& laser, const std::string& sim, const std::string& rest = "") {
  return SimRoom(10.0, 6.0,
                 "devices: {laser: {driver: " + laser +
                     "}}\n"
                     "sim:\n"
                     "  world: room.yaml\n"
                     "  start: {x_m: 1.5, y_m: 3.0, yaw_deg: 0}\n" +
                     sim + rest);
}

json Mission(LockstepRobot& robot, double x, double y) {
  const LockstepRobot::Reply started =
      robot.Call("POST", "/api/v1/missions", {{"waypoints", json::array({{{"x", x}, {"y", y}}})}});
  EXPECT_EQ(started.status, 201) << started.body.dump();
  return started.body;
}

double Speed(const json& state) { return std::abs(state["velocity"]["linear_mps"].get<double>()); }

SimRoom PillarRoom() {
  return Room("none",
              "  camera: {rate_hz: 15}\n"
              "  obstacles:\n"
              "    - {shape: cylinder, x_m: 5.0, y_m: 3.05, size_m: 0.3, height_m: 1.0}\n",
              // The 3D map would put the pillar in the planner's costmap once seen: this is about what the planner
              // does not know.
              "octomap: {costmap_layer: false}\n");
}

TEST(LocalNavigationLockstep, APillarOnThePlannedPathIsPassedAroundByMorpRbAtTheCameraRate) {
  const SimRoom room = PillarRoom();
  LockstepRobot robot(room.config());
  ASSERT_EQ(Mission(robot, 8.5, 3.0)["status"], "active");  // the plan goes straight through the pillar
  std::set<std::string> policies;
  double closest = std::numeric_limits<double>::infinity();
  bool bumped = false;
  const json state = robot.StateWhen(
      [&](const json& s) {
        if (s["mission"].is_object()) policies.insert(s["mission"]["policy"].get<std::string>());
        bumped = bumped || s["bumper_pressed"].get<bool>();
        const json& t = s["sim_true_pose"];
        closest = std::min(closest, std::hypot(t["x"].get<double>() - kPillarX, t["y"].get<double>() - kPillarY));
        return s["mission"]["status"] != "active";
      },
      90.0);
  ASSERT_EQ(state["mission"]["status"], "succeeded") << state["mission"].dump();
  EXPECT_FALSE(bumped) << "the bumper was pressed";
  EXPECT_GT(closest, kPillarR + 0.2) << "came that close to the pillar's centre";
  bool morp = false;
  for (const std::string& p : policies) morp = morp || p.starts_with("change_lane") || p == "stop_and_turn";
  EXPECT_TRUE(morp) << "MORP-RB never took over: " << json(policies).dump();
  // Commands followed the camera's frames, and the console can show how fast.
  EXPECT_GT(state["control_latency"]["samples"].get<int>(), 100) << state["control_latency"].dump();
  ASSERT_EQ(state["sim_obstacles"].size(), 1u);
  EXPECT_EQ(state["sim_obstacles"][0]["shape"], "cylinder");
}

TEST(LocalNavigationLockstep, TheCameraStopsAnsweringTheRobotStopsAtOnceAndGoesOnWhenItIsBack) {
  const SimRoom room = PillarRoom();
  LockstepRobot robot(room.config());
  Mission(robot, 6.5, 1.0);
  ASSERT_TRUE(robot.StepUntil([&] { return Speed(robot.State()) > 0.2; }, 20.0)) << "the robot never drove";
  ASSERT_EQ(robot.Call("PUT", "/api/v1/sim/faults", {{"camera_stopped", true}}).status, 200);
  // The safety budget: stopped within the depth timeout and what braking from its speed takes.
  ASSERT_TRUE(robot.StepUntil([&] { return Speed(robot.State()) < 0.005; }, 1.0)) << "still driving";
  const json stopped = robot.State();
  EXPECT_EQ(stopped["mission"]["status"], "active");
  robot.StepFor(1.0);
  const json still = robot.State();
  EXPECT_LT(Speed(still), 0.005) << "it does not stay stopped without frames";
  EXPECT_EQ(still["mission"]["policy"], "waiting_for_depth");
  // Bad requests change nothing.
  EXPECT_EQ(robot.Call("PUT", "/api/v1/sim/faults", {{"camera_stopped", "yes"}}).status, 400);
  EXPECT_EQ(robot.Call("PUT", "/api/v1/sim/faults", {{"lidar", true}}).status, 400);
  EXPECT_EQ(robot.State()["mission"]["policy"], "waiting_for_depth");
  ASSERT_EQ(robot.Call("PUT", "/api/v1/sim/faults", {{"camera_stopped", false}}).status, 200);
  const json done = robot.StateWhen([](const json& s) { return s["mission"]["status"] != "active"; }, 60.0);
  EXPECT_EQ(done["mission"]["status"], "succeeded") << done["mission"].dump();
}

// A person whose track matches them: moving near them, at about their velocity (a sensor sees a person's near side).
// A moving track within `within_m` of `person` for which `also` holds.
bool TrackNear(const json& state, const json& person, double within_m, const std::function<bool(const json&)>& also) {
  for (const json& o : state["tracked_objects"]) {
    const double off_m =
        std::hypot(o["x"].get<double>() - person["x"].get<double>(), o["y"].get<double>() - person["y"].get<double>());
    if (o["moving"].get<bool>() && off_m < within_m && also(o)) return true;
  }
  return false;
}

bool Tracked(const json& state, const json& person, double within_m, double speed_within_mps) {
  return TrackNear(state, person, within_m, [&](const json& o) {
    return std::hypot(o["vx"].get<double>() - person["vx"].get<double>(),
                      o["vy"].get<double>() - person["vy"].get<double>()) < speed_within_mps;
  });
}

// Steps until `found(state, person)` holds of someone among the simulated people (at most max_s); `state` is the last
// state taken.
bool UntilSomeone(LockstepRobot& robot, json& state,
                  const std::function<bool(const json& state, const json& person)>& found, double max_s) {
  state = robot.StateWhen(
      [&](const json& s) {
        for (const json& p : s["sim_pedestrians"]) {
          if (found(s, p)) return true;
        }
        return false;
      },
      max_s);
  for (const json& p : state["sim_pedestrians"]) {
    if (found(state, p)) return true;
  }
  return false;
}

std::string TrackingHealth(const json& state) {
  for (const json& n : state["nodes"]) {
    if (n["name"] == "tracking") return n["health"].get<std::string>();
  }
  return "no tracking node";
}

double SpeedOf(const json& person) { return std::hypot(person["vx"].get<double>(), person["vy"].get<double>()); }

// The bearing of `person` from the robot (radians, from straight ahead) and their distance.
std::pair<double, double> Seen(const json& state, const json& person) {
  const json& pose = state["sim_true_pose"];
  const double dx = person["x"].get<double>() - pose["x"].get<double>();
  const double dy = person["y"].get<double>() - pose["y"].get<double>();
  const double bearing = std::atan2(dy, dx) - pose["yaw"].get<double>();
  return {std::abs(std::atan2(std::sin(bearing), std::cos(bearing))), std::hypot(dx, dy)};
}

TEST(LocalNavigationLockstep, PeopleWalkAreTrackedByTheLaserRememberedWhereTheyTurnAndLeaveTheirMarkOnPlans) {
  const SimRoom room = Room("sim",
                            "  camera: {width: 160, height: 120}\n"
                            "  pedestrians: 2\n",
                            // decisive on the short stretch the plan below is made over
                            "tracking:\n  traffic: {weight: 10, lane_half_width_m: 0.5}\n");
  LockstepRobot robot(room.config());
  const json first = robot.State();
  ASSERT_EQ(first["sim_pedestrians"].size(), 2u);
  robot.StepFor(1.0);
  const json later = robot.State();
  bool moved = false;
  for (std::size_t i = 0; i < 2; ++i) {
    const json& a = first["sim_pedestrians"][i];
    const json& b = later["sim_pedestrians"][i];
    moved = moved ||
            std::hypot(b["x"].get<double>() - a["x"].get<double>(), b["y"].get<double>() - a["y"].get<double>()) > 0.2;
  }
  EXPECT_TRUE(moved) << "nobody walked";

  json state;
  EXPECT_TRUE(UntilSomeone(
      robot, state, [](const json& s, const json& p) { return SpeedOf(p) > 0.4 && Tracked(s, p, 0.5, 0.3); }, 8.0))
      << "no person tracked by the laser at their velocity";
  EXPECT_EQ(TrackingHealth(state), "ok");

  // People pace between two points: once a person has turned round at an end, walking back to it they are reported
  // with it ahead (the robot expects them to turn there).
  EXPECT_TRUE(robot.StepUntil(
      [&] {
        state = robot.State();  // kept: the loop below reads into it
        for (const json& o : state["tracked_objects"]) {
          if (!o["moving"].get<bool>() || !o.contains("walk_end")) continue;
          const double ahead = (o["walk_end"]["x"].get<double>() - o["x"].get<double>()) * o["vx"].get<double>() +
                               (o["walk_end"]["y"].get<double>() - o["y"].get<double>()) * o["vy"].get<double>();
          if (ahead > 0.0) return true;
        }
        return false;
      },
      40.0))
      << "no person with the end of their walk ahead";

  // Where someone walks: watched for 3 s, every place they pass is on their way. A plan from one end of what they
  // walked to the other would run straight along it; with the laser's traffic costs it keeps to one side.
  std::size_t who = 0;
  ASSERT_TRUE(robot.StepUntil(
      [&] {
        const json people = robot.State()["sim_pedestrians"];
        for (std::size_t i = 0; i < people.size(); ++i) {
          if (SpeedOf(people[i]) > 0.5) {
            who = i;
            return true;
          }
        }
        return false;
      },
      8.0));
  std::vector<Eigen::Vector2d> seen;
  for (int i = 0; i < 12; ++i) {
    const json p = robot.State()["sim_pedestrians"][who];
    seen.emplace_back(p["x"].get<double>(), p["y"].get<double>());
    robot.StepFor(0.25);
  }
  Eigen::Vector2d a = seen[0], b = seen[0];
  for (const auto& p : seen) {
    for (const auto& q : seen) {
      if ((p - q).norm() > (a - b).norm()) std::tie(a, b) = std::tie(p, q);
    }
  }
  const double walked = (a - b).norm();
  ASSERT_GT(walked, 1.2) << "the person walked only that far";
  robot.StepFor(1.5);  // the tracker hands its traffic costs to the planner every second
  const LockstepRobot::Reply plan = robot.Call(
      "POST", "/api/v1/plan", {{"start", {{"x", a.x()}, {"y", a.y()}}}, {"goal", {{"x", b.x()}, {"y", b.y()}}}});
  ASSERT_EQ(plan.status, 200) << plan.body.dump();
  double farthest = 0.0;  // how far the path's corners stray from the straight line a-b
  for (const json& p : plan.body["path"]) {
    const Eigen::Vector2d c(p["x"].get<double>(), p["y"].get<double>());
    farthest =
        std::max(farthest, std::abs((b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x())) / walked);
  }
  EXPECT_GT(farthest, 0.4) << "the plan runs along their way: " << plan.body["path"].dump();
}

TEST(LocalNavigationLockstep, WithoutALaserPeopleAreTrackedInTheCamerasViewAndKeptWhenTheyWalkOutOfIt) {
  const SimRoom room = Room("none",
                            "  camera: {width: 160, height: 120}\n"
                            "  pedestrians: 2\n");
  LockstepRobot robot(room.config());
  // The robot looks down the room: a person walking in front of it shows as a moving object near them, going their
  // way (the camera sees a person's near side: hence the tolerances).
  json state;
  EXPECT_TRUE(UntilSomeone(
      robot, state,
      [](const json& s, const json& p) {
        const auto [bearing, distance] = Seen(s, p);
        return bearing < 0.6 && distance < 5.0 && SpeedOf(p) > 0.4 && Tracked(s, p, 0.6, 0.4);
      },
      20.0))
      << "no person tracked by the camera";
  EXPECT_EQ(TrackingHealth(state), "ok");
  // A person beside the robot, out of the camera's 85 degrees, with a moving track near them that says it is not seen:
  // kept on its prediction (tracking.unseen_coast_s) rather than forgotten.
  EXPECT_TRUE(UntilSomeone(
      robot, state,
      [](const json& s, const json& p) {
        const auto [bearing, distance] = Seen(s, p);
        return bearing > 0.9 && distance < 4.0 &&
               TrackNear(s, p, 0.8, [](const json& o) { return !o["seen"].get<bool>(); });
      },
      40.0))
      << "no person out of view still tracked";
}

}  // namespace
}  // namespace corridor
