#include "server/store/map_library.h"

#include <spdlog/spdlog.h>

#include <opencv2/imgcodecs.hpp>

#include <set>

#include "nav/map/map_io.h"

namespace corridor::server {
namespace {

namespace fs = std::filesystem;

// An image in a file format OpenCV reads (PNG, PGM, ...), or an empty one when the bytes are none.
cv::Mat DecodeImage(const std::string& bytes, int flags) {
  const std::vector<std::uint8_t> data(bytes.begin(), bytes.end());
  try {
    return cv::imdecode(data, flags);
  } catch (const cv::Exception&) {
    return {};
  }
}

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
    const std::string name = entry.path().filename().string();
    if (ValidMapName(name) && fs::exists(entry.path() / "map.yaml")) others.insert(name);  // not one being deleted
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
  const cv::Mat image = DecodeImage(bytes, cv::IMREAD_GRAYSCALE);
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
  if (!ValidMapName(name)) throw MapEditError("'" + name + "' is not a map name", MapEditError::Kind::kUnknownMap);
  fs::path file = dir_ / name / "map.yaml";
  if (!fs::exists(file)) {
    if (name == initial_name_) return *initial_;
    std::lock_guard lock(mutex_);
    const auto it = configured_.find(name);
    if (it == configured_.end()) throw MapEditError("no map named '" + name + "'", MapEditError::Kind::kUnknownMap);
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

bool MapLibrary::Configured(const std::string& name) const {
  if (name == initial_name_) return true;
  std::lock_guard lock(mutex_);
  return configured_.contains(name);
}

void MapLibrary::Import(const std::string& name, const std::string& yaml, const std::string& image) {
  if (!ValidMapName(name))
    throw MapEditError("'" + name + "' is not a map name (letters, digits, '-', '_', '.')",
                       MapEditError::Kind::kBadName);
  if (Contains(name)) throw MapEditError("a map named '" + name + "' exists", MapEditError::Kind::kNameTaken);
  // The YAML's metadata as the map_server reader takes it from a file (its image name is not used: the image is
  // the bytes given).
  nav::OccupancyGrid grid;
  try {
    const nav::MapMetadata meta = nav::MapMetadataFromText(yaml, name + ".yaml");
    cv::Mat decoded = DecodeImage(image, cv::IMREAD_UNCHANGED);
    if (decoded.empty()) throw MapEditError("the image is not a PNG or PGM image");
    constexpr int kMaxCells = 8192 * 8192;  // 410 m square at 5 cm: a building's floor with room to spare
    if (decoded.total() > kMaxCells) throw MapEditError("the image has more than 8192 x 8192 cells");
    if (decoded.depth() != CV_8U) decoded.convertTo(decoded, CV_8U, 1.0 / 257.0);
    grid = nav::GridFromImage(decoded, meta);
  } catch (const nav::MapFileError& e) {
    throw MapEditError(std::string("not a map_server map: ") + e.what());
  }
  try {
    fs::create_directories(dir_ / name);
    nav::SaveMap(grid, dir_ / name / "map.yaml");
  } catch (const std::exception& e) {
    std::error_code ignored;
    fs::remove_all(dir_ / name, ignored);
    throw MapEditError(std::string("the map could not be saved: ") + e.what());
  }
}

void MapLibrary::CheckOwned(const std::string& name, const char* what) const {
  if (Configured(name)) {
    throw MapEditError("map '" + name + "' is the configuration's (corridor.yaml): it cannot be " + what,
                       MapEditError::Kind::kConfigured);
  }
  if (!ValidMapName(name) || !fs::exists(dir_ / name / "map.yaml"))
    throw MapEditError("no map named '" + name + "'", MapEditError::Kind::kUnknownMap);
  if (name == active()->name)
    throw MapEditError("map '" + name + "' is in use: choose another map first", MapEditError::Kind::kInUse);
}

void MapLibrary::Rename(const std::string& from, const std::string& to) {
  CheckOwned(from, "renamed");
  if (!ValidMapName(to))
    throw MapEditError("'" + to + "' is not a map name (letters, digits, '-', '_', '.')", MapEditError::Kind::kBadName);
  if (Contains(to)) throw MapEditError("a map named '" + to + "' exists", MapEditError::Kind::kNameTaken);
  std::error_code ec;
  fs::rename(dir_ / from, dir_ / to, ec);
  if (ec) throw MapEditError("map '" + from + "' could not be renamed: " + ec.message());
}

void MapLibrary::Delete(const std::string& name) {
  CheckOwned(name, "deleted");
  // Out of the library at once (a rename), then its files removed.
  const fs::path gone = dir_ / (".deleted-" + name);
  std::error_code ec;
  fs::remove_all(gone, ec);
  fs::rename(dir_ / name, gone, ec);
  if (ec) throw MapEditError("map '" + name + "' could not be deleted: " + ec.message());
  fs::remove_all(gone, ec);
}

std::pair<std::string, std::string> MapLibrary::Files(const std::string& name) const {
  const std::shared_ptr<const nav::OccupancyGrid> grid = Grid(name);
  return {nav::MapYaml(*grid, name + ".png"), EncodePng(*grid)};
}

bool MapLibrary::Contains(const std::string& name) const {
  if (name == active()->name || name == initial_name_ || (ValidMapName(name) && fs::exists(dir_ / name / "map.yaml")))
    return true;
  std::lock_guard lock(mutex_);
  return configured_.contains(name);
}

void MapLibrary::Add(const std::string& name, nav::OccupancyGrid grid) {
  if (!ValidMapName(name)) throw MapEditError("'" + name + "' is not a map name", MapEditError::Kind::kBadName);
  if (Contains(name)) throw MapEditError("a map named '" + name + "' exists", MapEditError::Kind::kNameTaken);
  if (grid.width() == 0 || grid.height() == 0) throw MapEditError("the map is empty");
  Publish(std::move(grid), name, true);
}

}  // namespace corridor::server
