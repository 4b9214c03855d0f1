#include "server/fleet/doors.h"

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

namespace corridor::server {

std::vector<MapDoor> DoorsOfMap(const Config& config, const std::vector<nav::Door>& drawn, const std::string& map,
                                bool simulated) {
  std::vector<MapDoor> doors;
  for (const DoorPlace& d : config.doors.list) {
    if (d.map == map) doors.push_back({{d.id, d.from, d.to}, "config"});
  }
  if (simulated && map == SimMapName(config)) {
    for (const drivers::sim::SimDoorOptions& d : config.sim.robot.doors) doors.push_back({{d.id, d.from, d.to}, "sim"});
  }
  for (const nav::Door& d : drawn) doors.push_back({d, "drawn"});
  return doors;
}

HttpDoorController::HttpDoorController(boost::asio::io_context& io, const DoorControllerOptions& options)
    : options_(options),
      http_(io, options.headers, options.request_timeout_s, {&options_.open, &options_.state, &options_.release},
            {"door"}) {}

void HttpDoorController::Open(const std::string& door, Done done) {
  http_.Send(options_.open, {{"door", door}}, [done = std::move(done)](int status, std::string, std::string error) {
    if (HttpSuccess(status)) return done({nav::DoorStatus::kOpening, ""});
    done({HttpRefusal(status) ? nav::DoorStatus::kRefused : nav::DoorStatus::kFailed, error});
  });
}

void HttpDoorController::State(const std::string& door, Done done) {
  http_.Send(
      options_.state, {{"door", door}},
      [this, done = std::move(done)](int status, std::string body, std::string error) {
        if (!HttpSuccess(status)) return done({nav::DoorStatus::kFailed, error});
        try {
          const bool open = ValueText(nlohmann::json::parse(body), options_.open_pointer) == options_.open_value;
          done({open ? nav::DoorStatus::kOpen : nav::DoorStatus::kOpening, ""});
        } catch (const nlohmann::json::exception& e) {
          done({nav::DoorStatus::kFailed, std::string("the door's state is not the JSON expected: ") + e.what()});
        }
      });
}

void HttpDoorController::Release(const std::string& door) {
  if (options_.release.url.empty()) return;  // this building's doors close by themselves
  http_.Send(options_.release, {{"door", door}}, [door](int status, std::string, std::string error) {
    if (!HttpSuccess(status)) spdlog::warn("doors: releasing {}: {}", door, error);
  });
}

}  // namespace corridor::server
