// Reading and writing maps in the ROS map_server format: a YAML file naming an image (PGM, PNG, ...) and
// its resolution, origin, thresholds, negate flag and mode (trinary, scale or raw), with the same pixel
// interpretation as nav2_map_server so that maps made by ROS tools load unchanged.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>

#include <opencv2/core.hpp>

#include "nav/map/occupancy_grid.h"

namespace corridor::nav {

enum class MapMode { kTrinary, kScale, kRaw };

// The metadata of a map_server YAML file.
struct MapMetadata {
  std::filesystem::path image;  // resolved against the YAML file's folder
  double resolution_m = 0.05;
  Pose2 origin;  // pose of the lower-left pixel's corner in the map frame
  double occupied_thresh = 0.65;
  double free_thresh = 0.196;
  bool negate = false;
  MapMode mode = MapMode::kTrinary;
};

// A map file that cannot be read or does not follow the format; what() names the file and the problem.
class MapFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Reads the YAML metadata only. Throws MapFileError.
MapMetadata LoadMapMetadata(const std::filesystem::path& yaml_path);
// The same from the YAML's text, as if it were the file `yaml_path` (its image resolved against that file's folder,
// errors naming it). Throws MapFileError.
MapMetadata MapMetadataFromText(const std::string& yaml, const std::filesystem::path& yaml_path);

// Turns an 8-bit image (grey, grey+alpha, BGR or BGRA; row 0 at the top) into a grid using the metadata's
// mode, negate flag and thresholds. Throws MapFileError for an empty or unsupported image.
OccupancyGrid GridFromImage(const cv::Mat& image, const MapMetadata& metadata);

// Loads a map_server map (YAML + image). Throws MapFileError naming the file for any problem.
OccupancyGrid LoadMap(const std::filesystem::path& yaml_path);

// Writes `grid` as `<stem>.pgm` and `<stem>.yaml` in trinary mode (occupied 0, free 254, unknown 205),
// each atomically (temporary file, then rename). Throws MapFileError when a file cannot be written.
void SaveMap(const OccupancyGrid& grid, const std::filesystem::path& yaml_path);

// The map_server YAML for `grid` in trinary mode naming `image` (its file name, beside the YAML), as SaveMap writes it.
std::string MapYaml(const OccupancyGrid& grid, const std::string& image);

// The image nav2_map_server would save for `grid` in trinary mode: 8-bit grey, row 0 at the top.
cv::Mat GridToImage(const OccupancyGrid& grid);

}  // namespace corridor::nav
