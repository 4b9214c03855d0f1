#include "nav/map/map_io.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <system_error>

namespace corridor::nav {
namespace {

// Trinary-mode pixel values written by nav2_map_server's map_saver.
constexpr std::uint8_t kSavedOccupied = 0;
constexpr std::uint8_t kSavedFree = 254;
constexpr std::uint8_t kSavedUnknown = 205;

[[noreturn]] void Fail(const std::filesystem::path& file, const std::string& what) {
  throw MapFileError("map file " + file.string() + ": " + what);
}

template <typename T>
T Required(const YAML::Node& root, const char* key, const std::filesystem::path& file) {
  const YAML::Node node = root[key];
  if (!node) Fail(file, std::string("missing key '") + key + "'");
  try {
    return node.as<T>();
  } catch (const YAML::Exception&) {
    Fail(file, std::string("key '") + key + "' has the wrong type");
  }
}

// map_server accepts negate as 0/1 as well as true/false.
bool ParseNegate(const YAML::Node& node, const std::filesystem::path& file) {
  if (!node) return false;
  const std::string text = node.as<std::string>("");
  if (text == "0" || text == "false" || text == "False") return false;
  if (text == "1" || text == "true" || text == "True") return true;
  Fail(file, "key 'negate' must be 0, 1, true or false, not '" + text + "'");
}

MapMode ParseMode(const YAML::Node& node, const std::filesystem::path& file) {
  if (!node) return MapMode::kTrinary;
  const std::string text = node.as<std::string>("");
  if (text == "trinary") return MapMode::kTrinary;
  if (text == "scale") return MapMode::kScale;
  if (text == "raw") return MapMode::kRaw;
  Fail(file, "key 'mode' must be trinary, scale or raw, not '" + text + "'");
}

void WriteAtomically(const std::filesystem::path& path, const std::string& bytes) {
  const std::filesystem::path tmp = path.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.flush();
    if (!out) Fail(path, "cannot write " + tmp.string());
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) Fail(path, "cannot rename into place: " + ec.message());
}

}  // namespace

namespace {

MapMetadata ParseMapMetadata(const YAML::Node& root, const std::filesystem::path& yaml_path) {
  if (!root.IsMap()) Fail(yaml_path, "is not a YAML mapping of map_server keys");

  MapMetadata m;
  const auto image = Required<std::string>(root, "image", yaml_path);
  if (image.empty()) Fail(yaml_path, "key 'image' is empty");
  m.image = std::filesystem::path(image).is_absolute() ? std::filesystem::path(image) : yaml_path.parent_path() / image;
  m.resolution_m = Required<double>(root, "resolution", yaml_path);
  if (!(m.resolution_m > 0.0) || !std::isfinite(m.resolution_m)) Fail(yaml_path, "'resolution' must be > 0");
  const auto origin = Required<std::vector<double>>(root, "origin", yaml_path);
  if (origin.size() != 3) Fail(yaml_path, "'origin' must be [x, y, yaw]");
  m.origin = {origin[0], origin[1], origin[2]};
  if (root["occupied_thresh"]) m.occupied_thresh = Required<double>(root, "occupied_thresh", yaml_path);
  if (root["free_thresh"]) m.free_thresh = Required<double>(root, "free_thresh", yaml_path);
  if (!(0.0 <= m.free_thresh && m.free_thresh < m.occupied_thresh && m.occupied_thresh <= 1.0)) {
    Fail(yaml_path, "thresholds must satisfy 0 <= free_thresh < occupied_thresh <= 1");
  }
  m.negate = ParseNegate(root["negate"], yaml_path);
  m.mode = ParseMode(root["mode"], yaml_path);
  return m;
}

}  // namespace

MapMetadata LoadMapMetadata(const std::filesystem::path& yaml_path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(yaml_path.string());
  } catch (const YAML::BadFile&) {
    Fail(yaml_path, "cannot be opened");
  } catch (const YAML::Exception& e) {
    Fail(yaml_path, "is not valid YAML: " + std::string(e.what()));
  }
  return ParseMapMetadata(root, yaml_path);
}

MapMetadata MapMetadataFromText(const std::string& yaml, const std::filesystem::path& yaml_path) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml);
  } catch (const YAML::Exception& e) {
    Fail(yaml_path, "is not valid YAML: " + std::string(e.what()));
  }
  return ParseMapMetadata(root, yaml_path);
}

