// VDA 5050's order logic through the daemon's graph in simulated time (testing/lockstep_robot.h), with a real
// mosquitto broker between the robot and a master control (this test, on the project's MQTT client): an order with a
// horizon driven to its decision point at the edge's speed, extended, paused and resumed; cancelOrder; an order to a
// node in a wall refused on arrival; startCharging and stopCharging. Each message either side sends is delivered before
// simulated time moves on (the robot's node counts what it received and what it sent), so the machine's load cannot
// decide a run. What needs the daemon's own transport and real time (going online, bad JSON, the broker restarting,
// the last will, the console's view of an order, every message against the standard's schemas) is
// tests/vda5050_test.mjs.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <condition_variable>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "server/fleet/mqtt_link.h"
#include "testing/lockstep_robot.h"
#include "testing/mosquitto.h"
#include "testing/sim_room.h"

namespace corridor {
namespace {

using nlohmann::json;
using testing::LockstepRobot;

const std::string kPrefix = "uagv/v2/corridor/r1/";
const std::string kMap = "room";
const std::string kProbe = "corridor-test/probe";  // the master's own topic, to learn that its subscriptions stand

// The master control: what the robot publishes on its four topics, in order of arrival; what it sends, with the
// standard's header.
class Master {
 public:
  explicit Master(const std::string& broker)
      : link_(
            [&] {
              server::MqttLinkOptions o;
              o.broker = broker;
              o.client_id = "master";
              for (const char* topic : {"state", "connection", "visualization", "factsheet"}) {
                o.subscriptions.push_back(kPrefix + topic);
              }
              o.subscriptions.push_back(kProbe);
              o.subscription_qos = 1;
              return o;
            }(),
            [this](std::string topic, std::string payload) { Arrived(std::move(topic), payload); }, [] {}) {
    link_.Connect();
  }

  struct Message {
    std::string topic;  // without the prefix
    json body;
  };

  void Publish(const std::string& topic, json body) {
    body["headerId"] = header_id_++;
    body["timestamp"] = "2026-11-29T08:00:00.000Z";
    body["version"] = "2.1.0";
    body["manufacturer"] = "corridor";
    body["serialNumber"] = "r1";
    link_.Publish({kPrefix + topic, body.dump(), 1, false});
  }
  std::size_t count() {
    std::lock_guard lock(mutex_);
    return messages_.size();
  }
  // The first `topic` message from index `since` on for which `holds` does.
  std::optional<json> Find(const std::string& topic, const std::function<bool(const json&)>& holds,
                           std::size_t since = 0) {
    std::lock_guard lock(mutex_);
    for (std::size_t i = since; i < messages_.size(); ++i) {
      if (messages_[i].topic == topic && holds(messages_[i].body)) return messages_[i].body;
    }
    return std::nullopt;
  }
  std::vector<Message> All(const std::string& topic, std::size_t since = 0) {
    std::lock_guard lock(mutex_);
    std::vector<Message> out;
    for (std::size_t i = since; i < messages_.size(); ++i) {
      if (messages_[i].topic == topic) out.push_back(messages_[i]);
    }
    return out;
  }
  // Waits (real time) until a message arrives after the first `seen`, or `ms` passes.
  void AwaitMore(std::size_t seen, int ms) {
    std::unique_lock lock(mutex_);
    arrived_.wait_for(lock, std::chrono::milliseconds(ms), [&] { return messages_.size() > seen; });
  }
  bool connected() const { return link_.connected(); }
  // Publishes on the probe topic until one comes back (at most 10 s): from then on nothing the robot sends is missed.
  bool AwaitSubscribed() {
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    std::unique_lock lock(mutex_);
    while (!probed_ && std::chrono::steady_clock::now() < end) {
      lock.unlock();
      link_.Publish({kProbe, "{}", 1, false});
      lock.lock();
      arrived_.wait_for(lock, std::chrono::milliseconds(100), [&] { return probed_; });
    }
    return probed_;
  }

