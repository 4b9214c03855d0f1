// Strict YAML reading: every key is read at most once by name; a key nobody read, a wrong type or a value out of
// range is an error that names the key's full path (e.g. "sim.camera.width").
#pragma once

#include <yaml-cpp/yaml.h>

#include <nlohmann/json.hpp>

#include <functional>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace corridor::server {

// A configuration problem, reported to the user as is; what() starts with the key path.
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// What a reader learns of each key it reads, when asked to (ConfigReader::Describe): the configuration's schema, made
// by the very code that checks it, so that the two cannot disagree.
struct ConfigField {
  std::string path;                  // dotted; a list's items as key[i]
  std::string type;                  // "boolean", "integer", "number" or "string"
  nlohmann::json default_value;      // the value before the key was read: the code's default
  std::optional<double> min, max;    // the range checked, when there is one
  std::vector<std::string> choices;  // the names allowed, when there is a fixed set
};
using ConfigSchema = std::vector<ConfigField>;

class ConfigReader {
 public:
  // `node` must be a mapping or null (an absent section); `path` is its dotted key path ("" at the root).
  ConfigReader(YAML::Node node, std::string path);

  // Reads an optional key into `value`, which keeps its default when the key is absent.
  template <typename T>
  void Read(const char* key, T& value) {
    if constexpr (std::is_arithmetic_v<T> || std::is_same_v<T, std::string>) Record(key, TypeId<T>(), value);
    const YAML::Node child = Take(key);
    if (!child || child.IsNull()) return;  // absent, or "key:" with no value: keep the default
    try {
      value = child.as<T>();
    } catch (const YAML::Exception&) {
      throw ConfigError(PathOf(key) + ": expected " + TypeName<T>() + ", got '" + Text(child) + "'");
    }
  }

  // Reads an optional number and checks min <= value <= max (the default is checked too).
  template <typename T>
  void Read(const char* key, T& value, T min, T max) {
    Read(key, value);
    Check(key, value, min, max);
  }
  // Throws ConfigError unless min <= value <= max.
  template <typename T>
  void Check(const char* key, const T& value, T min, T max) const {
    if (ConfigField* field = Recorded(key)) {
      field->min = static_cast<double>(min);
      field->max = static_cast<double>(max);
    }
    if (!(value >= min && value <= max)) {
      std::ostringstream msg;
      msg << PathOf(key) << ": must be between " << min << " and " << max << ", got " << value;
      throw ConfigError(msg.str());
    }
  }

  // Reads an optional key naming one of `choices` into `value`; an unknown name is an error that lists them.
  template <typename T>
  void ReadChoice(const char* key, T& value, const std::vector<std::pair<std::string, T>>& choices) {
    std::string name;
    std::string names;
    for (std::size_t i = 0; i < choices.size(); ++i) {
      if (choices[i].second == value) name = choices[i].first;
      names += (i == 0 ? "" : i + 1 == choices.size() ? " or " : ", ") + choices[i].first;
    }
    Read(key, name);
    if (ConfigField* field = Recorded(key)) {
      for (const auto& choice : choices) field->choices.push_back(choice.first);
    }
    for (const auto& [n, v] : choices) {
      if (n == name) {
        value = v;
        return;
      }
    }
    throw ConfigError(PathOf(key) + ": must be " + names + ", got '" + name + "'");
  }

  // Reads an optional nested section with `read`, then checks that no key in it was left unread.
  void Section(const char* key, const std::function<void(ConfigReader&)>& read);

  // Reads an optional list of mappings, each with `read_item` (its path is key[i]); absent or null: no items.
  void List(const char* key, const std::function<void(ConfigReader&)>& read_item);
  // Throws ConfigError naming the first key that was never read.
  void Finish() const;

  const std::string& path() const { return path_; }
  std::string PathOf(const char* key) const { return path_.empty() ? key : path_ + "." + key; }

  // Records every key read from here on (and in the sections and lists read through this reader) into `schema`.
  void Describe(ConfigSchema* schema) { schema_ = schema; }

 private:
  YAML::Node Take(const char* key);
  void Record(const char* key, const char* type, nlohmann::json default_value);
  // The field recorded for `key` by this reader, or null when not describing.
  ConfigField* Recorded(const char* key) const;
  template <typename T>
  static const char* TypeId() {
    if constexpr (std::is_same_v<T, bool>)
      return "boolean";
    else if constexpr (std::is_integral_v<T>)
      return "integer";
    else if constexpr (std::is_floating_point_v<T>)
      return "number";
    else
      return "string";
  }
  static std::string Text(const YAML::Node& node);
  // The type in an error's words.
  template <typename T>
  static std::string TypeName() {
    const std::string id = TypeId<T>();
    return id == "boolean"   ? "true or false"
           : id == "integer" ? "an integer"
           : id == "number"  ? "a number"
                             : "a string";
  }

  YAML::Node node_;
  std::string path_;
  std::set<std::string> read_;
  ConfigSchema* schema_ = nullptr;
};

}  // namespace corridor::server
