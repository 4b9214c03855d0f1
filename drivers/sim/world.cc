#include "drivers/sim/world.h"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <boost/property_tree/ptree.hpp>
#include <boost/property_tree/xml_parser.hpp>
#include <spdlog/spdlog.h>

#include <cctype>
#include <map>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <sstream>

#include "nav/map/map_io.h"

namespace corridor::drivers::sim {
namespace {

namespace fs = std::filesystem;
namespace pt = boost::property_tree;

const Eigen::Vector3f kWallColor(0.82f, 0.80f, 0.74f);
const Eigen::Vector3f kFloorColor(0.55f, 0.50f, 0.45f);
const Eigen::Vector3f kDefaultMeshColor(0.7f, 0.7f, 0.7f);
const Eigen::Vector3f kObstacleColor(0.75f, 0.45f, 0.2f);  // unmapped obstacles: orange
// A grid larger than this is almost surely stray geometry (see the willowgarage collision mesh).
constexpr double kMaxCollisionCells = 25e6;
// Cells at or above this occupancy (percent) become walls: map_server's default occupied threshold.
constexpr int kWallPercent = 65;

[[noreturn]] void Fail(const fs::path& file, const std::string& what) {
  throw WorldFileError("world file " + file.string() + ": " + what);
}

// SDF pose text "x y z roll pitch yaw" (fixed-axis roll, pitch, yaw) as a transform. Empty text is identity.
Eigen::Affine3f ParsePose(const std::string& text, const fs::path& file) {
  std::istringstream in(text);
  std::vector<float> v;
  for (float x; in >> x;) v.push_back(x);
  if (!in.eof() || (v.size() != 0 && v.size() != 6)) Fail(file, "bad <pose> '" + text + "'");
  if (v.empty()) return Eigen::Affine3f::Identity();
  return Eigen::Translation3f(v[0], v[1], v[2]) * Eigen::AngleAxisf(v[5], Eigen::Vector3f::UnitZ()) *
         Eigen::AngleAxisf(v[4], Eigen::Vector3f::UnitY()) * Eigen::AngleAxisf(v[3], Eigen::Vector3f::UnitX());
}

Eigen::Vector3f ParseVector3(const std::string& text, const fs::path& file, const char* what) {
  std::istringstream in(text);
  Eigen::Vector3f v;
  if (!(in >> v.x() >> v.y() >> v.z())) Fail(file, std::string("bad <") + what + "> '" + text + "'");
  return v;
}

Eigen::Affine3f PoseOf(const pt::ptree& element, const fs::path& file) {
  return ParsePose(element.get<std::string>("pose", ""), file);
}

// Loads SDF worlds and models, caching meshes that several models share.
class SdfLoader {
 public:
  // Model paths as Gazebo searches them: the configured ones (GAZEBO_MODEL_PATH's role), then beside the world.
  SdfLoader(const fs::path& world_file, const WorldOptions& options) : world_file_(fs::absolute(world_file)) {
    const fs::path dir = world_file_.parent_path();
    search_paths_ = options.model_paths;
    search_paths_.push_back(dir / "models");
    search_paths_.push_back(dir.parent_path() / "models");
    search_paths_.push_back(dir);
  }

  TriangleMesh LoadWorldFile() {
    pt::ptree doc = ReadXml(world_file_);
    const auto world = doc.get_child_optional("sdf.world");
    if (!world) Fail(world_file_, "has no <sdf><world> element");
    TriangleMesh out;
    for (const auto& [tag, child] : *world) {
      if (tag == "include") {
        AddInclude(child, Eigen::Affine3f::Identity(), out);
      } else if (tag == "model") {
        const Eigen::Affine3f world_T_model = PoseOf(child, world_file_);
        if (auto include = child.get_child_optional("include")) {
          AddInclude(*include, world_T_model, out);
        } else {
          AddModelLinks(child, world_file_.parent_path(), world_file_, world_T_model, out);
        }
      } else if (tag == "actor" || tag == "population" || tag == "road" || tag == "light") {
        Skip("<" + tag + ">");
      }
    }
    if (!skipped_.empty()) {
      std::string list;
      for (const auto& [what, count] : skipped_) {
        list += (list.empty() ? "" : ", ") + what + (count > 1 ? " x" + std::to_string(count) : "");
      }
      spdlog::warn("world {}: not simulated (nothing the robot can see or bump into): {}", world_file_.string(), list);
    }
    return out;
  }

