// YAML configuration with validation. No DDS here: cores and adapters both read it.
#pragma once

#include <yaml-cpp/yaml.h>

#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace scanbus {

// A configuration problem: the message names the file and the key, and the program exits 2.
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A view of one map in a YAML file. Typed getters remember every key they were asked for,
// so a key no one reads (a typo, a setting of another service) is reported as unknown by
// check_all_read() instead of being silently ignored.
class Config {
 public:
  static Config load(const std::string& path);
  static Config parse(const std::string& yaml_text, const std::string& origin);

  // The map under `key`; an empty map when absent.
  Config section(const std::string& key) const;
  bool has(const std::string& key) const;
  // Keys of this map (for maps keyed by names, e.g. topics).
  std::vector<std::string> keys() const;

  double number(const std::string& key, double fallback, double min, double max) const;
  long long integer(const std::string& key, long long fallback, long long min, long long max) const;
  bool flag(const std::string& key, bool fallback) const;
  std::string text(const std::string& key, const std::string& fallback) const;
  std::string choice(const std::string& key, const std::string& fallback,
                     const std::vector<std::string>& allowed) const;

  // A list of `width` numbers, or a list of such lists (rows); throws when absent.
  std::vector<double> numbers(const std::string& key, size_t width) const;
  std::vector<std::vector<double>> number_rows(const std::string& key, size_t width) const;
  // A list of names (empty when absent).
  std::vector<std::string> texts(const std::string& key) const;
  // Each map of a list of maps (empty when absent), named "key[i]" in errors.
  std::vector<Config> maps(const std::string& key) const;
  // Throws ConfigError saying the key is required.
  [[noreturn]] void missing(const std::string& key) const;
  // Throws ConfigError naming the file and the key: "<file>: key '<a.b>' <what>".
  [[noreturn]] void fail(const std::string& key, const std::string& what) const;

  // Throws ConfigError naming the first key under this view (the whole file for the
  // loaded root) that no getter asked for.
  void check_all_read() const;

  const std::string& origin() const { return state_->origin; }
  std::string path_of(const std::string& key) const;

 private:
  struct State {
    std::string origin;
    YAML::Node root;
    std::set<std::string> read_leaves;
    std::set<std::string> read_sections;
  };
  Config(std::shared_ptr<State> state, YAML::Node node, std::string prefix);
  YAML::Node scalar(const std::string& key) const;
  std::vector<double> row_of(const YAML::Node& list, const std::string& key, size_t width) const;
  void check_node(const YAML::Node& node, const std::string& prefix) const;

  std::shared_ptr<State> state_;
  YAML::Node node_;
  std::string prefix_;
};

}  // namespace scanbus
