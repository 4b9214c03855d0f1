// The API's route table, as the daemon's graph declares it, against the OpenAPI document it serves: every route
// documented with the access it declares, every documented operation served, and every operation declaring the
// refusals any request may get (401 and 403 where credentials are needed; 400, 413 and 415 where there is a body).
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <map>
#include <set>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include "server/api/api.h"
#include "testing/lockstep_robot.h"
#include "testing/source_dir.h"

namespace corridor {
namespace {

using Operation = std::pair<std::string, std::string>;  // lower-case method, path template

// How openapi.json's x-corridor-access names each access.
std::string DocumentedName(server::auth::Access access) {
  switch (access) {
    case server::auth::Access::kPublic: return "anyone";
    case server::auth::Access::kFace: return "screen";
    case server::auth::Access::kViewer: return "viewer";
    case server::auth::Access::kOperator: return "operator";
    case server::auth::Access::kAdmin: return "admin";
  }
  return "?";
}

// The route table and the document, read once for all the tests (building the graph is the expensive part).
class ApiRoutesTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    testing::LockstepRobot robot(testing::ShippedConfig());
    for (const server::Router::RouteInfo& route : robot.graph().api().Routes()) {
      std::string method(boost::beast::http::to_string(route.method));
      std::transform(method.begin(), method.end(), method.begin(), [](unsigned char c) { return std::tolower(c); });
      const bool fresh = served_.emplace(Operation{method, route.pattern}, route.access).second;
      EXPECT_TRUE(fresh) << method << " " << route.pattern << " is declared twice";
    }
    const nlohmann::json document = nlohmann::json::parse(server::OpenApiDocument());
    for (const auto& [path, item] : document.at("paths").items()) {
      for (const auto& [method, operation] : item.items()) {
        if (operation.is_object() && operation.contains("responses")) documented_[{method, path}] = operation;
      }
    }
  }

  static inline std::map<Operation, server::auth::Access> served_;
  static inline std::map<Operation, nlohmann::json> documented_;
};

TEST_F(ApiRoutesTest, EveryRouteIsDocumentedWithItsAccess) {
  ASSERT_GT(served_.size(), 90u);
  for (const auto& [operation, access] : served_) {
    const auto it = documented_.find(operation);
    if (it == documented_.end()) {
      ADD_FAILURE() << operation.first << " " << operation.second << " is served but not in openapi.json";
      continue;
    }
    EXPECT_EQ(it->second.value("x-corridor-access", ""), DocumentedName(access))
        << operation.first << " " << operation.second;
  }
}

TEST_F(ApiRoutesTest, EveryDocumentedOperationIsServed) {
  for (const auto& [operation, spec] : documented_) {
    EXPECT_TRUE(served_.contains(operation))
        << operation.first << " " << operation.second << " (" << spec.value("operationId", "") << ") is not served";
  }
}

TEST_F(ApiRoutesTest, EveryOperationDeclaresTheRefusalsItCanAnswer) {
  for (const auto& [operation, spec] : documented_) {
    const nlohmann::json& responses = spec.at("responses");
    const std::string name = operation.first + " " + operation.second;
    if (spec.value("x-corridor-access", "") != "anyone") {
      EXPECT_TRUE(responses.contains("401")) << name << ": needs credentials but does not declare 401";
      EXPECT_TRUE(responses.contains("403")) << name << ": needs a role but does not declare 403";
      EXPECT_FALSE(spec.contains("security")) << name << ": needs credentials but overrides the document's security";
    } else {
      EXPECT_EQ(spec.value("security", nlohmann::json()), nlohmann::json::array()) << name << ": open to anyone";
    }
    if (spec.contains("requestBody")) {
      for (const char* status : {"400", "413", "415"}) {
        EXPECT_TRUE(responses.contains(status)) << name << ": takes a body but does not declare " << status;
      }
    }
  }
}

// The API page groups operations by tag and shows each one's summary and description: every operation has one tag of
// those the document lists, a summary short enough for a line, and a description that says more.
TEST_F(ApiRoutesTest, EveryOperationIsTaggedSummarizedAndDescribed) {
  const nlohmann::json document = nlohmann::json::parse(server::OpenApiDocument());
  std::set<std::string> tags;
  for (const nlohmann::json& tag : document.at("tags")) {
    tags.insert(tag.at("name").get<std::string>());
    EXPECT_FALSE(tag.value("description", "").empty()) << tag.dump();
  }
  for (const auto& [operation, spec] : documented_) {
    const std::string name = operation.first + " " + operation.second;
    ASSERT_TRUE(spec.contains("tags") && spec.at("tags").size() == 1) << name << ": one tag";
    EXPECT_TRUE(tags.contains(spec.at("tags")[0].get<std::string>())) << name << ": a tag the document lists";
    const std::string summary = spec.value("summary", "");
    const std::string description = spec.value("description", "");
    EXPECT_FALSE(summary.empty()) << name;
    EXPECT_LE(summary.size(), 40u) << name << ": a summary is a line: " << summary;
    EXPECT_GT(description.size(), summary.size()) << name << ": the description says more than the summary";
  }
}

// A few routes whose access matters most, spelled out.
TEST_F(ApiRoutesTest, TheRolesThatMatterMost) {
  using server::auth::Access;
  EXPECT_EQ(served_.at({"get", "/api/v1/health"}), Access::kPublic);
  EXPECT_EQ(served_.at({"post", "/api/v1/session"}), Access::kPublic);
  EXPECT_EQ(served_.at({"get", "/api/v1/stream"}), Access::kFace);
  EXPECT_EQ(served_.at({"get", "/api/v1/state"}), Access::kViewer);
  EXPECT_EQ(served_.at({"post", "/api/v1/teleop"}), Access::kOperator);
  EXPECT_EQ(served_.at({"post", "/api/v1/missions/{id}/pause"}), Access::kOperator);
  EXPECT_EQ(served_.at({"put", "/api/v1/map/image"}), Access::kAdmin);
  EXPECT_EQ(served_.at({"get", "/api/v1/devices/hardware"}), Access::kAdmin);  // devices' paths and serials
  EXPECT_EQ(served_.at({"patch", "/api/v1/config"}), Access::kAdmin);
}

}  // namespace
}  // namespace corridor
