// Watches the soak's pipelines for bench/soak.sh: every PERIOD seconds one row with each
// service's resident memory (VmRSS of the pid its Health names, so a restarted service is
// followed) and, over that period, the latency from a scan reaching the bus to its pose
// (rt/scan -> rt/pose, same stamp) and to an assembled cloud that includes it
// (rt/cloud/assembled, stamped with the newest scan or pose). At the end a summary judged
// against the soak's targets, exit 1 when one is missed:
// - memory flat: each service's peak in the last third of the judged span within 5 % + 5 MB
//   of its peak in the first third (peaks, so a restarted service is judged across its lives);
// - pose latency not growing: the median of the rows' medians, last third against first
//   (without faults: a restarted cloud_assembly refilling its map costs CPU);
// - nothing lost after the warm-up: no sequence gap in any service's readers (Health
//   samples_lost, summed over a service's lives), no scan without its pose and no whole
//   room scan without its RoomMeasurement, except those that reached a service while it
//   or the one before it was down (the windows come from the faults in EVENTS);
// - every fault in EVENTS (bench/soak.sh --faults writes them) recovered within 5 s: a
//   service killed and started again publishes from its new process, a serial device
//   plugged in again gives a revolution.
//   soak_monitor --seconds S --period P --warm-up W --services NAME,... [--events FILE]
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>

#include "scanbus/clock.hpp"
#include "scanbus/messages.hpp"
#include "scanbus/service.hpp"
#include "scanbus/typed_topics.hpp"

namespace scanbus::bench {
namespace {

constexpr double kRecoveryLimit = 5.0;  // s, issue 21's target for a restart or a replug

double wall_now() { return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count(); }

// Resident memory of a process in MB, from /proc; 0 when it is gone.
double rss_mb(uint32_t pid) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  return 0;
}

// "2.31 s after WHAT", or "never" when `at` is 0 (nothing came).
std::string after(double at, double since, const char* what) {
  if (at <= 0) return "never";
  char text[64];
  std::snprintf(text, sizeof text, "%.2f s after %s", at - since, what);
  return text;
}

double percentile(std::vector<double> values, double share) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  return values[std::min(values.size() - 1, static_cast<size_t>(share * values.size()))];
}

// Every sample of one topic as it arrived: when (wall clock, s), its stamp, and which writer
// sent it (numbered in order of first appearance, so a restarted publisher is a new number).
class TopicLog {
 public:
  struct Arrival {
    double wall, stamp;
    size_t writer;
    uint32_t points;
  };
  void add(double stamp, const eprosima::fastdds::dds::SampleInfo& info, uint32_t points = 0) {
    const double wall = wall_now();
    std::lock_guard<std::mutex> lock(mutex_);
    auto [writer, is_new] = writers_.emplace(info.sample_identity.writer_guid(), writer_first_seen_.size());
    if (is_new) writer_first_seen_.push_back(wall);
    arrivals_.push_back({wall, stamp, writer->second, points});
  }
  std::vector<Arrival> arrivals() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return arrivals_;
  }
  // When the first writer that appeared at or after `since` sent its first sample; 0: none did.
  double first_new_writer(double since) const {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const double seen : writer_first_seen_)
      if (seen >= since) return seen;
    return 0;
  }
  // When the first sample from any writer arrived at or after `since`; 0: none did.
  double first_sample(double since) const {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& arrival : arrivals_)
      if (arrival.wall >= since) return arrival.wall;
    return 0;
  }

 private:
  mutable std::mutex mutex_;
  std::map<eprosima::fastrtps::rtps::GUID_t, size_t> writers_;
  std::vector<double> writer_first_seen_;
  std::vector<Arrival> arrivals_;
};

// Each service's current pid and its readers' lost samples, from rt/scanbus/health.
class ServiceTable {
 public:
  void health(const scanbus::msg::Health& m) {
    std::lock_guard<std::mutex> lock(mutex_);
    pid_[m.service()] = m.pid();
    for (const auto& counter : m.counters())
      if (counter.name() == "samples_lost") lost_[m.service()][m.pid()] = counter.value();
  }
  uint32_t pid(const std::string& service) const {
    std::lock_guard<std::mutex> lock(mutex_);
    auto found = pid_.find(service);
    return found == pid_.end() ? 0 : found->second;
  }
  uint64_t lost(const std::string& service) const {  // over every process the service had
    std::lock_guard<std::mutex> lock(mutex_);
    uint64_t total = 0;
    if (auto found = lost_.find(service); found != lost_.end())
      for (const auto& [pid, lost] : found->second) total += lost;
    return total;
  }

