#include "nav/planner/distance_field.h"

#include "nav/planner/bucket_queue.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace corridor::nav {
namespace {

constexpr float kBeyondMarch = std::numeric_limits<float>::infinity();
// Cells this close to an obstacle (in cells) get their exact Euclidean distance before marching starts. The front
// is most curved there (corners, single cells), where an upwind scheme errs most; farther out it is flat enough.
constexpr int kExactBand = 3;

enum class State : std::uint8_t { kFar, kTrial, kKnown };

// Bucket width of the trial queue, in cells: cells within one bucket leave in arrival order rather than strictly by
// value; at 1/32 of a cell that ordering error is far below the upwind scheme's own.
constexpr double kBucketCells = 1.0 / 32.0;

// Solves the upwind quadratic for one cell from its known neighbours, in cell units. kInterior: the cell is at
// least two cells from the grid's edge, so its second neighbours exist and need no bounds checks (nearly every cell;
// it is the march's inner loop).
class Solver {
 public:
  Solver(const std::vector<float>& t, const std::vector<State>& state, int width, int height)
      : t_(t), state_(state), width_(width), height_(height) {}

  float Solve(int x, int y) const {
    const bool interior = x >= 2 && y >= 2 && x < width_ - 2 && y < height_ - 2;
    return interior ? SolveAt<true>(x, y) : SolveAt<false>(x, y);
  }

 private:
  struct Term {
    float value;
    float coef;  // 1 (first order) or 9/4 (second order)
  };

  template <bool kInterior>
  bool Known(int x, int y) const {
    if constexpr (!kInterior) {
      if (x < 0 || y < 0 || x >= width_ || y >= height_) return false;
    }
    return state_[static_cast<std::size_t>(y) * width_ + x] == State::kKnown;
  }
  float Get(int x, int y) const { return t_[static_cast<std::size_t>(y) * width_ + x]; }

  // The best upwind term along one axis: first order from the nearer known neighbour, second order where the next
  // cell beyond it is known and not larger: dT ~ (3T - 4T1 + T2) / 2, i.e. (9/4) * (T - (4T1 - T2) / 3)^2.
  template <bool kInterior>
  Term AxisTerm(int x, int y, int dx, int dy) const {
    Term best{kBeyondMarch, 1.0f};
    for (int dir = -1; dir <= 1; dir += 2) {
      const int nx = x + dir * dx;
      const int ny = y + dir * dy;
      if (!Known<kInterior>(nx, ny)) continue;
      const float t1 = Get(nx, ny);
      Term term{t1, 1.0f};
      const int fx = nx + dir * dx;
      const int fy = ny + dir * dy;
      if (Known<kInterior>(fx, fy) && Get(fx, fy) <= t1) term = {(4.0f * t1 - Get(fx, fy)) / 3.0f, 9.0f / 4.0f};
      if (term.value < best.value) best = term;
    }
    return best;
  }

  template <bool kInterior>
  float SolveAt(int x, int y) const {
    Term a = AxisTerm<kInterior>(x, y, 1, 0);
    Term b = AxisTerm<kInterior>(x, y, 0, 1);
    if (b.value < a.value) std::swap(a, b);
    if (a.value == kBeyondMarch) return kBeyondMarch;
    // From the nearer axis alone; the other axis joins only if the front reached it first.
    const float one_sided = a.value + 1.0f / std::sqrt(a.coef);
    if (b.value == kBeyondMarch || one_sided <= b.value) return one_sided;
    const float qa = a.coef + b.coef;
    const float qb = -2.0f * (a.coef * a.value + b.coef * b.value);
    const float qc = a.coef * a.value * a.value + b.coef * b.value * b.value - 1.0f;
    const float disc = std::max(0.0f, qb * qb - 4.0f * qa * qc);
    return (-qb + std::sqrt(disc)) / (2.0f * qa);
  }

  const std::vector<float>& t_;
  const std::vector<State>& state_;
  int width_;
  int height_;
};

}  // namespace

