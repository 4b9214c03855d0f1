#include "nav/localization/scan_history.h"

#include <array>
#include <cmath>
#include <numbers>

namespace corridor::nav {
namespace {

// Travel and turn between two kept scans.
double Travel(const Pose2& a, const Pose2& b) { return (b.translation() - a.translation()).norm(); }
double Turn(const Pose2& a, const Pose2& b) { return std::abs(WrapAngle(b.yaw_rad - a.yaw_rad)); }

}  // namespace

void ScanHistory::Add(const Pose2& odom, const RangeScan& scan) {
  if (!scans_.empty()) {
    const Pose2& last = scans_.back().odom;
    if (Travel(last, odom) < options_.keep_every_m && Turn(last, odom) < options_.keep_every_rad) return;
  }
  scans_.push_back({odom, scan});
  double travel = 0.0;
  double turn = 0.0;
  for (std::size_t i = 1; i < scans_.size(); ++i) {
    travel += Travel(scans_[i - 1].odom, scans_[i].odom);
    turn += Turn(scans_[i - 1].odom, scans_[i].odom);
  }
  while (scans_.size() > 1 && (travel > options_.max_travel_m || turn > options_.max_turn_rad)) {
    travel -= Travel(scans_[0].odom, scans_[1].odom);
    turn -= Turn(scans_[0].odom, scans_[1].odom);
    scans_.pop_front();
  }
  turned_rad_ = turn;
}

void ScanHistory::Clear() {
  scans_.clear();
  turned_rad_ = 0.0;
}

RangeScan ScanHistory::Merged(const Pose2& odom) const {
  RangeScan merged;
  std::vector<Eigen::Vector2f> hits;
  const Pose2 now_T_odom = odom.Inverse();
  // Newest first: the voxel filter keeps the first point of a square, and the newest scan is the least drifted.
  for (auto it = scans_.rbegin(); it != scans_.rend(); ++it) {
    const Pose2 now_T_then = now_T_odom * it->odom;
    for (const Eigen::Vector2f& p : TransformPoints(now_T_then, it->scan.hits)) hits.push_back(p);
  }
  merged.hits = hits.empty() ? hits : VoxelFilter(hits, options_.voxel_m);
  if (!scans_.empty())
    merged.origin = (now_T_odom * scans_.back().odom).Transform(scans_.back().scan.origin.cast<double>()).cast<float>();
  return merged;
}

double ScanHistory::CoveredAngle(const Pose2& odom) const {
  constexpr int kBins = 36;
  std::array<bool, kBins> seen{};
  for (const Eigen::Vector2f& p : Merged(odom).hits) {
    const double bearing = std::atan2(p.y(), p.x()) + std::numbers::pi;  // 0 to 2 pi
    seen[static_cast<std::size_t>(std::min(kBins - 1, static_cast<int>(bearing / (2.0 * std::numbers::pi) * kBins)))] =
        true;
  }
  int covered = 0;
  for (const bool s : seen) covered += s;
  return 2.0 * std::numbers::pi * covered / kBins;
}

NarrowViewSearch PlanNarrowViewSearch(const ScanHistory& history, const Pose2& odom,
                                      const NarrowViewSearchOptions& options) {
  if (history.CoveredAngle(odom) >= options.min_covered_rad || history.turned_rad() >= 2.0 * std::numbers::pi) {
    return {true, 0.0};
  }
  return {false, options.turn_rps};
}

}  // namespace corridor::nav
