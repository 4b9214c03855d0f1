#include "nav/localization/carmen_log.h"

#include <cstring>
#include <memory>
#include <sstream>
#include <string>

#include <zlib.h>

namespace corridor::nav {
namespace {

struct GzCloser {
  void operator()(gzFile_s* f) const { gzclose(f); }
};

// Reads one line (without its end) into `line`; false at the end of the file.
bool ReadLine(gzFile file, std::string& line) {
  line.clear();
  char buffer[8192];
  while (gzgets(file, buffer, sizeof buffer) != nullptr) {
    line += buffer;
    if (!line.empty() && line.back() == '\n') {
      line.pop_back();
      return true;
    }
  }
  return !line.empty();
}

}  // namespace

CarmenLog ReadCarmenLog(const std::filesystem::path& path, double fov_rad) {
  // gzopen reads uncompressed files unchanged.
  std::unique_ptr<gzFile_s, GzCloser> file(gzopen(path.c_str(), "rb"));
  if (!file) throw CarmenLogError(path.string() + ": cannot open: " + std::strerror(errno));
  CarmenLog log;
  std::string line;
  int number = 0;
  while (ReadLine(file.get(), line)) {
    ++number;
    if (line.rfind("FLASER ", 0) != 0) continue;
    const auto fail = [&](const std::string& what) {
      return CarmenLogError(path.string() + ":" + std::to_string(number) + ": FLASER " + what);
    };
    std::istringstream in(line.substr(7));
    int n = 0;
    if (!(in >> n) || n <= 1 || n > 100000) throw fail("has no reading count");
    CarmenScan scan;
    scan.ranges_m.resize(n);
    for (float& r : scan.ranges_m) {
      if (!(in >> r)) throw fail("has fewer readings than its count " + std::to_string(n));
    }
    double odom[3];
    std::string host;
    if (!(in >> scan.pose.x_m >> scan.pose.y_m >> scan.pose.yaw_rad >> odom[0] >> odom[1] >> odom[2] >>
          scan.timestamp_s)) {
      throw fail("has no pose or timestamp after its readings");
    }
    scan.pose.yaw_rad = WrapAngle(scan.pose.yaw_rad);
    scan.angle_increment_rad = fov_rad / (n % 2 == 0 ? n : n - 1);
    scan.angle_min_rad = -fov_rad / 2.0;
    log.scans.push_back(std::move(scan));
  }
  int error = 0;
  gzerror(file.get(), &error);
  if (error != Z_OK && error != Z_STREAM_END) throw CarmenLogError(path.string() + ": the file is damaged");
  return log;
}

}  // namespace corridor::nav
