#include "scanbus/launch/system.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "scanbus/service.hpp"

namespace scanbus::launch {

namespace {

YAML::Node qos_node(const QosSettings& qos) {
  YAML::Node node;
  node["reliability"] = qos.reliable ? "reliable" : "best_effort";
  node["durability"] = qos.transient_local ? "transient_local" : "volatile";
  node["history"] = qos.keep_all ? "keep_all" : "keep_last";
  node["depth"] = qos.depth;
  return node;
}

std::string seconds_text(double seconds) {
  std::ostringstream text;
  text << seconds;
  return text.str();
}

}  // namespace

ServiceConfig::ServiceConfig(const ServiceConfig& other)
    : health_period(other.health_period),
      log_level(other.log_level),
      qos(other.qos),
      settings(YAML::Clone(other.settings)) {}

ServiceConfig& ServiceConfig::operator=(const ServiceConfig& other) {
  if (this == &other) return *this;
  health_period = other.health_period;
  log_level = other.log_level;
  qos = other.qos;
  settings.reset(YAML::Clone(other.settings));  // `=` would write into the node other copies share
  return *this;
}

std::string ServiceConfig::to_yaml(const std::string& service_name) const {
  YAML::Node root(YAML::NodeType::Map);
  if (health_period) root["service"]["health_period"] = *health_period;
  if (log_level) root["service"]["log_level"] = *log_level;
  for (const auto& [topic, settings] : qos) root["qos"][topic] = qos_node(settings);
  if (settings.size() > 0) root[service_name] = settings;
  YAML::Emitter out;
  out << root;
  return std::string(out.c_str()) + "\n";
}

System::System(SystemSettings settings) : settings_(std::move(settings)) {
  if (settings_.executable.empty())
    throw std::invalid_argument("launch::System: no executable to run the services with");
  std::filesystem::create_directories(settings_.work_dir);
}

System::~System() {
  while (!children_.empty()) children_.pop_back();  // the last started first
  if (settings_.temporary) {
    std::error_code ignored;  // a folder that cannot go is left, never an exception here
    std::filesystem::remove_all(settings_.work_dir, ignored);
  }
}

ChildProcess& System::start(const std::string& service, const ServiceConfig& config, Lifetime lifetime) {
  if (log_names_.count(service))
    throw std::invalid_argument("launch::System: " + service + " started twice (its log and config are one file each)");
  const std::string config_path = path(service + ".yaml");
  std::ofstream file(config_path);
  file << config.to_yaml(service);
  if (!file.flush()) throw std::runtime_error("cannot write " + config_path);
  return start_command(service, {"run", service, "--config", config_path}, lifetime);
}

ChildProcess& System::start_command(const std::string& log_name, const std::vector<std::string>& arguments,
                                    Lifetime lifetime) {
  return start_program(log_name, settings_.executable, arguments, lifetime);
}

ChildProcess& System::start_program(const std::string& log_name, const std::string& program,
                                    const std::vector<std::string>& arguments, Lifetime lifetime) {
  if (!log_names_.insert(log_name).second)
    throw std::invalid_argument("launch::System: " + log_name +
                                " started twice (its log and config are one file each)");
  children_.push_back(
      {std::make_unique<ChildProcess>(program, arguments, path(log_name + ".log"), dds_environment(settings_.dds)),
       lifetime});
  return *children_.back().process;
}

void System::stop(const ChildProcess& child) {
  children_.erase(std::remove_if(children_.begin(), children_.end(),
                                 [&](const Child& entry) { return entry.process.get() == &child; }),
                  children_.end());
}

void System::check() {
  for (auto& child : children_) {
    if (child.lifetime == Lifetime::UntilStopped) {
      child.process->expect_running();
    } else if (const auto status = child.process->exited(); status && *status != 0) {
      throw std::runtime_error(child.process->name() + " exited with status " + std::to_string(*status) + " (see " +
                               child.process->log_path() + ")");
    }
  }
}

bool System::wait_for(const std::function<bool()>& ready, double timeout, std::chrono::milliseconds poll) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout);
  for (;;) {
    const bool done = ready();
    check();
    if (done) return true;
    if (std::chrono::steady_clock::now() > deadline) return false;
    if (StopSignal::wait_for(poll)) throw std::runtime_error("interrupted");
  }
}

void System::wait_until(const std::function<bool()>& ready, double timeout, const std::string& failure,
                        std::chrono::milliseconds poll) {
  if (!wait_for(ready, timeout, poll)) throw std::runtime_error(failure + " within " + seconds_text(timeout) + " s");
}

std::string System::path(const std::string& file) const { return settings_.work_dir + "/" + file; }

}  // namespace scanbus::launch
