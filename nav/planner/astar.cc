#include "nav/planner/astar.h"

#include "nav/demand.h"
#include "nav/planner/bucket_queue.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace corridor::nav {
namespace {

constexpr float kNotReached = std::numeric_limits<float>::infinity();
constexpr double kSqrt2 = 1.4142135623730951;
constexpr int kCancelPollMask = 4095;  // poll the cancel flag every 4096 expansions

// Open-list bucket width in metres of f. Nodes within one bucket leave in arrival order, so a path may cost up to
// this much more than the optimum: a millimetre, against paths of metres.
constexpr double kOpenQuantumM = 0.001;

// A robot cut off from its goal by the inflated band crosses it (AStar) within kEscapeReachM of where it stands, each
// step through the band costing kEscapeFactor times its length and each step over the map's unknown specks
// kUnknownEscapeFactor times, so that the way out is short and over known floor where there is room.
constexpr float kEscapeFactor = 4.0f;
constexpr float kUnknownEscapeFactor = 8.0f;

std::string Where(const Eigen::Vector2d& p) {
  std::ostringstream s;
  s.precision(3);
  s << "(" << p.x() << ", " << p.y() << ")";
  return s.str();
}

}  // namespace

const char* ToString(PlanError error) {
  switch (error) {
    case PlanError::kNone: return "none";
    case PlanError::kStartOutsideMap: return "start_outside_map";
    case PlanError::kStartOccupied: return "start_occupied";
    case PlanError::kGoalOutsideMap: return "goal_outside_map";
    case PlanError::kGoalOccupied: return "goal_occupied";
    case PlanError::kNoPath: return "no_path";
    case PlanError::kCancelled: return "cancelled";
  }
  return "unknown";
}