 private:
  static pt::ptree ReadXml(const fs::path& file) {
    pt::ptree doc;
    try {
      pt::read_xml(file.string(), doc, pt::xml_parser::trim_whitespace);
    } catch (const pt::xml_parser_error& e) {
      Fail(file, std::string("is not valid XML: ") + e.what());
    }
    return doc;
  }

  // The folder of model `name` in the model paths, or nullopt.
  std::optional<fs::path> FindModel(const std::string& name) const {
    for (const fs::path& dir : search_paths_) {
      if (fs::exists(dir / name / "model.sdf")) return dir / name;
    }
    return std::nullopt;
  }

  fs::path ResolveModel(const std::string& name, const fs::path& referrer) const {
    if (auto dir = FindModel(name)) return *dir;
    std::string searched;
    for (const fs::path& dir : search_paths_) searched += (searched.empty() ? "" : ", ") + dir.string();
    Fail(referrer, "model://" + name + " not found in any model path (" + searched + "; more with sim.model_paths)");
  }

  // A URI as Gazebo resolves it: model://NAME/rest -> <NAME's folder in the model paths>/rest; file://PATH and plain
  // paths absolute as they are, relative to the referring file's folder first, then to each model path.
  fs::path ResolveUri(const std::string& uri, const fs::path& base_dir, const fs::path& referrer) const {
    constexpr std::string_view kModel = "model://";
    constexpr std::string_view kFile = "file://";
    if (uri.starts_with(kModel)) {
      const std::string rest = uri.substr(kModel.size());
      const auto slash = rest.find('/');
      const fs::path dir = ResolveModel(rest.substr(0, slash), referrer);
      return slash == std::string::npos ? dir : dir / rest.substr(slash + 1);
    }
    if (!uri.starts_with(kFile) && uri.find("://") != std::string::npos) {
      // A model on a server (Gazebo Fuel): only a copy in the model paths can be used.
      const std::string name = ModelName(uri);
      if (!name.empty()) {
        if (auto dir = FindModel(name)) return *dir;
      }
      Fail(referrer, uri + " is not on this machine: put the model in a folder of sim.model_paths" +
                         (name.empty() ? "" : " as '" + name + "'"));
    }
    const fs::path path(uri.starts_with(kFile) ? uri.substr(kFile.size()) : uri);
    if (path.is_absolute()) return path;
    if (fs::exists(base_dir / path)) return base_dir / path;
    for (const fs::path& dir : search_paths_) {
      if (fs::exists(dir / path)) return dir / path;
    }
    return base_dir / path;  // missing: the caller says so, naming this path
  }

  // The model a URI names: NAME of model://NAME/..., or of a Gazebo Fuel URL (https://fuel.../models/NAME/...), with
  // "%20" decoded; "" for other URIs.
  static std::string ModelName(const std::string& uri) {
    std::string rest;
    if (uri.starts_with("model://")) {
      rest = uri.substr(8);
    } else if (const auto at = uri.find("/models/"); at != std::string::npos && uri.find("://") != std::string::npos) {
      rest = uri.substr(at + 8);
    }
    rest = rest.substr(0, rest.find('/'));
    std::string name;
    for (std::size_t i = 0; i < rest.size(); ++i) {
      const bool space = rest.compare(i, 3, "%20") == 0;
      name += space ? ' ' : rest[i];
      if (space) i += 2;
    }
    return name;
  }

