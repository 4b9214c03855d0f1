// A lift has brought the robot to another floor (mission/floor_arrival): that floor's map becomes the one in use and
// localization takes the pose where the lift put the robot. On the io executor, where the map library is changed.
#pragma once

#include "server/config/config.h"
#include "server/runtime/node.h"
#include "server/runtime/topics.h"
#include "server/store/map_library.h"

namespace corridor::server {

class FloorNode final : public Node {
 public:
  // `maps` and `building` must outlive the node.
  FloorNode(Executor& io, Bus& bus, MapLibrary& maps, const BuildingOptions& building);
  void Activate() override;

 private:
  void Arrive(const FloorArrival& arrival);

  MapLibrary& maps_;
  const BuildingOptions& building_;
  Topic<LocalizationCommand>& localization_command_ = bus().Get(topics::kLocalizationCommand);
};

}  // namespace corridor::server
