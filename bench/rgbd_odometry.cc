// Should corridor fuse RGB-D odometry with its wheel odometry (issue 20: "measure and decide")? OpenCV's rgbd
// odometries (RgbdOdometry: photometric; ICPOdometry: depth; RgbdICPOdometry: both; FastICPOdometry: KinectFusion's
// ICP) between consecutive frames, against the wheel odometry they would join, and what each costs per frame on one
// core.
//   1. The simulator: the robot drives Willow Garage's start corridor at 0.5 m/s with 15 Hz frames of 320 x 240, then
//      turns a quarter on the spot at 0.5 rad/s and drives on; each method's frame-to-frame motion is taken into the
//      base frame and chained in the plane. Drift: the chained pose's end error per metre driven and heading error per
//      radian turned, against the simulator's wheel odometry model (drivers/sim/diff_drive_sim.h) on the same path.
//   2. Real frames (../shared/data/depth_rgbd): Open3D's rendered living room with its true camera poses (four pairs,
//      640 x 480, simulated Kinect noise) and the TUM desk pair (Kinect v1, no truth: the motion each method finds).
//   build/bench/rgbd_odometry [DATA_DIR]
// Results and the decision: docs/benchmarks.md.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/rgbd.hpp>

#include "drivers/sim/sensors.h"

namespace corridor {
namespace {

namespace fs = std::filesystem;

struct Frame {
  cv::Mat gray;   // CV_8UC1
  cv::Mat depth;  // CV_32FC1, metres, 0 where unknown
};

struct Method {
  const char* name;
  std::function<cv::Ptr<cv::rgbd::Odometry>(const cv::Mat& camera_matrix)> make;
};

const std::vector<Method>& Methods() {
  static const std::vector<Method> methods = {
      {"RgbdOdometry", [](const cv::Mat& k) { return cv::rgbd::RgbdOdometry::create(k); }},
      {"ICPOdometry", [](const cv::Mat& k) { return cv::rgbd::ICPOdometry::create(k); }},
      {"RgbdICPOdometry", [](const cv::Mat& k) { return cv::rgbd::RgbdICPOdometry::create(k); }},
      {"FastICPOdometry", [](const cv::Mat& k) { return cv::rgbd::FastICPOdometry::create(k); }},
  };
  return methods;
}

cv::Mat CameraMatrix(double fx, double fy, double cx, double cy) {
  return (cv::Mat_<double>(3, 3) << fx, 0, cx, 0, fy, cy, 0, 0, 1);
}

// The motion of the camera from `from` to `to` (to's pose in from's optical frame), or false when the method gives up.
// OpenCV's Rt maps points of the source frame into the destination frame: the camera's motion is its inverse.
bool Motion(const cv::rgbd::Odometry& odometry, const Frame& from, const Frame& to, Eigen::Isometry3d& from_T_to,
            double& ms) {
  cv::Mat rt;
  const cv::Mat mask_from = from.depth > 0.0f;
  const cv::Mat mask_to = to.depth > 0.0f;
  const auto start = std::chrono::steady_clock::now();
  const bool ok = odometry.compute(from.gray, from.depth, mask_from, to.gray, to.depth, mask_to, rt);
  ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  if (!ok) return false;
  cv::Mat rt64;
  rt.convertTo(rt64, CV_64F);
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) m(r, c) = rt64.at<double>(r, c);
  }
  from_T_to = Eigen::Isometry3d(m).inverse();
  return true;
}

double Percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(p * static_cast<double>(v.size())))];
}

nav::Pose2 Planar(const Eigen::Isometry3d& t) {
  return {t.translation().x(), t.translation().y(), std::atan2(t.linear()(1, 0), t.linear()(0, 0))};
}

