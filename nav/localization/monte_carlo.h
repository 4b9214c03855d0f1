// Monte Carlo localization in a known map, of the AMCL class (Thrun, Burgard and Fox, "Probabilistic Robotics",
// chapter 8; Fox, "Adapting the sample size in particle filters through KLD-sampling", IJRR 2003): particles moved by
// the odometry motion model (section 5.4) and weighted by the likelihood field of the map (section 6.4, from the map's
// distance field), resampled by low variance, their number adapted by KLD-sampling. A beam whose end is far from
// every wall (a person, a moved chair) costs no more than the random-measurement floor, so what is not on the map
// does not drag the estimate.
//
// The particles' mean is refined by scan matching against the map (CorrelativeMatch + RefineMatch), which is what is
// reported, and the health (ok | uncertain | lost) follows from the particles' spread and how much of the scan the map
// explains at the estimate. Global localization (Relocalize) searches the whole map by branch and bound for the scan
// and seeds the particles there.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <random>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "nav/localization/branch_and_bound.h"
#include "nav/localization/hit_field.h"
#include "nav/localization/range_scan.h"
#include "nav/map/occupancy_grid.h"

namespace corridor::nav {

enum class LocalizationHealth { kOk, kUncertain, kLost };
const char* ToString(LocalizationHealth health);

struct MonteCarloOptions {
  int min_particles = 300;
  int max_particles = 3000;
  // KLD-sampling: enough particles that the sampled distribution is within kld_error of the true one with
  // probability kld_quantile, histogrammed in bins of bin_m x bin_m x bin_rad.
  double kld_error = 0.05;
  double kld_z = 2.33;  // upper 0.99 quantile of the standard normal
  double bin_m = 0.1;
  double bin_rad = 0.1;
  // Odometry motion model (Thrun et al., table 5.6): standard deviations of sqrt(alpha * ...) per step.
  double alpha_rot_from_rot = 0.01;
  double alpha_rot_from_trans = 0.002;
  double alpha_trans_from_trans = 0.01;
  double alpha_trans_from_rot = 0.005;
  // The filter updates once the odometry moved this far or turned this much.
  double update_distance_m = 0.05;
  double update_angle_rad = 0.05;
  // After SetPose, the next scan is weighed whatever the motion, and while the robot stands still up to this many in
  // all (AMCL's "no-motion update"), so that a pose given to a robot standing still settles; each after the first
  // spreads the particles by settle_jitter_* first, so that weighing the same view again does not collapse them onto
  // a few. The first update from motion ends the settling.
  int settle_updates = 10;
  double settle_jitter_m = 0.01;
  double settle_jitter_rad = 0.005;
  // Likelihood field.
  double sigma_hit_m = 0.05;
  double z_hit = 0.9;
  double z_rand = 0.1;
  double max_range_m = 25.0;    // for the random-measurement density
  int max_beams = 90;           // beams used per update, spread evenly
  double beam_exponent = 0.25;  // each beam's log-likelihood counts this much (beams are not independent)
  // Scan matching refinement of the reported pose.
  bool refine = true;
  double refine_voxel_m = 0.05;
  // Health.
  double agree_distance_m = 0.15;  // a hit within this of a wall at the estimate agrees with the map
  double ok_agreement = 0.5;       // at least this fraction agrees, and the spread is below ok_spread
  double ok_spread_m = 0.2;
  double lost_agreement = 0.2;  // below this for lost_after scans in a row: lost (until ok_agreement for as many)
  int lost_after = 5;
  // Lost holds until a pose is given or a search finds the robot (Relocalize), however well the scans agree again: a
  // narrow view agrees by chance with walls at a wrong heading (a depth camera's, kidnapped in Willow Garage, agreed
  // 0.55-0.62 at 45 degrees off while the robot turned to look around).
  bool lost_until_found = false;
  // Also lost after this many scans in a row that agree less than ok_agreement (0: never). A narrow view carried
  // elsewhere often half-fits the walls it now sees, and would stay uncertain for ever.
  int doubtful_after = 0;
  // Also lost after lost_after scans in a row that agree less than lost_drop_ratio times the usual agreement (0:
  // never): an average of the agreement while ok, each ok scan weighing usual_agreement_rate, started afresh at
  // every new pose. A robot carried elsewhere while standing still sees walls that fit the map at its old pose by
  // chance, here and there (a fifth to a third of the scan, measured in Willow Garage): a fall from nearly all to that
  // is being lost, where a cluttered room that always agreed that little is not. The sudden fall of the measurement
  // likelihood is also what Augmented MCL reacts to (Thrun et al., table 8.3).
  double lost_drop_ratio = 0.5;
  double usual_agreement_rate = 0.02;
  int min_judged_hits = 10;  // a scan with fewer hits (a camera facing open floor) neither refines the pose
                             // nor counts towards lost or found: it says too little (ok becomes uncertain)
  // Global relocalization: the minimum mean probability of a match, and the particles seeded around it.
  double relocalize_min_score = 0.5;
  int relocalize_points = 80;            // the scan's hits searched with, at most
  double relocalize_resolution_m = 0.1;  // the whole map is searched at this cell size, then refined in the map's
  double relocalize_sigma_m = 0.1;
  double relocalize_sigma_rad = 0.05;
};

struct Particle {
  Pose2 pose;
  double weight = 0.0;
};

struct LocalizationEstimate {
  Pose2 pose;                                            // map frame
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  // of the particles, (x, y, yaw)
  LocalizationHealth health = LocalizationHealth::kUncertain;
  double agreement = 0.0;  // fraction of the last scan's hits within agree_distance_m of a wall
  int particles = 0;
};

class MonteCarloLocalization {
 public:
  // Localizes in `map` (occupied cells are walls). Throws std::invalid_argument for an empty map or bad options.
  MonteCarloLocalization(const OccupancyGrid& map, const MonteCarloOptions& options, std::uint64_t seed);
  ~MonteCarloLocalization();