DistanceField FastMarchingDistance(const std::vector<std::uint8_t>& obstacle, int width, int height,
                                   double resolution_m, const FastMarchingOptions& options) {
  if (width < 0 || height < 0 || obstacle.size() != static_cast<std::size_t>(width) * height) {
    throw std::invalid_argument("FastMarchingDistance: obstacle mask does not match width x height");
  }
  const std::size_t n = obstacle.size();
  std::vector<float> t(n, kBeyondMarch);
  std::vector<State> state(n, State::kFar);
  const float limit_cells =
      static_cast<float>(std::min(options.max_distance_m / resolution_m, static_cast<double>(width + height)));
  BucketQueue trial(kBucketCells, limit_cells + 2.0f);

  // Obstacle cell centres are the zero level set, so distances are centre to centre (as OpenCV's exact
  // distance transform measures them).
  for (std::size_t i = 0; i < n; ++i) {
    if (obstacle[i]) {
      t[i] = 0.0f;
      state[i] = State::kKnown;
    }
  }
  // The exact band: each obstacle cell on the boundary stamps its distance onto the cells around it. A cell whose
  // stamped distance is within the band has its nearest obstacle inside the stamp, so the value is exact.
  const auto is_boundary = [&](int x, int y) {
    return (x > 0 && !obstacle[static_cast<std::size_t>(y) * width + x - 1]) ||
           (x + 1 < width && !obstacle[static_cast<std::size_t>(y) * width + x + 1]) ||
           (y > 0 && !obstacle[static_cast<std::size_t>(y - 1) * width + x]) ||
           (y + 1 < height && !obstacle[static_cast<std::size_t>(y + 1) * width + x]);
  };
  float stamp[(2 * kExactBand + 1) * (2 * kExactBand + 1)];
  for (int dy = -kExactBand; dy <= kExactBand; ++dy) {
    for (int dx = -kExactBand; dx <= kExactBand; ++dx) {
      stamp[(dy + kExactBand) * (2 * kExactBand + 1) + dx + kExactBand] =
          std::sqrt(static_cast<float>(dx * dx + dy * dy));
    }
  }
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      if (!obstacle[static_cast<std::size_t>(y) * width + x] || !is_boundary(x, y)) continue;
      for (int dy = -kExactBand; dy <= kExactBand; ++dy) {
        const int ny = y + dy;
        if (ny < 0 || ny >= height) continue;
        for (int dx = -kExactBand; dx <= kExactBand; ++dx) {
          const int nx = x + dx;
          if (nx < 0 || nx >= width) continue;
          float& cell = t[static_cast<std::size_t>(ny) * width + nx];
          cell = std::min(cell, stamp[(dy + kExactBand) * (2 * kExactBand + 1) + dx + kExactBand]);
        }
      }
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (t[i] <= kExactBand) {
      state[i] = State::kKnown;
    } else {
      t[i] = kBeyondMarch;
    }
  }
  const Solver solver(t, state, width, height);
  static constexpr int kDx[4] = {1, -1, 0, 0};
  static constexpr int kDy[4] = {0, 0, 1, -1};
  const auto relax_neighbours = [&](int x, int y) {
    for (int k = 0; k < 4; ++k) {
      const int nx = x + kDx[k];
      const int ny = y + kDy[k];
      if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
      const std::size_t j = static_cast<std::size_t>(ny) * width + nx;
      if (state[j] == State::kKnown) continue;
      const float candidate = solver.Solve(nx, ny);
      if (candidate < t[j]) {
        t[j] = candidate;
        state[j] = State::kTrial;
        trial.Push(candidate, static_cast<int>(j));
      }
    }
  };
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const float v = t[static_cast<std::size_t>(y) * width + x];
      if (v > kExactBand - 1.5f && v <= kExactBand) relax_neighbours(x, y);  // the band's outer rim
    }
  }
  for (int index = trial.Pop(); index >= 0; index = trial.Pop()) {
    const std::size_t i = static_cast<std::size_t>(index);
    if (state[i] == State::kKnown) continue;  // queued again after an improvement
    if (t[i] > limit_cells) break;
    state[i] = State::kKnown;
    relax_neighbours(index % width, index / width);
  }

  DistanceField field{width, height, resolution_m, std::vector<float>(n, kBeyondMarch)};
  for (std::size_t i = 0; i < n; ++i) {
    if (state[i] == State::kKnown) field.distance_m[i] = t[i] * static_cast<float>(resolution_m);
  }
  return field;
}

}  // namespace corridor::nav
