// libFuzzer target: JSON bodies of the routes that take them (zones, places, missions, plans, map cells, teleop, sim
// faults, the active map, an imported or renamed map, the face, an initial pose, a webhook, pushed detections), through
// the real router and handlers. The first byte picks the route; the rest is the body.
#include <cstddef>
#include <cstdint>
#include <string>

#include "server/runtime/topics.h"
#include "tests/fuzz/fuzz_graph.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace http = boost::beast::http;
  struct Route {
    http::verb verb;
    const char* target;
  };
  static const Route kRoutes[] = {
      {http::verb::post, "/api/v1/zones"},     {http::verb::put, "/api/v1/zones/z1"},
      {http::verb::post, "/api/v1/places"},    {http::verb::put, "/api/v1/places/p1"},
      {http::verb::post, "/api/v1/missions"},  {http::verb::post, "/api/v1/plan"},
      {http::verb::put, "/api/v1/map/cells"},  {http::verb::post, "/api/v1/teleop"},
      {http::verb::put, "/api/v1/sim/faults"}, {http::verb::put, "/api/v1/map/active"},
      {http::verb::post, "/api/v1/face"},      {http::verb::put, "/api/v1/localization/pose"},
      {http::verb::post, "/api/v1/webhooks"},  {http::verb::post, "/api/v1/detections"},
      {http::verb::post, "/api/v1/maps"},      {http::verb::patch, "/api/v1/maps/m1"},
  };
  if (size == 0) return 0;
  const Route& route = kRoutes[data[0] % (sizeof(kRoutes) / sizeof(kRoutes[0]))];
  corridor::server::Request request{route.verb, route.target, 11};
  request.set(http::field::content_type, "application/json");
  request.body().assign(reinterpret_cast<const char*>(data + 1), size - 1);
  request.prepare_payload();
  auto& fuzz = corridor::fuzz::FuzzGraph::Get();
  fuzz.Answer(request);
  // A mission the body started is cancelled, so that the next inputs do not pile them up.
  const auto mission = fuzz.graph().bus().Get(corridor::server::topics::kMission).latest();
  if (mission && !mission->id.empty()) {
    fuzz.graph().core().Command(corridor::server::MissionStep::kCancel, mission->id, "fuzz");
    fuzz.graph().executors().RunUntilIdle();
  }
  // A webhook the body subscribed is deleted before anything is sent to it: a fuzzed URL may name any host.
  for (const auto& webhook : fuzz.graph().store().Webhooks()) fuzz.graph().store().DeleteWebhook(webhook.id);
  return 0;
}