  // What one of Gazebo's own models is, when the simulator has no use for it: "sun" (a light) and "ground_plane" (the
  // simulator lays its own floor); nullopt for any other.
  static std::optional<std::string> BuiltIn(std::string name) {
    for (char& c : name) c = c == ' ' ? '_' : static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (name == "sun") return "the sun (a light)";
    if (name == "ground_plane") return "the ground plane (the simulator lays its own floor)";
    return std::nullopt;
  }

  void Skip(const std::string& what) { ++skipped_[what]; }

  void AddInclude(const pt::ptree& include, const Eigen::Affine3f& parent_T_include, TriangleMesh& out) {
    const std::string uri = include.get<std::string>("uri", "");
    if (uri.empty()) Fail(world_file_, "<include> without <uri>");
    // Gazebo's own sun and ground plane are left out, unless the model paths hold a model of that name (a world may
    // bring its own ground, walls and all).
    const std::string name = ModelName(uri);
    if (const auto built_in = BuiltIn(name); built_in && !FindModel(name)) {
      Skip(*built_in);
      return;
    }
    const fs::path model_dir = ResolveUri(uri, world_file_.parent_path(), world_file_);
    const fs::path model_file = model_dir / "model.sdf";
    const pt::ptree doc = ReadXml(model_file);
    const auto model = doc.get_child_optional("sdf.model");
    if (!model) Fail(model_file, "has no <sdf><model> element");
    Eigen::Affine3f transform = parent_T_include * PoseOf(include, world_file_) * PoseOf(*model, model_file);
    if (auto scale = include.get_optional<std::string>("scale")) {
      transform = transform * Eigen::Scaling(ParseVector3(*scale, world_file_, "scale"));
    }
    AddModelLinks(*model, model_dir, model_file, transform, out);
  }

  void AddModelLinks(const pt::ptree& model, const fs::path& model_dir, const fs::path& file,
                     const Eigen::Affine3f& world_T_model, TriangleMesh& out) {
    for (const auto& [tag, link] : model) {
      if (tag != "link") continue;
      const Eigen::Affine3f world_T_link = world_T_model * PoseOf(link, file);
      // Collision shapes are what the robot bumps into and are lighter; visuals only where a link has none.
      bool added = false;
      for (const char* kind : {"collision", "visual"}) {
        for (const auto& [shape_tag, shape] : link) {
          if (shape_tag != kind) continue;
          added |= AddGeometry(shape, model_dir, file, world_T_link * PoseOf(shape, file), out);
        }
        if (added) break;
      }
    }
  }

  bool AddGeometry(const pt::ptree& shape, const fs::path& model_dir, const fs::path& file,
                   const Eigen::Affine3f& world_T_shape, TriangleMesh& out) {
    const auto geometry = shape.get_child_optional("geometry");
    if (!geometry) return false;
    if (auto mesh = geometry->get_child_optional("mesh")) {
      const fs::path mesh_file = ResolveUri(mesh->get<std::string>("uri", ""), model_dir, file);
      if (!fs::exists(mesh_file)) {
        Skip("missing mesh " + mesh_file.string());
        return false;
      }
      Eigen::Affine3f transform = world_T_shape;
      if (auto scale = mesh->get_optional<std::string>("scale")) {
        transform = transform * Eigen::Scaling(ParseVector3(*scale, file, "scale"));
      }
      out.Append(LoadMesh(mesh_file), transform);
      return true;
    }
    if (auto box = geometry->get_child_optional("box")) {
      const Eigen::Vector3f half = ParseVector3(box->get<std::string>("size", ""), file, "size") / 2.0f;
      TriangleMesh b;
      b.AddBox(-half, half, kDefaultMeshColor);
      out.Append(b, world_T_shape);
      return true;
    }
    // Cylinders stand along their z axis, centred; spheres become the cylinder around them (what a depth camera and
    // a footprint slice see of them is close enough).
    const auto cylinder = geometry->get_child_optional("cylinder");
    const auto sphere = geometry->get_child_optional("sphere");
    if (cylinder || sphere) {
      const float radius = (cylinder ? cylinder : sphere)->get<float>("radius", 0.0f);
      const float length = cylinder ? cylinder->get<float>("length", 0.0f) : 2.0f * radius;
      if (!(radius > 0.0f) || !(length > 0.0f)) Fail(file, "a cylinder or sphere without a positive size");
      TriangleMesh c;
      c.AddCylinder({0.0f, 0.0f}, radius, length, 24, kDefaultMeshColor);
      out.Append(c, world_T_shape * Eigen::Translation3f(0.0f, 0.0f, -length / 2.0f));
      return true;
    }
    for (const auto& [kind, unused] : *geometry) Skip("<" + kind + "> geometry");
    return false;
  }

