#include "face/detect/tracker.h"

#include <algorithm>
#include <limits>

namespace corridor::face {

double IntersectionOverUnion(const cv::Rect2d& a, const cv::Rect2d& b) {
  const double inter = (a & b).area();
  const double uni = a.area() + b.area() - inter;
  return uni > 0.0 ? inter / uni : 0.0;
}

void Tracker::Assign(std::vector<Detection>& detections, const nav::Pose2& world_T_base, drivers::TimeNs now_ns) {
  std::erase_if(tracks_, [&](const Track& t) { return now_ns - t.seen_ns > drivers::FromSeconds(options_.forget_s); });
  std::vector<bool> taken(tracks_.size(), false);
  for (Detection& d : detections) {
    std::optional<Eigen::Vector2d> world;
    if (d.position) world = world_T_base.Transform(d.position->head<2>());
    // The best free track of the same label: nearest by position, else most overlapping by box.
    int best = -1;
    double best_cost = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < tracks_.size(); ++i) {
      const Track& t = tracks_[i];
      if (taken[i] || t.label != d.label) continue;
      double cost = std::numeric_limits<double>::infinity();
      if (world && t.position) {
        const double dist = (*world - *t.position).norm();
        if (dist <= options_.gate_m) cost = dist;
      } else if (d.box && t.box) {
        const double iou = IntersectionOverUnion(*d.box, *t.box);
        if (iou >= options_.min_iou) cost = 1.0 - iou;
      }
      if (cost < best_cost) {
        best_cost = cost;
        best = static_cast<int>(i);
      }
    }
    if (best < 0) {
      tracks_.push_back({next_id_++, d.label, std::nullopt, std::nullopt, now_ns});
      taken.push_back(false);
      best = static_cast<int>(tracks_.size()) - 1;
    }
    Track& t = tracks_[static_cast<std::size_t>(best)];
    taken[static_cast<std::size_t>(best)] = true;
    t.position = world;
    t.box = d.box;
    t.seen_ns = now_ns;
    d.track_id = t.id;
  }
}

}  // namespace corridor::face
