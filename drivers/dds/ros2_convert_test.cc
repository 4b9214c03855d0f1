// The CDR bytes of the ROS 2 types corridor writes, against bytes worked out by hand from the CDR rules (little
// endian; each primitive aligned to its size from the start of the payload after the 4-byte encapsulation header;
// strings as a uint32 length counting the terminating NUL, then the characters and the NUL; sequences as a uint32
// count then the elements); and the conversions between corridor's types and ROS 2's.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "drivers/dds/participant.h"
#include "drivers/dds/ros2_convert.h"
#include "ros2/diagnostic_msgsPubSubTypes.h"
#include "ros2/geometry_msgsPubSubTypes.h"
#include "ros2/nav_msgsPubSubTypes.h"
#include "ros2/sensor_msgsPubSubTypes.h"
#include "ros2/std_msgsPubSubTypes.h"
#include "ros2/tf2_msgsPubSubTypes.h"

namespace corridor::drivers::dds {
namespace {

// Bytes written by hand: each call appends exactly what it says, no alignment of its own.
class Bytes {
 public:
  Bytes() { raw({0x00, 0x01, 0x00, 0x00}); }  // encapsulation: CDR, little endian; options 0
  Bytes& raw(std::initializer_list<std::uint8_t> b) {
    for (std::uint8_t byte : b)
      bytes_.push_back(byte);  // (insert() of a short list trips GCC 12's -Wstringop-overflow)
    return *this;
  }
  Bytes& pad(int n) {
    bytes_.insert(bytes_.end(), static_cast<std::size_t>(n), 0);
    return *this;
  }
  template <typename T>
  Bytes& le(T v) {
    std::uint8_t b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));  // this machine is little endian, as the encapsulation says
    bytes_.insert(bytes_.end(), b, b + sizeof(T));
    return *this;
  }
  Bytes& str(const std::string& s) {
    le<std::uint32_t>(static_cast<std::uint32_t>(s.size() + 1));
    bytes_.insert(bytes_.end(), s.begin(), s.end());
    bytes_.push_back(0);
    return *this;
  }
  const std::vector<std::uint8_t>& bytes() const { return bytes_; }

 private:
  std::vector<std::uint8_t> bytes_;
};

template <typename PubSubType>
std::vector<std::uint8_t> Serialize(typename PubSubType::type message) {
  PubSubType type;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(type.getSerializedSizeProvider(&message)());
  EXPECT_TRUE(type.serialize(&message, &payload));
  return {payload.data, payload.data + payload.length};
}

template <typename PubSubType>
typename PubSubType::type Deserialize(std::vector<std::uint8_t> bytes) {
  PubSubType type;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(static_cast<std::uint32_t>(bytes.size()));
  std::memcpy(payload.data, bytes.data(), bytes.size());
  payload.length = static_cast<std::uint32_t>(bytes.size());
  typename PubSubType::type message;
  EXPECT_TRUE(type.deserialize(&payload, &message));
  return message;
}

builtin_interfaces::msg::Time Stamp(std::int32_t sec, std::uint32_t nanosec) {
  builtin_interfaces::msg::Time t;
  t.sec(sec);
  t.nanosec(nanosec);
  return t;
}

TEST(Ros2Cdr, TypeNamesAreRos2s) {
  EXPECT_EQ(std::string(geometry_msgs::msg::TwistPubSubType().getName()), "geometry_msgs::msg::dds_::Twist_");
  EXPECT_EQ(std::string(std_msgs::msg::StringPubSubType().getName()), "std_msgs::msg::dds_::String_");
  EXPECT_EQ(std::string(tf2_msgs::msg::TFMessagePubSubType().getName()), "tf2_msgs::msg::dds_::TFMessage_");
  EXPECT_EQ(std::string(sensor_msgs::msg::BatteryStatePubSubType().getName()), "sensor_msgs::msg::dds_::BatteryState_");
  EXPECT_EQ(RosTopic("/cmd_vel"), "rt/cmd_vel");
  EXPECT_EQ(RosTopic("camera/depth/image_raw"), "rt/camera/depth/image_raw");
  EXPECT_THROW(RosTopic("/"), std::invalid_argument);
  EXPECT_THROW(RosTopic("/9lives"), std::invalid_argument);
  EXPECT_THROW(RosTopic("/a//b"), std::invalid_argument);
  EXPECT_THROW(RosTopic("/a b"), std::invalid_argument);
}