 private:
  void Arrived(std::string topic, const std::string& payload) {
    json body = json::parse(payload, nullptr, false);
    {
      std::lock_guard lock(mutex_);
      if (topic == kProbe) {
        probed_ = true;
      } else {
        messages_.push_back({topic.substr(kPrefix.size()), std::move(body)});
      }
    }
    arrived_.notify_all();
  }

  std::mutex mutex_;
  std::condition_variable arrived_;
  std::vector<Message> messages_;
  bool probed_ = false;
  int header_id_ = 0;
  server::MqttLink link_;  // last: its callbacks use the members above
};

json Node(const std::string& id, int sequence, bool released, double x, double y, json actions = json::array()) {
  return {{"nodeId", id},
          {"sequenceId", sequence},
          {"released", released},
          {"actions", std::move(actions)},
          {"nodePosition", {{"x", x}, {"y", y}, {"mapId", kMap}}}};
}
json Edge(const std::string& from, const std::string& to, int sequence, bool released, json extra = json::object()) {
  json e = {{"edgeId", from + "-" + to}, {"sequenceId", sequence}, {"released", released},
            {"startNodeId", from},       {"endNodeId", to},        {"actions", json::array()}};
  e.update(extra);
  return e;
}
json Order(const std::string& id, int update, json nodes, json edges) {
  return {{"orderId", id}, {"orderUpdateId", update}, {"nodes", std::move(nodes)}, {"edges", std::move(edges)}};
}
std::vector<std::string> NodeIds(const json& state) {
  std::vector<std::string> ids;
  for (const json& n : state["nodeStates"]) ids.push_back(n["nodeId"].get<std::string>());
  return ids;
}
std::string ActionStatus(const json& state, const std::string& id) {
  for (const json& a : state["actionStates"]) {
    if (a["actionId"] == id) return a["actionStatus"].get<std::string>();
  }
  return "";
}
const json* Error(const json& state, const std::string& type) {
  for (const json& e : state["errors"]) {
    if (e["errorType"] == type) return &e;
  }
  return nullptr;
}
bool Near(const json& state, double x, double y, double tolerance) {
  const json& p = state["agvPosition"];
  return std::hypot(p["x"].get<double>() - x, p["y"].get<double>() - y) < tolerance;
}

class Vda5050Lockstep : public ::testing::Test {
 protected:
  Vda5050Lockstep()
      : room_(6.0, 3.0,
              "sim:\n"
              "  world: room.yaml\n"
              "  start: {x_m: 1.0, y_m: 1.5, yaw_deg: 0}\n"
              "  camera: {width: 160, height: 120}\n"
              "  dock: {enabled: true, x_m: 5.2, y_m: 1.5, yaw_deg: 0}\n"
              "fleet:\n"
              "  vda5050: {serial_number: r1, state_interval_s: 2, broker: \"" +
                  broker_.url() + "\"}\n"),
        master_(broker_.url()) {}

  void SetUp() override {
    ASSERT_TRUE(Pump([&] { return master_.connected(); })) << "the master did not connect";
    ASSERT_TRUE(master_.AwaitSubscribed()) << "the master's subscriptions were not taken";
    robot_ = std::make_unique<LockstepRobot>(room_.config());
    for (const auto& node : robot_->graph().lifecycle().nodes()) {
      if (node->name() == "vda5050") {
        received_ = &node->Loop("message");
        sent_ = &node->Loop("send");
      }
    }
    ASSERT_NE(received_, nullptr);
    ASSERT_TRUE(Pump([&] {
      return master_.Find("connection", [](const json& m) { return m["connectionState"] == "ONLINE"; }).has_value();
    })) << "the robot did not come online";
    ASSERT_FALSE(WaitFor(
                     "state", [](const json& s) { return s["agvPosition"]["positionInitialized"] == true; }, 10.0)
                     .is_null());
  }

