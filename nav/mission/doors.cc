#include "nav/mission/doors.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace corridor::nav {
namespace {

double Cross(const Eigen::Vector2d& u, const Eigen::Vector2d& v) { return u.x() * v.y() - u.y() * v.x(); }

// Where segment p-q meets segment a-b, as a fraction of p-q; none when they do not meet (or are parallel).
std::optional<double> Meets(const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Eigen::Vector2d& a,
                            const Eigen::Vector2d& b) {
  const Eigen::Vector2d r = q - p;
  const Eigen::Vector2d s = b - a;
  const double denominator = Cross(r, s);
  if (std::abs(denominator) < 1e-12) return std::nullopt;
  const double t = Cross(a - p, s) / denominator;
  const double u = Cross(a - p, r) / denominator;
  if (t < 0.0 || t > 1.0 || u < 0.0 || u > 1.0) return std::nullopt;
  return t;
}

}  // namespace

void Validate(const DoorOptions& o) {
  if (!(o.hold_m >= 0.0 && o.release_m >= 0.0 && o.timeout_s > 0.0 && o.request_m > o.hold_m)) {
    throw std::invalid_argument("doors: request_m must exceed hold_m, distances must be >= 0 and timeout_s > 0");
  }
}

const char* ToString(DoorStatus status) {
  switch (status) {
    case DoorStatus::kClosed: return "closed";
    case DoorStatus::kOpening: return "opening";
    case DoorStatus::kOpen: return "open";
    case DoorStatus::kRefused: return "refused";
    case DoorStatus::kFailed: return "failed";
  }
  return "unknown";
}

std::vector<DoorCrossing> DoorsOnPath(const std::vector<Eigen::Vector2d>& path, const std::vector<Door>& doors) {
  std::vector<DoorCrossing> out;
  if (path.size() < 2) return out;
  // The length from each vertex to the end.
  std::vector<double> to_end(path.size(), 0.0);
  for (std::size_t i = path.size() - 1; i-- > 0;) to_end[i] = to_end[i + 1] + (path[i + 1] - path[i]).norm();
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    std::vector<DoorCrossing> here;
    for (const Door& d : doors) {
      const auto t = Meets(path[i], path[i + 1], d.a, d.b);
      if (!t) continue;
      const bool again = std::any_of(out.begin(), out.end(), [&](const DoorCrossing& c) { return c.door == d.id; });
      if (!again) here.push_back({d.id, to_end[i] - *t * (path[i + 1] - path[i]).norm()});
    }
    std::sort(here.begin(), here.end(),
              [](const DoorCrossing& x, const DoorCrossing& y) { return x.from_end_m > y.from_end_m; });
    out.insert(out.end(), here.begin(), here.end());
  }
  return out;
}

void ClearDoors(const OccupancyGrid& grid, const std::vector<Door>& doors, double half_width_m,
                std::vector<std::int8_t>& layer) {
  const double res = grid.resolution_m();
  for (const Door& d : doors) {
    const double length = (d.b - d.a).norm();
    const int steps = std::max(1, static_cast<int>(std::ceil(length / (res / 2.0))));
    const int reach = static_cast<int>(std::ceil(half_width_m / res));
    for (int i = 0; i <= steps; ++i) {
      const auto cell = grid.WorldToCell(d.a + (d.b - d.a) * (static_cast<double>(i) / steps));
      if (!cell) continue;
      for (int dy = -reach; dy <= reach; ++dy) {
        for (int dx = -reach; dx <= reach; ++dx) {
          const CellIndex n{cell->x + dx, cell->y + dy};
          if (grid.Contains(n)) layer[static_cast<std::size_t>(n.y) * grid.width() + n.x] = kFreeCell;
        }
      }
    }
  }
}

void DoorKeeper::SetPath(std::vector<DoorCrossing> crossings, std::vector<DoorRequest>& requests) {
  crossings_ = std::move(crossings);
  for (auto it = asked_.begin(); it != asked_.end();) {
    const bool crossed =
        std::any_of(crossings_.begin(), crossings_.end(), [&](const DoorCrossing& c) { return c.door == it->first; });
    if (crossed) {
      ++it;
      continue;
    }
    requests.push_back({it->first, false});
    it = asked_.erase(it);
  }
}

DoorKeeper::Step DoorKeeper::Update(double now_s, double remaining_m, const DoorReports& reports,
                                    std::vector<DoorRequest>& requests) {
  Step step;
  // Doors passed far enough: released.
  while (!crossings_.empty() && remaining_m < crossings_.front().from_end_m - options_.release_m) {
    const std::string door = crossings_.front().door;
    crossings_.erase(crossings_.begin());
    if (asked_.erase(door) > 0) requests.push_back({door, false});
  }
  for (const DoorCrossing& c : crossings_) {
    const double ahead = remaining_m - c.from_end_m;  // negative: the robot's centre is past the line
    if (ahead > options_.request_m) break;            // the next ones are farther still
    if (!asked_.contains(c.door)) {
      asked_[c.door] = now_s;
      requests.push_back({c.door, true});
    }
    const auto report = reports.find(c.door);
    const DoorStatus status = report == reports.end() ? DoorStatus::kClosed : report->second.status;
    if (status == DoorStatus::kOpen) continue;
    if (status == DoorStatus::kRefused || status == DoorStatus::kFailed) {
      const std::string why = report->second.detail.empty() ? "" : ": " + report->second.detail;
      step.failure = "door " + c.door + (status == DoorStatus::kRefused ? " refused to open" : " failed") + why;
      return step;
    }
    if (now_s - asked_[c.door] > options_.timeout_s) {
      step.failure =
          "door " + c.door + " did not open within " + std::to_string(static_cast<int>(options_.timeout_s)) + " s";
      return step;
    }
    // Not open yet: the robot goes no nearer than hold_m.
    if (ahead <= options_.hold_m + 0.05) {
      step.hold = true;
      step.waiting_for = c.door;
    }
    return step;  // the doors beyond wait for this one
  }
  return step;
}

void DoorKeeper::ReleaseAll(std::vector<DoorRequest>& requests) {
  for (const auto& [door, asked_s] : asked_) requests.push_back({door, false});
  asked_.clear();
  crossings_.clear();
}

}  // namespace corridor::nav