TEST(Ros2Cdr, Twist) {
  // Six doubles, all aligned at multiples of 8 from the start.
  const auto expected = Bytes().le(0.5).le(0.0).le(0.0).le(0.0).le(0.0).le(-1.0).bytes();
  EXPECT_EQ(Serialize<geometry_msgs::msg::TwistPubSubType>(ToRos(nav::Twist2{0.5, -1.0})), expected);
  const nav::Twist2 back = FromRos(Deserialize<geometry_msgs::msg::TwistPubSubType>(expected));
  EXPECT_EQ(back.linear_mps, 0.5);
  EXPECT_EQ(back.angular_rps, -1.0);
}

TEST(Ros2Cdr, String) {
  std_msgs::msg::String s;
  s.data("hi");
  EXPECT_EQ(Serialize<std_msgs::msg::StringPubSubType>(s), Bytes().raw({3, 0, 0, 0, 'h', 'i', 0}).bytes());
}

TEST(Ros2Cdr, PoseStamped) {
  geometry_msgs::msg::PoseStamped p;
  p.header(Header(Stamp(1, 2), "map"));
  p.pose(ToRos(nav::Pose2{1.0, 2.0, 0.0}));
  // 0 sec, 4 nanosec, 8 "map" (length 4), 16 position (8-aligned already), 40 orientation x y z w.
  const auto expected = Bytes()
                            .le<std::int32_t>(1)
                            .le<std::uint32_t>(2)
                            .str("map")
                            .le(1.0)
                            .le(2.0)
                            .le(0.0)
                            .le(0.0)
                            .le(0.0)
                            .le(0.0)
                            .le(1.0)
                            .bytes();
  EXPECT_EQ(Serialize<geometry_msgs::msg::PoseStampedPubSubType>(p), expected);
}

TEST(Ros2Cdr, LaserScan) {
  LaserScan scan;
  scan.stamp_ns = 3 * kNsPerSecond + 4;
  scan.angle_min_rad = -0.5;
  scan.angle_increment_rad = 0.25;
  scan.range_min_m = 0.125;
  scan.range_max_m = 8.0;
  scan.ranges = {1.5f, std::numeric_limits<float>::infinity()};
  // 0 sec, 4 nanosec, 8 "laser" (length 6, to 18), 2 bytes to align the floats at 20, seven floats, 48 ranges (2),
  // 60 intensities (0).
  const auto expected = Bytes()
                            .le<std::int32_t>(3)
                            .le<std::uint32_t>(4)
                            .str("laser")
                            .pad(2)
                            .le(-0.5f)
                            .le(-0.25f)
                            .le(0.25f)
                            .le(0.0f)
                            .le(0.0f)
                            .le(0.125f)
                            .le(8.0f)
                            .le<std::uint32_t>(2)
                            .le(1.5f)
                            .le(std::numeric_limits<float>::infinity())
                            .le<std::uint32_t>(0)
                            .bytes();
  EXPECT_EQ(Serialize<sensor_msgs::msg::LaserScanPubSubType>(ToRos(scan, StampClock(0), "laser")), expected);
}

TEST(Ros2Cdr, BatteryState) {
  BatteryState battery;
  battery.stamp_ns = 3 * kNsPerSecond + 4;
  battery.charge = 0.5;
  battery.voltage_v = 12.0;
  battery.current_a = -1.5;
  // 0 sec, 4 nanosec, 8 "base_link" (length 10, to 22), 2 bytes to align the floats at 24, seven floats (what is not
  // known NaN), at 52 the status (2: discharging), health, technology and present, at 56 two empty sequences, at 64
  // location "", 3 bytes to align, at 72 serial_number "".
  constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
  const auto expected = Bytes()
                            .le<std::int32_t>(3)
                            .le<std::uint32_t>(4)
                            .str("base_link")
                            .pad(2)
                            .le(12.0f)
                            .le(kNaN)
                            .le(-1.5f)
                            .le(kNaN)
                            .le(kNaN)
                            .le(kNaN)
                            .le(0.5f)
                            .raw({2, 0, 0, 1})
                            .le<std::uint32_t>(0)
                            .le<std::uint32_t>(0)
                            .str("")
                            .pad(3)
                            .str("")
                            .bytes();
  EXPECT_EQ(Serialize<sensor_msgs::msg::BatteryStatePubSubType>(ToRos(battery, StampClock(0))), expected);
}

