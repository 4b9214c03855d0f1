#include "server/config/config_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <charconv>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <regex>
#include <sstream>

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

// Where a comment starts in a YAML line (a '#' outside quotes, at the start or after a space), or npos.
std::size_t CommentStart(const std::string& line) {
  char quote = 0;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quote) {
      if (c == quote) quote = 0;
    } else if (c == '"' || c == '\'') {
      quote = c;
    } else if (c == '#' && (i == 0 || line[i - 1] == ' ' || line[i - 1] == '\t')) {
      return i;
    }
  }
  return std::string::npos;
}

std::string Trim(const std::string& text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string::npos) return "";
  return text.substr(first, text.find_last_not_of(" \t") - first + 1);
}

}  // namespace

std::map<std::string, std::string> ConfigComments(const std::string& yaml) {
  static const std::regex kKey(R"(^( *)([A-Za-z_][A-Za-z0-9_]*):( .*|)$)");
  std::map<std::string, std::string> help;
  std::vector<std::pair<std::size_t, std::string>> keys;  // the open keys: indentation, name
  std::string block;                                      // comment lines since the last key or blank line
  std::string* continued = nullptr;                       // the help a comment in `column` continues
  std::size_t column = std::string::npos;
  std::istringstream in(yaml);
  std::string line;
  while (std::getline(in, line)) {
    const std::size_t hash = CommentStart(line);
    const std::string code = Trim(line.substr(0, hash));
    const std::string comment = hash == std::string::npos ? "" : Trim(line.substr(hash + 1));
    if (code.empty()) {
      if (hash == std::string::npos) {  // a blank line ends a block
        block.clear();
        continued = nullptr;
      } else if (continued && hash == column) {
        *continued += " " + comment;
      } else {
        // Prose wrapped over lines joins up; an indented line (a table, an example) keeps its own line.
        continued = nullptr;
        const std::string raw = line.substr(hash + 1);
        const bool indented = raw.starts_with("  ");
        block += (block.empty() ? "" : indented ? "\n" : " ") + (indented ? raw.substr(1) : comment);
      }
      continue;
    }
    std::smatch match;
    continued = nullptr;
    const std::string before_comment = line.substr(0, hash);
    if (!std::regex_match(before_comment, match, kKey)) {
      block.clear();
      continue;
    }
    const std::size_t indent = match[1].length();
    while (!keys.empty() && keys.back().first >= indent) keys.pop_back();
    keys.emplace_back(indent, match[2]);
    std::string path;
    for (const auto& key : keys) path += (path.empty() ? "" : ".") + key.second;
    std::string text = block;
    if (!comment.empty()) text += (text.empty() ? "" : "\n") + comment;
    block.clear();
    if (text.empty()) continue;
    std::string& entry = help[path];
    entry = text;
    if (!comment.empty()) {
      continued = &entry;
      column = hash;
    }
  }
  return help;
}

std::string UnitOfKey(const std::string& key) {
  static const std::vector<std::pair<std::string, std::string>> kUnits = {
      {"_mps2", "m/s²"},   {"_rps2", "rad/s²"}, {"_mps", "m/s"},      {"_rps", "rad/s"}, {"_ms", "ms"},
      {"_m", "m"},         {"_s", "s"},         {"_hz", "Hz"},        {"_deg", "°"},     {"_rad", "rad"},
      {"_px", "px"},       {"_percent", "%"},   {"_v", "V"},          {"_w", "W"},       {"_wh", "Wh"},
      {"_bytes", "bytes"}, {"_hours", "h"},     {"_wpm", "words/min"}};
  for (const auto& [suffix, unit] : kUnits) {
    if (key.size() > suffix.size() && key.ends_with(suffix)) return unit;
  }
  return "";
}

json ConfigSchemaJson(const fs::path& file) {
  ConfigSchema schema;
  ConfigFromYaml(ReadConfigYaml(file), file, &schema);
  const std::map<std::string, std::string> comments = ConfigComments(ShippedConfigText());
  json fields = json::array();
  for (const ConfigField& f : schema) {
    json field = {{"path", f.path}, {"type", f.type}, {"default", f.default_value}};
    if (f.min) field["min"] = *f.min;
    if (f.max) field["max"] = *f.max;
    if (!f.choices.empty()) field["choices"] = f.choices;
    const std::string key = f.path.substr(f.path.rfind('.') + 1);
    field["unit"] = UnitOfKey(key);
    const auto help = comments.find(f.path);
    field["help"] = help == comments.end() ? "" : help->second;
    fields.push_back(std::move(field));
  }
  json sections = json::object();
  for (const auto& [path, help] : comments) {
    if (path.find('.') == std::string::npos) sections[path] = help;
  }
  return {{"fields", std::move(fields)}, {"sections", std::move(sections)}};
}

std::vector<std::string> ChangedKeys(const json& before, const json& after) {
  std::vector<std::string> changed;
  Differences(before, after, "", changed);
  return changed;
}

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
  ConfigChange change{after, ChangedKeys(before, after)};
  if (!change.changed.empty()) WriteAtomically(file, text);
  return change;
}

}  // namespace corridor::server
