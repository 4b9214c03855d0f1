#include "server/config/config_reader.h"

namespace corridor::server {

ConfigReader::ConfigReader(YAML::Node node, std::string path) : node_(std::move(node)), path_(std::move(path)) {
  if (node_ && !node_.IsNull() && !node_.IsMap()) {
    throw ConfigError((path_.empty() ? std::string("the file") : path_) + ": expected a mapping of keys");
  }
}

YAML::Node ConfigReader::Take(const char* key) {
  if (!read_.insert(key).second) throw std::logic_error("config key read twice: " + PathOf(key));
  // Looked up through a const node: yaml-cpp's non-const operator[] would insert the key.
  const YAML::Node& node = node_;
  if (!node || !node.IsMap()) return YAML::Node(YAML::NodeType::Null);
  return node[key];
}

void ConfigReader::Record(const char* key, const char* type, nlohmann::json default_value) {
  if (!schema_) return;
  ConfigField field;
  field.path = PathOf(key);
  field.type = type;
  field.default_value = std::move(default_value);
  schema_->push_back(std::move(field));
}

ConfigField* ConfigReader::Recorded(const char* key) const {
  if (!schema_) return nullptr;
  const std::string path = PathOf(key);
  for (auto field = schema_->rbegin(); field != schema_->rend(); ++field) {
    if (field->path == path) return &*field;
  }
  return nullptr;
}

void ConfigReader::Section(const char* key, const std::function<void(ConfigReader&)>& read) {
  ConfigReader section(Take(key), PathOf(key));
  section.schema_ = schema_;
  read(section);
  section.Finish();
}

void ConfigReader::List(const char* key, const std::function<void(ConfigReader&)>& read_item) {
  const YAML::Node list = Take(key);
  if (!list || list.IsNull()) return;
  if (!list.IsSequence()) throw ConfigError(PathOf(key) + ": expected a list");
  for (std::size_t i = 0; i < list.size(); ++i) {
    ConfigReader item(list[i], PathOf(key) + "[" + std::to_string(i) + "]");
    item.schema_ = schema_;
    read_item(item);
    item.Finish();
  }
}

void ConfigReader::Finish() const {
  if (!node_ || !node_.IsMap()) return;
  for (const auto& entry : node_) {
    // YAML allows any node as a key ("? a: 1" makes a mapping one); ours are plain names.
    if (!entry.first.IsScalar()) {
      throw ConfigError((path_.empty() ? std::string("the file") : path_) + ": a key must be a plain name, got " +
                        Text(entry.first) + " (line " + std::to_string(entry.first.Mark().line + 1) + ")");
    }
    const std::string key = entry.first.Scalar();
    if (!read_.contains(key)) throw ConfigError(PathOf(key.c_str()) + ": unknown key");
  }
}

std::string ConfigReader::Text(const YAML::Node& node) {
  if (node.IsScalar()) return node.Scalar();
  if (node.IsSequence()) return "a list";
  if (node.IsMap()) return "a mapping";
  return "nothing";
}

}  // namespace corridor::server
