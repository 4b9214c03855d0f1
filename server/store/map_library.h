// The maps the robot knows and the one it works in. Maps live in <state_dir>/maps/NAME/map.{yaml,pgm} (ROS
// map_server format); the configured map is the first, and an edited map is saved there under its name, so edits
// survive restarts. Saving is atomic (temporary file, then rename). Thread-safe.
#pragma once

#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "nav/map/occupancy_grid.h"

namespace corridor::server {

// The map in use, immutable once published: edits make a new one.
struct ActiveMap {
  std::string name;
  nav::OccupancyGrid grid;
  std::string png;             // 8-bit grey, map_server trinary shades, row 0 at the top
  std::uint64_t revision = 0;  // bumped by every edit and selection
};

// A map edit or selection the library refuses; what() says why, kind() what about (for an API's status).
class MapEditError : public std::invalid_argument {
 public:
  enum class Kind {
    kInvalid,     // the edit, the file or the image is not right
    kBadName,     // not a map name
    kNameTaken,   // a map of that name exists
    kUnknownMap,  // no map of that name
    kInUse,       // the map in use may not be renamed or deleted
    kConfigured,  // nor may a map the configuration names
  };
  explicit MapEditError(const std::string& what, Kind kind = Kind::kInvalid)
      : std::invalid_argument(what), kind_(kind) {}
  Kind kind() const { return kind_; }

 private:
  Kind kind_;
};

struct CellEdit {
  int x = 0;
  int y = 0;
  std::int8_t value = nav::kUnknownCell;  // -1, 0 or 100
};

class MapLibrary {
 public:
  // Starts with `initial` named `name`; a saved edit of the same name in the state directory takes precedence. The
  // initial map stays among the maps (Names, Select, Grid) whatever is made active after it.
  // `on_change` runs (on the caller's thread) after every edit or selection, with the lock released.
  MapLibrary(const std::filesystem::path& state_dir, std::string name, nav::OccupancyGrid initial,
             std::function<void(std::shared_ptr<const ActiveMap>)> on_change);

  std::shared_ptr<const ActiveMap> active() const;
  std::vector<std::string> Names() const;

  // Sets cells (grid coordinates, values -1, 0 or 100) and saves. Throws MapEditError for a cell outside the map
  // or a bad value; nothing changes then.
  void EditCells(const std::vector<CellEdit>& edits);
  // Replaces the whole map with an image of the same size (PNG or PGM bytes, map_server trinary shades).
  void ReplaceImage(const std::string& bytes);
  // Makes a saved map the active one. Throws MapEditError when there is no such map.
  void Select(const std::string& name);
  // Saves a new map (one just built) under `name` and makes it the active one. Throws MapEditError for a name that
  // is not valid or already taken, or when it cannot be saved; nothing changes then.
  void Add(const std::string& name, nav::OccupancyGrid grid);
  bool Contains(const std::string& name) const;
  // Whether `name` is a map the configuration names (the initial map, a floor's): it is neither renamed nor deleted.
  bool Configured(const std::string& name) const;
  // Saves a map given as map_server files' contents (its YAML, and the image whatever the YAML calls it: PNG or PGM)
  // under `name`, without making it the active one. Throws MapEditError for a name that is not valid or is taken, or
  // files that are not a map (saying what is wrong); nothing is saved then.
  void Import(const std::string& name, const std::string& yaml, const std::string& image);
  // Renames a saved map (its files, its 3D map). Throws MapEditError for the active map, a configured or unknown one,
  // or a new name that is not valid or is taken; nothing changes then.
  void Rename(const std::string& from, const std::string& to);
  // Deletes a saved map and its files. Throws MapEditError for the active map or a configured or unknown one.
  void Delete(const std::string& name);
  // Map `name` as map_server files: a YAML naming `name`.png, and that PNG. Throws MapEditError when there is no
  // such map or it cannot be read.
  std::pair<std::string, std::string> Files(const std::string& name) const;
  // A map the configuration names (a floor's): selectable by `name`, read from `file` unless an edited copy is saved.
  void AddConfigured(const std::string& name, const std::filesystem::path& file);
  // The grid of map `name` (the active one, an edited copy or a configured file). Throws MapEditError when there is
  // no such map or it cannot be read.
  std::shared_ptr<const nav::OccupancyGrid> Grid(const std::string& name) const;

 private:
  void Publish(nav::OccupancyGrid grid, const std::string& name, bool save);
  // Throws MapEditError unless `name` is a saved map that may be `what` (renamed, deleted): see Rename.
  void CheckOwned(const std::string& name, const char* what) const;
  // The saved (edited) copy of `name`, else its configured file; throws MapEditError.
  nav::OccupancyGrid Load(const std::string& name) const;

  std::filesystem::path dir_;
  std::function<void(std::shared_ptr<const ActiveMap>)> on_change_;
  mutable std::mutex mutex_;
  std::shared_ptr<const ActiveMap> active_;
  std::map<std::string, std::filesystem::path> configured_;  // guarded by mutex_
  // The map the library started with, as configured (it may have no file: a world's collision slice). It stays
  // selectable whatever becomes active after it; an edited copy saved under its name takes precedence.
  std::string initial_name_;
  std::shared_ptr<const nav::OccupancyGrid> initial_;
};

// The grid as an 8-bit grey PNG, map_server trinary shades, row 0 at the top.
std::string EncodePng(const nav::OccupancyGrid& grid);

// True for names usable as folder names: letters, digits, '-', '_' and '.', not starting with '.'.
bool ValidMapName(const std::string& name);

}  // namespace corridor::server
