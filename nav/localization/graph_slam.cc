#include "nav/localization/graph_slam.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace corridor::nav {

GraphSlam::GraphSlam(const GraphSlamOptions& options, const Pose2& start)
    : options_(options), graph_(options.graph), last_local_(start) {}

Pose2 GraphSlam::AddScan(const RangeScan& scan, const Pose2& odom_pose) {
  Scan added;
  added.points = VoxelFilter(scan.hits, options_.match_voxel_m);
  // Local SLAM: odometry's prediction, matched into the fuller of the active submaps.
  const Pose2 previous_local = last_local_;
  const Pose2 odom_step = last_odom_ ? last_odom_->Inverse() * odom_pose : Pose2{};
  const double sigma_m =
      options_.odometry_sigma_floor_m + options_.odometry_sigma_per_m * odom_step.translation().norm();
  const double sigma_rad =
      options_.odometry_sigma_floor_rad + options_.odometry_sigma_per_rad * std::abs(odom_step.yaw_rad);
  Pose2 local = last_local_ * odom_step;
  if (!active_.empty()) {
    const Submap& target = *submaps_[active_.front()];
    const ScanMatch coarse = CorrelativeMatch(target.grid, added.points, local, options_.local_window);
    RefineOptions refine = options_.local_refine;
    refine.translation_weight = options_.prior_translation_scale / sigma_m;
    refine.rotation_weight = options_.prior_rotation_scale / sigma_rad;
    local = RefineMatch(target.grid, added.points, coarse.pose, local, refine);
  }
  last_odom_ = odom_pose;
  last_local_ = local;
  travel_since_search_m_ += (local.translation() - previous_local.translation()).norm();

  const bool moved = !last_inserted_ ||
                     (local.translation() - last_inserted_->translation()).norm() >= options_.insert_distance_m ||
                     std::abs(WrapAngle(local.yaw_rad - last_inserted_->yaw_rad)) >= options_.insert_angle_rad;
  const Pose2 global = LocalToGlobal(local);
  if (moved) {
    if (active_.empty() ||
        (active_.size() == 1 && submaps_[active_.back()]->inserted >= options_.scans_per_submap / 2)) {
      auto submap = std::make_unique<Submap>(Submap{HitField(options_.grid), local, 0, 0, nullptr});
      submap->node = graph_.AddNode(global);
      active_.push_back(static_cast<int>(submaps_.size()));
      submaps_.push_back(std::move(submap));
      ++stats_.submaps;
    }
    for (int i : active_) {
      submaps_[i]->grid.Insert(scan, local);
      ++submaps_[i]->inserted;
    }
    added.inserted = true;
    added.range = scan;
    last_inserted_ = local;
    ++stats_.inserted;
  }
  // Where the scan lies in each active submap ties it into the graph.
  added.node = graph_.AddNode(global);
  for (int i : active_) {
    const Submap& s = *submaps_[i];
    graph_.AddConstraint({s.node, added.node, s.local_origin.Inverse() * local, options_.submap_translation_weight,
                          options_.submap_rotation_weight, false});
  }
  if (!scans_.empty()) {
    graph_.AddConstraint({scans_.back().node, added.node, previous_local.Inverse() * local,
                          options_.motion_translation_weight, options_.motion_rotation_weight, false});
  }
  if (!active_.empty() && submaps_[active_.front()]->inserted >= options_.scans_per_submap) {
    active_.erase(active_.begin());
  }
  ++stats_.scans;
  if (++since_loop_search_ >= options_.loop_closure_every && travel_since_search_m_ >= options_.loop_search_travel_m) {
    since_loop_search_ = 0;
    travel_since_search_m_ = 0.0;
    SearchLoopClosures(added, global);
  }
  scans_.push_back(std::move(added));
  if (++since_optimized_ >= options_.optimize_every && new_loop_closures_) Optimize();
  return LocalToGlobal(local);
}

