// The people detector's parts that are not its tuning: merging one person's finds, and people in the depth image.
// How well it finds people is measured on hand-annotated images (tools/detect, docs/benchmarks.md).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "face/detect/depth_people.h"
#include "face/detect/people_detector.h"

namespace corridor::face {
namespace {

Detection Person(double x, double y, double w, double h, double score, const char* source) {
  Detection d;
  d.label = "person";
  d.score = score;
  d.box = cv::Rect2d(x, y, w, h);
  d.source = source;
  return d;
}

TEST(MergePeopleTest, OnePersonsFindsBecomeOneAndOthersStay) {
  const std::vector<Detection> merged =
      MergePeople({Person(100, 50, 80, 200, 0.9, "hog"),           // a whole body
                   Person(110, 40, 70, 120, 0.5, "upper_body"),    // its head and shoulders, mostly inside it
                   Person(400, 60, 60, 80, 0.6, "face_frontal")},  // someone else
                  0.3);
  ASSERT_EQ(merged.size(), 2u);
  EXPECT_EQ(merged[0].source, "hog");
  EXPECT_DOUBLE_EQ(merged[0].box->area(), 80.0 * 200.0);
  EXPECT_EQ(merged[1].source, "face_frontal");
}

// A 320 x 240 camera 0.3 m above the floor looking ahead; the depth it sees of vertical cylinders standing on the
// floor (and of boxes lifted off it), ray-cast: the floor is left out, as a real scene's floor is the nearest thing
// only below the objects.
struct Solid {
  Eigen::Vector2d centre;
  double radius_m;
  double bottom_m;
  double top_m;
};

nav::PinholeCamera Camera() {
  nav::PinholeCamera camera;
  camera.width = 320;
  camera.height = 240;
  camera.fx = camera.fy = 260.0;
  camera.cx = 160.0;
  camera.cy = 120.0;
  camera.base_T_camera = nav::CameraMount(0.1, 0.3, 0.0);
  return camera;
}

cv::Mat Render(const nav::PinholeCamera& camera, const std::vector<Solid>& solids) {
  cv::Mat depth(camera.height, camera.width, CV_16UC1, cv::Scalar(0));
  const Eigen::Vector3d origin = camera.base_T_camera.translation();
  for (int v = 0; v < camera.height; ++v) {
    for (int u = 0; u < camera.width; ++u) {
      const Eigen::Vector3d ray = camera.base_T_camera.linear() * camera.Ray(u, v);  // depth t: origin + t ray
      double best = std::numeric_limits<double>::infinity();
      for (const Solid& s : solids) {
        // |origin.xy + t ray.xy - centre| = r, the nearer root.
        const Eigen::Vector2d o = origin.head<2>() - s.centre;
        const Eigen::Vector2d d = ray.head<2>();
        const double a = d.squaredNorm();
        const double b = 2.0 * o.dot(d);
        const double c = o.squaredNorm() - s.radius_m * s.radius_m;
        const double disc = b * b - 4.0 * a * c;
        if (disc < 0.0) continue;
        const double t = (-b - std::sqrt(disc)) / (2.0 * a);
        const double z = origin.z() + t * ray.z();
        if (t > 0.0 && z >= s.bottom_m && z <= s.top_m) best = std::min(best, t);
      }
      if (std::isfinite(best)) depth.at<std::uint16_t>(v, u) = static_cast<std::uint16_t>(best * 1000.0);
    }
  }
  return depth;
}

TEST(DepthPeopleTest, APersonSizedObjectOnTheFloorIsAPersonATableAPillarAndAShelfTopAreNot) {
  const nav::PinholeCamera camera = Camera();
  const Solid person{{3.0, 0.8}, 0.2, 0.0, 1.7};
  const Solid table{{3.0, -0.8}, 0.35, 0.0, 0.75};
  const Solid lifted{{4.0, 0.0}, 0.25, 0.9, 1.8};  // on a shelf, off the floor
  const cv::Mat depth = Render(camera, {person, table, lifted});
  const std::vector<DepthCandidate> candidates{{person.centre, 0.2}, {table.centre, 0.35}, {lifted.centre, 0.25}};
  const std::vector<Detection> found = DepthPeople(depth, camera, candidates);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].label, "person");
  EXPECT_EQ(found[0].source, "depth");
  ASSERT_TRUE(found[0].position.has_value());
  EXPECT_NEAR(found[0].position->head<2>().norm(), person.centre.norm() - person.radius_m, 0.1);
  EXPECT_GT(*found[0].bearing_rad, 0.0);  // on the left
}

TEST(DepthPeopleTest, SomeoneCloseWhoseHeadIsAboveTheViewIsAPerson) {
  const nav::PinholeCamera camera = Camera();
  const Solid near{{0.9, 0.0}, 0.2, 0.0, 1.75};
  const std::vector<Detection> found = DepthPeople(Render(camera, {near}), camera, {{near.centre, 0.2}});
  EXPECT_EQ(found.size(), 1u);
}

TEST(DepthPeopleTest, NothingWithoutAUsableDepthImageAndNoneTwice) {
  const nav::PinholeCamera camera = Camera();
  EXPECT_TRUE(DepthPeople(cv::Mat(), camera, {{{2.0, 0.0}, 0.2}}).empty());
  EXPECT_TRUE(DepthPeople(cv::Mat(10, 10, CV_16UC1, cv::Scalar(2000)), camera, {{{2.0, 0.0}, 0.2}}).empty());
  Detection by_image = Person(0, 0, 10, 10, 0.9, "hog");
  by_image.position = Eigen::Vector3d(2.9, 0.75, 0.8);
  Detection by_depth = Person(0, 0, 10, 10, 0.5, "depth");
  by_depth.position = Eigen::Vector3d(2.8, 0.8, 0.8);
  EXPECT_TRUE(NotAlreadyFound({by_depth}, {by_image}).empty());
  by_image.position = Eigen::Vector3d(1.0, -1.0, 0.8);
  EXPECT_EQ(NotAlreadyFound({by_depth}, {by_image}).size(), 1u);
}

}  // namespace
}  // namespace corridor::face
