// MORP, AFDS and the floor fit on depth images the simulator renders from known geometry (so the answer is known), and
// on real Kinect frames from the TUM RGB-D benchmark (holes and noise: the output must stay sane).
#include <gtest/gtest.h>

#include "testing/source_dir.h"

#include <cstdlib>
#include <numbers>
#include <opencv2/imgcodecs.hpp>

#include "drivers/sim/sensors.h"
#include "drivers/sim/sim_robot.h"
#include "drivers/sim/sim_stereo.h"
#include "nav/ground/afds.h"
#include "nav/ground/depth_scan.h"
#include "nav/ground/floor_fit.h"
#include "nav/ground/morp.h"
#include "nav/ground/voxel_obstacles.h"
#include "nav/policy/morp_rb.h"

namespace corridor {
namespace {

using drivers::sim::TriangleMesh;

using testing::SourceDir;

const Eigen::Vector3f kGrey(0.6f, 0.6f, 0.6f);

// A large floor at z = 0, optionally ending at x = floor_end_m with a lower floor 0.3 m down beyond it.
TriangleMesh Floor(float floor_end_m = 50.0f) {
  TriangleMesh m;
  m.AddBox({-5.0f, -10.0f, -0.01f}, {floor_end_m, 10.0f, 0.0f}, kGrey);
  if (floor_end_m < 50.0f) m.AddBox({floor_end_m, -10.0f, -0.31f}, {50.0f, 10.0f, -0.3f}, kGrey);
  return m;
}

drivers::sim::SimCameraOptions Camera() {
  drivers::sim::SimCameraOptions o;  // the simulator's default: RealSense-like, 0.3 m high, tilted 10 degrees
  o.width = 640;
  o.height = 480;
  o.max_range_m = 6.0;
  return o;
}

cv::Mat Render(const TriangleMesh& mesh, const drivers::sim::SimCameraOptions& o, std::uint32_t seed = 1) {
  const drivers::sim::RayCaster caster(mesh);
  const drivers::sim::RgbdRenderer renderer(caster, o);
  std::mt19937 rng(seed);
  drivers::RgbdFrame frame;
  renderer.Render(drivers::sim::MakeCameraInfo(o).camera.base_T_camera, rng, frame);  // the robot at the origin
  return frame.depth_mm;
}

// Lanes across the robot's width only (0.4 m, four lanes), so that each test's geometry reads simply.
nav::MorpOptions RobotWidthLanes() {
  nav::MorpOptions options;
  options.span_m = 0.4;
  return options;
}

nav::Morp MakeMorp(const drivers::sim::SimCameraOptions& o, nav::MorpOptions options = RobotWidthLanes()) {
  return nav::Morp(drivers::sim::MakeCameraInfo(o).camera, options);
}

TEST(VoxelObstaclesTest, TheComparisonFrontEndFindsTheWallAndTheBoxButNotTheFloor) {
  const auto o = Camera();
  TriangleMesh mesh = Floor();
  mesh.AddBox({2.5f, -3.0f, 0.0f}, {2.7f, 3.0f, 1.5f}, kGrey);  // a wall 2.5 m ahead
  mesh.AddBox({1.5f, 0.0f, 0.0f}, {1.8f, 0.5f, 0.4f}, kGrey);   // a box on the left
  nav::VoxelObstacles voxels(drivers::sim::MakeCameraInfo(o).camera, nav::VoxelObstacleOptions{});
  const auto& obstacles = voxels.Process(Render(mesh, o));
  ASSERT_FALSE(obstacles.empty());
  EXPECT_GT(voxels.cloud().size(), 100000u);  // most of a VGA frame
  int wall = 0;
  int box = 0;
  for (const Eigen::Vector2f& p : obstacles) {
    // Nothing on the open floor before the box and the wall.
    EXPECT_GT(p.x(), 1.4f) << p.transpose();
    if (p.x() > 2.4f) {
      ++wall;
      EXPECT_LT(p.x(), 2.6f) << p.transpose();  // the wall's face, within a voxel and depth noise
    } else {
      ++box;
      EXPECT_GT(p.y(), -0.06f) << p.transpose();  // the box is on the left
    }
  }
  EXPECT_GT(wall, 50);
  EXPECT_GT(box, 5);
}

TEST(DepthScanTest, EachColumnGivesItsNearestObstacleOnTheFloorPlaneAndWhatTheSidesCutIsLeftOut) {
  // A wall 3 m ahead and, in front of it on the left, a person-sized cylinder's box stand-in 1.5 m ahead; a low
  // step (5 cm) on the right that the robot drives over is not an obstacle, nor is the tilted camera's floor.
  const auto o = Camera();
  TriangleMesh mesh = Floor();
  mesh.AddBox({3.0f, -4.0f, 0.0f}, {3.2f, 4.0f, 1.5f}, kGrey);
  mesh.AddBox({1.5f, 0.2f, 0.0f}, {1.9f, 0.6f, 1.7f}, kGrey);
  mesh.AddBox({1.0f, -1.0f, 0.0f}, {1.4f, -0.3f, 0.05f}, kGrey);
  nav::DepthScanOptions keep_all;
  keep_all.segment_gap_m = 0.0;
  nav::DepthScan scan(drivers::sim::MakeCameraInfo(o).camera, keep_all);
  const cv::Mat depth = Render(mesh, o);
  const auto& points = scan.Process(depth);
  ASSERT_GT(points.size(), 600u);  // nearly every column of 640 sees the wall or the box
  int person = 0;
  for (const Eigen::Vector2d& p : points) {
    const bool in_box_shadow = p.y() > 0.15 && p.y() < 0.65 && p.x() < 2.0;
    if (in_box_shadow) {
      ++person;
      EXPECT_NEAR(p.x(), 1.7, 0.25) << p.transpose();  // the box's near face, or its side seen at an angle
    } else {
      // The wall's face (the nearest of a column's noisy pixels): not the floor, not the step.
      EXPECT_NEAR(p.x(), 3.0, 0.1) << p.transpose();
    }
  }
  EXPECT_GT(person, 40);
  // By default what the image's sides cut (the wall, seen from side to side) is left out: only the box is whole.
  nav::DepthScan whole(drivers::sim::MakeCameraInfo(o).camera, nav::DepthScanOptions{});
  const auto& kept = whole.Process(depth);
  EXPECT_EQ(static_cast<int>(kept.size()), person);
  for (const Eigen::Vector2d& p : kept) EXPECT_LT(p.x(), 2.0) << p.transpose();
  // Every column gives a point or a miss (free out to the range, on the column's bearing).
  EXPECT_EQ(points.size() + scan.misses().size(), static_cast<std::size_t>(o.width));
  // Holes give nothing but misses, one per column, spread across the view at the range.
  EXPECT_TRUE(scan.Process(cv::Mat::zeros(o.height, o.width, CV_16UC1)).empty());
  ASSERT_EQ(scan.misses().size(), static_cast<std::size_t>(o.width));
  const Eigen::Vector2d camera = drivers::sim::MakeCameraInfo(o).camera.base_T_camera.translation().head<2>();
  for (const Eigen::Vector2d& m : scan.misses()) EXPECT_NEAR((m - camera).norm(), keep_all.max_range_m, 1e-6);
  EXPECT_GT(scan.misses().front().y(), 1.0) << "the first column looks left";
  EXPECT_LT(scan.misses().back().y(), -1.0);
  EXPECT_THROW(scan.Process(cv::Mat::zeros(10, 10, CV_16UC1)), std::invalid_argument);
}

TEST(DepthScanTest, ItsViewIsTheImagesWidthOnTheFloorOutToItsRange) {
  // The simulator's camera: 85.2 degrees wide, at the base's origin looking forward, tilted down 10 degrees (its top
  // row's sides lean in to about 40.3 degrees). With the robot at (2, 1) facing +y, the view covers what is ahead
  // within that either side and 4 m (the scan's range).
  const nav::DepthScan scan(drivers::sim::MakeCameraInfo(Camera()).camera, nav::DepthScanOptions{});
  const nav::SensorView view = scan.View({2.0, 1.0, std::numbers::pi / 2.0});
  EXPECT_NEAR(view.half_angle_rad * 180.0 / std::numbers::pi, 40.3, 0.5);
  EXPECT_NEAR(view.range_m, 4.0, 1e-9);
  const auto at = [](double bearing_deg, double range) {
    const double a = std::numbers::pi / 2.0 + bearing_deg * std::numbers::pi / 180.0;
    return Eigen::Vector2d(2.0 + range * std::cos(a), 1.0 + range * std::sin(a));
  };
  EXPECT_TRUE(view.Covers(at(0.0, 2.0), 0.3));
  EXPECT_TRUE(view.Covers(at(-25.0, 2.0), 0.3));
  EXPECT_FALSE(view.Covers(at(40.0, 2.0), 0.3)) << "cut by the image's side";
  EXPECT_FALSE(view.Covers(at(60.0, 2.0), 0.3));
  EXPECT_FALSE(view.Covers(at(0.0, 3.9), 0.3)) << "beyond the range";
  EXPECT_FALSE(view.Covers(at(180.0, 1.0), 0.3));
  EXPECT_FALSE(view.Covers(at(0.0, 0.2), 0.3)) << "around the camera itself";
}

// A stereo pair's view leaves out its shadow: close by on the left, what the right camera cannot see; farther out
// at the same bearing, or close by on the right, it covers.
TEST(DepthScanTest, AStereoPairsViewLeavesOutWhatOnlyOneCameraSees) {
  nav::PinholeCamera camera = drivers::sim::MakeCameraInfo(drivers::sim::SimCameraOptions{}).camera;
  const nav::DepthScan depth_sensor(camera, nav::DepthScanOptions{});
  camera.stereo = {camera.fx * 0.12, 0.0};  // 12 cm between 174 px cameras
  const nav::DepthScan pair(camera, nav::DepthScanOptions{});
  const auto at = [](double bearing_deg, double range) {
    const double a = bearing_deg * std::numbers::pi / 180.0;
    return Eigen::Vector2d(0.1 + range * std::cos(a), range * std::sin(a));  // from the camera, 0.1 m ahead
  };
  const nav::SensorView sensor_view = depth_sensor.View({});
  const nav::SensorView pair_view = pair.View({});
  EXPECT_TRUE(sensor_view.Covers(at(33.0, 0.6), 0.05));
  EXPECT_FALSE(pair_view.Covers(at(33.0, 0.6), 0.05)) << "33 degrees left, 0.6 m away: 30 px into the shadow";
  EXPECT_TRUE(pair_view.Covers(at(33.0, 2.5), 0.05));
  EXPECT_TRUE(pair_view.Covers(at(-33.0, 0.6), 0.05));
}

TEST(MorpTest, OpenFloorHasNoDeadEnds) {
  const auto o = Camera();
  nav::Morp morp = MakeMorp(o);
  ASSERT_EQ(morp.lane_count(), 4);  // 0.4 m robot, 0.1 m lanes
  for (const nav::LaneResult& lane : morp.Process(Render(Floor(), o))) {
    EXPECT_FALSE(lane.dead_end) << "lane " << lane.offset_m << " at " << lane.free_distance_m;
    EXPECT_GT(lane.free_distance_m, 3.5);
  }
}

TEST(MorpTest, AWallAheadIsADeadEndAtItsDistanceInEveryLane) {
  const auto o = Camera();
  nav::Morp morp = MakeMorp(o);
  for (const float wall_x : {0.8f, 1.5f, 2.5f, 3.5f}) {
    TriangleMesh mesh = Floor();
    mesh.AddBox({wall_x, -3.0f, 0.0f}, {wall_x + 0.2f, 3.0f, 1.5f}, kGrey);
    for (const nav::LaneResult& lane : morp.Process(Render(mesh, o))) {
      EXPECT_TRUE(lane.dead_end) << "wall at " << wall_x << ", free " << lane.free_distance_m;
      // Depth noise at 3.5 m is about 2.5 cm; the dead-end is the wall's foot.
      EXPECT_NEAR(lane.free_distance_m, wall_x, 0.03 + 0.01 * wall_x) << "wall at " << wall_x;
      EXPECT_LT(lane.point.z(), 0.15);
    }
  }
}

TEST(MorpTest, ABoxOnTheLeftBlocksOnlyTheLeftLanes) {
  const auto o = Camera();
  nav::Morp morp = MakeMorp(o);
  TriangleMesh mesh = Floor();
  mesh.AddBox({1.5f, 0.0f, 0.0f}, {1.8f, 0.5f, 0.4f}, kGrey);
  for (const nav::LaneResult& lane : morp.Process(Render(mesh, o))) {
    if (lane.offset_m > 0.0) {
      EXPECT_TRUE(lane.dead_end) << lane.offset_m;
      EXPECT_NEAR(lane.free_distance_m, 1.5, 0.04);
    } else {
      EXPECT_FALSE(lane.dead_end) << lane.offset_m;
    }
  }
}

TEST(MorpTest, StepsJustUnderTheThresholdAreDrivenOverAndJustOverAreNot) {
  const auto o = Camera();
  nav::MorpOptions options = RobotWidthLanes();
  options.max_step_m = 0.03;
  nav::Morp morp = MakeMorp(o, options);
  const auto with_step = [](float height) {
    TriangleMesh mesh = Floor();
    mesh.AddBox({1.2f, -1.0f, 0.0f}, {1.6f, 1.0f, height}, kGrey);
    return mesh;
  };
  const cv::Mat low = Render(with_step(0.02f), o);
  const cv::Mat high = Render(with_step(0.045f), o);
  for (const nav::LaneResult& lane : morp.Process(low)) EXPECT_FALSE(lane.dead_end) << "2 cm step";
  for (const nav::LaneResult& lane : morp.Process(high)) {
    EXPECT_TRUE(lane.dead_end) << "4.5 cm step";
    EXPECT_NEAR(lane.free_distance_m, 1.2, 0.04);
  }
  // The same robot with bigger wheels: raise the threshold at run time, no retraining.
  morp.set_max_step_m(0.06);
  for (const nav::LaneResult& lane : morp.Process(high)) EXPECT_FALSE(lane.dead_end) << "4.5 cm step, 6 cm allowed";
}

TEST(MorpTest, ADropIsADeadEnd) {
  const auto o = Camera();
  nav::Morp morp = MakeMorp(o);
  for (const nav::LaneResult& lane : morp.Process(Render(Floor(1.5f), o))) {
    EXPECT_TRUE(lane.dead_end);
    EXPECT_NEAR(lane.free_distance_m, 1.5, 0.05);  // at the edge, though the lower floor is first seen at 3 m
    EXPECT_LT(lane.point.z(), -0.2);
  }
}

TEST(MorpTest, TooCloseToSeeMeansBlindAndStop) {
  const auto o = Camera();
  nav::Morp morp = MakeMorp(o);
  TriangleMesh mesh = Floor();
  mesh.AddBox({0.25f, -3.0f, 0.0f}, {0.4f, 3.0f, 1.5f}, kGrey);  // 0.15 m from the lens: under its 0.2 m range
  for (const nav::LaneResult& lane : morp.Process(Render(mesh, o))) {
    EXPECT_TRUE(lane.blind);
    EXPECT_TRUE(lane.dead_end);
    EXPECT_DOUBLE_EQ(lane.free_distance_m, morp.options().min_range_m);
  }
  EXPECT_THROW(morp.Process(cv::Mat(10, 10, CV_16UC1, cv::Scalar(0))), std::invalid_argument);
}

// A stereo pair sees nothing close by on its left (the right camera does not): its lanes there start where both
// cameras see the floor, so open floor gives no dead-end; read as a depth sensor's, the same frame blinds them.
TEST(MorpTest, AStereoPairsLeftLanesStartWhereBothCamerasSeeTheFloor) {
  const drivers::sim::SimCameraOptions o;  // 320 x 240, as the simulated pair matches
  drivers::sim::SimStereoOptions stereo;
  stereo.enabled = true;
  const TriangleMesh mesh = Floor();
  const drivers::sim::RayCaster caster(mesh);
  drivers::sim::SimStereoCamera pair(caster, o, stereo);
  std::mt19937 rng(1);
  drivers::RgbdFrame frame;
  pair.Render(Eigen::Isometry3d::Identity(), rng, frame);
  nav::Morp morp(pair.info().camera, nav::MorpOptions{});  // 1 m of lanes: 0.3 m past the robot's sides
  for (const nav::LaneResult& lane : morp.Process(frame.depth_mm)) {
    EXPECT_FALSE(lane.dead_end) << "lane " << lane.offset_m << " at " << lane.free_distance_m;
  }
  nav::PinholeCamera without_shadow = pair.info().camera;
  without_shadow.stereo = {};
  nav::Morp plain(without_shadow, nav::MorpOptions{});
  EXPECT_TRUE(plain.Process(frame.depth_mm).front().dead_end) << "the leftmost lane, 0.45 m left";
}

TEST(MorpTest, RealKinectFramesGiveSaneOutput) {
  // TUM RGB-D desk frames (freiburg2 Kinect): depth / 5000 = metres, a third of pixels are holes.
  nav::PinholeCamera camera{
      640, 480, 520.9, 521.0, 325.1, 249.7, drivers::sim::MakeCameraInfo(Camera()).camera.base_T_camera, {}};
  nav::Morp morp(camera, nav::MorpOptions{});
  for (const char* name : {"tests/data/depth/1_depth.png", "tests/data/depth/2_depth.png"}) {
    cv::Mat raw = cv::imread((SourceDir() / name).string(), cv::IMREAD_UNCHANGED);
    ASSERT_EQ(raw.type(), CV_16UC1) << name;
    cv::Mat metres;
    raw.convertTo(metres, CV_32FC1, 1.0 / 5000.0);
    const double holes = 1.0 - cv::countNonZero(raw) / static_cast<double>(raw.total());
    EXPECT_GT(holes, 0.1);
    for (const nav::LaneResult& lane : morp.Process(metres)) {
      EXPECT_TRUE(std::isfinite(lane.free_distance_m));
      EXPECT_GE(lane.free_distance_m, 0.0);
      EXPECT_LE(lane.free_distance_m, morp.options().max_range_m);
      if (lane.dead_end && !lane.blind) {
        EXPECT_TRUE(lane.point.allFinite());
      }
    }
  }
}

TEST(FloorFitTest, RecoversCameraHeightAndTiltFromOneFrame) {
  std::mt19937 rng(7);
  for (const auto& [height, tilt_deg] : {std::pair{0.3, 10.0}, {0.45, 25.0}, {0.2, 5.0}}) {
    auto o = Camera();
    o.mount_height_m = height;
    o.tilt_deg = tilt_deg;
    TriangleMesh mesh = Floor();
    mesh.AddBox({2.0f, -3.0f, 0.0f}, {2.2f, 3.0f, 1.5f}, kGrey);  // a wall too: it must not be taken for the floor
    const auto info = drivers::sim::MakeCameraInfo(o);
    const auto fit = nav::FitFloor(Render(mesh, o), info.camera, nav::FloorFitOptions{}, rng);
    ASSERT_TRUE(fit) << height << " m, " << tilt_deg << " degrees";
    EXPECT_NEAR(fit->camera_height_m, height, 0.01);
    EXPECT_NEAR(fit->tilt_rad * 180.0 / std::numbers::pi, tilt_deg, 0.5);
    EXPECT_NEAR(fit->roll_rad, 0.0, 0.01);
    // The mounting it implies maps the floor to z = 0.
    const Eigen::Isometry3d mount = nav::MountingFromFloor(*fit, info.camera.base_T_camera);
    EXPECT_TRUE(mount.isApprox(info.camera.base_T_camera, 0.02)) << mount.matrix() << "\n"
                                                                 << info.camera.base_T_camera.matrix();
  }
}

TEST(FloorFitTest, NoFloorInViewGivesNoFit) {
  auto o = Camera();
  TriangleMesh mesh;
  mesh.AddBox({0.5f, -3.0f, -3.0f}, {0.7f, 3.0f, 3.0f}, kGrey);  // a wall filling the view
  std::mt19937 rng(1);
  EXPECT_FALSE(nav::FitFloor(Render(mesh, o), drivers::sim::MakeCameraInfo(o).camera, nav::FloorFitOptions{}, rng));
}

// AFDS (ASNS's floor detection): the floor, each region's floor and what stands in it, and MORP's lanes from them.
nav::Afds MakeAfds(const drivers::sim::SimCameraOptions& o, nav::AfdsOptions options = {}) {
  return nav::Afds(drivers::sim::MakeCameraInfo(o).camera, options, RobotWidthLanes());
}

// The highest obstacle any region holds (what a box alone on the floor measures).
double TallestObstacle(const nav::AfdsFrame& frame) {
  double tallest = 0.0;
  for (const nav::AfdsCell& cell : frame.cells) tallest = std::max(tallest, cell.obstacle_height_m);
  return tallest;
}

TEST(AfdsTest, OpenFloorIsFloorInEveryRegionAndNoLaneEnds) {
  const auto o = Camera();
  nav::Afds afds = MakeAfds(o);
  const nav::AfdsFrame& frame = afds.Process(Render(Floor(), o));
  ASSERT_TRUE(frame.floor_found);
  EXPECT_GT(frame.floor.normal.z(), 0.9999);
  EXPECT_NEAR(frame.floor.offset, 0.0, 0.005);
  EXPECT_TRUE(frame.obstacles.empty()) << frame.obstacles.size() << " obstacle points";
  EXPECT_EQ(TallestObstacle(frame), 0.0);
  ASSERT_EQ(frame.cells.size(), 24u);  // 6 x 4
  for (const nav::AfdsCell& cell : frame.cells) {
    if (cell.row < 2) continue;  // the image's lower half is floor
    EXPECT_TRUE(cell.own_floor) << cell.column << ", " << cell.row;
  }
  for (const nav::LaneResult& lane : frame.lanes) {
    EXPECT_FALSE(lane.dead_end) << "lane " << lane.offset_m << " at " << lane.free_distance_m;
    EXPECT_GT(lane.free_distance_m, 3.5);
  }
}

TEST(AfdsTest, ABoxsHeightIsMeasuredFromItsTopAndAFacesFromItsEdge) {
  const auto o = Camera();
  for (const int columns : {3, 6, 12}) {
    nav::AfdsOptions options;
    options.grid_columns = columns;
    options.grid_rows = columns * 3 / 4;
    nav::Afds afds = MakeAfds(o, options);
    for (const auto& [x, height] : {std::pair{1.5f, 0.15f}, {2.5f, 0.2f}, {2.0f, 0.6f}}) {
      TriangleMesh mesh = Floor();
      mesh.AddBox({x, -0.5f, 0.0f}, {x + 0.5f, 0.5f, height}, kGrey);
      const nav::AfdsFrame& frame = afds.Process(Render(mesh, o));
      const std::string what =
          std::to_string(columns) + " columns, " + std::to_string(height) + " m at " + std::to_string(x) + " m";
      // A top seen from above (lower than the 0.3 m camera) is a plane: within millimetres; a face's edge lies
      // between two sampled rows (1.7 cm apart at 2 m).
      EXPECT_NEAR(TallestObstacle(frame), height, height < 0.3f ? 0.005 : 0.012) << what;
      for (const nav::LaneResult& lane : frame.lanes) {
        EXPECT_TRUE(lane.dead_end) << what;
        EXPECT_NEAR(lane.free_distance_m, x, 0.04) << what;
      }
    }
  }
}

TEST(AfdsTest, ACameraMountedLowerThanConfiguredStillFindsTheFloorAndTheStep) {
  auto o = Camera();
  const nav::PinholeCamera configured = drivers::sim::MakeCameraInfo(o).camera;
  o.mount_height_m += 0.04;  // the camera is 4 cm higher than its configuration says: MORP's floor is below ...
  TriangleMesh mesh = Floor();
  mesh.AddBox({1.2f, -1.0f, 0.0f}, {1.6f, 1.0f, 0.045f}, kGrey);  // ... a 4.5 cm step
  nav::Afds afds(configured, nav::AfdsOptions{}, RobotWidthLanes());
  const nav::AfdsFrame& frame = afds.Process(Render(mesh, o));
  ASSERT_TRUE(frame.floor_found);
  EXPECT_NEAR(frame.floor.offset, 0.04, 0.005);  // the floor 4 cm below the configured one
  EXPECT_NEAR(TallestObstacle(frame), 0.045, 0.005);
  for (const nav::LaneResult& lane : frame.lanes) {
    EXPECT_TRUE(lane.dead_end);
    EXPECT_NEAR(lane.free_distance_m, 1.2, 0.04);
  }
}

TEST(AfdsTest, ADropIsADeadEndAtItsEdgeAndTooCloseIsBlind) {
  const auto o = Camera();
  nav::Afds afds = MakeAfds(o);
  for (const nav::LaneResult& lane : afds.Process(Render(Floor(1.5f), o)).lanes) {
    EXPECT_TRUE(lane.dead_end);
    EXPECT_NEAR(lane.free_distance_m, 1.5, 0.05);
    EXPECT_LT(lane.point.z(), -0.2);
  }
  TriangleMesh mesh = Floor();
  mesh.AddBox({0.25f, -3.0f, 0.0f}, {0.4f, 3.0f, 1.5f}, kGrey);  // under the camera's 0.2 m range
  for (const nav::LaneResult& lane : afds.Process(Render(mesh, o)).lanes) {
    EXPECT_TRUE(lane.blind);
    EXPECT_TRUE(lane.dead_end);
  }
  EXPECT_THROW(afds.Process(cv::Mat(10, 10, CV_16UC1, cv::Scalar(0))), std::invalid_argument);
  nav::AfdsOptions too_fine;
  too_fine.grid_columns = 40;
  EXPECT_THROW(MakeAfds(o, too_fine), std::invalid_argument);
}

TEST(AfdsTest, AStereoPairsShadowIsNoObstacleAndItsBoxStandsWhereItIs) {
  const drivers::sim::SimCameraOptions o;
  drivers::sim::SimStereoOptions stereo;
  stereo.enabled = true;
  TriangleMesh mesh = Floor();
  mesh.AddBox({2.0f, -0.25f, 0.0f}, {2.5f, 0.25f, 0.2f}, kGrey);
  const drivers::sim::RayCaster caster(mesh);
  drivers::sim::SimStereoCamera pair(caster, o, stereo);
  std::mt19937 rng(1);
  drivers::RgbdFrame frame;
  pair.Render(Eigen::Isometry3d::Identity(), rng, frame);
  nav::Afds afds(pair.info().camera, nav::AfdsOptions{}, nav::MorpOptions{});
  const nav::AfdsFrame& out = afds.Process(frame.depth_mm);
  ASSERT_TRUE(out.floor_found);
  // The matcher's window lends the box's depth to the background's pixels just past its edges: a few centimetres
  // higher (and wider: the lanes at its sides, 0.25 m, may meet it or not).
  EXPECT_NEAR(TallestObstacle(out), 0.2, 0.05);
  for (const nav::LaneResult& lane : out.lanes) {
    EXPECT_FALSE(lane.blind) << "lane " << lane.offset_m;
    if (std::abs(std::abs(lane.offset_m) - 0.25) < 0.01) continue;
    if (std::abs(lane.offset_m) < 0.25) {
      EXPECT_NEAR(lane.free_distance_m, 2.0, 0.08) << "lane " << lane.offset_m;
    } else {
      EXPECT_FALSE(lane.dead_end) << "lane " << lane.offset_m << " at " << lane.free_distance_m;  // beside it
    }
  }
}

}  // namespace
}  // namespace corridor

