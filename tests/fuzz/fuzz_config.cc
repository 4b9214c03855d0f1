// libFuzzer target: a configuration file, through the strict YAML loader corridord starts with. Whatever is wrong with
// it must come out as a ConfigError naming the key; anything else escaping is a bug.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <string>

#include "server/config/config.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string file = "/tmp/corridor-fuzz-config-" + std::to_string(getpid()) + ".yaml";
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    corridor::server::LoadConfig(file);
  } catch (const corridor::server::ConfigError&) {
  }
  return 0;
}
