// Watches a running MAV pipeline for bench/soak.sh: every PERIOD seconds one row with each
// service's resident memory (VmRSS) and, over that period, the latency from a scan reaching
// the bus to its pose (rt/scan -> rt/pose, same stamp) and to an assembled cloud that
// includes it (rt/cloud/assembled, stamped with the newest scan or pose); at the end a
// summary judged against the soak's targets (exit 1 when one is missed): memory flat, pose
// latency not growing, no sample lost by the services after the warm-up (Health samples_lost).
//   soak_monitor SECONDS PERIOD WARM_UP NAME=PID [NAME=PID ...]
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

#include "scanbus/clock.hpp"
#include "scanbus/messages.hpp"
#include "scanbus/service.hpp"

namespace scanbus::bench {
namespace {

using Clock = std::chrono::steady_clock;

struct Service {
  std::string name;
  int pid;
};

// Resident memory of a process in MB, from /proc; 0 when it is gone.
double rss_mb(int pid) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  return 0;
}

double percentile(std::vector<double> values, double share) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  return values[std::min(values.size() - 1, static_cast<size_t>(share * values.size()))];
}

class LatencyProbe {
 public:
  void scan(double stamp) {
    std::lock_guard<std::mutex> lock(mutex_);
    seen_[stamp] = Clock::now();
    ++scans_;
    while (seen_.size() > 20000) seen_.erase(seen_.begin());  // 200 s at 100 Hz
  }
  void pose(double stamp) { record(stamp, pose_ms_, poses_); }
  void cloud(double stamp, uint32_t points) {
    record(stamp, cloud_ms_, clouds_);
    std::lock_guard<std::mutex> lock(mutex_);
    map_points_ = points;
  }

  struct Period {
    uint64_t scans, poses, clouds;
    std::vector<double> pose_ms, cloud_ms;
    uint32_t map_points;  // in the newest assembled cloud
  };
  Period take() {
    std::lock_guard<std::mutex> lock(mutex_);
    Period period{scans_, poses_, clouds_, std::move(pose_ms_), std::move(cloud_ms_), map_points_};
    scans_ = poses_ = clouds_ = 0;
    pose_ms_.clear();
    cloud_ms_.clear();
    return period;
  }

 private:
  void record(double stamp, std::vector<double>& into, uint64_t& count) {
    const auto now = Clock::now();
    std::lock_guard<std::mutex> lock(mutex_);
    ++count;
    if (auto found = seen_.find(stamp); found != seen_.end())
      into.push_back(std::chrono::duration<double, std::milli>(now - found->second).count());
  }
  std::mutex mutex_;
  std::map<double, Clock::time_point> seen_;
  uint64_t scans_ = 0, poses_ = 0, clouds_ = 0;
  std::vector<double> pose_ms_, cloud_ms_;
  uint32_t map_points_ = 0;
};

