#include "server/nodes/octree_node.h"

#include <fstream>
#include <sstream>

#include <spdlog/spdlog.h>

#include "server/runtime/topics.h"

namespace corridor::server {
namespace {

constexpr drivers::TimeNs kPoseGapNs = 100'000'000;  // a frame farther than this from every pose is not placed

drivers::TimeNs Ns(double seconds) { return static_cast<drivers::TimeNs>(seconds * 1e9); }

std::optional<std::string> ReadFile(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return std::move(bytes).str();
}

// Written to a temporary file first, then renamed over the old one: a crash leaves the old file or the new.
void WriteAtomically(const std::filesystem::path& file, const std::string& bytes) {
  std::filesystem::create_directories(file.parent_path());
  const std::filesystem::path temporary = file.string() + ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (!out) throw std::runtime_error(temporary.string() + ": cannot write");
  }
  std::filesystem::rename(temporary, file);
}

}  // namespace

OctreeNode::OctreeNode(Executor& mapping, Bus& bus, const OctreeOptions& options, const nav::PinholeCamera& camera,
                       bool trust_pose, std::filesystem::path maps_dir)
    : Node("octree", mapping, bus),
      options_(options),
      camera_(camera),
      trust_pose_(trust_pose),
      maps_dir_(std::move(maps_dir)),
      octree_(options.octree) {}

void OctreeNode::Activate() {
  if (!tapped_) {
    tapped_ = true;
    // Each pose recorded on its publisher's thread: this thread wakes for the frames, not the poses' 50 Hz.
    bus().Get(topics::kPose).Tap([poses = poses_](const StampedPose& pose) { poses->Add(pose.stamp_ns, pose.pose); });
  }
  Subscribe(topics::kMapping, "mapping", [this](const auto& mapping) { OnMapping(*mapping); });
  Subscribe(topics::kMapInUse, "map", [this](const auto& map) { OnMap(*map); });
  Subscribe(topics::kRgbd, "frame", [this](const auto& frame) { OnFrame(*frame); });
  SetHealth(Health::kOk, "waiting for a map and depth frames");
}

void OctreeNode::Cleanup() {
  Run("save", [this] { Save(); });
}

void OctreeNode::OnMap(const MapInUse& in_use) {
  if (!in_use.grid || in_use.grid == map_) return;  // its zones or doors changed, not its cells
  map_ = in_use.grid;
  layer_ = nullptr;
  if (in_use.name != name_) {
    Switch(in_use.name);
  } else if (mapping_) {
    mapping_ = false;  // the map just built is saved and in use: its octree is saved beside it now
    Save();
  }
  // The layer for the new grid, all of it, on the next frame.
  const nav::OccupancyGrid& map = *map_;
  const Eigen::Vector2d lo = map.origin().translation();
  touched_ = Eigen::AlignedBox2d(lo, lo + Eigen::Vector2d(map.width(), map.height()) * map.resolution_m());
  last_update_ns_ = 0;
}

void OctreeNode::Snapshot(std::function<void(std::shared_ptr<const OctreeSnapshot>)> done) {
  executor().Post([this, done = std::move(done)] {
    Run("snapshot", [&] {
      const drivers::TimeNs now = clock().Now();
      if (revision_ > 0 &&
          (!snapshot_ || (snapshot_->revision != revision_ && now - snapshot_ns_ >= Ns(options_.update_every_s)))) {
        auto snapshot = std::make_shared<OctreeSnapshot>();
        snapshot->map = name_;
        snapshot->revision = revision_;
        snapshot->resolution_m = octree_.resolution_m();
        snapshot->leaves = octree_.leaf_count();
        snapshot->bt = octree_.ToBinary();
        for (const nav::OccupiedVoxel& v : octree_.OccupiedVoxels()) {
          snapshot->voxels.insert(snapshot->voxels.end(), {v.center.x(), v.center.y(), v.center.z(), v.size_m});
        }
        snapshot_ = std::move(snapshot);
        snapshot_ns_ = now;
      }
    });
    done(revision_ > 0 ? snapshot_ : nullptr);  // whatever happened: the request must get its answer
  });
}

void OctreeNode::OnMapping(const MappingState& mapping) {
  if (mapping.active && !mapping_) {
    Save();  // the old map's octree, before the new one starts empty
    mapping_ = true;
    name_ = mapping.name;
    octree_ = nav::OccupancyOctree(options_.octree);
    unsaved_ = false;
    ++revision_;
    spdlog::info("octree: a new 3D map for '{}'", name_);
  }
}

