// A camera on a pan servo: its pose turned (PanTurn), the servo's angle at a frame's time (PanHistory), and the
// readers rebuilt for a new pose (Posed).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <optional>

#include "nav/geometry/camera_model.h"
#include "nav/geometry/pan_history.h"
#include "nav/geometry/posed.h"

namespace corridor::nav {
namespace {

constexpr double kRadPerDeg = std::numbers::pi / 180.0;

TEST(PanTest, TurningAboutTheAxisUnderTheCameraTurnsItsViewAndKeepsItsPlace) {
  const Eigen::Isometry3d mount = CameraMount(0.1, 0.3, 10.0 * kRadPerDeg);
  const Eigen::Isometry3d turned = PanTurn({0.1, 0.0}, 90.0 * kRadPerDeg) * mount;
  EXPECT_TRUE(turned.translation().isApprox(mount.translation(), 1e-12));
  // The optical axis, forward and down at rest, is to the left and down.
  const Eigen::Vector3d axis = turned.linear() * Eigen::Vector3d::UnitZ();
  EXPECT_NEAR(axis.x(), 0.0, 1e-12);
  EXPECT_NEAR(axis.y(), std::cos(10.0 * kRadPerDeg), 1e-12);
  EXPECT_NEAR(axis.z(), -std::sin(10.0 * kRadPerDeg), 1e-12);
  // An axis 5 cm behind the camera swings it round: 5 cm to the left of the axis.
  const Eigen::Isometry3d swung = PanTurn({0.05, 0.0}, 90.0 * kRadPerDeg) * mount;
  EXPECT_TRUE(swung.translation().isApprox(Eigen::Vector3d(0.05, 0.05, 0.3), 1e-12));
  EXPECT_FALSE(Moved(mount, PanTurn({0.1, 0.0}, 0.0) * mount));
  EXPECT_TRUE(Moved(mount, PanTurn({0.1, 0.0}, 0.001) * mount));
}

TEST(PanTest, TheAngleAtAFrameIsInterpolatedBetweenReadingsAndUnknownOutsideThem) {
  PanHistory history(0.1);
  EXPECT_FALSE(history.At(0.0).has_value());
  history.Add(1.00, 0.0, 1.0);
  history.Add(1.02, 0.02, 1.0);
  history.Add(1.04, 0.04, 0.0);
  EXPECT_NEAR(*history.At(1.01), 0.01, 1e-12);
  EXPECT_NEAR(*history.At(1.04), 0.04, 1e-12);
  EXPECT_NEAR(*history.At(1.09), 0.04, 1e-12);  // after the newest: carried on at its velocity (still)
  EXPECT_FALSE(history.At(1.2).has_value());    // the servo silent since
  EXPECT_FALSE(history.At(0.9).has_value());    // older than what is kept
  history.Add(1.03, 5.0, 0.0);                  // out of order: ignored
  EXPECT_NEAR(*history.At(1.035), 0.035, 1e-12);
  history.Add(1.5, 0.5, 0.0);  // after a gap of more than two max_gap_s: between them is not known
  EXPECT_FALSE(history.At(1.3).has_value());
}

// A reader that remembers the camera it was built for, and how often it was built.
struct PosedReader {
  PosedReader(const PinholeCamera& camera, int* builds) : pose(camera.base_T_camera) { ++*builds; }
  Eigen::Isometry3d pose;
};

TEST(PanTest, AReaderIsBuiltAnewOnlyWhenTheCameraMoves) {
  PinholeCamera camera;
  camera.base_T_camera = CameraMount(0.1, 0.3, 0.0);
  int builds = 0;
  Posed<PosedReader> posed;
  posed.Reset(camera, [&builds](std::optional<PosedReader>& r, const PinholeCamera& c) { r.emplace(c, &builds); });
  EXPECT_EQ(builds, 1);
  posed.At(std::nullopt);  // a fixed camera's frames
  posed.At(camera.base_T_camera);
  EXPECT_EQ(builds, 1);
  const Eigen::Isometry3d turned = PanTurn({0.1, 0.0}, 0.3) * camera.base_T_camera;
  EXPECT_TRUE(posed.At(turned).pose.isApprox(turned));
  posed.At(turned);
  EXPECT_EQ(builds, 2);
  EXPECT_TRUE(posed.camera().base_T_camera.isApprox(turned));
}

}  // namespace
}  // namespace corridor::nav
