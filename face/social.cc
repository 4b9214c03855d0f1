#include "face/social.h"

#include <algorithm>
#include <cmath>

namespace corridor::face {

SocialCues SocialSense::Update(const std::vector<Detection>& detections, double speed_mps, double turn_rps,
                               drivers::TimeNs now_ns) {
  SocialCues cues;
  double nearest = options_.gaze_m;
  for (const Detection& d : detections) {
    if (!d.position) continue;
    const Eigen::Vector2d p = d.position->head<2>();
    const double range = p.norm();
    const double bearing = std::atan2(p.y(), p.x());
    const bool ahead = std::abs(bearing) <= options_.ahead_half_angle_rad;
    if (d.label == "face") {
      cues.looking |= range <= options_.looking_m;
      continue;
    }
    if (d.label != "person") continue;
    cues.near |= ahead && range <= options_.near_m;
    cues.blocking |= range <= options_.blocking_m && std::abs(bearing) <= options_.blocking_half_angle_rad;
    if (range < nearest) {
      nearest = range;
      cues.gaze_rad = bearing;
      cues.gaze_at_person = true;
    }
    // Someone who stands near in front, tracked, for a while.
    if (d.track_id == 0) continue;
    auto [it, fresh] = standing_.try_emplace(d.track_id, Standing{p, now_ns, now_ns});
    Standing& s = it->second;
    if (!fresh && (p - s.where).norm() > options_.standing_radius_m) s = {p, now_ns, now_ns};
    s.seen_ns = now_ns;
    cues.looking |=
        ahead && range <= options_.near_m && now_ns - s.since_ns >= drivers::FromSeconds(options_.standing_s);
  }
  // Forget people not seen for a while.
  std::erase_if(standing_, [&](const auto& e) { return now_ns - e.second.seen_ns > drivers::FromSeconds(2.0); });
  if (!cues.gaze_at_person) {
    // The way it is turning: as a driver looks into a bend.
    cues.gaze_rad = std::atan2(turn_rps, std::max(std::abs(speed_mps), 0.3));
  }
  cues.gaze_rad = std::clamp(cues.gaze_rad, -options_.max_gaze_rad, options_.max_gaze_rad);
  return cues;
}

}  // namespace corridor::face
