#include "server/store/store.h"

#include <sqlite3.h>

#include <random>

namespace corridor::server {
namespace {

using nlohmann::json;

constexpr const char* kDeliveryColumns =
    "id, webhook, event, payload, status, attempts, created, last_attempt, response_status, error";

DeliveryRecord ReadDelivery(const Statement& s) {
  return {s.Text(0), s.Text(1), s.Text(2), s.Text(3), s.Text(4), s.Int(5), s.Text(6), s.Text(7), s.Int(8), s.Text(9)};
}

json PolygonJson(const std::vector<Eigen::Vector2d>& polygon) {
  json out = json::array();
  for (const auto& p : polygon) out.push_back({p.x(), p.y()});
  return out;
}

}  // namespace

std::string NewId() {
  static thread_local std::mt19937_64 rng{std::random_device{}()};
  char text[17];
  std::snprintf(text, sizeof(text), "%016llx", static_cast<unsigned long long>(rng()));
  return text;
}

namespace {

const char* const kSchema =
    "CREATE TABLE IF NOT EXISTS zones (map TEXT NOT NULL, id TEXT NOT NULL, name TEXT NOT NULL, kind TEXT NOT NULL,"
    " polygon TEXT NOT NULL, max_speed_mps REAL NOT NULL, PRIMARY KEY (map, id));"
    "CREATE TABLE IF NOT EXISTS places (map TEXT NOT NULL, id TEXT NOT NULL, name TEXT NOT NULL, x REAL NOT NULL,"
    " y REAL NOT NULL, yaw REAL NOT NULL, kind TEXT NOT NULL DEFAULT 'place', PRIMARY KEY (map, id));"
    "CREATE TABLE IF NOT EXISTS doors (map TEXT NOT NULL, id TEXT NOT NULL, x1 REAL NOT NULL, y1 REAL NOT NULL,"
    " x2 REAL NOT NULL, y2 REAL NOT NULL, PRIMARY KEY (map, id));"
    "CREATE TABLE IF NOT EXISTS lift_stops (lift TEXT NOT NULL, floor TEXT NOT NULL, x1 REAL NOT NULL,"
    " y1 REAL NOT NULL, x2 REAL NOT NULL, y2 REAL NOT NULL, lobby_x REAL NOT NULL, lobby_y REAL NOT NULL,"
    " lobby_yaw REAL NOT NULL, PRIMARY KEY (lift, floor));"
    "CREATE TABLE IF NOT EXISTS missions (id TEXT PRIMARY KEY, document TEXT NOT NULL,"
    " updated REAL NOT NULL DEFAULT (julianday('now')));"
    "CREATE TABLE IF NOT EXISTS webhooks (id TEXT PRIMARY KEY, url TEXT NOT NULL, events TEXT NOT NULL,"
    " secret TEXT NOT NULL, description TEXT NOT NULL, created TEXT NOT NULL);"
    "CREATE TABLE IF NOT EXISTS deliveries (seq INTEGER PRIMARY KEY AUTOINCREMENT, id TEXT NOT NULL UNIQUE,"
    " webhook TEXT NOT NULL, event TEXT NOT NULL, payload TEXT NOT NULL, status TEXT NOT NULL,"
    " attempts INTEGER NOT NULL, created TEXT NOT NULL, last_attempt TEXT NOT NULL,"
    " response_status INTEGER NOT NULL, error TEXT NOT NULL);"
    "CREATE INDEX IF NOT EXISTS deliveries_by_webhook ON deliveries (webhook, seq);"
    "CREATE TABLE IF NOT EXISTS events (seq INTEGER PRIMARY KEY AUTOINCREMENT, document TEXT NOT NULL);";

}  // namespace

Store::Store(const std::filesystem::path& file) : db_(file, kSchema) {
  // Databases from before places had kinds.
  Statement has_kind(db_, "SELECT COUNT(*) FROM pragma_table_info('places') WHERE name = 'kind'");
  if (has_kind.Step() && has_kind.Int(0) == 0)
    db_.Exec("ALTER TABLE places ADD COLUMN kind TEXT NOT NULL DEFAULT 'place'");
}

Store::~Store() = default;

std::vector<nav::Zone> Store::Zones(const std::string& map) const {
  std::lock_guard lock(mutex_);
  Statement s(db_, "SELECT id, name, kind, polygon, max_speed_mps FROM zones WHERE map = ? ORDER BY rowid");
  s.Bind(1, map);
  std::vector<nav::Zone> out;
  while (s.Step()) {
    nav::Zone z;
    z.id = s.Text(0);
    z.name = s.Text(1);
    z.kind = nav::ZoneKindFromString(s.Text(2)).value_or(nav::ZoneKind::kKeepOut);
    for (const json& p : json::parse(s.Text(3))) z.polygon.emplace_back(p[0].get<double>(), p[1].get<double>());
    z.max_speed_mps = s.Double(4);
    out.push_back(std::move(z));
  }
  return out;
}

void Store::RenameMap(const std::string& from, const std::string& to) {
  std::lock_guard lock(mutex_);
  InTransaction(db_, [&] {
    for (const char* sql : {"UPDATE zones SET map = ? WHERE map = ?", "UPDATE places SET map = ? WHERE map = ?",
                            "UPDATE doors SET map = ? WHERE map = ?"}) {
      Statement s(db_, sql);
      s.Bind(1, to).Bind(2, from);
      s.Step();
    }
  });
}

void Store::DeleteMap(const std::string& name) {
  std::lock_guard lock(mutex_);
  InTransaction(db_, [&] {
    for (const char* sql :
         {"DELETE FROM zones WHERE map = ?", "DELETE FROM places WHERE map = ?", "DELETE FROM doors WHERE map = ?"}) {
      Statement s(db_, sql);
      s.Bind(1, name);
      s.Step();
    }
  });
}

void Store::PutZone(const std::string& map, const nav::Zone& zone) {
  std::lock_guard lock(mutex_);
  Statement s(db_, "INSERT OR REPLACE INTO zones (map, id, name, kind, polygon, max_speed_mps) VALUES (?,?,?,?,?,?)");
  s.Bind(1, map).Bind(2, zone.id).Bind(3, zone.name).Bind(4, std::string(nav::ToString(zone.kind)));
  s.Bind(5, PolygonJson(zone.polygon).dump()).Bind(6, zone.max_speed_mps);
  s.Step();
}

bool Store::DeleteZone(const std::string& map, const std::string& id) {
  std::lock_guard lock(mutex_);
  Statement s(db_, "DELETE FROM zones WHERE map = ? AND id = ?");
  s.Bind(1, map).Bind(2, id);
  s.Step();
  return s.changes() > 0;
}

std::vector<nav::Place> Store::Places(const std::string& map) const {
  std::lock_guard lock(mutex_);
  Statement s(db_, "SELECT id, name, x, y, yaw, kind FROM places WHERE map = ? ORDER BY name");
  s.Bind(1, map);
  std::vector<nav::Place> out;
  while (s.Step()) {
    out.push_back({s.Text(0),
                   s.Text(1),
                   {s.Double(2), s.Double(3), s.Double(4)},
                   nav::PlaceKindFromString(s.Text(5)).value_or(nav::PlaceKind::kPlace)});
  }
  return out;
}

void Store::PutPlace(const std::string& map, const nav::Place& place) {
  std::lock_guard lock(mutex_);
  Statement s(db_, "INSERT OR REPLACE INTO places (map, id, name, x, y, yaw, kind) VALUES (?,?,?,?,?,?,?)");
  s.Bind(1, map).Bind(2, place.id).Bind(3, place.name).Bind(4, place.pose.x_m).Bind(5, place.pose.y_m);
  s.Bind(6, place.pose.yaw_rad).Bind(7, std::string(nav::ToString(place.kind)));
  s.Step();
}

bool Store::DeletePlace(const std::string& map, const std::string& id) {
  std::lock_guard lock(mutex_);
  Statement s(db_, "DELETE FROM places WHERE map = ? AND id = ?");
  s.Bind(1, map).Bind(2, id);
  s.Step();
  return s.changes() > 0;
}

std::vector<nav::Door> Store::Doors(const std::string& map) const {
  std::lock_guard lock(mutex_);
  Statement s(db_, "SELECT id, x1, y1, x2, y2 FROM doors WHERE map = ? ORDER BY id");
  s.Bind(1, map);
  std::vector<nav::Door> out;
  while (s.Step()) out.push_back({s.Text(0), {s.Double(1), s.Double(2)}, {s.Double(3), s.Double(4)}});
  return out;
}

void Store::PutDoor(const std::string& map, const nav::Door& door) {
  std::lock_guard lock(mutex_);
  Statement s(db_, "INSERT OR REPLACE INTO doors (map, id, x1, y1, x2, y2) VALUES (?,?,?,?,?,?)");
  s.Bind(1, map).Bind(2, door.id).Bind(3, door.a.x()).Bind(4, door.a.y()).Bind(5, door.b.x()).Bind(6, door.b.y());
  s.Step();
}

bool Store::DeleteDoor(const std::string& map, const std::string& id) {
  std::lock_guard lock(mutex_);
  Statement s(db_, "DELETE FROM doors WHERE map = ? AND id = ?");
  s.Bind(1, map).Bind(2, id);
  s.Step();
  return s.changes() > 0;
}

std::vector<std::pair<std::string, nav::LiftStop>> Store::LiftStops() const {
  std::lock_guard lock(mutex_);
  Statement s(db_,
              "SELECT lift, floor, x1, y1, x2, y2, lobby_x, lobby_y, lobby_yaw FROM lift_stops ORDER BY lift, floor");
  std::vector<std::pair<std::string, nav::LiftStop>> out;
  while (s.Step()) {
    nav::LiftStop stop{s.Text(1),
                       {"", {s.Double(2), s.Double(3)}, {s.Double(4), s.Double(5)}},
                       {s.Double(6), s.Double(7), s.Double(8)}};
    out.emplace_back(s.Text(0), std::move(stop));
  }
  return out;
}

void Store::PutLiftStop(const std::string& lift, const nav::LiftStop& stop) {
  std::lock_guard lock(mutex_);
  Statement s(db_,
              "INSERT OR REPLACE INTO lift_stops (lift, floor, x1, y1, x2, y2, lobby_x, lobby_y, lobby_yaw)"
              " VALUES (?,?,?,?,?,?,?,?,?)");
  s.Bind(1, lift).Bind(2, stop.floor).Bind(3, stop.door.a.x()).Bind(4, stop.door.a.y()).Bind(5, stop.door.b.x());
  s.Bind(6, stop.door.b.y()).Bind(7, stop.lobby.x_m).Bind(8, stop.lobby.y_m).Bind(9, stop.lobby.yaw_rad);
  s.Step();
}

bool Store::DeleteLiftStop(const std::string& lift, const std::string& floor) {
  std::lock_guard lock(mutex_);
  Statement s(db_, "DELETE FROM lift_stops WHERE lift = ? AND floor = ?");
  s.Bind(1, lift).Bind(2, floor);
  s.Step();
  return s.changes() > 0;
}

void Store::PutMission(const std::string& id, const json& document) {
  std::lock_guard lock(mutex_);
  Statement s(db_, "INSERT OR REPLACE INTO missions (id, document, updated) VALUES (?, ?, julianday('now'))");
  s.Bind(1, id).Bind(2, document.dump());
  s.Step();
}

std::optional<json> Store::Mission(const std::string& id) const {
  std::lock_guard lock(mutex_);
  Statement s(db_, "SELECT document FROM missions WHERE id = ?");
  s.Bind(1, id);
  if (!s.Step()) return std::nullopt;
  return json::parse(s.Text(0));
}

std::vector<json> Store::Missions(int limit) const {
  std::lock_guard lock(mutex_);
  Statement s(db_, "SELECT document FROM missions ORDER BY updated DESC LIMIT ?");
  s.Bind(1, static_cast<double>(limit));
  std::vector<json> out;
  while (s.Step()) out.push_back(json::parse(s.Text(0)));
  return out;
}

std::vector<WebhookRecord> Store::Webhooks() const {
  std::lock_guard lock(mutex_);
  Statement s(db_, "SELECT id, url, events, secret, description, created FROM webhooks ORDER BY created, id");
  std::vector<WebhookRecord> out;
  while (s.Step()) {
    out.push_back({s.Text(0), s.Text(1), json::parse(s.Text(2)).get<std::vector<std::string>>(), s.Text(3), s.Text(4),
                   s.Text(5)});
  }
  return out;
}

std::optional<WebhookRecord> Store::Webhook(const std::string& id) const {
  for (WebhookRecord& w : Webhooks()) {
    if (w.id == id) return std::move(w);
  }
  return std::nullopt;
}

void Store::PutWebhook(const WebhookRecord& w) {
  std::lock_guard lock(mutex_);
  Statement s(db_,
              "INSERT OR REPLACE INTO webhooks (id, url, events, secret, description, created) VALUES (?,?,?,?,?,?)");
  s.Bind(1, w.id).Bind(2, w.url).Bind(3, json(w.events).dump()).Bind(4, w.secret).Bind(5, w.description);
  s.Bind(6, w.created);
  s.Step();
}

bool Store::DeleteWebhook(const std::string& id) {
  std::lock_guard lock(mutex_);
  bool deleted = false;
  InTransaction(db_, [&] {
    Statement deliveries(db_, "DELETE FROM deliveries WHERE webhook = ?");
    deliveries.Bind(1, id);
    deliveries.Step();
    Statement s(db_, "DELETE FROM webhooks WHERE id = ?");
    s.Bind(1, id);
    s.Step();
    deleted = s.changes() > 0;
  });
  return deleted;
}

void Store::AddDelivery(const DeliveryRecord& d, int keep) {
  std::lock_guard lock(mutex_);
  InTransaction(db_, [&] {
    const std::string sql =
        std::string("INSERT INTO deliveries (") + kDeliveryColumns + ") VALUES (?,?,?,?,?,?,?,?,?,?)";
    Statement s(db_, sql.c_str());
    s.Bind(1, d.id).Bind(2, d.webhook).Bind(3, d.event).Bind(4, d.payload).Bind(5, d.status).Bind(6, d.attempts);
    s.Bind(7, d.created).Bind(8, d.last_attempt).Bind(9, d.response_status).Bind(10, d.error);
    s.Step();
    Statement prune(db_,
                    "DELETE FROM deliveries WHERE webhook = ? AND status != 'pending' AND seq NOT IN"
                    " (SELECT seq FROM deliveries WHERE webhook = ? ORDER BY seq DESC LIMIT ?)");
    prune.Bind(1, d.webhook).Bind(2, d.webhook).Bind(3, keep);
    prune.Step();
  });
}

void Store::UpdateDelivery(const DeliveryRecord& d) {
  std::lock_guard lock(mutex_);
  Statement s(db_,
              "UPDATE deliveries SET status = ?, attempts = ?, last_attempt = ?, response_status = ?, error = ?"
              " WHERE id = ?");
  s.Bind(1, d.status).Bind(2, d.attempts).Bind(3, d.last_attempt).Bind(4, d.response_status).Bind(5, d.error);
  s.Bind(6, d.id);
  s.Step();
}

std::vector<DeliveryRecord> Store::Deliveries(const std::string& webhook, int limit) const {
  std::lock_guard lock(mutex_);
  Statement s(
      db_, (std::string("SELECT ") + kDeliveryColumns + " FROM deliveries WHERE webhook = ? ORDER BY seq DESC LIMIT ?")
               .c_str());
  s.Bind(1, webhook).Bind(2, limit);
  std::vector<DeliveryRecord> out;
  while (s.Step()) out.push_back(ReadDelivery(s));
  return out;
}

std::vector<DeliveryRecord> Store::PendingDeliveries() const {
  std::lock_guard lock(mutex_);
  Statement s(
      db_,
      (std::string("SELECT ") + kDeliveryColumns + " FROM deliveries WHERE status = 'pending' ORDER BY seq").c_str());
  std::vector<DeliveryRecord> out;
  while (s.Step()) out.push_back(ReadDelivery(s));
  return out;
}

std::int64_t Store::AddEvent(const json& document, int keep) {
  std::lock_guard lock(mutex_);
  std::int64_t seq = 0;
  InTransaction(db_, [&] {
    Statement s(db_, "INSERT INTO events (document) VALUES (?)");
    s.Bind(1, document.dump());
    s.Step();
    seq = sqlite3_last_insert_rowid(db_.handle());
    Statement prune(db_, "DELETE FROM events WHERE seq <= ?");
    prune.Bind(1, seq - keep);
    prune.Step();
  });
  return seq;
}

std::vector<json> Store::Events(std::int64_t after, int limit) const {
  std::lock_guard lock(mutex_);
  Statement s(db_,
              "SELECT seq, document FROM (SELECT seq, document FROM events WHERE seq > ? ORDER BY seq DESC LIMIT ?)"
              " ORDER BY seq");
  s.Bind(1, after).Bind(2, limit);
  std::vector<json> out;
  while (s.Step()) {
    json e = json::parse(s.Text(1));
    e["sequence"] = s.Int64(0);
    out.push_back(std::move(e));
  }
  return out;
}

}  // namespace corridor::server
