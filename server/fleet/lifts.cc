#include "server/fleet/lifts.h"

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

namespace corridor::server {
namespace {

nav::LiftReport Failed(std::string why) {
  nav::LiftReport r;
  r.failed = true;
  r.detail = std::move(why);
  return r;
}

}  // namespace

HttpLiftController::HttpLiftController(boost::asio::io_context& io, const LiftControllerOptions& options)
    : options_(options),
      http_(io, options.headers, options.request_timeout_s, {&options_.call, &options_.state, &options_.release},
            {"lift", "floor"}) {}

void HttpLiftController::Call(const std::string& lift, const std::string& floor, Done done) {
  http_.Send(options_.call, {{"lift", lift}, {"floor", floor}},
             [done = std::move(done)](int status, std::string, std::string error) {
               if (HttpSuccess(status)) return done({});
               nav::LiftReport r = Failed(std::move(error));
               r.refused = HttpRefusal(status);
               r.failed = !r.refused;
               done(std::move(r));
             });
}

void HttpLiftController::State(const std::string& lift, Done done) {
  http_.Send(options_.state, {{"lift", lift}},
             [this, done = std::move(done)](int status, std::string body, std::string error) {
               if (!HttpSuccess(status)) return done(Failed(std::move(error)));
               try {
                 const nlohmann::json answer = nlohmann::json::parse(body);
                 nav::LiftReport r;
                 r.floor = ValueText(answer, options_.floor_pointer);
                 r.door_open = ValueText(answer, options_.door_pointer) == options_.door_open_value;
                 if (r.floor.empty())
                   return done(Failed("the lift's state names no floor at " + options_.floor_pointer));
                 done(std::move(r));
               } catch (const nlohmann::json::exception& e) {
                 done(Failed(std::string("the lift's state is not the JSON expected: ") + e.what()));
               }
             });
}

void HttpLiftController::Release(const std::string& lift) {
  if (options_.release.url.empty()) return;
  http_.Send(options_.release, {{"lift", lift}}, [lift](int status, std::string, std::string error) {
    if (!HttpSuccess(status)) spdlog::warn("lifts: releasing {}: {}", lift, error);
  });
}

}  // namespace corridor::server