bool OctreeNode::PoseTrusted() {
  if (trust_pose_ || mapping_) return true;
  const auto state = bus().Get(topics::kLocalization).latest();
  return state && state->estimate.health == nav::LocalizationHealth::kOk;
}

std::optional<nav::Pose2> OctreeNode::PoseAt(drivers::TimeNs stamp_ns) const {
  return poses_->At(stamp_ns, kPoseGapNs);
}

void OctreeNode::OnFrame(const drivers::RgbdFrame& frame) {
  if (name_.empty()) return;  // no map yet
  if (frame.stamp_ns - last_insert_ns_ >= Ns(options_.insert_every_s) && PoseTrusted()) {
    if (const auto pose = PoseAt(frame.stamp_ns)) {
      octree_.InsertDepth(frame.depth_mm, drivers::CameraAt(frame, camera_), *pose);
      last_insert_ns_ = frame.stamp_ns;
      unsaved_ = true;
      ++revision_;
      Touched(*pose);
    }
  }
  if (frame.stamp_ns - last_update_ns_ >= Ns(options_.update_every_s)) {
    last_update_ns_ = frame.stamp_ns;
    UpdateLayer();
  }
  if (unsaved_ && !mapping_ && frame.stamp_ns - last_save_ns_ >= Ns(options_.save_every_s)) {
    Save();
    last_save_ns_ = frame.stamp_ns;
  }
}

void OctreeNode::Touched(const nav::Pose2& map_T_base) {
  const Eigen::Vector2d camera = map_T_base.Transform(camera_.base_T_camera.translation().head<2>());
  const Eigen::Vector2d reach = Eigen::Vector2d::Constant(options_.octree.max_range_m + options_.octree.resolution_m);
  const Eigen::AlignedBox2d box(camera - reach, camera + reach);
  touched_ = touched_ ? touched_->merged(box) : box;
}

void OctreeNode::UpdateLayer() {
  // The layer belongs to the active map; while a new one is built, the planner has that map, not this octree's.
  if (!options_.costmap_layer || !map_ || mapping_ || !touched_) return;
  auto cells = layer_ ? std::make_shared<std::vector<std::int8_t>>(*layer_)
                      : std::make_shared<std::vector<std::int8_t>>(
                            static_cast<std::size_t>(map_->width()) * map_->height(), nav::kFreeCell);
  octree_.ProjectOccupied(*map_, options_.min_height_m, options_.max_height_m, *touched_, *cells);
  touched_.reset();
  if (layer_ && *layer_ == *cells) return;
  layer_ = cells;
  obstacle_topic_.Publish(ObstacleLayer{map_, std::move(cells)});
}

void OctreeNode::Switch(const std::string& name) {
  Save();
  name_ = name;
  mapping_ = false;
  unsaved_ = false;
  ++revision_;
  octree_ = nav::OccupancyOctree(options_.octree);
  SetHealth(Health::kOk, "3D map of '" + name + "'");
  const std::filesystem::path file = FileOf(name);
  const auto bytes = ReadFile(file);
  if (!bytes) return;  // a map without a 3D map yet
  try {
    octree_ = nav::OccupancyOctree::FromBinary(*bytes, options_.octree);
    spdlog::info("octree: '{}' read, {} leaves", file.string(), octree_.leaf_count());
  } catch (const nav::OctreeFormatError& e) {
    // Moved aside, not overwritten by the next save: someone may want it back.
    const std::filesystem::path aside = file.string() + ".unreadable";
    std::error_code ec;
    std::filesystem::rename(file, aside, ec);
    spdlog::warn("octree: '{}' cannot be read ({}); moved to '{}', starting an empty 3D map", file.string(), e.what(),
                 aside.string());
    SetHealth(Health::kDegraded, file.string() + " cannot be read (" + e.what() + "); moved aside");
  }
}

void OctreeNode::Save() {
  if (!unsaved_ || name_.empty() || mapping_) return;
  try {
    WriteAtomically(FileOf(name_), octree_.ToBinary());
    unsaved_ = false;
    spdlog::debug("octree: '{}' saved", FileOf(name_).string());
  } catch (const std::exception& e) {
    spdlog::error("octree: '{}' cannot be saved: {}", FileOf(name_).string(), e.what());
    SetHealth(Health::kDegraded, "cannot save: " + std::string(e.what()));
  }
}

}  // namespace corridor::server