TEST(Ros2Cdr, OccupancyGrid) {
  nav_msgs::msg::OccupancyGrid grid;
  grid.header(Header(Stamp(5, 6), "map"));
  grid.info().map_load_time(Stamp(7, 8));
  grid.info().resolution(0.05f);
  grid.info().width(2);
  grid.info().height(1);
  grid.info().origin(ToRos(nav::Pose2{-1.0, -2.0, 0.0}));
  grid.data({-1, 100});
  // 0 header (to 16), 16 map_load_time, 24 resolution, 28 width, 32 height, 4 bytes to align the origin's doubles at
  // 40, 96 data (2 bytes).
  const auto expected = Bytes()
                            .le<std::int32_t>(5)
                            .le<std::uint32_t>(6)
                            .str("map")
                            .le<std::int32_t>(7)
                            .le<std::uint32_t>(8)
                            .le(0.05f)
                            .le<std::uint32_t>(2)
                            .le<std::uint32_t>(1)
                            .pad(4)
                            .le(-1.0)
                            .le(-2.0)
                            .le(0.0)
                            .le(0.0)
                            .le(0.0)
                            .le(0.0)
                            .le(1.0)
                            .le<std::uint32_t>(2)
                            .raw({0xff, 100})
                            .bytes();
  EXPECT_EQ(Serialize<nav_msgs::msg::OccupancyGridPubSubType>(grid), expected);
}

TEST(Ros2Cdr, TFMessage) {
  tf2_msgs::msg::TFMessage tf;
  tf.transforms().push_back(Transform(Stamp(9, 10), "odom", "base_link", nav::Pose2{3.0, 4.0, 0.0}.ToIsometry3()));
  // 0 count 1, 4 sec, 8 nanosec, 12 "odom" (length 5, to 21), 3 bytes to align child_frame_id at 24, "base_link"
  // (length 10, to 38), 2 bytes to align the translation's doubles at 40, rotation at 64.
  const auto expected = Bytes()
                            .le<std::uint32_t>(1)
                            .le<std::int32_t>(9)
                            .le<std::uint32_t>(10)
                            .str("odom")
                            .pad(3)
                            .str("base_link")
                            .pad(2)
                            .le(3.0)
                            .le(4.0)
                            .le(0.0)
                            .le(0.0)
                            .le(0.0)
                            .le(0.0)
                            .le(1.0)
                            .bytes();
  EXPECT_EQ(Serialize<tf2_msgs::msg::TFMessagePubSubType>(tf), expected);
}

TEST(Ros2Cdr, Image) {
  cv::Mat depth(1, 2, CV_16UC1);
  depth.at<std::uint16_t>(0, 0) = 1000;
  depth.at<std::uint16_t>(0, 1) = 0x0102;
  // 0 header "cam" (to 16), 16 height, 20 width, 24 "16UC1" (length 6, to 34), 34 is_bigendian, 1 byte to align
  // step at 36, 40 data (4 bytes).
  const auto expected = Bytes()
                            .le<std::int32_t>(11)
                            .le<std::uint32_t>(12)
                            .str("cam")
                            .le<std::uint32_t>(1)
                            .le<std::uint32_t>(2)
                            .str("16UC1")
                            .raw({0})
                            .pad(1)
                            .le<std::uint32_t>(4)
                            .le<std::uint32_t>(4)
                            .raw({0xe8, 0x03, 0x02, 0x01})
                            .bytes();
  const auto bytes = Serialize<sensor_msgs::msg::ImagePubSubType>(DepthImage(depth, Stamp(11, 12), "cam"));
  EXPECT_EQ(bytes, expected);
  const cv::Mat back = DepthFromRos(Deserialize<sensor_msgs::msg::ImagePubSubType>(bytes));
  EXPECT_EQ(cv::countNonZero(back != depth), 0);
}

