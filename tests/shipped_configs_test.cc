// Every configuration corridor ships, as a new user runs it: the daemon's graph in lockstep with its simulator, from
// the file itself. What the README promises of the bundled worlds must hold in each.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string>
#include <vector>

#include "testing/lockstep_robot.h"
#include "testing/source_dir.h"

namespace corridor {
namespace {

namespace fs = std::filesystem;
using testing::LockstepRobot;
using testing::SourceDir;

std::vector<fs::path> ShippedConfigs() {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(SourceDir() / "config")) {
    if (entry.path().extension() == ".yaml") files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

class ShippedConfigTest : public ::testing::TestWithParam<fs::path> {};

// POST /api/v1/dock from the start pose, as the console's Dock button does: the mission drives to the dock's staging
// pose, docks, and the simulated charger's contacts close.
TEST_P(ShippedConfigTest, DocksFromItsStartPose) {
  LockstepRobot robot(GetParam());
  robot.StepFor(1.0);  // the first frames and poses
  const LockstepRobot::Reply started = robot.Call("POST", "/api/v1/dock", nlohmann::json::object());
  ASSERT_EQ(started.status, 201) << started.body.dump();
  std::string status;
  const bool ended = robot.StepUntil(
      [&] {
        const nlohmann::json mission = robot.State()["mission"];
        status = mission.is_null() ? "" : mission["status"].get<std::string>();
        return status != "active";
      },
      120.0);
  const nlohmann::json state = robot.State();
  ASSERT_TRUE(ended) << "still docking after 120 s: " << state["mission"].dump();
  EXPECT_EQ(status, "succeeded") << state["mission"].dump();
  EXPECT_TRUE(state["docked"].get<bool>());
  ASSERT_TRUE(state["battery"].is_object());
  EXPECT_TRUE(state["battery"]["on_charger"].get<bool>()) << state["battery"].dump();
}

// The test's name is the file's ("corridor", "small_house").
std::string ConfigName(const ::testing::TestParamInfo<fs::path>& param) {
  std::string name = param.param.stem().string();
  for (char& c : name) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  return name;
}

INSTANTIATE_TEST_SUITE_P(Config, ShippedConfigTest, ::testing::ValuesIn(ShippedConfigs()), ConfigName);

}  // namespace
}  // namespace corridor