  // Runs what the graph has to do, without moving simulated time, until `done` holds (at most 10 s of real time).
  bool Pump(const std::function<bool()>& done) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (!done()) {
      if (std::chrono::steady_clock::now() > end) return false;
      const std::size_t seen = master_.count();
      if (robot_) robot_->graph().executors().RunUntilIdle();
      if (!done()) master_.AwaitMore(seen, 2);
    }
    return true;
  }
  // Publishes `body` on `topic` and lets the robot take it before simulated time moves on.
  void Send(const std::string& topic, const json& body) {
    const std::uint64_t before = received_->snapshot().loops;
    master_.Publish(topic, body);
    ASSERT_TRUE(Pump([&] { return received_->snapshot().loops > before; })) << "the robot never got " << topic;
  }
  void Instant(const std::string& type, const std::string& id) {
    Send("instantActions",
         {{"actions",
           {{{"actionType", type}, {"actionId", id}, {"blockingType", "HARD"}, {"actionParameters", json::array()}}}}});
  }
  // Waits (real time, at most 10 s) until the master has everything the robot sent.
  void Delivered() {
    Pump([&] { return master_.count() >= sent_->snapshot().loops; });
  }
  // How many messages the master has, once all the robot sent has arrived: a `since` for what comes next.
  std::size_t Seen() {
    Delivered();
    return master_.count();
  }
  // The first `topic` message from index `since` on for which `holds` does, stepping simulated time (at most max_s)
  // until it arrives; null when none did. After each step, what the robot sent reaches the master before the next.
  json WaitFor(const std::string& topic, const std::function<bool(const json&)>& holds, double max_s,
               std::size_t since = 0) {
    std::optional<json> found;
    robot_->StepUntil(
        [&] {
          Delivered();
          found = master_.Find(topic, holds, since);
          return found.has_value();
        },
        max_s);
    return found.value_or(json());
  }