 public:
  // One mesh file through assimp, all nodes' transforms applied, in metres, Z-up kept.
  const TriangleMesh& LoadMesh(const fs::path& file) {
    auto it = cache_.find(file);
    if (it != cache_.end()) return it->second;
    Assimp::Importer importer;
    importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
    const aiScene* scene = importer.ReadFile(
        file.string(), aiProcess_Triangulate | aiProcess_PreTransformVertices | aiProcess_JoinIdenticalVertices);
    if (scene == nullptr) Fail(file, std::string("cannot be loaded: ") + importer.GetErrorString());
    TriangleMesh mesh;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
      const aiMesh* am = scene->mMeshes[m];
      Eigen::Vector3f color = kDefaultMeshColor;
      aiColor3D diffuse;
      if (scene->mMaterials[am->mMaterialIndex]->Get(AI_MATKEY_COLOR_DIFFUSE, diffuse) == AI_SUCCESS) {
        color = {diffuse.r, diffuse.g, diffuse.b};
      }
      const int base = static_cast<int>(mesh.vertices.size());
      for (unsigned v = 0; v < am->mNumVertices; ++v) {
        mesh.vertices.emplace_back(am->mVertices[v].x, am->mVertices[v].y, am->mVertices[v].z);
      }
      for (unsigned f = 0; f < am->mNumFaces; ++f) {
        const aiFace& face = am->mFaces[f];
        if (face.mNumIndices != 3) continue;  // points and lines left over after triangulation
        mesh.triangles.emplace_back(base + static_cast<int>(face.mIndices[0]),
                                    base + static_cast<int>(face.mIndices[1]),
                                    base + static_cast<int>(face.mIndices[2]));
        mesh.colors.push_back(color);
      }
    }
    return cache_.emplace(file, std::move(mesh)).first->second;
  }

 private:
  fs::path world_file_;
  std::vector<fs::path> search_paths_;
  std::map<fs::path, TriangleMesh> cache_;
  std::map<std::string, int> skipped_;  // what was left out, and how often: one warning at the end
};

// Clips a polygon to the half-space n . p >= d (one Sutherland-Hodgman step).
std::vector<Eigen::Vector3f> ClipAbove(const std::vector<Eigen::Vector3f>& poly, float z, bool keep_above) {
  std::vector<Eigen::Vector3f> out;
  const auto inside = [&](const Eigen::Vector3f& p) { return keep_above ? p.z() >= z : p.z() <= z; };
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Eigen::Vector3f& a = poly[i];
    const Eigen::Vector3f& b = poly[(i + 1) % poly.size()];
    if (inside(a)) out.push_back(a);
    if (inside(a) != inside(b)) out.push_back(a + (b - a) * ((z - a.z()) / (b.z() - a.z())));
  }
  return out;
}

}  // namespace

void TriangleMesh::Append(const TriangleMesh& other, const Eigen::Affine3f& transform) {
  const int base = static_cast<int>(vertices.size());
  vertices.reserve(vertices.size() + other.vertices.size());
  for (const Eigen::Vector3f& v : other.vertices) vertices.push_back(transform * v);
  for (const Eigen::Vector3i& t : other.triangles) triangles.push_back(t.array() + base);
  colors.insert(colors.end(), other.colors.begin(), other.colors.end());
}

