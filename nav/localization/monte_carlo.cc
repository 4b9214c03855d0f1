#include "nav/localization/monte_carlo.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <unordered_set>

#include "nav/localization/scan_matcher.h"
#include "nav/planner/distance_field.h"

namespace corridor::nav {
namespace {

// Fox 2003, eq. (11): particles needed so that, with probability given by z, the KL divergence between the sampled
// and the true distribution over k occupied bins stays below epsilon.
int KldBound(int k, double epsilon, double z) {
  if (k <= 1) return 1;
  const double a = 2.0 / (9.0 * (k - 1));
  const double b = 1.0 - a + std::sqrt(a) * z;
  return static_cast<int>(std::ceil((k - 1) / (2.0 * epsilon) * b * b * b));
}

std::uint64_t BinKey(const Pose2& p, double bin_m, double bin_rad) {
  const auto ix = static_cast<std::int64_t>(std::floor(p.x_m / bin_m));
  const auto iy = static_cast<std::int64_t>(std::floor(p.y_m / bin_m));
  const auto ia = static_cast<std::int64_t>(std::floor(p.yaw_rad / bin_rad));
  return (static_cast<std::uint64_t>(ix & 0x1FFFFF) << 42) | (static_cast<std::uint64_t>(iy & 0x1FFFFF) << 21) |
         static_cast<std::uint64_t>(ia & 0x1FFFFF);
}

// Beam ends spread evenly over the scan, at most max_beams.
std::vector<Eigen::Vector2f> SpreadBeams(std::span<const Eigen::Vector2f> hits, int max_beams) {
  if (static_cast<int>(hits.size()) <= max_beams) return {hits.begin(), hits.end()};
  std::vector<Eigen::Vector2f> out;
  out.reserve(max_beams);
  const double step = static_cast<double>(hits.size()) / max_beams;
  for (int i = 0; i < max_beams; ++i) out.push_back(hits[static_cast<std::size_t>(i * step)]);
  return out;
}

// The map at `factor` times coarser cells: occupied where any of its cells is, free where all are, else unknown.
OccupancyGrid Coarser(const OccupancyGrid& map, int factor) {
  const int w = (map.width() + factor - 1) / factor;
  const int h = (map.height() + factor - 1) / factor;
  OccupancyGrid out(w, h, map.resolution_m() * factor, map.origin(), kUnknownCell);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      bool occupied = false;
      bool all_free = true;
      for (int j = y * factor; j < std::min(map.height(), (y + 1) * factor); ++j) {
        for (int i = x * factor; i < std::min(map.width(), (x + 1) * factor); ++i) {
          const std::int8_t v = map.at({i, j});
          occupied |= v >= 65;
          all_free &= v == kFreeCell;
        }
      }
      out.at({x, y}) = occupied ? kOccupiedCell : all_free ? kFreeCell : kUnknownCell;
    }
  }
  return out;
}

}  // namespace

const char* ToString(LocalizationHealth health) {
  switch (health) {
    case LocalizationHealth::kOk: return "ok";
    case LocalizationHealth::kUncertain: return "uncertain";
    case LocalizationHealth::kLost: return "lost";
  }
  return "unknown";
}

