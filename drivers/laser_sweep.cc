#include "drivers/laser_sweep.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace corridor::drivers {

SweepAssembler::SweepAssembler(const SweepOptions& options) : options_(options) {
  if (options.bins < 4 || !(options.range_min_m >= 0.0) || !(options.range_max_m > options.range_min_m)) {
    throw std::invalid_argument("laser sweep: need bins >= 4 and 0 <= range_min_m < range_max_m");
  }
  ranges_.assign(static_cast<std::size_t>(options.bins), std::numeric_limits<float>::infinity());
}

std::optional<LaserScan> SweepAssembler::Add(const SweepPoint& point, TimeNs stamp_ns) {
  std::optional<LaserScan> scan;
  if (point.start) {
    if (started_ && points_ >= options_.min_points) scan = Finish(stamp_ns);
    last_end_ns_ = stamp_ns;
    std::fill(ranges_.begin(), ranges_.end(), std::numeric_limits<float>::infinity());
    points_ = 0;
    started_ = true;
  }
  if (!started_) return scan;  // the rest of a revolution begun before the first start flag
  ++points_;
  if (point.quality < options_.min_quality || point.distance_m < options_.range_min_m ||
      point.distance_m > options_.range_max_m) {
    return scan;
  }
  // Clockwise from forward in the device; counter-clockwise from -pi in the scan.
  const double angle = -point.angle_deg * std::numbers::pi / 180.0;
  const double increment = 2.0 * std::numbers::pi / options_.bins;
  const long index = std::lround((angle + std::numbers::pi) / increment);
  const auto bin = static_cast<std::size_t>(((index % options_.bins) + options_.bins) % options_.bins);
  ranges_[bin] = std::min(ranges_[bin], static_cast<float>(point.distance_m));
  return scan;
}

LaserScan SweepAssembler::Finish(TimeNs stamp_ns) {
  LaserScan scan;
  scan.stamp_ns = stamp_ns;
  scan.angle_min_rad = -std::numbers::pi;
  scan.angle_increment_rad = 2.0 * std::numbers::pi / options_.bins;
  scan.range_min_m = options_.range_min_m;
  scan.range_max_m = options_.range_max_m;
  scan.ranges = ranges_;
  // The sweep began where the one before ended, at the device's forward, and turned clockwise: the forward beam, which
  // holds what was measured just either side of forward, is taken as the first (the turn begins half a beam left of
  // it, so that no beam sits where it ends).
  const double since_s = last_end_ns_ >= 0 ? ToSeconds(stamp_ns - last_end_ns_) : 0.0;
  scan.sweep_s = since_s > 0.0 && since_s < 1.0 ? since_s : 0.0;
  scan.sweep_start_rad = 0.5 * scan.angle_increment_rad;
  scan.sweep_clockwise = true;
  return scan;
}

}  // namespace corridor::drivers