  // Particles around `pose` with the given standard deviations (an initial pose, as RViz's "2D Pose Estimate").
  void SetPose(const Pose2& pose, double sigma_m = 0.2, double sigma_rad = 0.1);
  // Searches the whole map for `scan` (base frame) and seeds the particles at the best match. False (particles left
  // as they were, health lost) when nothing in the map matches well enough.
  bool Relocalize(const RangeScan& scan);

  // The robot's odometry read `odom_pose` when `scan` was taken. Moves the particles by the odometry since the last
  // call and, when it moved enough, weighs them by the scan and resamples. Returns the estimate.
  const LocalizationEstimate& Update(const Pose2& odom_pose, const RangeScan& scan);

  const LocalizationEstimate& estimate() const { return estimate_; }
  // The fraction of `hits` (base frame) within agree_distance_m of a wall with the robot at `pose` (map frame): how
  // well a scan fits the map there (0 for no hits).
  double AgreementAt(std::span<const Eigen::Vector2f> hits, const Pose2& pose) const { return Agreement(hits, pose); }
  std::span<const Particle> particles() const { return particles_; }
  const OccupancyGrid& map() const { return map_; }

 private:
  void Move(const Pose2& from, const Pose2& to);
  void Weigh(std::span<const Eigen::Vector2f> hits);
  void Resample();
  void Estimate(std::span<const Eigen::Vector2f> hits);
  void UpdateHealth(std::span<const Eigen::Vector2f> hits);
  double Agreement(std::span<const Eigen::Vector2f> hits, const Pose2& pose) const;
  // Calls visit(cell) for each of `points` (base frame) with the robot at `pose` (map frame): the row-major index of
  // the map cell it falls in, or -1 outside the map. One sine and cosine per call, not per point: the weighing of
  // every particle by every beam is the filter's hot loop.
  template <typename Visit>
  void ForEachCell(const Pose2& pose, std::span<const Eigen::Vector2f> points, Visit&& visit) const;

  OccupancyGrid map_;
  Pose2 origin_inverse_;  // the map's origin, inverted
  MonteCarloOptions options_;
  std::mt19937_64 random_;
  std::vector<float> distance_m_;    // per map cell: to the nearest wall (+inf beyond the march limit)
  std::vector<float> likelihood_;    // per map cell: the beam end density's log, floor included
  float unknown_likelihood_ = 0.0f;  // outside the map or in unknown cells
  HitField match_grid_;
  std::unique_ptr<BranchAndBoundMatcher> global_matcher_;  // built on the first relocalization
  std::vector<Particle> particles_;
  std::optional<Pose2> last_odom_;         // at the last call
  std::optional<Pose2> last_update_odom_;  // at the last filter update
  Pose2 update_pose_;                      // the estimate at the last filter update
  LocalizationEstimate estimate_;
  int forced_updates_ = 1;         // settling scans left (after SetPose: settle_updates)
  int bad_updates_ = 0;            // scans in a row that the map explains too little
  int good_updates_ = 0;           // and well
  int doubtful_updates_ = 0;       // scans in a row that agree less than ok_agreement
  int dropped_updates_ = 0;        // scans in a row that agree less than lost_drop_ratio x the usual
  double usual_agreement_ = -1.0;  // while ok, since the last new pose; negative: none yet
};

}  // namespace corridor::nav
