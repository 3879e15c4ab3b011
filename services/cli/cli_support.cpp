#include <cstdlib>
#include <iostream>

#include "commands.hpp"

namespace scanbus::cli {

void add_dds_options(CLI::App& command, DdsOptions& options) {
  command
      .add_option("--dds-profile", options.profile_file,
                  "Fast DDS XML profile file (default: built-in loopback-only profile)")
      ->envname("SCANBUS_DDS_PROFILE_FILE");
  command.add_option("--dds-profile-name", options.profile, "Participant profile in that file")
      ->envname("SCANBUS_DDS_PROFILE");
  command.add_option("--domain", options.domain, "DDS domain id")
      ->check(CLI::Range(0, 232))
      ->envname("SCANBUS_DOMAIN_ID");
}

void on_run(CLI::App& command, int& exit_code, std::function<int()> body) {
  command.callback([&command, &exit_code, body = std::move(body)] {
    try {
      exit_code = body();
    } catch (const std::exception& e) {
      std::cerr << "scanbus " << command.get_name() << ": " << e.what() << "\n";
      exit_code = 1;
    }
  });
}

}  // namespace scanbus::cli
