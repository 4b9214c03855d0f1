// The daemon's graph (server/app/graph.h) in lockstep with its simulator, built from a configuration file as corridord
// builds it, with an in-process API client: for tests of behaviour in simulated time. No threads and no sleeps: a test
// steps the simulated clock, and the same configuration and seed give the same run every time, however busy the
// machine is.
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "server/app/graph.h"
#include "server/app/simulator.h"
#include "server/config/config.h"

namespace corridor::testing {

class LockstepRobot {
 public:
  // Loads `config_file` as corridord does, lets `adjust` change the configuration (after loading, before the derived
  // options are applied), and builds the graph in a state directory of its own (removed with the robot), or in
  // `state_dir` when given (kept). Throws what corridord's start-up throws for a configuration it refuses.
  explicit LockstepRobot(const std::filesystem::path& config_file,
                         const std::function<void(server::Config&)>& adjust = nullptr,
                         std::optional<std::filesystem::path> state_dir = std::nullopt);
  LockstepRobot(const LockstepRobot&) = delete;
  LockstepRobot& operator=(const LockstepRobot&) = delete;
  ~LockstepRobot();

  struct Reply {
    int status = 0;
    nlohmann::json body;  // null for an empty body
  };
  // One request through the API as a trusted in-process caller; steps the graph until it is answered (at most
  // max_seconds of simulated time: then status 0).
  Reply Call(const std::string& method, const std::string& target, const nlohmann::json& body = nullptr,
             double max_seconds = 30.0);
  nlohmann::json State() { return Call("GET", "/api/v1/state").body; }

  // Steps for `seconds` of simulated time.
  void StepFor(double seconds);
  // Steps until `done` holds (checked every step); false after max_seconds of simulated time.
  bool StepUntil(const std::function<bool()>& done, double max_seconds);
  // Steps until `done` holds of the state (GET /api/v1/state, taken every step); the last state taken, whether it
  // held or max_seconds of simulated time ran out.
  nlohmann::json StateWhen(const std::function<bool(const nlohmann::json&)>& done, double max_seconds);

  double now_s() const;
  server::Graph& graph() { return *graph_; }
  drivers::sim::SimRobot& sim() { return *sim_.robot; }
  const server::Config& config() const { return config_; }
  const std::filesystem::path& state_dir() const { return state_dir_; }

 private:
  std::filesystem::path state_dir_;
  bool own_state_dir_ = false;
  server::Config config_;
  server::Simulator sim_;
  std::unique_ptr<server::Graph> graph_;
};

}  // namespace corridor::testing
