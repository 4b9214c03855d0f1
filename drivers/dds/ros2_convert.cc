#include "drivers/dds/ros2_convert.h"

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace corridor::drivers::dds {
namespace {

bool Finite(std::initializer_list<double> values) {
  for (double v : values) {
    if (!std::isfinite(v)) return false;
  }
  return true;
}

}  // namespace

StampClock StampClock::For(const Clock& clock) {
  const TimeNs system =
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
  return StampClock(system - clock.Now());
}

builtin_interfaces::msg::Time StampClock::ToRos(TimeNs t) const {
  const TimeNs ns = std::max<TimeNs>(0, t + offset_ns_);
  builtin_interfaces::msg::Time stamp;
  stamp.sec(static_cast<std::int32_t>(ns / kNsPerSecond));
  stamp.nanosec(static_cast<std::uint32_t>(ns % kNsPerSecond));
  return stamp;
}

TimeNs StampClock::FromRos(const builtin_interfaces::msg::Time& stamp) const {
  return static_cast<TimeNs>(stamp.sec()) * kNsPerSecond + stamp.nanosec() - offset_ns_;
}

std_msgs::msg::Header Header(const builtin_interfaces::msg::Time& stamp, const std::string& frame) {
  std_msgs::msg::Header header;
  header.stamp(stamp);
  header.frame_id(frame);
  return header;
}

geometry_msgs::msg::Quaternion YawQuaternion(double yaw_rad) {
  geometry_msgs::msg::Quaternion q;
  q.x(0.0);
  q.y(0.0);
  q.z(std::sin(yaw_rad / 2.0));
  q.w(std::cos(yaw_rad / 2.0));
  return q;
}

double YawOf(const geometry_msgs::msg::Quaternion& q) {
  const double norm2 = q.x() * q.x() + q.y() * q.y() + q.z() * q.z() + q.w() * q.w();
  if (!Finite({q.x(), q.y(), q.z(), q.w()}) || norm2 < 1e-12) {
    throw std::invalid_argument("the orientation is not a rotation (zero or not finite quaternion)");
  }
  // This form needs no normalised quaternion: both arguments scale with its squared norm.
  return std::atan2(2.0 * (q.w() * q.z() + q.x() * q.y()),
                    q.w() * q.w() + q.x() * q.x() - q.y() * q.y() - q.z() * q.z());
}

geometry_msgs::msg::Pose ToRos(const nav::Pose2& pose) {
  geometry_msgs::msg::Pose p;
  p.position().x(pose.x_m);
  p.position().y(pose.y_m);
  p.position().z(0.0);
  p.orientation(YawQuaternion(pose.yaw_rad));
  return p;
}

nav::Pose2 FromRos(const geometry_msgs::msg::Pose& pose) {
  if (!Finite({pose.position().x(), pose.position().y()})) {
    throw std::invalid_argument("the position is not finite");
  }
  return {pose.position().x(), pose.position().y(), YawOf(pose.orientation())};
}

geometry_msgs::msg::Transform ToTransform(const Eigen::Isometry3d& t) {
  geometry_msgs::msg::Transform out;
  out.translation().x(t.translation().x());
  out.translation().y(t.translation().y());
  out.translation().z(t.translation().z());
  const Eigen::Quaterniond q(t.linear());
  out.rotation().x(q.x());
  out.rotation().y(q.y());
  out.rotation().z(q.z());
  out.rotation().w(q.w());
  return out;
}

geometry_msgs::msg::TransformStamped Transform(const builtin_interfaces::msg::Time& stamp, const std::string& parent,
                                               const std::string& child, const Eigen::Isometry3d& parent_T_child) {
  geometry_msgs::msg::TransformStamped t;
  t.header(Header(stamp, parent));
  t.child_frame_id(child);
  t.transform(ToTransform(parent_T_child));
  return t;
}

geometry_msgs::msg::Twist ToRos(const nav::Twist2& twist) {
  geometry_msgs::msg::Twist t;
  t.linear().x(twist.linear_mps);
  t.angular().z(twist.angular_rps);
  return t;
}

nav::Twist2 FromRos(const geometry_msgs::msg::Twist& twist) {
  if (!Finite({twist.linear().x(), twist.angular().z()})) throw std::invalid_argument("the twist is not finite");
  return {twist.linear().x(), twist.angular().z()};
}

nav_msgs::msg::Odometry ToRos(const WheelOdometry& odometry, const StampClock& clock) {
  nav_msgs::msg::Odometry o;
  o.header(Header(clock.ToRos(odometry.stamp_ns), kOdomFrame));
  o.child_frame_id(kBaseFrame);
  o.pose().pose(ToRos(odometry.odom_T_base));
  o.twist().twist(ToRos(odometry.velocity));
  // Wheel odometry knows nothing of z, roll and pitch (held at zero): a large variance there, as diff-drive
  // controllers report; x, y and yaw drift and are not estimated here (0: unknown).
  for (int i : {14, 21, 28}) {
    o.pose().covariance()[static_cast<std::size_t>(i)] = 1e6;
    o.twist().covariance()[static_cast<std::size_t>(i)] = 1e6;
  }
  return o;
}

WheelOdometry FromRos(const nav_msgs::msg::Odometry& odometry, const StampClock& clock) {
  WheelOdometry o;
  o.stamp_ns = clock.FromRos(odometry.header().stamp());
  o.odom_T_base = FromRos(odometry.pose().pose());
  o.velocity = FromRos(odometry.twist().twist());
  return o;
}

sensor_msgs::msg::LaserScan ToRos(const LaserScan& scan, const StampClock& clock, const std::string& frame) {
  sensor_msgs::msg::LaserScan s;
  s.header(Header(clock.ToRos(scan.stamp_ns), frame));
  s.angle_min(static_cast<float>(scan.angle_min_rad));
  const std::size_t n = scan.ranges.size();
  s.angle_max(
      static_cast<float>(scan.angle_min_rad + scan.angle_increment_rad * static_cast<double>(n == 0 ? 0 : n - 1)));
  s.angle_increment(static_cast<float>(scan.angle_increment_rad));
  s.range_min(static_cast<float>(scan.range_min_m));
  s.range_max(static_cast<float>(scan.range_max_m));
  s.scan_time(static_cast<float>(scan.sweep_s));
  s.ranges(scan.ranges);
  return s;
}

LaserScan FromRos(const sensor_msgs::msg::LaserScan& scan, const StampClock& clock) {
  if (!Finite({scan.angle_min(), scan.angle_increment(), scan.range_min(), scan.range_max()}) ||
      scan.angle_increment() == 0.0f || scan.range_max() <= 0.0f || scan.range_min() < 0.0f) {
    throw std::invalid_argument("the scan's angles or range limits are not usable");
  }
  LaserScan s;
  s.stamp_ns = clock.FromRos(scan.header().stamp());
  s.angle_min_rad = scan.angle_min();
  s.angle_increment_rad = scan.angle_increment();
  s.range_min_m = scan.range_min();
  s.range_max_m = scan.range_max();
  s.ranges.reserve(scan.ranges().size());
  for (float r : scan.ranges()) {
    // REP 117: NaN is an error reading, +inf nothing in range; below range_min is no reading either.
    const bool hit = std::isfinite(r) && r >= scan.range_min() && r <= scan.range_max();
    s.ranges.push_back(hit ? r : std::numeric_limits<float>::infinity());
  }
  // Beam i at the stamp plus i time increments: a turn of 2 pi / |increment| of them, in the increment's direction,
  // taken to end half an increment after the last beam (no beam where LaserScan's sweep begins and ends).
  const double dt = scan.time_increment();
  const double n = static_cast<double>(s.ranges.size());
  const double turn_s = std::isfinite(dt) ? dt * 2.0 * std::numbers::pi / std::abs(s.angle_increment_rad) : 0.0;
  if (dt > 0.0 && s.ranges.size() > 1 && turn_s < 1.0) {
    s.sweep_s = turn_s;
    s.sweep_clockwise = s.angle_increment_rad < 0.0;
    s.sweep_start_rad = s.angle_min_rad + (n - 0.5) * s.angle_increment_rad;
    s.stamp_ns += static_cast<TimeNs>((n - 0.5) * dt * 1e9);
  }
  return s;
}

sensor_msgs::msg::BatteryState ToRos(const BatteryState& battery, const StampClock& clock) {
  constexpr float kUnknown = std::numeric_limits<float>::quiet_NaN();
  constexpr std::uint8_t kCharging = 1, kDischarging = 2, kFull = 4;
  sensor_msgs::msg::BatteryState b;
  b.header(Header(clock.ToRos(battery.stamp_ns), kBaseFrame));
  b.voltage(static_cast<float>(battery.voltage_v));
  b.temperature(kUnknown);
  b.current(static_cast<float>(battery.current_a));
  b.charge(kUnknown);
  b.capacity(kUnknown);
  b.design_capacity(kUnknown);
  b.percentage(static_cast<float>(battery.charge));
  b.power_supply_status(battery.charging ? kCharging : battery.on_charger ? kFull : kDischarging);
  b.present(true);
  return b;
}

BatteryState FromRos(const sensor_msgs::msg::BatteryState& battery, const StampClock& clock) {
  constexpr std::uint8_t kCharging = 1, kFull = 4;
  const double percentage = battery.percentage();
  if (!std::isfinite(percentage) || percentage < 0.0 || percentage > 100.0) {
    throw std::invalid_argument("the battery's percentage is not a number from 0 to 1 (or 100)");
  }
  BatteryState b;
  b.stamp_ns = clock.FromRos(battery.header().stamp());
  b.charge = percentage > 1.0 ? percentage / 100.0 : percentage;
  b.voltage_v = std::isfinite(battery.voltage()) ? battery.voltage() : 0.0;
  b.current_a = std::isfinite(battery.current()) ? battery.current() : 0.0;
  b.charging = battery.power_supply_status() == kCharging;
  b.on_charger = b.charging || battery.power_supply_status() == kFull;
  return b;
}

sensor_msgs::msg::LaserScan ScanFromPoints(const std::vector<Eigen::Vector2d>& points, double increment_rad,
                                           double range_min_m, double range_max_m,
                                           const builtin_interfaces::msg::Time& stamp, const std::string& frame) {
  sensor_msgs::msg::LaserScan s;
  s.header(Header(stamp, frame));
  s.range_min(static_cast<float>(range_min_m));
  s.range_max(static_cast<float>(range_max_m));
  s.angle_increment(static_cast<float>(increment_rad));
  if (points.empty()) return s;
  double lo = std::numeric_limits<double>::infinity();
  double hi = -lo;
  for (const Eigen::Vector2d& p : points) {
    const double a = std::atan2(p.y(), p.x());
    lo = std::min(lo, a);
    hi = std::max(hi, a);
  }
  const auto bins = static_cast<std::size_t>(std::floor((hi - lo) / increment_rad)) + 1;
  std::vector<float> ranges(bins, std::numeric_limits<float>::infinity());
  for (const Eigen::Vector2d& p : points) {
    const double r = p.norm();
    if (r < range_min_m || r > range_max_m) continue;
    const auto bin = std::min(bins - 1, static_cast<std::size_t>((std::atan2(p.y(), p.x()) - lo) / increment_rad));
    ranges[bin] = std::min(ranges[bin], static_cast<float>(r));
  }
  s.angle_min(static_cast<float>(lo));
  s.angle_max(static_cast<float>(lo + increment_rad * static_cast<double>(bins - 1)));
  s.ranges(std::move(ranges));
  return s;
}

sensor_msgs::msg::Image DepthImage(const cv::Mat& depth_mm, const builtin_interfaces::msg::Time& stamp,
                                   const std::string& frame) {
  sensor_msgs::msg::Image image;
  image.header(Header(stamp, frame));
  image.height(static_cast<std::uint32_t>(depth_mm.rows));
  image.width(static_cast<std::uint32_t>(depth_mm.cols));
  image.encoding("16UC1");
  image.is_bigendian(0);
  image.step(static_cast<std::uint32_t>(depth_mm.cols * 2));
  std::vector<std::uint8_t>& data = image.data();
  data.resize(static_cast<std::size_t>(depth_mm.rows) * depth_mm.cols * 2);
  for (int r = 0; r < depth_mm.rows; ++r) {
    std::memcpy(data.data() + static_cast<std::size_t>(r) * depth_mm.cols * 2, depth_mm.ptr(r),
                static_cast<std::size_t>(depth_mm.cols) * 2);
  }
  return image;
}

namespace {

// The image's rows as a matrix of `type` over its data (not copied); checks the size.
cv::Mat View(const sensor_msgs::msg::Image& image, int type, std::size_t pixel_bytes) {
  if (image.is_bigendian() != 0) throw std::invalid_argument("big-endian images are not supported");
  if (image.width() == 0 || image.height() == 0 || image.step() < image.width() * pixel_bytes ||
      image.data().size() < static_cast<std::size_t>(image.step()) * image.height()) {
    throw std::invalid_argument("the image's size, step and data do not agree");
  }
  return cv::Mat(static_cast<int>(image.height()), static_cast<int>(image.width()), type,
                 const_cast<std::uint8_t*>(image.data().data()), image.step());
}

}  // namespace

cv::Mat DepthFromRos(const sensor_msgs::msg::Image& image) {
  if (image.encoding() == "16UC1" || image.encoding() == "mono16") return View(image, CV_16UC1, 2).clone();
  if (image.encoding() == "32FC1") {
    const cv::Mat metres = View(image, CV_32FC1, 4);
    cv::Mat mm(metres.size(), CV_16UC1);
    for (int r = 0; r < metres.rows; ++r) {
      const float* in = metres.ptr<float>(r);
      auto* out = mm.ptr<std::uint16_t>(r);
      for (int c = 0; c < metres.cols; ++c) {
        const float m = in[c];
        out[c] = std::isfinite(m) && m > 0.0f && m < 65.535f ? static_cast<std::uint16_t>(std::lround(m * 1000.0f)) : 0;
      }
    }
    return mm;
  }
  throw std::invalid_argument("depth images must be 16UC1 (mm) or 32FC1 (m), not '" + image.encoding() + "'");
}

cv::Mat ColorFromRos(const sensor_msgs::msg::Image& image) {
  if (image.encoding() == "bgr8") return View(image, CV_8UC3, 3).clone();
  if (image.encoding() == "rgb8") {
    cv::Mat bgr = View(image, CV_8UC3, 3).clone();
    for (int r = 0; r < bgr.rows; ++r) {
      auto* p = bgr.ptr<cv::Vec3b>(r);
      for (int c = 0; c < bgr.cols; ++c) std::swap(p[c][0], p[c][2]);
    }
    return bgr;
  }
  throw std::invalid_argument("colour images must be bgr8 or rgb8, not '" + image.encoding() + "'");
}

sensor_msgs::msg::CameraInfo ToRos(const nav::PinholeCamera& camera, const builtin_interfaces::msg::Time& stamp,
                                   const std::string& frame) {
  sensor_msgs::msg::CameraInfo info;
  info.header(Header(stamp, frame));
  info.width(static_cast<std::uint32_t>(camera.width));
  info.height(static_cast<std::uint32_t>(camera.height));
  info.distortion_model("plumb_bob");
  info.d({0.0, 0.0, 0.0, 0.0, 0.0});
  info.k({camera.fx, 0.0, camera.cx, 0.0, camera.fy, camera.cy, 0.0, 0.0, 1.0});
  info.r({1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0});
  info.p({camera.fx, 0.0, camera.cx, 0.0, 0.0, camera.fy, camera.cy, 0.0, 0.0, 0.0, 1.0, 0.0});
  return info;
}

nav::PinholeCamera FromRos(const sensor_msgs::msg::CameraInfo& info, const Eigen::Isometry3d& base_T_camera) {
  nav::PinholeCamera camera;
  camera.width = static_cast<int>(info.width());
  camera.height = static_cast<int>(info.height());
  camera.fx = info.k()[0];
  camera.fy = info.k()[4];
  camera.cx = info.k()[2];
  camera.cy = info.k()[5];
  camera.base_T_camera = base_T_camera;
  if (!camera.Valid() || !Finite({camera.fx, camera.fy, camera.cx, camera.cy}) || camera.width > 8192 ||
      camera.height > 8192) {
    throw std::invalid_argument("the camera info's size or focal lengths cannot be used");
  }
  return camera;
}

}  // namespace corridor::drivers::dds