// 1. The simulator.
void Simulated() {
  const drivers::sim::World world =
      drivers::sim::LoadWorld(std::string(CORRIDOR_SOURCE_DIR) + "/config/worlds/willow_garage/willow-full-0.05.yaml",
                              drivers::sim::WorldOptions{});
  const drivers::sim::RayCaster caster(world.mesh);
  const drivers::sim::SimCameraOptions options;
  const drivers::sim::RgbdRenderer renderer(caster, options);
  const nav::PinholeCamera camera = drivers::sim::MakeCameraInfo(options).camera;
  // 0.5 m/s and 0.5 rad/s at 15 Hz: 6 m north, a quarter turn, 3 m west.
  std::vector<nav::Pose2> path;
  nav::Pose2 p{24.38, 24.07, std::numbers::pi / 2};
  const double step_m = 0.5 / options.rate_hz;
  const double step_rad = 0.5 / options.rate_hz;
  const int turn_steps = static_cast<int>(std::lround(std::numbers::pi / 2 / step_rad));
  for (int i = 0; i < 180; ++i, p = p * nav::Pose2{step_m, 0.0, 0.0}) path.push_back(p);
  for (int i = 0; i < turn_steps; ++i, p = p * nav::Pose2{0.0, 0.0, std::numbers::pi / 2 / turn_steps})
    path.push_back(p);
  for (int i = 0; i < 90; ++i, p = p * nav::Pose2{step_m, 0.0, 0.0}) path.push_back(p);
  path.push_back(p);

  std::mt19937 rng(1);
  std::vector<Frame> frames;
  for (const nav::Pose2& pose : path) {
    drivers::RgbdFrame f;
    renderer.Render(pose.ToIsometry3() * camera.base_T_camera, rng, f);
    Frame frame;
    cv::cvtColor(f.color_bgr, frame.gray, cv::COLOR_BGR2GRAY);
    f.depth_mm.convertTo(frame.depth, CV_32F, 0.001);
    frames.push_back(std::move(frame));
  }
  double driven_m = 0.0;
  double turned_rad = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i) {
    const nav::Pose2 step = path[i - 1].Inverse() * path[i];
    driven_m += step.translation().norm();
    turned_rad += std::abs(step.yaw_rad);
  }
  std::printf("Simulator, Willow Garage: %zu frames 320 x 240, %.1f m driven, %.2f rad turned\n", frames.size(),
              driven_m, turned_rad);
  std::printf(
      "| method | failed frames | end error per metre | heading error per radian turned | ms per frame "
      "(mean, p99) | a core at 15 Hz |\n|---|---|---|---|---|---|\n");

  // Wheel odometry on the same path, seeded: the simulator's model (1 % of each step's length, 2 % of its turn), and a
  // worse base with slam_eval's biases besides (lengths read 2 % long, a degree of heading lost per metre).
  for (const bool biased : {false, true}) {
    std::mt19937 wheel_rng(2);
    std::normal_distribution<double> normal(0.0, 1.0);
    nav::Pose2 odom = path.front();
    for (std::size_t i = 1; i < path.size(); ++i) {
      const nav::Pose2 step = path[i - 1].Inverse() * path[i];
      const double length = step.translation().norm();
      const double scale = (biased ? 1.02 : 1.0) + 0.01 * normal(wheel_rng);
      const double drift = biased ? length * std::numbers::pi / 180.0 : 0.0;
      odom = odom * nav::Pose2{step.x_m * scale, step.y_m, step.yaw_rad * (1.0 + 0.02 * normal(wheel_rng)) + drift};
    }
    const nav::Pose2 error = path.back().Inverse() * odom;
    std::printf("| wheel odometry (%s) | - | %.4f m/m | %.2f deg/rad | - | - |\n",
                biased ? "2 % long, 1 deg/m drift" : "the simulator's model", error.translation().norm() / driven_m,
                std::abs(error.yaw_rad) * 180.0 / std::numbers::pi / turned_rad);
  }

  const cv::Mat k = CameraMatrix(camera.fx, camera.fy, camera.cx, camera.cy);
  for (const Method& method : Methods()) {
    const cv::Ptr<cv::rgbd::Odometry> odometry = method.make(k);
    nav::Pose2 chained = path.front();
    std::vector<double> times;
    int failed = 0;
    for (std::size_t i = 1; i < frames.size(); ++i) {
      Eigen::Isometry3d from_T_to;
      double ms = 0.0;
      nav::Pose2 step;
      if (Motion(*odometry, frames[i - 1], frames[i], from_T_to, ms)) {
        step = Planar(camera.base_T_camera * from_T_to * camera.base_T_camera.inverse());
      } else {
        ++failed;  // as a fusing filter would: no motion from this pair
      }
      times.push_back(ms);
      chained = chained * step;
    }
    const nav::Pose2 error = path.back().Inverse() * chained;
    double mean = 0.0;
    for (double t : times) mean += t / static_cast<double>(times.size());
    std::printf("| %s | %d of %zu | %.4f m/m | %.2f deg/rad | %.1f, %.1f | %.0f %% |\n", method.name, failed,
                frames.size() - 1, error.translation().norm() / driven_m,
                std::abs(error.yaw_rad) * 180.0 / std::numbers::pi / turned_rad, mean, Percentile(times, 0.99),
                mean * options.rate_hz / 10.0);
  }
}

Frame ReadFrame(const fs::path& colour, const fs::path& depth, double metres_per_unit) {
  Frame f;
  const cv::Mat c = cv::imread(colour.string(), cv::IMREAD_COLOR);
  const cv::Mat d = cv::imread(depth.string(), cv::IMREAD_ANYDEPTH);
  if (c.empty() || d.empty()) throw std::runtime_error("cannot read " + colour.string() + " or " + depth.string());
  cv::cvtColor(c, f.gray, cv::COLOR_BGR2GRAY);
  d.convertTo(f.depth, CV_32F, metres_per_unit);
  return f;
}