TEST(Ros2Cdr, Odometry) {
  WheelOdometry odometry;
  odometry.stamp_ns = 13 * kNsPerSecond + 14;
  odometry.odom_T_base = {1.0, 2.0, 0.0};
  odometry.velocity = {0.5, 0.25};
  // 0 header "odom" (to 17), 3 bytes to align child_frame_id at 20, "base_link" (to 34), 6 bytes to align the pose's
  // doubles at 40, 96 its covariance (36 doubles: z, roll and pitch 1e6), 384 the twist, 432 its covariance; 720 bytes.
  Bytes b;
  b.le<std::int32_t>(13).le<std::uint32_t>(14).str("odom").pad(3).str("base_link").pad(6);
  b.le(1.0).le(2.0).le(0.0).le(0.0).le(0.0).le(0.0).le(1.0);
  for (int i = 0; i < 36; ++i) b.le(i == 14 || i == 21 || i == 28 ? 1e6 : 0.0);
  b.le(0.5).le(0.0).le(0.0).le(0.0).le(0.0).le(0.25);
  for (int i = 0; i < 36; ++i) b.le(i == 14 || i == 21 || i == 28 ? 1e6 : 0.0);
  EXPECT_EQ(Serialize<nav_msgs::msg::OdometryPubSubType>(ToRos(odometry, StampClock(0))), b.bytes());
  const WheelOdometry back = FromRos(Deserialize<nav_msgs::msg::OdometryPubSubType>(b.bytes()), StampClock(0));
  EXPECT_EQ(back.stamp_ns, odometry.stamp_ns);
  EXPECT_EQ(back.odom_T_base.y_m, 2.0);
  EXPECT_EQ(back.velocity.angular_rps, 0.25);
}

TEST(Ros2Cdr, PathAndPoseWithCovariance) {
  nav_msgs::msg::Path path;
  path.header(Header(Stamp(1, 2), "map"));
  geometry_msgs::msg::PoseStamped p;
  p.header(Header(Stamp(3, 4), "map"));
  p.pose(ToRos(nav::Pose2{5.0, 6.0, 0.0}));
  path.poses().push_back(p);
  // 0 header (to 16), 16 count 1, 20 the pose's header (sec, nanosec, "map" to 36), 4 bytes to align its doubles at 40.
  EXPECT_EQ(Serialize<nav_msgs::msg::PathPubSubType>(path), Bytes()
                                                                .le<std::int32_t>(1)
                                                                .le<std::uint32_t>(2)
                                                                .str("map")
                                                                .le<std::uint32_t>(1)
                                                                .le<std::int32_t>(3)
                                                                .le<std::uint32_t>(4)
                                                                .str("map")
                                                                .pad(4)
                                                                .le(5.0)
                                                                .le(6.0)
                                                                .le(0.0)
                                                                .le(0.0)
                                                                .le(0.0)
                                                                .le(0.0)
                                                                .le(1.0)
                                                                .bytes());
  geometry_msgs::msg::PoseWithCovarianceStamped estimate;
  estimate.header(Header(Stamp(7, 8), "map"));
  estimate.pose().pose(ToRos(nav::Pose2{}));
  estimate.pose().covariance()[35] = 0.5;
  // 0 header (to 16, already aligned for doubles), 16 the pose, 72 the covariance; yaw's variance last.
  Bytes b;
  b.le<std::int32_t>(7).le<std::uint32_t>(8).str("map");
  b.le(0.0).le(0.0).le(0.0).le(0.0).le(0.0).le(0.0).le(1.0);
  for (int i = 0; i < 36; ++i) b.le(i == 35 ? 0.5 : 0.0);
  EXPECT_EQ(Serialize<geometry_msgs::msg::PoseWithCovarianceStampedPubSubType>(estimate), b.bytes());
}

nav::PinholeCamera Pinhole(int width, int height, double fx, double fy, double cx, double cy) {
  nav::PinholeCamera camera;
  camera.width = width;
  camera.height = height;
  camera.fx = fx;
  camera.fy = fy;
  camera.cx = cx;
  camera.cy = cy;
  return camera;
}

