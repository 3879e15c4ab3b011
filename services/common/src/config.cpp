#include "scanbus/config.hpp"

#include <fstream>

namespace scanbus {

namespace {

std::string join(const std::string& prefix, const std::string& key) {
  return prefix.empty() ? key : prefix + "." + key;
}

std::string describe(const YAML::Node& node) {
  if (node.IsMap()) return "a map";
  if (node.IsSequence()) return "a list";
  if (node.IsNull()) return "nothing";
  return "'" + node.Scalar() + "'";
}

// Bounds on what a config may hold. Aliases make a small file a large tree (yaml-cpp
// shares the aliased node, so each walk over it repeats it: eight levels of ten aliases
// made a 546-byte file that every walk took minutes over); the largest shipped config or
// room file has a few hundred nodes.
constexpr size_t kMaxFileBytes = 1 << 20;
constexpr size_t kMaxNodes = 100000;  // after following aliases
constexpr int kMaxDepth = 64;

// Every key a plain name: YAML allows lists and maps as keys ("[a, b]: 1"), which no getter
// can name (found by tests/fuzz, config). Counts the nodes with aliases followed.
void check_keys(const YAML::Node& node, const std::string& origin, int depth, size_t& nodes) {
  if (++nodes > kMaxNodes)
    throw ConfigError(origin + ": more than " + std::to_string(kMaxNodes) +
                      " values once its aliases are expanded; refused (aliases of aliases?)");
  if (depth > kMaxDepth)
    throw ConfigError(origin + ": line " + std::to_string(node.Mark().line + 1) + ": nested deeper than " +
                      std::to_string(kMaxDepth) + " levels; refused");
  if (node.IsSequence())
    for (const auto& item : node) check_keys(item, origin, depth + 1, nodes);
  if (!node.IsMap()) return;
  for (const auto& entry : node) {
    if (!entry.first.IsScalar())
      throw ConfigError(origin + ": line " + std::to_string(entry.first.Mark().line + 1) +
                        ": a key must be a plain name, got " + describe(entry.first));
    check_keys(entry.second, origin, depth + 1, nodes);
  }
}

}  // namespace

Config::Config(std::shared_ptr<State> state, YAML::Node node, std::string prefix)
    : state_(std::move(state)), node_(std::move(node)), prefix_(std::move(prefix)) {}

Config Config::load(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ConfigError(path + ": cannot open config file");
  std::string text(kMaxFileBytes + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<size_t>(in.gcount()));  // one byte past the bound is enough to refuse it
  return parse(text, path);
}

Config Config::parse(const std::string& yaml_text, const std::string& origin) {
  auto state = std::make_shared<State>();
  state->origin = origin;
  if (yaml_text.size() > kMaxFileBytes)
    throw ConfigError(origin + ": larger than " + std::to_string(kMaxFileBytes >> 20) +
                      " MiB; refused (not a config?)");
  try {
    state->root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw ConfigError(origin + ": invalid YAML at line " + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
  if (state->root.IsNull()) state->root = YAML::Node(YAML::NodeType::Map);
  if (!state->root.IsMap()) throw ConfigError(origin + ": top level must be a map of keys");
  size_t nodes = 0;
  check_keys(state->root, origin, 0, nodes);
  return Config(state, state->root, "");
}

std::string Config::path_of(const std::string& key) const { return join(prefix_, key); }

void Config::fail(const std::string& key, const std::string& what) const {
  throw ConfigError(state_->origin + ": key '" + path_of(key) + "' " + what);
}

bool Config::has(const std::string& key) const { return static_cast<bool>(node_[key]); }

Config Config::section(const std::string& key) const {
  state_->read_sections.insert(path_of(key));
  YAML::Node child = node_[key];
  if (!child || child.IsNull()) return Config(state_, YAML::Node(YAML::NodeType::Map), path_of(key));
  if (!child.IsMap()) fail(key, "must be a map, got " + describe(child));
  return Config(state_, child, path_of(key));
}

std::vector<std::string> Config::keys() const {
  std::vector<std::string> out;
  for (const auto& entry : node_) out.push_back(entry.first.as<std::string>());
  return out;
}

YAML::Node Config::scalar(const std::string& key) const {
  state_->read_leaves.insert(path_of(key));
  YAML::Node value = node_[key];
  if (value && !value.IsScalar()) fail(key, "must be a single value, got " + describe(value));
  return value;
}

double Config::number(const std::string& key, double fallback, double min, double max) const {
  YAML::Node value = scalar(key);
  double result = fallback;
  if (value) {
    try {
      result = value.as<double>();
    } catch (const YAML::Exception&) {
      fail(key, "must be a number, got " + describe(value));
    }
  }
  if (!(result >= min && result <= max)) {
    fail(key, "must be between " + std::to_string(min) + " and " + std::to_string(max) + ", got " +
                  (value ? value.Scalar() : std::to_string(result)));
  }
  return result;
}

long long Config::integer(const std::string& key, long long fallback, long long min, long long max) const {
  YAML::Node value = scalar(key);
  long long result = fallback;
  if (value) {
    try {
      result = value.as<long long>();
    } catch (const YAML::Exception&) {
      fail(key, "must be a whole number, got " + describe(value));
    }
  }
  if (result < min || result > max) {
    fail(key,
         "must be between " + std::to_string(min) + " and " + std::to_string(max) + ", got " + std::to_string(result));
  }
  return result;
}

bool Config::flag(const std::string& key, bool fallback) const {
  YAML::Node value = scalar(key);
  if (!value) return fallback;
  try {
    return value.as<bool>();
  } catch (const YAML::Exception&) {
    fail(key, "must be true or false, got " + describe(value));
  }
}

std::string Config::text(const std::string& key, const std::string& fallback) const {
  YAML::Node value = scalar(key);
  return value ? value.as<std::string>() : fallback;
}

std::string Config::choice(const std::string& key, const std::string& fallback,
                           const std::vector<std::string>& allowed) const {
  std::string value = text(key, fallback);
  for (const auto& option : allowed)
    if (option == value) return value;
  std::string list;
  for (const auto& option : allowed) list += (list.empty() ? "" : ", ") + option;
  fail(key, "must be one of " + list + ", got '" + value + "'");
}

void Config::missing(const std::string& key) const { fail(key, "is required"); }

std::vector<double> Config::row_of(const YAML::Node& list, const std::string& key, size_t width) const {
  if (!list.IsSequence() || list.size() != width)
    fail(key, "must be a list of " + std::to_string(width) + " numbers, got " + describe(list));
  std::vector<double> row;
  for (const auto& item : list) {
    try {
      row.push_back(item.as<double>());
    } catch (const YAML::Exception&) {
      fail(key, "must hold numbers, got " + describe(item));
    }
  }
  return row;
}

std::vector<double> Config::numbers(const std::string& key, size_t width) const {
  state_->read_leaves.insert(path_of(key));
  if (!node_[key]) missing(key);
  return row_of(node_[key], key, width);
}

std::vector<std::vector<double>> Config::number_rows(const std::string& key, size_t width) const {
  state_->read_leaves.insert(path_of(key));
  const YAML::Node list = node_[key];
  if (!list) missing(key);
  if (!list.IsSequence()) fail(key, "must be a list, got " + describe(list));
  std::vector<std::vector<double>> rows;
  for (size_t i = 0; i < list.size(); ++i) rows.push_back(row_of(list[i], key + "[" + std::to_string(i) + "]", width));
  return rows;
}

std::vector<std::string> Config::texts(const std::string& key) const {
  state_->read_leaves.insert(path_of(key));
  const YAML::Node list = node_[key];
  std::vector<std::string> out;
  if (!list || list.IsNull()) return out;
  if (!list.IsSequence()) fail(key, "must be a list of names, got " + describe(list));
  for (size_t i = 0; i < list.size(); ++i) {
    if (!list[i].IsScalar()) fail(key + "[" + std::to_string(i) + "]", "must be a name, got " + describe(list[i]));
    out.push_back(list[i].as<std::string>());
  }
  return out;
}

std::vector<Config> Config::maps(const std::string& key) const {
  state_->read_sections.insert(path_of(key));
  const YAML::Node list = node_[key];
  std::vector<Config> out;
  if (!list || list.IsNull()) return out;
  if (!list.IsSequence()) fail(key, "must be a list, got " + describe(list));
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string name = key + "[" + std::to_string(i) + "]";
    if (!list[i].IsMap()) fail(name, "must be a map, got " + describe(list[i]));
    state_->read_sections.insert(path_of(name));
    out.push_back(Config(state_, list[i], path_of(name)));
  }
  return out;
}

void Config::check_all_read() const { check_node(node_, prefix_); }

void Config::check_node(const YAML::Node& node, const std::string& prefix) const {
  if (!node.IsMap()) return;  // a list's values are values, not keys
  for (const auto& entry : node) {
    const std::string path = join(prefix, entry.first.as<std::string>());
    if (state_->read_leaves.count(path)) continue;
    if (state_->read_sections.count(path) && entry.second.IsMap()) {
      check_node(entry.second, path);
      continue;
    }
    if (state_->read_sections.count(path) && entry.second.IsNull()) continue;
    if (state_->read_sections.count(path) && entry.second.IsSequence()) {
      for (size_t i = 0; i < entry.second.size(); ++i)
        check_node(entry.second[i], path + "[" + std::to_string(i) + "]");
      continue;
    }
    throw ConfigError(state_->origin + ": unknown key '" + path + "'");
  }
}

}  // namespace scanbus
