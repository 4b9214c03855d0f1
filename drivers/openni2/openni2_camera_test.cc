// The OpenNI2 driver with OpenNI2 itself (Debian's libopenni2 and its drivers) on a machine with no depth camera: it
// starts, finds no device, says so, keeps trying, and stops cleanly. Frames from a real device are not run here
// (docs/hardware.md).
#include "drivers/openni2/openni2_camera.h"

#include <gtest/gtest.h>

#include "testing/eventually.h"

namespace corridor::drivers::openni2 {
namespace {

using corridor::testing::Eventually;
using namespace std::chrono_literals;

TEST(OpenNi2CameraTest, WithoutADeviceItSaysSoAndKeepsTrying) {
  EXPECT_TRUE(ListOpenNi2Devices().empty());  // this machine has none
  OpenNi2Options options;
  options.reconnect_s = 0.1;
  SteadyClock clock;
  OpenNi2Camera camera(options, clock);
  EXPECT_TRUE(camera.info().camera.Valid());
  EXPECT_NEAR(camera.info().camera.fx, 320.0 / std::tan(29.0 * M_PI / 180.0), 1e-9);
  ASSERT_TRUE(Eventually([&] { return camera.status().reconnects >= 2; }, 5000ms));
  EXPECT_NE(camera.status().state, LinkState::kRunning);  // connecting again, or disconnected
  EXPECT_NE(camera.status().last_error.find("no OpenNI2 device"), std::string::npos) << camera.status().last_error;
  EXPECT_EQ(camera.status().frames, 0u);
}

TEST(OpenNi2CameraTest, BadOptionsAreRefused) {
  SteadyClock clock;
  OpenNi2Options options;
  options.camera.fps = 0;
  EXPECT_THROW(OpenNi2Camera(options, clock), std::invalid_argument);
  options = OpenNi2Options{};
  options.camera.hfov_deg = 0.0;
  EXPECT_THROW(OpenNi2Camera(options, clock), std::invalid_argument);
}

}  // namespace
}  // namespace corridor::drivers::openni2