double StaticObstacle::bounding_radius_m() const {
  return shape == Shape::kCylinder ? size_m : size_m * std::numbers::sqrt2;
}

const char* ShapeName(StaticObstacle::Shape shape) {
  switch (shape) {
    case StaticObstacle::Shape::kCylinder: return "cylinder";
    case StaticObstacle::Shape::kBox: return "box";
    case StaticObstacle::Shape::kTable: return "table";
  }
  return "cylinder";
}

std::optional<StaticObstacle::Shape> ShapeFromName(const std::string& name) {
  for (const auto shape :
       {StaticObstacle::Shape::kCylinder, StaticObstacle::Shape::kBox, StaticObstacle::Shape::kTable}) {
    if (name == ShapeName(shape)) return shape;
  }
  return std::nullopt;
}

void AddObstacles(World& world, const std::vector<StaticObstacle>& obstacles) {
  nav::OccupancyGrid& grid = world.collision;
  world.obstacles.insert(world.obstacles.end(), obstacles.begin(), obstacles.end());
  for (const StaticObstacle& o : obstacles) {
    const Eigen::Vector2f c = o.center.cast<float>();
    if (o.shape == StaticObstacle::Shape::kCylinder) {
      world.mesh.AddCylinder(c, static_cast<float>(o.size_m), static_cast<float>(o.height_m), 24, kObstacleColor);
    } else {
      TriangleMesh box;
      const float h = static_cast<float>(o.size_m);
      const float top = static_cast<float>(o.height_m);
      if (o.shape == StaticObstacle::Shape::kTable) {
        constexpr float kTopThickness = 0.03f;
        constexpr float kLeg = 0.04f;  // legs' side, at the top's corners
        box.AddBox({-h, -h, std::max(0.0f, top - kTopThickness)}, {h, h, top}, kObstacleColor);
        for (const float sx : {-1.0f, 1.0f}) {
          for (const float sy : {-1.0f, 1.0f}) {
            const Eigen::Vector3f corner(sx * (h - kLeg / 2), sy * (h - kLeg / 2), 0.0f);
            box.AddBox(corner - Eigen::Vector3f(kLeg / 2, kLeg / 2, 0.0f),
                       corner + Eigen::Vector3f(kLeg / 2, kLeg / 2, top), kObstacleColor);
          }
        }
      } else {
        box.AddBox({-h, -h, 0.0f}, {h, h, top}, kObstacleColor);
      }
      world.mesh.Append(box, Eigen::Translation3f(c.x(), c.y(), 0.0f) *
                                 Eigen::AngleAxisf(static_cast<float>(o.yaw_rad), Eigen::Vector3f::UnitZ()));
    }
    // Footprint cells: every cell whose centre lies within half a cell of the shape, searched over the cells
    // around its bounding circle. A table's whole top is its footprint (the robot cannot pass under it).
    const double res = grid.resolution_m();
    const double tolerance = o.size_m + 0.5 * res;
    const Eigen::Rotation2Dd to_box(-o.yaw_rad);
    const auto covers = [&](const Eigen::Vector2d& cell_center) {
      const Eigen::Vector2d d = cell_center - o.center;
      if (o.shape == StaticObstacle::Shape::kCylinder) return d.norm() <= tolerance;
      const Eigen::Vector2d local = to_box * d;
      return std::abs(local.x()) <= tolerance && std::abs(local.y()) <= tolerance;
    };
    const Eigen::Vector2d center = grid.origin().Inverse().Transform(o.center) / res;  // in cells
    const int reach = static_cast<int>(std::ceil(o.bounding_radius_m() / res)) + 1;
    const int cx = static_cast<int>(std::floor(center.x()));
    const int cy = static_cast<int>(std::floor(center.y()));
    for (int y = std::max(0, cy - reach); y <= std::min(grid.height() - 1, cy + reach); ++y) {
      for (int x = std::max(0, cx - reach); x <= std::min(grid.width() - 1, cx + reach); ++x) {
        if (covers(grid.CellCenter({x, y}))) grid.at({x, y}) = nav::kOccupiedCell;
      }
    }
  }
}

