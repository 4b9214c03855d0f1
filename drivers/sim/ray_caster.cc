#include "drivers/sim/ray_caster.h"

#include <embree3/rtcore.h>

#include <limits>
#include <stdexcept>
#include <vector>

namespace corridor::drivers::sim {

struct RayCaster::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
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

RayHit ToHit(const RTCRayHit& rh) {
  RayHit hit;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
    hit.distance = std::numeric_limits<float>::infinity();
    return hit;
  }
  hit.distance = rh.ray.tfar;
  hit.triangle = static_cast<int>(rh.hit.primID);
  hit.normal = Eigen::Vector3f(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z).normalized();
  return hit;
}

}  // namespace

RayCaster::RayCaster(const TriangleMesh& mesh) : impl_(std::make_unique<Impl>()) {
  // Embree builds the scene with its own worker threads; the world is built once, and one worker keeps the
  // build from taking both of the board's cores. Casting runs on the caller's thread.
  impl_->device = rtcNewDevice("threads=1");
  if (impl_->device == nullptr) throw std::runtime_error("Embree: cannot create a device");
  impl_->scene = rtcNewScene(impl_->device);
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                               3 * sizeof(float), mesh.vertices.size()));
  auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                 3 * sizeof(unsigned), mesh.triangles.size()));
  Check(impl_->device, "buffer allocation");
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    for (int k = 0; k < 3; ++k) vertices[3 * i + k] = mesh.vertices[i][k];
  }
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    for (int k = 0; k < 3; ++k) indices[3 * i + k] = static_cast<unsigned>(mesh.triangles[i][k]);
  }
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(impl_->scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(impl_->scene);
  Check(impl_->device, "scene build");
}

RayCaster::~RayCaster() {
  rtcReleaseScene(impl_->scene);
  rtcReleaseDevice(impl_->device);
}

RayHit RayCaster::Cast(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float t_min,
                       float t_max) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh = MakeRay(origin, direction, t_min, t_max);
  rtcIntersect1(impl_->scene, &context, &rh);
  return ToHit(rh);
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
    for (std::size_t i = 0; i < n; ++i) hits[start + i] = ToHit(batch[i]);
  }
}

}  // namespace corridor::drivers::sim