namespace corridor {
namespace {

// A 10 x 6 m room with a 0.6 m pillar on the straight line from the start to the goal.
std::shared_ptr<const drivers::sim::World> PillarRoom() {
  nav::OccupancyGrid grid(200, 120, 0.05, {}, nav::kFreeCell);
  for (int i = 0; i < 200; ++i) grid.at({i, 0}) = grid.at({i, 119}) = nav::kOccupiedCell;
  for (int i = 0; i < 120; ++i) grid.at({0, i}) = grid.at({199, i}) = nav::kOccupiedCell;
  for (int y = 54; y < 66; ++y)
    for (int x = 84; x < 96; ++x) grid.at({x, y}) = nav::kOccupiedCell;  // x 4.2-4.8 m, y 2.7-3.3 m
  return std::make_shared<const drivers::sim::World>(drivers::sim::WorldFromMap(grid, drivers::sim::WorldOptions{}));
}

TEST(MorpClosedLoopTest, DrivesAroundAPillarToItsGoalWithoutTouchingIt) {
  drivers::sim::SimOptions o;
  o.start = {1.0, 3.0, 0.0};
  o.seed = 2022;
  o.camera.rate_hz = 15.0;
  o.base.limits.max_linear_mps = 0.26;  // DPoom's speed
  o.laser.enabled = false;
  drivers::sim::SimRobot robot(PillarRoom(), o);
  nav::Morp morp(robot.info().camera, RobotWidthLanes());  // MORP-RB alone steers on every lane it is given
  nav::MorpRb policy{nav::MorpRbOptions{}};
  const Eigen::Vector2d goal(8.0, 3.0);
  bool bumped = false;
  bool avoided = false;
  robot.SetOdometryHandler([&](const drivers::WheelOdometry& w) { bumped |= w.bumper_pressed; });
  robot.SetFrameHandler([&](std::shared_ptr<const drivers::RgbdFrame> frame) {
    // The control loop at the camera's rate: lanes, then the rule-based policy toward the goal.
    const nav::Pose2 pose = robot.true_pose();
    const Eigen::Vector2d to_goal = goal - pose.translation();
    const double heading_error = std::atan2(to_goal.y(), to_goal.x()) - pose.yaw_rad;
    const nav::MorpRbDecision d = policy.Decide(morp.Process(frame->depth_mm), heading_error, 1.0 / 15.0);
    avoided |= d.mode != nav::MorpRbMode::kFollow;
    robot.SetVelocity(to_goal.norm() < 0.15 ? nav::Twist2{} : d.twist);
  });
  double seconds = 0.0;
  while (seconds < 90.0 && (robot.true_pose().translation() - goal).norm() >= 0.15) {
    robot.Step();
    seconds += robot.step_s();
  }
  EXPECT_LT((robot.true_pose().translation() - goal).norm(), 0.15)
      << "stuck at " << robot.true_pose().x_m << ", " << robot.true_pose().y_m;
  EXPECT_FALSE(bumped);
  EXPECT_TRUE(avoided) << "the pillar was never seen";
}

}  // namespace
}  // namespace corridor
