// VDA 5050 2.1, the interface between a mobile robot and a master control over MQTT: topic names, the messages this
// robot sends (connection, state, visualization, factsheet), made from a sample of the robot, and every message
// checked against the standard's own JSON schemas (server/fleet/vda5050/, MIT, Verband der Automobilindustrie), which
// are compiled in and read by valijson. The MQTT client and orders build on this (server/fleet, issue 23).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "nav/geometry/pose2.h"

namespace corridor::server {

inline constexpr const char* kVdaVersion = "2.1.0";
inline constexpr const char* kVdaMajorVersion = "v2";

// Who the robot is to the master control: its topics are interface_name/v2/manufacturer/serial_number/<topic>.
struct VdaIdentity {
  std::string interface_name = "uagv";
  std::string manufacturer = "corridor";
  std::string serial_number;
};
std::string VdaTopic(const VdaIdentity& identity, std::string_view topic);

enum class VdaMessage { kOrder, kInstantActions, kState, kConnection, kFactsheet, kVisualization };
const char* ToString(VdaMessage message);  // its topic: order, instantActions, state, ...
// The standard's schema of `message`, as shipped (compiled in from server/fleet/vda5050/).
const std::string& VdaSchemaText(VdaMessage message);

// Checks messages against the schemas. Thread-safe after construction (parsing all six takes a few milliseconds).
class VdaSchemas {
 public:
  VdaSchemas();
  ~VdaSchemas();
  VdaSchemas(const VdaSchemas&) = delete;
  VdaSchemas& operator=(const VdaSchemas&) = delete;
  // Why `document` is not a valid `message`, one line per error naming where ("actions[0].actionType: ..."); empty
  // when it is.
  std::vector<std::string> Check(VdaMessage message, const nlohmann::json& document) const;

 private:
  struct Parsed;
  std::unique_ptr<Parsed> parsed_;
};

// Every message's header: a counter per topic and the time (ISO 8601, UTC, milliseconds).
struct VdaHeader {
  std::uint32_t header_id = 0;
  std::string timestamp;
};
// `unix_ms` as VDA 5050's timestamp: "2026-11-26T04:40:00.123Z".
std::string VdaTimestamp(std::int64_t unix_ms);

// The robot as state and visualization report it.
struct VdaRobot {
  std::string map_id;
  bool position_initialized = false;
  nav::Pose2 pose;
  double localization_score = 0.0;  // 0..1
  nav::Twist2 velocity;
  bool driving = false;
  bool paused = false;
  std::optional<double> battery_percent;
  double battery_voltage_v = 0.0;
  bool charging = false;
  bool manual = false;           // a person drives it (teleop): operatingMode MANUAL, else AUTOMATIC
  bool protective_stop = false;  // the command gate holds it (bump, fault, device not answering): eStop AUTOACK
  bool field_violation = false;  // something in the robot's way slows or stops it
  struct Error {
    std::string type;
    std::string level;  // WARNING or FATAL
    std::string description;
  };
  std::vector<Error> errors;
};

// connectionState: ONLINE, OFFLINE or CONNECTIONBROKEN (the broker's last will).
nlohmann::json VdaConnection(const VdaIdentity& identity, const VdaHeader& header, std::string_view state);
// The state without an order (orderId "", no nodes, edges or actions): what the robot reports before it takes
// orders over VDA 5050.
nlohmann::json VdaState(const VdaIdentity& identity, const VdaHeader& header, const VdaRobot& robot);
nlohmann::json VdaVisualization(const VdaIdentity& identity, const VdaHeader& header, const VdaRobot& robot);

// What the factsheet says of the robot's body.
struct VdaVehicle {
  std::string series_name = "corridor";
  double max_speed_mps = 0.5;
  double max_acceleration_mps2 = 1.0;
  double max_deceleration_mps2 = 0.8;
  double radius_m = 0.2;
  double height_m = 0.5;
};
nlohmann::json VdaFactsheet(const VdaIdentity& identity, const VdaHeader& header, const VdaVehicle& vehicle);

}  // namespace corridor::server
