// The detection hook on real images (a video of people walking from Debian's opencv-doc, a TUM RGB-D desk frame without
// people) and on the simulator's frames (a person of the crowd's size, located by the depth inside their box).
#include <filesystem>
#include <fstream>
#include <random>
#include <stdexcept>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "drivers/sim/sensors.h"
#include "face/detect/dnn_detector.h"
#include "face/detect/face_cascade.h"
#include "face/detect/hog_people.h"
#include "face/detect/locate.h"
#include "face/detect/simulated_people.h"
#include "face/detect/tracker.h"
#include "testing/source_dir.h"

namespace corridor::face {
namespace {

constexpr const char* kVideo = "/usr/share/doc/opencv-doc/examples/data/vtest.avi";  // Debian's opencv-doc

cv::Mat VideoFrame(int index) {
  cv::VideoCapture video(kVideo);
  if (!video.isOpened()) throw std::runtime_error(std::string(kVideo) + " is missing: ./dev installs opencv-doc");
  cv::Mat frame;
  for (int i = 0; i <= index; ++i) video.read(frame);
  return frame;
}

bool Finds(const std::vector<Detection>& found, const cv::Rect2d& person, double min_iou) {
  for (const Detection& d : found) {
    if (d.label == "person" && d.box && IntersectionOverUnion(*d.box, person) >= min_iou) return true;
  }
  return false;
}

TEST(HogPeopleDetectorTest, FindsThePeopleWalkingInARealVideoFrame) {
  // vtest.avi frame 507: two people walking apart from the others, boxed by hand (tests/data/detect).
  HogPeopleDetector hog;
  const std::vector<Detection> found = hog.Detect(VideoFrame(507), cv::Mat());
  EXPECT_TRUE(Finds(found, cv::Rect2d(545, 226, 36, 107), 0.6));
  EXPECT_TRUE(Finds(found, cv::Rect2d(723, 232, 36, 98), 0.5));
  for (const Detection& d : found) {
    EXPECT_EQ(d.source, "hog");
    EXPECT_GT(d.score, 0.0);
    EXPECT_LT(d.score, 1.0);
  }
}

TEST(HogPeopleDetectorTest, FindsNobodyInARealIndoorFrameWithoutPeople) {
  // The TUM RGB-D desk, a Kinect's colour frame: a room, a desk, a chair, no one.
  const cv::Mat desk = cv::imread((testing::SourceDir() / "tests/data/depth/1.png").string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(desk.empty());
  HogPeopleDetector hog;
  EXPECT_TRUE(hog.Detect(desk, cv::Mat()).empty());
  FaceCascadeDetector faces;
  EXPECT_TRUE(faces.Detect(desk, cv::Mat()).empty());
}

TEST(HogPeopleDetectorTest, RejectsWhatItCannotUse) {
  EXPECT_THROW(HogPeopleDetector(HogOptions{.upscale = 0.5}), std::invalid_argument);
  HogPeopleDetector hog;
  EXPECT_THROW(hog.Detect(cv::Mat(120, 160, CV_8UC1, cv::Scalar(0)), cv::Mat()), std::invalid_argument);
}

TEST(FaceCascadeDetectorTest, SaysWhichCascadeItCannotRead) {
  try {
    FaceCascadeDetector({.cascade = "/nonexistent/cascade.xml"});
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/cascade.xml"), std::string::npos);
  }
}

// The simulator's camera (a RealSense-like 320 x 240, 0.3 m up, tilted 10 degrees down) in a room with a floor, a wall
// 8 m ahead, and a person of the crowd's size 2.5 m ahead and 0.4 m to the left.
struct SimScene {
  drivers::sim::SimCameraOptions options;
  nav::PinholeCamera camera;
  Eigen::Vector2d person{2.5, 0.4};
  drivers::RgbdFrame frame;

  explicit SimScene(Eigen::Vector2d at = {2.5, 0.4}) : person(at) {
    options.dropout_fraction = 0.0;
    camera = drivers::sim::MakeCameraInfo(options).camera;
    drivers::sim::TriangleMesh mesh;
    mesh.AddBox({-1.0f, -10.0f, -0.1f}, {9.0f, 10.0f, 0.0f}, {0.5f, 0.5f, 0.5f});
    mesh.AddBox({8.0f, -10.0f, 0.0f}, {8.2f, 10.0f, 2.5f}, {0.8f, 0.8f, 0.8f});
    mesh.AddCylinder(person.cast<float>(), 0.25f, 1.7f, 16, {0.2f, 0.3f, 0.8f});
    const drivers::sim::RayCaster caster(mesh);
    const drivers::sim::RgbdRenderer renderer(caster, options);
    std::mt19937 rng(1);
    renderer.Render(camera.base_T_camera, rng, frame);
  }
};

TEST(LocateTest, ASimulatedPersonIsLocatedByTheDepthInTheirBoxAndIsPersonSized) {
  const SimScene scene;
  SimulatedPeople people({.miss_rate = 0.0});
  std::vector<Detection> found = people.Detect({scene.person}, nav::Pose2{}, scene.frame.depth_mm, scene.camera);
  ASSERT_EQ(found.size(), 1u);
  ASSERT_TRUE(found[0].box);
  const std::optional<Located> located = Locate(*found[0].box, scene.frame.depth_mm, scene.camera);
  ASSERT_TRUE(located);
  // The near surface of the body, 0.25 m short of its centre along the ray.
  const Eigen::Vector2d truth = scene.person * (1.0 - 0.25 / scene.person.norm());
  EXPECT_LT((located->position.head<2>() - truth).norm(), 0.1) << located->position.transpose();
  EXPECT_TRUE(Plausible(*located, *found[0].box, scene.frame.depth_mm.size(), PersonSize()));
  // The simulated source's own position agrees.
  EXPECT_LT((found[0].position->head<2>() - truth).norm(), 0.05);
  // LocateDetections keeps it and sets its position from the depth.
  found[0].position.reset();
  LocateDetections(found, scene.frame.depth_mm, scene.camera);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_TRUE(found[0].position);
}

TEST(LocateTest, ABoxTooSmallForAPersonAtItsDepthIsNotAPerson) {
  // Someone on a poster: a box a third of a person's height over a real person's depth. The whole body is in
  // view at 5 m (nearer, the tilted camera cuts the head off and the height is not judged).
  const SimScene scene({5.0, 0.3});
  SimulatedPeople people({.miss_rate = 0.0});
  std::vector<Detection> found = people.Detect({scene.person}, nav::Pose2{}, scene.frame.depth_mm, scene.camera);
  ASSERT_EQ(found.size(), 1u);
  const std::optional<Located> whole = Locate(*found[0].box, scene.frame.depth_mm, scene.camera);
  ASSERT_TRUE(whole);
  EXPECT_NEAR(whole->height_m, 1.7, 0.25);
  EXPECT_TRUE(Plausible(*whole, *found[0].box, scene.frame.depth_mm.size(), PersonSize()));
  cv::Rect2d& box = *found[0].box;
  box.y += box.height / 3.0;
  box.height /= 3.0;
  LocateDetections(found, scene.frame.depth_mm, scene.camera);
  EXPECT_TRUE(found.empty());
}

TEST(LocateTest, NoDepthInTheBoxLeavesItUnlocatedAndBadDepthIsRefused) {
  const SimScene scene;
  const cv::Mat empty(scene.camera.height, scene.camera.width, CV_16UC1, cv::Scalar(0));
  EXPECT_FALSE(Locate(cv::Rect2d(100, 60, 40, 100), empty, scene.camera));
  EXPECT_THROW(Locate(cv::Rect2d(0, 0, 10, 10), cv::Mat(10, 10, CV_32FC1), scene.camera), std::invalid_argument);
}

TEST(SimulatedPeopleTest, PeopleBehindAWallOrBehindTheRobotAreNotSeen) {
  const SimScene scene;
  SimulatedPeople people({.miss_rate = 0.0});
  // Behind the wall at 8 m, behind the robot, beyond the range.
  EXPECT_TRUE(
      people.Detect({{8.6, 0.0}, {-2.0, 0.0}, {3.0, 30.0}}, nav::Pose2{}, scene.frame.depth_mm, scene.camera).empty());
  SimulatedPeople blind({.miss_rate = 1.0});
  EXPECT_TRUE(blind.Detect({scene.person}, nav::Pose2{}, scene.frame.depth_mm, scene.camera).empty());
  EXPECT_THROW(SimulatedPeople({.miss_rate = 1.5}), std::invalid_argument);
}

TEST(TrackerTest, APersonKeepsTheirIdAsTheyAndTheRobotMoveAndANewOneGetsANewId) {
  Tracker tracker;
  nav::Pose2 robot{0.0, 0.0, 0.0};
  Eigen::Vector2d person{3.0, 0.0};  // world frame, walking towards the robot
  int id = 0;
  for (int i = 0; i < 10; ++i) {
    robot = robot * nav::Pose2{0.05, 0.0, 0.02};
    person += Eigen::Vector2d(-0.1, 0.02);
    const Eigen::Vector2d in_base = robot.Inverse().Transform(person);
    std::vector<Detection> frame{
        {"person", 0.9, std::nullopt, Eigen::Vector3d(in_base.x(), in_base.y(), 0.8), 0, "sim"}};
    if (i == 5) frame.push_back({"person", 0.8, std::nullopt, Eigen::Vector3d(2.0, -1.5, 0.8), 0, "sim"});
    tracker.Assign(frame, robot, drivers::FromSeconds(0.2 * i));
    if (i == 0) id = frame[0].track_id;
    EXPECT_EQ(frame[0].track_id, id) << i;
    if (i == 5) {
      EXPECT_NE(frame[1].track_id, id);
    }
  }
  // Unseen for longer than forget_s, they come back as someone new.
  std::vector<Detection> later{{"person", 0.9, std::nullopt, Eigen::Vector3d(1.0, 0.0, 0.8), 0, "sim"}};
  tracker.Assign(later, robot, drivers::FromSeconds(10.0));
  EXPECT_NE(later[0].track_id, id);
}

TEST(TrackerTest, WithoutDepthBoxesThatOverlapAreTheSamePerson) {
  Tracker tracker;
  std::vector<Detection> a{{"person", 0.9, cv::Rect2d(100, 50, 40, 100), std::nullopt, 0, "hog"}};
  tracker.Assign(a, nav::Pose2{}, 0);
  std::vector<Detection> b{{"person", 0.9, cv::Rect2d(106, 52, 40, 100), std::nullopt, 0, "hog"},
                           {"person", 0.7, cv::Rect2d(300, 50, 40, 100), std::nullopt, 0, "hog"}};
  tracker.Assign(b, nav::Pose2{}, drivers::FromSeconds(0.3));
  EXPECT_EQ(b[0].track_id, a[0].track_id);
  EXPECT_NE(b[1].track_id, a[0].track_id);
}

TEST(DnnDetectorTest, ReadsYoloRowsAndYolov8ColumnsIntoBoxesOfTheImage) {
  const std::vector<std::string> classes{"person", "chair"};
  // Two rows (cx, cy, w, h, objectness, person, chair), fractions of the image: a person and a faint chair.
  const cv::Mat rows = (cv::Mat_<float>(2, 7) << 0.5f, 0.5f, 0.2f, 0.6f, 0.9f, 0.95f, 0.1f,  //
                        0.2f, 0.3f, 0.1f, 0.1f, 0.3f, 0.2f, 0.5f);
  DnnOptions options;
  const std::vector<Detection> found = ParseYoloOutput(rows, classes, cv::Size(640, 480), options);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].label, "person");
  EXPECT_NEAR(found[0].score, 0.9 * 0.95, 1e-6);
  EXPECT_NEAR(found[0].box->x, 0.4 * 640, 1e-3);
  EXPECT_NEAR(found[0].box->height, 0.6 * 480, 1e-3);
  // YOLOv8: columns of (cx, cy, w, h, scores...) in input pixels.
  DnnOptions v8;
  v8.transposed = true;
  v8.boxes_in_pixels = true;
  v8.input_size_px = 320;
  const cv::Mat columns = (cv::Mat_<float>(6, 1) << 160.0f, 160.0f, 64.0f, 192.0f, 0.8f, 0.1f);
  const std::vector<Detection> found8 = ParseYoloOutput(columns, classes, cv::Size(640, 480), v8);
  ASSERT_EQ(found8.size(), 1u);
  EXPECT_NEAR(found8[0].box->width, 64.0 * 2.0, 1e-3);
  EXPECT_THROW(ParseYoloOutput(rows, {"person"}, cv::Size(640, 480), options), std::invalid_argument);
}

TEST(DnnDetectorTest, SaysWhichFileItCannotRead) {
  const std::filesystem::path classes = std::filesystem::temp_directory_path() / "corridor_dnn_classes.txt";
  std::ofstream(classes) << "person\n";
  DnnOptions options;
  options.model = "/nonexistent/model.onnx";
  options.classes = classes;
  try {
    DnnDetector detector(options);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/model.onnx"), std::string::npos) << e.what();
  }
  options.classes = "/nonexistent/classes.txt";
  EXPECT_THROW(DnnDetector{options}, std::invalid_argument);
  std::filesystem::remove(classes);
}

}  // namespace
}  // namespace corridor::face
