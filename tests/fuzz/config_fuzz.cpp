// YAML configuration as every service loads it: the parse, the typed getters of the scan
// matcher's and the pose estimator's sections (ranges, lists, angles), the unknown-key check.
#include <string>

#include "fuzz_input.hpp"
#include "scanbus/config.hpp"
#include "scanbus/pose_estimation/pose_estimator.hpp"
#include "scanbus/scan_matcher/pl_icp.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const scanbus::Config root = scanbus::Config::parse(text, "fuzz.yaml");
    try {
      scanbus::scan_matcher::matcher_settings_from_config(root.section("scan_matcher").section("matcher"));
    } catch (const scanbus::ConfigError&) {
    }
    try {
      scanbus::pose_estimation::pose_estimator_settings_from_config(root.section("pose_estimation"));
    } catch (const scanbus::ConfigError&) {
    }
    root.section("service").number("health_period", 1.0, 0.01, 3600);
    root.section("dds").text("profile", "localhost");
    root.check_all_read();
  } catch (const scanbus::ConfigError&) {
  }
  return 0;
}
