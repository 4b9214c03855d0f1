// The REST API's route table: each route's method, path pattern, the access it needs (server/auth/gate.h) and its
// handler, declared once by the resource that serves it (api_*.h) and checked against openapi.json by
// tests/api_routes_test.cc.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "server/api/rest.h"
#include "server/auth/gate.h"

namespace corridor::server {

class Router {
 public:
  // A handler answers through the reply it is given, exactly once, from any thread (a throw before it hands off
  // becomes the problem it throws).
  using Handler = std::function<void(const Request&, const Params&, Reply)>;
  // A handler that needs to know its caller (logging in, minting a token): where from, and who (as the gate found).
  using CallerHandler = std::function<Response(const Request&, const Params&, const Caller&, const Identity&)>;

  struct Route {
    http::verb method;
    std::vector<std::string> segments;  // "{name}" captures a segment
    auth::Access access;                // who may call it
    Handler handler;                    // one of the two
    CallerHandler caller_handler;
  };
  // A route as declared: its method, path pattern ("/api/v1/missions/{id}") and the access it needs.
  struct RouteInfo {
    http::verb method;
    std::string pattern;
    auth::Access access;
  };

  void Add(http::verb method, const std::string& pattern, auth::Access access, Handler handler);
  void AddWithCaller(http::verb method, const std::string& pattern, auth::Access access, CallerHandler handler);

  // The route `method` `path` names (params filled), or null; `path_matched` tells whether another method would.
  const Route* Find(http::verb method, std::string_view path, Params& params, bool& path_matched) const;
  std::vector<RouteInfo> Routes() const;

 private:
  std::vector<Route> routes_;
};

// A handler that answers synchronously.
Router::Handler Sync(std::function<Response(const Request&, const Params&)> f);

}  // namespace corridor::server