TEST(Ros2Cdr, CameraInfo) {
  const nav::PinholeCamera camera = Pinhole(4, 3, 2.0, 2.5, 1.5, 1.0);
  // 0 header "cam" (to 16), 16 height, 20 width, 24 "plumb_bob" (length 10, to 38), 2 bytes to align d's count at 40,
  // 4 bytes to align its doubles at 48, 88 k, 160 r, 232 p, 328 binning, 336 the region of interest (to 353).
  Bytes b;
  b.le<std::int32_t>(0).le<std::uint32_t>(9).str("cam").le<std::uint32_t>(3).le<std::uint32_t>(4).str("plumb_bob");
  b.pad(2).le<std::uint32_t>(5).pad(4);
  for (int i = 0; i < 5; ++i) b.le(0.0);
  for (double v : {2.0, 0.0, 1.5, 0.0, 2.5, 1.0, 0.0, 0.0, 1.0}) b.le(v);
  for (double v : {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0}) b.le(v);
  for (double v : {2.0, 0.0, 1.5, 0.0, 0.0, 2.5, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0}) b.le(v);
  b.le<std::uint32_t>(0).le<std::uint32_t>(0);
  b.le<std::uint32_t>(0).le<std::uint32_t>(0).le<std::uint32_t>(0).le<std::uint32_t>(0).raw({0});
  EXPECT_EQ(Serialize<sensor_msgs::msg::CameraInfoPubSubType>(ToRos(camera, Stamp(0, 9), "cam")), b.bytes());
}

TEST(Ros2Cdr, DiagnosticArray) {
  diagnostic_msgs::msg::DiagnosticArray array;
  array.header(Header(Stamp(0, 0), ""));
  diagnostic_msgs::msg::DiagnosticStatus status;
  status.level(2);
  status.name("n");
  status.message("m");
  status.hardware_id("h");
  diagnostic_msgs::msg::KeyValue kv;
  kv.key("k");
  kv.value("v");
  status.values().push_back(kv);
  array.status().push_back(status);
  // 0 sec, 4 nanosec, 8 "" (length 1, to 13), 3 bytes to align the count at 16, 20 level, then each string aligned to
  // 4: name at 24, message at 32, hardware_id at 40, 48 the values' count, key at 52, value at 60 (to 66).
  EXPECT_EQ(Serialize<diagnostic_msgs::msg::DiagnosticArrayPubSubType>(array), Bytes()
                                                                                   .le<std::int32_t>(0)
                                                                                   .le<std::uint32_t>(0)
                                                                                   .str("")
                                                                                   .pad(3)
                                                                                   .le<std::uint32_t>(1)
                                                                                   .raw({2})
                                                                                   .pad(3)
                                                                                   .str("n")
                                                                                   .pad(2)
                                                                                   .str("m")
                                                                                   .pad(2)
                                                                                   .str("h")
                                                                                   .pad(2)
                                                                                   .le<std::uint32_t>(1)
                                                                                   .str("k")
                                                                                   .pad(2)
                                                                                   .str("v")
                                                                                   .bytes());
}

TEST(Ros2Convert, PosesAndYaw) {
  for (double yaw : {0.0, 1.0, -2.5, 3.1}) {
    const nav::Pose2 back = FromRos(ToRos(nav::Pose2{1.0, -2.0, yaw}));
    EXPECT_NEAR(back.yaw_rad, yaw, 1e-12);
    EXPECT_EQ(back.x_m, 1.0);
  }
  // An unnormalised quaternion is a rotation all the same (RViz sends normalised ones; hand-written ones may not be).
  geometry_msgs::msg::Quaternion q = YawQuaternion(0.7);
  q.z(q.z() * 3.0);
  q.w(q.w() * 3.0);
  EXPECT_NEAR(YawOf(q), 0.7, 1e-12);
  EXPECT_THROW(YawOf(geometry_msgs::msg::Quaternion()), std::invalid_argument);  // all zero
  geometry_msgs::msg::Pose bad = ToRos(nav::Pose2{});
  bad.position().x(std::nan(""));
  EXPECT_THROW(FromRos(bad), std::invalid_argument);
  geometry_msgs::msg::Twist fast;
  fast.linear().x(std::numeric_limits<double>::infinity());
  EXPECT_THROW(FromRos(fast), std::invalid_argument);
}