namespace {

// The search itself. With `escape`, the robot standing at `start` may also cross the inflated band and the map's
// unknown specks anywhere within kEscapeReachM of it (see AStar), where its footprint keeps a cell from every wall the
// map knows (unknown cells are obstacles to plans, not walls: the robot got onto its island over them), at
// kEscapeFactor (kUnknownEscapeFactor) times the cost. Keep-out zones stay closed.
SearchResult Search(const Costmap& costmap, const Eigen::Vector2d& start, const Eigen::Vector2d& goal,
                    const std::atomic<bool>* cancel, std::span<const float> extra_cost, bool robot_at_start,
                    bool escape) {
  SearchResult result;
  const OccupancyGrid& grid = costmap.grid();
  if (!extra_cost.empty() && extra_cost.size() != grid.cells().size()) {
    throw std::invalid_argument("AStar: extra_cost has " + std::to_string(extra_cost.size()) + " cells, the costmap " +
                                std::to_string(grid.cells().size()));
  }
  const auto start_cell = grid.WorldToCell(start);
  if (!start_cell) return {PlanError::kStartOutsideMap, "start " + Where(start) + " is outside the map", {}};
  const auto goal_cell = grid.WorldToCell(goal);
  if (!goal_cell) return {PlanError::kGoalOutsideMap, "goal " + Where(goal) + " is outside the map", {}};
  const std::size_t s = costmap.Index(*start_cell);
  const std::size_t g = costmap.Index(*goal_cell);
  if (costmap.IsObstacle(s) && (costmap.InKeepOut(s) || !robot_at_start)) {
    return {PlanError::kStartOccupied,
            "start " + Where(start) + (costmap.InKeepOut(s) ? " is in a keep-out zone" : " is on an obstacle"),
            {}};
  }
  if (!costmap.Traversable(g)) {
    const std::string why = costmap.InKeepOut(g)    ? " is in a keep-out zone"
                            : costmap.IsObstacle(g) ? " is on an obstacle or unknown space"
                                                    : " is too close to an obstacle for the robot";
    return {PlanError::kGoalOccupied, "goal " + Where(goal) + why, {}};
  }

  const int width = costmap.width();
  const int height = costmap.height();
  const double res = grid.resolution_m();
  const auto heuristic = [&](int index) {
    const int dx = std::abs(index % width - goal_cell->x);
    const int dy = std::abs(index / width - goal_cell->y);
    return static_cast<float>(res * (std::max(dx, dy) + (kSqrt2 - 1.0) * std::min(dx, dy)));
  };
  std::vector<float> cost(grid.cells().size(), kNotReached);
  std::vector<int> parent(grid.cells().size(), -1);
  std::vector<std::uint8_t> closed(grid.cells().size(), 0);
  BucketQueue open(kOpenQuantumM, 3.0 * heuristic(static_cast<int>(s)));
  cost[s] = 0.0f;
  open.Push(heuristic(static_cast<int>(s)), static_cast<int>(s));

  static constexpr int kDx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
  static constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};
  const float step_length[8] = {static_cast<float>(res),          static_cast<float>(res),
                                static_cast<float>(res),          static_cast<float>(res),
                                static_cast<float>(kSqrt2 * res), static_cast<float>(kSqrt2 * res),
                                static_cast<float>(kSqrt2 * res), static_cast<float>(kSqrt2 * res)};
  // A start inside the inflated band may cross the band's cells near it; with the robot at the start, whatever lies
  // under its footprint is passable: it stands on it, whatever the map says (a speck, unknown space, a wall a few
  // centimetres off after a localization error). Keep-out zones stay closed.
  const bool start_inside = !costmap.Traversable(s);
  const auto within = [&](int nx, int ny, double radius_m) {
    const double dx = (nx - start_cell->x) * res;
    const double dy = (ny - start_cell->y) * res;
    return dx * dx + dy * dy <= radius_m * radius_m;
  };
  const double footprint_m = costmap.options().robot_radius_m;
  const auto near_start = [&](int nx, int ny) { return within(nx, ny, kEscapeRadiusM); };
  // Through the band, the footprint keeps a cell from every wall the map knows (cells are squares, and paths keep a
  // cell more), except under the footprint at the start.
  const double wall_clearance_m = footprint_m + res;
  const auto clear_of_walls = [&](int nx, int ny) {
    return within(nx, ny, footprint_m) || !costmap.WallWithin(grid.CellCenter({nx, ny}), wall_clearance_m);
  };
  const auto escape_through = [&](std::size_t i, int nx, int ny) {
    return escape && !costmap.InKeepOut(i) && within(nx, ny, kEscapeReachM) && clear_of_walls(nx, ny);
  };
  // An obstacle cell the search may not enter: any but those under the footprint where the robot stands; then the
  // escape's crossing may still open it (blocked).
  const auto obstacle = [&](std::size_t i, int nx, int ny) {
    return costmap.IsObstacle(i) && (!robot_at_start || costmap.InKeepOut(i) || !within(nx, ny, footprint_m));
  };
  const auto blocked = [&](std::size_t i, int nx, int ny) { return obstacle(i, nx, ny) && !escape_through(i, nx, ny); };
  for (int top = open.Pop(); top >= 0; top = open.Pop()) {
    const std::size_t cur = static_cast<std::size_t>(top);
    if (closed[cur]) continue;
    closed[cur] = 1;
    if ((++result.path.expanded & kCancelPollMask) == 0 && cancel && cancel->load(std::memory_order_relaxed)) {
      return {PlanError::kCancelled, "the plan was cancelled", {}};
    }
    if (cur == g) break;
    const int x = top % width;
    const int y = top / width;
    // Inside the grid's one-cell rim every neighbour exists: no bounds checks (nearly every expansion).
    const bool interior = x > 0 && y > 0 && x < width - 1 && y < height - 1;
    const bool escaping = !costmap.Traversable(cur);  // the start, or a cell on its way out of the band
    for (int k = 0; k < 8; ++k) {
      const int nx = x + kDx[k];
      const int ny = y + kDy[k];
      if (!interior && (nx < 0 || ny < 0 || nx >= width || ny >= height)) continue;
      const std::size_t next = cur + static_cast<std::ptrdiff_t>(kDy[k]) * width + kDx[k];
      if (closed[next]) continue;
      const bool traversable = costmap.Traversable(next);
      const bool through_band = !traversable && escape_through(next, nx, ny);  // the walls looked up once a cell
      if (!through_band && obstacle(next, nx, ny)) continue;
      // Out of the band along rising clearance, or near a start inside it.
      const bool leaving =
          (escaping && costmap.clearance_m(next) > costmap.clearance_m(cur)) || (start_inside && near_start(nx, ny));
      const bool ok = traversable || through_band || (leaving && clear_of_walls(nx, ny));
      if (!ok) continue;
      if (k >= 4) {
        // No cutting corners: both cells beside the diagonal must be passable too.
        const std::size_t side_a = cur + kDx[k];
        const std::size_t side_b = cur + static_cast<std::ptrdiff_t>(kDy[k]) * width;
        if (blocked(side_a, nx, y) || blocked(side_b, x, ny)) continue;
        if (!escaping && !escape && (!costmap.Traversable(side_a) || !costmap.Traversable(side_b))) continue;
      }
      const float escape_factor = costmap.IsObstacle(next) ? kUnknownEscapeFactor : kEscapeFactor;
      const float factor = (through_band ? escape_factor : 1.0f) * costmap.step_factor(next) +
                           (extra_cost.empty() ? 0.0f : extra_cost[next]);
      const float candidate = cost[cur] + step_length[k] * factor;
      if (candidate < cost[next]) {
        cost[next] = candidate;
        parent[next] = static_cast<int>(cur);
        open.Push(candidate + heuristic(static_cast<int>(next)), static_cast<int>(next));
      }
    }
  }
  if (!closed[g]) {
    result.error = PlanError::kNoPath;
    std::ostringstream detail;
    detail << "no path from " << Where(start) << " to " << Where(goal) << " for a robot of radius "
           << costmap.options().robot_radius_m << " m";
    result.detail = detail.str();
    return result;
  }
  for (int i = static_cast<int>(g); i != -1; i = parent[i]) {
    result.path.cells.push_back({i % width, i / width});
    DEMAND(result.path.cells.size() <= grid.cells().size());  // the parents form a chain back to the start, no loop
  }
  std::reverse(result.path.cells.begin(), result.path.cells.end());
  result.path.cost = cost[g];
  return result;
}

}  // namespace

SearchResult AStar(const Costmap& costmap, const Eigen::Vector2d& start, const Eigen::Vector2d& goal,
                   const std::atomic<bool>* cancel, std::span<const float> extra_cost, bool robot_at_start) {
  SearchResult result = Search(costmap, start, goal, cancel, extra_cost, robot_at_start, false);
  if (result.error == PlanError::kNoPath && robot_at_start) {
    // Cut off from the goal by the inflated band (an island of free space among a map's specks, or deep in the band
    // beside a wall): out through the band near the robot, slowly (PlanPath), then on.
    SearchResult out = Search(costmap, start, goal, cancel, extra_cost, robot_at_start, true);
    if (out.error != PlanError::kNoPath) return out;
  }
  return result;
}

}  // namespace corridor::nav
