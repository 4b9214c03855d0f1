// The configuration file read and changed through the API (GET and PATCH /api/v1/config): the file's document as
// JSON, and a JSON merge patch (RFC 7396) applied to it, checked as strictly as at start-up, then written in place of
// the file atomically (a temporary file beside it, renamed over it). corridord reads its configuration at start, so
// every change takes effect at the next start. Comments in the file are not kept by a rewrite.
#pragma once

#include <nlohmann/json.hpp>

#include <filesystem>
#include <map>
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

// The dotted key paths whose values differ between two documents (a key absent from one counts as changed).
std::vector<std::string> ChangedKeys(const nlohmann::json& before, const nlohmann::json& after);

// The configuration's schema for people, for the file's configuration: every key it reads (the checking code
// describing itself: type, default, range, choices), with the unit its name ends in and the help the shipped
// config/corridor.yaml gives it in comments. {"fields": [{path, type, default, min, max, choices, unit, help}],
// "sections": {name: help}}. Throws ConfigError when the file is not a valid configuration.
nlohmann::json ConfigSchemaJson(const std::filesystem::path& file);

// The comments of a commented YAML configuration by dotted key path: the comment after a key with the comment lines
// continuing it, after a block of comment lines right above the key (a blank line ends a block).
std::map<std::string, std::string> ConfigComments(const std::string& yaml);

// The unit a key's name ends in ("_mps": "m/s"), or "" for none.
std::string UnitOfKey(const std::string& key);

// The configuration file corridor ships (config/corridor.yaml), comments and all, as built in.
const std::string& ShippedConfigText();

}  // namespace corridor::server
