#include <iostream>

#include "commands.hpp"
#include "service_registry.hpp"

namespace scanbus::cli {

void add_run_command(CLI::App& app, int& exit_code) {
  static std::string name;
  static std::string config;
  static bool check_only = false;
  auto* command = app.add_subcommand("run", "Start a service in the foreground");
  std::string names;
  for (const auto& entry : service_registry()) names += (names.empty() ? "" : ", ") + entry.first;
  command->add_option("service", name, "One of: " + names)->required();
  command->add_option("-c,--config", config, "YAML config file (defaults built in)");
  command->add_flag("--check-config", check_only, "Validate the config and exit");
  command->callback([&exit_code] {
    const auto found = service_registry().find(name);
    if (found == service_registry().end()) {
      std::cerr << "scanbus run: unknown service '" << name << "' (see scanbus run --help)\n";
      exit_code = 2;
      return;
    }
    exit_code = run_service(name, config, found->second, check_only);
  });
}

}  // namespace scanbus::cli
