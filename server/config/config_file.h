// The configuration file read and changed through the API (GET and PATCH /api/v1/config): the file's document as
// JSON, and a JSON merge patch (RFC 7396) applied to it, checked as strictly as at start-up, then written in place of
// the file atomically (a temporary file beside it, renamed over it). corridord reads its configuration at start, so
// every change takes effect at the next start. Comments in the file are not kept by a rewrite.
#pragma once

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace corridor::server {

// The file's document. Throws ConfigError when it cannot be read.
nlohmann::json ConfigDocument(const std::filesystem::path& file);

struct ConfigChange {
  nlohmann::json document;           // the file's document now
  std::vector<std::string> changed;  // dotted key paths whose value changed
};

// Applies `patch` (an object: null removes a key) to the file. Throws ConfigError for a result that is not a valid
// configuration (the file is left as it was) and std::runtime_error when the file cannot be written.
ConfigChange PatchConfigFile(const std::filesystem::path& file, const nlohmann::json& patch);

}  // namespace corridor::server