MonteCarloLocalization::MonteCarloLocalization(const OccupancyGrid& map, const MonteCarloOptions& options,
                                               std::uint64_t seed)
    : map_(map),
      origin_inverse_(map.origin().Inverse()),
      options_(options),
      random_(seed),
      match_grid_(HitField::FromOccupancyGrid(map)) {
  if (map.width() == 0 || map.height() == 0) throw std::invalid_argument("localization: the map is empty");
  if (options.min_particles < 1 || options.max_particles < options.min_particles) {
    throw std::invalid_argument("localization: need 1 <= min_particles <= max_particles");
  }
  if (!(options.sigma_hit_m > 0.0) || !(options.z_hit > 0.0) || !(options.z_rand > 0.0) || options.max_beams < 1) {
    throw std::invalid_argument("localization: sigma_hit_m, z_hit, z_rand and max_beams must be positive");
  }
  std::vector<std::uint8_t> walls(map.cells().size());
  for (std::size_t i = 0; i < walls.size(); ++i) walls[i] = map.cells()[i] >= 65 ? 1 : 0;
  const double limit = std::max({4.0 * options.sigma_hit_m, options.agree_distance_m, 0.5}) + 0.1;
  distance_m_ =
      FastMarchingDistance(walls, map.width(), map.height(), map.resolution_m(), {.max_distance_m = limit}).distance_m;
  const double floor = options.z_rand / options.max_range_m;
  unknown_likelihood_ = static_cast<float>(std::log(floor));
  likelihood_.resize(distance_m_.size());
  for (std::size_t i = 0; i < distance_m_.size(); ++i) {
    const double d = distance_m_[i];
    const double p_hit = std::isfinite(d) ? std::exp(-d * d / (2.0 * options.sigma_hit_m * options.sigma_hit_m)) : 0.0;
    likelihood_[i] = static_cast<float>(std::log(options.z_hit * p_hit + floor));
  }
  SetPose(Pose2{}, 0.0, 0.0);
}

MonteCarloLocalization::~MonteCarloLocalization() = default;

template <typename Visit>
void MonteCarloLocalization::ForEachCell(const Pose2& pose, std::span<const Eigen::Vector2f> points,
                                         Visit&& visit) const {
  // The point in continuous cell units: (origin^-1 * pose * p) / resolution, as one affine map.
  const Pose2 grid_T_base = origin_inverse_ * pose;
  const auto scale = static_cast<float>(1.0 / map_.resolution_m());
  const float c = static_cast<float>(std::cos(grid_T_base.yaw_rad)) * scale;
  const float s = static_cast<float>(std::sin(grid_T_base.yaw_rad)) * scale;
  const float tx = static_cast<float>(grid_T_base.x_m) * scale;
  const float ty = static_cast<float>(grid_T_base.y_m) * scale;
  const int width = map_.width();
  const int height = map_.height();
  for (const Eigen::Vector2f& p : points) {
    const auto x = static_cast<int>(std::floor(tx + c * p.x() - s * p.y()));
    const auto y = static_cast<int>(std::floor(ty + s * p.x() + c * p.y()));
    const bool inside = x >= 0 && y >= 0 && x < width && y < height;
    visit(inside ? static_cast<std::ptrdiff_t>(y) * width + x : std::ptrdiff_t{-1});
  }
}

void MonteCarloLocalization::SetPose(const Pose2& pose, double sigma_m, double sigma_rad) {
  std::normal_distribution<double> normal(0.0, 1.0);
  const int n = std::max(options_.min_particles, std::min(options_.max_particles, 1000));
  particles_.assign(n, Particle{pose, 1.0 / n});
  for (Particle& p : particles_) {
    p.pose = {pose.x_m + sigma_m * normal(random_), pose.y_m + sigma_m * normal(random_),
              WrapAngle(pose.yaw_rad + sigma_rad * normal(random_))};
  }
  estimate_.pose = pose;
  estimate_.covariance = Eigen::Vector3d(sigma_m * sigma_m, sigma_m * sigma_m, sigma_rad * sigma_rad).asDiagonal();
  estimate_.particles = n;
  estimate_.health = LocalizationHealth::kUncertain;
  update_pose_ = pose;
  last_update_odom_ = last_odom_;
  forced_updates_ = std::max(1, options_.settle_updates);
  bad_updates_ = 0;
  good_updates_ = 0;
  doubtful_updates_ = 0;
  dropped_updates_ = 0;
  usual_agreement_ = -1.0;
}

