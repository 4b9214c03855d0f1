// libFuzzer target: a ROS map_server map (YAML + PGM or PNG image), through the loader the daemon and the simulator
// use. Whatever is wrong with it must come out as a MapFileError; anything else escaping is a bug.
#include <fuzzer/FuzzedDataProvider.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "nav/map/map_io.h"

namespace {

void Write(const std::filesystem::path& file, const std::string& bytes) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::filesystem::path dir = [] {
    const auto d = std::filesystem::temp_directory_path() / ("corridor-fuzz-map-" + std::to_string(getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  FuzzedDataProvider input(data, size);
  const std::string yaml = input.ConsumeRandomLengthString(4096);
  const std::string image = input.ConsumeRemainingBytesAsString();
  Write(dir / "map.yaml", yaml);
  Write(dir / "map.pgm", image);  // the seeds' YAML names one of the two
  Write(dir / "map.png", image);
  try {
    corridor::nav::LoadMap(dir / "map.yaml");
  } catch (const corridor::nav::MapFileError&) {
  }
  return 0;
}
