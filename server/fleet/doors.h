// The building's door controller, as missions need it (nav/mission/doors.h): ask a door to open, ask how it is, say
// the robot is through. HttpDoorController speaks to the building's own REST API with the requests the configuration
// describes (doors.controller), asynchronously on the io executor (server/fleet/building_http.h).
#pragma once

#include <boost/asio/io_context.hpp>

#include <functional>
#include <string>

#include "nav/mission/doors.h"
#include "server/config/config.h"
#include "server/fleet/building_http.h"

namespace corridor::server {

// A door on a map and where it is described: "config" (doors.list), "sim" (the simulator's, on its world's map) or
// "drawn" (in the store: drawn in the console or posted to /api/v1/doors).
struct MapDoor {
  nav::Door door;
  std::string source;
};
// Every door on `map`: the configuration's, the simulator's (`simulated`), and `drawn`.
std::vector<MapDoor> DoorsOfMap(const Config& config, const std::vector<nav::Door>& drawn, const std::string& map,
                                bool simulated);

class DoorController {
 public:
  using Done = std::function<void(nav::DoorReport)>;
  virtual ~DoorController() = default;
  // Asks `door` to open: kOpening when the controller took it (or kOpen), kRefused, or kFailed (no answer).
  virtual void Open(const std::string& door, Done done) = 0;
  // How `door` is: kOpen, kOpening (not yet), or kFailed.
  virtual void State(const std::string& door, Done done) = 0;
  // The robot is through (or no longer comes): the door may close. Failures are logged.
  virtual void Release(const std::string& door) = 0;
  // Every poll, whether or not a door is in use (a connection to keep up, say).
  virtual void Tick() {}
};

class HttpDoorController final : public DoorController {
 public:
  // Throws std::invalid_argument for a request URL that is not an http(s) URL.
  HttpDoorController(boost::asio::io_context& io, const DoorControllerOptions& options);
  void Open(const std::string& door, Done done) override;
  void State(const std::string& door, Done done) override;
  void Release(const std::string& door) override;

 private:
  DoorControllerOptions options_;
  BuildingHttp http_;
};

}  // namespace corridor::server
