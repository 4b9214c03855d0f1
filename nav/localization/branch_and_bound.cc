#include "nav/localization/branch_and_bound.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace corridor::nav {

struct BranchAndBoundMatcher::Candidate {
  int angle = 0;  // index into the rotated scans
  int x = 0;      // offset in cells, the block's lower corner
  int y = 0;
  float score = 0.0f;
};

BranchAndBoundMatcher::BranchAndBoundMatcher(const HitField& grid, int depth)
    : resolution_m_(grid.resolution_m()), min_corner_(grid.min_corner()), width_(grid.width()), height_(grid.height()) {
  if (depth < 1) throw std::invalid_argument("BranchAndBoundMatcher: depth must be at least 1");
  const int w = grid.width();
  const int h = grid.height();
  // 0 beyond the grid, the grid's match values inside: scores are sums of them.
  // Level 0 is the grid; level h pools two blocks of level h - 1 along each axis: max over [x, x + 2^h) is the max of
  // the maxima over [x, x + 2^(h-1)) and [x + 2^(h-1), x + 2^h).
  Level base;
  base.width = w;
  base.height = h;
  base.max.resize(static_cast<std::size_t>(w) * h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) base.max[static_cast<std::size_t>(y) * w + x] = grid.match_value(x, y);
  }
  levels_.push_back(std::move(base));
  for (int level = 1; level < depth; ++level) {
    const Level& below = levels_.back();
    const int block = 1 << level;
    const int half = block / 2;
    Level out;
    out.offset = block - 1;
    out.width = w + block - 1;
    out.height = h + block - 1;
    out.max.resize(static_cast<std::size_t>(out.width) * out.height);
    for (int j = 0; j < out.height; ++j) {
      const int y = j - out.offset;
      for (int i = 0; i < out.width; ++i) {
        const int x = i - out.offset;
        out.max[static_cast<std::size_t>(j) * out.width + i] =
            std::max(std::max(below.at(x, y), below.at(x + half, y)),
                     std::max(below.at(x, y + half), below.at(x + half, y + half)));
      }
    }
    levels_.push_back(std::move(out));
  }
}

std::optional<ScanMatch> BranchAndBoundMatcher::Match(std::span<const Eigen::Vector2f> points, const Pose2& guess,
                                                      const SearchWindow& window, double min_score) const {
  const int cells = static_cast<int>(std::ceil(window.linear_m / resolution_m_));
  return Search(points, guess, cells, cells, window.angular_rad, min_score);
}

std::optional<ScanMatch> BranchAndBoundMatcher::MatchEverywhere(std::span<const Eigen::Vector2f> points,
                                                                double min_score) const {
  const double r = resolution_m_;
  const Eigen::Vector2d centre = min_corner_ + Eigen::Vector2d(width_, height_) * (r / 2.0);
  return Search(points, Pose2{centre.x(), centre.y(), 0.0}, (width_ + 1) / 2, (height_ + 1) / 2, std::numbers::pi,
                min_score);
}

std::optional<ScanMatch> BranchAndBoundMatcher::Search(std::span<const Eigen::Vector2f> points, const Pose2& centre,
                                                       int linear_cells_x, int linear_cells_y, double angular_rad,
                                                       double min_score) const {
  if (points.empty() || width_ == 0) return std::nullopt;
  const double r = resolution_m_;
  double far = 0.0;
  for (const Eigen::Vector2f& p : points) far = std::max(far, static_cast<double>(p.norm()));
  const double step = far > r ? std::acos(1.0 - r * r / (2.0 * far * far)) : 0.05;
  const int n_angles = static_cast<int>(std::ceil(angular_rad / step));
  // A full turn is searched once: the angles wrap.
  const int count = std::min(2 * n_angles + 1, static_cast<int>(std::ceil(2.0 * std::numbers::pi / step)));
  // Each angle's scan as cells relative to the centre's cell.
  std::vector<std::vector<CellIndex>> scans(count);
  std::vector<double> yaws(count);
  const int middle = count / 2;  // the angle index of the centre's heading
  for (int a = 0; a < count; ++a) {
    yaws[a] = centre.yaw_rad + (a - middle) * step;
    const double c = std::cos(yaws[a]);
    const double s = std::sin(yaws[a]);
    scans[a].reserve(points.size());
    for (const Eigen::Vector2f& p : points) {
      const Eigen::Vector2d q(c * p.x() - s * p.y() + centre.x_m, s * p.x() + c * p.y() + centre.y_m);
      scans[a].push_back(CellOf(q));
    }
  }
  const auto score = [&](const Candidate& k, int level) {
    const Level& pooled = levels_[level];
    float sum = 0.0f;
    for (const CellIndex& c : scans[k.angle]) sum += pooled.at(c.x + k.x, c.y + k.y);
    return sum / static_cast<float>(points.size());
  };
  // Top-level blocks tile the window.
  const int top = static_cast<int>(levels_.size()) - 1;
  const int block = 1 << top;
  std::vector<Candidate> candidates;
  for (int a = 0; a < count; ++a) {
    for (int y = -linear_cells_y; y <= linear_cells_y; y += block) {
      for (int x = -linear_cells_x; x <= linear_cells_x; x += block) {
        Candidate k{a, x, y, 0.0f};
        k.score = score(k, top);
        candidates.push_back(k);
      }
    }
  }
  std::sort(candidates.begin(), candidates.end(),
            [](const Candidate& a, const Candidate& b) { return a.score > b.score; });
  float best_score = static_cast<float>(min_score);
  std::optional<Candidate> best;
  // Depth first, best child first: a good candidate found early prunes most of the rest.
  const auto descend = [&](auto&& self, std::vector<Candidate>& level_candidates, int level) -> void {
    for (const Candidate& k : level_candidates) {
      if (k.score <= best_score) break;  // sorted: nothing after beats the best either
      if (level == 0) {
        best_score = k.score;
        best = k;
        continue;
      }
      const int half = 1 << (level - 1);
      std::vector<Candidate> children;
      children.reserve(4);
      for (int dy : {0, half}) {
        for (int dx : {0, half}) {
          Candidate child{k.angle, k.x + dx, k.y + dy, 0.0f};
          if (child.x > linear_cells_x || child.y > linear_cells_y) continue;
          child.score = score(child, level - 1);
          children.push_back(child);
        }
      }
      std::sort(children.begin(), children.end(),
                [](const Candidate& a, const Candidate& b) { return a.score > b.score; });
      self(self, children, level - 1);
    }
  };
  descend(descend, candidates, top);
  if (!best) return std::nullopt;
  return ScanMatch{Pose2{centre.x_m + best->x * r, centre.y_m + best->y * r, WrapAngle(yaws[best->angle])},
                   best->score};
}

}  // namespace corridor::nav
