#include "server/config/config.h"

#include <charconv>
#include <cstdlib>
#include <fstream>
#include <functional>

#include <map>
#include <numbers>
#include <set>
#include <sstream>
#include <string>

#include "drivers/serial/byte_stream.h"
#include "nav/policy/flmc.h"
#include "server/config/config_reader.h"

namespace corridor::server {
namespace {

namespace fs = std::filesystem;

constexpr double kDegToRad = std::numbers::pi / 180.0;

void ReadPath(ConfigReader& r, const char* key, fs::path& value, const fs::path& base) {
  std::string text = value.string();
  r.Read(key, text);
  value = text.empty() || fs::path(text).is_absolute() ? fs::path(text) : base / text;
}

// A key that has moved elsewhere: its old place names the new one.
void RefuseMoved(ConfigReader& r, const char* key, const std::string& to) {
  YAML::Node value;
  r.Read(key, value);
  if (!value.IsNull()) throw ConfigError(r.PathOf(key) + ": moved to " + to);  // a default node is null
}

void CheckTopic(const ConfigReader& r, const char* key, const std::string& topic) {
  if (!topic.empty() && !drivers::dds::IsRosTopicName(topic)) {
    throw ConfigError(r.PathOf(key) + ": '" + topic + "' is not a ROS 2 topic name");
  }
}

void ReadServer(ConfigReader& r, ServerOptions& o, const fs::path& base) {
  r.Read("port", o.port, 0, 65535);
  r.Read("bind_address", o.bind_address);
  ReadPath(r, "web_root", o.web_root, base);
  r.Read("max_body_bytes", o.max_body_bytes, 256, 64 * 1024 * 1024);
  r.Read("stream_rate_hz", o.stream_rate_hz, 1.0, 100.0);
  r.Section("tls", [&](ConfigReader& t) {
    t.Read("enabled", o.tls.enabled);
    ReadPath(t, "certificate", o.tls.certificate, base);
    ReadPath(t, "key", o.tls.key, base);
    t.Read("redirect_port", o.tls.redirect_port, 0, 65535);
  });
  if (o.tls.certificate.empty() != o.tls.key.empty()) {
    throw ConfigError("server.tls: give both certificate and key, or neither (a self-signed one is made)");
  }
}

void ReadAuth(ConfigReader& r, auth::AuthOptions& a) {
  r.Read("anonymous_viewer", a.anonymous_viewer);
  r.Read("local_face", a.local_face);
  r.Read("session_hours", a.session_hours, 0.1, 24.0 * 90);
  r.Read("login_failures_per_minute", a.login_failures_per_minute, 1, 1000);
  r.Read("keep_audit", a.keep_audit, 100, 10000000);
}

void ReadSafety(ConfigReader& r, SafetyOptions& o) {
  r.Read("teleop_deadman_s", o.teleop_deadman_s, 0.05, 5.0);
  r.Read("max_linear_mps", o.max_linear_mps, 0.0, 3.0);
  r.Read("max_angular_rps", o.max_angular_rps, 0.0, 6.0);
  r.Read("odometry_timeout_s", o.odometry_timeout_s, 0.05, 5.0);
  r.Read("control_rate_hz", o.control_rate_hz, 5.0, 200.0);
  r.Read("depth_timeout_s", o.depth_timeout_s, 0.02, 5.0);
  r.Read("laser_timeout_s", o.laser_timeout_s, 0.02, 5.0);
  r.Read("front_offset_m", o.front_offset_m, 0.0, 2.0);
  r.Read("corridor_half_width_m", o.corridor_half_width_m, 0.01, 2.0);
  r.Read("max_decel_mps2", o.stopping.max_decel_mps2, 0.05, 10.0);
  r.Read("reaction_time_s", o.stopping.reaction_time_s, 0.0, 2.0);
  r.Read("stop_margin_m", o.stopping.margin_m, 0.0, 1.0);
  r.Read("fault_hold_s", o.fault_hold_s, 0.1, 60.0);
  r.Read("docking_max_mps", o.docking_max_mps, 0.01, 0.5);
  r.Read("person_near_m", o.person_near_m, 0.0, 10.0);
  r.Read("person_speed_factor", o.person_speed_factor, 0.0, 1.0);
}

// A base's limits; `max_linear_mps` bounds its top speed.
void ReadBaseLimits(ConfigReader& r, drivers::BaseLimits& l, double max_linear_mps) {
  r.Read("max_linear_mps", l.max_linear_mps, 0.01, max_linear_mps);
  r.Read("max_angular_rps", l.max_angular_rps, 0.01, 10.0);
  r.Read("max_linear_accel_mps2", l.max_linear_accel_mps2, 0.01, 20.0);
  r.Read("max_angular_accel_rps2", l.max_angular_accel_rps2, 0.01, 50.0);
  r.Read("footprint_radius_m", l.footprint_radius_m, 0.05, 2.0);
}

void ReadBase(ConfigReader& r, drivers::sim::SimBaseOptions& o) {
  ReadBaseLimits(r, o.limits, 3.0);
  r.Read("command_timeout_s", o.command_timeout_s, 0.05, 5.0);
  r.Read("odom_linear_noise", o.odom_linear_noise, 0.0, 0.5);
  r.Read("odom_angular_noise", o.odom_angular_noise, 0.0, 0.5);
  r.Read("wheel_diameter_error", o.wheel_diameter_error, 0.5, 2.0);
  r.Read("track_error", o.track_error, 0.5, 2.0);
}

// A stereo camera's depth path (a device's or the simulator's): matched at depth_width (at most the views' width).
void ReadStereoDepth(ConfigReader& s, drivers::stereo::StereoDepthOptions& d, int views_width) {
  using drivers::stereo::MatcherKind;
  d.width = std::min(d.width, views_width);
  s.Read("depth_width", d.width, 64, views_width);
  s.ReadChoice<MatcherKind>("matcher", d.matcher.kind,
                            {{"sgbm", MatcherKind::kSemiGlobal}, {"bm", MatcherKind::kBlock}});
  s.Read("disparities", d.matcher.disparities, 16, 512);
  s.Read("block_px", d.matcher.block_px, 1, 51);
  s.Read("uniqueness_percent", d.matcher.uniqueness_percent, 0, 100);
  s.Read("left_right_px", d.matcher.left_right_px, -1, 64);
  s.Read("min_texture", d.matcher.min_texture, 0.0, 128.0);
  s.Read("edge_px", d.matcher.edge_px, 0, 64);
  s.Read("min_range_m", d.min_range_m, 0.05, 5.0);
  s.Read("max_range_m", d.max_range_m, 0.5, 50.0);
  try {
    drivers::stereo::ValidateStereoDepthOptions(d);
  } catch (const std::invalid_argument& e) {
    throw ConfigError(s.PathOf("depth_width") + "..max_range_m: " + e.what());
  }
}

void ReadCamera(ConfigReader& r, drivers::sim::SimCameraOptions& o) {
  r.Read("width", o.width, 16, 4096);
  r.Read("height", o.height, 16, 4096);
  r.Read("horizontal_fov_deg", o.horizontal_fov_deg, 10.0, 170.0);
  r.Read("vertical_fov_deg", o.vertical_fov_deg, 10.0, 170.0);
  r.Read("mount_x_m", o.mount_x_m, -2.0, 2.0);
  r.Read("mount_height_m", o.mount_height_m, 0.02, 3.0);
  r.Read("tilt_deg", o.tilt_deg, -45.0, 90.0);
  r.Read("min_range_m", o.min_range_m, 0.0, 10.0);
  r.Read("max_range_m", o.max_range_m, 0.1, 65.0);
  r.Read("rate_hz", o.rate_hz, 1.0, 120.0);
  r.Read("noise_a_m", o.noise_a_m, 0.0, 1.0);
  r.Read("noise_b_per_m", o.noise_b_per_m, 0.0, 1.0);
  r.Read("dropout_fraction", o.dropout_fraction, 0.0, 1.0);
  r.Read("grazing_cutoff_deg", o.grazing_cutoff_deg, 0.0, 90.0);
  if (o.min_range_m >= o.max_range_m) throw ConfigError(r.PathOf("min_range_m") + ": must be below max_range_m");
}

// The wide pair's search and its fusion with the narrow one (drivers/stereo/multi_baseline.h).
void ReadBaselineFusion(ConfigReader& r, int& wide_disparities, drivers::stereo::BaselineFusionOptions& f) {
  r.Read("wide_disparities", wide_disparities, 16, 512);
  if (wide_disparities % 16 != 0) throw ConfigError(r.PathOf("wide_disparities") + ": a multiple of 16");
  r.Read("near_max_m", f.near_max_m, 0.1, 50.0);
  r.Read("far_min_m", f.far_min_m, 0.1, 50.0);
  r.Read("disparity_sigma_px", f.disparity_sigma_px, 0.01, 10.0);
  r.Read("agree_sigmas", f.agree_sigmas, 0.1, 100.0);
  if (f.far_min_m > f.near_max_m) {
    throw ConfigError(r.PathOf("far_min_m") + ": at most near_max_m (the overlap of the pairs' bands)");
  }
}

// Where a pan servo stands and how it may turn (the simulator's and a real one's).
void ReadPanMount(ConfigReader& r, double& axis_x_m, double& axis_y_m, double& min_deg, double& max_deg,
                  double& max_speed_dps) {
  r.Read("axis_x_m", axis_x_m, -2.0, 2.0);
  r.Read("axis_y_m", axis_y_m, -2.0, 2.0);
  r.Read("min_deg", min_deg, -180.0, 0.0);
  r.Read("max_deg", max_deg, 0.0, 180.0);
  r.Read("max_speed_dps", max_speed_dps, 1.0, 1000.0);
}

// sim.camera.pan: the simulated camera's pan servo, fitted when devices.camera.pan.driver is sim.
void ReadSimPan(ConfigReader& r, drivers::sim::SimPanOptions& o) {
  ReadPanMount(r, o.axis_x_m, o.axis_y_m, o.min_deg, o.max_deg, o.max_speed_dps);
  r.Read("rate_hz", o.rate_hz, 1.0, 1000.0);
}

// sim.camera.stereo: the simulated camera as a stereo pair (docs/asns.md).
void ReadSimStereo(ConfigReader& r, drivers::sim::SimStereoOptions& o, int views_width) {
  r.Read("enabled", o.enabled);
  r.Read("baseline_m", o.baseline_m, 0.01, 1.0);
  r.Read("wide_baseline_m", o.wide_baseline_m, 0.0, 2.0);
  if (o.wide_baseline_m > 0.0 && o.wide_baseline_m <= o.baseline_m) {
    throw ConfigError(r.PathOf("wide_baseline_m") + ": 0 (none) or longer than baseline_m");
  }
  ReadBaselineFusion(r, o.wide_disparities, o.fusion);
  r.Read("image_noise", o.image_noise, 0.0, 50.0);
  r.Read("texture", o.texture, 0.0, 1.0);
  ReadStereoDepth(r, o.depth, views_width);
}

void ReadLaser(ConfigReader& r, drivers::sim::SimLaserOptions& o) {
  RefuseMoved(r, "enabled", "devices.laser.driver (sim or none)");
  r.Read("beams", o.beams, 8, 8192);
  r.Read("mount_height_m", o.mount_height_m, 0.01, 3.0);
  r.Read("min_range_m", o.min_range_m, 0.0, 10.0);
  r.Read("max_range_m", o.max_range_m, 0.1, 100.0);
  r.Read("rate_hz", o.rate_hz, 1.0, 100.0);
  r.Read("noise_m", o.noise_m, 0.0, 1.0);
  r.Read("mount_yaw_deg", o.mount_yaw_deg, -180.0, 180.0);
  r.Read("sweep", o.sweep);
}

// multi_view: step 5 of the stereo camera's filter (nav/ground/multi_view.h).
void ReadMultiView(ConfigReader& r, nav::MultiViewOptions& o) {
  r.Read("enabled", o.enabled);
  r.Read("cell_m", o.cell_m, 0.01, 1.0);
  r.Read("window", o.window, 1, 32);
  r.Read("views", o.views, 1, o.window);
  r.Read("from_m", o.from_m, 0.0, 50.0);
}

// gaze: where a camera on a pan servo looks (nav/policy/gaze.h, docs/asns.md).
void ReadGaze(ConfigReader& r, CameraGazeOptions& o) {
  r.Read("enabled", o.enabled);
  r.Read("rate_hz", o.rate_hz, 1.0, 100.0);
  nav::GazeOptions& g = o.policy;
  r.Read("lookahead_m", g.lookahead_m, 0.1, 10.0);
  r.Read("obstacle_min_m", g.obstacle_min_m, 0.0, 10.0);
  r.Read("obstacle_max_m", g.obstacle_max_m, g.obstacle_min_m + 0.1, 20.0);
  r.Read("path_margin_m", g.path_margin_m, 0.05, 5.0);
  r.Read("goal_near_m", g.goal_near_m, 0.0, 10.0);
  r.Read("keep_ahead_deg", g.keep_ahead_deg, 0.0, 180.0);
  r.Read("moving_mps", g.moving_mps, 0.0, 1.0);
}

void ReadGround(ConfigReader& r, GroundOptions& ground) {
  r.ReadChoice<GroundTest>("test", ground.test, {{"morp", GroundTest::kMorp}, {"afds", GroundTest::kAfds}});
  nav::MorpOptions& o = ground.morp;
  r.Read("lanes", o.lanes, 0, 64);
  r.Read("span_m", o.span_m, 0.05, 3.0);
  r.Read("lane_width_m", o.lane_width_m, 0.01, 1.0);
  r.Read("w1", o.w1, 0.0, 10.0);
  r.Read("w2", o.w2, 0.0, 10.0);
  r.Read("score_threshold", o.score_threshold, 0.01, 100.0);
  r.Read("max_step_m", o.max_step_m, 0.0, 0.5);
  r.Read("max_drop_m", o.max_drop_m, 0.0, 1.0);
  r.Read("min_range_m", o.min_range_m, 0.0, 5.0);
  r.Read("max_range_m", o.max_range_m, 0.2, 20.0);
  r.Read("blind_range_m", o.blind_range_m, 0.05, 10.0);
  r.Read("half_window_px", o.half_window_px, 0, 20);
  if (o.min_range_m >= o.max_range_m) throw ConfigError(r.PathOf("min_range_m") + ": must be below max_range_m");
  nav::AfdsOptions& a = ground.afds;
  r.Section("afds", [&](ConfigReader& s) {
    s.Read("grid_columns", a.grid_columns, 1, 32);
    s.Read("grid_rows", a.grid_rows, 1, 32);
    s.Read("stride_px", a.stride_px, 1, 16);
    s.Read("max_range_m", a.max_range_m, 0.5, 20.0);
    s.Read("iterations", a.iterations, 1, 10000);
    s.Read("inlier_m", a.inlier_m, 0.001, 0.5);
    s.Read("noise_b_per_m", a.noise_b_per_m, 0.0, 0.1);
    s.Read("max_planes", a.max_planes, 1, 16);
    s.Read("min_plane_points", a.min_plane_points, 3, 100000);
    s.Read("max_floor_angle_deg", a.max_floor_angle_deg, 0.0, 45.0);
    s.Read("floor_search_m", a.floor_search_m, 0.0, 1.0);
    s.Read("floor_tolerance_m", a.floor_tolerance_m, 0.0, 0.5);
    s.Read("obstacle_run_m", a.obstacle_run_m, 0.0, 2.0);
  });
  a.min_range_m = o.min_range_m;
  a.max_step_m = o.max_step_m;
  a.max_drop_m = o.max_drop_m;
}

void ReadPlanner(ConfigReader& r, nav::CostmapOptions& o) {
  r.Read("robot_radius_m", o.robot_radius_m, 0.05, 2.0);
  r.Read("distance_weight", o.distance_weight, 0.0, 100.0);
  r.Read("saturation_m", o.saturation_m, 0.01, 10.0);
  r.Read("occupied_threshold", o.occupied_threshold, 1, 100);
  r.Read("layer_cost", o.layer_cost, 0.0, 1000.0);
  bool unknown_is_free = o.unknown == nav::UnknownPolicy::kFree;
  r.Read("unknown_is_free", unknown_is_free);
  o.unknown = unknown_is_free ? nav::UnknownPolicy::kFree : nav::UnknownPolicy::kObstacle;
}

void ReadAvoid(ConfigReader& r, nav::MorpRbOptions& o) {
  r.Read("max_linear_mps", o.max_linear_mps, 0.01, 3.0);
  r.Read("max_angular_rps", o.max_angular_rps, 0.01, 6.0);
  r.Read("clear_distance_m", o.clear_distance_m, 0.1, 10.0);
  r.Read("pass_distance_m", o.pass_distance_m, 0.05, 10.0);
  r.Read("avoid_turn_rps", o.avoid_turn_rps, 0.01, 6.0);
  r.Read("tie_margin_m", o.tie_margin_m, 0.0, 5.0);
  r.Read("overtake_distance_m", o.overtake_distance_m, 0.0, 10.0);
  if (o.pass_distance_m >= o.clear_distance_m) {
    throw ConfigError(r.PathOf("pass_distance_m") + ": must be below clear_distance_m");
  }
}

void ReadEvade(ConfigReader& r, nav::EvasionOptions& o) {
  r.Read("margin_m", o.margin_m, 0.0, 2.0);
  r.Read("horizon_s", o.horizon_s, 0.5, 10.0);
  r.Read("uncertainty_mps", o.uncertainty_mps, 0.0, 2.0);
  r.Read("max_reverse_mps", o.max_reverse_mps, 0.0, 2.0);
  r.Read("max_turn_rps", o.max_turn_rps, 0.1, 6.0);
  o.static_horizon_s = std::min(o.static_horizon_s, o.horizon_s);
}

void ReadLocalization(ConfigReader& r, LocalizationOptions& l) {
  using Source = LocalizationOptions::Source;
  r.ReadChoice<Source>(
      "source", l.source,
      {{"odometry", Source::kOdometry}, {"sim_truth", Source::kSimTruth}, {"mcl", Source::kMonteCarlo}});
  r.Read("initial_sigma_m", l.initial_sigma_m, 0.0, 10.0);
  r.Read("initial_sigma_deg", l.initial_sigma_deg, 0.0, 180.0);
  r.Read("relocalize_every_s", l.relocalize_every_s, 0.1, 3600.0);
  r.Read("depth_max_range_m", l.depth.max_range_m, 1.0, 10.0);
  r.Read("depth_doubtful_scans", l.depth_doubtful_scans, 0, 10000);
  r.Section("mcl", [&](ConfigReader& s) {
    nav::MonteCarloOptions& o = l.mcl;
    int seed = static_cast<int>(l.seed);
    s.Read("seed", seed, 0, 1000000000);
    l.seed = static_cast<std::uint64_t>(seed);
    s.Read("min_particles", o.min_particles, 10, 100000);
    s.Read("max_particles", o.max_particles, 10, 100000);
    if (o.max_particles < o.min_particles) {
      throw ConfigError(s.PathOf("max_particles") + ": must be at least min_particles");
    }
    s.Read("sigma_hit_m", o.sigma_hit_m, 0.01, 1.0);
    s.Read("max_beams", o.max_beams, 1, 10000);
    s.Read("update_distance_m", o.update_distance_m, 0.0, 5.0);
    s.Read("update_angle_deg", o.update_angle_rad, 0.0, 180.0);
    o.update_angle_rad *= std::numbers::pi / 180.0;
  });
}

void ReadOctomap(ConfigReader& r, OctreeOptions& o) {
  r.Read("enabled", o.enabled);
  r.Read("resolution_m", o.octree.resolution_m, 0.01, 1.0);
  r.Read("max_range_m", o.octree.max_range_m, 0.5, 20.0);
  r.Read("pixel_step", o.octree.pixel_step, 1, 16);
  r.Read("layer_min_probability", o.octree.project_min_probability, 0.5, 0.97);
  r.Read("insert_every_s", o.insert_every_s, 0.0, 60.0);
  r.Read("min_height_m", o.min_height_m, 0.0, 3.0);
  r.Read("max_height_m", o.max_height_m, 0.0, 5.0);
  if (o.max_height_m <= o.min_height_m) throw ConfigError(r.PathOf("max_height_m") + ": must exceed min_height_m");
  r.Read("costmap_layer", o.costmap_layer);
  r.Read("update_every_s", o.update_every_s, 0.1, 600.0);
  r.Read("save_every_s", o.save_every_s, 1.0, 86400.0);
}

void ReadPerception(ConfigReader& r, PerceptionOptions& p) {
  r.Read("enabled", p.enabled);
  using Detector = PerceptionOptions::Detector;
  r.ReadChoice<Detector>("detector", p.detector,
                         {{"auto", Detector::kAuto},
                          {"sim", Detector::kSimulated},
                          {"hog", Detector::kHog},
                          {"people", Detector::kPeople},
                          {"dnn", Detector::kDnn}});
  r.Read("faces", p.faces);
  r.Read("rate_hz", p.rate_hz, 0.2, 30.0);
  r.Read("max_ttl_s", p.max_ttl_s, 0.1, 600.0);
  r.Section("hog", [&](ConfigReader& h) {
    h.Read("upscale", p.hog.upscale, 1.0, 4.0);
    h.Read("scale_step", p.hog.scale_step, 1.01, 2.0);
    h.Read("window_stride_px", p.hog.window_stride_px, 1, 64);
    h.Read("padding_px", p.hog.padding_px, 0, 64);
    h.Read("min_score", p.hog.min_score, 0.0, 1.0);
  });
  r.Section("people", [&](ConfigReader& c) {
    c.Read("upper_body", p.people.upper_body);
    c.Read("upper_body_neighbours", p.people.upper_body_neighbours, 1, 50);
    c.Read("upper_body_min_px", p.people.upper_body_min_px, 16, 2000);
    c.Read("faces", p.people.faces);
    c.Read("face_neighbours", p.people.face_neighbours, 1, 50);
    c.Read("face_min_px", p.people.face_min_px, 8, 2000);
    c.Read("merge_iou", p.people.merge_iou, 0.01, 0.99);
  });
  p.people.hog = p.hog;
  r.Read("depth_people", p.depth_people);
  r.Section("depth", [&](ConfigReader& d) {
    d.Read("min_height_m", p.depth.min_height_m, 0.3, 2.5);
    d.Read("max_height_m", p.depth.max_height_m, 0.5, 3.0);
    d.Read("max_floor_gap_m", p.depth.max_floor_gap_m, 0.0, 1.0);
    d.Read("min_width_m", p.depth.min_width_m, 0.0, 2.0);
    d.Read("max_width_m", p.depth.max_width_m, 0.05, 3.0);
  });
  if (p.depth.max_height_m <= p.depth.min_height_m) {
    throw ConfigError(r.PathOf("depth") + ": max_height_m must be above min_height_m");
  }
  r.Section("face_cascade", [&](ConfigReader& f) {
    std::string cascade = p.face_cascade.cascade.string();
    f.Read("file", cascade);
    p.face_cascade.cascade = cascade;
    f.Read("min_size_px", p.face_cascade.min_size_px, 8, 1000);
  });
  r.Section("dnn", [&](ConfigReader& d) {
    std::string model;
    std::string config;
    std::string classes;
    d.Read("model", model);
    d.Read("config", config);
    d.Read("classes", classes);
    p.dnn.model = model;
    p.dnn.config = config;
    p.dnn.classes = classes;
    d.Read("input_size_px", p.dnn.input_size_px, 32, 2048);
    d.Read("transposed", p.dnn.transposed);
    d.Read("boxes_in_pixels", p.dnn.boxes_in_pixels);
    d.Read("min_score", p.dnn.min_score, 0.0, 1.0);
  });
  if (p.detector == PerceptionOptions::Detector::kDnn && (p.dnn.model.empty() || p.dnn.classes.empty())) {
    throw ConfigError(r.PathOf("dnn") + ": the dnn detector needs model and classes");
  }
  r.Section("sim", [&](ConfigReader& s) {
    s.Read("miss_rate", p.sim.miss_rate, 0.0, 1.0);
    s.Read("max_range_m", p.sim.max_range_m, 0.5, 50.0);
  });
}

void ReadFace(ConfigReader& r, FaceOptions& f) {
  face::ExpressionOptions& e = f.expression;
  r.Read("min_hold_s", e.min_hold_s, 0.0, 60.0);
  r.Read("sleepy_after_s", e.sleepy_after_s, 1.0, 86400.0);
  r.Read("greeting_every_s", e.greeting_every_s, 0.0, 86400.0);
  r.Read("excuse_me_after_s", e.excuse_me_after_s, 0.0, 600.0);
  const auto phrase = [&](const char* key, std::string& text) {
    r.Read(key, text);
    if (text.empty() || text.size() > 200) throw ConfigError(r.PathOf(key) + ": a phrase of 1 to 200 characters");
  };
  phrase("greeting", e.greeting_text);
  phrase("excuse_me", e.excuse_me_text);
  phrase("arrived", e.arrived_text);
  phrase("arrived_at", e.arrived_at_text);
  r.Section("events", [&](ConfigReader& v) {
    v.Read("person_left_after_s", f.events.person_left_after_s, 0.0, 600.0);
    v.Read("blocked_after_s", f.events.blocked_after_s, 0.0, 600.0);
    v.Read("battery_low_percent", f.events.battery_low_percent, 0.0, 100.0);
  });
  r.Section("voice", [&](ConfigReader& v) {
    v.Read("mute", f.mute);
    v.Read("name", f.voice.voice);
    v.Read("rate_wpm", f.voice.rate_wpm, 80, 450);
    v.Read("pitch", f.voice.pitch, 0, 100);
    v.Read("volume", f.voice.volume, 0, 200);
  });
}

void ReadWebhooks(ConfigReader& r, WebhookOptions& w) {
  r.Read("timeout_s", w.timeout_s, 0.1, 60.0);
  r.Read("max_attempts", w.max_attempts, 1, 100);
  r.Read("first_retry_s", w.first_retry_s, 0.0, 3600.0);
  r.Read("max_retry_s", w.max_retry_s, 0.0, 86400.0);
  r.Read("keep_deliveries", w.keep_deliveries, 1, 100000);
  r.Read("max_pending", w.max_pending, 1, 100000);
  r.Read("ca_file", w.ca_file);
  r.Read("robot", w.robot);
}

void ReadFleet(ConfigReader& r, FleetOptions& f) {
  r.Section("vda5050", [&](ConfigReader& v) {
    Vda5050Options& o = f.vda5050;
    v.Read("broker", o.broker);
    if (!o.broker.empty() && o.broker.rfind("mqtt://", 0) != 0 && o.broker.rfind("mqtts://", 0) != 0) {
      throw ConfigError(v.PathOf("broker") + ": must be an MQTT URL, mqtt://host:port or mqtts://host:port");
    }
    v.Read("interface_name", o.interface_name);
    v.Read("manufacturer", o.manufacturer);
    v.Read("serial_number", o.serial_number);
    // Topic levels: no MQTT wildcards or separators (the standard allows A-Z a-z 0-9 _ . : -).
    for (const auto& [key, value] :
         {std::pair{"interface_name", &o.interface_name}, std::pair{"manufacturer", &o.manufacturer},
          std::pair{"serial_number", &o.serial_number}}) {
      if (value->find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_.:-") !=
              std::string::npos ||
          (value->empty() && std::string(key) != "serial_number")) {
        throw ConfigError(v.PathOf(key) + ": letters, digits, '_', '.', ':' and '-' only");
      }
    }
    v.Read("qos", o.qos, 0, 2);
    v.Read("state_interval_s", o.state_interval_s, 1.0, 30.0);
    v.Read("visualization_hz", o.visualization_hz, 0.1, 10.0);
  });
}

void ReadRequestTemplate(ConfigReader& r, HttpRequestTemplate& t) {
  r.Read("method", t.method);
  static const std::set<std::string> kMethods = {"GET", "POST", "PUT", "PATCH", "DELETE"};
  if (!kMethods.contains(t.method)) throw ConfigError(r.PathOf("method") + ": one of GET, POST, PUT, PATCH, DELETE");
  r.Read("url", t.url);
  if (!t.url.empty() && t.url.rfind("http://", 0) != 0 && t.url.rfind("https://", 0) != 0) {
    throw ConfigError(r.PathOf("url") + ": an http:// or https:// URL");
  }
  r.Read("body", t.body);
}

Eigen::Vector2d ReadPoint(ConfigReader& r, const char* x, const char* y) {
  Eigen::Vector2d p = Eigen::Vector2d::Zero();
  r.Read(x, p.x(), -1e5, 1e5);
  r.Read(y, p.y(), -1e5, 1e5);
  return p;
}

void ReadHeaders(ConfigReader& r, std::vector<std::pair<std::string, std::string>>& headers) {
  r.List("headers", [&](ConfigReader& h) {
    std::pair<std::string, std::string> header;
    h.Read("name", header.first);
    h.Read("value", header.second);
    if (header.first.empty() || header.first.find_first_of(" :\r\n") != std::string::npos ||
        header.second.find_first_of("\r\n") != std::string::npos) {
      throw ConfigError(h.PathOf("name") + ": a header name and a value on one line");
    }
    headers.push_back(std::move(header));
  });
}

void ReadJsonPointer(ConfigReader& r, const char* key, std::string& pointer) {
  r.Read(key, pointer);
  if (!pointer.empty() && pointer.front() != '/') {
    throw ConfigError(r.PathOf(key) + ": a JSON pointer, starting with /");
  }
}

void ReadRmfMqtt(ConfigReader& r, RmfMqttOptions& o) {
  r.Section("mqtt", [&](ConfigReader& m) {
    m.Read("broker", o.broker);
    if (!o.broker.empty() && o.broker.rfind("mqtt://", 0) != 0 && o.broker.rfind("mqtts://", 0) != 0) {
      throw ConfigError(m.PathOf("broker") + ": must be an MQTT URL, mqtt://host:port or mqtts://host:port");
    }
    m.Read("prefix", o.prefix);
    m.Read("requester_id", o.requester_id);
    if (o.prefix.empty() || o.requester_id.empty()) throw ConfigError(m.PathOf("prefix") + ", requester_id: required");
  });
}

// What door and lift controllers share: the headers sent, how often the state is polled, one exchange's timeout,
// and the MQTT alternative to HTTP.
template <typename ControllerOptions>
void ReadControllerLink(ConfigReader& c, ControllerOptions& o) {
  ReadHeaders(c, o.headers);
  c.Read("poll_s", o.poll_s, 0.05, 60.0);
  c.Read("request_timeout_s", o.request_timeout_s, 0.1, 60.0);
  ReadRmfMqtt(c, o.mqtt);
}

void ReadBuilding(ConfigReader& r, BuildingOptions& b, nav::LiftOptions& ride, const fs::path& base) {
  r.Read("name", b.name);
  r.List("floors", [&](ConfigReader& item) {
    FloorOptions floor;
    item.Read("name", floor.name);
    ReadPath(item, "map", floor.map, base);
    if (floor.name.empty() || floor.map.empty()) throw ConfigError(item.PathOf("name") + ", map: required");
    b.floors.push_back(std::move(floor));
  });
  r.List("lifts", [&](ConfigReader& item) {
    nav::Lift lift;
    item.Read("id", lift.id);
    item.Read("car_width_m", lift.car_width_m, 0.5, 10.0);
    item.Read("car_depth_m", lift.car_depth_m, 0.5, 10.0);
    item.List("stops", [&](ConfigReader& s) {
      nav::LiftStop stop;
      s.Read("floor", stop.floor);
      stop.door.id = lift.id + "@" + stop.floor;
      stop.door.a = ReadPoint(s, "x1_m", "y1_m");
      stop.door.b = ReadPoint(s, "x2_m", "y2_m");
      double yaw_deg = 0.0;
      s.Read("lobby_x_m", stop.lobby.x_m, -1e5, 1e5);
      s.Read("lobby_y_m", stop.lobby.y_m, -1e5, 1e5);
      s.Read("lobby_yaw_deg", yaw_deg, -360.0, 360.0);
      stop.lobby.yaw_rad = nav::WrapAngle(yaw_deg * kDegToRad);
      lift.stops.push_back(std::move(stop));
    });
    b.lifts.push_back(std::move(lift));
  });
  r.Section("ride", [&](ConfigReader& s) {
    s.Read("call_timeout_s", ride.call_timeout_s, 1.0, 3600.0);
    s.Read("ride_timeout_s", ride.ride_timeout_s, 1.0, 3600.0);
    s.Read("empty_wait_s", ride.empty_wait_s, 1.0, 3600.0);
    s.Read("speed_mps", ride.speed_mps, 0.02, 1.0);
  });
  r.Section("controller", [&](ConfigReader& c) {
    LiftControllerOptions& o = b.controller;
    c.Section("call", [&](ConfigReader& t) { ReadRequestTemplate(t, o.call); });
    c.Section("state", [&](ConfigReader& t) { ReadRequestTemplate(t, o.state); });
    ReadJsonPointer(c, "floor_pointer", o.floor_pointer);
    ReadJsonPointer(c, "door_pointer", o.door_pointer);
    c.Read("door_open_value", o.door_open_value);
    c.Section("release", [&](ConfigReader& t) { ReadRequestTemplate(t, o.release); });
    ReadControllerLink(c, o);
  });
  r.Section("sim", [&](ConfigReader& s) {
    s.Read("travel_s", b.sim_travel_s, 0.0, 600.0);
    s.Read("floor_gap_m", b.sim_floor_gap_m, 1.0, 1000.0);
  });
  try {
    nav::Validate(BuildingOf(b));
  } catch (const std::invalid_argument& e) {
    throw ConfigError(r.PathOf("floors") + ": " + e.what());
  }
}

// A serial device: a path, and a baud rate a UART takes.
void ReadSerial(ConfigReader& r, fs::path& port, int& baud_rate, const fs::path& base) {
  ReadPath(r, "port", port, base);
  if (port.empty()) throw ConfigError(r.PathOf("port") + ": required (a serial device, e.g. /dev/ttyUSB0)");
  static const std::set<int> kRates = {9600, 19200, 38400, 57600, 115200, 230400, 256000, 460800, 921600, 1000000};
  r.Read("baud_rate", baud_rate);
  if (!kRates.contains(baud_rate)) {
    throw ConfigError(r.PathOf("baud_rate") + ": " + std::to_string(baud_rate) +
                      " is not a serial rate the drivers use");
  }
}

// A base on a serial port with wheel encoders (Create 2, Kobuki, TurtleBot 3, serial text): its port, wheels, limits
// (forward up to `top_speed_mps`, the device's own) and link timeouts, the keys the same for each. A base whose driver
// knows no wheels of its own (serial-text) requires them.
template <typename Options>
void ReadSerialBase(ConfigReader& s, Options& c, double top_speed_mps, const fs::path& base) {
  ReadSerial(s, c.port, c.baud_rate, base);
  const auto wheel = [&](const char* key, double& value, double min, double max) {
    const bool has_default = value > 0.0;
    s.Read(key, value);
    if (!has_default && value == 0.0) {
      throw ConfigError(s.PathOf(key) +
                        ": required with this driver (the base's own wheels: wheel_diameter_m, "
                        "track_m, counts_per_revolution)");
    }
    s.Check(key, value, min, max);
  };
  wheel("wheel_diameter_m", c.wheels.wheel_diameter_m, 0.01, 1.0);
  wheel("track_m", c.wheels.track_m, 0.05, 2.0);
  wheel("counts_per_revolution", c.wheels.counts_per_revolution, 1.0, 1e6);
  s.Read("max_linear_mps", c.max_linear_mps, 0.01, top_speed_mps);
  s.Read("max_angular_rps", c.max_angular_rps, 0.01, 10.0);
  s.Read("max_linear_accel_mps2", c.max_linear_accel_mps2, 0.01, 20.0);
  s.Read("max_angular_accel_rps2", c.max_angular_accel_rps2, 0.01, 50.0);
  s.Read("footprint_radius_m", c.footprint_radius_m, 0.05, 2.0);
  s.Read("command_timeout_s", c.command_timeout_s, 0.05, 5.0);
  s.Read("stale_s", c.stale_s, 0.02, 1.0);
  s.Read("silence_s", c.silence_s, c.stale_s, 10.0);
}

// The mounting pose of a device on the base (base frame): x_m, y_m forward and left of the base's centre, yaw_deg.
void ReadMount(ConfigReader& r, nav::Pose2& pose) {
  double yaw_deg = pose.yaw_rad / kDegToRad;
  r.Read("mount_x_m", pose.x_m, -2.0, 2.0);
  r.Read("mount_y_m", pose.y_m, -2.0, 2.0);
  r.Read("mount_yaw_deg", yaw_deg, -180.0, 180.0);
  pose.yaw_rad = yaw_deg * kDegToRad;
}

// A native depth camera's image, intrinsics and mounting (drivers/camera_mount.h).
void ReadCameraMount(ConfigReader& r, drivers::CameraMountOptions& c) {
  r.Read("width", c.width, 16, 4096);
  r.Read("height", c.height, 16, 4096);
  r.Read("fps", c.fps, 1, 120);
  r.Read("fx", c.fx, 0.0, 1e5);
  r.Read("fy", c.fy, 0.0, 1e5);
  r.Read("cx", c.cx, 0.0, 1e5);
  r.Read("cy", c.cy, 0.0, 1e5);
  r.Read("hfov_deg", c.hfov_deg, 1.0, 179.0);
  r.Read("vfov_deg", c.vfov_deg, 1.0, 179.0);
  r.Read("mount_x_m", c.mount_x_m, -2.0, 2.0);
  r.Read("mount_height_m", c.mount_height_m, 0.0, 3.0);
  r.Read("tilt_deg", c.tilt_deg, -90.0, 90.0);
  r.Read("min_range_m", c.min_range_m, 0.0, 5.0);
  r.Read("max_range_m", c.max_range_m, 0.5, 50.0);
  if ((c.fx > 0.0) != (c.fy > 0.0)) throw ConfigError(r.PathOf("fx") + ", fy: both or neither (a calibration)");
}

// A stereo calibration `key` made for the camera's views (c.width x c.height), or a ConfigError saying what it is for.
void CheckCalibrationSize(ConfigReader& s, const char* key, const drivers::stereo::StereoCalibration& calibration,
                          const drivers::stereo::StereoCameraOptions& c) {
  if (calibration.image_size == cv::Size(c.width, c.height)) return;
  throw ConfigError(s.PathOf(key) + ": made for " + std::to_string(calibration.image_size.width) + " x " +
                    std::to_string(calibration.image_size.height) + " px views, the camera's are " +
                    std::to_string(c.width) + " x " + std::to_string(c.height) + " (width, height)");
}

// devices.camera.pan with driver dynamixel (drivers/dynamixel/pan_servo.h, docs/hardware.md).
void ReadPanServo(ConfigReader& r, drivers::dynamixel::PanServoOptions& o, const fs::path& base) {
  ReadSerial(r, o.port, o.baud_rate, base);
  r.Read("id", o.id, 0, 252);
  r.Read("center_position", o.center_position, 0, 4095);
  r.Read("reversed", o.reversed);
  ReadPanMount(r, o.axis_x_m, o.axis_y_m, o.min_deg, o.max_deg, o.max_speed_dps);
  r.Read("max_accel_dps2", o.max_accel_dps2, 1.0, 100000.0);
  r.Read("poll_period_s", o.poll_period_s, 0.005, 0.5);
  r.Read("stale_s", o.stale_s, 0.02, 1.0);
  r.Read("silence_s", o.silence_s, o.stale_s + 0.01, 10.0);
}

// devices.camera with driver stereo: the device, its calibration (read and checked here) and the depth path's settings.
void ReadStereoCamera(ConfigReader& s, drivers::stereo::StereoCameraOptions& c, const fs::path& base) {
  using drivers::stereo::StereoLayout;
  using drivers::stereo::VideoFormat;
  s.ReadChoice<StereoLayout>("layout", c.layout,
                             {{"side-by-side", StereoLayout::kSideBySide}, {"two-cameras", StereoLayout::kTwoCameras}});
  s.Read("name", c.name);
  s.Read("node", c.node);
  s.Read("left_node", c.left_node);
  s.Read("right_node", c.right_node);
  if (c.layout == StereoLayout::kTwoCameras && (c.left_node.empty() || c.right_node.empty())) {
    throw ConfigError(s.PathOf("left_node") + ", right_node: required with two cameras (stable names, such as " +
                      "/dev/v4l/by-path/...: two cameras of one model share their name)");
  }
  s.ReadChoice<VideoFormat>("format", c.format, {{"mjpeg", VideoFormat::kMjpeg}, {"yuyv", VideoFormat::kYuyv}});
  s.Read("width", c.width, 16, 4096);
  s.Read("height", c.height, 16, 4096);
  s.Read("fps", c.fps, 1, 120);
  ReadPath(s, "calibration", c.calibration_file, base);
  if (c.calibration_file.empty()) {
    throw ConfigError(s.PathOf("calibration") + ": required (a file from corridor-stereo calibrate)");
  }
  try {
    c.calibration = drivers::stereo::LoadStereoCalibration(c.calibration_file);
  } catch (const drivers::stereo::StereoCalibrationError& e) {
    throw ConfigError(s.PathOf("calibration") + ": " + e.what());
  }
  CheckCalibrationSize(s, "calibration", c.calibration, c);
  // ASNS's wide baseline: a third camera and the left camera's calibration with it.
  s.Read("third_node", c.third_node);
  ReadPath(s, "wide_calibration", c.wide_calibration_file, base);
  if (c.third_node.empty() != c.wide_calibration_file.empty()) {
    throw ConfigError(s.PathOf("third_node") + ", wide_calibration: both or neither (a third camera and the " +
                      "calibration of the left camera with it)");
  }
  if (!c.wide_calibration_file.empty()) {
    try {
      c.wide_calibration = drivers::stereo::LoadStereoCalibration(c.wide_calibration_file);
    } catch (const drivers::stereo::StereoCalibrationError& e) {
      throw ConfigError(s.PathOf("wide_calibration") + ": " + e.what());
    }
    CheckCalibrationSize(s, "wide_calibration", *c.wide_calibration, c);
    if (c.wide_calibration->baseline_m() <= c.calibration.baseline_m()) {
      throw ConfigError(s.PathOf("wide_calibration") + ": its baseline must be longer than the pair's");
    }
  }
  ReadBaselineFusion(s, c.wide_disparities, c.fusion);
  s.Read("mount_x_m", c.mount_x_m, -2.0, 2.0);
  s.Read("mount_height_m", c.mount_height_m, 0.0, 3.0);
  s.Read("tilt_deg", c.tilt_deg, -90.0, 90.0);
  ReadStereoDepth(s, c.depth, c.width);
  s.Read("pair_tolerance_s", c.pair_tolerance_s, 0.001, 0.5);
  s.Read("stale_s", c.stale_s, 0.02, 1.0);
  s.Read("silence_s", c.silence_s, c.stale_s, 10.0);
}

void ReadDevices(ConfigReader& r, DevicesOptions& d, const fs::path& base) {
  using D = DeviceDriver;
  const auto driver = [](ConfigReader& s, DeviceDriver& value, std::vector<std::pair<std::string, D>> choices) {
    s.ReadChoice("driver", value, choices);
  };
  r.Section("base", [&](ConfigReader& s) {
    BaseSlotOptions& o = d.base;
    driver(s, o.driver,
           {{"sim", D::kSim},
            {"dds", D::kDds},
            {"create2", D::kCreate2},
            {"kobuki", D::kKobuki},
            {"turtlebot3", D::kTurtlebot3},
            {"serial-text", D::kSerialText}});
    if (o.driver == D::kDds) {
      s.Read("odom_topic", o.dds.odom_topic);
      s.Read("cmd_vel_topic", o.dds.cmd_vel_topic);
      CheckTopic(s, "odom_topic", o.dds.odom_topic);
      CheckTopic(s, "cmd_vel_topic", o.dds.cmd_vel_topic);
      s.Read("battery_topic", o.dds.battery_topic);
      if (!o.dds.battery_topic.empty()) CheckTopic(s, "battery_topic", o.dds.battery_topic);
      ReadBaseLimits(s, o.dds.limits, 5.0);
    } else if (o.driver == D::kCreate2) {
      ReadSerialBase(s, o.create2, 0.5, base);  // the OI's 500 mm/s a wheel
    } else if (o.driver == D::kKobuki) {
      drivers::kobuki::KobukiOptions& k = o.kobuki;
      ReadSerialBase(s, k, 0.7, base);
      s.Read("battery_empty_v", k.battery_empty_v, 5.0, 30.0);
      s.Read("battery_full_v", k.battery_full_v, k.battery_empty_v + 0.1, 30.0);
    } else if (o.driver == D::kTurtlebot3) {
      ReadSerialBase(s, o.turtlebot3, 0.26, base);  // the Waffle Pi's top speed; the Burger's is 0.22
    } else if (o.driver == D::kSerialText) {
      drivers::serial_text::SerialTextOptions& t = o.serial_text;
      ReadSerialBase(s, t, 2.0, base);
      s.Read("pid_rate_hz", t.pid_rate_hz, 1.0, 1000.0);
      s.Read("poll_period_s", t.poll_period_s, 0.005, 0.5);
      s.Read("boot_s", t.boot_s, 0.1, 30.0);
    }
  });
  r.Section("laser", [&](ConfigReader& s) {
    LaserSlotOptions& o = d.laser;
    driver(s, o.driver,
           {{"sim", D::kSim},
            {"dds", D::kDds},
            {"rplidar", D::kRplidar},
            {"hokuyo", D::kHokuyo},
            {"lds", D::kLds},
            {"none", D::kNone}});
    if (o.driver == D::kDds) {
      s.Read("topic", o.dds.topic);
      if (o.dds.topic.empty()) throw ConfigError(s.PathOf("topic") + ": required with driver dds (e.g. /scan)");
      CheckTopic(s, "topic", o.dds.topic);
      ReadMount(s, o.dds.base_T_laser);
      s.Read("mount_height_m", o.dds.height_m, 0.0, 3.0);
    } else if (o.driver == D::kRplidar) {
      drivers::rplidar::RplidarOptions& l = o.rplidar;
      ReadSerial(s, l.port, l.baud_rate, base);
      ReadMount(s, l.base_T_laser);
      s.Read("mount_height_m", l.height_m, 0.0, 3.0);
      s.ReadChoice<drivers::rplidar::ScanMode>(
          "scan", l.scan_mode,
          {{"standard", drivers::rplidar::ScanMode::kStandard}, {"express", drivers::rplidar::ScanMode::kExpress}});
      s.Read("beams", l.sweep.bins, 8, 8192);
      s.Read("min_range_m", l.sweep.range_min_m, 0.0, 10.0);
      s.Read("max_range_m", l.sweep.range_max_m, 0.5, 100.0);
      s.Read("stale_s", l.stale_s, 0.02, 1.0);
      s.Read("silence_s", l.silence_s, l.stale_s, 10.0);
    } else if (o.driver == D::kLds) {
      drivers::lds::LdsOptions& l = o.lds;
      s.ReadChoice<drivers::lds::Model>(
          "model", l.model, {{"lds-02", drivers::lds::Model::kLds02}, {"lds-01", drivers::lds::Model::kLds01}});
      // The LDS-01 measures to 3.5 m; the LDS-02 to 8 m.
      if (l.model == drivers::lds::Model::kLds01) l.sweep.range_max_m = 3.5;
      ReadSerial(s, l.port, l.baud_rate, base);
      ReadMount(s, l.base_T_laser);
      s.Read("mount_height_m", l.height_m, 0.0, 3.0);
      s.Read("min_range_m", l.sweep.range_min_m, 0.0, 10.0);
      s.Read("max_range_m", l.sweep.range_max_m, 0.5, 100.0);
      s.Read("stale_s", l.stale_s, 0.02, 1.0);
      s.Read("silence_s", l.silence_s, l.stale_s, 10.0);
    } else if (o.driver == D::kHokuyo) {
      drivers::hokuyo::HokuyoOptions& h = o.hokuyo;
      s.Read("port", h.port);
      if (h.port.empty()) {
        throw ConfigError(s.PathOf("port") + ": required (a serial device, e.g. /dev/ttyACM0, or host:port, e.g. " +
                          "192.168.0.10:10940)");
      }
      if (drivers::IsNetworkPort(h.port)) {
        if (!drivers::NetworkPortNumber(h.port)) {
          throw ConfigError(s.PathOf("port") + ": '" + h.port + "': " + h.port.substr(h.port.rfind(':') + 1) +
                            " is not a TCP port");
        }
      } else {
        h.port = (base / h.port).lexically_normal().string();  // a path relative to the configuration's directory
      }
      s.Read("baud_rate", h.baud_rate, 9600, 1000000);
      ReadMount(s, h.base_T_laser);
      s.Read("mount_height_m", h.height_m, 0.0, 3.0);
      s.Read("min_range_m", h.min_range_m, 0.0, 10.0);
      s.Read("max_range_m", h.max_range_m, 0.5, 100.0);
      s.Read("stale_s", h.stale_s, 0.0, 1.0);
      s.Read("silence_s", h.silence_s, std::max(h.stale_s, 0.1), 10.0);
    }
  });
  r.Section("camera", [&](ConfigReader& s) {
    CameraSlotOptions& o = d.camera;
    driver(s, o.driver,
           {{"sim", D::kSim},
            {"dds", D::kDds},
            {"realsense", D::kRealsense},
            {"openni2", D::kOpenni2},
            {"stereo", D::kStereo},
            {"none", D::kNone}});
    if (o.driver == D::kRealsense) {
      drivers::realsense::RealSenseOptions& c = o.realsense;
      s.Read("name", c.name);
      s.Read("depth_node", c.depth_node);
      s.Read("color_node", c.color_node);
      ReadCameraMount(s, c.camera);
      s.Read("depth_scale_m", c.depth_scale_m, 1e-5, 0.01);
      s.Read("stale_s", c.stale_s, 0.02, 1.0);
      s.Read("silence_s", c.silence_s, c.stale_s, 10.0);
    } else if (o.driver == D::kStereo) {
      ReadStereoCamera(s, o.stereo, base);
    } else if (o.driver == D::kOpenni2) {
      drivers::openni2::OpenNi2Options& c = o.openni2;
      s.Read("uri", c.uri);
      s.Read("color", c.color);
      ReadCameraMount(s, c.camera);
      s.Read("stale_s", c.stale_s, 0.02, 1.0);
      s.Read("silence_s", c.silence_s, c.stale_s, 10.0);
    } else if (o.driver == D::kDds) {
      drivers::dds::DdsCameraOptions& c = o.dds;
      s.Read("depth_topic", c.depth_topic);
      s.Read("info_topic", c.info_topic);
      s.Read("color_topic", c.color_topic);
      CheckTopic(s, "depth_topic", c.depth_topic);
      CheckTopic(s, "info_topic", c.info_topic);
      CheckTopic(s, "color_topic", c.color_topic);
      s.Read("mount_x_m", c.mount_x_m, -2.0, 2.0);
      s.Read("mount_height_m", c.mount_height_m, 0.0, 3.0);
      s.Read("tilt_deg", c.tilt_deg, -90.0, 90.0);
      s.Read("min_range_m", c.min_range_m, 0.0, 5.0);
      s.Read("max_range_m", c.max_range_m, 0.5, 50.0);
      s.Read("info_wait_s", o.info_wait_s, 0.5, 600.0);
    }
    s.Section("pan", [&](ConfigReader& p) {
      p.ReadChoice("driver", o.pan_driver, {{"none", D::kNone}, {"sim", D::kSim}, {"dynamixel", D::kDynamixel}});
      if (o.pan_driver == D::kDynamixel) ReadPanServo(p, o.pan, base);
    });
    if (o.pan_driver != D::kNone && o.driver == D::kNone) {
      throw ConfigError(s.PathOf("pan.driver") + ": a pan servo with no camera on it");
    }
    if ((o.pan_driver == D::kSim) != (o.driver == D::kSim) && o.pan_driver != D::kNone) {
      throw ConfigError(s.PathOf("pan.driver") + ": " + ToString(o.pan_driver) + " with a " + ToString(o.driver) +
                        " camera: the simulator's pan servo turns only the simulator's camera");
    }
  });
  // The simulator's robot is all of the devices or none of them (less a camera or a laser it is built without).
  const bool sim_base = d.base.driver == D::kSim;
  if (sim_base ? (d.camera.driver != D::kSim && d.camera.driver != D::kNone) : d.camera.driver == D::kSim) {
    throw ConfigError(r.PathOf("camera.driver") + ": " + ToString(d.camera.driver) + " with a " +
                      ToString(d.base.driver) + " base: the simulator's camera rides only on the simulator's base");
  }
  if (sim_base ? (d.laser.driver != D::kSim && d.laser.driver != D::kNone) : d.laser.driver == D::kSim) {
    throw ConfigError(r.PathOf("laser.driver") + ": " + ToString(d.laser.driver) + " with a " +
                      ToString(d.base.driver) + " base: the simulator's laser rides only on the simulator's base");
  }
  if (d.camera.driver == D::kNone && d.laser.driver == D::kNone) {
    throw ConfigError(r.PathOf("camera.driver") + ": none with no laser either: the robot needs a depth camera or a " +
                      "laser to see");
  }
}

void ReadDds(ConfigReader& r, DdsOptions& d, const fs::path& base) {
  r.Read("enabled", d.enabled);
  r.Read("domain_id", d.domain_id, -1, 232);
  r.Read("peers", d.peers);
  r.Read("interfaces", d.interfaces);
  r.Read("allow_writes", d.allow_writes);
  r.Read("camera_hz", d.camera_hz, 0.0, 30.0);
  r.Read("cmd_vel_topic", d.cmd_vel_topic);
  RefuseMoved(r, "devices", "devices.base, devices.laser and devices.camera with driver: dds");
  r.Section("security", [&](ConfigReader& s) {
    ReadPath(s, "enclave", d.security_enclave, base);
    if (d.security_enclave.empty()) return;
    if (const std::string file = drivers::dds::UnreadableEnclaveFile(d.security_enclave); !file.empty()) {
      throw ConfigError(s.PathOf("enclave") + ": " + file + " is missing or unreadable (make an enclave with " +
                        "tools/dds-keystore or ros2 security create_enclave)");
    }
  });
  CheckTopic(r, "cmd_vel_topic", d.cmd_vel_topic);
  for (const std::string& peer : d.peers) {
    if (!drivers::dds::IsIpv4Address(peer)) {
      throw ConfigError(r.PathOf("peers") + ": '" + peer + "' is not an IPv4 address");
    }
  }
}

void ReadDoors(ConfigReader& r, DoorsOptions& d, nav::DoorOptions& passing) {
  r.Read("request_m", passing.request_m, 0.5, 50.0);
  r.Read("hold_m", passing.hold_m, 0.2, 5.0);
  r.Read("release_m", passing.release_m, 0.0, 10.0);
  r.Read("timeout_s", passing.timeout_s, 1.0, 3600.0);
  try {
    nav::Validate(passing);
  } catch (const std::invalid_argument& e) {
    throw ConfigError(r.PathOf("request_m") + ", hold_m: " + e.what());
  }
  r.Section("controller", [&](ConfigReader& c) {
    DoorControllerOptions& o = d.controller;
    c.Section("open", [&](ConfigReader& t) { ReadRequestTemplate(t, o.open); });
    c.Section("state", [&](ConfigReader& t) { ReadRequestTemplate(t, o.state); });
    ReadJsonPointer(c, "open_pointer", o.open_pointer);
    c.Read("open_value", o.open_value);
    c.Section("release", [&](ConfigReader& t) { ReadRequestTemplate(t, o.release); });
    ReadControllerLink(c, o);
  });
  r.List("list", [&](ConfigReader& item) {
    DoorPlace door;
    item.Read("id", door.id);
    item.Read("map", door.map);
    if (door.id.empty() || door.map.empty()) throw ConfigError(item.PathOf("id") + ", map: required");
    door.from = ReadPoint(item, "x1_m", "y1_m");
    door.to = ReadPoint(item, "x2_m", "y2_m");
    d.list.push_back(std::move(door));
  });
}

void ReadTracking(ConfigReader& r, TrackingOptions& t) {
  nav::MovingObjectOptions& o = t.objects;
  r.Read("enabled", t.enabled);
  r.Read("camera", t.camera);
  r.Read("window_scans", o.window_scans, 2, 100);
  r.Read("cluster_distance_m", o.cluster_distance_m, 0.01, 2.0);
  r.Read("time_scale_mps", o.time_scale_mps, 0.01, 10.0);
  r.Read("min_points", o.min_points, 2, 10000);
  r.Read("moving_speed_mps", o.moving_speed_mps, 0.0, 5.0);
  r.Read("map_clearance_m", o.map_clearance_m, 0.0, 1.0);
  r.Read("range_m", o.range_m, 0.5, 100.0);
  r.Read("coast_s", o.coast_s, 0.0, 10.0);
  r.Read("unseen_coast_s", o.unseen_coast_s, 0.0, 60.0);
  if (o.unseen_coast_s < o.coast_s) {
    throw ConfigError(r.PathOf("unseen_coast_s") +
                      ": must be at least coast_s (someone out of the camera's view is not forgotten sooner than "
                      "someone in it)");
  }
  r.Read("merged_hold_s", o.merged_hold_s, 0.0, 60.0);
  if (o.merged_hold_s < o.coast_s) {
    throw ConfigError(r.PathOf("merged_hold_s") +
                      ": must be at least coast_s (someone walking beside another is not forgotten sooner than "
                      "someone hidden)");
  }
  r.Read("walk_end_memory_s", o.walk_end_memory_s, 0.0, 86400.0);
  r.Section("traffic", [&](ConfigReader& s) {
    s.Read("weight", t.traffic.weight, 0.0, 100.0);
    s.Read("lane_half_width_m", t.traffic.lane_half_width_m, 0.0, 5.0);
    s.Read("memory_s", t.traffic.memory_s, 1.0, 86400.0);
  });
}

// The network of the configured policy from `weights` (section `section`'s key), checked by `check`; a missing or
// unfit file is a ConfigError naming the key.
std::shared_ptr<const nav::Mlp> ReadNetwork(ConfigReader& r, const char* section, nav::LocalPolicyKind policy,
                                            const fs::path& weights,
                                            const std::function<void(const nav::Mlp&)>& check) {
  const std::string key = r.PathOf(section) + ".weights";
  if (weights.empty()) throw ConfigError(key + ": required with policy " + nav::ToString(policy));
  try {
    auto net = std::make_shared<nav::Mlp>(nav::Mlp::Load(weights));
    check(*net);
    return net;
  } catch (const std::exception& e) {
    throw ConfigError(key + ": " + e.what());
  }
}

void ReadMission(ConfigReader& r, nav::MissionRunnerOptions& mission, const fs::path& base) {
  using Policy = nav::LocalPolicyKind;
  r.ReadChoice<Policy>("policy", mission.policy,
                       {{"morp-rb", Policy::kMorpRb},
                        {"voxel-reactive", Policy::kVoxelReactive},
                        {"morp-il", Policy::kMorpIl},
                        {"takiguchi", Policy::kTakiguchi},
                        {"flmc", Policy::kFlmc}});
  nav::LocalNavigatorOptions& navigator = mission.navigator;
  nav::FollowerOptions& o = navigator.follower;
  r.Read("k_rho", o.gains.k_rho, -100.0, 100.0);
  r.Read("k_alpha", o.gains.k_alpha, -100.0, 100.0);
  r.Read("k_beta", o.gains.k_beta, -100.0, 100.0);
  try {
    nav::ValidateGains(o.gains);
  } catch (const std::invalid_argument& e) {
    throw ConfigError(r.PathOf("k_rho") + ", k_alpha, k_beta: " + e.what() +
                      " (the polar controller would not converge)");
  }
  r.Read("lookahead_m", o.lookahead_m, 0.05, 5.0);
  r.Read("approach_m", o.approach_m, 0.05, 5.0);
  r.Read("max_linear_mps", o.max_linear_mps, 0.01, 3.0);
  r.Read("max_angular_rps", o.max_angular_rps, 0.01, 6.0);
  r.Read("max_linear_accel_mps2", o.max_linear_accel_mps2, 0.01, 10.0);
  r.Read("position_tolerance_m", o.position_tolerance_m, 0.001, 1.0);
  double yaw_tolerance_deg = o.yaw_tolerance_rad / kDegToRad;
  r.Read("yaw_tolerance_deg", yaw_tolerance_deg, 0.1, 45.0);
  o.yaw_tolerance_rad = yaw_tolerance_deg * kDegToRad;
  r.Read("replan_distance_m", navigator.replan_distance_m, 0.1, 100.0);
  r.Read("reroute_s", navigator.reroute_s, 0.0, 600.0);
  r.Read("stuck_s", navigator.stuck_s, 0.0, 600.0);
  r.Section("avoid", [&](ConfigReader& a) { ReadAvoid(a, navigator.avoid); });
  r.Section("evade", [&](ConfigReader& e) { ReadEvade(e, navigator.evade); });
  // MORP-IL's network is read only when it drives.
  fs::path weights;
  r.Section("morp_il", [&](ConfigReader& m) {
    ReadPath(m, "weights", weights, base);
    m.Read("history", navigator.il.history, 1, 20);
    m.Read("scale_linear_mps", navigator.il.max_linear_mps, 0.01, 3.0);
    m.Read("scale_angular_rps", navigator.il.max_angular_rps, 0.01, 6.0);
  });
  if (mission.policy == Policy::kMorpIl) {
    navigator.learned = ReadNetwork(r, "morp_il", mission.policy, weights,
                                    [&](const nav::Mlp& net) { nav::CheckMorpIlNetwork(net, navigator.il); });
  }
  fs::path direction_weights;
  r.Section("takiguchi", [&](ConfigReader& t) {
    ReadPath(t, "weights", direction_weights, base);
    t.Read("speed_mps", navigator.takiguchi.max_linear_mps, 0.01, 3.0);
    t.Read("rays", navigator.takiguchi.rays, 3, 10000);
    double field_deg = navigator.takiguchi.field_rad * 180.0 / std::numbers::pi;
    t.Read("field_deg", field_deg, 1.0, 360.0);
    navigator.takiguchi.field_rad = field_deg * std::numbers::pi / 180.0;
  });
  // ASNS's fuzzy controllers: their rule bases (FLL files; none: corridor's own) are read and built here, so that one
  // that cannot run stops start-up naming its key.
  r.Section("flmc", [&](ConfigReader& f) {
    nav::FlmcOptions& fuzzy = navigator.flmc;
    f.Read("stop_within_m", fuzzy.stop_within_m, 0.0, 1.0);
    f.Read("rotate_within_m", fuzzy.rotate_within_m, 0.0, 5.0);
    double rotate_above_deg = fuzzy.rotate_above_rad * 180.0 / std::numbers::pi;
    f.Read("rotate_above_deg", rotate_above_deg, 0.0, 180.0);
    fuzzy.rotate_above_rad = rotate_above_deg * std::numbers::pi / 180.0;
    f.Read("avoid_within_m", fuzzy.avoid_within_m, 0.0, 5.0);
    for (const auto& [key, text] :
         {std::pair{"motion_rules", &fuzzy.motion_fll}, std::pair{"avoidance_rules", &fuzzy.avoidance_fll},
          std::pair{"rotation_rules", &fuzzy.rotation_fll}}) {
      fs::path file;
      ReadPath(f, key, file, base);
      if (file.empty()) continue;
      std::ifstream in(file);
      std::stringstream contents;
      contents << in.rdbuf();
      if (!in) throw ConfigError(f.PathOf(key) + ": " + file.string() + ": cannot be read");
      *text = contents.str();
    }
  });
  navigator.flmc.max_linear_mps = o.max_linear_mps;
  navigator.flmc.max_angular_rps = o.max_angular_rps;
  if (mission.policy == Policy::kFlmc) {
    try {
      nav::Flmc check(navigator.flmc);
    } catch (const std::invalid_argument& e) {
      throw ConfigError(r.PathOf("flmc") + ": " + e.what());
    }
  }
  if (mission.policy == Policy::kTakiguchi) {
    navigator.direction = ReadNetwork(r, "takiguchi", mission.policy, direction_weights, [&](const nav::Mlp& net) {
      nav::CheckTakiguchiNetwork(net, navigator.takiguchi);
    });
  }
}

drivers::sim::StaticObstacle ReadObstacle(ConfigReader& r) {
  drivers::sim::StaticObstacle o;
  std::string shape = "cylinder";
  r.Read("shape", shape);
  const auto parsed = drivers::sim::ShapeFromName(shape);
  if (!parsed) throw ConfigError(r.PathOf("shape") + ": must be cylinder, box or table");
  o.shape = *parsed;
  r.Read("x_m", o.center.x(), -1e5, 1e5);
  r.Read("y_m", o.center.y(), -1e5, 1e5);
  r.Read("size_m", o.size_m, 0.01, 10.0);
  r.Read("height_m", o.height_m, 0.01, 10.0);
  double yaw_deg = 0.0;
  r.Read("yaw_deg", yaw_deg, -360.0, 360.0);
  o.yaw_rad = yaw_deg * kDegToRad;
  return o;
}

void ReadDocking(ConfigReader& r, nav::DockingOptions& o, nav::ChargingOptions& charging) {
  r.Read("width_m", o.dock.width_m, 0.05, 2.0);
  r.Read("face_distance_m", o.dock.face_distance_m, 0.01, 2.0);
  r.Read("staging_distance_m", o.dock.staging_distance_m, 0.1, 5.0);
  r.Read("max_speed_mps", o.max_speed_mps, 0.01, 0.5);
  r.Read("position_tolerance_m", o.position_tolerance_m, 0.001, 0.1);
  double yaw_tolerance_deg = o.yaw_tolerance_rad / kDegToRad;
  r.Read("yaw_tolerance_deg", yaw_tolerance_deg, 0.1, 10.0);
  o.yaw_tolerance_rad = yaw_tolerance_deg * kDegToRad;
  r.Read("blind_distance_m", o.blind_distance_m, 0.05, 3.0);
  r.Read("timeout_s", o.timeout_s, 5.0, 600.0);
  r.Read("charge_below_percent", charging.charge_below_percent, 0.0, 100.0);
  r.Read("retry_s", charging.retry_s, 10.0, 86400.0);
  try {
    nav::Validate(o);
  } catch (const std::invalid_argument& e) {
    throw ConfigError(r.PathOf("staging_distance_m") + ", blind_distance_m, face_distance_m: " + e.what());
  }
}

void ReadSim(ConfigReader& r, SimulatorOptions& o, const fs::path& base) {
  RefuseMoved(r, "enabled",
              "devices.base.driver (sim, or dds, create2, kobuki, turtlebot3 or serial-text for the robot's own base)");
  ReadPath(r, "world", o.world, base);
  drivers::sim::WorldOptions& w = o.world_options;
  r.Read("wall_height_m", w.wall_height_m, 0.1, 20.0);
  r.Read("collision_resolution_m", w.collision_resolution_m, 0.01, 0.5);
  r.Read("collision_min_height_m", w.collision_min_height_m, 0.0, 1.0);
  r.Read("collision_max_height_m", w.collision_max_height_m, 0.1, 5.0);
  drivers::sim::SimOptions& s = o.robot;
  r.Section("start", [&](ConfigReader& p) {
    double yaw_deg = s.start.yaw_rad / kDegToRad;
    p.Read("x_m", s.start.x_m, -1e5, 1e5);
    p.Read("y_m", s.start.y_m, -1e5, 1e5);
    p.Read("yaw_deg", yaw_deg, -360.0, 360.0);
    s.start.yaw_rad = yaw_deg * kDegToRad;
  });
  r.Read("physics_rate_hz", s.physics_rate_hz, 10.0, 2000.0);
  r.Read("odometry_rate_hz", s.odometry_rate_hz, 1.0, 1000.0);
  r.Read("seed", s.seed);
  r.Section("base", [&](ConfigReader& b) { ReadBase(b, s.base); });
  r.Section("camera", [&](ConfigReader& c) {
    ReadCamera(c, s.camera);
    c.Section("stereo", [&](ConfigReader& t) { ReadSimStereo(t, s.stereo, s.camera.width); });
    c.Section("pan", [&](ConfigReader& t) { ReadSimPan(t, s.pan); });
  });
  r.Section("laser", [&](ConfigReader& l) { ReadLaser(l, s.laser); });
  r.List("obstacles", [&](ConfigReader& item) { o.obstacles.push_back(ReadObstacle(item)); });
  r.Read("pedestrians", o.pedestrians, 0, 20);
  r.Read("pedestrians_within_m", o.pedestrians_within_m, 2.0, 100.0);
  r.Section("crowd", [&](ConfigReader& c) {
    c.Read("radius_m", s.crowd.radius_m, 0.05, 1.0);
    c.Read("preferred_speed_mps", s.crowd.preferred_speed_mps, 0.0, 3.0);
    c.Read("max_speed_mps", s.crowd.max_speed_mps, 0.0, 5.0);
    c.Read("time_horizon_s", s.crowd.time_horizon_s, 0.1, 20.0);
    c.Read("see_robot", s.crowd.see_robot);
  });
  r.Section("battery", [&](ConfigReader& b) {
    drivers::sim::SimBatteryOptions& battery = s.battery;
    b.Read("capacity_wh", battery.capacity_wh, 0.001, 10000.0);
    b.Read("initial_percent", battery.initial_percent, 0.0, 100.0);
    b.Read("idle_w", battery.idle_w, 0.0, 1000.0);
    b.Read("drive_w_per_mps", battery.drive_w_per_mps, 0.0, 1000.0);
    b.Read("turn_w_per_rps", battery.turn_w_per_rps, 0.0, 1000.0);
    b.Read("charge_w", battery.charge_w, 0.0, 5000.0);
  });
  r.Section("dock", [&](ConfigReader& d) {
    bool enabled = false;
    d.Read("enabled", enabled);
    drivers::sim::SimDockOptions dock;
    double yaw_deg = 0.0;
    d.Read("x_m", dock.pose.x_m, -1e5, 1e5);
    d.Read("y_m", dock.pose.y_m, -1e5, 1e5);
    d.Read("yaw_deg", yaw_deg, -360.0, 360.0);
    dock.pose.yaw_rad = nav::WrapAngle(yaw_deg * kDegToRad);
    if (enabled) s.dock = dock;
  });
  r.List("doors", [&](ConfigReader& item) {
    drivers::sim::SimDoorOptions door;
    item.Read("id", door.id);
    if (door.id.empty()) throw ConfigError(item.PathOf("id") + ": required");
    door.from = ReadPoint(item, "x1_m", "y1_m");
    door.to = ReadPoint(item, "x2_m", "y2_m");
    item.Read("open", door.open);
    s.doors.push_back(std::move(door));
  });
}

// What the devices ask of the rest of the configuration.
void CheckDevices(const Config& config) {
  const DevicesOptions& d = config.devices;
  const bool any_dds = d.base.driver == DeviceDriver::kDds || d.laser.driver == DeviceDriver::kDds ||
                       d.camera.driver == DeviceDriver::kDds;
  if (any_dds && !config.dds.enabled) {
    throw ConfigError("devices: a driver dds needs dds.enabled (the robot's ROS 2 drivers are reached over DDS)");
  }
  if (d.base.driver == DeviceDriver::kDds && config.dds.allow_writes &&
      config.dds.cmd_vel_topic == d.base.dds.cmd_vel_topic) {
    throw ConfigError("dds.cmd_vel_topic: '" + config.dds.cmd_vel_topic + "' is the base's own command topic " +
                      "(devices.base.cmd_vel_topic): give ROS 2 tools another, e.g. /corridor/cmd_vel");
  }
  if (!Simulated(config) && config.map.file.empty() && config.building.floors.empty()) {
    throw ConfigError("map.file: required with the robot's own devices (a ROS map_server map of where it works)");
  }
  // A native camera's frame period longer than the gate's patience would never let the robot drive forward.
  for (const auto& [driver, fps] : {std::pair{DeviceDriver::kRealsense, d.camera.realsense.camera.fps},
                                    std::pair{DeviceDriver::kOpenni2, d.camera.openni2.camera.fps},
                                    std::pair{DeviceDriver::kStereo, d.camera.stereo.fps}}) {
    if (d.camera.driver == driver && 1.0 / fps >= config.safety.depth_timeout_s) {
      throw ConfigError("devices.camera.fps: frames every " + std::to_string(1.0 / fps) +
                        " s are always older than safety.depth_timeout_s: raise the rate or the timeout");
    }
  }
  if (Simulated(config)) {
    if (config.sim.world.empty() && config.building.floors.empty()) {
      throw ConfigError("sim.world: required with the simulator's devices (unless building.floors are its world)");
    }
    // A frame period longer than the gate's patience would never let the robot drive forward.
    if (d.camera.driver == DeviceDriver::kSim &&
        1.0 / config.sim.robot.camera.rate_hz >= config.safety.depth_timeout_s) {
      throw ConfigError("sim.camera.rate_hz: frames every " + std::to_string(1.0 / config.sim.robot.camera.rate_hz) +
                        " s are always older than safety.depth_timeout_s: raise the rate or the timeout");
    }
    if (d.laser.driver == DeviceDriver::kSim && 1.0 / config.sim.robot.laser.rate_hz >= config.safety.laser_timeout_s) {
      throw ConfigError("sim.laser.rate_hz: scans every " + std::to_string(1.0 / config.sim.robot.laser.rate_hz) +
                        " s are always older than safety.laser_timeout_s: raise the rate or the timeout");
    }
  }
}

}  // namespace

// The floors' names and maps (by their files' stems), and the lifts, for the mission runner.
nav::Building BuildingOf(const BuildingOptions& o) {
  nav::Building b;
  b.name = o.name;
  for (const FloorOptions& f : o.floors) b.floors.push_back({f.name, f.map.stem().string()});
  b.lifts = o.lifts;
  return b;
}

std::string SimMapName(const Config& config) {
  if (!config.building.floors.empty()) return config.building.floors.front().map.stem().string();
  if (!config.map.file.empty()) return config.map.file.stem().string();
  return config.sim.world.stem().string();
}

const char* ToString(DeviceDriver driver) {
  switch (driver) {
    case DeviceDriver::kSim: return "sim";
    case DeviceDriver::kDds: return "dds";
    case DeviceDriver::kCreate2: return "create2";
    case DeviceDriver::kKobuki: return "kobuki";
    case DeviceDriver::kTurtlebot3: return "turtlebot3";
    case DeviceDriver::kSerialText: return "serial-text";
    case DeviceDriver::kRplidar: return "rplidar";
    case DeviceDriver::kHokuyo: return "hokuyo";
    case DeviceDriver::kLds: return "lds";
    case DeviceDriver::kRealsense: return "realsense";
    case DeviceDriver::kOpenni2: return "openni2";
    case DeviceDriver::kStereo: return "stereo";
    case DeviceDriver::kDynamixel: return "dynamixel";
    case DeviceDriver::kNone: return "none";
  }
  return "unknown";
}

void ApplyDerivedOptions(Config& config) {
  // The simulator's laser is fitted when the laser's slot takes it; the gate wants fresh scans from any laser.
  config.sim.robot.laser.enabled = config.devices.laser.driver == DeviceDriver::kSim;
  config.sim.robot.pan.enabled = config.devices.camera.pan_driver == DeviceDriver::kSim;
  config.safety.require_laser = config.devices.laser.driver != DeviceDriver::kNone;
  // MORP-RB and the comparison policy brake by the control loop's model.
  nav::LocalNavigatorOptions& navigator = config.mission.navigator;
  navigator.avoid.stopping = config.safety.stopping;
  navigator.avoid.front_offset_m = config.safety.front_offset_m;
  navigator.memory.robot_radius_m = config.safety.front_offset_m;
  // The planner keeps the guard's margin from what the camera saw (at a cost), so that it does not plan gaps the
  // guard refuses.
  config.planner.layer_margin_m = navigator.memory.margin_m;
  navigator.evade.robot_radius_m = config.safety.front_offset_m;
  navigator.evade.max_linear_mps = navigator.follower.max_linear_mps;
  navigator.safe.robot_radius_m = config.safety.front_offset_m;
  navigator.corridor_half_width_m = config.safety.corridor_half_width_m;
  nav::ReactiveOptions& reactive = config.mission.reactive;
  reactive.max_linear_mps = navigator.follower.max_linear_mps;
  reactive.front_offset_m = config.safety.front_offset_m;
  reactive.stopping = config.safety.stopping;
  // The simulated dock is the model the robot is configured for.
  if (config.sim.robot.dock) config.sim.robot.dock->geometry = config.mission.docking.dock;
}

YAML::Node ReadConfigYaml(const fs::path& file) {
  try {
    return YAML::LoadFile(file.string());
  } catch (const YAML::BadFile&) {
    throw ConfigError(file.string() + ": cannot be opened");
  } catch (const YAML::Exception& e) {
    throw ConfigError(file.string() + ": is not valid YAML: " + e.what());
  }
}

int DdsDomain(const DdsOptions& dds) {
  if (dds.domain_id >= 0) return dds.domain_id;
  const char* env = std::getenv("ROS_DOMAIN_ID");
  if (env == nullptr || *env == '\0') return 0;
  int domain = -1;
  const std::string text = env;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), domain);
  if (ec != std::errc() || end != text.data() + text.size() || domain < 0 || domain > 232) {
    throw ConfigError("ROS_DOMAIN_ID: must be a number within 0..232, got '" + text + "'");
  }
  return domain;
}

