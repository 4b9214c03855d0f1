#include "drivers/sim/ray_caster.h"

#include <embree3/rtcore.h>

#include <limits>
#include <stdexcept>
#include <vector>

namespace corridor::drivers::sim {

struct RayCaster::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  RTCScene movers = nullptr;  // null when there are none
  const TriangleMesh* mesh = nullptr;
  TriangleMesh mover_mesh;
};

namespace {

// Batches of this many rays go to Embree at once: large enough to amortise the call, small enough for the stack.
constexpr std::size_t kBatch = 256;

void Check(RTCDevice device, const char* what) {
  const RTCError error = rtcGetDeviceError(device);
  if (error != RTC_ERROR_NONE) throw std::runtime_error(std::string("Embree: ") + what + " failed");
}

RTCRayHit MakeRay(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float t_min, float t_max) {
  RTCRayHit rh{};
  rh.ray.org_x = o.x();
  rh.ray.org_y = o.y();
  rh.ray.org_z = o.z();
  rh.ray.dir_x = d.x();
  rh.ray.dir_y = d.y();
  rh.ray.dir_z = d.z();
  rh.ray.tnear = t_min;
  rh.ray.tfar = t_max;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
  return rh;
}

RayHit ToHit(const RTCRayHit& rh, const TriangleMesh& mesh, bool mover) {
  RayHit hit;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
    hit.distance = std::numeric_limits<float>::infinity();
    return hit;
  }
  hit.distance = rh.ray.tfar;
  hit.mover = mover;
  hit.triangle = mover ? -1 : static_cast<int>(rh.hit.primID);
  hit.normal = Eigen::Vector3f(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z).normalized();
  hit.color = mesh.colors[rh.hit.primID];
  return hit;
}

// A scene of one triangle geometry holding `mesh`.
RTCScene BuildScene(RTCDevice device, const TriangleMesh& mesh, RTCBuildQuality quality) {
  RTCScene scene = rtcNewScene(device);
  rtcSetSceneBuildQuality(scene, quality);
  RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetGeometryBuildQuality(geometry, quality);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                               3 * sizeof(float), mesh.vertices.size()));
  auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                 3 * sizeof(unsigned), mesh.triangles.size()));
  Check(device, "buffer allocation");
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    for (int k = 0; k < 3; ++k) vertices[3 * i + k] = mesh.vertices[i][k];
  }
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    for (int k = 0; k < 3; ++k) indices[3 * i + k] = static_cast<unsigned>(mesh.triangles[i][k]);
  }
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(scene);
  Check(device, "scene build");
  return scene;
}

}  // namespace

RayCaster::RayCaster(const TriangleMesh& mesh) : impl_(std::make_unique<Impl>()) {
  // Embree builds the scene with its own worker threads; the world is built once, and one worker keeps the
  // build from taking both of the board's cores. Casting runs on the caller's thread.
  impl_->device = rtcNewDevice("threads=1");
  if (impl_->device == nullptr) throw std::runtime_error("Embree: cannot create a device");
  impl_->mesh = &mesh;
  impl_->scene = BuildScene(impl_->device, mesh, RTC_BUILD_QUALITY_HIGH);
}

RayCaster::~RayCaster() {
  if (impl_->movers != nullptr) rtcReleaseScene(impl_->movers);
  rtcReleaseScene(impl_->scene);
  rtcReleaseDevice(impl_->device);
}

void RayCaster::SetMovers(const TriangleMesh& movers) {
  if (impl_->movers != nullptr) rtcReleaseScene(impl_->movers);
  impl_->movers = nullptr;
  impl_->mover_mesh = movers;
  // A few hundred triangles: a low-quality build takes microseconds and is as fast to cast against.
  if (!movers.triangles.empty()) impl_->movers = BuildScene(impl_->device, impl_->mover_mesh, RTC_BUILD_QUALITY_LOW);
}

RayHit RayCaster::Cast(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float t_min,
                       float t_max) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh = MakeRay(origin, direction, t_min, t_max);
  rtcIntersect1(impl_->scene, &context, &rh);
  RayHit hit = ToHit(rh, *impl_->mesh, false);
  if (impl_->movers != nullptr) {
    RTCRayHit mover = MakeRay(origin, direction, t_min, rh.ray.tfar);
    rtcIntersect1(impl_->movers, &context, &mover);
    if (mover.hit.geomID != RTC_INVALID_GEOMETRY_ID) hit = ToHit(mover, impl_->mover_mesh, true);
  }
  return hit;
}

void RayCaster::CastFan(const Eigen::Vector3f& origin, std::span<const Eigen::Vector3f> directions, float t_min,
                        float t_max, std::span<RayHit> hits) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  RTCRayHit batch[kBatch];
  for (std::size_t start = 0; start < directions.size(); start += kBatch) {
    const std::size_t n = std::min(kBatch, directions.size() - start);
    for (std::size_t i = 0; i < n; ++i) batch[i] = MakeRay(origin, directions[start + i], t_min, t_max);
    rtcIntersect1M(impl_->scene, &context, batch, static_cast<unsigned>(n), sizeof(RTCRayHit));
    for (std::size_t i = 0; i < n; ++i) hits[start + i] = ToHit(batch[i], *impl_->mesh, false);
    if (impl_->movers == nullptr) continue;
    // The movers, only nearer than what each ray already hit.
    for (std::size_t i = 0; i < n; ++i) batch[i] = MakeRay(origin, directions[start + i], t_min, batch[i].ray.tfar);
    rtcIntersect1M(impl_->movers, &context, batch, static_cast<unsigned>(n), sizeof(RTCRayHit));
    for (std::size_t i = 0; i < n; ++i) {
      if (batch[i].hit.geomID != RTC_INVALID_GEOMETRY_ID) hits[start + i] = ToHit(batch[i], impl_->mover_mesh, true);
    }
  }
}

}  // namespace corridor::drivers::sim
