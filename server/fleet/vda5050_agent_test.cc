#include "server/fleet/vda5050_agent.h"

#include <gtest/gtest.h>

#include <map>

#include "server/fleet/vda5050.h"

namespace corridor::server {
namespace {

using json = nlohmann::json;

json Node(const std::string& id, int sequence, bool released, double x, double y, json actions = json::array()) {
  return {{"nodeId", id},
          {"sequenceId", sequence},
          {"released", released},
          {"nodePosition", {{"x", x}, {"y", y}, {"mapId", "willow"}}},
          {"actions", std::move(actions)}};
}

json Edge(const std::string& from, const std::string& to, int sequence, bool released, json actions = json::array()) {
  return {{"edgeId", from + "-" + to}, {"sequenceId", sequence}, {"released", released},
          {"startNodeId", from},       {"endNodeId", to},        {"actions", std::move(actions)}};
}

json Say(const std::string& id, const std::string& text) {
  return {{"actionType", "say"},
          {"actionId", id},
          {"blockingType", "NONE"},
          {"actionParameters", {{{"key", "text"}, {"value", text}}}}};
}

json Order(const std::string& id, int update, json nodes, json edges) {
  return {{"headerId", 1},
          {"timestamp", "2026-11-26T04:40:00.00Z"},
          {"version", "2.1.0"},
          {"manufacturer", "corridor"},
          {"serialNumber", "r1"},
          {"orderId", id},
          {"orderUpdateId", update},
          {"nodes", std::move(nodes)},
          {"edges", std::move(edges)}};
}

json Instant(const std::string& type, const std::string& id, json params = json::array()) {
  return {
      {"headerId", 2},
      {"timestamp", "2026-11-26T04:40:00.00Z"},
      {"version", "2.1.0"},
      {"manufacturer", "corridor"},
      {"serialNumber", "r1"},
      {"actions", {{{"actionType", type}, {"actionId", id}, {"blockingType", "HARD"}, {"actionParameters", params}}}}};
}

// A released base a-b-c and a horizon d, the robot standing on a.
json FirstOrder() {
  return Order("o1", 0,
               {Node("a", 0, true, 0, 0), Node("b", 2, true, 1, 0, {Say("s1", "hello")}), Node("c", 4, true, 2, 0),
                Node("d", 6, false, 3, 0)},
               {Edge("a", "b", 1, true), Edge("b", "c", 3, true, {Say("s2", "on my way")}), Edge("c", "d", 5, false)});
}

class VdaAgentTest : public ::testing::Test {
 protected:
  VdaAgentTest()
      : agent_({}, [](const nav::Pose2& near) -> std::optional<nav::MissionGoal> {
          if (std::hypot(near.x_m - 5.0, near.y_m) > 2.0) return std::nullopt;
          nav::MissionGoal goal;
          goal.action = nav::GoalAction::kDock;
          goal.pose = {5.0, 0.7, 0.0};
          goal.dock = {5.0, 0.0, 0.0};
          return goal;
        }) {
    robot_.pose = nav::Pose2{0.05, 0.0, 0.0};
    robot_.map_id = "willow";
    robot_.can_set_pose = true;
  }

  json State() {
    VdaRobot robot;
    robot.battery_percent = 80.0;  // the agent's own errors are the only ones
    json state = VdaState({"uagv", "corridor", "r1"}, {1, "2026-11-26T04:40:00.000Z"}, robot);
    agent_.FillState(state);
    const auto errors = schemas_.Check(VdaMessage::kState, state);
    EXPECT_TRUE(errors.empty()) << errors.front() << "\n" << state.dump();
    return state;
  }
  std::vector<std::string> NodeIds() {
    std::vector<std::string> ids;
    const json state = State();
    for (const json& n : state["nodeStates"]) ids.push_back(n["nodeId"]);
    return ids;
  }
  std::string ActionStatus(const std::string& id) {
    const json state = State();
    for (const json& a : state["actionStates"]) {
      if (a["actionId"] == id) return a["actionStatus"];
    }
    return "";
  }
  std::string FirstErrorType() {
    const json state = State();
    return state["errors"].empty() ? "" : state["errors"][0]["errorType"].get<std::string>();
  }

