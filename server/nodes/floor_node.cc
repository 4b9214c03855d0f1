#include "server/nodes/floor_node.h"

#include <spdlog/spdlog.h>

namespace corridor::server {

FloorNode::FloorNode(Executor& io, Bus& bus, MapLibrary& maps, const BuildingOptions& building)
    : Node("floors", io, bus), maps_(maps), building_(building) {}

void FloorNode::Activate() {
  Subscribe(topics::kFloorArrival, "arrival", [this](const auto& arrival) { Arrive(*arrival); });
  Node::Activate();
}

void FloorNode::Arrive(const FloorArrival& arrival) {
  const nav::Building building = BuildingOf(building_);
  const nav::Floor* floor = building.FloorNamed(arrival.floor);
  if (floor == nullptr) {
    spdlog::error("floor {}: not a floor of the building", arrival.floor);
    return;
  }
  try {
    maps_.Select(floor->map);
  } catch (const MapEditError& e) {
    spdlog::error("floor {}: its map '{}' cannot be used: {}", arrival.floor, floor->map, e.what());
    return;
  }
  spdlog::info("floor {}: map '{}', the robot at ({:.2f}, {:.2f})", arrival.floor, floor->map, arrival.pose.x_m,
               arrival.pose.y_m);
  LocalizationCommand command;
  command.kind = LocalizationCommand::Kind::kSetPose;
  command.pose = arrival.pose;
  command.sigma_m = 0.05;
  command.sigma_rad = 0.03;
  localization_command_.Publish(command);
}

}  // namespace corridor::server
