#include "server/nodes/localization_node.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include <spdlog/spdlog.h>

#include <stdexcept>

#include "nav/localization/range_scan.h"
#include "server/runtime/topics.h"

namespace corridor::server {
namespace {

// Over a sweep of a rotating laser, the base moved less than this and its beams are taken as measured at once: a beam
// 8 m away put 8 mm off at most, a sixth of a map cell.
constexpr double kStillM = 0.001;
constexpr double kStillRad = 0.001;
constexpr std::size_t kParticlesShown = 200;
constexpr drivers::TimeNs kRenderEveryNs = 3'000'000'000;  // the map being built, for the console
constexpr double kMapResolutionM = 0.05;

double Radians(double deg) { return deg * std::numbers::pi / 180.0; }

bool Moved(const nav::Pose2& from, const nav::Pose2& to) {
  const nav::Pose2 d = from.Inverse() * to;
  return std::hypot(d.x_m, d.y_m) >= kStillM || std::abs(d.yaw_rad) >= kStillRad;
}

}  // namespace

LocalizationNode::LocalizationNode(Executor& executor, Bus& bus, const LocalizationOptions& options,
                                   nav::Pose2 initial_pose, std::optional<nav::Pose2> base_T_laser,
                                   const nav::PinholeCamera& camera, std::filesystem::path pose_file,
                                   std::optional<SavedPose> restored, MapBuilt on_map_built)
    : Node("localization", executor, bus),
      options_(options),
      base_T_laser_(base_T_laser),
      frame_(std::make_shared<OdometryFrame>(initial_pose)),
      pose_file_(std::move(pose_file)),
      saved_(restored),
      restored_(std::move(restored)),
      on_map_built_(std::move(on_map_built)) {
  if (!base_T_laser_) {
    // Throws for a camera without size: a configuration error.
    depth_scan_.Reset(camera, [depth = options_.depth](std::optional<nav::DepthScan>& scan,
                                                       const nav::PinholeCamera& c) { scan.emplace(c, depth); });
    // The likelihood field's random-measurement floor spreads over what the sensor can see.
    options_.mcl.max_range_m = options_.depth.max_range_m;
    options_.mcl.doubtful_after = options_.depth_doubtful_scans;
    // Its narrow view is found again by the search after a look around, not by agreeing with some wall.
    options_.mcl.lost_until_found = true;
  }
  // The initial pose is known before the first odometry arrives. Published here, before the executors run: from
  // Activate it raced SetMap, which may change it on the executor.
  bus.Get(topics::kPose).Publish(StampedPose{clock().Now(), initial_pose});
}

void LocalizationNode::Save(const nav::Pose2& pose, double sigma_m, double sigma_rad, bool always) {
  if (pose_file_.empty()) return;
  const SavedPose now{map_name_, pose, sigma_m, sigma_rad};
  if (!always && saved_ && !MovedEnough(*saved_, now)) return;
  SavePose(pose_file_, now);  // a failure is a fault of this loop: logged, the node degraded
  saved_ = now;
}

void LocalizationNode::OnMap(const MapInUse& in_use) {
  if (!in_use.grid || in_use.grid == map_) return;  // its zones or doors changed, not its walls
  map_ = in_use.grid;
  map_name_ = in_use.name;
  double sigma_m = options_.initial_sigma_m;
  double sigma_rad = Radians(options_.initial_sigma_deg);
  const nav::Pose2 odom = frame_->Latest();
  if (restored_ && restored_->place == map_name_) {
    frame_->set_map_T_odom(restored_->pose * odom.Inverse());
    sigma_m = std::max(sigma_m, restored_->sigma_m);
    sigma_rad = std::max(sigma_rad, restored_->sigma_rad);
    spdlog::info("localization: starting where the robot was in map '{}': ({:.2f}, {:.2f})", map_name_,
                 restored_->pose.x_m, restored_->pose.y_m);
  }
  restored_.reset();
  if (options_.source != LocalizationOptions::Source::kMonteCarlo) return;
  // Where the robot is now, by the last estimate: the filter restarts there in the new map.
  filter_ = std::make_unique<nav::MonteCarloLocalization>(*map_, options_.mcl, options_.seed);
  ResetFilter(frame_->map_T_odom() * odom, sigma_m, sigma_rad);
}

void LocalizationNode::ResetFilter(const nav::Pose2& pose, double sigma_m, double sigma_rad) {
  filter_->SetPose(pose, sigma_m, sigma_rad);
  relocalize_ = false;
}

void LocalizationNode::Cleanup() {
  // Where the robot stands at the stop is the pose after the restart. Without this, the file could hold a pose from
  // before the last few centimetres, or (had the daemon stopped between a search finding the robot and the next
  // update) from another room.
  if (map_name_.empty() || slam_) return;
  try {
    if (filter_) {
      const nav::LocalizationEstimate& estimate = filter_->estimate();
      if (estimate.health == nav::LocalizationHealth::kLost) return;  // the file keeps the last pose found
      const Eigen::Matrix3d& c = estimate.covariance;
      Save(estimate.pose, std::sqrt(c(0, 0) + c(1, 1)), std::sqrt(c(2, 2)), true);
    } else if (options_.source == LocalizationOptions::Source::kOdometry) {
      Save(frame_->map_T_odom() * frame_->Latest(), options_.initial_sigma_m, Radians(options_.initial_sigma_deg),
           true);
    }
  } catch (const std::exception& e) {
    spdlog::error("localization: the pose at the stop was not saved: {}", e.what());
  }
}

void LocalizationNode::Activate() {
  auto& pose = pose_topic_;
  using Source = LocalizationOptions::Source;
  Subscribe(topics::kMapInUse, "map", [this](const auto& map) { OnMap(*map); });
  if (options_.source == Source::kSimTruth) {
    Subscribe(topics::kSimTruePose, "truth", [&pose](const auto& truth) { pose.Publish(truth); });
    SetHealth(Health::kOk, "the simulator's ground truth");
    return;
  }
  if (!tapped_) {
    tapped_ = true;
    bus().Get(topics::kOdometry).Tap([frame = frame_, &pose](const drivers::WheelOdometry& odometry) {
      pose.Publish(StampedPose{odometry.stamp_ns, frame->Add(odometry)});
    });
  }
  if (options_.source == Source::kOdometry) {
    // Dead reckoning has no spread to speak of: the start's is kept. Saved here, off the publisher's thread.
    Subscribe(topics::kOdometry, "odometry", [this](const auto& odometry) {
      if (!map_name_.empty()) {
        Save(frame_->map_T_odom() * odometry->odom_T_base, options_.initial_sigma_m,
             Radians(options_.initial_sigma_deg));
      }
    });
    SetHealth(Health::kOk, "dead reckoning from wheel odometry");
    return;
  }
  if (base_T_laser_) {
    Subscribe(topics::kScan, "scan", [this](const auto& scan) { OnScan(*scan); });
  } else {
    Subscribe(topics::kRgbd, "frame", [this](const auto& frame) { OnFrame(*frame); });
  }
  Subscribe(topics::kLocalizationCommand, "command", [this](const auto& command) { OnCommand(*command); });
  SetHealth(Health::kDegraded, base_T_laser_ ? "waiting for the first scan" : "waiting for the first depth frame");
}

void LocalizationNode::OnScan(const drivers::LaserScan& scan) {
  nav::RangeLimits limits;
  limits.min_range_m = std::max(limits.min_range_m, scan.range_min_m);
  limits.max_range_m = scan.range_max_m;
  // A rotating laser's beams are put where they lie at the stamp, by the odometry over the sweep (unless the base
  // stood still through it).
  nav::BeamMotion motion;
  const std::optional<nav::Pose2> at_stamp = scan.sweep_s > 0.0 ? frame_->At(scan.stamp_ns) : std::nullopt;
  if (at_stamp && Moved(*frame_->At(scan.stamp_ns - drivers::FromSeconds(scan.sweep_s)), *at_stamp)) {
    motion = [this, &scan, stamp_T_odom = at_stamp->Inverse()](std::size_t i) {
      const auto age_ns = static_cast<drivers::TimeNs>(drivers::BeamAgeS(scan, i) * 1e9);
      return stamp_T_odom * *frame_->At(scan.stamp_ns - age_ns);
    };
  }
  Localize(scan.stamp_ns, nav::ScanFromRanges(*base_T_laser_, scan.angle_min_rad, scan.angle_increment_rad, scan.ranges,
                                              limits, motion));
}

void LocalizationNode::OnFrame(const drivers::RgbdFrame& frame) {
  nav::RangeScan range;
  try {
    for (const Eigen::Vector2d& p : depth_scan_.At(frame.base_T_camera).Process(frame.depth_mm)) {
      range.hits.push_back(p.cast<float>());
    }
  } catch (const std::invalid_argument& e) {
    SetHealth(Health::kDegraded, e.what());
    return;
  }
  for (const Eigen::Vector2d& p : depth_scan_->misses()) range.misses.push_back(p.cast<float>());
  range.origin = depth_scan_->View({}).world_T_sensor.translation().cast<float>();
  Localize(frame.stamp_ns, range);
}

void LocalizationNode::Localize(drivers::TimeNs stamp_ns, const nav::RangeScan& range) {
  if (!filter_) {
    SetHealth(Health::kDegraded, "no map to localize in");
    return;
  }
  const std::optional<nav::Pose2> odom = frame_->At(stamp_ns);
  if (!odom) return;  // no odometry yet: nothing to move the filter with
  if (held_) {
    SetHealth(Health::kOk, "holding on odometry");
    return;
  }
  if (slam_) {
    Map(stamp_ns, *odom, range);
    return;
  }
  const bool lost = filter_->estimate().health == nav::LocalizationHealth::kLost;
  const bool search_due =
      lost && stamp_ns - last_search_ns_ >= static_cast<drivers::TimeNs>(options_.relocalize_every_s * 1e9);
  // The camera's narrow view searches once it has seen enough around the robot; until then the robot turns.
  bool view_ready = true;
  look_around_rps_ = 0.0;
  if (depth_scan_) {
    history_.Add(*odom, range);
    if (lost || relocalize_) {
      const nav::NarrowViewSearch plan = nav::PlanNarrowViewSearch(history_, *odom);
      view_ready = plan.search;
      look_around_rps_ = plan.turn_rps;
    }
  }
  if ((relocalize_ || search_due) && view_ready) {
    last_search_ns_ = stamp_ns;
    relocalize_ = false;
    const auto start = std::chrono::steady_clock::now();
    const bool found = filter_->Relocalize(depth_scan_ ? history_.Merged(*odom) : range);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (found) {
      spdlog::info("localization: found the robot at ({:.2f}, {:.2f}) by a search of the whole map in {:.0f} ms",
                   filter_->estimate().pose.x_m, filter_->estimate().pose.y_m, ms);
    } else {
      spdlog::warn("localization: a search of the whole map ({:.0f} ms) found nothing that fits the scan", ms);
    }
  }
  last_scan_ = std::make_pair(*odom, range);
  const nav::LocalizationEstimate& estimate = filter_->Update(*odom, range);
  if (estimate.health == nav::LocalizationHealth::kLost && !lost) {
    // Just lost: what the camera saw before may be where the robot was carried from.
    history_.Clear();
    if (depth_scan_) history_.Add(*odom, range);
  }
  frame_->set_map_T_odom(estimate.pose * odom->Inverse());
  Publish(stamp_ns);
  if (estimate.health != nav::LocalizationHealth::kLost) {
    const Eigen::Matrix3d& c = estimate.covariance;
    Save(estimate.pose, std::sqrt(c(0, 0) + c(1, 1)), std::sqrt(c(2, 2)));
  }
  switch (estimate.health) {
    case nav::LocalizationHealth::kOk: SetHealth(Health::kOk, "localized in the map"); break;
    case nav::LocalizationHealth::kUncertain:
      SetHealth(Health::kDegraded, "uncertain: the scans agree little with the map or the particles are spread");
      break;
    case nav::LocalizationHealth::kLost: SetHealth(Health::kError, "lost: searching the map for the robot"); break;
  }
}

void LocalizationNode::OnCommand(const LocalizationCommand& command) {
  using Kind = LocalizationCommand::Kind;
  if (command.kind == Kind::kSetPose && options_.source == LocalizationOptions::Source::kOdometry) {
    TakePose(command.pose, command.sigma_m, command.sigma_rad);
    return;
  }
  if (!filter_) return;
  if (command.kind == Kind::kHold || command.kind == Kind::kResume) {
    held_ = command.kind == Kind::kHold;
    spdlog::info("localization: {}", held_ ? "holding on odometry" : "back on the scans");
    if (!held_) {
      ResetFilter(frame_->map_T_odom() * frame_->Latest(), options_.initial_sigma_m,
                  Radians(options_.initial_sigma_deg));
    }
    return;
  }
  if (command.kind == LocalizationCommand::Kind::kStartMapping) {
    StartMapping(command.name);
    return;
  }
  if (command.kind == LocalizationCommand::Kind::kStopMapping) {
    StopMapping();
    return;
  }
  if (slam_) return;  // while mapping, the map being built is where the robot is
  if (command.kind == LocalizationCommand::Kind::kRelocalize) {
    relocalize_ = true;
    history_.Clear();  // asked to search: the robot may have been carried
    return;
  }
  TakePose(command.pose, command.sigma_m, command.sigma_rad);
}

void LocalizationNode::SetPose(const nav::Pose2& pose, double sigma_m, double sigma_rad,
                               std::function<void(PoseCheck)> done) {
  executor().Post([this, pose, sigma_m, sigma_rad, done = std::move(done)] {
    PoseCheck check;
    if (!Run("command", [&] { check = TakePose(pose, sigma_m, sigma_rad); })) {
      check.detail = "localization failed to take the pose (see the log)";
    }
    done(std::move(check));
  });
}

PoseCheck LocalizationNode::TakePose(const nav::Pose2& pose, double sigma_m, double sigma_rad) {
  PoseCheck check;
  if (options_.source == LocalizationOptions::Source::kOdometry || !filter_) {
    // Dead reckoning goes on from the pose given (or, with no map yet, the filter starts there).
    frame_->set_map_T_odom(pose * frame_->Latest().Inverse());
    check.taken = true;
    check.detail = filter_ || options_.source == LocalizationOptions::Source::kOdometry
                       ? "taken: dead reckoning goes on from it"
                       : "taken; there is no map to localize in yet";
    return check;
  }
  if (slam_) {
    check.detail = "mapping '" + mapping_.name + "' is under way: the map being built says where the robot is";
    return check;
  }
  if (last_scan_) {
    // The last scan, at the given pose carried back to when it was taken, against where the filter had the robot then.
    const auto& [scan_odom, scan] = *last_scan_;
    const nav::Pose2 then = pose * frame_->Latest().Inverse() * scan_odom;
    check.checked = true;
    check.agreement = filter_->AgreementAt(scan.hits, then);
    check.agreement_before = filter_->AgreementAt(scan.hits, filter_->estimate().pose);
    const double ok = options_.mcl.ok_agreement;
    check.agrees = check.agreement >= ok || check.agreement >= 0.8 * check.agreement_before;
  }
  ResetFilter(pose, sigma_m, sigma_rad);
  frame_->set_map_T_odom(pose * frame_->Latest().Inverse());
  Publish(clock().Now());
  check.taken = true;
  const auto percent = [](double f) { return std::to_string(static_cast<int>(std::lround(100.0 * f))) + " %"; };
  if (!check.checked) {
    check.detail = "taken; no scan yet to check it against";
  } else if (check.agrees) {
    check.detail = "taken: the scan fits the map there (" + percent(check.agreement) + " of it on walls)";
  } else {
    check.detail = "taken, but the scan does not fit the map there: " + percent(check.agreement) +
                   " of it on walls, against " + percent(check.agreement_before) +
                   " where localization had the robot; it will likely move the robot back";
  }
  spdlog::info("localization: pose ({:.2f}, {:.2f}, {:.0f} deg) {}", pose.x_m, pose.y_m,
               pose.yaw_rad * 180.0 / std::numbers::pi, check.detail);
  return check;
}

void LocalizationNode::Publish(drivers::TimeNs stamp_ns) {
  LocalizationState state;
  state.stamp_ns = stamp_ns;
  state.source = "mcl";
  state.sensor = base_T_laser_ ? "laser" : "depth";
  state.look_around_rps = look_around_rps_;
  state.estimate = filter_->estimate();
  const auto particles = filter_->particles();
  const std::size_t step = std::max<std::size_t>(1, particles.size() / kParticlesShown);
  for (std::size_t i = 0; i < particles.size() && state.particles.size() < kParticlesShown; i += step) {
    state.particles.push_back(particles[i].pose);
  }
  localization_topic_.Publish(std::move(state));
}

void LocalizationNode::StartMapping(const std::string& name) {
  if (slam_) return;
  // From where the robot is in the present map: the new map shares its frame.
  const nav::Pose2 start = frame_->map_T_odom() * frame_->Latest();
  slam_ = std::make_unique<nav::GraphSlam>(nav::GraphSlamOptions{}, start);
  mapping_ = MappingState{};
  mapping_.active = true;
  mapping_.name = name;
  last_render_ns_ = 0;
  spdlog::info("mapping '{}': started at ({:.2f}, {:.2f})", name, start.x_m, start.y_m);
  PublishMapping(clock().Now(), false);
  SetHealth(Health::kOk, "mapping '" + name + "'");
}

void LocalizationNode::Map(drivers::TimeNs stamp_ns, const nav::Pose2& odom, const nav::RangeScan& scan) {
  const nav::Pose2 pose = slam_->AddScan(scan, odom);
  slam_odom_ = odom;
  frame_->set_map_T_odom(pose * odom.Inverse());
  PublishMapping(stamp_ns, stamp_ns - last_render_ns_ >= kRenderEveryNs);
}

void LocalizationNode::PublishMapping(drivers::TimeNs stamp_ns, bool render) {
  mapping_.stamp_ns = stamp_ns;
  if (slam_) {
    const nav::GraphSlamStats& stats = slam_->stats();
    mapping_.scans = stats.scans;
    mapping_.submaps = stats.submaps;
    mapping_.loop_closures = stats.loop_closures;
    if (render && stats.inserted > 0) {
      mapping_.grid = std::make_shared<const nav::OccupancyGrid>(slam_->RenderMap(kMapResolutionM));
      ++mapping_.revision;
      last_render_ns_ = stamp_ns;
    }
  }
  mapping_topic_.Publish(mapping_);
}

void LocalizationNode::StopMapping() {
  if (!slam_) return;
  slam_->Finish();
  if (slam_->stats().inserted == 0) {
    mapping_.error = "no scan was mapped: nothing to save";
    spdlog::warn("mapping '{}': {}", mapping_.name, mapping_.error);
    PublishMapping(clock().Now(), false);
    return;
  }
  // The final pose graph's estimate of where the robot is now.
  const nav::Pose2 pose = slam_->Trajectory().back();
  nav::OccupancyGrid grid = slam_->RenderMap(kMapResolutionM);
  try {
    if (on_map_built_) on_map_built_(mapping_.name, grid);
  } catch (const std::exception& e) {
    // The scans are kept: mapping goes on and a later stop can save it (under another name).
    mapping_.error = std::string("the map could not be saved: ") + e.what();
    spdlog::error("mapping '{}': {}", mapping_.name, mapping_.error);
    PublishMapping(clock().Now(), true);
    return;
  }
  frame_->set_map_T_odom(pose * slam_odom_.Inverse());
  spdlog::info("mapping '{}': saved ({} scans, {} loop closures)", mapping_.name, slam_->stats().scans,
               slam_->stats().loop_closures);
  PublishMapping(clock().Now(), true);
  slam_.reset();
  mapping_.active = false;
  mapping_.saved = mapping_.name;
  mapping_.error.clear();
  mapping_topic_.Publish(mapping_);
}

}  // namespace corridor::server