nav::OccupancyGrid RoomMap(double width_m, double height_m, double resolution_m) {
  const int w = static_cast<int>(std::lround(width_m / resolution_m)) + 2;
  const int h = static_cast<int>(std::lround(height_m / resolution_m)) + 2;
  nav::OccupancyGrid grid(w, h, resolution_m, nav::Pose2{-resolution_m, -resolution_m, 0.0}, nav::kFreeCell);
  for (int x = 0; x < w; ++x) grid.at({x, 0}) = grid.at({x, h - 1}) = nav::kOccupiedCell;
  for (int y = 0; y < h; ++y) grid.at({0, y}) = grid.at({w - 1, y}) = nav::kOccupiedCell;
  return grid;
}

void TriangleMesh::AddCylinder(const Eigen::Vector2f& center, float radius, float height, int sides,
                               const Eigen::Vector3f& color) {
  const int b = static_cast<int>(vertices.size());
  for (int i = 0; i < sides; ++i) {
    const double a = 2.0 * std::numbers::pi * i / sides;
    const Eigen::Vector2f p =
        center + radius * Eigen::Vector2f(static_cast<float>(std::cos(a)), static_cast<float>(std::sin(a)));
    vertices.emplace_back(p.x(), p.y(), 0.0f);
    vertices.emplace_back(p.x(), p.y(), height);
  }
  const int bottom = static_cast<int>(vertices.size());
  vertices.emplace_back(center.x(), center.y(), 0.0f);
  vertices.emplace_back(center.x(), center.y(), height);
  for (int i = 0; i < sides; ++i) {
    const int j = (i + 1) % sides;
    const int lo_i = b + 2 * i, hi_i = lo_i + 1, lo_j = b + 2 * j, hi_j = lo_j + 1;
    for (const Eigen::Vector3i& t : {Eigen::Vector3i(lo_i, lo_j, hi_j), Eigen::Vector3i(lo_i, hi_j, hi_i),
                                     Eigen::Vector3i(bottom, lo_j, lo_i), Eigen::Vector3i(bottom + 1, hi_i, hi_j)}) {
      triangles.push_back(t);
      colors.push_back(color);
    }
  }
}