TEST(Ros2Convert, StampsShiftByTheClocksOffset) {
  const StampClock stamps(1'700'000'000LL * kNsPerSecond);
  const auto t = stamps.ToRos(2 * kNsPerSecond + 5);
  EXPECT_EQ(t.sec(), 1'700'000'002);
  EXPECT_EQ(t.nanosec(), 5u);
  EXPECT_EQ(stamps.FromRos(t), 2 * kNsPerSecond + 5);
}

TEST(Ros2Convert, ScansFromRosFollowRep117) {
  sensor_msgs::msg::LaserScan s;
  s.angle_min(-1.0f);
  s.angle_increment(0.5f);
  s.range_min(0.1f);
  s.range_max(10.0f);
  s.ranges({2.0f, std::nanf(""), 0.05f, 20.0f, std::numeric_limits<float>::infinity()});
  const LaserScan scan = FromRos(s, StampClock(0));
  ASSERT_EQ(scan.ranges.size(), 5u);
  EXPECT_EQ(scan.ranges[0], 2.0f);
  for (std::size_t i = 1; i < 5; ++i) EXPECT_TRUE(std::isinf(scan.ranges[i])) << i;
  s.angle_increment(0.0f);
  EXPECT_THROW(FromRos(s, StampClock(0)), std::invalid_argument);
}

// A laser driver's time_increment: beam i measured i increments after the stamp, a turn of 2 pi / angle_increment
// beams; corridor's scan ends half an increment after the last beam, and each beam's age says when it was measured.
TEST(Ros2Convert, AScansTimeIncrementIsItsSweep) {
  sensor_msgs::msg::LaserScan s;
  s.header().stamp(Stamp(2, 0));
  s.angle_min(static_cast<float>(-M_PI));
  s.angle_increment(static_cast<float>(2 * M_PI / 360));
  s.range_min(0.1f);
  s.range_max(10.0f);
  s.time_increment(0.1f / 360);
  s.ranges(std::vector<float>(360, 2.0f));
  const LaserScan scan = FromRos(s, StampClock(0));
  EXPECT_NEAR(scan.sweep_s, 0.1, 1e-6);
  EXPECT_FALSE(scan.sweep_clockwise);
  EXPECT_NEAR(ToSeconds(scan.stamp_ns), 2.0 + 359.5 * 0.1 / 360, 1e-6);  // half a beam after the last
  for (const std::size_t i : {std::size_t{0}, std::size_t{90}, std::size_t{359}}) {
    EXPECT_NEAR(ToSeconds(scan.stamp_ns) - BeamAgeS(scan, i), 2.0 + i * 0.1 / 360, 1e-6) << i;
  }
  // Counting clockwise (a negative increment): the same, turning the other way.
  s.angle_min(static_cast<float>(M_PI));
  s.angle_increment(static_cast<float>(-2 * M_PI / 360));
  const LaserScan clockwise = FromRos(s, StampClock(0));
  EXPECT_TRUE(clockwise.sweep_clockwise);
  EXPECT_NEAR(ToSeconds(clockwise.stamp_ns) - BeamAgeS(clockwise, 90), 2.0 + 90 * 0.1 / 360, 1e-6);
  // No time increment: every beam at the stamp, as before.
  s.time_increment(0.0f);
  EXPECT_EQ(FromRos(s, StampClock(0)).sweep_s, 0.0);
  EXPECT_EQ(FromRos(s, StampClock(0)).stamp_ns, 2 * kNsPerSecond);
}

// A base driver's BatteryState: the charge from the percentage (0-1, or 0-100 from drivers that send that), charging
// and on the charger from the status; a percentage that is not a number is refused.
TEST(Ros2Convert, TheBatteryFromABaseDriver) {
  sensor_msgs::msg::BatteryState b;
  b.header().stamp(Stamp(5, 0));
  b.percentage(0.42f);
  b.voltage(12.1f);
  b.current(std::nanf(""));
  b.power_supply_status(2);
  BatteryState battery = FromRos(b, StampClock(0));
  EXPECT_NEAR(battery.charge, 0.42, 1e-6);
  EXPECT_NEAR(battery.voltage_v, 12.1, 1e-6);
  EXPECT_EQ(battery.current_a, 0.0);
  EXPECT_FALSE(battery.charging);
  EXPECT_FALSE(battery.on_charger);
  EXPECT_EQ(battery.stamp_ns, 5 * kNsPerSecond);
  b.percentage(87.0f);
  b.power_supply_status(1);
  battery = FromRos(b, StampClock(0));
  EXPECT_NEAR(battery.charge, 0.87, 1e-6);
  EXPECT_TRUE(battery.charging);
  EXPECT_TRUE(battery.on_charger);
  b.power_supply_status(4);
  EXPECT_TRUE(FromRos(b, StampClock(0)).on_charger);
  EXPECT_FALSE(FromRos(b, StampClock(0)).charging);
  for (const float bad : {std::nanf(""), -0.1f, 101.0f}) {
    b.percentage(bad);
    EXPECT_THROW(FromRos(b, StampClock(0)), std::invalid_argument) << bad;
  }
  // Back: full on the dock is status 4, charging 1.
  BatteryState docked;
  docked.charge = 1.0;
  docked.on_charger = true;
  EXPECT_EQ(ToRos(docked, StampClock(0)).power_supply_status(), 4);
  docked.charging = true;
  EXPECT_EQ(ToRos(docked, StampClock(0)).power_supply_status(), 1);
}

TEST(Ros2Convert, DepthImagesIn16UC1Or32FC1) {
  sensor_msgs::msg::Image metres;
  metres.height(1);
  metres.width(3);
  metres.encoding("32FC1");
  metres.step(12);
  const float values[3] = {1.5f, std::nanf(""), -1.0f};
  metres.data(std::vector<std::uint8_t>(reinterpret_cast<const std::uint8_t*>(values),
                                        reinterpret_cast<const std::uint8_t*>(values) + 12));
  const cv::Mat mm = DepthFromRos(metres);
  EXPECT_EQ(mm.type(), CV_16UC1);
  EXPECT_EQ(mm.at<std::uint16_t>(0, 0), 1500);
  EXPECT_EQ(mm.at<std::uint16_t>(0, 1), 0);  // no measurement
  EXPECT_EQ(mm.at<std::uint16_t>(0, 2), 0);
  metres.data().resize(8);  // shorter than step * height
  EXPECT_THROW(DepthFromRos(metres), std::invalid_argument);
  metres.encoding("rgb8");
  EXPECT_THROW(DepthFromRos(metres), std::invalid_argument);
}

TEST(Ros2Convert, CameraInfoRoundTrip) {
  const nav::PinholeCamera camera = Pinhole(640, 480, 525.0, 526.0, 319.5, 239.5);
  const nav::PinholeCamera back = FromRos(ToRos(camera, Stamp(0, 0), "cam"), Eigen::Isometry3d::Identity());
  EXPECT_EQ(back.width, 640);
  EXPECT_EQ(back.fy, 526.0);
  EXPECT_EQ(back.cx, 319.5);
  EXPECT_THROW(FromRos(sensor_msgs::msg::CameraInfo(), Eigen::Isometry3d::Identity()), std::invalid_argument);
}

TEST(Ros2Convert, ScanFromPointsKeepsTheNearestPerBearing) {
  const std::vector<Eigen::Vector2d> points = {{2.0, 0.0}, {1.0, 0.0}, {1.0, 1.0}, {30.0, 0.1}};
  const auto scan = ScanFromPoints(points, 0.1, 0.2, 10.0, Stamp(0, 0), "base_link");
  EXPECT_NEAR(scan.angle_min(), 0.0, 1e-6);
  ASSERT_EQ(scan.ranges().size(), 8u);  // 0 .. pi/4 in steps of 0.1
  EXPECT_EQ(scan.ranges()[0], 1.0f);    // the nearer of the two ahead; the one 30 m off is beyond range
  EXPECT_NEAR(scan.ranges()[7], std::sqrt(2.0), 1e-6);
  EXPECT_TRUE(std::isinf(scan.ranges()[3]));
}

}  // namespace
}  // namespace corridor::drivers::dds
