// `scanbus security`: the DDS Security permissions of every service, from the topic
// catalogue (scanbus/permissions.hpp); scripts/make-security.sh signs them.
#include <iostream>

#include "commands.hpp"
#include "scanbus/permissions.hpp"
#include "service_registry.hpp"

namespace scanbus::cli {

namespace {

std::vector<Grant> grants() {
  std::vector<std::string> services;
  for (const auto& [name, factory] : service_registry()) services.push_back(name);
  return catalogue_grants(services);
}

}  // namespace

void add_security_command(CLI::App& app, int& exit_code) {
  auto* security = app.add_subcommand("security", "DDS Security: identities and their permissions");
  security->require_subcommand(1);
  static std::string not_before = "2020-01-01T00:00:00", not_after = "2040-01-01T00:00:00";
  auto* permissions = security->add_subcommand(
      "permissions", "The permissions XML: each service may publish and subscribe its catalogue topics only");
  permissions->add_option("--not-before", not_before, "Grants valid from (UTC, YYYY-MM-DDThh:mm:ss)");
  permissions->add_option("--not-after", not_after, "Grants valid until (UTC)");
  on_run(*permissions, exit_code, [] {
    std::cout << permissions_document(grants(), not_before, not_after);
    return 0;
  });
  auto* identities = security->add_subcommand("identities", "One identity per line: the services, then operator");
  on_run(*identities, exit_code, [] {
    for (const auto& grant : grants()) std::cout << grant.identity << "\n";
    return 0;
  });
}

}  // namespace scanbus::cli