void TriangleMesh::AddBox(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, const Eigen::Vector3f& color) {
  const int b = static_cast<int>(vertices.size());
  for (int i = 0; i < 8; ++i) {
    vertices.emplace_back((i & 1) ? hi.x() : lo.x(), (i & 2) ? hi.y() : lo.y(), (i & 4) ? hi.z() : lo.z());
  }
  // Two triangles per face, wound outwards.
  static constexpr int kFaces[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                                        {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  for (const auto& f : kFaces) {
    triangles.emplace_back(b + f[0], b + f[1], b + f[2]);
    colors.push_back(color);
  }
}

Eigen::AlignedBox3f TriangleMesh::Bounds() const {
  Eigen::AlignedBox3f box;
  for (const Eigen::Vector3i& t : triangles) {
    for (int k = 0; k < 3; ++k) box.extend(vertices[t[k]]);
  }
  return box;
}

nav::OccupancyGrid CollisionGridFromMesh(const TriangleMesh& mesh, const WorldOptions& options) {
  const float zmin = static_cast<float>(options.collision_min_height_m);
  const float zmax = static_cast<float>(options.collision_max_height_m);
  // Size the grid from the geometry that can collide, with a margin, so floors far out do not inflate it.
  Eigen::AlignedBox2f extent;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3f& v = mesh.vertices[t[k]];
      if (v.z() >= zmin && v.z() <= zmax) extent.extend(v.head<2>());
    }
  }
  const double res = options.collision_resolution_m;
  if (extent.isEmpty()) return nav::OccupancyGrid(1, 1, res, {}, nav::kFreeCell);
  const Eigen::Vector2f lo = extent.min().array() - 1.0f;
  const Eigen::Vector2f size = extent.sizes().array() + 2.0f;
  const int width = static_cast<int>(std::ceil(size.x() / res));
  const int height = static_cast<int>(std::ceil(size.y() / res));
  if (static_cast<double>(width) * height > kMaxCollisionCells) {
    throw WorldFileError("world geometry spans " + std::to_string(size.x()) + " x " + std::to_string(size.y()) +
                         " m, too large for the collision grid (stray geometry?)");
  }
  cv::Mat occupied(height, width, CV_8UC1, cv::Scalar(0));
  constexpr int kShift = 8;  // sub-cell precision for OpenCV's fixed-point rasteriser
  const float scale = static_cast<float>((1 << kShift) / res);
  for (const Eigen::Vector3i& t : mesh.triangles) {
    std::vector<Eigen::Vector3f> poly = {mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]};
    poly = ClipAbove(poly, zmin, true);
    if (poly.size() >= 3) poly = ClipAbove(poly, zmax, false);
    if (poly.size() < 2) continue;
    std::vector<cv::Point> pixels;
    for (const Eigen::Vector3f& p : poly) {
      pixels.emplace_back(static_cast<int>((p.x() - lo.x()) * scale), static_cast<int>((p.y() - lo.y()) * scale));
    }
    // A vertical wall projects to a line, which fillConvexPoly may leave empty: draw the outline too.
    cv::fillConvexPoly(occupied, pixels, cv::Scalar(255), cv::LINE_8, kShift);
    cv::polylines(occupied, pixels, true, cv::Scalar(255), 1, cv::LINE_8, kShift);
  }
  nav::OccupancyGrid grid(width, height, res, nav::Pose2{lo.x(), lo.y(), 0.0}, nav::kFreeCell);
  for (int y = 0; y < height; ++y) {
    const std::uint8_t* row = occupied.ptr<std::uint8_t>(y);
    for (int x = 0; x < width; ++x) {
      if (row[x]) grid.at({x, y}) = nav::kOccupiedCell;
    }
  }
  return grid;
}

Floors FloorsSideBySide(const std::vector<nav::OccupancyGrid>& floors, double gap_m) {
  if (floors.empty()) throw WorldFileError("a building needs one floor at least");
  const double res = floors.front().resolution_m();
  Floors out;
  double next_x = floors.front().origin().x_m;
  double min_y = 1e300;
  double max_y = -1e300;
  for (const nav::OccupancyGrid& f : floors) {
    if (std::abs(f.resolution_m() - res) > 1e-9 || std::abs(f.origin().yaw_rad) > 1e-9) {
      throw WorldFileError("a building's floor maps must share one resolution and have unrotated origins");
    }
    const double shift = next_x - f.origin().x_m;
    out.offsets.emplace_back(shift, 0.0);
    out.spans.emplace_back(next_x, next_x + f.width() * res);
    next_x += f.width() * res + gap_m;
    min_y = std::min(min_y, f.origin().y_m);
    max_y = std::max(max_y, f.origin().y_m + f.height() * res);
  }
  const double min_x = floors.front().origin().x_m;
  const int width = static_cast<int>(std::ceil((next_x - gap_m - min_x) / res));
  const int height = static_cast<int>(std::ceil((max_y - min_y) / res));
  out.map = nav::OccupancyGrid(width, height, res, nav::Pose2{min_x, min_y, 0.0}, nav::kUnknownCell);
  for (std::size_t i = 0; i < floors.size(); ++i) {
    const nav::OccupancyGrid& f = floors[i];
    const int dx = static_cast<int>(std::lround((f.origin().x_m + out.offsets[i].x() - min_x) / res));
    const int dy = static_cast<int>(std::lround((f.origin().y_m - min_y) / res));
    for (int y = 0; y < f.height(); ++y) {
      for (int x = 0; x < f.width(); ++x) {
        const nav::CellIndex c{x + dx, y + dy};
        if (out.map.Contains(c)) out.map.at(c) = f.at({x, y});
      }
    }
  }
  return out;
}