Config LoadConfig(const fs::path& file, const ConfigOverrides& overrides) {
  YAML::Node root = ReadConfigYaml(file);
  if (!root.IsMap()) throw ConfigError(file.string() + ": expected a mapping of sections");
  // Command-line overrides replace keys before reading so they get the same validation.
  const auto set = [&](const char* section, const char* key, const std::string& value) {
    if (!root[section] || root[section].IsNull()) root[section] = YAML::Node(YAML::NodeType::Map);
    root[section][key] = value;
  };
  if (overrides.port) set("server", "port", std::to_string(*overrides.port));
  if (overrides.state_dir) set("store", "state_dir", fs::absolute(*overrides.state_dir).string());
  if (overrides.map) set("map", "file", fs::absolute(*overrides.map).string());
  if (overrides.world) set("sim", "world", fs::absolute(*overrides.world).string());
  if (overrides.mqtt) {
    if (!root["fleet"] || root["fleet"].IsNull()) root["fleet"] = YAML::Node(YAML::NodeType::Map);
    YAML::Node fleet = root["fleet"];
    if (!fleet["vda5050"] || fleet["vda5050"].IsNull()) fleet["vda5050"] = YAML::Node(YAML::NodeType::Map);
    fleet["vda5050"]["broker"] = *overrides.mqtt;
  }
  Config config = ConfigFromYaml(root, file);
  config.file = fs::absolute(file);
  return config;
}

