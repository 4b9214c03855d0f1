#include "nav/planner/frontiers.h"

#include <cmath>
#include <limits>
#include <queue>
#include <vector>

#include <opencv2/imgproc.hpp>

namespace corridor::nav {
namespace {

constexpr int kNone = -1;
constexpr float kUnreached = std::numeric_limits<float>::infinity();

bool Free(std::int8_t v) { return v >= 0 && v < 50; }
bool Occupied(std::int8_t v) { return v >= 50; }

// The eight neighbours' offsets and step lengths (cells).
struct Step {
  int dx;
  int dy;
  float length;
};
constexpr Step kSteps[] = {{1, 0, 1.0f},    {-1, 0, 1.0f},    {0, 1, 1.0f},     {0, -1, 1.0f},
                           {1, 1, 1.4142f}, {1, -1, 1.4142f}, {-1, 1, 1.4142f}, {-1, -1, 1.4142f}};

}  // namespace

std::optional<FrontierGoal> NextFrontierGoal(const OccupancyGrid& map, const Eigen::Vector2d& robot,
                                             std::span<const Eigen::Vector2d> given_up,
                                             const FrontierOptions& options) {
  const int w = map.width();
  const int h = map.height();
  if (w == 0 || h == 0) return std::nullopt;
  const double res = map.resolution_m();
  const std::vector<std::int8_t>& cells = map.cells();
  const auto index = [w](int x, int y) { return static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + x; };
  const auto inside = [w, h](int x, int y) { return x >= 0 && y >= 0 && x < w && y < h; };

  // Where the robot may be: known free floor at least clearance_m from anything else (walls and the unknown).
  cv::Mat free_mask(h, w, CV_8U);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) free_mask.at<std::uint8_t>(y, x) = Free(cells[index(x, y)]) ? 255 : 0;
  }
  cv::Mat clearance;
  cv::distanceTransform(free_mask, clearance, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  const auto passable = [&](int x, int y) { return clearance.at<float>(y, x) * res >= options.clearance_m; };

  // Driving distance from the robot over passable cells (Dijkstra on the 8-neighbourhood). A robot standing nearer a
  // wall than the clearance starts from the passable cells within half a metre.
  std::vector<float> path(cells.size(), kUnreached);
  using Item = std::pair<float, std::size_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  const std::optional<CellIndex> start = map.WorldToCell(robot);
  if (!start) return std::nullopt;
  const int near = static_cast<int>(std::ceil(0.5 / res));
  for (int dy = -near; dy <= near; ++dy) {
    for (int dx = -near; dx <= near; ++dx) {
      const int x = start->x + dx;
      const int y = start->y + dy;
      if (!inside(x, y) || !passable(x, y)) continue;
      const float d = std::hypot(static_cast<float>(dx), static_cast<float>(dy));
      if (d > static_cast<float>(near)) continue;
      path[index(x, y)] = d;
      open.emplace(d, index(x, y));
    }
  }
  while (!open.empty()) {
    const auto [d, i] = open.top();
    open.pop();
    if (d > path[i]) continue;
    const int x = static_cast<int>(i % static_cast<std::size_t>(w));
    const int y = static_cast<int>(i / static_cast<std::size_t>(w));
    for (const Step& s : kSteps) {
      const int nx = x + s.dx;
      const int ny = y + s.dy;
      if (!inside(nx, ny) || !passable(nx, ny)) continue;
      const std::size_t n = index(nx, ny);
      if (d + s.length < path[n]) {
        path[n] = d + s.length;
        open.emplace(path[n], n);
      }
    }
  }

  // Frontier cells (free, beside the unknown), grouped into 8-connected frontiers; the small ones dropped.
  std::vector<int> frontier(cells.size(), kNone);
  // Free cells touching a wall are not frontier cells: a wall seen at a grazing angle has unknown gaps between its
  // hits, and what lies behind them is the wall, not a room.
  const auto is_frontier_cell = [&](int x, int y) {
    if (!Free(cells[index(x, y)])) return false;
    bool unknown = false;
    for (const Step& s : kSteps) {
      const int nx = x + s.dx;
      const int ny = y + s.dy;
      if (!inside(nx, ny)) continue;
      if (Occupied(cells[index(nx, ny)])) return false;
      unknown = unknown || (s.length == 1.0f && cells[index(nx, ny)] == kUnknownCell);
    }
    return unknown;
  };
  // Each kept frontier's goal: the reachable place nearest its centroid (within view_distance_m of it), so that the
  // robot drives into what it has not seen rather than stopping at its edge.
  const auto min_cells = static_cast<std::size_t>(std::ceil(options.min_frontier_m / res));
  const int reach = static_cast<int>(std::ceil(options.view_distance_m / res));
  std::optional<FrontierGoal> best;
  int frontiers = 0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (frontier[index(x, y)] != kNone || !is_frontier_cell(x, y)) continue;
      std::vector<std::size_t> members{index(x, y)};
      frontier[members[0]] = 1;
      Eigen::Vector2d sum = Eigen::Vector2d::Zero();
      for (std::size_t k = 0; k < members.size(); ++k) {
        const int mx = static_cast<int>(members[k] % static_cast<std::size_t>(w));
        const int my = static_cast<int>(members[k] / static_cast<std::size_t>(w));
        sum += Eigen::Vector2d(mx, my);
        for (const Step& s : kSteps) {
          const int nx = mx + s.dx;
          const int ny = my + s.dy;
          if (!inside(nx, ny) || frontier[index(nx, ny)] != kNone || !is_frontier_cell(nx, ny)) continue;
          frontier[index(nx, ny)] = 1;
          members.push_back(index(nx, ny));
        }
      }
      if (members.size() < min_cells) continue;
      const Eigen::Vector2d centroid = sum / static_cast<double>(members.size());
      // The reachable cell nearest `around` (cells) within view distance, not near a goal given up.
      const auto nearest_reachable = [&](const Eigen::Vector2d& around) {
        std::optional<FrontierGoal> found;
        double found_d2 = std::numeric_limits<double>::infinity();
        const int cx = static_cast<int>(std::lround(around.x()));
        const int cy = static_cast<int>(std::lround(around.y()));
        for (int ty = cy - reach; ty <= cy + reach; ++ty) {
          for (int tx = cx - reach; tx <= cx + reach; ++tx) {
            const double d2 = (Eigen::Vector2d(tx, ty) - around).squaredNorm();
            if (!inside(tx, ty) || path[index(tx, ty)] == kUnreached || d2 > reach * reach || d2 >= found_d2) continue;
            const Eigen::Vector2d at = map.CellCenter({tx, ty});
            bool abandoned = false;
            for (const Eigen::Vector2d& g : given_up)
              abandoned = abandoned || (g - at).norm() <= options.given_up_radius_m;
            if (abandoned) continue;
            found_d2 = d2;
            found = FrontierGoal{at, path[index(tx, ty)] * res, 0};
          }
        }
        return found;
      };
      // Near the centroid, else (a frontier seen through a narrow gap) near any of its cells, the nearest by driving.
      std::optional<FrontierGoal> target = nearest_reachable(centroid);
      for (std::size_t k = 0; !target && k < members.size(); k += 4) {
        const std::size_t column = members[k] % static_cast<std::size_t>(w);
        const std::size_t row = members[k] / static_cast<std::size_t>(w);
        const std::optional<FrontierGoal> near_member =
            nearest_reachable(Eigen::Vector2d(static_cast<double>(column), static_cast<double>(row)));
        if (near_member && (!target || near_member->path_m < target->path_m)) target = near_member;
      }
      if (!target) continue;
      ++frontiers;
      if (!best || target->path_m < best->path_m) best = target;
    }
  }
  if (!best) return std::nullopt;
  best->frontiers = frontiers;
  return best;
}

}  // namespace corridor::nav
