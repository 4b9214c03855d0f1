#include "server/api/api_webhooks.h"

#include <algorithm>
#include <cstdint>
#include <limits>

namespace corridor::server {
namespace {

using auth::Access;
using nlohmann::json;

constexpr std::size_t kMinSecret = 16;
constexpr std::size_t kMaxSecret = 256;
constexpr std::size_t kMaxDescription = 200;
constexpr int kEventsPerPage = 256;

json WebhookJson(const WebhookRecord& w) {
  return {{"id", w.id}, {"url", w.url}, {"events", w.events}, {"description", w.description}, {"created", w.created}};
}

json DeliveryJson(const DeliveryRecord& d) {
  json payload = json::parse(d.payload, nullptr, false);
  return {{"id", d.id},
          {"event", d.event},
          {"status", d.status},
          {"attempts", d.attempts},
          {"created", d.created},
          {"last_attempt", d.last_attempt.empty() ? json(nullptr) : json(d.last_attempt)},
          {"response_status", d.response_status == 0 ? json(nullptr) : json(d.response_status)},
          {"error", d.error.empty() ? json(nullptr) : json(d.error)},
          {"payload", payload.is_discarded() ? json(d.payload) : payload}};
}

WebhookRecord ParseWebhook(const json& body) {
  const std::string where = "webhook";
  if (!body.is_object()) throw ApiError(http::status::bad_request, "Invalid request", "the body must be an object");
  AllowOnlyKeys(body, {"url", "events", "secret", "description"}, where);
  WebhookRecord w;
  if (!body.contains("url") || !body["url"].is_string()) {
    throw ApiError(http::status::bad_request, "Invalid request", "url: required, a string");
  }
  w.url = body["url"].get<std::string>();
  try {
    ParseHttpUrl(w.url);
  } catch (const std::invalid_argument& e) {
    throw ApiError(http::status::bad_request, "Invalid request", e.what());
  }
  std::string names;
  for (int i = 0; i < face::kEventTypeCount; ++i) {
    names += (i ? ", " : "") + std::string(face::ToString(static_cast<face::EventType>(i)));
  }
  if (!body.contains("events") || !body["events"].is_array() || body["events"].empty()) {
    throw ApiError(http::status::bad_request, "Invalid request", "events: required, a non-empty list among " + names);
  }
  for (const json& e : body["events"]) {
    if (!e.is_string() || !face::EventTypeFromString(e.get<std::string>())) {
      throw ApiError(http::status::bad_request, "Invalid request",
                     "events: " + Dump(e) + " is not an event; the events are " + names);
    }
    const std::string name = e.get<std::string>();
    if (std::find(w.events.begin(), w.events.end(), name) == w.events.end()) w.events.push_back(name);
  }
  if (body.contains("secret")) {
    if (!body["secret"].is_string() || body["secret"].get<std::string>().size() < kMinSecret ||
        body["secret"].get<std::string>().size() > kMaxSecret) {
      throw ApiError(http::status::bad_request, "Invalid request",
                     "secret: a string of " + std::to_string(kMinSecret) + " to " + std::to_string(kMaxSecret) +
                         " characters (or none: the robot makes one)");
    }
    w.secret = body["secret"].get<std::string>();
  } else {
    w.secret = NewWebhookSecret();
  }
  if (body.contains("description")) {
    if (!body["description"].is_string() || body["description"].get<std::string>().size() > kMaxDescription) {
      throw ApiError(http::status::bad_request, "Invalid request", "description: a string of at most 200 characters");
    }
    w.description = body["description"].get<std::string>();
  }
  return w;
}

}  // namespace

WebhooksApi::WebhooksApi(Store& store, Webhooks& webhooks, const WebhookOptions& options)
    : store_(store), webhooks_(webhooks), options_(options) {}

void WebhooksApi::AddRoutes(Router& routes) const {
  routes.Add(http::verb::get, "/api/v1/webhooks", Access::kAdmin, Sync([this](const Request& r, const Params&) {
               json hooks = json::array();
               for (const WebhookRecord& w : store_.Webhooks()) hooks.push_back(WebhookJson(w));
               return JsonResponse(r, {{"webhooks", hooks}});
             }));
  routes.Add(http::verb::post, "/api/v1/webhooks", Access::kAdmin, Sync([this](const Request& r, const Params&) {
               WebhookRecord w = ParseWebhook(ParseJsonBody(r));
               w.id = NewId();
               w.created = IsoUtc(std::chrono::system_clock::now());
               store_.PutWebhook(w);
               // The secret is shown once, here: the receiver needs it to check signatures.
               json body = WebhookJson(w);
               body["secret"] = w.secret;
               Response res = JsonResponse(r, body, http::status::created);
               res.set(http::field::location, "/api/v1/webhooks/" + w.id);
               return res;
             }));
  const auto find = [this](const std::string& id) {
    std::optional<WebhookRecord> w = store_.Webhook(id);
    if (!w) throw ApiError(http::status::not_found, "Not found", "no webhook " + id);
    return *w;
  };
  routes.Add(http::verb::get, "/api/v1/webhooks/{id}", Access::kAdmin, Sync([find](const Request& r, const Params& p) {
               return JsonResponse(r, WebhookJson(find(p.at("id"))));
             }));
  routes.Add(http::verb::delete_, "/api/v1/webhooks/{id}", Access::kAdmin,
             Sync([this](const Request& r, const Params& p) {
               if (!store_.DeleteWebhook(p.at("id"))) {
                 throw ApiError(http::status::not_found, "Not found", "no webhook " + p.at("id"));
               }
               webhooks_.Forget(p.at("id"));
               return MakeResponse(r, http::status::no_content, "application/json", "");
             }));
  routes.Add(http::verb::get, "/api/v1/webhooks/{id}/deliveries", Access::kAdmin,
             Sync([this, find](const Request& r, const Params& p) {
               const WebhookRecord w = find(p.at("id"));
               json deliveries = json::array();
               const int most = options_.keep_deliveries + options_.max_pending;
               for (const DeliveryRecord& d : store_.Deliveries(w.id, most)) {
                 deliveries.push_back(DeliveryJson(d));
               }
               return JsonResponse(r, {{"deliveries", deliveries}});
             }));
  routes.Add(http::verb::post, "/api/v1/webhooks/{id}/ping", Access::kAdmin,
             Sync([this, find](const Request& r, const Params& p) {
               const std::string delivery = webhooks_.Ping(find(p.at("id")));
               webhooks_.Dispatch();
               return JsonResponse(r, {{"delivery", delivery}}, http::status::accepted);
             }));
  // The events recorded in the database: the newest 256, or those after `after` (a poller's last sequence).
  routes.Add(http::verb::get, "/api/v1/events", Access::kViewer, Sync([this](const Request& r, const Params&) {
               return JsonResponse(r, {{"events", store_.Events(AfterParameter(r.target()), kEventsPerPage)}});
             }));
}

}  // namespace corridor::server