OccupancyGrid GridFromImage(const cv::Mat& image, const MapMetadata& m) {
  if (image.empty()) Fail(m.image, "image is empty");
  if (image.depth() != CV_8U) Fail(m.image, "only 8-bit images are supported");
  const int channels = image.channels();
  if (channels != 1 && channels != 2 && channels != 3 && channels != 4) Fail(m.image, "unsupported channel count");
  const bool has_alpha = channels == 2 || channels == 4;
  const int colour_channels = has_alpha ? channels - 1 : channels;

  OccupancyGrid grid(image.cols, image.rows, m.resolution_m, m.origin);
  for (int row = 0; row < image.rows; ++row) {
    const std::uint8_t* p = image.ptr<std::uint8_t>(row);
    for (int col = 0; col < image.cols; ++col, p += channels) {
      // Like map_server: the mean of the colour channels, 0 (black) .. 1 (white).
      int sum = 0;
      for (int c = 0; c < colour_channels; ++c) sum += p[c];
      const double shade = sum / (255.0 * colour_channels);
      const bool opaque = !has_alpha || p[channels - 1] == 255;
      std::int8_t value = kUnknownCell;
      if (m.mode == MapMode::kRaw) {
        const double raw = std::round(shade * 255.0);
        if (raw >= 0.0 && raw <= 100.0) value = static_cast<std::int8_t>(raw);
      } else {
        const double occ = m.negate ? shade : 1.0 - shade;
        if (m.mode == MapMode::kScale && !opaque) {
          value = kUnknownCell;
        } else if (occ > m.occupied_thresh) {
          value = kOccupiedCell;
        } else if (occ < m.free_thresh) {
          value = kFreeCell;
        } else if (m.mode == MapMode::kScale) {
          value =
              static_cast<std::int8_t>(std::rint(99.0 * (occ - m.free_thresh) / (m.occupied_thresh - m.free_thresh)));
        }
      }
      // Image row 0 is the top of the map; grid row 0 is the bottom.
      grid.at({col, image.rows - 1 - row}) = value;
    }
  }
  return grid;
}

OccupancyGrid LoadMap(const std::filesystem::path& yaml_path) {
  const MapMetadata m = LoadMapMetadata(yaml_path);
  // The error_code form: a name the system cannot even look up (too long, say) is a bad file, not an exception.
  std::error_code error;
  if (!std::filesystem::exists(m.image, error)) {
    Fail(yaml_path, "image " + m.image.string() + (error ? ": " + error.message() : " does not exist"));
  }
  cv::Mat image;
  try {
    image = cv::imread(m.image.string(), cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    Fail(m.image, std::string("cannot be decoded: ") + e.what());
  }
  if (image.empty()) Fail(m.image, "is not a readable image");
  if (image.depth() == CV_16U) image.convertTo(image, CV_8U, 1.0 / 257.0);
  return GridFromImage(image, m);
}

cv::Mat GridToImage(const OccupancyGrid& grid) {
  cv::Mat image(grid.height(), grid.width(), CV_8UC1);
  for (int y = 0; y < grid.height(); ++y) {
    std::uint8_t* row = image.ptr<std::uint8_t>(grid.height() - 1 - y);
    for (int x = 0; x < grid.width(); ++x) {
      const std::int8_t v = grid.at({x, y});
      row[x] = v < 0 ? kSavedUnknown : v >= 65 ? kSavedOccupied : v <= 19 ? kSavedFree : kSavedUnknown;
    }
  }
  return image;
}

void SaveMap(const OccupancyGrid& grid, const std::filesystem::path& yaml_path) {
  std::vector<std::uint8_t> pgm;
  if (!cv::imencode(".pgm", GridToImage(grid), pgm)) Fail(yaml_path, "cannot encode the image");
  std::filesystem::path image_path = yaml_path;
  image_path.replace_extension(".pgm");
  WriteAtomically(image_path, std::string(pgm.begin(), pgm.end()));

  WriteAtomically(yaml_path, MapYaml(grid, image_path.filename().string()));
}

std::string MapYaml(const OccupancyGrid& grid, const std::string& image) {
  YAML::Emitter out;
  out << YAML::BeginMap << YAML::Key << "image" << YAML::Value << image << YAML::Key << "mode" << YAML::Value
      << "trinary" << YAML::Key << "resolution" << YAML::Value << grid.resolution_m() << YAML::Key << "origin"
      << YAML::Value << YAML::Flow << YAML::BeginSeq << grid.origin().x_m << grid.origin().y_m << grid.origin().yaw_rad
      << YAML::EndSeq << YAML::Key << "negate" << YAML::Value << 0 << YAML::Key << "occupied_thresh" << YAML::Value
      << 0.65 << YAML::Key << "free_thresh" << YAML::Value << 0.196 << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

}  // namespace corridor::nav
