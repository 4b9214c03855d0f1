#include "server/fleet/vda5050.h"

#include <gtest/gtest.h>

#include "server/fleet/mqtt_link.h"

namespace corridor::server {
namespace {

const VdaIdentity kRobot{"uagv", "corridor", "robot-1"};
const VdaHeader kHeader{7, "2026-11-26T04:40:00.123Z"};

bool Mentions(const std::vector<std::string>& errors, const std::string& text) {
  for (const std::string& e : errors) {
    if (e.find(text) != std::string::npos) return true;
  }
  return false;
}

TEST(VdaTest, TopicsAndTimestampsAreTheStandardsOwn) {
  EXPECT_EQ(VdaTopic(kRobot, "state"), "uagv/v2/corridor/robot-1/state");
  EXPECT_EQ(VdaTimestamp(1795668000123), "2026-11-26T04:40:00.123Z");
  EXPECT_EQ(VdaTimestamp(0), "1970-01-01T00:00:00.000Z");
}

TEST(VdaTest, WhatTheRobotSendsIsValidAgainstTheStandardsSchemas) {
  const VdaSchemas schemas;
  VdaRobot robot;
  robot.map_id = "willow";
  robot.position_initialized = true;
  robot.pose = {24.4, 24.1, 1.57};
  robot.localization_score = 0.9;
  robot.velocity = {0.3, 0.1};
  robot.driving = true;
  robot.battery_percent = 79.5;
  robot.battery_voltage_v = 12.1;
  robot.errors.push_back({"lost", "WARNING", "localization does not know where the robot is"});
  for (const auto& [kind, message] : {std::pair{VdaMessage::kState, VdaState(kRobot, kHeader, robot)},
                                      std::pair{VdaMessage::kConnection, VdaConnection(kRobot, kHeader, "ONLINE")},
                                      std::pair{VdaMessage::kVisualization, VdaVisualization(kRobot, kHeader, robot)},
                                      std::pair{VdaMessage::kFactsheet, VdaFactsheet(kRobot, kHeader, VdaVehicle{})}}) {
    const auto errors = schemas.Check(kind, message);
    EXPECT_TRUE(errors.empty()) << ToString(kind) << ": " << errors.front() << "\n" << message.dump();
  }
  EXPECT_TRUE(VdaState(kRobot, kHeader, robot)["errors"].size() == 1);
  // A robot that does not know where it is yet, with no battery reported: still valid, and says so.
  const nlohmann::json unknown = VdaState(kRobot, kHeader, VdaRobot{});
  EXPECT_TRUE(schemas.Check(VdaMessage::kState, unknown).empty());
  EXPECT_EQ(unknown["errors"][0]["errorType"], "batteryUnknown");
}

TEST(VdaTest, MessagesThatBreakTheSchemaAreReportedWithWhere) {
  const VdaSchemas schemas;
  nlohmann::json connection = VdaConnection(kRobot, kHeader, "ONLINE");
  connection["connectionState"] = "SLEEPING";
  EXPECT_TRUE(Mentions(schemas.Check(VdaMessage::kConnection, connection), "connectionState"));
  nlohmann::json state = VdaState(kRobot, kHeader, VdaRobot{});
  state.erase("batteryState");
  EXPECT_TRUE(Mentions(schemas.Check(VdaMessage::kState, state), "batteryState"));
  // An order as a master control sends it, then broken in the ways the standard's receivers must refuse.
  nlohmann::json order = {
      {"headerId", 1},
      {"timestamp", kHeader.timestamp},
      {"version", "2.1.0"},
      {"manufacturer", "corridor"},
      {"serialNumber", "robot-1"},
      {"orderId", "o1"},
      {"orderUpdateId", 0},
      {"nodes", {{{"nodeId", "n1"}, {"sequenceId", 0}, {"released", true}, {"actions", nlohmann::json::array()}}}},
      {"edges", nlohmann::json::array()}};
  EXPECT_TRUE(schemas.Check(VdaMessage::kOrder, order).empty()) << schemas.Check(VdaMessage::kOrder, order).front();
  order["nodes"][0]["sequenceId"] = "first";
  const auto order_errors = schemas.Check(VdaMessage::kOrder, order);
  EXPECT_TRUE(Mentions(order_errors, "nodes[0].sequenceId"))
      << (order_errors.empty() ? order.dump() : order_errors.front());
  EXPECT_FALSE(schemas.Check(VdaMessage::kInstantActions, nlohmann::json::array()).empty());
}

TEST(MqttLinkTest, BrokerAddressesAreMqttUrlsWithHostAndPort) {
  EXPECT_EQ(PahoServerUri("mqtt://127.0.0.1:1883"), "tcp://127.0.0.1:1883");
  EXPECT_EQ(PahoServerUri("mqtts://broker.local:8883"), "ssl://broker.local:8883");
  for (const char* bad :
       {"127.0.0.1:1883", "http://x:80", "mqtt://x", "mqtt://:1883", "mqtt://x:80/path", "mqtt://x:"}) {
    EXPECT_THROW(PahoServerUri(bad), std::invalid_argument) << bad;
  }
}

}  // namespace
}  // namespace corridor::server
