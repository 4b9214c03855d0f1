#include "nav/ground/multi_view.h"

#include <array>
#include <bit>
#include <cmath>
#include <stdexcept>

namespace corridor::nav {
namespace {

// A cell's three indices, each in 21 bits (offset so that negative ones fit): +-105 km at 10 cm.
constexpr int kAxisBits = 21;
std::uint64_t CellKey(const Eigen::Vector3f& point, float inverse_cell) {
  constexpr std::int64_t kOffset = 1 << 20;
  constexpr std::uint64_t kMask = (1u << kAxisBits) - 1;
  const auto index = [&](float x) {
    return static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(x * inverse_cell)) + kOffset) & kMask;
  };
  return index(point.x()) | (index(point.y()) << kAxisBits) | (index(point.z()) << (2 * kAxisBits));
}

// The six cells beside `key`'s (one index up or down; an index never at its range's ends within +-105 km).
std::array<std::uint64_t, 6> Beside(std::uint64_t key) {
  std::array<std::uint64_t, 6> keys{};
  for (int axis = 0; axis < 3; ++axis) {
    const std::uint64_t one = std::uint64_t{1} << (axis * kAxisBits);
    keys[2 * axis] = key + one;
    keys[2 * axis + 1] = key - one;
  }
  return keys;
}

}  // namespace

void ValidateMultiViewOptions(const MultiViewOptions& o) {
  if (!(o.cell_m >= 0.01 && o.cell_m <= 1.0)) throw std::invalid_argument("cell_m: from 0.01 to 1 m");
  if (o.window < 1 || o.window > 32) throw std::invalid_argument("window: from 1 to 32 frames");
  if (o.views < 1 || o.views > o.window) throw std::invalid_argument("views: from 1 to window");
  if (!(o.from_m >= 0.0)) throw std::invalid_argument("from_m: 0 or more");
}

MultiViewFilter::MultiViewFilter(const PinholeCamera& camera, const MultiViewOptions& options)
    : camera_(camera),
      options_((ValidateMultiViewOptions(options), options)),
      window_mask_(options.window == 32 ? 0xffffffffu : (1u << options.window) - 1u) {
  if (!camera.Valid()) throw std::invalid_argument("multi-view filter: a camera with a size and focal length");
  rays_.reserve(static_cast<std::size_t>(camera.width) * static_cast<std::size_t>(camera.height));
  for (int v = 0; v < camera.height; ++v) {
    for (int u = 0; u < camera.width; ++u) rays_.push_back(camera.Ray(u, v).cast<float>());
  }
  pixel_cells_.resize(rays_.size());
}

int MultiViewFilter::Apply(cv::Mat& depth_mm, const Pose2& odom_T_base,
                           const std::optional<Eigen::Isometry3d>& base_T_camera) {
  CV_Assert(depth_mm.type() == CV_16UC1 && depth_mm.cols == camera_.width && depth_mm.rows == camera_.height);
  ++frame_;
  const Eigen::Isometry3f odom_T_camera =
      (odom_T_base.ToIsometry3() * base_T_camera.value_or(camera_.base_T_camera)).cast<float>();
  const float inverse_cell = static_cast<float>(1.0 / options_.cell_m);
  const auto from_mm = static_cast<std::uint16_t>(std::lround(std::min(1e3 * options_.from_m, 65535.0)));
  // Each reading marks its cell seen in this frame.
  std::size_t i = 0;
  for (int v = 0; v < depth_mm.rows; ++v) {
    const auto* row = depth_mm.ptr<std::uint16_t>(v);
    for (int u = 0; u < depth_mm.cols; ++u, ++i) {
      if (row[u] == 0 || row[u] < from_mm) {
        pixel_cells_[i] = nullptr;
        continue;
      }
      const Eigen::Vector3f point = odom_T_camera * (rays_[i] * (1e-3f * static_cast<float>(row[u])));
      const std::uint64_t key = CellKey(point, inverse_cell);
      Cell& cell = cells_[key];
      cell.key = key;
      pixel_cells_[i] = &cell;
      if (cell.frame == frame_) continue;
      const std::int64_t age = frame_ - cell.frame;
      cell.seen = (age >= 32 ? 0u : cell.seen << age) | 1u;
      cell.frame = frame_;
    }
  }
  // ... and is kept when that cell was seen often enough.
  int zeroed = 0;
  i = 0;
  for (int v = 0; v < depth_mm.rows; ++v) {
    auto* row = depth_mm.ptr<std::uint16_t>(v);
    for (int u = 0; u < depth_mm.cols; ++u, ++i) {
      if (pixel_cells_[i] == nullptr) continue;
      if (!Keep(*pixel_cells_[i])) {
        row[u] = 0;
        ++zeroed;
      }
    }
  }
  // Cells not seen within the window can never count again.
  if (frame_ % 16 == 0) {
    std::erase_if(cells_, [&](const auto& entry) { return frame_ - entry.second.frame >= options_.window; });
  }
  return zeroed;
}

bool MultiViewFilter::Keep(Cell& cell) {
  if (cell.judged == frame_) return cell.keep;
  std::uint32_t seen = cell.seen;
  for (const std::uint64_t beside : Beside(cell.key)) {
    const auto it = cells_.find(beside);
    if (it == cells_.end() || frame_ - it->second.frame >= 32) continue;
    seen |= it->second.seen << (frame_ - it->second.frame);
  }
  cell.judged = frame_;
  cell.keep = std::popcount(seen & window_mask_) >= options_.views;
  return cell.keep;
}

}  // namespace corridor::nav