int monitor(double seconds, double period, double warm_up, const std::vector<Service>& services) {
  StopSignal::install();
  Participant participant(dds_settings_from_config(Config::parse("", "")), "soak_monitor");
  LatencyProbe probe;
  Reader<sensor_msgs::msg::LaserScanPubSubType> scans(participant, "rt/scan", [&](const auto& m, const auto&) {
    probe.scan(to_seconds(m.header().stamp()));
  });
  Reader<geometry_msgs::msg::PoseWithCovarianceStampedPubSubType> poses(
      participant, "rt/pose", [&](const auto& m, const auto&) { probe.pose(to_seconds(m.header().stamp())); });
  Reader<sensor_msgs::msg::PointCloud2PubSubType> clouds(
      participant, "rt/cloud/assembled", [&](const auto& m, const auto&) { probe.cloud(to_seconds(m.header().stamp()), m.width() * m.height()); });
  std::mutex lost_mutex;
  std::map<std::string, uint64_t> lost_by_service;
  Reader<scanbus::msg::HealthPubSubType> health(participant, "rt/scanbus/health", [&](const auto& m, const auto&) {
    for (const auto& counter : m.counters())
      if (counter.name() == "samples_lost") {
        std::lock_guard<std::mutex> lock(lost_mutex);
        lost_by_service[m.service()] = counter.value();
      }
  });

  std::printf("%6s %6s %6s | pose latency ms %5s %5s %5s | cloud ms %5s %5s %9s |", "t s", "scans", "poses", "p50",
              "p99", "max", "p50", "max", "points");
  for (const auto& service : services) std::printf(" %14s", (service.name + " MB").c_str());
  std::printf("\n");
  struct Row {
    double t, pose_p50, pose_p99;
    std::vector<double> rss;
    std::map<std::string, uint64_t> lost;  // samples_lost by service, so far
  };
  std::vector<Row> rows;
  std::vector<double> all_pose_ms;
  uint64_t scans_total = 0, poses_total = 0;
  const auto start = Clock::now();
  for (double next = period; next <= seconds + 1e-9; next += period) {
    if (StopSignal::wait_for(std::chrono::duration_cast<std::chrono::milliseconds>(
            start + std::chrono::duration<double>(next) - Clock::now())))
      break;
    LatencyProbe::Period p = probe.take();
    Row row{next, percentile(p.pose_ms, 0.5), percentile(p.pose_ms, 0.99), {}, {}};
    {
      std::lock_guard<std::mutex> lock(lost_mutex);
      row.lost = lost_by_service;
    }
    std::printf("%6.0f %6lu %6lu | %21.1f %5.1f %5.1f |", next, static_cast<unsigned long>(p.scans),
                static_cast<unsigned long>(p.poses), row.pose_p50, row.pose_p99, percentile(p.pose_ms, 1.0));
    // cloud_assembly publishes only when its map grew: none once the voxel budget is full.
    if (p.cloud_ms.empty()) std::printf(" %14s %5s %9u |", "-", "-", p.map_points);
    else std::printf(" %14.1f %5.1f %9u |", percentile(p.cloud_ms, 0.5), percentile(p.cloud_ms, 1.0), p.map_points);
    for (const auto& service : services) {
      row.rss.push_back(rss_mb(service.pid));
      std::printf(" %14.1f", row.rss.back());
    }
    std::printf("\n");
    std::fflush(stdout);
    rows.push_back(row);
    if (next > warm_up) {
      all_pose_ms.insert(all_pose_ms.end(), p.pose_ms.begin(), p.pose_ms.end());
      scans_total += p.scans;
      poses_total += p.poses;
    }
  }
  // Judged from the first row after the warm-up to the last.
  auto first = std::find_if(rows.begin(), rows.end(), [&](const Row& r) { return r.t > warm_up; });
  if (first == rows.end() || first == rows.end() - 1) {
    std::printf("too short to judge: need two rows after the %.0f s warm-up\n", warm_up);
    return 1;
  }
  const Row& last = rows.back();
  bool ok = true;
  std::printf("\nafter the %.0f s warm-up (t = %.0f to %.0f s): %lu scans, %lu poses; pose latency p50 %.1f ms, p99 %.1f ms, max %.1f ms\n",
              warm_up, first->t, last.t, static_cast<unsigned long>(scans_total), static_cast<unsigned long>(poses_total),
              percentile(all_pose_ms, 0.5), percentile(all_pose_ms, 0.99), percentile(all_pose_ms, 1.0));
  // Flat memory: growth over the judged span within 5 % + 5 MB (allocator noise).
  for (size_t i = 0; i < services.size(); ++i) {
    const double growth = last.rss[i] - first->rss[i];
    const bool flat = last.rss[i] > 0 && growth <= 0.05 * first->rss[i] + 5;
    ok = ok && flat;
    std::printf("%-16s RSS %.1f -> %.1f MB (%+.1f MB): %s\n", services[i].name.c_str(), first->rss[i], last.rss[i],
                growth, last.rss[i] == 0 ? "NOT RUNNING" : flat ? "flat" : "GROWING");
  }
  // No growing latency: the last period's median within 20 % + 2 ms of the first's.
  const bool steady = last.pose_p50 <= 1.2 * first->pose_p50 + 2;
  ok = ok && steady && poses_total > 0;
  std::printf("pose latency p50 %.1f -> %.1f ms: %s\n", first->pose_p50, last.pose_p50, steady ? "steady" : "GROWING");
  // Nothing lost after the warm-up (what a start-up hiccup lost is printed, not judged).
  for (const auto& service : services) {
    auto lost = [&](const Row& row) { return row.lost.count(service.name) ? row.lost.at(service.name) : 0; };
    const uint64_t judged = lost(last) - lost(*first);
    ok = ok && judged == 0;
    std::printf("%-16s samples lost: %lu after the warm-up (%lu before)\n", service.name.c_str(),
                static_cast<unsigned long>(judged), static_cast<unsigned long>(lost(*first)));
  }
  if (const uint64_t lost = participant.lost())
    std::printf("(this monitor's own readers lost %lu samples: its latencies miss them)\n", static_cast<unsigned long>(lost));
  return ok ? 0 : 1;
}

}  // namespace
}  // namespace scanbus::bench

int main(int argc, char** argv) {
  if (argc < 5) {
    std::cerr << "usage: soak_monitor SECONDS PERIOD WARM_UP NAME=PID [NAME=PID ...]\n";
    return 2;
  }
  std::vector<scanbus::bench::Service> services;
  for (int i = 4; i < argc; ++i) {
    const std::string arg = argv[i];
    const auto equals = arg.find('=');
    if (equals == std::string::npos) {
      std::cerr << "soak_monitor: '" << arg << "' is not NAME=PID\n";
      return 2;
    }
    services.push_back({arg.substr(0, equals), std::stoi(arg.substr(equals + 1))});
  }
  try {
    return scanbus::bench::monitor(std::stod(argv[1]), std::stod(argv[2]), std::stod(argv[3]), services);
  } catch (const std::exception& error) {
    std::cerr << "soak_monitor: " << error.what() << "\n";
    return 1;
  }
}
