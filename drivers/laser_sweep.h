// Revolutions of a rotating laser (RPLIDAR, LDS) assembled into scans. Such a device reports its measurements one by
// one, clockwise seen from above (angle 0 forward), and marks where a revolution begins; a LaserScan is counter-
// clockwise (REP-103), one beam per bin: SweepAssembler turns one into the other.
#pragma once

#include <optional>
#include <vector>

#include "drivers/laser2d.h"

namespace corridor::drivers {

// One measurement of a rotating laser.
struct SweepPoint {
  bool start = false;       // the first measurement of a new revolution
  int quality = 0;          // the device's own measure (RPLIDAR: 0..63; LDS: the intensity), 0: it saw nothing
  double angle_deg = 0.0;   // clockwise from the device's forward
  double distance_m = 0.0;  // 0: none
};

struct SweepOptions {
  int bins = 360;             // the scan's beams over the full turn, counter-clockwise from forward
  double range_min_m = 0.15;  // nearer measurements are dropped (inside the housing)
  double range_max_m = 12.0;  // farther ones too
  int min_quality = 1;        // measurements of lower quality are dropped (0: the device saw nothing)
  int min_points = 50;        // a sweep with fewer measurements is not a scan (the motor still spinning up)
};

// Revolutions from measurements: each with the start flag ends the sweep before it. A sweep becomes a LaserScan
// (counter-clockwise from forward, REP-103) of `bins` beams, each the nearest good measurement in it, +infinity
// where there is none, with its timing: clockwise from forward over the time since the sweep before ended (none for
// the first, or after a gap of a second).
class SweepAssembler {
 public:
  // Throws std::invalid_argument for options that cannot work.
  explicit SweepAssembler(const SweepOptions& options = {});
  // The scan the point completes, stamped `stamp_ns` (when the sweep's last byte arrived), or nothing.
  std::optional<LaserScan> Add(const SweepPoint& point, TimeNs stamp_ns);

 private:
  LaserScan Finish(TimeNs stamp_ns);

  SweepOptions options_;
  std::vector<float> ranges_;
  int points_ = 0;
  bool started_ = false;     // a start flag was seen: the sweep under way is whole
  TimeNs last_end_ns_ = -1;  // when the sweep under way began (the last start flag)
};

}  // namespace corridor::drivers