Config ConfigFromYaml(const YAML::Node& root, const fs::path& file, ConfigSchema* schema) {
  if (!root.IsMap()) throw ConfigError(file.string() + ": expected a mapping of sections");
  const fs::path base = fs::absolute(file).parent_path();
  Config config;
  try {
    ConfigReader r(root, "");
    r.Describe(schema);
    r.Section("server", [&](ConfigReader& s) { ReadServer(s, config.server, base); });
    r.Section("store", [&](ConfigReader& s) { ReadPath(s, "state_dir", config.store.state_dir, base); });
    r.Section("map", [&](ConfigReader& s) { ReadPath(s, "file", config.map.file, base); });
    r.Section("safety", [&](ConfigReader& s) { ReadSafety(s, config.safety); });
    r.Section("devices", [&](ConfigReader& s) { ReadDevices(s, config.devices, base); });
    r.Section("sim", [&](ConfigReader& s) { ReadSim(s, config.sim, base); });
    r.Section("ground", [&](ConfigReader& s) { ReadGround(s, config.ground); });
    r.Section("multi_view", [&](ConfigReader& s) { ReadMultiView(s, config.multi_view); });
    r.Section("gaze", [&](ConfigReader& s) { ReadGaze(s, config.gaze); });
    r.Section("planner", [&](ConfigReader& s) { ReadPlanner(s, config.planner); });
    r.Section("mission", [&](ConfigReader& s) { ReadMission(s, config.mission, base); });
    r.Section("docking", [&](ConfigReader& s) { ReadDocking(s, config.mission.docking, config.charging); });
    r.Section("tracking", [&](ConfigReader& s) { ReadTracking(s, config.tracking); });
    r.Section("localization", [&](ConfigReader& s) { ReadLocalization(s, config.localization); });
    r.Section("octomap", [&](ConfigReader& s) { ReadOctomap(s, config.octomap); });
    r.Section("perception", [&](ConfigReader& s) { ReadPerception(s, config.perception); });
    r.Section("face", [&](ConfigReader& s) { ReadFace(s, config.face); });
    r.Section("webhooks", [&](ConfigReader& s) { ReadWebhooks(s, config.webhooks); });
    r.Section("fleet", [&](ConfigReader& s) { ReadFleet(s, config.fleet); });
    r.Section("doors", [&](ConfigReader& s) { ReadDoors(s, config.doors, config.mission.doors); });
    r.Section("building", [&](ConfigReader& s) { ReadBuilding(s, config.building, config.mission.lifts, base); });
    r.Section("dds", [&](ConfigReader& s) { ReadDds(s, config.dds, base); });
    r.Section("auth", [&](ConfigReader& s) { ReadAuth(s, config.auth); });
    r.Section("log", [&](ConfigReader& s) {
      s.ReadChoice<std::string>(
          "level", config.log.level,
          {{"trace", "trace"}, {"debug", "debug"}, {"info", "info"}, {"warn", "warn"}, {"error", "error"}});
    });
    r.Finish();
    CheckDevices(config);
    // MORP-RB brakes by the control loop's model.
    ApplyDerivedOptions(config);
  } catch (const ConfigError& e) {
    throw ConfigError(file.string() + ": " + e.what());
  }
  if (config.store.state_dir.empty()) throw ConfigError(file.string() + ": store.state_dir: must not be empty");
  return config;
}

}  // namespace corridor::server