int Floors::FloorAt(const Eigen::Vector2d& world) const {
  int best = -1;
  double best_distance = 1e300;
  for (std::size_t i = 0; i < spans.size(); ++i) {
    const double d = std::max({0.0, spans[i].first - world.x(), world.x() - spans[i].second});
    if (d < best_distance) {
      best_distance = d;
      best = static_cast<int>(i);
    }
  }
  return best;
}

World WorldFromMap(const nav::OccupancyGrid& map, const WorldOptions& options) {
  World world;
  const float res = static_cast<float>(map.resolution_m());
  const float h = static_cast<float>(options.wall_height_m);
  TriangleMesh walls;
  // One box per horizontal run of occupied cells keeps the triangle count near the wall length, not area.
  for (int y = 0; y < map.height(); ++y) {
    for (int x = 0; x < map.width();) {
      if (map.at({x, y}) < kWallPercent) {
        ++x;
        continue;
      }
      const int start = x;
      while (x < map.width() && map.at({x, y}) >= kWallPercent) ++x;
      walls.AddBox({start * res, y * res, 0.0f}, {x * res, (y + 1) * res, h}, kWallColor);
    }
  }
  const nav::Pose2& o = map.origin();
  const Eigen::Affine3f world_T_map = Eigen::Translation3f(static_cast<float>(o.x_m), static_cast<float>(o.y_m), 0.0f) *
                                      Eigen::AngleAxisf(static_cast<float>(o.yaw_rad), Eigen::Vector3f::UnitZ());
  world.mesh.Append(walls, world_T_map);
  if (options.add_floor) {
    TriangleMesh floor;
    floor.AddBox({0.0f, 0.0f, -0.01f}, {map.width() * res, map.height() * res, 0.0f}, kFloorColor);
    world.mesh.Append(floor, world_T_map);
  }
  // The map itself is the collision grid: the robot bumps into exactly what the map shows as occupied.
  world.collision = nav::OccupancyGrid(map.width(), map.height(), map.resolution_m(), map.origin(), nav::kFreeCell);
  for (std::size_t i = 0; i < map.cells().size(); ++i) {
    if (map.cells()[i] >= kWallPercent) world.collision.mutable_cells()[i] = nav::kOccupiedCell;
  }
  world.source_map = map;
  std::ostringstream description;
  description << "map extruded to " << options.wall_height_m << " m walls";
  world.description = description.str();
  return world;
}

World LoadWorld(const fs::path& path, const WorldOptions& options) {
  if (!fs::exists(path)) Fail(path, "does not exist");
  const std::string ext = path.extension().string();
  if (ext == ".yaml" || ext == ".yml") {
    try {
      World world = WorldFromMap(nav::LoadMap(path), options);
      world.description = path.filename().string() + ": " + world.description;
      return world;
    } catch (const nav::MapFileError& e) {
      throw WorldFileError(e.what());
    }
  }
  World world;
  SdfLoader loader(path, options);
  if (ext == ".world" || ext == ".sdf") {
    world.mesh = loader.LoadWorldFile();
  } else {
    world.mesh = loader.LoadMesh(path);
  }
  if (world.mesh.triangles.empty()) Fail(path, "holds no triangles");
  world.collision = CollisionGridFromMesh(world.mesh, options);
  if (options.add_floor) {
    const Eigen::AlignedBox3f b = world.mesh.Bounds();
    world.mesh.AddBox({b.min().x(), b.min().y(), -0.01f}, {b.max().x(), b.max().y(), 0.0f}, kFloorColor);
  }
  world.description = path.filename().string() + ": " + std::to_string(world.mesh.triangles.size()) + " triangles";
  spdlog::info("world {}", world.description);
  return world;
}

}  // namespace corridor::drivers::sim
