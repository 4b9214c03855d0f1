// The robot's database (SQLite, <state_dir>/corridor.db): zones and named places per map, and missions. Every
// write is one transaction, so a crash or power cut leaves the old or the new state, never a torn one.
// Thread-safe: one connection behind a mutex (writes are rare and small; keep them off the control executor).
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "nav/map/zones.h"
#include "nav/mission/doors.h"
#include "nav/mission/lifts.h"
#include "server/store/sqlite.h"

namespace corridor::server {

// A subscription to the robot's events (server/api/webhooks.h): where they are POSTed, which, and the secret their
// signature is made with.
struct WebhookRecord {
  std::string id;
  std::string url;
  std::vector<std::string> events;  // face/events.h names
  std::string secret;
  std::string description;
  std::string created;  // ISO 8601, UTC
};

// One event's delivery to one webhook, and how it went.
struct DeliveryRecord {
  std::string id{};
  std::string webhook{};
  std::string event{};             // its type
  std::string payload{};           // the JSON body sent
  std::string status = "pending";  // pending, delivered, failed
  int attempts = 0;
  std::string created{};       // ISO 8601, UTC
  std::string last_attempt{};  // ISO 8601, UTC; empty before the first
  int response_status = 0;     // the receiver's HTTP status at the last attempt; 0: none (it could not be reached)
  std::string error{};         // why the last attempt failed
};

class Store {
 public:
  // Opens or creates the database and its tables. Throws StoreError.
  explicit Store(const std::filesystem::path& file);
  Store(const Store&) = delete;
  Store& operator=(const Store&) = delete;
  ~Store();

  std::vector<nav::Zone> Zones(const std::string& map) const;
  void PutZone(const std::string& map, const nav::Zone& zone);  // insert or replace by id
  bool DeleteZone(const std::string& map, const std::string& id);

  std::vector<nav::Place> Places(const std::string& map) const;
  void PutPlace(const std::string& map, const nav::Place& place);
  bool DeletePlace(const std::string& map, const std::string& id);

  // Doors drawn on a map (the console's); the configuration's are not here.
  std::vector<nav::Door> Doors(const std::string& map) const;
  void PutDoor(const std::string& map, const nav::Door& door);  // insert or replace by id
  bool DeleteDoor(const std::string& map, const std::string& id);

  // What belongs to map `from` (its zones, places and doors) now belongs to map `to`, in one transaction.
  void RenameMap(const std::string& from, const std::string& to);
  // Forgets map `name`'s zones, places and doors, in one transaction.
  void DeleteMap(const std::string& name);

  // Lift stops drawn in the console (lift id, stop), for the building beside the configuration's lifts.
  std::vector<std::pair<std::string, nav::LiftStop>> LiftStops() const;
  void PutLiftStop(const std::string& lift, const nav::LiftStop& stop);  // insert or replace by lift and floor
  bool DeleteLiftStop(const std::string& lift, const std::string& floor);

  // Missions are kept as their JSON documents (request and latest status), newest first.
  void PutMission(const std::string& id, const nlohmann::json& document);
  std::optional<nlohmann::json> Mission(const std::string& id) const;
  std::vector<nlohmann::json> Missions(int limit) const;

  std::vector<WebhookRecord> Webhooks() const;
  std::optional<WebhookRecord> Webhook(const std::string& id) const;
  void PutWebhook(const WebhookRecord& webhook);
  bool DeleteWebhook(const std::string& id);  // and its deliveries

  // Adds a delivery, then forgets the oldest finished ones of its webhook beyond `keep`.
  void AddDelivery(const DeliveryRecord& delivery, int keep);
  void UpdateDelivery(const DeliveryRecord& delivery);
  std::vector<DeliveryRecord> Deliveries(const std::string& webhook, int limit) const;  // newest first
  std::vector<DeliveryRecord> PendingDeliveries() const;                                // oldest first

  // The robot's events (face/events.h) as their JSON documents, numbered from 1 across restarts. AddEvent returns the
  // event's number and forgets all but the newest `keep`.
  std::int64_t AddEvent(const nlohmann::json& document, int keep);
  // The newest `limit` events numbered above `after`, oldest first, each with its "sequence".
  std::vector<nlohmann::json> Events(std::int64_t after, int limit) const;

 private:
  mutable std::mutex mutex_;
  Database db_;
};

// A random identifier for new records: 16 hex digits.
std::string NewId();

}  // namespace corridor::server
