#include "server/store/map_library.h"

#include <spdlog/spdlog.h>

#include <opencv2/imgcodecs.hpp>

#include <set>

#include "nav/map/map_io.h"

namespace corridor::server {
namespace {

namespace fs = std::filesystem;

}  // namespace

std::string EncodePng(const nav::OccupancyGrid& grid) {
  std::vector<std::uint8_t> png;
  cv::imencode(".png", nav::GridToImage(grid), png);
  return {png.begin(), png.end()};
}

bool ValidMapName(const std::string& name) {
  if (name.empty() || name.size() > 64 || name[0] == '.') return false;
  for (char c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_' && c != '.') return false;
  }
  return true;
}

MapLibrary::MapLibrary(const fs::path& state_dir, std::string name, nav::OccupancyGrid initial,
                       std::function<void(std::shared_ptr<const ActiveMap>)> on_change)
    : dir_(state_dir / "maps"), on_change_(std::move(on_change)) {
  if (!ValidMapName(name)) name = "map";
  initial_name_ = name;
  initial_ = std::make_shared<const nav::OccupancyGrid>(initial);
  const fs::path saved = dir_ / name / "map.yaml";
  if (fs::exists(saved)) {
    try {
      initial = nav::LoadMap(saved);
      spdlog::info("map '{}': using the edited copy in {}", name, saved.string());
    } catch (const nav::MapFileError& e) {
      spdlog::warn("map '{}': the edited copy is unreadable ({}); using the configured map", name, e.what());
    }
  }
  auto map = std::make_shared<ActiveMap>();
  map->name = std::move(name);
  map->png = EncodePng(initial);
  map->grid = std::move(initial);
  active_ = std::move(map);
}

std::shared_ptr<const ActiveMap> MapLibrary::active() const {
  std::lock_guard lock(mutex_);
  return active_;
}

std::vector<std::string> MapLibrary::Names() const {
  std::vector<std::string> names{active()->name};
  std::set<std::string> others;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir_, ec)) {
    if (fs::exists(entry.path() / "map.yaml")) others.insert(entry.path().filename().string());
  }
  {
    std::lock_guard lock(mutex_);
    for (const auto& [name, file] : configured_) others.insert(name);
  }
  others.insert(initial_name_);
  others.erase(names[0]);
  names.insert(names.end(), others.begin(), others.end());
  return names;
}

void MapLibrary::Publish(nav::OccupancyGrid grid, const std::string& name, bool save) {
  if (save) {
    fs::create_directories(dir_ / name);
    try {
      nav::SaveMap(grid, dir_ / name / "map.yaml");
    } catch (const nav::MapFileError& e) {
      throw MapEditError(std::string("the map could not be saved: ") + e.what());
    }
  }
  auto map = std::make_shared<ActiveMap>();
  map->name = name;
  map->png = EncodePng(grid);
  map->grid = std::move(grid);
  std::shared_ptr<const ActiveMap> published;
  {
    std::lock_guard lock(mutex_);
    map->revision = active_->revision + 1;
    active_ = std::move(map);
    published = active_;
  }
  if (on_change_) on_change_(published);
}

void MapLibrary::EditCells(const std::vector<CellEdit>& edits) {
  const auto current = active();
  nav::OccupancyGrid grid = current->grid;
  for (std::size_t i = 0; i < edits.size(); ++i) {
    const CellEdit& e = edits[i];
    if (!grid.Contains({e.x, e.y})) {
      throw MapEditError("cells[" + std::to_string(i) + "]: (" + std::to_string(e.x) + ", " + std::to_string(e.y) +
                         ") is outside the " + std::to_string(grid.width()) + " x " + std::to_string(grid.height()) +
                         " map");
    }
    if (e.value != nav::kUnknownCell && e.value != nav::kFreeCell && e.value != nav::kOccupiedCell) {
      throw MapEditError("cells[" + std::to_string(i) + "]: value must be -1 (unknown), 0 (free) or 100 (occupied)");
    }
    grid.at({e.x, e.y}) = e.value;
  }
  Publish(std::move(grid), current->name, true);
}

void MapLibrary::ReplaceImage(const std::string& bytes) {
  const auto current = active();
  const std::vector<std::uint8_t> data(bytes.begin(), bytes.end());
  cv::Mat image;
  try {
    image = cv::imdecode(data, cv::IMREAD_GRAYSCALE);
  } catch (const cv::Exception&) {
  }
  if (image.empty()) throw MapEditError("the body is not a PNG or PGM image");
  if (image.cols != current->grid.width() || image.rows != current->grid.height()) {
    throw MapEditError("the image is " + std::to_string(image.cols) + " x " + std::to_string(image.rows) +
                       ", the map is " + std::to_string(current->grid.width()) + " x " +
                       std::to_string(current->grid.height()));
  }
  nav::MapMetadata meta;
  meta.resolution_m = current->grid.resolution_m();
  meta.origin = current->grid.origin();
  Publish(nav::GridFromImage(image, meta), current->name, true);
}

nav::OccupancyGrid MapLibrary::Load(const std::string& name) const {
  if (!ValidMapName(name)) throw MapEditError("'" + name + "' is not a map name");
  fs::path file = dir_ / name / "map.yaml";
  if (!fs::exists(file)) {
    if (name == initial_name_) return *initial_;
    std::lock_guard lock(mutex_);
    const auto it = configured_.find(name);
    if (it == configured_.end()) throw MapEditError("no map named '" + name + "'");
    file = it->second;
  }
  try {
    return nav::LoadMap(file);
  } catch (const nav::MapFileError& e) {
    throw MapEditError(e.what());
  }
}

void MapLibrary::Select(const std::string& name) {
  if (name == active()->name) return;
  Publish(Load(name), name, false);
}

std::shared_ptr<const nav::OccupancyGrid> MapLibrary::Grid(const std::string& name) const {
  const auto current = active();
  if (current->name == name) return {current, &current->grid};
  return std::make_shared<const nav::OccupancyGrid>(Load(name));
}

void MapLibrary::AddConfigured(const std::string& name, const fs::path& file) {
  std::lock_guard lock(mutex_);
  configured_[name] = file;
}

bool MapLibrary::Contains(const std::string& name) const {
  if (name == active()->name || name == initial_name_ || (ValidMapName(name) && fs::exists(dir_ / name / "map.yaml")))
    return true;
  std::lock_guard lock(mutex_);
  return configured_.contains(name);
}

void MapLibrary::Add(const std::string& name, nav::OccupancyGrid grid) {
  if (!ValidMapName(name)) throw MapEditError("'" + name + "' is not a map name");
  if (Contains(name)) throw MapEditError("a map named '" + name + "' exists");
  if (grid.width() == 0 || grid.height() == 0) throw MapEditError("the map is empty");
  Publish(std::move(grid), name, true);
}

}  // namespace corridor::server
