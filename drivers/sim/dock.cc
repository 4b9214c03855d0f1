#include "drivers/sim/dock.h"

#include <cmath>

namespace corridor::drivers::sim {

SimDock::SimDock(const SimDockOptions& options) : options_(options) {
  const double face = options.geometry.face_distance_m;
  block_.center = options.pose * nav::Pose2{face + options.depth_m / 2.0, 0.0, 0.0};
  block_.half_extents = {options.depth_m / 2.0, options.geometry.width_m / 2.0};
}

TriangleMesh SimDock::Mesh() const {
  TriangleMesh box;
  const Eigen::Vector3f half(static_cast<float>(block_.half_extents.x()), static_cast<float>(block_.half_extents.y()),
                             0.0f);
  box.AddBox(-half, half + Eigen::Vector3f(0.0f, 0.0f, static_cast<float>(options_.height_m)),
             Eigen::Vector3f(0.25f, 0.25f, 0.3f));
  const Eigen::Affine3f placed(block_.center.ToIsometry3().cast<float>().matrix());
  TriangleMesh out;
  out.Append(box, placed);
  return out;
}

bool SimDock::Contacts(const nav::Pose2& robot) const {
  const nav::Pose2 error = options_.pose.Inverse() * robot;
  return error.translation().norm() <= options_.contact_m && std::abs(error.yaw_rad) <= options_.contact_rad;
}

void AddDock(World& world, const SimDock& dock) { world.mesh.Append(dock.Mesh()); }

}  // namespace corridor::drivers::sim
