#include "server/store/store.h"

#include <gtest/gtest.h>

#include <fstream>

namespace corridor::server {
namespace {

namespace fs = std::filesystem;

class StoreTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("corridor_store_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(StoreTest, ZonesPlacesAndMissionsSurviveReopening) {
  {
    Store store(dir_ / "corridor.db");
    store.PutZone("willow", {"z1", "wet floor", nav::ZoneKind::kKeepOut, {{0, 0}, {1, 0}, {1, 1}}, 0.0});
    store.PutZone("willow", {"z2", "lobby", nav::ZoneKind::kSpeedLimit, {{0, 0}, {2, 0}, {2, 2}}, 0.3});
    store.PutZone("house", {"z3", "other map", nav::ZoneKind::kKeepOut, {{0, 0}, {1, 0}, {1, 1}}, 0.0});
    store.PutPlace("willow", {"p1", "kitchen", {1.0, 2.0, 0.5}});
    store.PutMission("m1", {{"id", "m1"}, {"status", "active"}});
    store.PutMission("m1", {{"id", "m1"}, {"status", "succeeded"}});
  }
  Store store(dir_ / "corridor.db");
  const auto zones = store.Zones("willow");
  ASSERT_EQ(zones.size(), 2u);
  EXPECT_EQ(zones[1].kind, nav::ZoneKind::kSpeedLimit);
  EXPECT_DOUBLE_EQ(zones[1].max_speed_mps, 0.3);
  EXPECT_TRUE(zones[0].polygon[1].isApprox(Eigen::Vector2d(1, 0)));
  EXPECT_EQ(store.Zones("house").size(), 1u);
  EXPECT_TRUE(store.DeleteZone("willow", "z1"));
  EXPECT_FALSE(store.DeleteZone("willow", "z1"));
  EXPECT_EQ(store.Places("willow").at(0).name, "kitchen");
  EXPECT_DOUBLE_EQ(store.Places("willow").at(0).pose.yaw_rad, 0.5);
  EXPECT_EQ((*store.Mission("m1"))["status"], "succeeded");
  EXPECT_EQ(store.Missions(10).size(), 1u);
  EXPECT_FALSE(store.Mission("nope"));
}

TEST_F(StoreTest, ADatabaseFromBeforePlaceKindsKeepsItsPlacesAndTakesDocks) {
  {
    // The places table as releases before docks made it.
    Database old(dir_ / "corridor.db",
                 "CREATE TABLE places (map TEXT NOT NULL, id TEXT NOT NULL, name TEXT NOT NULL, x REAL NOT NULL,"
                 " y REAL NOT NULL, yaw REAL NOT NULL, PRIMARY KEY (map, id));"
                 "INSERT INTO places VALUES ('willow', 'p1', 'kitchen', 1.0, 2.0, 0.5);");
  }
  Store store(dir_ / "corridor.db");
  ASSERT_EQ(store.Places("willow").size(), 1u);
  EXPECT_EQ(store.Places("willow")[0].kind, nav::PlaceKind::kPlace);
  store.PutPlace("willow", {"d1", "charger", {3.0, 1.0, 0.0}, nav::PlaceKind::kDock});
  Store reopened(dir_ / "corridor.db");
  const auto places = reopened.Places("willow");
  ASSERT_EQ(places.size(), 2u);
  EXPECT_EQ(places[0].name, "charger");
  EXPECT_EQ(places[0].kind, nav::PlaceKind::kDock);
  EXPECT_EQ(places[1].kind, nav::PlaceKind::kPlace);
}

TEST_F(StoreTest, WebhooksAndTheirDeliveriesSurviveReopeningAndOldOnesAreForgotten) {
  {
    Store store(dir_ / "corridor.db");
    store.PutWebhook({"w1", "http://127.0.0.1:9000/hook", {"bump", "lost"}, "s3cret-s3cret-s3cret", "lift", "t0"});
    store.PutWebhook({"w2", "https://example.org/x", {"fault"}, "another-secret-0000", "", "t1"});
    for (int i = 0; i < 5; ++i) {
      DeliveryRecord d{"d" + std::to_string(i), "w1", "bump", "{}"};
      if (i < 4) d.status = "delivered";
      store.AddDelivery(d, 3);
    }
    store.AddDelivery({"e0", "w2", "fault", "{}"}, 3);
    DeliveryRecord updated{"d4", "w1", "bump", "{}", "failed", 8, "t", "t2", 503, "503 Service Unavailable"};
    store.UpdateDelivery(updated);
  }
  Store store(dir_ / "corridor.db");
  ASSERT_EQ(store.Webhooks().size(), 2u);
  EXPECT_EQ(store.Webhook("w1")->events, (std::vector<std::string>{"bump", "lost"}));
  EXPECT_EQ(store.Webhook("w1")->secret, "s3cret-s3cret-s3cret");
  const auto deliveries = store.Deliveries("w1", 10);
  ASSERT_EQ(deliveries.size(), 3u);  // the newest three
  EXPECT_EQ(deliveries[0].id, "d4");
  EXPECT_EQ(deliveries[0].status, "failed");
  EXPECT_EQ(deliveries[0].attempts, 8);
  EXPECT_EQ(deliveries[0].response_status, 503);
  EXPECT_EQ(deliveries[2].id, "d2");
  ASSERT_EQ(store.PendingDeliveries().size(), 1u);
  EXPECT_EQ(store.PendingDeliveries()[0].id, "e0");
  EXPECT_TRUE(store.DeleteWebhook("w2"));
  EXPECT_FALSE(store.DeleteWebhook("w2"));
  EXPECT_TRUE(store.PendingDeliveries().empty());
  EXPECT_FALSE(store.Webhook("w2"));
}

TEST_F(StoreTest, EventsAreNumberedAcrossReopeningAndOnlyTheNewestAreKept) {
  {
    Store store(dir_ / "corridor.db");
    for (int i = 1; i <= 5; ++i) EXPECT_EQ(store.AddEvent({{"type", "bump"}, {"n", i}}, 3), i);
  }
  Store store(dir_ / "corridor.db");
  EXPECT_EQ(store.AddEvent({{"type", "lost"}}, 3), 6);
  const auto all = store.Events(0, 100);
  ASSERT_EQ(all.size(), 3u);  // 4, 5, 6
  EXPECT_EQ(all[0]["sequence"], 4);
  EXPECT_EQ(all[0]["n"], 4);
  EXPECT_EQ(all[2]["type"], "lost");
  const auto after = store.Events(4, 100);
  ASSERT_EQ(after.size(), 2u);
  EXPECT_EQ(after[0]["sequence"], 5);
  const auto newest = store.Events(0, 1);
  ASSERT_EQ(newest.size(), 1u);
  EXPECT_EQ(newest[0]["sequence"], 6);
}

TEST_F(StoreTest, AFileThatIsNotADatabaseIsReported) {
  std::ofstream(dir_ / "junk.db") << std::string(4096, 'x');
  try {
    Store store(dir_ / "junk.db");
    ADD_FAILURE();
  } catch (const StoreError& e) {
    EXPECT_NE(std::string(e.what()).find("junk.db"), std::string::npos) << e.what();
  }
}

TEST(NewIdTest, IdsAreSixteenHexDigitsAndDistinct) {
  const std::string a = NewId();
  EXPECT_EQ(a.size(), 16u);
  EXPECT_NE(a, NewId());
}

}  // namespace
}  // namespace corridor::server