bool MonteCarloLocalization::Relocalize(const RangeScan& scan) {
  // The search's cost grows with the points: a few dozen spread over the scan place it as well.
  const std::vector<Eigen::Vector2f> thinned = VoxelFilter(scan.hits, 2.0 * options_.refine_voxel_m);
  const std::vector<Eigen::Vector2f> points = SpreadBeams(thinned, options_.relocalize_points);
  // Coarse to fine: the whole map at relocalize_resolution_m (the search's cost falls with the cube of the cell size:
  // positions and headings), then the map's own cells around what it found.
  if (!global_matcher_) {
    const int factor =
        std::max(1, static_cast<int>(std::lround(options_.relocalize_resolution_m / map_.resolution_m())));
    HitFieldOptions coarse;
    coarse.sigma_m = map_.resolution_m() * factor;
    global_matcher_ = std::make_unique<BranchAndBoundMatcher>(
        HitField::FromOccupancyGrid(factor > 1 ? Coarser(map_, factor) : map_, coarse), 7);
  }
  const std::optional<ScanMatch> found = global_matcher_->MatchEverywhere(points, options_.relocalize_min_score);
  if (!found) {
    estimate_.health = LocalizationHealth::kLost;
    return false;
  }
  const double coarse_m = global_matcher_->resolution_m();
  const ScanMatch fine =
      CorrelativeMatch(match_grid_, thinned, found->pose, SearchWindow{coarse_m, 2.0 * coarse_m / 4.0});
  const Pose2 refined = RefineMatch(match_grid_, thinned, fine.pose, fine.pose);
  SetPose(refined, options_.relocalize_sigma_m, options_.relocalize_sigma_rad);
  return true;
}

void MonteCarloLocalization::Move(const Pose2& from, const Pose2& to) {
  const Pose2 step = from.Inverse() * to;
  const double trans = step.translation().norm();
  const double rot1 = trans > 0.01 ? std::atan2(step.y_m, step.x_m) : 0.0;
  const double rot2 = WrapAngle(step.yaw_rad - rot1);
  // Driving backwards is a turn of pi by this model's decomposition: its noise is that of the smaller turn.
  const auto turned = [](double a) { return std::min(std::abs(a), std::abs(std::numbers::pi - std::abs(a))); };
  const double r1 = turned(rot1);
  const double r2 = turned(rot2);
  const MonteCarloOptions& o = options_;
  const double sd_rot1 = std::sqrt(o.alpha_rot_from_rot * r1 * r1 + o.alpha_rot_from_trans * trans * trans);
  const double sd_trans =
      std::sqrt(o.alpha_trans_from_trans * trans * trans + o.alpha_trans_from_rot * (r1 * r1 + r2 * r2));
  const double sd_rot2 = std::sqrt(o.alpha_rot_from_rot * r2 * r2 + o.alpha_rot_from_trans * trans * trans);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (Particle& p : particles_) {
    const double a1 = rot1 + sd_rot1 * normal(random_);
    const double t = trans + sd_trans * normal(random_);
    const double a2 = rot2 + sd_rot2 * normal(random_);
    p.pose = p.pose * Pose2{t * std::cos(a1), t * std::sin(a1), a1 + a2};
  }
}

void MonteCarloLocalization::Weigh(std::span<const Eigen::Vector2f> hits) {
  std::vector<double> log_weights(particles_.size());
  double best = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    float sum = 0.0f;
    ForEachCell(particles_[i].pose, hits,
                [&](std::ptrdiff_t cell) { sum += cell < 0 ? unknown_likelihood_ : likelihood_[cell]; });
    log_weights[i] = std::log(std::max(particles_[i].weight, 1e-300)) + options_.beam_exponent * sum;
    best = std::max(best, log_weights[i]);
  }
  double total = 0.0;
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    particles_[i].weight = std::exp(log_weights[i] - best);
    total += particles_[i].weight;
  }
  for (Particle& p : particles_) p.weight /= total;
}