 private:
  mutable std::mutex mutex_;
  std::map<std::string, uint32_t> pid_;
  std::map<std::string, std::map<uint32_t, uint64_t>> lost_;
};

// One line of bench/soak.sh's events file: "WALL kill|start NAME" or "WALL unplug|replug".
struct Event {
  double wall;
  std::string kind, service;
};

std::vector<Event> read_events(const std::string& path) {
  std::vector<Event> events;
  if (path.empty()) return events;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    Event event;
    if (fields >> event.wall >> event.kind) {
      fields >> event.service;
      events.push_back(event);
    }
  }
  return events;
}

// What each service publishes, so its return after a restart can be seen.
const std::map<std::string, std::string>& output_topic() {
  static const std::map<std::string, std::string> outputs = {{"scan_matcher", topics::kScanMatch.name},
                                                             {"pose_estimation", topics::kPose.name},
                                                             {"cloud_assembly", topics::kCloudAssembled.name},
                                                             {"scanner_io", topics::kScannerCloud.name},
                                                             {"room_measurement", topics::kRoomMeasurement.name}};
  return outputs;
}

struct Outage {  // a service down: from its kill to its first sample from the new process
  std::string service;
  double from, to;
};

class Soak {
  // A reader's handler that logs each sample of `topic` by its header stamp.
  auto logger(const char* topic) {
    return [this, topic](const auto& m, const auto& info) { log_.at(topic).add(to_seconds(m.header().stamp()), info); };
  }

 public:
  explicit Soak(Participant& participant)
      : scans_(participant, topics::kScan, logger(topics::kScan.name)),
        matches_(participant, topics::kScanMatch, logger(topics::kScanMatch.name)),
        poses_(participant, topics::kPose, logger(topics::kPose.name)),
        clouds_(participant, topics::kCloudAssembled,
                [this](const auto& m, const auto& i) {
                  log_.at(topics::kCloudAssembled.name).add(to_seconds(m.header().stamp()), i, m.width() * m.height());
                }),
        revolutions_(participant, topics::kScannerCloud, logger(topics::kScannerCloud.name)),
        room_scans_(participant, topics::kScannerScanCloud, logger(topics::kScannerScanCloud.name)),
        rooms_(participant, topics::kRoomMeasurement, logger(topics::kRoomMeasurement.name)),
        health_(participant, topics::kHealth, [this](const auto& m, const auto&) { services_.health(m); }) {}

  const TopicLog& log(const std::string& topic) const { return log_.at(topic); }
  const ServiceTable& services() const { return services_; }

 private:
  // Made before the readers, whose callbacks write into it; std::map nodes never move.
  static std::map<std::string, TopicLog> topic_logs() {
    std::map<std::string, TopicLog> logs;
    for (const char* topic :
         {topics::kScan.name, topics::kScanMatch.name, topics::kPose.name, topics::kCloudAssembled.name,
          topics::kScannerCloud.name, topics::kScannerScanCloud.name, topics::kRoomMeasurement.name})
      logs.try_emplace(topic);
    return logs;
  }
  std::map<std::string, TopicLog> log_ = topic_logs();
  ServiceTable services_;
  Reader<sensor_msgs::msg::LaserScanPubSubType> scans_;
  Reader<scanbus::msg::ScanMatchPubSubType> matches_;
  Reader<geometry_msgs::msg::PoseWithCovarianceStampedPubSubType> poses_;
  Reader<sensor_msgs::msg::PointCloud2PubSubType> clouds_;
  Reader<sensor_msgs::msg::PointCloud2PubSubType> revolutions_;
  Reader<sensor_msgs::msg::PointCloud2PubSubType> room_scans_;
  Reader<scanbus::msg::RoomMeasurementPubSubType> rooms_;
  Reader<scanbus::msg::HealthPubSubType> health_;
};

// Latencies (ms) from an input's arrival to the output with the same stamp, for outputs that
// arrived in [from, to).
std::vector<double> latencies(const std::map<double, double>& input_wall, const std::vector<TopicLog::Arrival>& outputs,
                              double from, double to) {
  std::vector<double> ms;
  for (const auto& output : outputs)
    if (output.wall >= from && output.wall < to)
      if (auto found = input_wall.find(output.stamp); found != input_wall.end())
        ms.push_back(1000.0 * (output.wall - found->second));
  return ms;
}

