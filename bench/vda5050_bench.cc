// What a VDA 5050 message costs the robot: building the state, checking it against the standard's schema (every
// message in and out is checked), and serializing it. The node sends a visualization every second and a state at
// least every 30 s, and checks each order as it arrives.
#include <benchmark/benchmark.h>

#include "server/fleet/vda5050.h"
#include "server/fleet/vda5050_agent.h"

namespace corridor::server {
namespace {

const VdaIdentity kRobot{"uagv", "corridor", "robot-1"};

VdaRobot Robot() {
  VdaRobot r;
  r.map_id = "willow";
  r.position_initialized = true;
  r.pose = {24.4, 24.1, 1.57};
  r.battery_percent = 80.0;
  r.driving = true;
  return r;
}

// "n3", "e3": built without operator+ on a literal, which GCC 12 warns of falsely (-Wrestrict, bug 105329).
std::string Id(char kind, int i) {
  std::string id(1, kind);
  id += std::to_string(i);
  return id;
}

// An order of `n` released nodes along a line, with the edges between them.
nlohmann::json Order(int n) {
  nlohmann::json nodes = nlohmann::json::array();
  nlohmann::json edges = nlohmann::json::array();
  for (int i = 0; i < n; ++i) {
    nodes.push_back({{"nodeId", Id('n', i)},
                     {"sequenceId", 2 * i},
                     {"released", true},
                     {"nodePosition", {{"x", 1.0 * i}, {"y", 0.0}, {"mapId", "willow"}}},
                     {"actions", nlohmann::json::array()}});
    if (i > 0) {
      edges.push_back({{"edgeId", Id('e', i)},
                       {"sequenceId", 2 * i - 1},
                       {"released", true},
                       {"startNodeId", Id('n', i - 1)},
                       {"endNodeId", Id('n', i)},
                       {"actions", nlohmann::json::array()}});
    }
  }
  return {{"headerId", 1},
          {"timestamp", "2026-11-26T08:00:00.000Z"},
          {"version", "2.1.0"},
          {"manufacturer", "corridor"},
          {"serialNumber", "robot-1"},
          {"orderId", "o1"},
          {"orderUpdateId", 0},
          {"nodes", nodes},
          {"edges", edges}};
}

void BM_StateBuildCheckDump(benchmark::State& state) {
  const VdaSchemas schemas;
  VdaAgent agent({}, {});
  VdaRobotNow now;
  now.pose = nav::Pose2{0.0, 0.0, 0.0};
  now.map_id = "willow";
  agent.Order(Order(static_cast<int>(state.range(0))), now);
  std::uint32_t id = 0;
  for (auto _ : state) {
    nlohmann::json message = VdaState(kRobot, {id++, VdaTimestamp(0)}, Robot());
    agent.FillState(message);
    benchmark::DoNotOptimize(schemas.Check(VdaMessage::kState, message));
    benchmark::DoNotOptimize(message.dump());
  }
}
BENCHMARK(BM_StateBuildCheckDump)->Arg(1)->Arg(20)->Unit(benchmark::kMicrosecond);

void BM_VisualizationBuildCheckDump(benchmark::State& state) {
  const VdaSchemas schemas;
  std::uint32_t id = 0;
  for (auto _ : state) {
    const nlohmann::json message = VdaVisualization(kRobot, {id++, VdaTimestamp(0)}, Robot());
    benchmark::DoNotOptimize(schemas.Check(VdaMessage::kVisualization, message));
    benchmark::DoNotOptimize(message.dump());
  }
}
BENCHMARK(BM_VisualizationBuildCheckDump)->Unit(benchmark::kMicrosecond);

// An order as it arrives: parsed, checked, and taken.
void BM_OrderParseCheckTake(benchmark::State& state) {
  const VdaSchemas schemas;
  const std::string text = Order(static_cast<int>(state.range(0))).dump();
  VdaRobotNow now;
  now.pose = nav::Pose2{0.0, 0.0, 0.0};
  now.map_id = "willow";
  for (auto _ : state) {
    const nlohmann::json order = nlohmann::json::parse(text);
    benchmark::DoNotOptimize(schemas.Check(VdaMessage::kOrder, order));
    VdaAgent agent({}, {});
    benchmark::DoNotOptimize(agent.Order(order, now));
  }
}
BENCHMARK(BM_OrderParseCheckTake)->Arg(2)->Arg(20)->Arg(100)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace corridor::server

BENCHMARK_MAIN();
