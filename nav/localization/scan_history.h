// The last scans, each with the odometry it was taken at, merged into one scan in the robot's frame now.
//
// A narrow sensor (the depth camera's 85 degrees out to 4 m) sees too little of a building in one frame to be found
// in it by a search of the whole map: one wall fits anywhere. The frames of a turn, joined by the odometry (precise
// over a few metres and one turn), see the room around the robot, and that is what global relocalization searches
// for. A wide laser needs no history: its one scan is the view.
#pragma once

#include <deque>

#include "nav/geometry/pose2.h"
#include "nav/localization/range_scan.h"

namespace corridor::nav {

struct ScanHistoryOptions {
  double keep_every_m = 0.1;     // a scan is kept once the robot moved this far since the last one kept
  double keep_every_rad = 0.15;  // or turned this much
  double max_travel_m = 3.0;     // the kept scans span at most this much travel (odometry drifts beyond)
  double max_turn_rad = 7.0;     // and a little more than one turn
  double voxel_m = 0.05;         // the merged hits, at most one per square of this side
};

class ScanHistory {
 public:
  explicit ScanHistory(const ScanHistoryOptions& options = {}) : options_(options) {}

  // `scan` (base frame) was taken with the odometry at `odom`. Kept when the robot moved or turned enough since the
  // last scan kept; the oldest are dropped beyond the travel and turn spanned.
  void Add(const Pose2& odom, const RangeScan& scan);
  // Forgets every scan (the robot may have been carried elsewhere: what it saw before is not around it now).
  void Clear();

  // Every kept scan's hits in the frame of the robot at `odom`, thinned to one per voxel (newest first), with the
  // newest scan's origin. Hits only: the misses of scans from different places do not share one origin.
  RangeScan Merged(const Pose2& odom) const;
  // How much of the circle around the robot's present position the kept hits cover, in radians (0 to 2 pi), in
  // bins of 10 degrees.
  double CoveredAngle(const Pose2& odom) const;
  // How much the robot turned over the kept scans.
  double turned_rad() const { return turned_rad_; }
  std::size_t size() const { return scans_.size(); }

 private:
  struct Kept {
    Pose2 odom;
    RangeScan scan;
  };
  ScanHistoryOptions options_;
  std::deque<Kept> scans_;
  double turned_rad_ = 0.0;
};

// A narrow sensor's search of the whole map: what to do while the robot is lost.
struct NarrowViewSearchOptions {
  double min_covered_rad = 4.7;  // the history covers this much of the circle around the robot (270 degrees)
  double turn_rps = 0.8;         // else the robot turns on the spot this fast to see more, at most one turn
};
struct NarrowViewSearch {
  bool search = false;    // the history sees enough (or one turn saw all there is): search the map with it
  double turn_rps = 0.0;  // else turn on the spot this fast (0: stand still)
};
NarrowViewSearch PlanNarrowViewSearch(const ScanHistory& history, const Pose2& odom,
                                      const NarrowViewSearchOptions& options = {});

}  // namespace corridor::nav
