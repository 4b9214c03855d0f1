#include "server/config/config_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <charconv>
#include <cstdlib>
#include <cstring>
#include <fstream>

#include "server/config/config.h"

namespace corridor::server {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// A plain YAML scalar as the JSON value YAML 1.2's core schema gives it; quoted ones stay strings.
json ScalarJson(const YAML::Node& node) {
  const std::string& text = node.Scalar();
  if (node.Tag() == "!") return text;
  if (text == "true" || text == "True" || text == "TRUE") return true;
  if (text == "false" || text == "False" || text == "FALSE") return false;
  if (text.empty() || text == "~" || text == "null" || text == "Null" || text == "NULL") return nullptr;
  long long integer = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), integer);
  if (ec == std::errc() && end == text.data() + text.size()) return integer;
  char* stop = nullptr;
  const double number = std::strtod(text.c_str(), &stop);
  if (stop == text.c_str() + text.size() && text.find_first_of("0123456789") != std::string::npos) return number;
  return text;
}

json ToJson(const YAML::Node& node) {
  switch (node.Type()) {
    case YAML::NodeType::Map: {
      json out = json::object();
      for (const auto& entry : node) out[entry.first.as<std::string>()] = ToJson(entry.second);
      return out;
    }
    case YAML::NodeType::Sequence: {
      json out = json::array();
      for (const auto& item : node) out.push_back(ToJson(item));
      return out;
    }
    case YAML::NodeType::Scalar: return ScalarJson(node);
    default: return nullptr;
  }
}

void Emit(YAML::Emitter& out, const json& value) {
  if (value.is_object()) {
    out << YAML::BeginMap;
    for (const auto& [key, item] : value.items()) {
      out << YAML::Key << key << YAML::Value;
      Emit(out, item);
    }
    out << YAML::EndMap;
  } else if (value.is_array()) {
    out << YAML::Flow << YAML::BeginSeq;
    for (const json& item : value) Emit(out, item);
    out << YAML::EndSeq;
  } else if (value.is_string()) {
    // A string that would read back as another type is quoted.
    const std::string& text = value.get_ref<const std::string&>();
    YAML::Node probe;
    try {
      probe = YAML::Load(text);
    } catch (const YAML::Exception&) {
    }
    const bool plain = probe.IsScalar() && probe.Scalar() == text && ScalarJson(probe).is_string();
    if (plain) {
      out << text;
    } else {
      out << YAML::DoubleQuoted << text;
    }
  } else if (value.is_null()) {
    out << YAML::Null;
  } else {
    out << value.dump();
  }
}

void Differences(const json& before, const json& after, const std::string& path, std::vector<std::string>& out) {
  // An absent section is an empty one: the keys added or removed are named, not the section.
  if (before.is_null() && after.is_object()) return Differences(json::object(), after, path, out);
  if (before.is_object() && after.is_null()) return Differences(before, json::object(), path, out);
  if (before.is_object() && after.is_object()) {
    for (const auto& [key, value] : before.items()) {
      const std::string at = path.empty() ? key : path + "." + key;
      Differences(value, after.contains(key) ? after[key] : json(), at, out);
    }
    for (const auto& [key, value] : after.items()) {
      if (!before.contains(key)) Differences(json(), value, path.empty() ? key : path + "." + key, out);
    }
  } else if (before != after) {
    out.push_back(path);
  }
}

// Writes `text` to `file` through a temporary file beside it, synced before it is renamed over the file.
void WriteAtomically(const fs::path& file, const std::string& text) {
  const fs::path temporary = file.string() + ".new";
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0640);
  if (fd < 0) throw std::runtime_error("cannot write " + temporary.string() + ": " + std::strerror(errno));
  struct stat old {};
  if (::stat(file.c_str(), &old) == 0) ::fchmod(fd, old.st_mode & 07777);
  const bool written = ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size()) && ::fsync(fd) == 0;
  ::close(fd);
  if (!written || ::rename(temporary.c_str(), file.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    ::unlink(temporary.c_str());
    throw std::runtime_error("cannot replace " + file.string() + ": " + why);
  }
}

}  // namespace

json ConfigDocument(const fs::path& file) {
  const json document = ToJson(ReadConfigYaml(file));
  return document.is_object() ? document : json::object();
}

ConfigChange PatchConfigFile(const fs::path& file, const json& patch) {
  const json before = ConfigDocument(file);
  json after = before;
  after.merge_patch(patch);
  YAML::Emitter out;
  out << YAML::Comment("corridord configuration, last written through PATCH /api/v1/config") << YAML::Newline;
  Emit(out, after);
  const std::string text = std::string(out.c_str()) + "\n";
  ConfigFromYaml(YAML::Load(text), file);  // as strict as at start-up; throws ConfigError
  ConfigChange change{after, {}};
  Differences(before, after, "", change.changed);
  if (!change.changed.empty()) WriteAtomically(file, text);
  return change;
}

}  // namespace corridor::server
