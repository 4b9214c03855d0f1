// The REST API and the WebSocket stream's messages, independent of the transport (http_server.h carries them).
// Every route is described in openapi.json; errors are RFC 9457 problem details (application/problem+json).
#pragma once

#include <boost/beast/http.hpp>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <stdexcept>
#include <string>

#include "nav/map/occupancy_grid.h"
#include "server/runtime/bus.h"
#include "server/runtime/config.h"
#include "server/runtime/node.h"

namespace corridor::server {

namespace http = boost::beast::http;
using Request = http::request<http::string_body>;
using Response = http::response<http::string_body>;

// A request the API refuses; becomes a problem+json response with this status.
class ApiError : public std::runtime_error {
 public:
  ApiError(http::status status, std::string title, const std::string& detail)
      : std::runtime_error(detail), status_(status), title_(std::move(title)) {}
  http::status status() const { return status_; }
  const std::string& title() const { return title_; }

 private:
  http::status status_;
  std::string title_;
};

// The map the robot works in, with its image encoded once for the console.
struct ActiveMap {
  std::string name;
  nav::OccupancyGrid grid;
  std::string png;  // 8-bit grey, map_server trinary shades, row 0 at the top
};

Response ProblemResponse(http::status status, const std::string& title, const std::string& detail,
                         unsigned version, bool keep_alive);

class Api {
 public:
  Api(Bus& bus, const Lifecycle& lifecycle, const ActiveMap& map, const Config& config, const drivers::Clock& clock);

  // Answers one HTTP request (never throws; errors become problem responses). Called on the io executor.
  Response Handle(const Request& request) const;

  // The state document of GET /api/v1/state, also pushed on the stream.
  nlohmann::json State() const;

  // Validates a teleop body {"linear_mps", "angular_rps"} and publishes it; returns what will be applied.
  // Throws ApiError for a malformed command.
  nlohmann::json Teleop(const nlohmann::json& body, const std::string& source) const;

  // Handles one text message from a stream client; returns the reply to send, if any. Throws ApiError.
  nlohmann::json StreamMessage(const std::string& text, std::vector<std::string>& subscriptions) const;

  // The stream's message for one topic, or nullopt when it has no JSON message yet.
  std::optional<nlohmann::json> TopicMessage(const std::string& topic) const;

  const std::filesystem::path& web_root() const { return web_root_; }

 private:
  Response Route(const Request& request) const;
  Response ServeFile(const Request& request, const std::string& target) const;
  Response CameraImage(const Request& request, bool depth) const;

  Bus& bus_;
  const Lifecycle& lifecycle_;
  const ActiveMap& map_;
  const Config& config_;
  const drivers::Clock& clock_;
  drivers::TimeNs start_ns_;
  std::filesystem::path web_root_;
};

// The OpenAPI 3.1 document (server/api/openapi.json, built into the binary).
const std::string& OpenApiDocument();

}  // namespace corridor::server
