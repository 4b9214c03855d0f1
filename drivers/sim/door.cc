#include "drivers/sim/door.h"

#include <cmath>

namespace corridor::drivers::sim {

SimDoor::SimDoor(const SimDoorOptions& options) : options_(options), open_(options.open) {
  const Eigen::Vector2d along = options.to - options.from;
  const Eigen::Vector2d middle = (options.from + options.to) / 2.0;
  block_.center = {middle.x(), middle.y(), std::atan2(along.y(), along.x())};
  block_.half_extents = {along.norm() / 2.0, options.thickness_m / 2.0};
}

TriangleMesh SimDoor::Mesh() const {
  TriangleMesh panel;
  const Eigen::Vector3f half(static_cast<float>(block_.half_extents.x()), static_cast<float>(block_.half_extents.y()),
                             0.0f);
  panel.AddBox(-half, half + Eigen::Vector3f(0.0f, 0.0f, static_cast<float>(options_.height_m)),
               Eigen::Vector3f(0.55f, 0.4f, 0.25f));
  TriangleMesh out;
  out.Append(panel, Eigen::Affine3f(block_.center.ToIsometry3().cast<float>().matrix()));
  return out;
}

}  // namespace corridor::drivers::sim
