// Ray casting with Embree (the Intel ray-tracing kernels) against a static triangle mesh and a few moving ones
// (people): the simulator's depth camera and laser. The static scene is built once; the movers are a second, small
// scene rebuilt whenever they move, cast after the static one with the ray cut at the static hit. Any number of threads
// may cast at the same time, but not while SetMovers runs.
#pragma once

#include <limits>
#include <memory>
#include <span>

#include <Eigen/Core>

#include "drivers/sim/world.h"

namespace corridor::drivers::sim {

struct RayHit {
  float distance = 0.0f;   // along the ray, in metres; +infinity for a miss
  int triangle = -1;       // index into the static mesh's triangles, -1 for a miss or a mover
  bool mover = false;      // the hit is on a mover
  Eigen::Vector3f normal;  // unit geometric normal of the hit triangle (world frame)
  Eigen::Vector3f color;   // the hit triangle's colour

  bool hit() const { return distance < std::numeric_limits<float>::infinity(); }
};

class RayCaster {
 public:
  // `mesh` must outlive the caster.
  explicit RayCaster(const TriangleMesh& mesh);
  RayCaster(const RayCaster&) = delete;
  RayCaster& operator=(const RayCaster&) = delete;
  ~RayCaster();

  // Replaces the moving geometry (an empty mesh removes it). Not concurrently with casting.
  void SetMovers(const TriangleMesh& movers);

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
