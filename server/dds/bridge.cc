#include "server/dds/bridge.h"

#include <spdlog/spdlog.h>

#include <cmath>
#include <limits>
#include <variant>

#include "server/runtime/topics.h"

namespace corridor::server {
namespace {

namespace dds = drivers::dds;
using drivers::dds::Qos;

constexpr double kBridgeRateHz = 2.0;       // the state's rate; diagnostics every other tick (1 Hz, as ROS does)
constexpr double kMapOdomToleranceS = 0.5;  // map -> odom is dated this far ahead (AMCL's transform_tolerance)
constexpr double kMapOdomPeriodS = 0.1;     // and sent at most this often (it changes only with localization)
constexpr double kDepthScanIncrementRad = 0.5 * M_PI / 180.0;

std::uint8_t DiagnosticLevel(const std::string& health) {
  if (health == "ok") return 0;
  if (health == "degraded") return 1;
  if (health == "error") return 2;
  return 3;  // inactive: stale
}

tf2_msgs::msg::TFMessage OneTransform(geometry_msgs::msg::TransformStamped t) {
  tf2_msgs::msg::TFMessage message;
  message.transforms().push_back(std::move(t));
  return message;
}

}  // namespace

std::unique_ptr<dds::Participant> MakeParticipant(const DdsOptions& options) {
  dds::ParticipantOptions o;
  o.domain_id = DdsDomain(options);
  o.peers = options.peers;
  o.interfaces = options.interfaces;
  o.security_enclave = options.security_enclave.string();
  return std::make_unique<dds::Participant>(o);
}

DdsBridge::DdsBridge(Executor& executor, Bus& bus, dds::Participant& participant, const DdsOptions& options,
                     RobotFrames frames, const RobotCore& core, const MapLibrary& maps, const Lifecycle& lifecycle)
    : PeriodicNode("dds", executor, bus, kBridgeRateHz),
      participant_(participant),
      options_(options),
      frames_(std::move(frames)),
      core_(core),
      maps_(maps),
      lifecycle_(lifecycle),
      stamps_(dds::StampClock::For(executor.clock())) {}

void DdsBridge::Activate() {
  // Writers first, so that no bus message finds one missing.
  if (!frames_.base_over_dds) {
    odom_ = participant_.Advertise<nav_msgs::msg::OdometryPubSubType>("/odom", Qos::kDefault);
    battery_ = participant_.Advertise<sensor_msgs::msg::BatteryStatePubSubType>("/battery_state", Qos::kDefault);
  }
  tf_ = participant_.Advertise<tf2_msgs::msg::TFMessagePubSubType>("/tf", Qos::kTf);
  tf_static_ = participant_.Advertise<tf2_msgs::msg::TFMessagePubSubType>("/tf_static", Qos::kLatched);
  if (!frames_.laser_over_dds) {
    scan_ = participant_.Advertise<sensor_msgs::msg::LaserScanPubSubType>("/scan", Qos::kDefault);
  }
  map_ = participant_.Advertise<nav_msgs::msg::OccupancyGridPubSubType>("/map", Qos::kLatched, /*large=*/true);
  plan_ = participant_.Advertise<nav_msgs::msg::PathPubSubType>("/plan", Qos::kDefault);
  pose_ = participant_.Advertise<geometry_msgs::msg::PoseWithCovarianceStampedPubSubType>("/amcl_pose", Qos::kLatched);
  diagnostics_ = participant_.Advertise<diagnostic_msgs::msg::DiagnosticArrayPubSubType>("/diagnostics", Qos::kDefault);
  state_ = participant_.Advertise<std_msgs::msg::StringPubSubType>("/corridor/state", Qos::kDefault);
  if (options_.camera_hz > 0.0 && frames_.camera && !frames_.camera_over_dds) {
    // Reliable, as everything here: a reliable writer meets best-effort readers too, and RViz's displays ask for
    // reliable by default.
    depth_ = participant_.Advertise<sensor_msgs::msg::ImagePubSubType>("/camera/depth/image_raw", Qos::kDefault,
                                                                       /*large=*/true);
    camera_info_ =
        participant_.Advertise<sensor_msgs::msg::CameraInfoPubSubType>("/camera/depth/camera_info", Qos::kDefault);
  }

  // The body's fixed frames, once (transient local: late joiners get them).
  {
    tf2_msgs::msg::TFMessage statics;
    const auto now = stamps_.ToRos(clock().Now());
    if (frames_.base_T_laser) {
      statics.transforms().push_back(dds::Transform(now, dds::kBaseFrame, dds::kLaserFrame, *frames_.base_T_laser));
    }
    if (frames_.camera) {
      statics.transforms().push_back(
          dds::Transform(now, dds::kBaseFrame, dds::kCameraFrame, frames_.camera->camera.base_T_camera));
    }
    tf_static_->Write(statics);
  }

  // The table: bus topic -> ROS 2 topic.
  if (!frames_.base_over_dds) {
    Subscribe(topics::kBattery, "battery",
              [this](const auto& battery) { battery_->Write(dds::ToRos(*battery, stamps_)); });
    Subscribe(topics::kOdometry, "odom", [this](const auto& odometry) {
      const nav_msgs::msg::Odometry message = dds::ToRos(*odometry, stamps_);
      odom_->Write(message);
      tf_->Write(OneTransform(dds::Transform(message.header().stamp(), dds::kOdomFrame, dds::kBaseFrame,
                                             odometry->odom_T_base.ToIsometry3())));
    });
  }
  Subscribe(topics::kPose, "pose", [this](const auto& pose) {
    const auto odometry = bus().Get(topics::kOdometry).latest();
    if (!odometry || pose->stamp_ns < next_map_odom_ns_) return;
    next_map_odom_ns_ = pose->stamp_ns + drivers::FromSeconds(kMapOdomPeriodS);
    const nav::Pose2 map_T_odom = pose->pose * odometry->odom_T_base.Inverse();
    tf_->Write(OneTransform(dds::Transform(stamps_.ToRos(pose->stamp_ns + drivers::FromSeconds(kMapOdomToleranceS)),
                                           dds::kMapFrame, dds::kOdomFrame, map_T_odom.ToIsometry3())));
  });
  Subscribe(topics::kLocalization, "localization", [this](const auto& localization) {
    geometry_msgs::msg::PoseWithCovarianceStamped message;
    message.header(dds::Header(stamps_.ToRos(localization->stamp_ns), dds::kMapFrame));
    message.pose().pose(dds::ToRos(localization->estimate.pose));
    // (x, y, yaw) into ROS's 6x6 (x, y, z, roll, pitch, yaw), row-major.
    const Eigen::Matrix3d& c = localization->estimate.covariance;
    const int index[3] = {0, 1, 5};
    for (int r = 0; r < 3; ++r) {
      for (int k = 0; k < 3; ++k)
        message.pose().covariance()[static_cast<std::size_t>(index[r] * 6 + index[k])] = c(r, k);
    }
    pose_->Write(message);
  });
  if (frames_.base_T_laser && !frames_.laser_over_dds) {
    Subscribe(topics::kScan, "scan",
              [this](const auto& scan) { scan_->Write(dds::ToRos(*scan, stamps_, dds::kLaserFrame)); });
  } else if (!frames_.base_T_laser && frames_.camera) {
    // No laser: the depth camera's nearest obstacle per column, as a scan in base_link.
    Subscribe(topics::kGroundLanes, "scan", [this](const auto& ground) {
      if (ground->scan.empty()) return;
      scan_->Write(dds::ScanFromPoints(ground->scan, kDepthScanIncrementRad, frames_.camera->min_range_m,
                                       frames_.camera->max_range_m, stamps_.ToRos(ground->stamp_ns), dds::kBaseFrame));
    });
  }
  Subscribe(topics::kMission, "plan", [this](const auto& mission) {
    const auto& path = mission->path;
    const bool same = path.size() == plan_path_.size() &&
                      std::equal(path.begin(), path.end(), plan_path_.begin(), [](const auto& a, const auto& b) {
                        return a.x_m == b.x_m && a.y_m == b.y_m && a.yaw_rad == b.yaw_rad;
                      });
    if (same) return;
    plan_path_ = path;
    nav_msgs::msg::Path message;
    message.header(dds::Header(stamps_.ToRos(clock().Now()), dds::kMapFrame));
    for (const nav::Pose2& p : path) {
      geometry_msgs::msg::PoseStamped stamped;
      stamped.header(message.header());
      stamped.pose(dds::ToRos(p));
      message.poses().push_back(std::move(stamped));
    }
    plan_->Write(message);
  });
  if (depth_) {
    Subscribe(topics::kRgbd, "depth", [this](const auto& frame) {
      const drivers::TimeNs now = clock().Now();
      if (now < next_depth_ns_) return;
      next_depth_ns_ = now + drivers::FromSeconds(1.0 / options_.camera_hz);
      const auto stamp = stamps_.ToRos(frame->stamp_ns);
      depth_->Write(dds::DepthImage(frame->depth_mm, stamp, dds::kCameraFrame));
      camera_info_->Write(dds::ToRos(frames_.camera->camera, stamp, dds::kCameraFrame));
    });
  }

  // What ROS 2 tools send.
  TakeWrites<geometry_msgs::msg::TwistPubSubType>(
      options_.cmd_vel_topic, [this](const geometry_msgs::msg::Twist& t) { core_.Teleop(dds::FromRos(t), "dds"); });
  TakeWrites<geometry_msgs::msg::PoseStampedPubSubType>("/goal_pose", [this](const geometry_msgs::msg::PoseStamped& g) {
    const nav::Pose2 p = dds::FromRos(g.pose());
    RequireMapFrame(g.header());
    nav::MissionGoal goal;
    goal.pose = p;
    goal.has_yaw = true;
    core_.StartMission({{goal}, std::numeric_limits<double>::infinity(), "dds /goal_pose"}, [](MissionResult result) {
      if (const auto* refusal = std::get_if<nav::MissionRefusal>(&result)) {
        spdlog::warn("dds: /goal_pose refused ({}): {}", nav::ToString(refusal->reason),
                     nav::Describe(*refusal, "the goal"));
      }
    });
  });
  TakeWrites<geometry_msgs::msg::PoseWithCovarianceStampedPubSubType>(
      "/initialpose", [this](const geometry_msgs::msg::PoseWithCovarianceStamped& pose) {
        const nav::Pose2 p = dds::FromRos(pose.pose().pose());
        RequireMapFrame(pose.header());
        const auto& c = pose.pose().covariance();
        PoseOrder order;
        order.pose = p;
        order.origin = "dds /initialpose";
        // RViz's 2D Pose Estimate sends 0.25 m^2 on x and y and (pi/12)^2 on yaw: take its spread when it gives one.
        if (c[0] > 0.0 && c[7] > 0.0 && std::isfinite(c[0] + c[7])) order.sigma_m = std::sqrt(0.5 * (c[0] + c[7]));
        if (c[35] > 0.0 && std::isfinite(c[35])) order.sigma_rad = std::sqrt(c[35]);
        core_.SetPose(order, [](PoseResult result) {
          if (const auto* refused = std::get_if<PoseRefused>(&result)) {
            spdlog::warn("dds: /initialpose refused: {}", refused->detail);
          } else {
            spdlog::info("dds: /initialpose taken: {}", std::get<PoseCheck>(result).detail);
          }
        });
      });
  PeriodicNode::Activate();
  const dds::ParticipantOptions& o = participant_.options();
  SetHealth(Health::kOk, "domain " + std::to_string(o.domain_id) +
                             (o.security_enclave.empty() ? ", no security" : ", secured by " + o.security_enclave));
}

void DdsBridge::Deactivate() {
  subscriptions_.clear();  // nothing from ROS 2 moves the robot from here on
  drops_.clear();
  PeriodicNode::Deactivate();
}

template <typename PubSubType>
void DdsBridge::TakeWrites(const std::string& topic, std::function<void(const typename PubSubType::type&)> take) {
  auto& drops = *drops_.emplace_back(std::make_unique<dds::DropLog>(topic));
  subscriptions_.push_back(participant_.Subscribe<PubSubType>(
      topic, Qos::kDefault, [this, &drops, take = std::move(take)](const typename PubSubType::type& message) {
        if (!options_.allow_writes) return drops.Drop("writes over DDS are off (dds.allow_writes)");
        try {
          take(message);
        } catch (const std::invalid_argument& e) {
          drops.Drop(e.what());
        }
      }));
}

void DdsBridge::RequireMapFrame(const std_msgs::msg::Header& header) {
  const std::string& frame = header.frame_id();
  if (!frame.empty() && frame != dds::kMapFrame) {
    throw std::invalid_argument("poses must be in the map frame, not '" + frame + "'");
  }
}

void DdsBridge::Tick() {
  PublishMap();
  std_msgs::msg::String state;
  state.data(core_.State()->text);
  state_->Write(state);
  if (++ticks_ % 2 == 0) PublishDiagnostics();
}

void DdsBridge::PublishMap() {
  std::shared_ptr<const nav::OccupancyGrid> grid;
  const auto mapping = bus().Get(topics::kMapping).latest();
  if (mapping && mapping->active && mapping->grid) {
    // Mapping a new building: the map as it grows.
    if (mapping->revision == mapping_revision_) return;
    mapping_revision_ = mapping->revision;
    grid = mapping->grid;
  } else {
    const auto active = maps_.active();
    if (active->name == map_name_ && active->revision == map_revision_ && mapping_revision_ == 0) return;
    map_name_ = active->name;
    map_revision_ = active->revision;
    mapping_revision_ = 0;
    grid = std::shared_ptr<const nav::OccupancyGrid>(active, &active->grid);
  }
  const auto stamp = stamps_.ToRos(clock().Now());
  nav_msgs::msg::OccupancyGrid message;
  message.header(dds::Header(stamp, dds::kMapFrame));
  message.info().map_load_time(stamp);
  message.info().resolution(static_cast<float>(grid->resolution_m()));
  message.info().width(static_cast<std::uint32_t>(grid->width()));
  message.info().height(static_cast<std::uint32_t>(grid->height()));
  message.info().origin(dds::ToRos(grid->origin()));
  message.data(grid->cells());
  map_->Write(message);
}

void DdsBridge::PublishDiagnostics() {
  diagnostic_msgs::msg::DiagnosticArray array;
  array.header(dds::Header(stamps_.ToRos(clock().Now()), ""));
  for (const auto& node : lifecycle_.nodes()) {
    const nlohmann::json status = node->Status();
    diagnostic_msgs::msg::DiagnosticStatus s;
    s.level(DiagnosticLevel(status.value("health", "")));
    s.name("corridor/" + node->name());
    s.message(status.value("message", ""));
    s.hardware_id("corridord");
    for (const auto& loop : status.value("callbacks", nlohmann::json::array())) {
      const std::string loop_name = loop.value("name", "");
      diagnostic_msgs::msg::KeyValue rate;
      rate.key(loop_name + " rate (Hz)");
      rate.value(std::to_string(loop.value("rate_hz", 0.0)));
      s.values().push_back(rate);
      diagnostic_msgs::msg::KeyValue mean;
      mean.key(loop_name + " mean (ms)");
      mean.value(std::to_string(loop.value("mean_ms", 0.0)));
      s.values().push_back(mean);
    }
    array.status().push_back(std::move(s));
  }
  // Each device, as ROS drivers report theirs: its health, its port as the hardware id, its rate and last error.
  if (const auto devices = bus().Get(topics::kDevices).latest()) {
    for (const DeviceReport& d : devices->devices) {
      diagnostic_msgs::msg::DiagnosticStatus s;
      s.level(d.state == nav::DeviceState::kOk ? 0 : d.state == nav::DeviceState::kStale ? 1 : 2);  // OK, WARN, ERROR
      s.name("corridor/devices/" + d.device);
      s.message(std::string(nav::ToString(d.state)) + (d.last_error.empty() ? "" : ": " + d.last_error));
      s.hardware_id(d.driver + (d.port.empty() ? "" : " " + d.port));
      for (const auto& [key, value] : {std::pair<std::string, std::string>{"rate (Hz)", std::to_string(d.rate_hz)},
                                       {"age (s)", std::to_string(d.age_s)},
                                       {"link", d.link},
                                       {"reconnects", std::to_string(d.reconnects)}}) {
        diagnostic_msgs::msg::KeyValue kv;
        kv.key(key);
        kv.value(value);
        s.values().push_back(kv);
      }
      array.status().push_back(std::move(s));
    }
  }
  diagnostics_->Write(array);
}

}  // namespace corridor::server
