// The building's lift controller, as lift rides need it (nav/mission/lifts.h): call a lift to a floor (its door to
// open there), ask where it is and whether its door is open, say the robot is done with it. HttpLiftController speaks
// to the building's own REST API with the requests the configuration describes (building.controller), asynchronously
// on the io executor (server/fleet/building_http.h).
#pragma once

#include <functional>
#include <string>

#include "nav/mission/lifts.h"
#include "server/config/config.h"
#include "server/fleet/building_http.h"

namespace corridor::server {

class LiftController {
 public:
  using Done = std::function<void(nav::LiftReport)>;
  virtual ~LiftController() = default;
  // Asks `lift` to come to `floor` and open there: a report with refused (and why) or failed (no answer), else an
  // empty one (taken; the state tells the rest).
  virtual void Call(const std::string& lift, const std::string& floor, Done done) = 0;
  // Where `lift` is and whether its door is open, or failed.
  virtual void State(const std::string& lift, Done done) = 0;
  // The robot is done with `lift`. Failures are logged.
  virtual void Release(const std::string& lift) = 0;
  // Every poll, whether or not a lift is in use (a connection to keep up, say).
  virtual void Tick() {}
};

class HttpLiftController final : public LiftController {
 public:
  // Throws std::invalid_argument for a request URL that is not an http(s) URL.
  HttpLiftController(boost::asio::io_context& io, const LiftControllerOptions& options);
  void Call(const std::string& lift, const std::string& floor, Done done) override;
  void State(const std::string& lift, Done done) override;
  void Release(const std::string& lift) override;

 private:
  LiftControllerOptions options_;
  BuildingHttp http_;
};

}  // namespace corridor::server
