#include "server/fleet/doors.h"

#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

namespace corridor::server {

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
  http_.Send(options_.state, {{"door", door}}, [this, done = std::move(done)](int status, std::string body,
                                                                              std::string error) {
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
