// What the API fuzz targets share: the daemon's graph in lockstep with a simulated robot in a 10 x 10 m room, in a
// temporary state directory, built once per fuzzing process, and one request answered through its API.
#pragma once

#include <boost/beast/http.hpp>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "drivers/sim/sim_robot.h"
#include "drivers/sim/world.h"
#include "server/app/graph.h"
#include "server/runtime/topics.h"

namespace corridor::fuzz {

class FuzzGraph {
 public:
  static FuzzGraph& Get() {
    static FuzzGraph* graph = new FuzzGraph();  // never destroyed: libFuzzer exits without unwinding
    return *graph;
  }

  server::Graph& graph() { return *graph_; }

  // Answers `request` through the API, running the graph until the reply comes and what it set off is done. A
  // handler that never replies, a server error (other than "not available yet") or a daemon left unhealthy is a
  // bug: abort, so that libFuzzer keeps the input.
  // `caller`: from the network (the gate checks the request's credentials); without one, a trusted in-process caller.
  server::Response Answer(const server::Request& request, const std::optional<server::Caller>& caller = std::nullopt) {
    std::optional<server::Response> reply;
    int replies = 0;
    const auto take = [&](server::Response r) {
      ++replies;
      reply = std::move(r);
    };
    if (caller) {
      graph_->api().Handle(request, *caller, take);
    } else {
      graph_->api().Handle(request, take);
    }
    for (int i = 0; i < 1000 && !reply; ++i) graph_->executors().RunUntilIdle();
    if (!reply || replies != 1) Fail("the API did not reply exactly once", Describe(request));
    const int status = reply->result_int();
    if (status >= 500 && status != 503) {
      Fail("server error " + std::to_string(status) + ": " + reply->body(), Describe(request));
    }
    CheckHealthy(Describe(request));
    return std::move(*reply);
  }

  // Runs what is pending; aborts if any node's callback failed (a fault on safety/faults) or an exception reached an
  // executor: the input left the daemon unhealthy.
  void CheckHealthy(const std::string& input) {
    graph_->executors().RunUntilIdle();
    if (const auto fault = graph_->bus().Get(server::topics::kFaults).latest()) {
      Fail(fault->node + ": " + fault->loop + " failed: " + fault->what, input);
    }
    for (server::Executor* e :
         {&graph_->executors().control, &graph_->executors().mapping, &graph_->executors().planning,
          &graph_->executors().perception, &graph_->executors().io, &graph_->executors().sim}) {
      if (e->escaped() > 0) Fail("an exception reached the " + e->name() + " executor", input);
    }
  }

  static std::string Describe(const server::Request& request) {
    return std::string(request.method_string()) + " " + std::string(request.target());
  }

  [[noreturn]] static void Fail(const std::string& what, const std::string& input) {
    std::fprintf(stderr, "fuzz: %s\ninput: %s\n", what.c_str(), input.c_str());
    std::abort();
  }

 private:
  FuzzGraph() {
    char pattern[] = "/tmp/corridor-fuzz-XXXXXX";
    if (mkdtemp(pattern) == nullptr) std::abort();
    server::Config config;
    config.store.state_dir = pattern;
    config.sim.robot.start = {5.0, 5.0, 0.0};
    config.sim.robot.camera.width = 64;
    config.sim.robot.camera.height = 48;
    server::ApplyDerivedOptions(config);
    const nav::OccupancyGrid room = drivers::sim::RoomMap(10.0, 10.0, 0.05);
    world_ = std::make_shared<const drivers::sim::World>(drivers::sim::WorldFromMap(room, {}));
    robot_ = std::make_unique<drivers::sim::SimRobot>(world_, config.sim.robot);
    graph_ = std::make_unique<server::Graph>(config, server::Devices{robot_.get(), *robot_, robot_.get(), robot_.get()},
                                             server::NamedMap{"room", room}, server::Schedule::kLockstep);
    graph_->Start();
    for (int i = 0; i < 20; ++i) graph_->Step();  // a camera frame and odometry on the bus
  }

  std::shared_ptr<const drivers::sim::World> world_;
  std::unique_ptr<drivers::sim::SimRobot> robot_;
  std::unique_ptr<server::Graph> graph_;
};

}  // namespace corridor::fuzz
