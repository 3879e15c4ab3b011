// The main job: start the services as separate processes on the loopback profile, let
// them scan the built-in room, and write what came out over DDS.
#include <fcntl.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <mutex>
#include <optional>

#include "cloud_files.hpp"
#include "commands.hpp"
#include "scanbus/json.hpp"
#include "scanbus/point_cloud.hpp"
#include "scanbus/service.hpp"

extern char** environ;

namespace scanbus::cli {

namespace {

struct DemoOptions {
  DdsOptions dds;
  std::string out = "out";
  bool json = false;
  double timeout = 120;
};

// A service started as `scanbus run NAME`, stopped with SIGTERM when this goes away.
class ChildService {
 public:
  ChildService(const std::string& name, const std::string& log_path) : name_(name) {
    char self[4096] = {};
    if (readlink("/proc/self/exe", self, sizeof(self) - 1) < 0) throw std::runtime_error("cannot find own executable");
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    std::string run = "run";
    char* argv[] = {self, run.data(), name_.data(), nullptr};
    const int error = posix_spawn(&pid_, self, &actions, nullptr, argv, environ);
    posix_spawn_file_actions_destroy(&actions);
    if (error != 0) throw std::runtime_error("cannot start " + name + ": " + std::strerror(error));
  }
  ~ChildService() {
    if (pid_ <= 0) return;
    kill(pid_, SIGTERM);
    int status = 0;
    waitpid(pid_, &status, 0);
  }
  // The exit status when it has ended on its own.
  std::optional<int> exited() {
    int status = 0;
    if (pid_ > 0 && waitpid(pid_, &status, WNOHANG) == pid_) {
      pid_ = 0;
      exit_status_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    }
    return pid_ == 0 ? std::optional<int>(exit_status_) : std::nullopt;
  }

 private:
  std::string name_;
  pid_t pid_ = 0;
  int exit_status_ = 0;
};

struct ScanResult {
  std::vector<CloudPoint> points;
  uint32_t revolutions = 0;
};

int run_demo(const DemoOptions& options) {
  StopSignal::install();
  const bool progress = !options.json && isatty(STDOUT_FILENO);
  mkdir(options.out.c_str(), 0755);
  Participant participant(DdsSettings{options.dds.profile_file, "localhost", options.dds.domain}, "scanbus/demo");
  std::mutex mutex;
  std::optional<ScanResult> result;
  uint32_t revolutions = 0;
  Reader<sensor_msgs::msg::PointCloud2PubSubType> revolution_reader(
      participant, "rt/scanner/cloud", [&](const auto&, const auto&) {
        std::lock_guard<std::mutex> lock(mutex);
        ++revolutions;
        if (progress) std::printf("\rscanning: revolution %u of 27", revolutions), std::fflush(stdout);
      });
  Reader<sensor_msgs::msg::PointCloud2PubSubType> scan_reader(
      participant, "rt/scanner/scan_cloud", [&](const auto& cloud, const auto&) {
        std::lock_guard<std::mutex> lock(mutex);
        result = ScanResult{from_point_cloud2(cloud), revolutions};
        StopSignal::request();
      });

  // The services read their DDS settings from the environment: same domain and profile as ours.
  setenv("SCANBUS_DOMAIN_ID", std::to_string(options.dds.domain).c_str(), 1);
  if (!options.dds.profile_file.empty()) setenv("SCANBUS_DDS_PROFILE_FILE", options.dds.profile_file.c_str(), 1);
  ChildService scanner_io("scanner_io", options.out + "/scanner_io.log");
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(options.timeout);
  while (!StopSignal::wait_for(std::chrono::milliseconds(100))) {
    if (auto status = scanner_io.exited()) {
      std::cerr << "scanbus demo: scanner_io exited early with status " << *status << " (see " << options.out
                << "/scanner_io.log)\n";
      return 1;
    }
    if (std::chrono::steady_clock::now() > deadline) {
      std::cerr << "scanbus demo: no complete scan within " << options.timeout << " s\n";
      return 1;
    }
  }
  if (progress) std::printf("\n");
  std::lock_guard<std::mutex> lock(mutex);
  if (!result) {
    std::cerr << "scanbus demo: interrupted before the scan completed\n";
    return 130;
  }
  Eigen::Vector3f low = result->points.front().position, high = low;
  for (const auto& point : result->points) {
    low = low.cwiseMin(point.position);
    high = high.cwiseMax(point.position);
  }
  const std::string pcd = options.out + "/room.pcd", png = options.out + "/room_top.png";
  write_pcd(pcd, result->points);
  write_top_view_png(png, result->points, "scanbus demo: simulated scan of the built-in room");
  if (options.json) {
    std::cout << nlohmann::json{{"points", result->points.size()},
                                {"revolutions", result->revolutions},
                                {"extent_min", {low.x(), low.y(), low.z()}},
                                {"extent_max", {high.x(), high.y(), high.z()}},
                                {"files", {pcd, png}}}
              << "\n";
  } else {
    std::printf("scan of the built-in room: %zu points from %u revolutions\n", result->points.size(), result->revolutions);
    std::printf("cloud extent: x %.2f..%.2f m, y %.2f..%.2f m, z %.2f..%.2f m (floor to ceiling %.2f m)\n", low.x(),
                high.x(), low.y(), high.y(), low.z(), high.z(), high.z() - low.z());
    std::printf("wrote %s and %s\n", pcd.c_str(), png.c_str());
  }
  return 0;
}

}  // namespace

void add_demo_command(CLI::App& app, int& exit_code) {
  static DemoOptions options;
  auto* command = app.add_subcommand("demo", "Scan the built-in room through the services and write the result");
  command->add_option("--out", options.out, "Folder for the cloud, the picture and service logs");
  command->add_flag("--json", options.json, "Print the result as one JSON object, no progress");
  command->add_option("--timeout", options.timeout, "Give up after this many seconds")->check(CLI::PositiveNumber);
  add_dds_options(*command, options.dds);
  on_run(*command, exit_code, [] { return run_demo(options); });
}

}  // namespace scanbus::cli
