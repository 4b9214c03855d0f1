// For tests: the source tree, where test data and shipped configuration live. CTest passes it as
// CORRIDOR_SOURCE_DIR (see corridor_add_test); run by hand from the tree's root, it is the working directory.
#pragma once

#include <cstdlib>
#include <filesystem>

namespace corridor::testing {

inline std::filesystem::path SourceDir() {
  const char* dir = std::getenv("CORRIDOR_SOURCE_DIR");
  return dir ? std::filesystem::path(dir) : std::filesystem::current_path();
}

// The shipped configuration, config/corridor.yaml (the simulated robot in the default world).
inline std::filesystem::path ShippedConfig() { return SourceDir() / "config/corridor.yaml"; }

}  // namespace corridor::testing
