#include "testing/lockstep_robot.h"

#include <unistd.h>

#include <atomic>

namespace corridor::testing {
namespace {

namespace fs = std::filesystem;
namespace http = server::http;

fs::path NewStateDir() {
  static std::atomic<int> count{0};
  const fs::path dir =
      fs::temp_directory_path() / ("corridor_lockstep_" + std::to_string(::getpid()) + "_" + std::to_string(count++));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

}  // namespace

LockstepRobot::LockstepRobot(const fs::path& config_file, const std::function<void(server::Config&)>& adjust,
                             std::optional<fs::path> state_dir) {
  own_state_dir_ = !state_dir;
  state_dir_ = state_dir ? *state_dir : NewStateDir();
  fs::create_directories(state_dir_);
  server::ConfigOverrides overrides;
  overrides.state_dir = state_dir_;
  config_ = server::LoadConfig(config_file, overrides);
  if (adjust) {
    adjust(config_);
    server::ApplyDerivedOptions(config_);
  }
  if (!server::Simulated(config_)) {
    throw std::invalid_argument("a lockstep robot needs the simulator (devices.base.driver: sim)");
  }
  sim_ = server::MakeSimulator(config_);
  graph_ = std::make_unique<server::Graph>(config_, sim_.devices(config_),
                                           server::InitialMap(config_, sim_.world.get()), server::Schedule::kLockstep);
  graph_->Start();
}

LockstepRobot::~LockstepRobot() {
  graph_->Stop();
  graph_.reset();
  if (own_state_dir_) {
    std::error_code ec;
    fs::remove_all(state_dir_, ec);
  }
}

LockstepRobot::Reply LockstepRobot::Call(const std::string& method, const std::string& target,
                                         const nlohmann::json& body, double max_seconds) {
  server::Request request{http::string_to_verb(method), target, 11};
  if (!body.is_null()) {
    request.set(http::field::content_type, "application/json");
    request.body() = body.dump();
  }
  request.prepare_payload();
  std::optional<Reply> reply;
  graph_->api().Handle(request, [&reply](server::Response response) {
    Reply r{static_cast<int>(response.result_int()), nullptr};
    if (!response.body().empty()) r.body = nlohmann::json::parse(response.body(), nullptr, false);
    reply = std::move(r);
  });
  // Most answers come from the io executor without a step; those computed elsewhere (plans) need the clock to move.
  graph_->executors().RunUntilIdle();
  if (!reply) StepUntil([&reply] { return reply.has_value(); }, max_seconds);
  return reply.value_or(Reply{});
}

void LockstepRobot::StepFor(double seconds) {
  const double end = now_s() + seconds;
  while (now_s() < end) graph_->Step();
}

bool LockstepRobot::StepUntil(const std::function<bool()>& done, double max_seconds) {
  const double end = now_s() + max_seconds;
  while (!done()) {
    if (now_s() >= end) return false;
    graph_->Step();
  }
  return true;
}

nlohmann::json LockstepRobot::StateWhen(const std::function<bool(const nlohmann::json&)>& done, double max_seconds) {
  nlohmann::json state;
  StepUntil(
      [&] {
        state = State();
        return done(state);
      },
      max_seconds);
  return state;
}

double LockstepRobot::now_s() const { return drivers::ToSeconds(sim_.robot->now_ns()); }

}  // namespace corridor::testing
