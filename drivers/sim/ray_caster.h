// Ray casting against a static triangle mesh with Embree (the Intel ray-tracing kernels): the simulator's depth
// camera and laser. Thread-safe once constructed: any number of threads may cast at the same time.
#pragma once

#include <memory>
#include <span>

#include <Eigen/Core>

#include "drivers/sim/world.h"

namespace corridor::drivers::sim {

struct RayHit {
  float distance = 0.0f;       // along the ray, in metres; +infinity for a miss
  int triangle = -1;           // index into the mesh's triangles, -1 for a miss
  Eigen::Vector3f normal;      // unit geometric normal of the hit triangle (world frame)
};

class RayCaster {
 public:
  explicit RayCaster(const TriangleMesh& mesh);
  RayCaster(const RayCaster&) = delete;
  RayCaster& operator=(const RayCaster&) = delete;
  ~RayCaster();

  // The nearest hit along origin + t * direction for t in [t_min, t_max]. direction need not be unit length;
  // distances are then in units of its length.
  RayHit Cast(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float t_min, float t_max) const;

  // Casts one ray per direction from a shared origin (a camera or laser centre) as one coherent batch.
  void CastFan(const Eigen::Vector3f& origin, std::span<const Eigen::Vector3f> directions, float t_min, float t_max,
               std::span<RayHit> hits) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace corridor::drivers::sim
