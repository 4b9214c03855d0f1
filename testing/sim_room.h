// For lockstep tests: an empty rectangular room (drivers::sim::RoomMap, walls all round) saved as room.yaml, a
// map_server map, in a directory of its own, beside corridor.yaml, a configuration of the test's own that simulates it
// (`sim: world: room.yaml`); both removed with the object.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

#include "drivers/sim/world.h"
#include "nav/map/map_io.h"
#include "testing/temp_dir.h"

namespace corridor::testing {

class SimRoom {
 public:
  SimRoom(double width_m, double height_m, const std::string& config_yaml) {
    nav::SaveMap(drivers::sim::RoomMap(width_m, height_m, 0.05), dir_.path() / "room.yaml");
    std::ofstream(config()) << config_yaml;
  }
  std::filesystem::path config() const { return dir_.path() / "corridor.yaml"; }

 private:
  TempDir dir_{"corridor_room"};
};

}  // namespace corridor::testing