void MonteCarloLocalization::Resample() {
  // Resample only once the weights have grown uneven (effective sample size below half), as is usual.
  double sum_sq = 0.0;
  for (const Particle& p : particles_) sum_sq += p.weight * p.weight;
  if (1.0 / sum_sq > 0.5 * static_cast<double>(particles_.size())) return;
  std::vector<double> cumulative(particles_.size());
  double total = 0.0;
  for (std::size_t i = 0; i < particles_.size(); ++i) cumulative[i] = total += particles_[i].weight;
  std::uniform_real_distribution<double> uniform(0.0, total);
  std::vector<Particle> drawn;
  std::unordered_set<std::uint64_t> bins;
  int needed = options_.min_particles;
  // KLD-sampling: draw until the sample covers the occupied bins well enough.
  while (static_cast<int>(drawn.size()) < std::max(needed, options_.min_particles) &&
         static_cast<int>(drawn.size()) < options_.max_particles) {
    const auto it = std::lower_bound(cumulative.begin(), cumulative.end(), uniform(random_));
    const Particle& p = particles_[std::min<std::size_t>(it - cumulative.begin(), particles_.size() - 1)];
    drawn.push_back({p.pose, 1.0});
    if (bins.insert(BinKey(p.pose, options_.bin_m, options_.bin_rad)).second) {
      needed = KldBound(static_cast<int>(bins.size()), options_.kld_error, options_.kld_z);
    }
  }
  for (Particle& p : drawn) p.weight = 1.0 / static_cast<double>(drawn.size());
  particles_ = std::move(drawn);
}

double MonteCarloLocalization::Agreement(std::span<const Eigen::Vector2f> hits, const Pose2& pose) const {
  if (hits.empty()) return 0.0;
  int agree = 0;
  const auto agree_m = static_cast<float>(options_.agree_distance_m);
  ForEachCell(pose, hits, [&](std::ptrdiff_t cell) { agree += cell >= 0 && distance_m_[cell] <= agree_m; });
  return static_cast<double>(agree) / static_cast<double>(hits.size());
}

void MonteCarloLocalization::Estimate(std::span<const Eigen::Vector2f> hits) {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  double cos_sum = 0.0;
  double sin_sum = 0.0;
  for (const Particle& p : particles_) {
    mean += p.weight * p.pose.translation();
    cos_sum += p.weight * std::cos(p.pose.yaw_rad);
    sin_sum += p.weight * std::sin(p.pose.yaw_rad);
  }
  const double yaw = std::atan2(sin_sum, cos_sum);
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const Particle& p : particles_) {
    const Eigen::Vector3d d(p.pose.x_m - mean.x(), p.pose.y_m - mean.y(), WrapAngle(p.pose.yaw_rad - yaw));
    covariance += p.weight * d * d.transpose();
  }
  Pose2 pose{mean.x(), mean.y(), yaw};
  if (options_.refine && static_cast<int>(hits.size()) >= options_.min_judged_hits) {
    const std::vector<Eigen::Vector2f> points = VoxelFilter(hits, options_.refine_voxel_m);
    const ScanMatch coarse = CorrelativeMatch(match_grid_, points, pose, SearchWindow{0.1, 0.05});
    pose = RefineMatch(match_grid_, points, coarse.pose, pose);
  }
  estimate_.pose = pose;
  estimate_.covariance = covariance;
  estimate_.particles = static_cast<int>(particles_.size());
  UpdateHealth(hits);
}

