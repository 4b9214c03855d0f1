// The simulator's static world: a triangle mesh in the world frame (metres, z up, floor at z = 0) for ray casting
// depth and laser, and a 2D collision grid for the robot's footprint. Worlds come from a ROS map_server map
// (occupied cells extruded to walls) or from 3D meshes (an SDF .world with model includes, or one mesh file).
#pragma once

#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "nav/map/occupancy_grid.h"

namespace corridor::drivers::sim {

// Triangles with one RGB colour (0..1) each.
struct TriangleMesh {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<Eigen::Vector3i> triangles;
  std::vector<Eigen::Vector3f> colors;

  // Adds `other` transformed by `transform`.
  void Append(const TriangleMesh& other, const Eigen::Affine3f& transform = Eigen::Affine3f::Identity());
  // Adds an axis-aligned box with corners lo and hi.
  void AddBox(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, const Eigen::Vector3f& color);
  // Adds a vertical cylinder standing on z = 0 as a closed prism of `sides` faces.
  void AddCylinder(const Eigen::Vector2f& center, float radius, float height, int sides, const Eigen::Vector3f& color);
  Eigen::AlignedBox3f Bounds() const;
};

struct WorldOptions {
  double wall_height_m = 2.5;                      // height of walls extruded from a 2D map
  double collision_resolution_m = 0.05;            // cell size of the footprint collision grid
  double collision_min_height_m = 0.03;            // geometry below this (floors, carpets, thresholds) is driven over
  double collision_max_height_m = 1.2;             // geometry above this (tables' undersides aside) is passed under
  bool add_floor = true;                           // add a floor plane at z = 0 under the whole world
  std::vector<std::filesystem::path> model_paths;  // extra folders searched for model://NAME
};

// Things standing on the floor that are not in the robot's map: the DPoom evaluation's unit cubes and cylinders, and
// tables (a square top on four thin legs: a laser below the top sees only the legs).
struct StaticObstacle {
  enum class Shape { kCylinder, kBox, kTable };
  Shape shape = Shape::kCylinder;
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  double size_m = 0.5;    // cylinder: radius; box and table: half the side of the square
  double height_m = 1.0;  // table: of its top
  double yaw_rad = 0.0;   // boxes and tables

  // The radius of a circle around it, for avoidance and placement.
  double bounding_radius_m() const;
};

// "cylinder", "box" or "table"; and back (nullopt for another name).
const char* ShapeName(StaticObstacle::Shape shape);
std::optional<StaticObstacle::Shape> ShapeFromName(const std::string& name);

struct World {
  TriangleMesh mesh;
  // Occupied where any geometry lies between collision_min_height_m and collision_max_height_m.
  nav::OccupancyGrid collision;
  // The map the world was extruded from (map_server worlds only): the daemon works in it without reading it again.
  std::optional<nav::OccupancyGrid> source_map;
  // Obstacles added with AddObstacles (in mesh and collision, not in source_map).
  std::vector<StaticObstacle> obstacles;
  std::string description;
};

// A world file that cannot be loaded; what() names the file and the problem.
class WorldFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// An empty rectangular room, width_m x height_m inside, walled by one cell, its inside corner at (0, 0): a map for
// scenarios and tests.
nav::OccupancyGrid RoomMap(double width_m, double height_m, double resolution_m);

// Walls of wall_height_m on every occupied cell of `map`; unknown cells are left open.
World WorldFromMap(const nav::OccupancyGrid& map, const WorldOptions& options);

// A building's floors (their maps, same resolution) side by side along x, gap_m apart, as one map: floor i's map
// frame is the world frame shifted by offsets[i] (the first floor's is zero). Throws WorldFileError for no floors or
// mixed resolutions.
struct Floors {
  nav::OccupancyGrid map;
  std::vector<Eigen::Vector2d> offsets;
  // The floor a world point lies on: the one whose extent along x holds it (or the nearest); -1 without floors.
  int FloorAt(const Eigen::Vector2d& world) const;
  std::vector<std::pair<double, double>> spans;  // each floor's extent along x, world frame
};
Floors FloorsSideBySide(const std::vector<nav::OccupancyGrid>& floors, double gap_m);

// Loads by extension: .yaml (map_server map), .world or .sdf (SDF world: <include> and <model><include> entries
// with their poses, each model's mesh URIs and scales; collision meshes preferred over visual ones), anything else
// as a single mesh file through assimp (COLLADA kept Z-up, units applied). Throws WorldFileError.
World LoadWorld(const std::filesystem::path& path, const WorldOptions& options);

// Adds obstacles to a world: their surfaces to the mesh (seen by the camera and the laser) and their footprints to
// the collision grid. Not to its source map: they are what the robot's map does not know.
void AddObstacles(World& world, const std::vector<StaticObstacle>& obstacles);

// Rasterises the mesh's parts between the collision heights into a grid covering the mesh's extent.
nav::OccupancyGrid CollisionGridFromMesh(const TriangleMesh& mesh, const WorldOptions& options);

}  // namespace corridor::drivers::sim
