#include "server/api/router.h"

namespace corridor::server {
namespace {

std::vector<std::string> Split(std::string_view path) {
  std::vector<std::string> out;
  while (!path.empty()) {
    if (path.front() == '/') {
      path.remove_prefix(1);
      continue;
    }
    const auto slash = path.find('/');
    out.emplace_back(path.substr(0, slash));
    if (slash == std::string_view::npos) break;
    path.remove_prefix(slash);
  }
  return out;
}

}  // namespace

Router::Handler Sync(std::function<Response(const Request&, const Params&)> f) {
  return [f = std::move(f)](const Request& request, const Params& params, Reply reply) { reply(f(request, params)); };
}

void Router::Add(http::verb method, const std::string& pattern, auth::Access access, Handler handler) {
  routes_.push_back({method, Split(pattern), access, std::move(handler), nullptr});
}

void Router::AddWithCaller(http::verb method, const std::string& pattern, auth::Access access, CallerHandler handler) {
  routes_.push_back({method, Split(pattern), access, nullptr, std::move(handler)});
}

std::vector<Router::RouteInfo> Router::Routes() const {
  std::vector<RouteInfo> routes;
  for (const Route& route : routes_) {
    std::string pattern;
    for (const std::string& segment : route.segments) pattern += "/" + segment;
    routes.push_back({route.method, pattern, route.access});
  }
  return routes;
}

const Router::Route* Router::Find(http::verb method, std::string_view path, Params& params, bool& path_matched) const {
  const std::vector<std::string> segments = Split(path);
  path_matched = false;
  for (const Route& route : routes_) {
    if (route.segments.size() != segments.size()) continue;
    Params captured;
    bool match = true;
    for (std::size_t i = 0; i < segments.size() && match; ++i) {
      const std::string& want = route.segments[i];
      if (want.size() > 2 && want.front() == '{' && want.back() == '}') {
        captured[want.substr(1, want.size() - 2)] = segments[i];
      } else {
        match = want == segments[i];
      }
    }
    if (!match) continue;
    path_matched = true;
    if (route.method != method) continue;
    params = std::move(captured);
    return &route;
  }
  return nullptr;
}

}  // namespace corridor::server