void MonteCarloLocalization::UpdateHealth(std::span<const Eigen::Vector2f> hits) {
  if (static_cast<int>(hits.size()) < options_.min_judged_hits) {
    // Too little seen to tell: not ok (nothing confirms the pose), not lost either.
    if (estimate_.health == LocalizationHealth::kOk) estimate_.health = LocalizationHealth::kUncertain;
    return;
  }
  estimate_.agreement = Agreement(hits, estimate_.pose);
  const Eigen::Matrix3d& covariance = estimate_.covariance;
  const double spread = std::sqrt(covariance(0, 0) + covariance(1, 1));
  bad_updates_ = estimate_.agreement < options_.lost_agreement ? bad_updates_ + 1 : 0;
  // Lost holds until a pose is given or found, or the scans agree well again for as long as it took to get lost: a
  // narrow view agrees by chance with some wall now and then, which is not being found.
  good_updates_ = estimate_.agreement >= options_.ok_agreement ? good_updates_ + 1 : 0;
  doubtful_updates_ = estimate_.agreement < options_.ok_agreement ? doubtful_updates_ + 1 : 0;
  const bool dropped = options_.lost_drop_ratio > 0.0 && usual_agreement_ >= 0.0 &&
                       estimate_.agreement < options_.lost_drop_ratio * usual_agreement_;
  dropped_updates_ = dropped ? dropped_updates_ + 1 : 0;
  const bool stays_lost = estimate_.health == LocalizationHealth::kLost &&
                          (options_.lost_until_found || good_updates_ < options_.lost_after);
  const bool doubtful = options_.doubtful_after > 0 && doubtful_updates_ >= options_.doubtful_after;
  if (bad_updates_ >= options_.lost_after || dropped_updates_ >= options_.lost_after || doubtful || stays_lost) {
    estimate_.health = LocalizationHealth::kLost;
  } else if (estimate_.agreement >= options_.ok_agreement && spread <= options_.ok_spread_m) {
    estimate_.health = LocalizationHealth::kOk;
    usual_agreement_ = usual_agreement_ < 0.0 ? estimate_.agreement
                                              : usual_agreement_ + options_.usual_agreement_rate *
                                                                       (estimate_.agreement - usual_agreement_);
  } else {
    estimate_.health = LocalizationHealth::kUncertain;
  }
}

const LocalizationEstimate& MonteCarloLocalization::Update(const Pose2& odom_pose, const RangeScan& scan) {
  if (!last_update_odom_) last_update_odom_ = odom_pose;
  last_odom_ = odom_pose;
  const Pose2 since = last_update_odom_->Inverse() * odom_pose;
  const bool moved =
      since.translation().norm() >= options_.update_distance_m || std::abs(since.yaw_rad) >= options_.update_angle_rad;
  // The first scan after SetPose is weighed whatever the motion; the rest of the settling ones only while the robot
  // stands still, each after spreading the particles a little, so that weighing the same view again does not collapse
  // them onto a few. Once the robot moves, the usual updates take over.
  const bool first = forced_updates_ == std::max(1, options_.settle_updates);
  const bool still = since.translation().norm() < 0.001 && std::abs(since.yaw_rad) < 0.002;
  const bool settling = forced_updates_ > 0 && (first || still);
  if (!moved && !settling) {
    // Standing still the filter does not change, but whether the scans still fit the map does (a kidnapped robot).
    estimate_.pose = update_pose_ * since;
    UpdateHealth(scan.hits);
    return estimate_;
  }
  Move(*last_update_odom_, odom_pose);
  if (moved) {
    forced_updates_ = 0;
  } else {
    if (!first) {
      std::normal_distribution<double> normal(0.0, 1.0);
      for (Particle& p : particles_) {
        p.pose = {p.pose.x_m + options_.settle_jitter_m * normal(random_),
                  p.pose.y_m + options_.settle_jitter_m * normal(random_),
                  WrapAngle(p.pose.yaw_rad + options_.settle_jitter_rad * normal(random_))};
      }
    }
    --forced_updates_;
  }
  last_update_odom_ = odom_pose;
  const std::vector<Eigen::Vector2f> beams = SpreadBeams(scan.hits, options_.max_beams);
  Weigh(beams);
  Estimate(scan.hits);
  Resample();
  update_pose_ = estimate_.pose;
  return estimate_;
}

}  // namespace corridor::nav
