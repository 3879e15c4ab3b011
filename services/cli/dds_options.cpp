#include "commands.hpp"

namespace scanbus::cli {

void add_dds_options(CLI::App& command, DdsOptions& options) {
  command.add_option("--dds-profile", options.profile_file,
                     "Fast DDS XML profile file (default: built-in loopback-only profile)");
  command.add_option("--domain", options.domain, "DDS domain id")->check(CLI::Range(0, 232))->envname("SCANBUS_DOMAIN_ID");
}

}  // namespace scanbus::cli