std::map<double, double> wall_by_stamp(const std::vector<TopicLog::Arrival>& arrivals) {
  std::map<double, double> walls;
  for (const auto& arrival : arrivals) walls.emplace(arrival.stamp, arrival.wall);
  return walls;
}

struct Row {
  double t, pose_p50;
  std::vector<double> rss;
};

struct Options {
  double seconds = 600, period = 30, warm_up = 120;
  std::vector<std::string> services;
  std::string events;
};

// Inputs that arrived in [from, to) with no output of the same stamp, other than those that
// arrived while one of `outages` (widened by a second before the kill) was on.
struct Completeness {
  size_t inputs = 0, missing = 0, missing_in_outages = 0;
  std::vector<double> unexplained_walls;
};
Completeness completeness(const std::vector<TopicLog::Arrival>& inputs, const std::vector<TopicLog::Arrival>& outputs,
                          const std::vector<Outage>& outages, double from, double to) {
  std::set<double> produced;
  for (const auto& output : outputs) produced.insert(output.stamp);
  Completeness result;
  for (const auto& input : inputs) {
    if (input.wall < from || input.wall >= to) continue;
    ++result.inputs;
    if (produced.count(input.stamp)) continue;
    ++result.missing;
    const bool explained = std::any_of(outages.begin(), outages.end(), [&](const Outage& outage) {
      return input.wall >= outage.from - 1.0 && input.wall <= outage.to;
    });
    if (explained)
      ++result.missing_in_outages;
    else
      result.unexplained_walls.push_back(input.wall);
  }
  return result;
}

// Judges each fault's recovery, prints one line per fault; the outages found, by service.
std::vector<Outage> judge_faults(const Soak& soak, const std::vector<Event>& events, double start, bool& ok) {
  std::vector<Outage> outages;
  if (!events.empty())
    std::printf("\nfaults (t from the soak's start; recovery counted from the restart or the replug):\n");
  for (size_t i = 0; i < events.size(); ++i) {
    const Event& event = events[i];
    if (event.kind == "start") {
      auto kill = std::find_if(events.rbegin() + static_cast<long>(events.size() - i), events.rend(),
                               [&](const Event& e) { return e.kind == "kill" && e.service == event.service; });
      if (kill == events.rend() || !output_topic().count(event.service)) continue;
      const double back = soak.log(output_topic().at(event.service)).first_new_writer(event.wall);
      const double recovery = back > 0 ? back - event.wall : -1;
      const bool recovered = back > 0 && recovery <= kRecoveryLimit;
      ok = ok && recovered;
      outages.push_back({event.service, kill->wall, back > 0 ? back : 1e300});
      std::printf("  t %6.1f s  %-16s killed (SIGKILL), started %.2f s later, publishing %s again %s: %s\n",
                  kill->wall - start, event.service.c_str(), event.wall - kill->wall,
                  output_topic().at(event.service).c_str(), after(back, event.wall, "its start").c_str(),
                  recovered ? "ok" : "TOO SLOW");
    } else if (event.kind == "replug") {
      auto unplug = std::find_if(events.rbegin() + static_cast<long>(events.size() - i), events.rend(),
                                 [](const Event& e) { return e.kind == "unplug"; });
      const double back = soak.log(topics::kScannerCloud.name).first_sample(event.wall);
      const double recovery = back > 0 ? back - event.wall : -1;
      const bool recovered = back > 0 && recovery <= kRecoveryLimit;
      ok = ok && recovered;
      if (unplug != events.rend()) outages.push_back({"serial device", unplug->wall, back > 0 ? back : 1e300});
      std::printf("  t %6.1f s  serial device    unplugged for %.1f s, a revolution %s: %s\n",
                  (unplug != events.rend() ? unplug->wall : event.wall) - start,
                  unplug != events.rend() ? event.wall - unplug->wall : 0.0,
                  after(back, event.wall, "the replug").c_str(), recovered ? "ok" : "TOO SLOW");
    }
  }
  return outages;
}

std::vector<Outage> outages_of(const std::vector<Outage>& all, std::initializer_list<const char*> services) {
  std::vector<Outage> chosen;
  for (const auto& outage : all)
    for (const char* service : services)
      if (outage.service == service) chosen.push_back(outage);
  return chosen;
}