  testing::Mosquitto broker_;
  testing::SimRoom room_;
  Master master_;
  std::unique_ptr<LockstepRobot> robot_;
  server::LoopStats* received_ = nullptr;
  server::LoopStats* sent_ = nullptr;
};

TEST_F(Vda5050Lockstep, AnOrderWithAHorizonIsDrivenToItsDecisionPointAtTheEdgesSpeedExtendedPausedAndResumed) {
  const json say = {{"actionType", "say"},
                    {"actionId", "s1"},
                    {"blockingType", "NONE"},
                    {"actionParameters", {{{"key", "text"}, {"value", "node b"}}}}};
  Send(
      "order",
      Order("o1", 0, {Node("a", 0, true, 1.0, 1.5), Node("b", 2, true, 2.5, 1.5, {say}), Node("c", 4, false, 4.0, 1.5)},
            {Edge("a", "b", 1, true, {{"maxSpeed", 0.3}}), Edge("b", "c", 3, false)}));
  const std::size_t start = Seen();
  const json taken = WaitFor(
      "state", [](const json& s) { return s["orderId"] == "o1"; }, 5.0);
  ASSERT_FALSE(taken.is_null());
  EXPECT_EQ(NodeIds(taken), (std::vector<std::string>{"b", "c"}));
  EXPECT_EQ(taken["lastNodeId"], "a");
  EXPECT_EQ(taken["edgeStates"].size(), 2U);
  // At b: the node is traversed and its action done; the robot stops at the decision point with c still waiting.
  const json at_b = WaitFor(
      "state", [](const json& s) { return s["lastNodeId"] == "b"; }, 30.0);
  ASSERT_FALSE(at_b.is_null()) << robot_->State()["mission"].dump();
  EXPECT_EQ(NodeIds(at_b), std::vector<std::string>{"c"});
  EXPECT_EQ(ActionStatus(at_b, "s1"), "FINISHED");
  EXPECT_TRUE(Near(at_b, 2.5, 1.5, 0.3)) << at_b["agvPosition"].dump();
  // The edge's maxSpeed held the robot to 0.3 m/s on the way.
  const std::vector<Master::Message> shown = master_.All("visualization", start);
  EXPECT_GT(shown.size(), 2U);
  for (const Master::Message& m : shown) {
    if (m.body.contains("velocity")) {
      EXPECT_LE(m.body["velocity"]["vx"].get<double>(), 0.36) << m.body.dump();
    }
  }
  ASSERT_FALSE(WaitFor(
                   "state", [](const json& s) { return s["driving"] == false && s["lastNodeId"] == "b"; }, 10.0)
                   .is_null());
  robot_->StepFor(2.0);
  EXPECT_TRUE(Near(WaitFor(
                       "state", [](const json&) { return true; }, 5.0, Seen()),
                   2.5, 1.5, 0.3))
      << "waits at the decision point";
  // The API's state shows the order: c is the horizon.
  const json fleet = robot_->State()["fleet"];
  EXPECT_EQ(fleet["connected"], true);
  ASSERT_EQ(fleet["nodes"].size(), 2U) << fleet.dump();
  EXPECT_EQ(fleet["nodes"][0]["id"], "b");
  EXPECT_EQ(fleet["nodes"][0]["traversed"], true);
  EXPECT_EQ(fleet["nodes"][1]["id"], "c");
  EXPECT_EQ(fleet["nodes"][1]["released"], false);

  // The update stitches on b, releases c and adds a horizon d; paused on the way, it stands until resumed.
  Send("order",
       Order("o1", 1, {Node("b", 2, true, 2.5, 1.5), Node("c", 4, true, 4.0, 1.5), Node("d", 6, false, 4.0, 2.2)},
             {Edge("b", "c", 3, true), Edge("c", "d", 5, false)}));
  ASSERT_FALSE(WaitFor(
                   "state", [](const json& s) { return s["orderUpdateId"] == 1 && s["driving"] == true; }, 10.0)
                   .is_null());
  Instant("startPause", "p1");
  const json paused = WaitFor(
      "state", [](const json& s) { return s["paused"] == true && ActionStatus(s, "p1") == "FINISHED"; }, 5.0);
  ASSERT_FALSE(paused.is_null());
  EXPECT_EQ(NodeIds(paused), (std::vector<std::string>{"c", "d"}));
  ASSERT_FALSE(WaitFor(
                   "state", [](const json& s) { return s["paused"] == true && s["driving"] == false; }, 5.0)
                   .is_null());
  const json stood = robot_->State()["sim_true_pose"];
  robot_->StepFor(1.5);
  const json later = robot_->State()["sim_true_pose"];
  EXPECT_LT(std::hypot(later["x"].get<double>() - stood["x"].get<double>(),
                       later["y"].get<double>() - stood["y"].get<double>()),
            0.02)
      << "no driving while paused";
  Instant("stopPause", "p2");
  const json at_c = WaitFor(
      "state", [](const json& s) { return s["lastNodeId"] == "c" && s["paused"] == false; }, 30.0);
  ASSERT_FALSE(at_c.is_null());
  EXPECT_EQ(NodeIds(at_c), std::vector<std::string>{"d"});
  EXPECT_TRUE(Near(at_c, 4.0, 1.5, 0.3)) << at_c["agvPosition"].dump();
}

TEST_F(Vda5050Lockstep, CancelOrderStopsAndDropsTheOrderAndWithNoneIsNoOrderToCancel) {
  Send("order",
       Order("o1", 0, {Node("a", 0, true, 1.0, 1.5), Node("b", 2, true, 4.5, 1.5)}, {Edge("a", "b", 1, true)}));
  ASSERT_FALSE(WaitFor(
                   "state", [](const json& s) { return s["orderId"] == "o1" && s["driving"] == true; }, 10.0)
                   .is_null());
  Instant("cancelOrder", "c1");
  const json cancelled = WaitFor(
      "state", [](const json& s) { return ActionStatus(s, "c1") == "FINISHED"; }, 5.0);
  ASSERT_FALSE(cancelled.is_null());
  EXPECT_TRUE(NodeIds(cancelled).empty());
  EXPECT_EQ(cancelled["orderId"], "o1");  // kept, as the standard says
  ASSERT_FALSE(WaitFor(
                   "state", [](const json& s) { return s["driving"] == false; }, 5.0, Seen())
                   .is_null());
  const json stood = robot_->State()["sim_true_pose"];
  robot_->StepFor(1.0);
  EXPECT_NEAR(robot_->State()["sim_true_pose"]["x"].get<double>(), stood["x"].get<double>(), 0.02);

  Instant("cancelOrder", "c2");
  const json none = WaitFor(
      "state", [](const json& s) { return ActionStatus(s, "c2") == "FAILED"; }, 5.0);
  ASSERT_FALSE(none.is_null());
  const json* error = Error(none, "noOrderToCancel");
  ASSERT_NE(error, nullptr) << none["errors"].dump();
  EXPECT_EQ((*error)["errorReferences"][0]["referenceValue"], "c2");
}

TEST_F(Vda5050Lockstep, AnOrderToANodeTheConsoleWouldRefuseIsRefusedOnArrivalNamingTheNodeAndNothingMoves) {
  const json here = robot_->State()["sim_true_pose"];
  const std::size_t since = Seen();
  Send("order",
       Order("o7", 0,
             {Node("s", 0, true, here["x"].get<double>(), here["y"].get<double>()), Node("wall", 2, true, 3.0, 0.02)},
             {Edge("s", "wall", 1, true)}));
  const json refused = WaitFor(
      "state", [](const json& s) { return Error(s, "noRouteError") != nullptr; }, 5.0, since);
  ASSERT_FALSE(refused.is_null());
  const json& error = *Error(refused, "noRouteError");
  std::map<std::string, std::string> references;
  for (const json& r : error["errorReferences"]) references[r["referenceKey"]] = r["referenceValue"];
  EXPECT_EQ(references["nodeId"], "wall") << error.dump();
  EXPECT_EQ(references["orderId"], "o7");
  EXPECT_NE(refused["orderId"], "o7") << "the refused order is not taken";
  EXPECT_TRUE(NodeIds(refused).empty());
  robot_->StepFor(3.0);
  const json later = robot_->State();
  EXPECT_FALSE(later["mission"].is_object() && later["mission"]["status"] == "active") << later["mission"].dump();
  EXPECT_NEAR(later["sim_true_pose"]["x"].get<double>(), here["x"].get<double>(), 0.02);
  EXPECT_NEAR(later["sim_true_pose"]["y"].get<double>(), here["y"].get<double>(), 0.02);
}

TEST_F(Vda5050Lockstep, StartChargingDocksAndStopChargingBacksOff) {
  Instant("startCharging", "ch1");
  ASSERT_FALSE(WaitFor(
                   "state", [](const json& s) { return ActionStatus(s, "ch1") == "RUNNING"; }, 5.0)
                   .is_null());
  const json charging = WaitFor(
      "state",
      [](const json& s) { return ActionStatus(s, "ch1") == "FINISHED" && s["batteryState"]["charging"] == true; },
      120.0);
  ASSERT_FALSE(charging.is_null()) << robot_->State()["mission"].dump();
  EXPECT_TRUE(Near(charging, 5.2, 1.5, 0.05)) << charging["agvPosition"].dump();
  Instant("stopCharging", "ch2");
  const json off = WaitFor(
      "state", [](const json& s) { return ActionStatus(s, "ch2") == "FINISHED"; }, 30.0);
  ASSERT_FALSE(off.is_null()) << robot_->State()["mission"].dump();
  EXPECT_FALSE(Near(off, 5.2, 1.5, 0.3)) << off["agvPosition"].dump();
  EXPECT_EQ(off["batteryState"]["charging"], false);
}

}  // namespace
}  // namespace corridor