void GraphSlam::SearchLoopClosures(const Scan& scan, const Pose2& global_estimate) {
  if (scan.points.empty()) return;
  // The nearest finished submaps.
  std::vector<std::pair<double, int>> near;
  for (std::size_t i = 0; i < submaps_.size(); ++i) {
    if (std::find(active_.begin(), active_.end(), static_cast<int>(i)) != active_.end()) continue;
    const double d = (graph_.pose(submaps_[i]->node).translation() - global_estimate.translation()).norm();
    if (d <= options_.loop_search_radius_m) near.emplace_back(d, static_cast<int>(i));
  }
  const std::size_t count = std::min(near.size(), static_cast<std::size_t>(std::max(0, options_.loop_max_submaps)));
  std::partial_sort(near.begin(), near.begin() + static_cast<long>(count), near.end());
  const std::vector<Eigen::Vector2f> points = VoxelFilter(scan.points, options_.loop_voxel_m);
  for (std::size_t k = 0; k < count; ++k) {
    Submap& s = *submaps_[near[k].second];
    const Pose2 global_submap = graph_.pose(s.node);
    if (!s.matcher) s.matcher = std::make_unique<BranchAndBoundMatcher>(s.grid);
    // The guess in the submap's grid frame (the local SLAM frame the submap was built in).
    const Pose2 guess = s.local_origin * (global_submap.Inverse() * global_estimate);
    ++stats_.loop_searches;
    const std::optional<ScanMatch> found =
        s.matcher->Match(points, guess, options_.loop_window, options_.loop_min_score);
    if (!found) continue;
    const Pose2 refined = RefineMatch(s.grid, scan.points, found->pose, found->pose, options_.loop_refine);
    graph_.AddConstraint({s.node, scan.node, s.local_origin.Inverse() * refined, options_.loop_translation_weight,
                          options_.loop_rotation_weight, true});
    ++stats_.loop_closures;
    new_loop_closures_ = true;
  }
}

void GraphSlam::Optimize() {
  graph_.Optimize();
  ++stats_.optimizations;
  new_loop_closures_ = false;
  since_optimized_ = 0;
  if (!active_.empty()) {
    const Submap& newest = *submaps_[active_.back()];
    global_T_local_ = graph_.pose(newest.node) * newest.local_origin.Inverse();
  }
}

void GraphSlam::Finish() {
  if (new_loop_closures_) Optimize();
}

std::vector<Pose2> GraphSlam::Trajectory() const {
  std::vector<Pose2> out;
  out.reserve(scans_.size());
  for (const Scan& s : scans_) out.push_back(graph_.pose(s.node));
  return out;
}

OccupancyGrid GraphSlam::RenderMap(double resolution_m, const LogOddsOptions& options) const {
  std::vector<const RangeScan*> scans;
  std::vector<Pose2> poses;
  for (const Scan& s : scans_) {
    if (!s.inserted) continue;
    scans.push_back(&s.range);
    poses.push_back(graph_.pose(s.node));
  }
  return RenderScans(scans, poses, resolution_m, options);
}

OccupancyGrid RenderScans(std::span<const RangeScan* const> scans, std::span<const Pose2> poses, double resolution_m,
                          const LogOddsOptions& options) {
  if (scans.size() != poses.size()) throw std::invalid_argument("RenderScans: a pose for every scan");
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  for (std::size_t i = 0; i < scans.size(); ++i) {
    for (const auto* points : {&scans[i]->hits, &scans[i]->misses}) {
      for (const Eigen::Vector2f& p : *points) {
        const Eigen::Vector2d q = poses[i].Transform(p.cast<double>());
        lo = lo.cwiseMin(q);
        hi = hi.cwiseMax(q);
      }
    }
    lo = lo.cwiseMin(poses[i].translation());
    hi = hi.cwiseMax(poses[i].translation());
  }
  if (!(lo.array() <= hi.array()).all()) return OccupancyGrid(0, 0, resolution_m, Pose2{});
  lo.array() -= resolution_m;
  hi.array() += resolution_m;
  const int width = static_cast<int>(std::ceil((hi.x() - lo.x()) / resolution_m));
  const int height = static_cast<int>(std::ceil((hi.y() - lo.y()) / resolution_m));
  LogOddsGrid grid(width, height, resolution_m, Pose2{lo.x(), lo.y(), 0.0}, options);
  for (std::size_t i = 0; i < scans.size(); ++i) {
    const Pose2& pose = poses[i];
    const Eigen::Vector2d origin = pose.Transform(scans[i]->origin.cast<double>());
    for (const Eigen::Vector2f& p : scans[i]->hits) grid.IntegrateRay(origin, pose.Transform(p.cast<double>()), true);
    for (const Eigen::Vector2f& p : scans[i]->misses)
      grid.IntegrateRay(origin, pose.Transform(p.cast<double>()), false);
  }
  return grid.ToOccupancyGrid();
}

}  // namespace corridor::nav