bool judge_completeness(const char* what, const Completeness& c, double start) {
  std::printf("%s: %zu of %zu missing, %zu of them while a service on the way was down%s\n", what, c.missing, c.inputs,
              c.missing_in_outages, c.unexplained_walls.empty() ? "" : ": LOST");
  for (size_t i = 0; i < std::min<size_t>(5, c.unexplained_walls.size()); ++i)
    std::printf("  lost: arrived at t %.2f s\n", c.unexplained_walls[i] - start);
  return c.unexplained_walls.empty();
}

int monitor(const Options& options) {
  StopSignal::install();
  Participant participant(dds_settings_from_config(Config::parse("", "")), "soak_monitor");
  Soak soak(participant);

  std::printf("%6s %6s %6s | pose latency ms %5s %5s %5s | cloud ms %5s %5s %9s |", "t s", "scans", "poses", "p50",
              "p99", "max", "p50", "max", "points");
  for (const auto& service : options.services)
    std::printf(" %*s", static_cast<int>(std::max<size_t>(8, service.size() + 3)), (service + " MB").c_str());
  std::printf("\n");
  std::vector<Row> rows;
  std::map<std::string, uint64_t> lost_at_warm_up;
  const double start = wall_now();
  double last_row = start;
  for (double next = options.period; next <= options.seconds + 1e-9; next += options.period) {
    if (StopSignal::wait_for(std::chrono::milliseconds(static_cast<int64_t>(1000 * (start + next - wall_now())))))
      break;
    const double now = wall_now();
    const auto scans = soak.log(topics::kScan.name).arrivals();
    const auto scan_wall = wall_by_stamp(scans);
    const auto poses = soak.log(topics::kPose.name).arrivals();
    const auto clouds = soak.log(topics::kCloudAssembled.name).arrivals();
    auto in_row = [&](const std::vector<TopicLog::Arrival>& arrivals) {
      return std::count_if(arrivals.begin(), arrivals.end(),
                           [&](const auto& a) { return a.wall >= last_row && a.wall < now; });
    };
    const std::vector<double> pose_ms = latencies(scan_wall, poses, last_row, now);
    const std::vector<double> cloud_ms = latencies(scan_wall, clouds, last_row, now);
    Row row{next, percentile(pose_ms, 0.5), {}};
    std::printf("%6.0f %6ld %6ld | %21.1f %5.1f %5.1f |", next, in_row(scans), in_row(poses), row.pose_p50,
                percentile(pose_ms, 0.99), percentile(pose_ms, 1.0));
    const uint32_t map_points = clouds.empty() ? 0 : clouds.back().points;
    // cloud_assembly publishes only when its map grew: none once the voxel budget is full.
    if (cloud_ms.empty())
      std::printf(" %14s %5s %9u |", "-", "-", map_points);
    else
      std::printf(" %14.1f %5.1f %9u |", percentile(cloud_ms, 0.5), percentile(cloud_ms, 1.0), map_points);
    for (const auto& service : options.services) {
      row.rss.push_back(rss_mb(soak.services().pid(service)));
      std::printf(" %*.1f", static_cast<int>(std::max<size_t>(8, service.size() + 3)), row.rss.back());
    }
    std::printf("\n");
    std::fflush(stdout);
    rows.push_back(row);
    if (next <= options.warm_up)
      for (const auto& service : options.services) lost_at_warm_up[service] = soak.services().lost(service);
    last_row = now;
  }
  const auto judged_begin = std::find_if(rows.begin(), rows.end(), [&](const Row& r) { return r.t > options.warm_up; });
  const size_t judged = static_cast<size_t>(rows.end() - judged_begin);
  if (judged < 3) {
    std::printf("too short to judge: need three rows after the %.0f s warm-up\n", options.warm_up);
    return 1;
  }
  const size_t third = judged / 3;
  const std::vector<Row> first(judged_begin, judged_begin + static_cast<long>(third));
  const std::vector<Row> last(rows.end() - static_cast<long>(third), rows.end());
  const double judged_from = start + options.warm_up, judged_to = start + rows.back().t;
  bool ok = true;

  const auto scans = soak.log(topics::kScan.name).arrivals();
  const std::vector<double> pose_ms =
      latencies(wall_by_stamp(scans), soak.log(topics::kPose.name).arrivals(), judged_from, judged_to);
  std::printf(
      "\nafter the %.0f s warm-up (t = %.0f to %.0f s): scan to pose latency p50 %.1f ms, p99 %.1f ms, max %.1f ms\n",
      options.warm_up, options.warm_up, rows.back().t, percentile(pose_ms, 0.5), percentile(pose_ms, 0.99),
      percentile(pose_ms, 1.0));
  for (size_t i = 0; i < options.services.size(); ++i) {
    auto peak = [&](const std::vector<Row>& span) {
      double mb = 0;
      for (const auto& row : span) mb = std::max(mb, row.rss[i]);
      return mb;
    };
    const double before = peak(first), after = peak(last), growth = after - before;
    const bool running = rows.back().rss[i] > 0, flat = growth <= 0.05 * before + 5;
    ok = ok && running && flat;
    std::printf("%-16s RSS peak %.1f MB in the first third, %.1f MB in the last (%+.1f MB): %s\n",
                options.services[i].c_str(), before, after, growth,
                !running ? "NOT RUNNING"
                : flat   ? "flat"
                         : "GROWING");
  }
  auto median_p50 = [](const std::vector<Row>& span) {
    std::vector<double> p50;
    for (const auto& row : span) p50.push_back(row.pose_p50);
    return percentile(p50, 0.5);
  };
  // Not judged with faults: a restarted cloud_assembly refills its map, which costs CPU.
  const std::vector<Event> events = read_events(options.events);
  const bool steady = median_p50(last) <= 1.2 * median_p50(first) + 2;
  ok = ok && (steady || !events.empty()) && !pose_ms.empty();
  std::printf("pose latency, median of the rows' p50: %.1f ms in the first third, %.1f ms in the last: %s\n",
              median_p50(first), median_p50(last),
              !events.empty() ? "not judged (faults)"
              : steady        ? "steady"
                              : "GROWING");
  for (const auto& service : options.services) {
    const uint64_t lost = soak.services().lost(service) - lost_at_warm_up[service];
    ok = ok && lost == 0;
    std::printf(
        "%-16s samples lost by its readers (sequence gaps, Health samples_lost): %lu after the warm-up, %lu before\n",
        service.c_str(), static_cast<unsigned long>(lost), static_cast<unsigned long>(lost_at_warm_up[service]));
  }

  const std::vector<Outage> outages = judge_faults(soak, events, start, ok);
  // Up to 2 s before the end: what is still on its way is not lost.
  ok = judge_completeness(
           "\nscans (rt/scan) without a pose (rt/pose)",
           completeness(scans, soak.log(topics::kPose.name).arrivals(),
                        outages_of(outages, {"scan_matcher", "pose_estimation"}), judged_from, judged_to - 2),
           start) &&
       ok;
  const auto room_scans = soak.log(topics::kScannerScanCloud.name).arrivals();
  if (!room_scans.empty())
    ok = judge_completeness("whole room scans (rt/scanner/scan_cloud) without a RoomMeasurement",
                            completeness(room_scans, soak.log(topics::kRoomMeasurement.name).arrivals(),
                                         outages_of(outages, {"room_measurement"}), judged_from, judged_to - 5),
                            start) &&
         ok;
  if (const uint64_t lost = participant.lost())
    std::printf("(this monitor's own readers lost %lu samples: its figures miss them)\n",
                static_cast<unsigned long>(lost));
  return ok ? 0 : 1;
}

}  // namespace
}  // namespace scanbus::bench

int main(int argc, char** argv) {
  scanbus::bench::Options options;
  CLI::App app("Watches bench/soak.sh's services and judges the soak's targets");
  app.add_option("--seconds", options.seconds, "How long to watch, s")->required()->check(CLI::PositiveNumber);
  app.add_option("--period", options.period, "One row every this many s")->check(CLI::PositiveNumber);
  app.add_option("--warm-up", options.warm_up, "Not judged before this, s")->check(CLI::NonNegativeNumber);
  app.add_option("--services", options.services, "Services to follow (their Health names)")->required()->delimiter(',');
  app.add_option("--events", options.events, "Faults file bench/soak.sh --faults writes");
  CLI11_PARSE(app, argc, argv);
  try {
    return scanbus::bench::monitor(options);
  } catch (const std::exception& error) {
    std::cerr << "soak_monitor: " << error.what() << "\n";
    return 1;
  }
}
