#include <unistd.h>

#include <iostream>
#include <map>
#include <mutex>

#include "commands.hpp"
#include "scanbus/clock.hpp"
#include "scanbus/json.hpp"
#include "scanbus/service.hpp"
#include "scanbus/typed_topics.hpp"

namespace scanbus::cli {

namespace {

struct HealthOptions {
  DdsOptions dds;
  bool once = false;
  bool json = false;
  std::string check;
  double timeout = 3.0;
};

const char* state_name(uint8_t state) {
  switch (state) {
    case scanbus::msg::Health_Constants::STARTING:
      return "starting";
    case scanbus::msg::Health_Constants::OK:
      return "ok";
    case scanbus::msg::Health_Constants::DEGRADED:
      return "degraded";
    case scanbus::msg::Health_Constants::FAILED:
      return "failed";
    case scanbus::msg::Health_Constants::STOPPING:
      return "stopping";
  }
  return "unknown";
}

void print_table(const std::map<std::string, scanbus::msg::Health>& latest, bool clear) {
  if (clear) std::cout << "\x1b[H\x1b[2J";
  std::printf("%-20s %-8s %-9s %9s  %s\n", "SERVICE", "PID", "STATE", "UPTIME s", "COUNTERS / LAST ERROR");
  for (const auto& [key, health] : latest) {
    std::string counters;
    for (const auto& counter : health.counters())
      counters += counter.name() + "=" + std::to_string(counter.value()) + " ";
    if (!health.last_error().empty()) counters += "error: " + health.last_error();
    std::printf("%-20s %-8u %-9s %9.1f  %s\n", health.service().c_str(), health.pid(), state_name(health.state()),
                health.uptime(), counters.c_str());
  }
  std::fflush(stdout);
}

int run_health(const HealthOptions& options) {
  StopSignal::install();
  Participant participant(options.dds.settings(), "scanbus/health");
  std::mutex mutex;
  std::map<std::string, scanbus::msg::Health> latest;  // by service and pid
  bool check_passed = false;
  Reader<scanbus::msg::HealthPubSubType> reader(participant, topics::kHealth, [&](const auto& sample, const auto&) {
    std::lock_guard<std::mutex> lock(mutex);
    latest[sample.service() + "/" + std::to_string(sample.pid())] = sample;
    if (options.json && !options.once) std::cout << nlohmann::json(sample).dump() << std::endl;
    if (sample.service() == options.check && sample.state() == scanbus::msg::Health_Constants::OK) {
      check_passed = true;
      StopSignal::request();
    }
  });

  const bool live = options.check.empty() && !options.once && !options.json;
  const bool terminal = isatty(STDOUT_FILENO);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(options.timeout);
  while (!StopSignal::wait_for(std::chrono::milliseconds(live ? 1000 : 100))) {
    if (live) {
      std::lock_guard<std::mutex> lock(mutex);
      print_table(latest, terminal);
    } else if (std::chrono::steady_clock::now() > deadline) {
      break;
    }
  }
  std::lock_guard<std::mutex> lock(mutex);
  if (!options.check.empty()) {
    if (!check_passed)
      std::cerr << "scanbus health: no OK Health from '" << options.check << "' within " << options.timeout << " s\n";
    return check_passed ? 0 : 1;
  }
  if (options.once && options.json) {
    for (const auto& [key, health] : latest) std::cout << nlohmann::json(health).dump() << "\n";
  } else if (options.once) {
    print_table(latest, false);
  }
  return 0;
}

}  // namespace

void add_health_command(CLI::App& app, int& exit_code) {
  static HealthOptions options;
  auto* command = app.add_subcommand("health", "Live table of running services from their Health samples");
  command->add_flag("--once", options.once, "Collect for --timeout seconds, print one table and exit");
  command->add_flag("--json", options.json, "JSON lines instead of a table");
  command->add_option("--check", options.check, "Exit 0 once SERVICE reports OK, 1 if not within --timeout");
  command->add_option("--timeout", options.timeout, "Seconds to collect (--once) or wait (--check)")
      ->check(CLI::PositiveNumber);
  add_dds_options(*command, options.dds);
  on_run(*command, exit_code, [] { return run_health(options); });
}

}  // namespace scanbus::cli
