#include "server/store/saved_pose.h"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

namespace corridor::server {
namespace {

namespace fs = std::filesystem;

class SavedPoseTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("corridor_pose_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(SavedPoseTest, APoseSavedIsThePoseLoaded) {
  const fs::path file = dir_ / "pose.json";
  EXPECT_FALSE(LoadSavedPose(file));
  SavePose(file, {"willow", {1.5, -2.0, 3.0}, 0.05, 0.02});
  SavePose(file, {"willow", {1.25, -2.5, -3.0}, 0.04, 0.01});  // replaces it
  const std::optional<SavedPose> loaded = LoadSavedPose(file);
  ASSERT_TRUE(loaded);
  EXPECT_EQ(loaded->place, "willow");
  EXPECT_DOUBLE_EQ(loaded->pose.x_m, 1.25);
  EXPECT_DOUBLE_EQ(loaded->pose.y_m, -2.5);
  EXPECT_DOUBLE_EQ(loaded->pose.yaw_rad, -3.0);
  EXPECT_DOUBLE_EQ(loaded->sigma_m, 0.04);
  EXPECT_FALSE(fs::exists(dir_ / "pose.json.tmp"));
}

TEST_F(SavedPoseTest, ABrokenFileIsIgnoredNotFatal) {
  for (const char* text :
       {"", "{\"place\": \"m\", \"x\": 1", "{\"place\": \"m\", \"x\": 1, \"y\": \"two\", \"yaw\": 0}",
        "{\"place\": \"m\", \"x\": 1e999, \"y\": 0, \"yaw\": 0}", "[1, 2, 3]"}) {
    std::ofstream(dir_ / "pose.json") << text;
    EXPECT_FALSE(LoadSavedPose(dir_ / "pose.json")) << text;
  }
  EXPECT_THROW(SavePose(dir_ / "no" / "such" / "dir.json", {}), std::runtime_error);
}

TEST_F(SavedPoseTest, SavingAgainWaitsForAMoveWorthIt) {
  const SavedPose a{"m", {0.0, 0.0, 0.0}, 0.0, 0.0};
  EXPECT_FALSE(MovedEnough(a, {"m", {0.05, 0.0, 0.05}, 0.0, 0.0}));
  EXPECT_TRUE(MovedEnough(a, {"m", {0.1, 0.0, 0.0}, 0.0, 0.0}));
  EXPECT_TRUE(MovedEnough(a, {"m", {0.0, 0.0, 0.1}, 0.0, 0.0}));
  EXPECT_TRUE(MovedEnough(a, {"other", {0.0, 0.0, 0.0}, 0.0, 0.0}));
}

}  // namespace
}  // namespace corridor::server
