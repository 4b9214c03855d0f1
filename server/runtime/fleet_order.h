// A fleet manager's order as the robot holds it, for the console's map and /api/v1/state: the last node traversed,
// the nodes still to traverse and the edges between them (released ones are the base, the rest the horizon), and
// whether the fleet manager's connection is up.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace corridor::server {

struct FleetOrder {
  std::int64_t stamp_ns = 0;
  std::string protocol;  // "vda5050"
  bool connected = false;
  std::string order_id;  // "" before the first order
  std::uint32_t order_update_id = 0;
  std::string last_node_id;
  struct Node {
    std::string id;
    bool released = false;
    double x = 0.0;
    double y = 0.0;
    bool traversed = false;  // the last node traversed (first in `nodes`, when the order has one)
  };
  std::vector<Node> nodes;
  struct Edge {
    std::string id;
    std::string start;
    std::string end;
    bool released = false;
  };
  std::vector<Edge> edges;
};

}  // namespace corridor::server
