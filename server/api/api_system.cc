#include "server/api/api_system.h"

#include <spdlog/fmt/ranges.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "drivers/discovery.h"
#include "drivers/openni2/openni2_camera.h"
#include "drivers/realsense/v4l2_capture.h"
#include "server/config/config_file.h"
#include "server/runtime/topics.h"

namespace corridor::server {
namespace {

using auth::Access;
using nlohmann::json;

// The serial ports, video nodes and OpenNI2 devices of this machine, with the driver each suggests.
json Hardware() {
  json serial = json::array();
  for (const drivers::SerialPortInfo& p : drivers::ListSerialPorts()) {
    serial.push_back({{"path", p.path}, {"names", p.names}, {"usb_id", p.usb_id}, {"driver", p.driver}});
  }
  json video = json::array();
  for (const drivers::realsense::VideoNode& v : drivers::realsense::ListVideoNodes()) {
    json formats = json::array();
    bool depth = false;
    for (const std::uint32_t f : v.formats) {
      std::string code;
      for (int shift = 0; shift < 32; shift += 8) code.push_back(static_cast<char>((f >> shift) & 0xFF));
      while (!code.empty() && code.back() == ' ') code.pop_back();
      formats.push_back(code);
      depth = depth || f == drivers::realsense::kZ16;
    }
    const bool realsense = depth && v.card.find("RealSense") != std::string::npos;
    video.push_back(
        {{"path", v.path}, {"name", v.card}, {"formats", formats}, {"driver", realsense ? "realsense" : ""}});
  }
  json openni2 = json::array();
  try {
    for (const drivers::openni2::OpenNi2Device& d : drivers::openni2::ListOpenNi2Devices()) {
      openni2.push_back({{"uri", d.uri}, {"name", d.name}, {"vendor", d.vendor}});
    }
  } catch (const std::runtime_error& e) {
    spdlog::warn("devices: listing OpenNI2 devices: {}", e.what());
  }
  return {{"serial", serial}, {"video", video}, {"openni2", openni2}};
}

}  // namespace

SystemApi::SystemApi(Bus& bus, const RobotCore& core, const Config& config, const drivers::Clock& clock,
                     const drivers::Laser2D* laser)
    : bus_(bus), core_(core), config_(config), clock_(clock), laser_(laser), start_ns_(clock.Now()) {
  if (config_.file.empty()) return;
  try {
    started_config_ = ConfigDocument(config_.file);
  } catch (const ConfigError&) {
  }
}

void SystemApi::AddRoutes(Router& routes) const {
  routes.Add(http::verb::get, "/api/v1/health", Access::kPublic, Sync([this](const Request& r, const Params&) {
               return JsonResponse(r, {{"status", "ok"},
                                       {"version", CORRIDOR_VERSION},
                                       {"uptime_s", drivers::ToSeconds(clock_.Now() - start_ns_)}});
             }));
  routes.Add(http::verb::get, "/api/v1/state", Access::kViewer, Sync([this](const Request& r, const Params&) {
               return MakeResponse(r, http::status::ok, "application/json", core_.State()->text);
             }));
  routes.Add(http::verb::post, "/api/v1/teleop", Access::kOperator, Sync([this](const Request& r, const Params&) {
               return JsonResponse(r, Teleop(ParseJsonBody(r), "rest"));
             }));
  routes.Add(http::verb::get, "/api/v1/camera/depth", Access::kViewer,
             Sync([this](const Request& r, const Params&) { return CameraImage(r, true); }));
  routes.Add(http::verb::get, "/api/v1/camera/color", Access::kViewer,
             Sync([this](const Request& r, const Params&) { return CameraImage(r, false); }));
  routes.Add(http::verb::get, "/api/v1/devices", Access::kViewer, Sync([this](const Request& r, const Params&) {
               const auto health = bus_.Get(topics::kDevices).latest();
               if (!health) {
                 throw ApiError(http::status::service_unavailable, "Not yet",
                                "the devices' health is not reported yet");
               }
               return JsonResponse(r, ToJson(*health));
             }));
  // What is plugged in, for setting a robot up: serial ports, video nodes, OpenNI2 devices (admin: it names devices'
  // paths and serial numbers).
  routes.Add(http::verb::get, "/api/v1/devices/hardware", Access::kAdmin,
             Sync([](const Request& r, const Params&) { return JsonResponse(r, Hardware()); }));
  routes.Add(http::verb::get, "/api/v1/laser/scan", Access::kViewer, Sync([this](const Request& r, const Params&) {
               if (laser_ == nullptr) throw ApiError(http::status::not_found, "No laser", "this robot has no laser");
               const auto scan = bus_.Get(topics::kScan).latest();
               if (!scan)
                 throw ApiError(http::status::service_unavailable, "No scan", "the laser has not sent a scan yet");
               json body = ToJson(*scan);
               body["frame"] = "laser";
               body["base_T_laser"] = ToJson(laser_->base_T_laser());
               body["height_m"] = laser_->height_m();
               return JsonResponse(r, body);
             }));
  routes.Add(http::verb::get, "/api/v1/topics", Access::kViewer, Sync([this](const Request& r, const Params&) {
               return JsonResponse(r, {{"topics", bus_.names()}});
             }));
  routes.Add(http::verb::get, "/api/v1/openapi.json", Access::kPublic, Sync([](const Request& r, const Params&) {
               return MakeResponse(r, http::status::ok, "application/json", OpenApiDocument());
             }));
  // The configuration file: read, and changed with a JSON merge patch checked as strictly as at start-up.
  const auto config_file = [this]() {
    if (config_.file.empty()) throw ApiError(http::status::not_found, "No configuration file", "built in code");
    return config_.file;
  };
  // The keys whose values in the file are not those the daemon started with: they take effect at the next start.
  const auto pending = [this](const json& document) {
    return started_config_.is_null() ? json::array() : json(ChangedKeys(started_config_, document));
  };
  routes.Add(
      http::verb::get, "/api/v1/config", Access::kAdmin, Sync([config_file, pending](const Request& r, const Params&) {
        const auto file = config_file();
        try {
          const json document = ConfigDocument(file);
          return JsonResponse(r, {{"file", file.string()}, {"config", document}, {"pending", pending(document)}});
        } catch (const ConfigError& e) {
          throw ApiError(http::status::service_unavailable, "Configuration unreadable", e.what());
        }
      }));
  routes.Add(http::verb::get, "/api/v1/config/schema", Access::kAdmin,
             Sync([config_file](const Request& r, const Params&) {
               const auto file = config_file();
               try {
                 return JsonResponse(r, ConfigSchemaJson(file));
               } catch (const ConfigError& e) {
                 throw ApiError(http::status::service_unavailable, "Configuration unreadable", e.what());
               }
             }));
  routes.Add(
      http::verb::patch, "/api/v1/config", Access::kAdmin,
      Sync([config_file, pending](const Request& r, const Params&) {
        const auto file = config_file();
        const json patch = ParseJsonBody(r);
        ConfigChange change;
        try {
          change = PatchConfigFile(file, patch);
        } catch (const ConfigError& e) {
          throw ApiError(http::status::unprocessable_entity, "Invalid configuration", e.what(), "invalid_config");
        } catch (const std::runtime_error& e) {
          throw ApiError(http::status::conflict, "Configuration not written", e.what(), "not_writable");
        }
        spdlog::info("configuration changed through the API: {}", fmt::join(change.changed, ", "));
        return JsonResponse(r, {{"file", file.string()},
                                {"config", change.document},
                                {"changed", change.changed},
                                {"pending", pending(change.document)},
                                {"restart_required", !change.changed.empty()},
                                {"detail", change.changed.empty() ? "nothing changed"
                                                                  : "corridord reads its configuration at start: "
                                                                    "restart it (systemctl restart corridor)"}});
      }));
}

json SystemApi::Teleop(const json& body, const std::string& source) const {
  if (!body.is_object()) throw ApiError(http::status::bad_request, "Invalid command", "expected a JSON object");
  AllowOnlyKeys(body, {"linear_mps", "angular_rps", "type"}, "");
  const double v = RequireNumber(body, "linear_mps", "");
  const double w = RequireNumber(body, "angular_rps", "");
  const nav::Twist2 applied = core_.Teleop({v, w}, source);
  return {{"applied", ToJson(applied)}, {"expires_in_s", config_.safety.teleop_deadman_s}};
}

Response SystemApi::CameraImage(const Request& request, bool depth) const {
  if (config_.devices.camera.driver == DeviceDriver::kNone) {
    throw ApiError(http::status::not_found, "No camera", "this robot has no camera (devices.camera.driver: none)");
  }
  const auto frame = bus_.Get(topics::kRgbd).latest();
  if (!frame)
    throw ApiError(http::status::service_unavailable, "No camera frame", "the camera has not sent a frame yet");
  std::vector<std::uint8_t> bytes;
  std::string type = "image/png";
  if (!depth) {
    cv::imencode(".jpg", frame->color_bgr, bytes, {cv::IMWRITE_JPEG_QUALITY, 85});
    type = "image/jpeg";
  } else if (QueryValue(request.target(), "colormap") == "true") {
    // For people: near is warm, far is cool, holes are black.
    cv::Mat scaled;
    const double max_mm = std::max(1.0, config_.sim.robot.camera.max_range_m * 1000.0);
    frame->depth_mm.convertTo(scaled, CV_8U, -255.0 / max_mm, 255.0);
    cv::Mat colored;
    cv::applyColorMap(scaled, colored, cv::COLORMAP_TURBO);
    colored.setTo(cv::Scalar(0, 0, 0), frame->depth_mm == 0);
    cv::imencode(".png", colored, bytes);
  } else {
    cv::imencode(".png", frame->depth_mm, bytes);  // 16-bit, millimetres, 0 = no measurement
  }
  Response res = MakeResponse(request, http::status::ok, type, std::string(bytes.begin(), bytes.end()));
  res.set("X-Frame-Sequence", std::to_string(frame->sequence));
  res.prepare_payload();
  return res;
}

}  // namespace corridor::server
