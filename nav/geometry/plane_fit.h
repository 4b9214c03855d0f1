// Planes in point clouds: RANSAC (Fischler and Bolles, CACM 1981) for the plane with the most points within a
// distance, then least squares on those points (the plane through their centroid, normal to their least-spread
// direction). The floor's calibration (nav/ground/floor_fit.h) and ASNS's floor detection (nav/ground/afds.h) fit
// their planes with it. Written here: the loop is a few lines over Eigen, and PCL is a large dependency for it.
#pragma once

#include <functional>
#include <optional>
#include <random>
#include <span>

#include <Eigen/Core>

namespace corridor::nav {

// normal . p + offset = 0, `normal` of unit length.
struct Plane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double offset = 0.0;

  double Distance(const Eigen::Vector3d& p) const { return normal.dot(p) + offset; }  // signed, along the normal
};

struct PlaneRansacOptions {
  int iterations = 200;
  double inlier_m = 0.015;  // a point within this of a plane supports it
};

// The admissible plane through three of `points` (picked with `rng`) that the most points lie within inlier_m of,
// and their count; nullopt when no draw gave an admissible plane. `admissible` may flip the plane it is given (its
// normal to the side it wants) and says whether to keep it; none keeps every plane.
std::optional<std::pair<Plane, int>> RansacPlane(std::span<const Eigen::Vector3d> points,
                                                 const PlaneRansacOptions& options, std::mt19937& rng,
                                                 const std::function<bool(Plane&)>& admissible = {});

// The least-squares plane of the points within `inlier_m` of `plane` (nullopt with fewer than three), its normal on
// the same side as `plane`'s.
std::optional<Plane> RefinePlane(std::span<const Eigen::Vector3d> points, const Plane& plane, double inlier_m);

}  // namespace corridor::nav