  VdaSchemas schemas_;
  VdaAgent agent_;
  VdaRobotNow robot_;
};

TEST_F(VdaAgentTest, AnOrdersBaseBecomesAMissionAndItsProgressTheNodeStates) {
  VdaCommands c = agent_.Order(FirstOrder(), robot_);
  ASSERT_TRUE(c.start);
  ASSERT_EQ(c.start->size(), 2u);  // a is where the robot stands: traversed at once
  EXPECT_EQ((*c.start)[0].place, "b");
  EXPECT_EQ((*c.start)[1].pose.x_m, 2.0);
  EXPECT_EQ(NodeIds(), (std::vector<std::string>{"b", "c", "d"}));
  EXPECT_EQ(State()["lastNodeId"], "a");
  agent_.Started("m1", 0);
  EXPECT_TRUE(agent_.Busy());
  // b reached: its action says hello, the edge to c is entered and says its phrase.
  c = agent_.Progress({"m1", nav::MissionStatus::kActive, 1, 2, ""});
  EXPECT_EQ(c.say, (std::vector<std::string>{"hello", "on my way"}));
  EXPECT_EQ(NodeIds(), (std::vector<std::string>{"c", "d"}));
  EXPECT_EQ(ActionStatus("s1"), "FINISHED");
  EXPECT_EQ(State()["lastNodeSequenceId"], 2);
  c = agent_.Progress({"m1", nav::MissionStatus::kSucceeded, 1, 2, ""});
  EXPECT_EQ(NodeIds(), (std::vector<std::string>{"d"}));  // the horizon waits for an update
  // As the map shows it: c just traversed, then d; the edge c-d joins them.
  const FleetOrder view = agent_.Describe();
  ASSERT_EQ(view.nodes.size(), 2u);
  EXPECT_TRUE(view.nodes[0].traversed);
  EXPECT_EQ(view.nodes[0].x, 2.0);
  EXPECT_FALSE(view.nodes[1].released);
  ASSERT_EQ(view.edges.size(), 1u);
  EXPECT_EQ(view.edges[0].start, "c");
  EXPECT_EQ(ActionStatus("s2"), "FINISHED");
  EXPECT_EQ(State()["edgeStates"].size(), 1u);
}

TEST_F(VdaAgentTest, AnOrderTheCoreRefusesIsNotTakenAndTheErrorNamesTheOrderAndTheNode) {
  agent_.Order(Order("o1", 0, {Node("a", 0, true, 0, 0), Node("b", 2, true, 1, 0)}, {Edge("a", "b", 1, true)}), robot_);
  agent_.Started("m1", 0);
  agent_.Progress({"m1", nav::MissionStatus::kSucceeded, 1, 1, ""});
  ASSERT_FALSE(agent_.Busy());
  // o2's node w is in a wall: the core refuses the mission.
  robot_.pose = nav::Pose2{1.0, 0.0, 0.0};
  VdaCommands c =
      agent_.Order(Order("o2", 0, {Node("b", 0, true, 1, 0), Node("w", 2, true, 4, 0, {Say("s9", "there")})},
                         {Edge("b", "w", 1, true)}),
                   robot_);
  ASSERT_TRUE(c.start);
  EXPECT_EQ((*c.start)[0].place, "w");
  c = agent_.Refused("noRouteError", "node w is occupied or too close to an obstacle", "w");
  EXPECT_TRUE(c.send_state);
  const json state = State();
  EXPECT_EQ(state["orderId"], "o1");
  EXPECT_EQ(state["orderUpdateId"], 0);
  EXPECT_TRUE(state["nodeStates"].empty());
  EXPECT_EQ(ActionStatus("s9"), "");  // its actions went with it
  ASSERT_EQ(state["errors"].size(), 1u);
  const json& error = state["errors"][0];
  EXPECT_EQ(error["errorType"], "noRouteError");
  std::map<std::string, std::string> refs;
  for (const json& r : error["errorReferences"]) refs[r["referenceKey"]] = r["referenceValue"];
  EXPECT_EQ(refs["orderId"], "o2");
  EXPECT_EQ(refs["nodeId"], "w");
  EXPECT_FALSE(agent_.Busy());
  // The master control may send another order at once.
  c = agent_.Order(Order("o3", 0, {Node("b", 0, true, 1, 0), Node("e", 2, true, 1, 1)}, {Edge("b", "e", 1, true)}),
                   robot_);
  EXPECT_TRUE(c.start);
  EXPECT_EQ(State()["orderId"], "o3");
}

TEST_F(VdaAgentTest, AnUpdateStitchesOntoTheDecisionPointAndExtendsTheMission) {
  agent_.Order(FirstOrder(), robot_);
  agent_.Started("m1", 0);
  json update = Order("o1", 1, {Node("c", 4, true, 2, 0), Node("d", 6, true, 3, 0), Node("e", 8, false, 4, 0)},
                      {Edge("c", "d", 5, true), Edge("d", "e", 7, false)});
  VdaCommands c = agent_.Order(update, robot_);
  ASSERT_EQ(c.extend.size(), 1u);
  EXPECT_EQ(c.extend[0].place, "d");
  agent_.Extended();
  EXPECT_EQ(NodeIds(), (std::vector<std::string>{"b", "c", "d", "e"}));
  EXPECT_EQ(State()["orderUpdateId"], 1);
  // The same update again is ignored; an older one is refused and changes nothing.
  c = agent_.Order(update, robot_);
  EXPECT_TRUE(c.extend.empty() && !c.start);
  c = agent_.Order(Order("o1", 0, {Node("c", 4, true, 2, 0)}, json::array()), robot_);
  EXPECT_EQ(FirstErrorType(), "orderUpdateError");
  // An update that does not start at the decision point is refused.
  c = agent_.Order(Order("o1", 2, {Node("b", 2, true, 1, 0)}, json::array()), robot_);
  EXPECT_TRUE(c.extend.empty());
  EXPECT_EQ(NodeIds().size(), 4u);
  // All three goals reached: d is traversed; e stays as the horizon.
  agent_.Progress({"m1", nav::MissionStatus::kSucceeded, 2, 3, ""});
  EXPECT_EQ(NodeIds(), (std::vector<std::string>{"e"}));
  EXPECT_EQ(State()["lastNodeId"], "d");
  // Once the mission has ended, the next update starts a new mission from the last node.
  c = agent_.Order(Order("o1", 3, {Node("d", 6, true, 3, 0), Node("e", 8, true, 4, 0)}, {Edge("d", "e", 7, true)}),
                   robot_);
  ASSERT_TRUE(c.start);
  EXPECT_EQ((*c.start)[0].place, "e");
  EXPECT_TRUE(State()["errors"].empty());  // a taken update clears the rejections
}

TEST_F(VdaAgentTest, OrdersItCannotDoAreRefusedWithTheStandardsErrors) {
  robot_.pose = nav::Pose2{3.0, 3.0, 0.0};
  VdaCommands c = agent_.Order(FirstOrder(), robot_);
  EXPECT_FALSE(c.start);
  EXPECT_EQ(FirstErrorType(), "orderError");  // not at the first node
  EXPECT_FALSE(agent_.has_order());
  robot_.pose = nav::Pose2{0.0, 0.0, 0.0};
  json pick = FirstOrder();
  pick["nodes"][1]["actions"] = {{{"actionType", "pick"}, {"actionId", "p1"}, {"blockingType", "HARD"}}};
  agent_.Order(pick, robot_);
  EXPECT_EQ(State()["errors"].back()["errorReferences"][0]["referenceValue"], "p1");
  json other_map = FirstOrder();
  other_map["nodes"][2]["nodePosition"]["mapId"] = "level2";
  agent_.Order(other_map, robot_);
  json released_after_horizon = FirstOrder();
  released_after_horizon["nodes"][2]["released"] = false;
  agent_.Order(released_after_horizon, robot_);
  EXPECT_EQ(State()["errors"].size(), 4u);
  EXPECT_FALSE(agent_.has_order());
  // A good order clears them; a second order while it runs is refused.
  agent_.Order(FirstOrder(), robot_);
  agent_.Started("m1", 0);
  EXPECT_TRUE(State()["errors"].empty());
  c = agent_.Order(Order("o2", 0, {Node("a", 0, true, 0, 0)}, json::array()), robot_);
  EXPECT_EQ(FirstErrorType(), "orderUpdateError");
  EXPECT_EQ(State()["orderId"], "o1");
  agent_.Invalid("order", {"nodes[0].sequenceId: not an integer"});
  EXPECT_EQ(State()["errors"].back()["errorType"], "validationError");
}

TEST_F(VdaAgentTest, PauseCancelAndTheInstantActions) {
  agent_.Order(FirstOrder(), robot_);
  agent_.Started("m1", 0);
  VdaCommands c = agent_.InstantActions(Instant("startPause", "i1"), robot_);
  EXPECT_TRUE(c.pause);
  EXPECT_TRUE(agent_.paused());
  c = agent_.InstantActions(Instant("stopPause", "i2"), robot_);
  EXPECT_TRUE(c.resume);
  c = agent_.InstantActions(Instant("cancelOrder", "i3"), robot_);
  EXPECT_EQ(c.cancel, "m1");
  EXPECT_TRUE(NodeIds().empty());
  EXPECT_EQ(ActionStatus("i3"), "FINISHED");
  EXPECT_EQ(ActionStatus("s1"), "FAILED");  // the order's actions that had not run
  EXPECT_EQ(State()["orderId"], "o1");      // kept, as the standard says
  EXPECT_FALSE(agent_.Busy());
  // Nothing to cancel now.
  agent_.InstantActions(Instant("cancelOrder", "i4"), robot_);
  EXPECT_EQ(ActionStatus("i4"), "FAILED");
  EXPECT_EQ(FirstErrorType(), "noOrderToCancel");
  c = agent_.InstantActions(Instant("factsheetRequest", "i5"), robot_);
  EXPECT_TRUE(c.send_factsheet);
  c = agent_.InstantActions(Instant("initPosition", "i6",
                                    {{{"key", "x"}, {"value", 1.5}},
                                     {{"key", "y"}, {"value", 2.5}},
                                     {{"key", "theta"}, {"value", 0.3}},
                                     {{"key", "mapId"}, {"value", "willow"}}}),
                            robot_);
  ASSERT_TRUE(c.set_pose);
  EXPECT_DOUBLE_EQ(c.set_pose->y_m, 2.5);
  EXPECT_EQ(ActionStatus("i6"), "RUNNING");  // until the robot core answers
  agent_.PoseAnswered(c.set_pose_action, "");
  EXPECT_EQ(ActionStatus("i6"), "FINISHED");
  c = agent_.InstantActions(Instant("initPosition", "i9",
                                    {{{"key", "x"}, {"value", 900.0}},
                                     {{"key", "y"}, {"value", 2.5}},
                                     {{"key", "theta"}, {"value", 0.3}},
                                     {{"key", "mapId"}, {"value", "willow"}}}),
                            robot_);
  agent_.PoseAnswered(c.set_pose_action, "(900, 2.5) is not on map 'willow'");
  EXPECT_EQ(ActionStatus("i9"), "FAILED");
  const json refused = State()["errors"].back();
  EXPECT_EQ(refused["errorType"], "actionError");
  EXPECT_NE(refused["errorDescription"].get<std::string>().find("not on map"), std::string::npos);
  c = agent_.InstantActions(Instant("initPosition", "i7", {{{"key", "x"}, {"value", "left"}}}), robot_);
  EXPECT_FALSE(c.set_pose);
  EXPECT_EQ(ActionStatus("i7"), "FAILED");
  agent_.InstantActions(Instant("pick", "i8"), robot_);
  EXPECT_EQ(ActionStatus("i8"), "FAILED");
}

TEST_F(VdaAgentTest, ChargingOnANodeDocksThereAndStoppingBacksOff) {
  robot_.pose = nav::Pose2{4.0, 0.0, 0.0};
  json charge = {{"actionType", "startCharging"}, {"actionId", "c1"}, {"blockingType", "HARD"}};
  VdaCommands c = agent_.Order(
      Order("o1", 0, {Node("a", 0, true, 4, 0), Node("dock", 2, true, 5, 0.7, {charge})}, {Edge("a", "dock", 1, true)}),
      robot_);
  ASSERT_TRUE(c.start);
  EXPECT_EQ((*c.start)[0].action, nav::GoalAction::kDock);
  agent_.Started("m1", 0);
  agent_.Progress({"m1", nav::MissionStatus::kSucceeded, 0, 1, ""});
  EXPECT_EQ(ActionStatus("c1"), "FINISHED");
  // Docked, a new order from the dock node that stops charging backs off first.
  robot_.docked = true;
  robot_.pose = nav::Pose2{5.0, 0.0, 0.0};
  json stop = {{"actionType", "stopCharging"}, {"actionId", "c2"}, {"blockingType", "HARD"}};
  c = agent_.Order(
      Order("o2", 0, {Node("dock", 0, true, 5, 0, {stop}), Node("b", 2, true, 3, 0)}, {Edge("dock", "b", 1, true)}),
      robot_);
  ASSERT_TRUE(c.start);
  ASSERT_EQ(c.start->size(), 2u);
  EXPECT_EQ((*c.start)[0].action, nav::GoalAction::kUndock);
  agent_.Started("m2", 0);
  EXPECT_EQ(ActionStatus("c2"), "RUNNING");
  agent_.Progress({"m2", nav::MissionStatus::kActive, 1, 2, ""});
  EXPECT_EQ(ActionStatus("c2"), "FINISHED");
  // No dock near a node that asks to charge: refused.
  robot_.docked = false;
  agent_.Progress({"m2", nav::MissionStatus::kSucceeded, 1, 2, ""});
  robot_.pose = nav::Pose2{3.0, 0.0, 0.0};
  agent_.Order(
      Order("o3", 0, {Node("b", 0, true, 3, 0), Node("far", 2, true, 20, 0, {charge})}, {Edge("b", "far", 1, true)}),
      robot_);
  EXPECT_EQ(FirstErrorType(), "orderError");
}

TEST_F(VdaAgentTest, AMissionStartedBySomeoneElseEndsTheOrdersWithANavigationError) {
  agent_.Order(FirstOrder(), robot_);
  agent_.Started("m1", 0);
  agent_.Progress({"m1", nav::MissionStatus::kActive, 0, 2, ""});
  agent_.Started("m2", 0);  // an update handed on to a mission of its own: a late word of m1 is not news
  EXPECT_FALSE(agent_.Progress({"m1", nav::MissionStatus::kActive, 0, 2, ""}).send_state);
  EXPECT_EQ(FirstErrorType(), "");
  const VdaCommands c = agent_.Progress({"console", nav::MissionStatus::kActive, 0, 1, ""});
  EXPECT_TRUE(c.send_state);
  EXPECT_EQ(FirstErrorType(), "navigationError");
  EXPECT_EQ(NodeIds().size(), 3u);  // the nodes stay the master's to hand on
  EXPECT_FALSE(agent_.Progress({"console", nav::MissionStatus::kSucceeded, 1, 1, ""}).send_state);
}

TEST_F(VdaAgentTest, AFailedMissionLeavesTheNodesForTheMasterAndSaysWhy) {
  agent_.Order(FirstOrder(), robot_);
  agent_.Started("m1", 0);
  agent_.Progress({"m1", nav::MissionStatus::kFailed, 0, 2, "no path to the goal"});
  EXPECT_EQ(NodeIds().size(), 3u);
  EXPECT_EQ(FirstErrorType(), "navigationError");
  // cancelOrder then ends it; the state still validates throughout (State() checks every time).
  EXPECT_EQ(agent_.InstantActions(Instant("cancelOrder", "x"), robot_).cancel, "");
  EXPECT_FALSE(agent_.Busy());
}

TEST(VdaAgentFactsheetTest, TheActionsItDoesAreInAValidFactsheet) {
  json factsheet = VdaFactsheet({"uagv", "corridor", "r1"}, {1, "2026-11-26T04:40:00.000Z"}, VdaVehicle{});
  factsheet["protocolFeatures"]["agvActions"] = VdaAgent::FactsheetActions();
  const auto errors = VdaSchemas().Check(VdaMessage::kFactsheet, factsheet);
  EXPECT_TRUE(errors.empty()) << errors.front();
  EXPECT_GE(factsheet["protocolFeatures"]["agvActions"].size(), 9u);
}

}  // namespace
}  // namespace corridor::server
