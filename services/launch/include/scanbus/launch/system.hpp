// Services started as separate processes, the way the demo, `scanbus scan`, the integration
// tests and the benchmarks run them: each config written from settings with yaml-cpp, every
// child on the caller's DDS domain and profile, the children watched while the caller waits,
// and all of them stopped (the last started first) when the System goes away.
#pragma once

#include <yaml-cpp/yaml.h>

#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "scanbus/child_process.hpp"
#include "scanbus/dds.hpp"

namespace scanbus::launch {

// A service's --config file. The keys are the ones the services read and check
// (scanbus/service.hpp for `service`, scanbus/topics.hpp for `qos`): a misspelt key in
// `settings` stops the service at start with the key named, which check() then reports.
struct ServiceConfig {
  std::optional<double> health_period;       // s between Health samples (the service's default: 1 s)
  std::optional<std::string> log_level;      // trace, debug, info, warn, error or off (default: info)
  std::map<std::string, QosSettings> qos;    // by DDS topic name ("rt/scan"), over the catalogue's
  YAML::Node settings{YAML::NodeType::Map};  // the service's own section, e.g. scanner_io's port

  ServiceConfig() = default;
  // A copy has its own settings (a copied YAML::Node is the same node: setting a key in one
  // config would set it in every copy). No moves: yaml-cpp's would share the node too.
  ServiceConfig(const ServiceConfig& other);
  ServiceConfig& operator=(const ServiceConfig& other);

  // The file's text, the service's section under `service_name`.
  std::string to_yaml(const std::string& service_name) const;
};

struct SystemSettings {
  std::string executable;  // the scanbus command, which runs `scanbus run <service>`
  std::string work_dir;    // created when missing; each child's config and log go here
  DdsSettings dds;         // every child's domain and profile, through its environment
  bool temporary = false;  // the work folder goes with the System, after its children (tests)
};

// Whether a child ending on its own is a failure (a service) or its job done (a replay).
enum class Lifetime { UntilStopped, RunsToEnd };

class System {
 public:
  explicit System(SystemSettings settings);
  ~System();
  System(const System&) = delete;
  System& operator=(const System&) = delete;

  // `scanbus run <service> --config <work_dir>/<service>.yaml`, its output in <service>.log.
  // Each name (service or log) once: a second would overwrite the first's files.
  ChildProcess& start(const std::string& service, const ServiceConfig& config = {},
                      Lifetime lifetime = Lifetime::UntilStopped);
  // Another command of the scanbus executable (a simulator), its output in <log_name>.log.
  ChildProcess& start_command(const std::string& log_name, const std::vector<std::string>& arguments,
                              Lifetime lifetime = Lifetime::UntilStopped);
  // Any program (a benchmark's own relay), its output in <log_name>.log.
  ChildProcess& start_program(const std::string& log_name, const std::string& program,
                              const std::vector<std::string>& arguments, Lifetime lifetime = Lifetime::UntilStopped);
  // Stops one child now (SIGTERM, then SIGKILL after 10 s), as the System does at its end.
  void stop(const ChildProcess& child);

  // Throws std::runtime_error naming the first child that failed: a service that ended, or a
  // RunsToEnd child that ended with a status other than 0; the message names its log.
  void check();
  // Waits until `ready()` holds, asking every `poll` and checking the children each time
  // (after asking, so a child that failed is reported even when `ready()` then holds); false
  // after `timeout` s. Throws check()'s error, or "interrupted" on StopSignal.
  bool wait_for(const std::function<bool()>& ready, double timeout,
                std::chrono::milliseconds poll = std::chrono::milliseconds(20));
  // As wait_for; when the time is up, throws std::runtime_error "<failure> within <timeout> s".
  void wait_until(const std::function<bool()>& ready, double timeout, const std::string& failure,
                  std::chrono::milliseconds poll = std::chrono::milliseconds(20));

  // <work_dir>/<file>
  std::string path(const std::string& file) const;
  const DdsSettings& dds() const { return settings_.dds; }

 private:
  struct Child {
    std::unique_ptr<ChildProcess> process;
    Lifetime lifetime;
  };
  SystemSettings settings_;
  std::vector<Child> children_;
  std::set<std::string> log_names_;
};

}  // namespace scanbus::launch
