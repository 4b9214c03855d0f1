#include "server/fleet/vda5050.h"

#include <chrono>
#include <cstdio>
#include <ctime>
#include <map>
#include <mutex>
#include <stdexcept>

#include <valijson/adapters/nlohmann_json_adapter.hpp>
#include <valijson/schema.hpp>
#include <valijson/schema_parser.hpp>
#include <valijson/validator.hpp>

namespace corridor::server {
namespace {

constexpr VdaMessage kAll[] = {VdaMessage::kOrder,      VdaMessage::kInstantActions, VdaMessage::kState,
                               VdaMessage::kConnection, VdaMessage::kFactsheet,      VdaMessage::kVisualization};

nlohmann::json Header(const VdaIdentity& identity, const VdaHeader& header) {
  return {{"headerId", header.header_id},
          {"timestamp", header.timestamp},
          {"version", kVdaVersion},
          {"manufacturer", identity.manufacturer},
          {"serialNumber", identity.serial_number}};
}

nlohmann::json Position(const VdaRobot& robot) {
  return {{"x", robot.pose.x_m},
          {"y", robot.pose.y_m},
          {"theta", robot.pose.yaw_rad},
          {"mapId", robot.map_id},
          {"positionInitialized", robot.position_initialized},
          {"localizationScore", robot.localization_score}};
}

nlohmann::json Velocity(const VdaRobot& robot) {
  return {{"vx", robot.velocity.linear_mps}, {"vy", 0.0}, {"omega", robot.velocity.angular_rps}};
}

}  // namespace

std::string VdaTopic(const VdaIdentity& identity, std::string_view topic) {
  return identity.interface_name + "/" + kVdaMajorVersion + "/" + identity.manufacturer + "/" + identity.serial_number +
         "/" + std::string(topic);
}

const char* ToString(VdaMessage message) {
  switch (message) {
    case VdaMessage::kOrder: return "order";
    case VdaMessage::kInstantActions: return "instantActions";
    case VdaMessage::kState: return "state";
    case VdaMessage::kConnection: return "connection";
    case VdaMessage::kFactsheet: return "factsheet";
    case VdaMessage::kVisualization: return "visualization";
  }
  return "unknown";
}

struct VdaSchemas::Parsed {
  std::map<VdaMessage, valijson::Schema> schemas;
  // One validator for every check: it keeps the schemas' patterns compiled (compiling them each time was 90 % of a
  // check's cost). It is not thread-safe, hence the lock.
  std::mutex mutex;
  valijson::Validator validator;
};

VdaSchemas::VdaSchemas() : parsed_(std::make_unique<Parsed>()) {
  // The files say draft 2020-12 but use only keywords draft 7 has, which is what valijson reads.
  valijson::SchemaParser parser(valijson::SchemaParser::kDraft7);
  for (VdaMessage m : kAll) {
    const nlohmann::json document = nlohmann::json::parse(VdaSchemaText(m));
    parser.populateSchema(valijson::adapters::NlohmannJsonAdapter(document), parsed_->schemas[m]);
  }
}

VdaSchemas::~VdaSchemas() = default;

std::vector<std::string> VdaSchemas::Check(VdaMessage message, const nlohmann::json& document) const {
  valijson::ValidationResults results;
  std::vector<std::string> errors;
  {
    std::lock_guard lock(parsed_->mutex);
    if (parsed_->validator.validate(parsed_->schemas.at(message), valijson::adapters::NlohmannJsonAdapter(document),
                                    &results)) {
      return errors;
    }
  }
  valijson::ValidationResults::Error error;
  while (results.popError(error)) {
    // valijson's context: "<root>", then [key] for properties and [n] for array items.
    std::string where;
    for (const std::string& part : error.context) {
      if (part.size() < 3 || part.front() != '[' || part.back() != ']') continue;
      std::string_view inner = std::string_view(part).substr(1, part.size() - 2);
      if (inner.size() >= 2 && inner.front() == '"' && inner.back() == '"') inner = inner.substr(1, inner.size() - 2);
      const bool index = inner.find_first_not_of("0123456789") == std::string_view::npos;
      if (index) {
        where.push_back('[');
        where.append(inner);
        where.push_back(']');
      } else {
        if (!where.empty()) where.push_back('.');
        where.append(inner);
      }
    }
    if (where.empty()) where = "the message";
    where.append(": ");
    where.append(error.description);
    errors.push_back(std::move(where));
  }
  return errors;
}

std::string VdaTimestamp(std::int64_t unix_ms) {
  const std::time_t seconds = static_cast<std::time_t>(unix_ms / 1000);
  std::tm utc{};
  gmtime_r(&seconds, &utc);
  char text[64];
  std::snprintf(text, sizeof(text), "%04d-%02d-%02dT%02d:%02d:%02d.%03dZ", utc.tm_year + 1900, utc.tm_mon + 1,
                utc.tm_mday, utc.tm_hour, utc.tm_min, utc.tm_sec, static_cast<int>(unix_ms % 1000));
  return text;
}

nlohmann::json VdaConnection(const VdaIdentity& identity, const VdaHeader& header, std::string_view state) {
  nlohmann::json message = Header(identity, header);
  message["connectionState"] = std::string(state);
  return message;
}

nlohmann::json VdaState(const VdaIdentity& identity, const VdaHeader& header, const VdaRobot& robot) {
  nlohmann::json message = Header(identity, header);
  message["orderId"] = "";
  message["orderUpdateId"] = 0;
  message["lastNodeId"] = "";
  message["lastNodeSequenceId"] = 0;
  message["nodeStates"] = nlohmann::json::array();
  message["edgeStates"] = nlohmann::json::array();
  message["actionStates"] = nlohmann::json::array();
  message["driving"] = robot.driving;
  message["paused"] = robot.paused;
  message["operatingMode"] = robot.manual ? "MANUAL" : "AUTOMATIC";
  if (robot.position_initialized || !robot.map_id.empty()) message["agvPosition"] = Position(robot);
  message["velocity"] = Velocity(robot);
  nlohmann::json battery = {{"batteryCharge", robot.battery_percent.value_or(0.0)}, {"charging", robot.charging}};
  if (robot.battery_percent) battery["batteryVoltage"] = robot.battery_voltage_v;
  message["batteryState"] = std::move(battery);
  nlohmann::json errors = nlohmann::json::array();
  // batteryCharge is required; a 0 alone would read as an empty battery, so the master is told it is not known.
  if (!robot.battery_percent) {
    errors.push_back({{"errorType", "batteryUnknown"},
                      {"errorLevel", "WARNING"},
                      {"errorDescription", "the base has not reported its battery yet"}});
  }
  for (const VdaRobot::Error& e : robot.errors) {
    errors.push_back({{"errorType", e.type}, {"errorLevel", e.level}, {"errorDescription", e.description}});
  }
  message["errors"] = std::move(errors);
  message["safetyState"] = {{"eStop", robot.protective_stop ? "AUTOACK" : "NONE"},
                            {"fieldViolation", robot.field_violation}};
  return message;
}

nlohmann::json VdaVisualization(const VdaIdentity& identity, const VdaHeader& header, const VdaRobot& robot) {
  nlohmann::json message = Header(identity, header);
  message["agvPosition"] = Position(robot);
  message["velocity"] = Velocity(robot);
  return message;
}

nlohmann::json VdaFactsheet(const VdaIdentity& identity, const VdaHeader& header, const VdaVehicle& v) {
  nlohmann::json message = Header(identity, header);
  message["typeSpecification"] = {
      {"seriesName", v.series_name}, {"agvKinematic", "DIFF"},           {"agvClass", "CARRIER"},
      {"maxLoadMass", 0.0},          {"localizationTypes", {"NATURAL"}}, {"navigationTypes", {"AUTONOMOUS"}}};
  message["physicalParameters"] = {{"speedMin", 0.0},
                                   {"speedMax", v.max_speed_mps},
                                   {"accelerationMax", v.max_acceleration_mps2},
                                   {"decelerationMax", v.max_deceleration_mps2},
                                   {"heightMax", v.height_m},
                                   {"width", 2.0 * v.radius_m},
                                   {"length", 2.0 * v.radius_m}};
  message["protocolLimits"] = {{"maxStringLens", nlohmann::json::object()},
                               {"maxArrayLens", nlohmann::json::object()},
                               {"timing", {{"minOrderInterval", 1.0}, {"minStateInterval", 0.1}}}};
  message["protocolFeatures"] = {{"optionalParameters", nlohmann::json::array()},
                                 {"agvActions", nlohmann::json::array()}};
  message["agvGeometry"] = nlohmann::json::object();
  message["loadSpecification"] = nlohmann::json::object();
  return message;
}

}  // namespace corridor::server