// Open3D's trajectory.log: per frame a line of ids, then the 4 x 4 camera-to-world matrix.
std::vector<Eigen::Isometry3d> ReadTrajectory(const fs::path& file) {
  std::ifstream in(file);
  std::vector<Eigen::Isometry3d> poses;
  int a = 0;
  int b = 0;
  int c = 0;
  while (in >> a >> b >> c) {
    Eigen::Matrix4d m;
    for (int r = 0; r < 4; ++r) {
      for (int col = 0; col < 4; ++col) in >> m(r, col);
    }
    poses.emplace_back(m);
  }
  return poses;
}

double Degrees(const Eigen::Matrix3d& r) { return Eigen::AngleAxisd(r).angle() * 180.0 / std::numbers::pi; }

// 2. Real frames.
void Recorded(const fs::path& data) {
  const fs::path room = data / "open3d_testdata/RGBD";
  const std::vector<Eigen::Isometry3d> truth = ReadTrajectory(room / "trajectory.log");
  std::vector<Frame> frames;
  for (int i = 0; i < 5; ++i) {
    char name[16];
    std::snprintf(name, sizeof name, "%05d", i);
    frames.push_back(
        ReadFrame(room / "color" / (std::string(name) + ".jpg"), room / "depth" / (std::string(name) + ".png"), 0.001));
  }
  if (truth.size() < frames.size()) throw std::runtime_error("trajectory.log holds fewer poses than frames");
  std::printf("\nOpen3D living room (rendered, Kinect noise), 640 x 480, pairs 0-1 .. 3-4:\n");
  std::printf(
      "| method | failed pairs | translation error (mean, max) | rotation error (mean, max) | ms per pair |\n"
      "|---|---|---|---|---|\n");
  const cv::Mat k = CameraMatrix(525.0, 525.0, 319.5, 239.5);
  for (const Method& method : Methods()) {
    const cv::Ptr<cv::rgbd::Odometry> odometry = method.make(k);
    int failed = 0;
    std::vector<double> t_err;
    std::vector<double> r_err;
    double ms_total = 0.0;
    for (std::size_t i = 1; i < frames.size(); ++i) {
      Eigen::Isometry3d from_T_to;
      double ms = 0.0;
      const bool ok = Motion(*odometry, frames[i - 1], frames[i], from_T_to, ms);
      ms_total += ms;
      if (!ok) {
        ++failed;
        continue;
      }
      const Eigen::Isometry3d true_step = truth[i - 1].inverse() * truth[i];
      const Eigen::Isometry3d e = true_step.inverse() * from_T_to;
      t_err.push_back(e.translation().norm());
      r_err.push_back(Degrees(e.linear()));
    }
    const auto mean = [](const std::vector<double>& v) {
      double s = 0.0;
      for (double x : v) s += x;
      return v.empty() ? 0.0 : s / static_cast<double>(v.size());
    };
    std::printf("| %s | %d of 4 | %.1f, %.1f mm | %.2f, %.2f deg | %.1f |\n", method.name, failed, 1000.0 * mean(t_err),
                1000.0 * Percentile(t_err, 1.0), mean(r_err), Percentile(r_err, 1.0), ms_total / 4.0);
  }

  const fs::path tum = data / "slambook2_ch7_tum_pair";
  const Frame a = ReadFrame(tum / "1.png", tum / "1_depth.png", 1.0 / 5000.0);
  const Frame b = ReadFrame(tum / "2.png", tum / "2_depth.png", 1.0 / 5000.0);
  std::printf("\nTUM desk pair (real Kinect v1), 640 x 480: the camera's motion each finds (no truth)\n");
  std::printf("| method | found | translation (m) | rotation (deg) | ms |\n|---|---|---|---|---|\n");
  const cv::Mat k_tum = CameraMatrix(520.9, 521.0, 325.1, 249.7);
  for (const Method& method : Methods()) {
    Eigen::Isometry3d from_T_to = Eigen::Isometry3d::Identity();
    double ms = 0.0;
    const bool ok = Motion(*method.make(k_tum), a, b, from_T_to, ms);
    const Eigen::Vector3d t = from_T_to.translation();
    std::printf("| %s | %s | (%.3f, %.3f, %.3f) | %.2f | %.1f |\n", method.name, ok ? "yes" : "no", t.x(), t.y(), t.z(),
                Degrees(from_T_to.linear()), ms);
  }
}

}  // namespace
}  // namespace corridor

int main(int argc, char** argv) {
  try {
    corridor::Simulated();
    corridor::Recorded(argc > 1 ? argv[1] : std::string(CORRIDOR_SOURCE_DIR) + "/../shared/data/depth_rgbd");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rgbd_odometry: %s\n", e.what());
    return 1;
  }
  return 0;
}
