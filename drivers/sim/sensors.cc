#include "drivers/sim/sensors.h"

#include <cmath>
#include <limits>
#include <numbers>

namespace corridor::drivers::sim {
namespace {

double Radians(double deg) { return deg * std::numbers::pi / 180.0; }

const Eigen::Vector3f kBackground(0.85f, 0.85f, 0.88f);

// A lattice point's value in [0, 1) (a 32-bit integer hash of its coordinates).
float LatticeValue(int x, int y, int z) {
  std::uint32_t h = static_cast<std::uint32_t>(x) * 0x8da6b343u ^ static_cast<std::uint32_t>(y) * 0xd8163841u ^
                    static_cast<std::uint32_t>(z) * 0xcb1ab31fu;
  h ^= h >> 13;
  h *= 0x5bd1e995u;
  h ^= h >> 15;
  return static_cast<float>(h & 0xFFFFFFu) / static_cast<float>(0x1000000u);
}

// Value noise: the lattice's values at `scale_m` spacing, blended smoothly (trilinear, smoothstep weights).
float ValueNoise(const Eigen::Vector3f& p, float scale_m) {
  const Eigen::Vector3f q = p / scale_m;
  const Eigen::Vector3f floor = q.array().floor();
  const Eigen::Vector3f f = q - floor;
  const Eigen::Vector3f w = f.array() * f.array() * (3.0f - 2.0f * f.array());
  const int x = static_cast<int>(floor.x());
  const int y = static_cast<int>(floor.y());
  const int z = static_cast<int>(floor.z());
  float value = 0.0f;
  for (int corner = 0; corner < 8; ++corner) {
    const int dx = corner & 1;
    const int dy = (corner >> 1) & 1;
    const int dz = (corner >> 2) & 1;
    const float weight = (dx ? w.x() : 1.0f - w.x()) * (dy ? w.y() : 1.0f - w.y()) * (dz ? w.z() : 1.0f - w.z());
    value += weight * LatticeValue(x + dx, y + dy, z + dz);
  }
  return value;
}

// How squarely a ray meets the surface it hits: |cos| of the angle between them.
float CosIncidence(const RayHit& hit, const Eigen::Vector3f& direction) {
  return std::abs(hit.normal.dot(direction.normalized()));
}

// A hit's colour as the camera sees it: the surface's colour, textured, lit from the camera.
Eigen::Vector3f Shade(const RayHit& hit, float cos_incidence, const Eigen::Vector3f& origin,
                      const Eigen::Vector3f& direction, double texture) {
  Eigen::Vector3f color = hit.color * (0.3f + 0.7f * cos_incidence);
  if (texture > 0.0) {
    const float t = SurfaceTexture(origin + hit.distance * direction);
    color *= static_cast<float>(1.0 - texture + 2.0 * texture * t);
  }
  return color;
}

cv::Vec3b ToBgr(const Eigen::Vector3f& color) {
  return cv::Vec3b(static_cast<std::uint8_t>(std::clamp(color.z(), 0.0f, 1.0f) * 255.0f),
                   static_cast<std::uint8_t>(std::clamp(color.y(), 0.0f, 1.0f) * 255.0f),
                   static_cast<std::uint8_t>(std::clamp(color.x(), 0.0f, 1.0f) * 255.0f));
}

}  // namespace

float SurfaceTexture(const Eigen::Vector3f& point_m) {
  return 0.65f * ValueNoise(point_m, 0.04f) + 0.35f * ValueNoise(point_m, 0.015f);
}

CameraInfo MakeCameraInfo(const SimCameraOptions& o) {
  CameraInfo info;
  nav::PinholeCamera& k = info.camera;
  k.width = o.width;
  k.height = o.height;
  k.fx = o.width / (2.0 * std::tan(Radians(o.horizontal_fov_deg) / 2.0));
  k.fy = o.height / (2.0 * std::tan(Radians(o.vertical_fov_deg) / 2.0));
  k.cx = o.width / 2.0;
  k.cy = o.height / 2.0;
  info.camera.base_T_camera = nav::CameraMount(o.mount_x_m, o.mount_height_m, Radians(o.tilt_deg));
  info.min_range_m = o.min_range_m;
  info.max_range_m = o.max_range_m;
  return info;
}

RgbdRenderer::RgbdRenderer(const RayCaster& caster, const SimCameraOptions& options)
    : caster_(caster), options_(options), info_(MakeCameraInfo(options)) {
  const nav::PinholeCamera& k = info_.camera;
  rays_.reserve(static_cast<std::size_t>(k.width) * k.height);
  for (int v = 0; v < k.height; ++v) {
    for (int u = 0; u < k.width; ++u) {
      rays_.emplace_back(static_cast<float>((u + 0.5 - k.cx) / k.fx), static_cast<float>((v + 0.5 - k.cy) / k.fy),
                         1.0f);
    }
  }
}

void RgbdRenderer::CastPixels(const Eigen::Isometry3d& world_T_camera, std::vector<Eigen::Vector3f>& directions,
                              std::vector<RayHit>& hits) const {
  const Eigen::Matrix3f rotation = world_T_camera.linear().cast<float>();
  directions.resize(rays_.size());
  for (std::size_t i = 0; i < rays_.size(); ++i) directions[i] = rotation * rays_[i];
  hits.resize(rays_.size());
  // Cast past max range so that colour still sees far walls; depth drops them below.
  caster_.CastFan(world_T_camera.translation().cast<float>(), directions, 0.0f, 1e3f, hits);
}

void RgbdRenderer::Render(const Eigen::Isometry3d& world_T_camera, std::mt19937& rng, RgbdFrame& frame) const {
  const nav::PinholeCamera& k = info_.camera;
  const Eigen::Vector3f origin = world_T_camera.translation().cast<float>();
  std::vector<Eigen::Vector3f> directions;
  std::vector<RayHit> hits;
  CastPixels(world_T_camera, directions, hits);

  frame.depth_mm.create(k.height, k.width, CV_16UC1);
  frame.color_bgr.create(k.height, k.width, CV_8UC3);
  std::normal_distribution<float> unit_normal(0.0f, 1.0f);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  const float cos_cutoff = static_cast<float>(std::cos(Radians(options_.grazing_cutoff_deg)));
  for (int v = 0; v < k.height; ++v) {
    auto* depth_row = frame.depth_mm.ptr<std::uint16_t>(v);
    auto* color_row = frame.color_bgr.ptr<cv::Vec3b>(v);
    for (int u = 0; u < k.width; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * k.width + u;
      const RayHit& hit = hits[i];
      Eigen::Vector3f color = kBackground;
      std::uint16_t depth = 0;
      if (hit.hit()) {
        const float cos_incidence = CosIncidence(hit, directions[i]);
        color = Shade(hit, cos_incidence, origin, directions[i], 0.0);
        const float z = hit.distance;  // rays have unit optical-axis component: t is depth
        const bool in_range = z >= options_.min_range_m && z <= options_.max_range_m;
        if (in_range && cos_incidence >= cos_cutoff && uniform(rng) >= options_.dropout_fraction) {
          const float sigma = static_cast<float>(options_.noise_a_m + options_.noise_b_per_m * z * z);
          const float noisy_mm = (z + sigma * unit_normal(rng)) * 1000.0f;
          depth = static_cast<std::uint16_t>(std::clamp(std::lround(noisy_mm), 1L, 65535L));
        }
      }
      depth_row[u] = depth;
      color_row[u] = ToBgr(color);
    }
  }
}

void RgbdRenderer::RenderColor(const Eigen::Isometry3d& world_T_camera, double texture, double noise_levels,
                               std::mt19937& rng, cv::Mat& bgr) const {
  const nav::PinholeCamera& k = info_.camera;
  const Eigen::Vector3f origin = world_T_camera.translation().cast<float>();
  std::vector<Eigen::Vector3f> directions;
  std::vector<RayHit> hits;
  CastPixels(world_T_camera, directions, hits);
  bgr.create(k.height, k.width, CV_8UC3);
  std::normal_distribution<float> noise(0.0f, static_cast<float>(noise_levels / 255.0));
  for (int v = 0; v < k.height; ++v) {
    auto* row = bgr.ptr<cv::Vec3b>(v);
    for (int u = 0; u < k.width; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * k.width + u;
      const RayHit& hit = hits[i];
      Eigen::Vector3f color =
          hit.hit() ? Shade(hit, CosIncidence(hit, directions[i]), origin, directions[i], texture) : kBackground;
      if (noise_levels > 0.0) color.array() += noise(rng);
      row[u] = ToBgr(color);
    }
  }
}

void StartScan(const SimLaserOptions& options, LaserScan& scan) {
  scan.angle_increment_rad = 2.0 * std::numbers::pi / options.beams;
  scan.angle_min_rad = -std::numbers::pi;
  scan.range_min_m = options.min_range_m;
  scan.range_max_m = options.max_range_m;
  scan.ranges.assign(static_cast<std::size_t>(options.beams), std::numeric_limits<float>::infinity());
}

void CastBeams(const RayCaster& caster, const Eigen::Isometry3d& world_T_laser, const SimLaserOptions& options,
               std::mt19937& rng, int first, int last, LaserScan& scan) {
  const int n = options.beams;
  if (first >= last) return;
  std::vector<int> index(static_cast<std::size_t>(last - first));
  std::vector<Eigen::Vector3f> directions(index.size());
  const Eigen::Matrix3f rotation = world_T_laser.linear().cast<float>();
  for (int k = first; k < last; ++k) {
    // k beams clockwise from forward is the scan's beam n/2 - k (forward is its middle).
    const int i = ((n / 2 - k) % n + n) % n;
    const double a = scan.angle_min_rad + i * scan.angle_increment_rad;
    index[static_cast<std::size_t>(k - first)] = i;
    directions[static_cast<std::size_t>(k - first)] =
        rotation * Eigen::Vector3f(static_cast<float>(std::cos(a)), static_cast<float>(std::sin(a)), 0.0f);
  }
  std::vector<RayHit> hits(index.size());
  caster.CastFan(world_T_laser.translation().cast<float>(), directions, static_cast<float>(options.min_range_m),
                 static_cast<float>(options.max_range_m), hits);
  std::normal_distribution<float> noise(0.0f, static_cast<float>(options.noise_m));
  for (std::size_t j = 0; j < index.size(); ++j) {
    scan.ranges[static_cast<std::size_t>(index[j])] =
        hits[j].hit() ? hits[j].distance + noise(rng) : std::numeric_limits<float>::infinity();
  }
}

void CastScan(const RayCaster& caster, const Eigen::Isometry3d& world_T_laser, const SimLaserOptions& options,
              std::mt19937& rng, LaserScan& scan) {
  StartScan(options, scan);
  CastBeams(caster, world_T_laser, options, rng, 0, options.beams, scan);
}

}  // namespace corridor::drivers::sim
